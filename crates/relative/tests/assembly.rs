//! §4.5 step 8 and §8 items 6–7: the recursive M and Q against the dense Rᵀ M̄ R and
//! Rᵀ (Q̄ − M̄ Ṙ ż) built here column by column, D against a difference of the velocities,
//! and Q against Lagrange's equations by finite differences.

mod common;
use common::*;
use flexmbd_core::Formulation;
use flexmbd_model::Scene;

fn check_assembly(scene: &Scene) {
    at_test_states(scene, 0..4, |f, z, zd, t| {
        let r = dense_r(f, &z);
        let (m, q) = dense_terms(f, &z, &zd, &r);
        let mut d_err = 0.0f64;
        for b in 0..f.n_bodies() {
            let (v, d) = f.body_velocity(&z, &zd, b);
            assert!((&r[b] * &zd - &v).amax() < 1e-13, "Z = R ż");
            // Ṙ ż by a central difference of R along ż (no modal part).
            let eps = 1e-6;
            let rp = dense_r(f, &(&z + eps * &zd));
            let rm = dense_r(f, &(&z - eps * &zd));
            let d_fd = (&rp[b] - &rm[b]) * &zd / (2.0 * eps);
            d_err = d_err.max((&d_fd - &d).amax() / d.amax().max(1.0));
        }
        let dm = (&t.mass - &m).amax() / m.amax();
        let dq = (&t.forces - &q).amax() / q.amax();
        eprintln!(
            "{}: |M − RᵀM̄R| {dm:.1e}, |Q − Rᵀ(Q̄ − M̄Ṙż)| {dq:.1e}, D vs difference {d_err:.1e}",
            scene.name
        );
        assert!(dm < 1e-13 && dq < 1e-13, "dm {dm:e} dq {dq:e}");
        assert!(d_err < 1e-7, "D {d_err:e}");
    });
}

/// Q = −Ṁ ż + ∂T/∂z − ∂V/∂z with T = ½ żᵀ M(z) ż and V the gravity and elastic potential.
fn check_lagrange(scene: &Scene) {
    at_test_states(scene, 7..10, |f, z, zd, t| {
        let rhs = lagrange_forces(f, &z, &zd, 1e-6);
        let err = (&t.forces - &rhs).amax() / t.forces.amax().max(1.0);
        eprintln!("{}: Q vs Lagrange {err:.1e}", scene.name);
        assert!(err < 1e-6, "Lagrange {err:e}");
    });
}

/// Φ_z and c against differences of Φ along z(t) = z + t ż.
fn check_constraints(scene: &Scene) {
    at_test_states(scene, 3..6, |f, z, zd, t| {
        let (ev, ea) = constraint_rate_errors(f, &z, &zd, &t);
        eprintln!(
            "{}: Φ_z ż vs difference {ev:.1e}, c vs second difference {ea:.1e}",
            scene.name
        );
        assert!(ev < 1e-7 && ea < 1e-4, "ev {ev:e} ea {ea:e}");
    });
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
