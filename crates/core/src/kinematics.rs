//! The kinematic query a formulation answers for the elements written once over it: force
//! elements (`flexmbd_model::force_elements`) and, later, sensors and inputs.
//!
//! An element names the formulation's markers by the formulation's own handle
//! ([`MarkerKinematics::Marker`], resolved once when the scene is compiled) and asks, at a
//! state (q, q̇):
//!
//! - the marker's position r_P and velocity ṙ_P (ground components; z = 0 in a planar
//!   scene);
//! - the non-zero columns ∂r_P/∂q_i of the marker's position Jacobian, so that a force F on
//!   the marker adds Q_i += ∂r_P/∂q_i · F (the virtual work F · δr_P, docs/methods.md §2.6).
//!
//! A formulation whose kinematics are recursive (the relative one) answers from its last
//! kinematic pass, which must be at (q, q̇): it calls the elements after that pass.

use nalgebra::{DVector, Matrix3, Vector3};

/// Marker positions, velocities and Jacobian columns of a formulation.
pub trait MarkerKinematics {
    /// The formulation's handle of a marker.
    type Marker;

    /// Position r_P (m) and velocity ṙ_P (m/s) of `marker` at (q, q̇), ground components.
    fn marker_state(
        &self,
        marker: &Self::Marker,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector3<f64>, Vector3<f64>);

    /// Visit the non-zero columns (i, ∂r_P/∂q_i) of `marker` at q. A coordinate visited twice
    /// has the sum of its columns.
    fn marker_jacobian(
        &mut self,
        marker: &Self::Marker,
        q: &DVector<f64>,
        visit: &mut dyn FnMut(usize, Vector3<f64>),
    );
}

/// What the sensors written once (`flexmbd_model::sensors`) need beyond the markers.
pub trait SensorQuery: MarkerKinematics {
    /// The formulation's handle of a joint coordinate (resolved when the scene is compiled).
    type JointCoordinate;

    /// Origin r0 (m) and rotation A (columns: body axes, ground components) of a body's frame
    /// at q, the body named by its index in the prepared scene. Planar: z = 0, A about z.
    fn body_frame(&self, body: usize, q: &DVector<f64>) -> (Vector3<f64>, Matrix3<f64>);

    /// A joint coordinate at (q, q̇), relative to its value at the start.
    fn joint_coordinate(
        &self,
        joint: &Self::JointCoordinate,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> JointReading;

    /// Total mechanical energy at (q, q̇) (J): kinetic, gravity, elastic, force elements.
    fn total_energy(&mut self, q: &DVector<f64>, qd: &DVector<f64>) -> f64;

    /// The state of force element `element` (its index in the scene's `forces`) at (q, q̇),
    /// computed by the same code as its forces.
    fn element_reading(
        &self,
        element: usize,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> ElementReading;

    /// The motion of a body's frame at (q, q̇, q̈): its origin, rotation, and their first and
    /// second time derivatives, exact for the formulation's coordinates (the body named by
    /// its index in the prepared scene). A formulation with recursive kinematics answers from
    /// its last kinematics pass, which the caller has run at (q, q̇).
    fn frame_motion(
        &self,
        body: usize,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        qdd: &DVector<f64>,
    ) -> FrameMotion;
}

/// The motion of a body frame {r0, A} (ground components; planar: z = 0, ω and ω̇ along z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameMotion {
    /// Origin r0 (m).
    pub origin: Vector3<f64>,
    /// Rotation A: columns are the body axes (ground components).
    pub rotation: Matrix3<f64>,
    /// ṙ0 (m/s).
    pub velocity: Vector3<f64>,
    /// Angular velocity ω (rad/s): Ȧ = ω̃ A.
    pub angular_velocity: Vector3<f64>,
    /// r̈0 (m/s²).
    pub acceleration: Vector3<f64>,
    /// Angular acceleration ω̇ (rad/s²).
    pub angular_acceleration: Vector3<f64>,
}

impl FrameMotion {
    /// The motion of a frame whose rotation A = [a₁ a₂ a₃] is given with its derivatives
    /// (natural coordinates: A is linear in q, so Ȧ and Ä are A of q̇ and q̈): for an
    /// orthonormal A, ȧᵢ = ω × aᵢ gives ω = ½ Σ aᵢ × ȧᵢ, and ω̇ = ½ Σ aᵢ × äᵢ (the terms
    /// ȧᵢ × ȧᵢ vanish).
    pub fn from_rotation_rates(
        origin: [Vector3<f64>; 3],
        rotation: [&Matrix3<f64>; 3],
    ) -> FrameMotion {
        let [a, ad, add] = rotation;
        let half_sum = |b: &Matrix3<f64>| {
            0.5 * (0..3).fold(Vector3::zeros(), |s, i| s + a.column(i).cross(&b.column(i)))
        };
        FrameMotion {
            origin: origin[0],
            rotation: *a,
            velocity: origin[1],
            angular_velocity: half_sum(ad),
            acceleration: origin[2],
            angular_acceleration: half_sum(add),
        }
    }
}

/// A force element's state as a sensor reads it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ElementReading {
    /// Tension (N; a tyre: its normal force, ≥ 0).
    pub force: f64,
    /// The length its laws are evaluated at (m; a tyre: its deflection δ, negative in the
    /// air).
    pub length: f64,
}

/// A joint coordinate as a formulation reads it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointReading {
    /// An angle known up to whole turns (rad); the sensor counts the turns.
    Angle(f64),
    /// A distance or an angle already continuous in time (m or rad).
    Value(f64),
}

#[cfg(test)]
mod tests {
    use super::FrameMotion;
    use nalgebra::{Matrix3, Rotation3, Unit, Vector3};

    #[test]
    fn frame_motion_recovers_the_angular_velocity_and_acceleration_of_a_turning_frame() {
        // A = R(θ n) A₀ with θ̇ = 2, θ̈ = 3: Ȧ = θ̇ ñ A, Ä = θ̈ ñ A + θ̇² ñ² A.
        let n = Unit::new_normalize(Vector3::new(1.0, -2.0, 0.5));
        let a0 = Rotation3::from_euler_angles(0.3, -0.2, 1.1);
        let a = (Rotation3::from_axis_angle(&n, 0.7) * a0).into_inner();
        let nt = n.into_inner().cross_matrix();
        let (td, tdd) = (2.0, 3.0);
        let ad = td * nt * a;
        let add: Matrix3<f64> = tdd * nt * a + td * td * nt * nt * a;
        let zero = Vector3::zeros();
        let m = FrameMotion::from_rotation_rates([zero; 3], [&a, &ad, &add]);
        assert!((m.angular_velocity - td * n.into_inner()).norm() < 1e-14);
        assert!((m.angular_acceleration - tdd * n.into_inner()).norm() < 1e-14);
    }
}
