//! One ALI3-P step of the relative (semi-recursive) formulation on planar pendulum
//! chains of 2 to 32 rigid links (1 kg, 1 m, revolute joints, gravity), released from
//! horizontal: the per-step cost should grow no faster than the cube of the coordinate
//! count (docs/methods.md §4.5, "Cost": O(n) kinematics, O(n²) assembly, O(n³)
//! factorisation). The same chains in the absolute formulation for comparison.
//! Every measured step starts from the same state at t = 0.05 s.

use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use flexmbd::integrators::{Ali3p, Ali3pSettings};
use flexmbd::model::{FormulationKind, Scene};
use flexmbd::simulation::compile;

/// A planar chain of `n` rigid links along x, pinned to the ground at the origin.
pub fn chain(n: usize, formulation: FormulationKind) -> Scene {
    let mut bodies = String::new();
    let mut joints = String::from(
        "(name: \"j0\", kind: Revolute(), body1: \"ground\", marker1: \"O\", body2: \"l0\", marker2: \"A\"),",
    );
    for i in 0..n {
        bodies.push_str(&format!(
            "(name: \"l{i}\", origin: [{i}.0, 0.0], model: Rigid(mass: 1.0, center_of_mass: [0.5, 0.0], \
             inertia: Planar(0.08333333333333333)), markers: [(name: \"A\", position: [0.0, 0.0]), \
             (name: \"B\", position: [1.0, 0.0])]),"
        ));
        if i + 1 < n {
            joints.push_str(&format!(
                "(name: \"j{}\", kind: Revolute(), body1: \"l{i}\", marker1: \"B\", body2: \"l{}\", marker2: \"A\"),",
                i + 1,
                i + 1
            ));
        }
    }
    let text = format!(
        "(name: \"chain\", dim: Planar, gravity: [0.0, -9.81], ground: [(name: \"O\", position: [0.0, 0.0])], \
         bodies: [{bodies}], joints: [{joints}], solver: (step: 1e-3, duration: 1.0))"
    );
    let mut scene = Scene::from_ron_str(&text, "chain").expect("the chain scene parses");
    scene.validate().expect("the chain scene is valid");
    scene.solver.formulation = formulation;
    scene
}

fn chains(c: &mut Criterion) {
    let mut group = c.benchmark_group("chain_step");
    group
        .sample_size(15)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_millis(800));
    for (formulation, name) in [
        (FormulationKind::Relative, "relative"),
        (FormulationKind::Absolute, "absolute"),
    ] {
        for n in [2usize, 4, 8, 16, 32] {
            let sc = chain(n, formulation);
            let mut f = compile(&sc).expect("the chain compiles");
            let settings = Ali3pSettings {
                step: 1e-3,
                ..Default::default()
            };
            let mut integ = Ali3p::new(f.as_mut(), 0.0, settings).expect("consistent start");
            for _ in 0..50 {
                integ.step(f.as_mut()).expect("lead-in step");
            }
            let start = integ.checkpoint();
            eprintln!(
                "chain_step/{name}/{n}: {} coordinates, {} constraints",
                f.n_coordinates(),
                f.n_constraints()
            );
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
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

criterion_group!(benches, chains);
criterion_main!(benches);
