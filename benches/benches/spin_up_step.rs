//! One ALI3-P step of the 2D spin-up beam (docs/scenes.md §5, h = 1 ms) with each stiffening
//! method in each formulation that runs it (thesis ch. 4; the targets are for the
//! whole 20 s: FS0 and FNL1 in 40 ms relative, 80 ms absolute, i.e. 2 and 4 µs per step).
//! Every measured step starts from the same state at t = 8 s (mid spin-up).
//!
//! FS0 rows: `fs0` (the scene's default inertia route, the FS0 shape integrals), `fs0_bmatrix`
//! (the B-matrix projection over the 80-point cloud, the reference), and the 3D beam
//! (docs/scenes.md §5 scene F, gravity, 8 bending modes, 320-point cloud) by both routes:
//! `fs0_3d`, `fs0_3d_bmatrix`.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use flexmbd::body::InertiaMethod;
use flexmbd::integrators::{Ali3p, Ali3pSettings};
use flexmbd::model::{FormulationKind, Scene, Stiffening};
use flexmbd::simulation::compile;

/// (row, scene file, stiffening, inertia route if not the scene's default).
const METHODS: [(&str, &str, Stiffening, Option<InertiaMethod>); 8] = [
    ("fnl1", "spin_up_beam_2d.ron", Stiffening::Fnl1, None),
    ("fnl2", "spin_up_beam_2d.ron", Stiffening::Fnl2, None),
    (
        "fs0",
        "spin_up_beam_2d.ron",
        Stiffening::Foreshortening,
        None,
    ),
    (
        "fs0_bmatrix",
        "spin_up_beam_2d.ron",
        Stiffening::Foreshortening,
        Some(InertiaMethod::BMatrix),
    ),
    (
        "fs0_3d",
        "spin_up_beam_3d.ron",
        Stiffening::Foreshortening,
        None,
    ),
    (
        "fs0_3d_bmatrix",
        "spin_up_beam_3d.ron",
        Stiffening::Foreshortening,
        Some(InertiaMethod::BMatrix),
    ),
    (
        "sb10",
        "spin_up_beam_2d.ron",
        Stiffening::Substructuring(10),
        None,
    ),
    (
        "sb20",
        "spin_up_beam_2d.ron",
        Stiffening::Substructuring(20),
        None,
    ),
];

fn spin_up(c: &mut Criterion) {
    let mut group = c.benchmark_group("spin_up_step");
    group
        .sample_size(15)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_millis(600));
    let models = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../models");
    for (form, fname) in [
        (FormulationKind::Relative, "relative"),
        (FormulationKind::Absolute, "absolute"),
    ] {
        for &(name, file, stiffening, inertia) in &METHODS {
            let mut scene = Scene::load(models.join(file)).expect("the spin-up scene loads");
            scene.solver.formulation = form;
            scene.solver.stiffening = stiffening;
            if let Some(m) = inertia {
                scene.solver.inertia = m;
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
            let start = integ.checkpoint();
            eprintln!(
                "spin_up_step/{fname}/{name}: {} coordinates",
                f.n_coordinates()
            );
            group.bench_with_input(BenchmarkId::new(fname, name), &name, |b, _| {
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

criterion_group!(benches, spin_up);
criterion_main!(benches);
