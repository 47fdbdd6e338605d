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
