//! Planar vector algebra: the quarter turn E, the matrix C(p) of a body-frame vector and the
//! scalar cross product.

use nalgebra::{Matrix2, Vector2};

/// E = [[0, −1], [1, 0]]: e_z × a = E a.
#[inline]
pub(crate) fn e_mat() -> Matrix2<f64> {
    Matrix2::new(0.0, -1.0, 1.0, 0.0)
}

/// C(p) = p₁ I + p₂ E, so that A p = C(p) u for A = [u  E u].
#[inline]
pub(crate) fn c_of(p: &Vector2<f64>) -> Matrix2<f64> {
    Matrix2::new(p.x, -p.y, p.y, p.x)
}

/// The scalar cross product a × b = a₁ b₂ − a₂ b₁ (the z component).
#[inline]
pub(super) fn cross(a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn e_is_the_quarter_turn() {
        let e = e_mat();
        assert_eq!(e * Vector2::new(1.0, 0.0), Vector2::new(0.0, 1.0));
        assert_eq!(e * Vector2::new(0.0, 1.0), Vector2::new(-1.0, 0.0));
        assert_eq!(e * e, -Matrix2::identity());
    }

    #[test]
    fn c_of_p_times_u_is_a_times_p() {
        let (p, u) = (Vector2::new(0.3, -1.7), Vector2::new(0.8, 0.6));
        let a = Matrix2::from_columns(&[u, e_mat() * u]);
        assert!((c_of(&p) * u - a * p).norm() < 1e-15);
        // C(p) = p₁ I + p₂ E commutes with E.
        assert_eq!(c_of(&p) * e_mat(), e_mat() * c_of(&p));
        assert_eq!(c_of(&Vector2::new(1.0, 0.0)), Matrix2::identity());
    }

    #[test]
    fn cross_is_the_z_component() {
        let (a, b) = (Vector2::new(2.0, 0.5), Vector2::new(-1.0, 3.0));
        assert_eq!(cross(&Vector2::x(), &Vector2::y()), 1.0);
        assert_eq!(cross(&a, &b), -cross(&b, &a));
        assert!((cross(&a, &b) - (e_mat() * a).dot(&b)).abs() < 1e-15);
        assert_eq!(cross(&a, &a), 0.0);
    }
}
