//! The sparse Cholesky of large leading matrices (`flexmbd_integrators::sparse_llt`) against
//! the dense one, on the Iltis vehicle in natural coordinates (`models/iltis_vehicle.ron`,
//! absolute formulation: 204 coordinates rigid, 280 with 12 flexible bodies), whose factor is
//! about 16 % full: the integrator takes the sparse path by itself, and the trajectory is
//! the dense path's to round-off — same Newton iterations, positions within 1e-10 m after
//! 0.2 s (the Newton tolerance is 1e-9). The relative formulation of the same vehicle keeps
//! the dense kernels (its factor is too full to gain).

use flexmbd::integrators::{Ali3p, Ali3pSettings};
use flexmbd::model::FormulationKind;
use flexmbd_test_support::iltis::vehicle_flexible;

/// 200 steps of the vehicle from its nominal (not static) position, with the sparse
/// factorisation allowed or not: (positions, stats).
fn run(
    form: FormulationKind,
    flexible: usize,
    sparse: bool,
) -> (Vec<f64>, flexmbd::integrators::Stats) {
    let scene = flexmbd_test_support::scenes::model_with(
        "iltis_vehicle.ron",
        form,
        &vehicle_flexible(flexible),
    );
    let mut f = flexmbd::simulation::compile(&scene).expect("the vehicle compiles");
    let settings = Ali3pSettings {
        sparse_factorisation: sparse,
        ..flexmbd::integrator_settings(&scene.solver)
    };
    let mut integrator = Ali3p::new(f.as_mut(), 0.0, settings).expect("consistent start");
    for _ in 0..200 {
        integrator.step(f.as_mut()).expect("the step converges");
    }
    (integrator.q.as_slice().to_vec(), integrator.stats.clone())
}

#[test]
fn the_sparse_cholesky_follows_the_dense_one_on_the_absolute_vehicle() {
    for flexible in [0, 12] {
        let (q_sparse, sparse) = run(FormulationKind::Absolute, flexible, true);
        let (q_dense, dense) = run(FormulationKind::Absolute, flexible, false);
        assert_eq!(sparse.sparse_factorizations, sparse.factorizations);
        assert_eq!(dense.sparse_factorizations, 0);
        assert_eq!(sparse.newton_iterations, dense.newton_iterations);
        let difference = q_sparse
            .iter()
            .zip(&q_dense)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "{flexible} flexible: {} coordinates, |Δq| ≤ {difference:.2e}",
            q_dense.len()
        );
        assert!(
            difference < 1e-10,
            "{flexible} flexible: |Δq| = {difference:e}"
        );
    }
}

#[test]
fn the_relative_vehicle_keeps_the_dense_kernels() {
    let (_, stats) = run(FormulationKind::Relative, 12, true);
    assert_eq!(stats.sparse_factorizations, 0);
    assert!(stats.factorizations > 0);
}
