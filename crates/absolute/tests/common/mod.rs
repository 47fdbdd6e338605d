//! Shared by the absolute formulation's tests: a scene compiled, all system terms at a
//! state (`terms_at`, from the shared test support), the ALI3-P step loop's allocations, a driven coordinate's error against its law, and
//! the frequency of a signal.
#![allow(dead_code, unused_imports)]

use flexmbd_absolute::Absolute;
use flexmbd_body::InertiaMethod;
use flexmbd_core::{Formulation, Request, State, SystemTerms};
use flexmbd_integrators::{Ali3p, Ali3pSettings};
use flexmbd_model::{MotionLaw, Scene};
use nalgebra::DVector;

/// `scene` prepared and compiled in natural coordinates (panics on an error).
pub use flexmbd_test_support::scenes::{
    ali3p_at, drift, flexible_pendulum_energy_drift, largest_difference, record, sensor_column,
    spring_gradient_error, terms_at, with_and_without_forces,
};

pub fn absolute(scene: &Scene) -> Absolute {
    flexmbd_test_support::scenes::compiled(scene, flexmbd_absolute::compile)
}

/// The allocations of `steps` ALI3-P steps (default settings) of `scene`, after a first step.
pub fn step_loop_allocations(scene: &Scene, steps: usize) -> usize {
    let mut f = absolute(scene);
    let mut s = Ali3p::new(&mut f, 0.0, Ali3pSettings::default()).unwrap();
    s.step(&mut f).unwrap();
    flexmbd_test_support::allocations_in(|| {
        for _ in 0..steps {
            s.step(&mut f).unwrap();
        }
    })
}

/// Both inertia routes of `scene` step without allocating (`steps` steps after the first).
pub fn assert_steps_allocate_nothing(mut scene: Scene, steps: usize) {
    for method in [InertiaMethod::ShapeIntegrals, InertiaMethod::BMatrix] {
        scene.solver.inertia = method;
        let allocated = step_loop_allocations(&scene, steps);
        assert_eq!(
            allocated, 0,
            "{method:?}: the step loop allocated {allocated} times"
        );
    }
}

/// The largest |x − law(t)| of the first sensor column, its rows at t = 0, h, 2h, …
pub fn law_error(rows: &[Vec<f64>], law: &MotionLaw, h: f64) -> f64 {
    rows.iter()
        .enumerate()
        .map(|(k, r)| (r[0] - law.eval(k as f64 * h).0).abs())
        .fold(0.0, f64::max)
}

/// Frequency of a signal from its zero crossings (linear interpolation), in Hz.
pub fn crossing_frequency(t: &[f64], x: &[f64]) -> f64 {
    let mut crossings = Vec::new();
    for i in 1..x.len() {
        if x[i - 1] != 0.0 && x[i - 1].signum() != x[i].signum() {
            crossings.push(t[i - 1] + (t[i] - t[i - 1]) * x[i - 1] / (x[i - 1] - x[i]));
        }
    }
    assert!(crossings.len() >= 4, "too few crossings");
    let span = crossings[crossings.len() - 1] - crossings[0];
    (crossings.len() - 1) as f64 / (2.0 * span)
}
