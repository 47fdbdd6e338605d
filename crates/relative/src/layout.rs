//! The layout of a pass's 6-vectors — twists {v; ω}, subtree inertias 𝕄 and forces ℙ — for
//! each dimension: a spatial scene uses all six entries, a planar one x, y and θz (entries
//! 0, 1, 5; the others are exact zeros). The dynamics pass is generic over it, so the
//! entries a product reads are fixed when the pass is compiled rather than tested per
//! product, and loops over them have a length the compiler knows.

use nalgebra::{Matrix6, Vector6};

/// The entries of the 6-layout a scene's dimension uses, and the products over them.
pub(crate) trait Layout {
    /// The rigid velocity entries of a body (x, y, θz in 2D).
    const ENTRIES: &'static [usize];
    /// aᵀ b over [`ENTRIES`](Self::ENTRIES).
    fn dot(a: &Vector6<f64>, b: &Vector6<f64>) -> f64;
    /// 𝕄 v on [`ENTRIES`](Self::ENTRIES) (the other entries of the result are zero).
    fn inertia_times(m: &Matrix6<f64>, v: &Vector6<f64>) -> Vector6<f64>;
}

/// A planar scene: x, y, θz.
pub(crate) struct Planar;

/// A spatial scene: all six entries.
pub(crate) struct Spatial;

impl Layout for Planar {
    const ENTRIES: &'static [usize] = &[0, 1, 5];

    #[inline(always)]
    fn dot(a: &Vector6<f64>, b: &Vector6<f64>) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[5] * b[5]
    }

    #[inline(always)]
    fn inertia_times(m: &Matrix6<f64>, v: &Vector6<f64>) -> Vector6<f64> {
        let mut k = Vector6::zeros();
        for r in [0, 1, 5] {
            k[r] = m[(r, 0)] * v[0] + m[(r, 1)] * v[1] + m[(r, 5)] * v[5];
        }
        k
    }
}

impl Layout for Spatial {
    const ENTRIES: &'static [usize] = &[0, 1, 2, 3, 4, 5];

    #[inline(always)]
    fn dot(a: &Vector6<f64>, b: &Vector6<f64>) -> f64 {
        a.dot(b)
    }

    #[inline(always)]
    fn inertia_times(m: &Matrix6<f64>, v: &Vector6<f64>) -> Vector6<f64> {
        m * v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planar_products_read_x_y_theta_z_only() {
        let a = Vector6::new(1.0, 2.0, 100.0, 100.0, 100.0, 3.0);
        let b = Vector6::new(4.0, 5.0, 7.0, 7.0, 7.0, 6.0);
        assert_eq!(Planar::dot(&a, &b), 4.0 + 10.0 + 18.0);
        assert_eq!(Spatial::dot(&a, &b), a.dot(&b));
        let m = Matrix6::from_fn(|i, j| (1 + i * 6 + j) as f64);
        let k = Planar::inertia_times(&m, &a);
        for r in [0, 1, 5] {
            assert_eq!(k[r], m[(r, 0)] + 2.0 * m[(r, 1)] + 3.0 * m[(r, 5)]);
        }
        assert_eq!([k[2], k[3], k[4]], [0.0; 3]);
        assert_eq!(Spatial::inertia_times(&m, &a), m * a);
    }
}
