//! §4.5 step 8 and §8 items 6–7: the recursive M and Q against the dense Rᵀ M̄ R and
//! Rᵀ (Q̄ − M̄ Ṙ ż) built here column by column, D against a difference of the velocities,
//! and Q against Lagrange's equations by finite differences.

mod common;
use common::*;
use flexmbd_core::{Formulation, SystemTerms};
use flexmbd_model::Scene;
use flexmbd_relative::Relative;
use nalgebra::{DMatrix, DVector};

fn eval(f: &mut Relative, z: &DVector<f64>, zd: &DVector<f64>) -> SystemTerms {
    terms_at(f, 0.3, z, zd)
}

/// Dense R (rows: every body's Z_k stacked) at z, by unit velocities.
fn dense_r(f: &mut Relative, z: &DVector<f64>) -> Vec<DMatrix<f64>> {
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

fn check_assembly(scene: &Scene) {
    let mut f = relative(scene);
    let n = f.n_coordinates();
    for k in 0..4 {
        let (z, zd) = state(n, k);
        let t = eval(&mut f, &z, &zd);
        let r = dense_r(&mut f, &z);
        let mut m = DMatrix::zeros(n, n);
        let mut q = DVector::zeros(n);
        let mut d_err = 0.0f64;
        for b in 0..f.n_bodies() {
            let (mb, qb) = f.body_terms(&z, &zd, b);
            let (v, d) = f.body_velocity(&z, &zd, b);
            assert!((&r[b] * &zd - &v).amax() < 1e-13, "Z = R ż");
            // Ṙ ż by a central difference of R along ż (no modal part).
            let eps = 1e-6;
            let rp = dense_r(&mut f, &(&z + eps * &zd));
            let rm = dense_r(&mut f, &(&z - eps * &zd));
            let d_fd = (&rp[b] - &rm[b]) * &zd / (2.0 * eps);
            d_err = d_err.max((&d_fd - &d).amax() / d.amax().max(1.0));
            m += r[b].transpose() * &mb * &r[b];
            q += r[b].transpose() * (&qb - &mb * &d);
        }
        let dm = (&t.mass - &m).amax() / m.amax();
        let dq = (&t.forces - &q).amax() / q.amax();
        eprintln!(
            "{}: |M − RᵀM̄R| {dm:.1e}, |Q − Rᵀ(Q̄ − M̄Ṙż)| {dq:.1e}, D vs difference {d_err:.1e}",
            scene.name
        );
        assert!(dm < 1e-13 && dq < 1e-13, "dm {dm:e} dq {dq:e}");
        assert!(d_err < 1e-7, "D {d_err:e}");
    }
}

/// Q = −Ṁ ż + ∂T/∂z − ∂V/∂z with T = ½ żᵀ M(z) ż and V the gravity and elastic potential.
fn check_lagrange(scene: &Scene) {
    let mut f = relative(scene);
    let n = f.n_coordinates();
    for k in 0..3 {
        let (z, zd) = state(n, k + 7);
        let t = eval(&mut f, &z, &zd);
        let rhs = lagrange_forces(&mut f, &z, &zd, 1e-6);
        let err = (&t.forces - &rhs).amax() / t.forces.amax().max(1.0);
        eprintln!("{}: Q vs Lagrange {err:.1e}", scene.name);
        assert!(err < 1e-6, "Lagrange {err:e}");
    }
}

/// Φ_z and c against differences of Φ along z(t) = z + t ż.
fn check_constraints(scene: &Scene) {
    let mut f = relative(scene);
    let n = f.n_coordinates();
    for k in 0..3 {
        let (z, zd) = state(n, k + 3);
        let t = eval(&mut f, &z, &zd);
        let eps = 1e-5;
        let phi_at = |f: &mut Relative, s: f64| eval(f, &(&z + s * &zd), &zd).phi;
        let (pp, p0, pm) = (
            phi_at(&mut f, eps),
            phi_at(&mut f, 0.0),
            phi_at(&mut f, -eps),
        );
        let vel = (&pp - &pm) / (2.0 * eps);
        let acc = (&pp - 2.0 * &p0 + &pm) / (eps * eps);
        let ev = (&t.phi_q * &zd + &t.phi_t - &vel).amax() / vel.amax().max(1.0);
        let ea = (&t.accel_term - &acc).amax() / acc.amax().max(1.0);
        eprintln!(
            "{}: Φ_z ż vs difference {ev:.1e}, c vs second difference {ea:.1e}",
            scene.name
        );
        assert!(ev < 1e-7 && ea < 1e-4, "ev {ev:e} ea {ea:e}");
    }
}

#[test]
fn recursive_terms_equal_the_dense_products() {
    for k in [0, 1, 5] {
        check_assembly(&four_bar(k));
    }
    check_assembly(&model("flexible_pendulum.ron"));
}

#[test]
fn generalized_forces_satisfy_lagrange() {
    for k in [0, 2, 5] {
        check_lagrange(&four_bar(k));
    }
    check_lagrange(&model("flexible_pendulum.ron"));
}

#[test]
fn constraint_jacobian_and_bias_match_differences() {
    for k in [0, 5] {
        check_constraints(&four_bar(k));
    }
}

#[test]
fn coordinate_counts_of_the_flexible_four_bar() {
    for k in 0..=5 {
        let f = relative(&four_bar(k));
        eprintln!(
            "{k} flexible bars: {} coordinates, {} constraints",
            f.n_coordinates(),
            f.n_constraints()
        );
        assert_eq!(f.n_coordinates(), 5 + 4 * k);
        assert_eq!(f.n_constraints(), 4);
    }
}
