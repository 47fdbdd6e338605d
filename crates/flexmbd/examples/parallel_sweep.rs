//! A parameter sweep on every core: the Iltis benchmark vehicle (`models/iltis_bump.ron`,
//! docs/scenes.md §3.3) over the cosine bump at 16 forward speeds from 2.5 to 10 m/s, each
//! run independent, spread over the cores with rayon — and the same 16 runs one after the
//! other, which must give the same numbers bit for bit (a run does not depend on the thread
//! it runs on). For each speed it prints the chassis's peak rise and the smallest tyre force
//! (0: a wheel left the road). `flexmbd::sweep` does the same for work–precision grids, and
//! the Python package's `flexmbd.sweep` hands such runs to a Dask cluster.
//!
//! Run: `cargo run --release -p flexmbd --example parallel_sweep`

use flexmbd::model::{FormulationKind, Scene, parse_set};
use rayon::prelude::*;

/// Peak rise of the chassis centre of mass (m) and the smallest tyre force (N) of the bump
/// run at `speed` (m/s), with the lateral tyre dampers C_α/V of docs/scenes.md §3.4.
fn bump(base: &Scene, speed: f64) -> Result<(f64, f64), flexmbd::Error> {
    let mut scene = base.clone();
    let mut sets = vec![format!("initial_velocity.0={speed}")];
    for (corner, cornering) in [
        ("fl", 41641.0),
        ("fr", 41641.0),
        ("rl", 40162.0),
        ("rr", 40162.0),
    ] {
        sets.push(format!(
            "forces.tyre_{corner}.lateral_damping={}",
            cornering / speed
        ));
    }
    let sets = sets
        .iter()
        .map(|s| parse_set(s))
        .collect::<Result<Vec<_>, _>>()?;
    scene.apply_sets(&sets)?;
    let (_, history) = flexmbd::simulation::run(&scene, |_| {})?;
    let column = |name: &str| {
        history
            .header
            .iter()
            .position(|h| h == name)
            .expect("a sensor of the scene")
    };
    let z = column("chassis_z");
    let tyres: Vec<usize> = ["tyre_fl", "tyre_fr", "tyre_rl", "tyre_rr"]
        .iter()
        .map(|n| column(n))
        .collect();
    let z0 = history.rows[0][z];
    let rise = history
        .rows
        .iter()
        .map(|r| r[z] - z0)
        .fold(f64::NEG_INFINITY, f64::max);
    let lowest = history
        .rows
        .iter()
        .flat_map(|r| tyres.iter().map(move |&k| r[k]))
        .fold(f64::INFINITY, f64::min);
    Ok((rise, lowest))
}

fn main() -> Result<(), flexmbd::Error> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/iltis_bump.ron");
    let mut base = Scene::load(path)?;
    base.solver.formulation = FormulationKind::Relative;
    let speeds: Vec<f64> = (0..16).map(|k| 2.5 + 0.5 * k as f64).collect();

    let clock = std::time::Instant::now();
    let parallel = speeds
        .par_iter()
        .map(|&v| bump(&base, v))
        .collect::<Result<Vec<_>, _>>()?;
    let parallel_seconds = clock.elapsed().as_secs_f64();
    let clock = std::time::Instant::now();
    let serial = speeds
        .iter()
        .map(|&v| bump(&base, v))
        .collect::<Result<Vec<_>, _>>()?;
    let serial_seconds = clock.elapsed().as_secs_f64();

    println!(
        "{:>10} {:>14} {:>20}",
        "speed m/s", "peak rise mm", "smallest tyre force N"
    );
    for (v, (rise, lowest)) in speeds.iter().zip(&parallel) {
        println!("{v:10.1} {:14.1} {lowest:20.1}", rise * 1e3);
    }
    let same = parallel
        .iter()
        .zip(&serial)
        .all(|(a, b)| a.0.to_bits() == b.0.to_bits() && a.1.to_bits() == b.1.to_bits());
    println!(
        "16 runs: {parallel_seconds:.2} s wall on {} threads, {serial_seconds:.2} s one after the other; identical results: {same}",
        rayon::current_num_threads()
    );
    assert!(same, "a run's numbers depend on its thread");
    Ok(())
}
