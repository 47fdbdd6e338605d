//! The 2D (or 3D) spin-up beam with every available stiffening method, against the ANCF
//! reference (docs/methods.md §6, §7; docs/scenes.md §5): max |Δu_x|, |Δu_y| (|Δu_z|) over the run,
//! CPU time and Newton iterations per step.
//!
//! `cargo run --release -p flexmbd-validation --example spin_up_methods -- [2d|3d] [duration] [absolute|relative]`
//! with `SPIN_UP_METHODS=linear,fnl1,fnl2,sb5,sb10,sb20` (substructuring runs relative).

use flexmbd::model::{FormulationKind, Scene, Stiffening};
use flexmbd::simulation::run;
use flexmbd_ancf::{Cable, CableSpec, History, run_cable, run_spin_up};
use flexmbd_core::Dim;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dim = if args.get(1).map(String::as_str) == Some("3d") {
        Dim::Spatial
    } else {
        Dim::Planar
    };
    let duration: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20.0);
    let formulation = match args.get(3).map(String::as_str) {
        Some("relative") => FormulationKind::Relative,
        _ => FormulationKind::Absolute,
    };
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/");
    let file = match dim {
        Dim::Planar => "spin_up_beam_2d.ron",
        Dim::Spatial => "spin_up_beam_3d.ron",
    };
    // SPIN_UP_SCENE=path runs another scene file (e.g. another axial basis).
    let path = std::env::var("SPIN_UP_SCENE").unwrap_or_else(|_| format!("{root}{file}"));
    // SPIN_UP_METHODS=linear,fnl1,fnl2,sb5,sb10,sb20 (default linear,fnl1,fnl2).
    let methods: Vec<Stiffening> = std::env::var("SPIN_UP_METHODS")
        .unwrap_or_else(|_| "linear,fnl1,fnl2".into())
        .split(',')
        .map(|m| match m {
            "linear" => Stiffening::Linear,
            "fnl1" => Stiffening::Fnl1,
            "fnl2" => Stiffening::Fnl2,
            sb => Stiffening::Substructuring(
                sb.trim_start_matches("sb").parse().expect("method name"),
            ),
        })
        .collect();
    let t0 = std::time::Instant::now();
    // 3D: the scene starts undeformed at rest (no static start), so the reference does too
    // unless SPIN_UP_STATIC_START is set.
    let reference = if dim == Dim::Spatial && std::env::var("SPIN_UP_STATIC_START").is_err() {
        ancf_from_rest(&CableSpec::spin_up_beam(dim, 16), 1e-3, duration, 0.01)
    } else {
        run_spin_up(&CableSpec::spin_up_beam(dim, 16), 1e-3, duration, 0.01)
            .expect("ANCF reference")
    };
    println!(
        "ANCF 16 elements: {:.2} s CPU, min u_y {:.4} m",
        t0.elapsed().as_secs_f64(),
        reference.min(1)
    );
    let nc = if dim == Dim::Spatial { 3 } else { 2 };
    for st in methods {
        let mut scene = Scene::load(&path).expect("scene");
        scene.solver.stiffening = st;
        scene.solver.duration = duration;
        scene.solver.formulation = match st {
            Stiffening::Substructuring(_) => FormulationKind::Relative,
            _ => formulation,
        };
        let (summary, hist) = run(&scene, |_| {}).expect("compile");
        let cols = ["tip_x", "tip_y", "tip_z"];
        let mut err = [0.0_f64; 3];
        let mut when = [0.0_f64; 3];
        for c in 0..nc {
            let v = hist.column(cols[c]).expect("sensor");
            for (k, val) in v.iter().enumerate() {
                let u = if c == 0 { val - 10.0 } else { *val };
                if k < reference.tip.len() {
                    let d = (u - reference.tip[k][c]).abs();
                    if d > err[c] || d.is_nan() {
                        err[c] = d;
                        when[c] = reference.t[k];
                    }
                }
            }
        }
        println!(
            "{st:?}: status {} {} n = {}, max |Δu| (mm) x {:.3} (t {:.2}) y {:.3} (t {:.2}) z {:.3}, cpu {:.2} s, Newton/step {:.3}, min u_y {:.4}",
            summary.status,
            summary.message.clone().unwrap_or_default(),
            summary.n_coordinates,
            err[0] * 1e3,
            when[0],
            err[1] * 1e3,
            when[1],
            err[2] * 1e3,
            summary.cpu_seconds,
            summary.newton_iterations as f64 / summary.steps.max(1) as f64,
            hist.column("tip_y")
                .unwrap()
                .iter()
                .fold(f64::INFINITY, |a, v| a.min(*v)),
        );
    }
}

/// The ANCF spin-up started undeformed at rest (as the scene files start), recording the
/// tip displacement in the turning frame every `every_s` seconds.
fn ancf_from_rest(spec: &CableSpec, h: f64, duration: f64, every_s: f64) -> History {
    let settings = flexmbd::integrators::Ali3pSettings {
        step: h,
        ..Default::default()
    };
    let mut cable = Cable::new(spec).expect("cable");
    run_cable(&mut cable, settings, duration, every_s).expect("ANCF run")
}
