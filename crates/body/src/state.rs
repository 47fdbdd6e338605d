//! The state of one body in the relative set (docs/methods.md §2.4 / §4.1).

use nalgebra::{Matrix3, Vector2, Vector3};

/// The state of one body in the relative set (plain data).
///
/// * `r0`: global position of the body-frame origin O;
/// * `a`: rotation matrix, columns = body axes in global components;
/// * `omega`: global angular velocity ω (2D: `(0, 0, ω_z)`);
/// * `s_dot`: ṡ, the velocity of the body point that coincides with the global
///   origin: `ṡ = ṙ0 + r0 × ω`, equivalently `ṙ0 = ṡ − r̃0 ω`;
/// * `y`, `y_dot`: modal coordinates and their rates (length n).
///
/// In 2D the z components of `r0`, `omega.xy`, `s_dot` must be zero and `a` a
/// rotation about z ([`BodyState::planar`] builds one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState<'a> {
    /// Global position of the frame origin O (m).
    pub r0: Vector3<f64>,
    /// Orientation A (columns = body axes, global components).
    pub a: Matrix3<f64>,
    /// Global angular velocity ω (rad/s).
    pub omega: Vector3<f64>,
    /// ṡ = ṙ0 + r0 × ω (m/s).
    pub s_dot: Vector3<f64>,
    /// Modal coordinates y.
    pub y: &'a [f64],
    /// Modal rates ẏ.
    pub y_dot: &'a [f64],
}

impl<'a> BodyState<'a> {
    /// Build from the velocity of the frame origin: `ṡ = ṙ0 + r0 × ω`.
    pub fn from_origin_velocity(
        r0: Vector3<f64>,
        a: Matrix3<f64>,
        omega: Vector3<f64>,
        r0_dot: Vector3<f64>,
        y: &'a [f64],
        y_dot: &'a [f64],
    ) -> Self {
        Self {
            r0,
            a,
            omega,
            s_dot: r0_dot + r0.cross(&omega),
            y,
            y_dot,
        }
    }

    /// A planar state: origin (x, y), angle θ about z, ṡ = (ṡx, ṡy), ω_z.
    pub fn planar(
        r0: Vector2<f64>,
        theta: f64,
        s_dot: Vector2<f64>,
        omega_z: f64,
        y: &'a [f64],
        y_dot: &'a [f64],
    ) -> Self {
        let (s, c) = theta.sin_cos();
        Self {
            r0: Vector3::new(r0.x, r0.y, 0.0),
            a: Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0),
            omega: Vector3::new(0.0, 0.0, omega_z),
            s_dot: Vector3::new(s_dot.x, s_dot.y, 0.0),
            y,
            y_dot,
        }
    }

    /// Velocity of the frame origin, `ṙ0 = ṡ − r0 × ω`.
    pub fn r0_dot(&self) -> Vector3<f64> {
        self.s_dot - self.r0.cross(&self.omega)
    }
}
