//! Shared helpers of the relative formulation's physics tests: the shared scenes and runs of
//! `flexmbd_test_support::scenes`, a run in the relative formulation, the system terms at a
//! state, the test states, and the Lagrange right-hand side.
#![allow(dead_code, unused_imports)]

use flexmbd_model::{FormulationKind, Scene};
use flexmbd_relative::Relative;
pub use flexmbd_test_support::scenes::*;
use nalgebra::DVector;

/// `scene` prepared and compiled in the relative formulation (panics on an error).
pub fn relative(scene: &Scene) -> Relative {
    compiled(scene, flexmbd_relative::compile)
}

/// Run `scene` in the relative formulation: sensor rows every `every` steps for `secs`, largest
/// ‖Φ‖∞.
pub fn run_relative(scene: &Scene, h: f64, secs: f64, every: usize) -> (Vec<Vec<f64>>, f64) {
    let kind = FormulationKind::Relative;
    run_as(scene, kind, flexmbd_relative::compile, h, secs, every)
}

/// The k-th test state (z, ż) of n coordinates: smooth, all components non-zero.
pub fn state(n: usize, k: usize) -> (DVector<f64>, DVector<f64>) {
    let z = DVector::from_fn(n, |i, _| 0.2 * ((i * 7 + k * 13) as f64 * 0.37).sin());
    let zd = DVector::from_fn(n, |i, _| 0.9 * ((i * 3 + k * 5) as f64 * 0.91).cos());
    (z, zd)
}

/// The right-hand side of Lagrange's equations, −Ṁ ż + ∂T/∂z − ∂V/∂z with T = ½ żᵀ M(z) ż and
/// V the gravity and elastic potential, by central differences of step `eps` (M at t = 0.3).
pub fn lagrange_forces(
    f: &mut Relative,
    z: &DVector<f64>,
    zd: &DVector<f64>,
    eps: f64,
) -> DVector<f64> {
    let n = z.len();
    let zero = DVector::zeros(n);
    let mp = terms_at(f, 0.3, &(z + eps * zd), zd).mass;
    let mm = terms_at(f, 0.3, &(z - eps * zd), zd).mass;
    let mdot_zd = (mp - mm) * zd / (2.0 * eps);
    let mut rhs = -mdot_zd;
    for c in 0..n {
        let mut e = DVector::zeros(n);
        e[c] = eps;
        let tp = 0.5 * zd.dot(&(terms_at(f, 0.3, &(z + &e), zd).mass * zd));
        let tm = 0.5 * zd.dot(&(terms_at(f, 0.3, &(z - &e), zd).mass * zd));
        let vp = f.total_energy(&(z + &e), &zero);
        let vm = f.total_energy(&(z - &e), &zero);
        rhs[c] += (tp - tm) / (2.0 * eps) - (vp - vm) / (2.0 * eps);
    }
    rhs
}
