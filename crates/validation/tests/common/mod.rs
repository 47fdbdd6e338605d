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
