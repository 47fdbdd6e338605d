//! One ALI3-P integration step of the double four-bar (docs/scenes.md §1), absolute
//! formulation, h = 1 ms, with 0 to 5 flexible bars (crank1, coupler1, crank2,
//! coupler2, crank3 in that order) and each inertia route.
//!
//! The mechanism is first stepped to t = 0.1 s, away from the initial state and from
//! the singular configuration; every measured step then starts from that same state
//! (restored outside the timed region), so each sample solves the same step with the
//! same number of Newton iterations.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use flexmbd::body::InertiaMethod;
use flexmbd::integrator_settings;
use flexmbd::integrators::Ali3p;
use flexmbd::model::Scene;
use flexmbd::simulation::compile;

const BARS: [&str; 5] = ["crank1", "coupler1", "crank2", "coupler2", "crank3"];
/// Steps taken before measuring (0.1 s at h = 1 ms).
const LEAD_IN: usize = 100;

fn scene(k: usize, method: InertiaMethod) -> Scene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../models/double_four_bar.ron");
    let mut scene = Scene::load(&path).expect("the double four-bar scene loads");
    let sets: Vec<(String, String)> = BARS[..k]
        .iter()
        .map(|b| (format!("bodies.{b}.flexible"), "true".to_string()))
        .collect();
    scene.apply_sets(&sets).expect("the bars exist");
    scene.solver.inertia = method;
    scene
}

fn step(c: &mut Criterion) {
    let mut group = c.benchmark_group("four_bar_step");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_millis(1000));
    for (method, name) in [
        (InertiaMethod::ShapeIntegrals, "shape_integrals"),
        (InertiaMethod::BMatrix, "b_matrix"),
    ] {
        for k in 0..=5usize {
            let sc = scene(k, method);
            let settings = integrator_settings(&sc.solver);
            let mut f = compile(&sc).expect("the scene compiles");
            let mut integ =
                Ali3p::new(f.as_mut(), 0.0, settings).expect("consistent initial conditions");
            for _ in 0..LEAD_IN {
                integ.step(f.as_mut()).expect("lead-in step");
            }
            let start = integ.checkpoint();
            let start_iterations = integ.stats.newton_iterations;
            // The step measured: how many Newton iterations it takes.
            integ.step(f.as_mut()).expect("measured step");
            eprintln!(
                "four_bar_step/{name}/{k}: n = {}, m = {}, {} Newton iterations in the measured step",
                f.n_coordinates(),
                f.n_constraints(),
                integ.stats.newton_iterations - start_iterations
            );
            group.bench_with_input(BenchmarkId::new(name, k), &k, |b, _| {
                b.iter_custom(|iters| {
                    let mut total = Duration::ZERO;
                    for _ in 0..iters {
                        integ.restore(&start);
                        let t = Instant::now();
                        integ.step(f.as_mut()).expect("step");
                        total += t.elapsed();
                    }
                    std::hint::black_box(&integ.q);
                    total
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, step);
criterion_main!(benches);
