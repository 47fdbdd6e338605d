//! Steps of the spin-up beam with FS0 (or another stiffening), for instruction counts:
//!
//! ```text
//! cargo run --release -p flexmbd-benches --example fs0_steps -- DIM FORM INERTIA LEAD STEPS [STIFF]
//! ```
//!
//! DIM `2d`/`3d`, FORM `relative`/`absolute`, INERTIA `bmatrix`/`shape`, LEAD steps of lead-in,
//! then STEPS measured steps (STIFF: `fs0` default, `fnl1`). Run it twice under
//! `perf stat -e instructions:u` (STEPS = N and STEPS = 0): the difference over N is the
//! instruction count of one step. Prints the tip displacement at the end (a checksum).

use std::path::PathBuf;

use flexmbd::body::InertiaMethod;
use flexmbd::integrators::{Ali3p, Ali3pSettings};
use flexmbd::model::{FormulationKind, Scene, Stiffening};
use flexmbd::simulation::compile;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let usage = "DIM(2d|3d) FORM(relative|absolute) INERTIA(bmatrix|shape) LEAD STEPS [fs0|fnl1]";
    assert!(a.len() >= 6, "usage: {usage}");
    let file = match a[1].as_str() {
        "2d" => "spin_up_beam_2d.ron",
        "3d" => "spin_up_beam_3d.ron",
        _ => panic!("usage: {usage}"),
    };
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../models")
        .join(file);
    let mut scene = Scene::load(&path).expect("scene loads");
    scene.solver.formulation = match a[2].as_str() {
        "relative" => FormulationKind::Relative,
        "absolute" => FormulationKind::Absolute,
        _ => panic!("usage: {usage}"),
    };
    scene.solver.inertia = match a[3].as_str() {
        "bmatrix" => InertiaMethod::BMatrix,
        "shape" => InertiaMethod::ShapeIntegrals,
        _ => panic!("usage: {usage}"),
    };
    scene.solver.stiffening = match a.get(6).map(String::as_str) {
        None | Some("fs0") => Stiffening::Foreshortening,
        Some("fnl1") => Stiffening::Fnl1,
        _ => panic!("usage: {usage}"),
    };
    let lead: usize = a[4].parse().expect("LEAD");
    let steps: usize = a[5].parse().expect("STEPS");
    let mut f = compile(&scene).expect("compiles");
    let settings = Ali3pSettings {
        step: scene.solver.step,
        ..Default::default()
    };
    let mut integ = Ali3p::new(f.as_mut(), 0.0, settings).expect("consistent start");
    for _ in 0..lead + steps {
        integ.step(f.as_mut()).expect("step");
    }
    let mut s = vec![0.0; f.sensor_names().len()];
    let t = integ.t;
    f.sensors(integ.state(), &mut s);
    println!(
        "t = {t:.3}, {} coordinates, sensors {:?}",
        f.n_coordinates(),
        f.sensor_names().iter().zip(&s).collect::<Vec<_>>()
    );
}
