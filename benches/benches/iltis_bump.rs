//! The rigid IAVSD Iltis benchmark vehicle over the cosine bump (`models/iltis_bump.ron`,
//! docs/scenes.md §3.3): the whole 2.5 s run at h = 1 ms (2500 ALI3-P steps) in each
//! formulation, from the static start at 5 m/s. The start (static equilibrium, consistent
//! initial conditions) is done once; each sample restores it and integrates to 2.5 s. Issue 13's
//! target: at most 25 ms (100× real time) in the faster formulation, on one core.

use std::path::PathBuf;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use flexmbd::Simulation;
use flexmbd::model::{FormulationKind, Scene};
use flexmbd_benches::time_whole_runs;

fn bump(c: &mut Criterion) {
    let mut group = c.benchmark_group("iltis_bump_2_5_s");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for (form, name) in [
        (FormulationKind::Absolute, "absolute"),
        (FormulationKind::Relative, "relative"),
    ] {
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../models/iltis_bump.ron");
        let mut scene = Scene::load(&path).expect("the bump scene loads");
        scene.solver.formulation = form;
        let mut simulation = Simulation::new(&scene).expect("the vehicle starts");
        let start = simulation.checkpoint();
        let duration = scene.solver.duration;
        group.bench_function(name, |b| {
            b.iter_custom(|iters| time_whole_runs(&mut simulation, &start, duration, iters))
        });
    }
    group.finish();
}

criterion_group!(benches, bump);
criterion_main!(benches);
