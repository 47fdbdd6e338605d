//! Shared helpers of the relative formulation's physics tests: the shared scenes and runs of
//! `flexmbd_test_support::scenes`, and a run in the relative formulation.
#![allow(dead_code, unused_imports)]

use flexmbd_model::{FormulationKind, PreparedScene, Scene};
pub use flexmbd_test_support::scenes::{four_bar, model, planar_scene_in_3d, run_with, settings};

/// Run `scene` in the relative formulation: sensor rows every `every` steps, largest ‖Φ‖∞.
pub fn run_relative(scene: &Scene, h: f64, duration: f64, every: usize) -> (Vec<Vec<f64>>, f64) {
    let mut s = scene.clone();
    s.solver.formulation = FormulationKind::Relative;
    let mut f = PreparedScene::new(&s)
        .and_then(|p| flexmbd_relative::compile(&p))
        .unwrap();
    run_with(&mut f, &s, h, duration, every)
}
