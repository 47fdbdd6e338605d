//! One ALI3-P step of the 2D spin-up beam (scenes.md §5, h = 1 ms) with each stiffening
//! method in each formulation that runs it (thesis ch. 4; the targets are for the
//! whole 20 s: FS0 and FNL1 in 40 ms relative, 80 ms absolute, i.e. 2 and 4 µs per step).
//! Every measured step starts from the same state at t = 8 s (mid spin-up).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use flexmbd::body::InertiaMethod;
use flexmbd::integrators::{Ali3p, Ali3pSettings};
use flexmbd::model::{FormulationKind, Scene, Stiffening};
use flexmbd::simulation::compile;

const METHODS: [(&str, Stiffening); 5] = [
    ("fnl1", Stiffening::Fnl1),
    ("fnl2", Stiffening::Fnl2),
    ("fs0", Stiffening::Foreshortening),
    ("sb10", Stiffening::Substructuring(10)),
    ("sb20", Stiffening::Substructuring(20)),
];

fn spin_up(c: &mut Criterion) {
    let mut group = c.benchmark_group("spin_up_step");
    group
        .sample_size(15)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_millis(600));
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../models/spin_up_beam_2d.ron");
    for (form, fname) in [
        (FormulationKind::Relative, "relative"),
        (FormulationKind::Absolute, "absolute"),
    ] {
        for &(name, stiffening) in &METHODS {
            let mut scene = Scene::load(&path).expect("the spin-up scene loads");
            scene.solver.formulation = form;
            scene.solver.stiffening = stiffening;
            if stiffening == Stiffening::Foreshortening {
                scene.solver.inertia = InertiaMethod::BMatrix;
            }
            // Combinations a formulation refuses (e.g. SBn in absolute coordinates) are skipped.
            let Ok(mut f) = compile(&scene) else { continue };
            let settings = Ali3pSettings {
                step: scene.solver.step,
                ..Default::default()
            };
            let mut integ = Ali3p::new(f.as_mut(), 0.0, settings).expect("consistent start");
            for _ in 0..8000 {
                integ.step(f.as_mut()).expect("lead-in step");
            }
            let (q, qd, qdd, lambda, stats) = (
                integ.q.clone(),
                integ.qd.clone(),
                integ.qdd.clone(),
                integ.lambda.clone(),
                integ.stats.clone(),
            );
            eprintln!(
                "spin_up_step/{fname}/{name}: {} coordinates",
                f.n_coordinates()
            );
            group.bench_with_input(BenchmarkId::new(fname, name), &name, |b, _| {
                b.iter_custom(|iters| {
                    let mut total = Duration::ZERO;
                    for _ in 0..iters {
                        integ.q.copy_from(&q);
                        integ.qd.copy_from(&qd);
                        integ.qdd.copy_from(&qdd);
                        integ.lambda.copy_from(&lambda);
                        integ.stats.clone_from(&stats);
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

criterion_group!(benches, spin_up);
criterion_main!(benches);
