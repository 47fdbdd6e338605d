//! Run one scene of the CPU targets for a number of ALI3-P steps, for instruction counts
//! (`valgrind --tool=callgrind --toggle-collect='*run_steps*'`) and trajectory checks.
//!
//! `steps four-bar K rel|abs [--steps N] [--save FILE] [--compare FILE]`
//! `steps spin-up fnl1|fnl2|fs0|lin rel|abs [...]`
//!
//! Prints n, m, the counters, an FNV hash of every step's (q, q̇, q̈) bits (bit-identical
//! trajectories give the same hash) and, with `--compare`, the largest difference of q
//! from a trajectory saved by `--save`.

use std::path::PathBuf;

use flexmbd::body::InertiaMethod;
use flexmbd::core::Formulation;
use flexmbd::integrator_settings;
use flexmbd::integrators::Ali3p;
use flexmbd::model::{FormulationKind, Scene, Stiffening};
use flexmbd::simulation::compile;

const BARS: [&str; 5] = ["crank1", "coupler1", "crank2", "coupler2", "crank3"];

fn models() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../models")
}

#[inline(never)]
fn run_steps(integ: &mut Ali3p, f: &mut dyn Formulation, steps: usize, traj: &mut Vec<f64>) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for _ in 0..steps {
        integ.step(f).expect("step");
        for v in integ
            .q
            .iter()
            .chain(integ.qd.iter())
            .chain(integ.qdd.iter())
        {
            hash = (hash ^ v.to_bits()).wrapping_mul(0x0100_0000_01b3);
        }
        traj.extend(integ.q.iter());
    }
    hash
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let opt = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .map(|i| args[i + 1].clone())
    };
    let form = match args[2].as_str() {
        "rel" => FormulationKind::Relative,
        "abs" => FormulationKind::Absolute,
        o => panic!("rel or abs, not {o}"),
    };
    let (mut scene, default_steps) = match args[0].as_str() {
        "four-bar" => {
            let k: usize = args[1].parse().expect("number of flexible bars");
            let mut scene = Scene::load(models().join("double_four_bar.ron")).expect("scene");
            let sets: Vec<(String, String)> = BARS[..k]
                .iter()
                .map(|b| (format!("bodies.{b}.flexible"), "true".to_string()))
                .collect();
            scene.apply_sets(&sets).expect("bars");
            scene.solver.inertia = InertiaMethod::ShapeIntegrals;
            (scene, 5000)
        }
        "spin-up" => {
            let mut scene = Scene::load(models().join("spin_up_beam_2d.ron")).expect("scene");
            scene.solver.stiffening = match args[1].as_str() {
                "fnl1" => Stiffening::Fnl1,
                "fnl2" => Stiffening::Fnl2,
                "fs0" => {
                    scene.solver.inertia = InertiaMethod::BMatrix;
                    Stiffening::Foreshortening
                }
                "lin" => Stiffening::Linear,
                o => panic!("unknown method {o}"),
            };
            (scene, 20000)
        }
        o => panic!("four-bar or spin-up, not {o}"),
    };
    scene.solver.formulation = form;
    let steps: usize = opt("--steps").map_or(default_steps, |s| s.parse().expect("steps"));
    let settings = integrator_settings(&scene.solver);
    let mut f = compile(&scene).expect("compiles");
    let mut integ = Ali3p::new(f.as_mut(), 0.0, settings).expect("consistent start");
    let n = f.n_coordinates();
    let mut traj = Vec::with_capacity(n * steps);
    let t = std::time::Instant::now();
    let hash = run_steps(&mut integ, f.as_mut(), steps, &mut traj);
    let el = t.elapsed().as_secs_f64();
    let st = &integ.stats;
    println!(
        "n = {n}, m = {}, steps = {}, newton = {} ({:.3}/step), factorizations = {}, evaluations = {}, accepted_unconverged = {}",
        f.n_constraints(),
        st.steps,
        st.newton_iterations,
        st.newton_iterations as f64 / st.steps as f64,
        st.factorizations,
        st.evaluations,
        st.accepted_unconverged
    );
    println!(
        "wall {:.3} ms ({:.3} µs/step), hash {hash:016x}",
        el * 1e3,
        el * 1e6 / steps as f64
    );
    let names = f.sensor_names().to_vec();
    let mut vals = vec![0.0; names.len()];
    f.sensors(integ.state(), &mut vals);
    let shown: Vec<String> = names
        .iter()
        .zip(&vals)
        .filter(|(n, _)| n.starts_with("B0") || n.starts_with("tip"))
        .map(|(n, v)| format!("{n} = {v:.10}"))
        .collect();
    println!("t = {:.3}: {}", integ.t, shown.join(", "));
    if let Some(path) = opt("--save") {
        let bytes: Vec<u8> = traj.iter().flat_map(|v| v.to_le_bytes()).collect();
        std::fs::write(path, bytes).expect("write");
    }
    if let Some(path) = opt("--compare") {
        let bytes = std::fs::read(path).expect("read");
        let other: Vec<f64> = bytes
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect();
        let mut worst = (0.0f64, 0usize, 0usize);
        for (i, (a, b)) in traj.iter().zip(&other).enumerate() {
            let d = (a - b).abs();
            if d > worst.0 {
                worst = (d, i / n, i % n);
            }
        }
        println!(
            "max |Δq| = {:.3e} at step {} coordinate {} (over {} steps)",
            worst.0,
            worst.1 + 1,
            worst.2,
            other.len().min(traj.len()) / n
        );
    }
}
