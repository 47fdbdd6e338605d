//! The equations of the scene's [`Constraint`](crate::Constraint)s, written once for every
//! formulation (docs/methods.md §3.4) in the relative motion of their two markers.
//!
//! With d = r_P2 − r_P1, its rate ḋ and its bias d̈|q̈=0 (each formulation's own marker
//! kinematics: the natural-coordinate terms, the relative formulation's tree walk), and for a
//! plane the body1-fixed normal n with ṅ and its bias:
//!
//! ```text
//! Distance:      Φ = ½ (d·d − L²),  ∂Φ/∂d = d,                c = ḋ·ḋ + d·d̈_bias
//! PointInPlane:  Φ = n·d,           ∂Φ/∂d = n,  ∂Φ/∂n = d,    c = n·d̈_bias + d·n̈_bias + 2 ṅ·ḋ
//! ```
//!
//! so that Φ_q = (∂Φ/∂d)ᵀ ∂d/∂q (+ (∂Φ/∂n)ᵀ ∂n/∂q) and Φ̈ = Φ_q q̈ + c. The halved square
//! keeps the distance row polynomial (no square root, regular at any length) and gives it
//! the units of m², its gradient d of m: for a length L it equals L times the length error to
//! first order. Neither equation depends on t (Φ_t = 0).
//!
//! The marker kinematics of [`flexmbd_core::MarkerKinematics`] (positions and Jacobian
//! columns) are not enough here: the acceleration term needs each marker's bias, which only
//! the formulations' own kinematics carry; so each formulation evaluates these functions
//! with its motions and scatters the gradients through its own Jacobians.

use nalgebra::Vector3;

/// A vector's value, rate and bias (second derivative at q̈ = 0), ground components.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// The value.
    pub value: Vector3<f64>,
    /// Its rate.
    pub rate: Vector3<f64>,
    /// Its bias: the second derivative along q̇ at q̈ = 0.
    pub bias: Vector3<f64>,
}

impl Motion {
    /// `self − other`, term by term (the separation d of two points).
    pub fn minus(&self, other: &Motion) -> Motion {
        Motion {
            value: self.value - other.value,
            rate: self.rate - other.rate,
            bias: self.bias - other.bias,
        }
    }
}

/// One constraint row at a state: Φ and the acceleration term c (Φ̈ = Φ_q q̈ + c).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    /// Φ.
    pub phi: f64,
    /// c = Φ̇_q q̇.
    pub accel_term: f64,
}

/// Distance: Φ = ½ (d·d − L²) for the separation `d` and the length L; its gradient with
/// respect to d is d itself.
pub fn distance(d: &Motion, length: f64) -> Row {
    Row {
        phi: 0.5 * (d.value.norm_squared() - length * length),
        accel_term: d.rate.norm_squared() + d.value.dot(&d.bias),
    }
}

/// Point in plane: Φ = n·d for the separation `d` and the normal `n`; its gradients are n
/// (with respect to d) and d (with respect to n).
pub fn point_in_plane(d: &Motion, n: &Motion) -> Row {
    Row {
        phi: n.value.dot(&d.value),
        accel_term: n.value.dot(&d.bias) + d.value.dot(&n.bias) + 2.0 * n.rate.dot(&d.rate),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point moving as x(t) = x0 + v t + ½ a t² + (1/6) j t³: its motion at t.
    fn cubic(x0: [f64; 3], v: [f64; 3], a: [f64; 3], j: [f64; 3], t: f64) -> Motion {
        let [x0, v, a, j] = [x0, v, a, j].map(Vector3::from);
        Motion {
            value: x0 + v * t + a * (0.5 * t * t) + j * (t * t * t / 6.0),
            rate: v + a * t + j * (0.5 * t * t),
            bias: a + j * t,
        }
    }

    /// Along a path, Φ̈ (central differences of Φ) is the acceleration term when the motions'
    /// biases are their whole second derivatives (q̈ = 0 along the path).
    #[test]
    fn accel_terms_are_the_second_derivatives_along_a_path() {
        let d = |t| {
            cubic(
                [0.3, -0.2, 0.5],
                [1.0, 0.4, -0.7],
                [0.2, -1.1, 0.6],
                [0.5, 0.3, -0.2],
                t,
            )
        };
        let n = |t| {
            cubic(
                [0.0, 0.6, 0.8],
                [0.3, -0.2, 0.1],
                [-0.4, 0.1, 0.9],
                [0.1, 0.2, 0.3],
                t,
            )
        };
        let h = 1e-4;
        type Law = fn(&Motion, &Motion) -> Row;
        let laws: [(&str, Law); 2] = [
            ("distance", |d, _| distance(d, 0.7)),
            ("point in plane", point_in_plane),
        ];
        for (what, law) in laws {
            let phi = |t: f64| law(&d(t), &n(t)).phi;
            let fd = (phi(h) - 2.0 * phi(0.0) + phi(-h)) / (h * h);
            let c = law(&d(0.0), &n(0.0)).accel_term;
            assert!((fd - c).abs() < 1e-6, "{what}: Φ̈ = {fd}, c = {c}");
        }
    }

    #[test]
    fn distance_vanishes_at_the_length_and_grows_with_the_stretch() {
        let at = |x: f64| Motion {
            value: Vector3::new(0.0, x, 0.0),
            rate: Vector3::zeros(),
            bias: Vector3::zeros(),
        };
        assert_eq!(distance(&at(2.0), 2.0).phi, 0.0);
        // ½ (L + e)² − ½ L² = L e + ½ e².
        let phi = distance(&at(2.001), 2.0).phi;
        assert!((phi - (2.0 * 1e-3 + 0.5e-6)).abs() < 1e-15, "{phi}");
    }
}
