//! Shared helpers of the validation tests: the shared scenes and runs of
//! `flexmbd_test_support::scenes`, and a run in each formulation.
#![allow(dead_code, unused_imports)]

use flexmbd_model::{FormulationKind::Relative, Scene};
pub use flexmbd_test_support::scenes::*;

/// `scene` prepared and compiled in the relative formulation (panics on an error).
pub fn relative(scene: &Scene) -> flexmbd_relative::Relative {
    compiled(scene, flexmbd_relative::compile)
}

/// `scene` prepared and compiled in the absolute formulation (panics on an error).
pub fn absolute(scene: &Scene) -> flexmbd_absolute::Absolute {
    compiled(scene, flexmbd_absolute::compile)
}

/// Run `scene` in the relative formulation: sensor rows every `every` steps for `secs`, largest
/// ‖Φ‖∞.
pub fn run_relative(scene: &Scene, h: f64, secs: f64, every: usize) -> (Vec<Vec<f64>>, f64) {
    run_as(scene, Relative, flexmbd_relative::compile, h, secs, every)
}

/// Run `scene` in the absolute formulation: sensor rows every `every` steps, largest ‖Φ‖∞.
pub fn run_absolute(scene: &Scene, h: f64, duration: f64, every: usize) -> (Vec<Vec<f64>>, f64) {
    run_compiled(scene, flexmbd_absolute::compile, h, duration, every)
}

/// The 12-flexible-body Iltis vehicle (`models/iltis_vehicle.ron`, relative coordinates)
/// from its moving static start, `steps` steps with the scene's integrator settings changed
/// by `settings`: its coordinates at the end and the Newton iterations it took (panics on a
/// failed step, naming `label`).
pub fn flexible_vehicle_run(
    label: &str,
    settings: impl FnOnce(flexmbd::integrators::Ali3pSettings) -> flexmbd::integrators::Ali3pSettings,
    steps: usize,
) -> (Vec<f64>, usize) {
    use flexmbd::integrators::{Ali3p, StartFrom, StaticSettings, solve_static};
    let scene = model_with(
        "iltis_vehicle.ron",
        Relative,
        &flexmbd_test_support::iltis::vehicle_flexible(12),
    );
    let mut compiled = flexmbd::simulation::compile(&scene).expect("the vehicle compiles");
    let f = compiled.as_mut();
    let equilibrium = solve_static(f, 0.0, &StaticSettings::default()).expect("it stands");
    let (mut q, mut qd) = (equilibrium.q.clone(), equilibrium.q.clone());
    f.initial_guess(&mut q, &mut qd);
    let settings = settings(flexmbd::integrator_settings(&scene.solver));
    let mut start = StartFrom::new(f, equilibrium.q.clone(), qd);
    let mut integrator = Ali3p::new(&mut start, 0.0, settings).expect("consistent start");
    for step in 0..steps {
        if let Err(e) = integrator.step(f) {
            panic!("{label}, step {step}: {e}");
        }
    }
    let q = integrator.q.as_slice().to_vec();
    (q, integrator.stats.newton_iterations)
}
