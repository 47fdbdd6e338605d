//! Shared helpers of the relative formulation's physics tests: the shared scenes and runs of
//! `flexmbd_test_support::scenes`, a run in the relative formulation, the test states, the
//! dense products the recursive terms are checked against, the differences of Φ the
//! constraint terms are checked against, and the Lagrange right-hand side.
#![allow(dead_code, unused_imports)]

use flexmbd_core::{Formulation, SystemTerms};
use flexmbd_model::{FormulationKind, Scene};
use flexmbd_relative::Relative;
pub use flexmbd_test_support::scenes::*;
use nalgebra::{DMatrix, DVector};

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

/// `check(f, z, ż, terms)` at the test states `ks` ([`state`]) of `scene` in the relative
/// formulation, with all its terms there at t = 0.3.
pub fn at_test_states(
    scene: &Scene,
    ks: impl IntoIterator<Item = usize>,
    mut check: impl FnMut(&mut Relative, DVector<f64>, DVector<f64>, SystemTerms),
) {
    let mut f = relative(scene);
    let n = f.n_coordinates();
    for k in ks {
        let (z, zd) = state(n, k);
        let terms = terms_at(&mut f, 0.3, &z, &zd);
        check(&mut f, z, zd, terms);
    }
}

/// Dense R_k of every body k (rows: its Z_k) at z, column c its velocity at ż = e_c.
pub fn dense_r(f: &mut Relative, z: &DVector<f64>) -> Vec<DMatrix<f64>> {
    let n = f.n_coordinates();
    (0..f.n_bodies())
        .map(|k| {
            let nc = f.rigid_size() + f.body_modes(k).1;
            let mut r = DMatrix::zeros(nc, n);
            for c in 0..n {
                let mut e = DVector::zeros(n);
                e[c] = 1.0;
                let (v, _) = f.body_velocity(z, &e, k);
                r.column_mut(c).copy_from(&v);
            }
            r
        })
        .collect()
}

/// M and Q as dense products over the bodies at (z, ż), given their R_k (`dense_r`):
/// Σ_k R_kᵀ M̄_k R_k and Σ_k R_kᵀ (Q̄_k − M̄_k D_k), D_k = Ṙ_k ż.
pub fn dense_terms(
    f: &mut Relative,
    z: &DVector<f64>,
    zd: &DVector<f64>,
    r: &[DMatrix<f64>],
) -> (DMatrix<f64>, DVector<f64>) {
    let n = z.len();
    let mut m = DMatrix::zeros(n, n);
    let mut q = DVector::zeros(n);
    for (b, r) in r.iter().enumerate() {
        let (mb, qb) = f.body_terms(z, zd, b);
        let (_, d) = f.body_velocity(z, zd, b);
        m += r.transpose() * &mb * r;
        q += r.transpose() * (&qb - &mb * &d);
    }
    (m, q)
}

/// Φ_z ż + Φ_t and c of `terms` (at (z, ż)) against the first and second central differences
/// of Φ along z + s ż (step 1e-5, Φ at t = 0.3): the relative errors of both.
pub fn constraint_rate_errors(
    f: &mut Relative,
    z: &DVector<f64>,
    zd: &DVector<f64>,
    terms: &SystemTerms,
) -> (f64, f64) {
    let eps = 1e-5;
    let mut phi_at = |s: f64| terms_at(f, 0.3, &(z + s * zd), zd).phi;
    let (pp, p0, pm) = (phi_at(eps), phi_at(0.0), phi_at(-eps));
    let vel = (&pp - &pm) / (2.0 * eps);
    let acc = (&pp - 2.0 * &p0 + &pm) / (eps * eps);
    let ev = (&terms.phi_q * zd + &terms.phi_t - &vel).amax() / vel.amax().max(1.0);
    let ea = (&terms.accel_term - &acc).amax() / acc.amax().max(1.0);
    (ev, ea)
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
