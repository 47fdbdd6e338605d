//! Elastic and damping forces of the modal coordinates (docs/methods.md §1.5, §6).
//!
//! The body calls its elastic model through the [`ElasticModel`] trait, so that the
//! geometric-stiffening models of §6 (FNL1 with `StiffeningIntegrals::k_g`, FNL2,
//! …, in the `flexmbd-stiffening` crate) plug in later through
//! [`FlexibleBody::set_elastic_model`]
//! without changing the body's interface. Only the linear model is implemented here.

use flexmbd_fe::ReducedBody;

use crate::FlexibleBody;
use nalgebra::{DMatrix, DMatrixViewMut};

/// Generalized elastic + damping force on the modal coordinates, `Q_el(y, ẏ)`.
///
/// Implementations must not allocate in [`forces`](ElasticModel::forces) or
/// [`add_tangents`](ElasticModel::add_tangents) (they run once per evaluation).
pub trait ElasticModel: Send + Sync + std::fmt::Debug {
    /// Short name for reports (`"linear"`, `"FNL1"`, …).
    fn name(&self) -> &str;
    /// Write `Q_el(y, ẏ)` (length n) into `out`, overwriting it.
    fn forces(&self, y: &[f64], y_dot: &[f64], out: &mut [f64]);
    /// Add `k_scale · (−∂Q_el/∂y) + c_scale · (−∂Q_el/∂ẏ)` (n × n) to `out`.
    fn add_tangents(
        &self,
        y: &[f64],
        y_dot: &[f64],
        k_scale: f64,
        c_scale: f64,
        out: DMatrixViewMut<'_, f64>,
    );
    /// Strain energy U(y) whose gradient the conservative part of `Q_el` is (½yᵀK_ff y for
    /// linear elasticity); the `Energy` sensors of the formulations add it.
    fn strain_energy(&self, y: &[f64]) -> f64;
    /// A boxed copy (lets [`FlexibleBody`] be `Clone`).
    fn clone_box(&self) -> Box<dyn ElasticModel>;
    /// True when the tangents do not depend on (y, ẏ) (formulations then report
    /// `constant_tangents`). Nonlinear stiffening models return false.
    fn is_linear(&self) -> bool {
        true
    }
    /// True when the stiffness tangent is symmetric (FNL1's is not).
    fn is_symmetric(&self) -> bool {
        true
    }
}

/// What the elastic models of a system's bodies let the integrator assume of its tangents.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ElasticTangents {
    /// Every model's tangents are constant ([`ElasticModel::is_linear`]).
    pub linear: bool,
    /// Every model's stiffness tangent is symmetric ([`ElasticModel::is_symmetric`]).
    pub symmetric: bool,
}

impl ElasticTangents {
    /// Of the elastic models of `bodies` (both true for none).
    pub fn of<'a>(bodies: impl IntoIterator<Item = &'a FlexibleBody>) -> Self {
        let mut tangents = ElasticTangents {
            linear: true,
            symmetric: true,
        };
        for body in bodies {
            let model = body.elastic_model();
            tangents.linear &= model.is_linear();
            tangents.symmetric &= model.is_symmetric();
        }
        tangents
    }
}

impl Clone for Box<dyn ElasticModel> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

/// Linear FFR elasticity (docs/methods.md §1.5): `Q_el = −K_ff y − C_ff ẏ`.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearElastic {
    n: usize,
    /// K_ff row-major (n²).
    k: Vec<f64>,
    /// C_ff row-major (n²).
    c: Vec<f64>,
    /// C_ff has no non-zero entry (an undamped body): `forces` skips its products, whose
    /// +0 terms leave every sum as it was.
    undamped: bool,
}

impl LinearElastic {
    /// From the reduced stiffness and damping of a body.
    pub fn new(k_ff: &DMatrix<f64>, c_ff: &DMatrix<f64>) -> Self {
        let n = k_ff.nrows();
        assert_eq!(k_ff.shape(), (n, n), "K_ff must be square");
        assert_eq!(c_ff.shape(), (n, n), "C_ff must have the shape of K_ff");
        let row_major = |m: &DMatrix<f64>| -> Vec<f64> {
            let mut v = Vec::with_capacity(n * n);
            for i in 0..n {
                for j in 0..n {
                    v.push(m[(i, j)]);
                }
            }
            v
        };
        let c = row_major(c_ff);
        Self {
            n,
            k: row_major(k_ff),
            undamped: c.iter().all(|&v| v == 0.0),
            c,
        }
    }

    /// From a reduced body's `k_ff` and `c_ff`.
    pub fn from_reduced(body: &ReducedBody) -> Self {
        Self::new(&body.k_ff, &body.c_ff)
    }
}

impl ElasticModel for LinearElastic {
    fn name(&self) -> &str {
        "linear"
    }

    fn forces(&self, y: &[f64], y_dot: &[f64], out: &mut [f64]) {
        let n = self.n;
        assert!(y.len() == n && y_dot.len() == n && out.len() == n);
        if self.undamped {
            // Each term k y + 0 ẏ is k y (or a zero, which adds nothing to a sum that starts
            // at +0): the same sums as below.
            for (i, o) in out.iter_mut().enumerate() {
                let mut s = 0.0;
                for (k, y) in self.k[i * n..(i + 1) * n].iter().zip(y) {
                    s += k * y;
                }
                *o = -s;
            }
            return;
        }
        for i in 0..n {
            let kr = &self.k[i * n..(i + 1) * n];
            let cr = &self.c[i * n..(i + 1) * n];
            let mut s = 0.0;
            for j in 0..n {
                s += kr[j] * y[j] + cr[j] * y_dot[j];
            }
            out[i] = -s;
        }
    }

    fn add_tangents(
        &self,
        _y: &[f64],
        _y_dot: &[f64],
        k_scale: f64,
        c_scale: f64,
        mut out: DMatrixViewMut<'_, f64>,
    ) {
        let n = self.n;
        assert_eq!(out.shape(), (n, n));
        for i in 0..n {
            for j in 0..n {
                out[(i, j)] += k_scale * self.k[i * n + j] + c_scale * self.c[i * n + j];
            }
        }
    }

    fn strain_energy(&self, y: &[f64]) -> f64 {
        let n = self.n;
        assert_eq!(y.len(), n);
        let mut u = 0.0;
        for i in 0..n {
            let kr = &self.k[i * n..(i + 1) * n];
            u += y[i] * kr.iter().zip(y).map(|(k, yj)| k * yj).sum::<f64>();
        }
        0.5 * u
    }

    fn clone_box(&self) -> Box<dyn ElasticModel> {
        Box::new(self.clone())
    }
}
