//! What the facade's test binaries share: the flexible pendulum set up in each formulation.

use flexmbd::model::{FormulationKind, Scene};
use flexmbd_test_support::scenes::model;

/// `models/flexible_pendulum.ron` in the absolute then the relative formulation, run for
/// `duration` s with a row every `output_interval` s (`None`: every step).
pub fn flexible_pendulums(duration: f64, output_interval: Option<f64>) -> [Scene; 2] {
    [FormulationKind::Absolute, FormulationKind::Relative].map(|form| {
        let mut scene = model("flexible_pendulum.ron");
        scene.solver.formulation = form;
        scene.solver.duration = duration;
        scene.solver.output_interval = output_interval;
        scene
    })
}
