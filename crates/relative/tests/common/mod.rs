//! Shared helpers of the physics tests.
#![allow(dead_code)]

use flexmbd_core::Formulation;
use flexmbd_integrators::{Ali3p, Ali3pSettings};
use flexmbd_model::{FormulationKind, Scene};

pub const BARS: [&str; 5] = ["crank1", "coupler1", "crank2", "coupler2", "crank3"];

pub fn model(name: &str) -> Scene {
    Scene::load(format!(
        "{}/../../models/{name}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
}

/// The double four-bar with the first `flexible` bars flexible.
pub fn four_bar(flexible: usize) -> Scene {
    let mut s = model("double_four_bar.ron");
    for b in s
        .bodies
        .iter_mut()
        .filter(|b| BARS[..flexible].contains(&b.name.as_str()))
    {
        b.flexible = true;
    }
    s
}

pub fn settings(scene: &Scene, h: f64) -> Ali3pSettings {
    Ali3pSettings {
        step: h,
        tol_q: scene.solver.newton_tolerance,
        tol_phi: scene.solver.newton_tolerance,
        max_iterations: scene.solver.max_iterations,
        penalty: scene.solver.penalty,
        ..Default::default()
    }
}

/// Run a compiled formulation; the sensor rows at every `every` steps (and t = 0), plus
/// the largest ‖Φ‖∞ after a step.
pub fn run_with<F: Formulation>(
    f: &mut F,
    scene: &Scene,
    h: f64,
    duration: f64,
    every: usize,
) -> (Vec<Vec<f64>>, f64) {
    let mut s = Ali3p::new(f, 0.0, settings(scene, h)).unwrap();
    let ns = f.sensor_names().len();
    let mut rows = Vec::new();
    let mut row = vec![0.0; ns];
    f.sensors(0.0, &s.q, &s.qd, &mut row);
    rows.push(row.clone());
    let steps = (duration / h).round() as usize;
    let mut phi_max = 0.0f64;
    let mut terms = flexmbd_core::SystemTerms::new(f.n_coordinates(), f.n_constraints());
    for k in 1..=steps {
        s.step(f).unwrap();
        if k % every == 0 {
            f.sensors(s.t, &s.q, &s.qd, &mut row);
            rows.push(row.clone());
            terms.clear(flexmbd_core::Request::CONSTRAINTS);
            f.evaluate(
                s.t,
                &s.q,
                &s.qd,
                flexmbd_core::Request::CONSTRAINTS,
                &mut terms,
            );
            phi_max = phi_max.max(terms.phi.amax());
        }
    }
    (rows, phi_max)
}

pub fn run_relative(scene: &Scene, h: f64, duration: f64, every: usize) -> (Vec<Vec<f64>>, f64) {
    let mut s = scene.clone();
    s.solver.formulation = FormulationKind::Relative;
    let mut f = flexmbd_model::PreparedScene::new(&s)
        .and_then(|p| flexmbd_relative::compile(&p))
        .unwrap();
    run_with(&mut f, &s, h, duration, every)
}

pub fn run_absolute(scene: &Scene, h: f64, duration: f64, every: usize) -> (Vec<Vec<f64>>, f64) {
    let mut f = flexmbd_model::PreparedScene::new(scene)
        .and_then(|p| flexmbd_absolute::compile(&p))
        .unwrap();
    run_with(&mut f, scene, h, duration, every)
}
