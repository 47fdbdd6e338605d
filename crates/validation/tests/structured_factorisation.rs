//! The structured factorisations of the leading matrix (`flexmbd_integrators::structured`)
//! against the dense one, on the Iltis vehicle (`models/iltis_vehicle.ron`): the integrator
//! finds the structure by itself, and the trajectory is the dense path's to round-off — same
//! Newton iterations, positions within 1e-10 (m, rad) after 0.2 s (the Newton tolerance is
//! 1e-9).
//!
//! - Natural coordinates (204 coordinates rigid, 280 with 12 flexible bodies): a factor about
//!   16 % full, the sparse Cholesky (`sparse_llt`).
//! - Relative coordinates (42 rigid, 118 with 12 flexible bodies): the arrow form of the tree
//!   (`arrow_llt`), the chassis's six coordinates the border, the four corners the blocks.

use flexmbd::integrators::{Ali3p, Ali3pSettings};
use flexmbd::model::FormulationKind;
use flexmbd_test_support::iltis::vehicle_flexible;

/// 200 steps of the vehicle from its nominal (not static) position, with the structured
/// factorisations allowed or not: (positions, stats).
fn run(
    form: FormulationKind,
    flexible: usize,
    structured: bool,
) -> (Vec<f64>, flexmbd::integrators::Stats) {
    let scene = flexmbd_test_support::scenes::model_with(
        "iltis_vehicle.ron",
        form,
        &vehicle_flexible(flexible),
    );
    let mut f = flexmbd::simulation::compile(&scene).expect("the vehicle compiles");
    let settings = Ali3pSettings {
        structured_factorisation: structured,
        ..flexmbd::integrator_settings(&scene.solver)
    };
    let mut integrator = Ali3p::new(f.as_mut(), 0.0, settings).expect("consistent start");
    for _ in 0..200 {
        integrator.step(f.as_mut()).expect("the step converges");
    }
    (integrator.q.as_slice().to_vec(), integrator.stats.clone())
}

#[test]
fn the_structured_factorisations_follow_the_dense_one_on_the_vehicle() {
    for form in [FormulationKind::Absolute, FormulationKind::Relative] {
        for flexible in [0, 12] {
            let (q_structured, structured) = run(form, flexible, true);
            let (q_dense, dense) = run(form, flexible, false);
            assert_eq!(
                structured.structured_factorizations,
                structured.factorizations
            );
            assert_eq!(dense.structured_factorizations, 0);
            assert_eq!(structured.newton_iterations, dense.newton_iterations);
            let difference = q_structured
                .iter()
                .zip(&q_dense)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            eprintln!(
                "{form:?}, {flexible} flexible: {} coordinates, |Δq| ≤ {difference:.2e}",
                q_dense.len()
            );
            assert!(
                difference < 1e-10,
                "{form:?}, {flexible} flexible: |Δq| = {difference:e}"
            );
        }
    }
}
