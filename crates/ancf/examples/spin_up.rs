//! One spin-up run of the ANCF reference (docs/methods.md §7.3, docs/scenes.md §5).
//!
//! `cargo run --release -p flexmbd-ancf --example spin_up -- [2d|3d] [elements] [h] [duration] [csv]`

use flexmbd_ancf::{CableSpec, run_spin_up};
use flexmbd_core::Dim;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dim = match args.get(1).map(String::as_str) {
        Some("3d") => Dim::Spatial,
        _ => Dim::Planar,
    };
    let elements: usize = args.get(2).map_or(16, |s| s.parse().unwrap());
    let h: f64 = args.get(3).map_or(1e-3, |s| s.parse().unwrap());
    let duration: f64 = args.get(4).map_or(20.0, |s| s.parse().unwrap());
    let spec = CableSpec::spin_up_beam(dim, elements);
    let hist = run_spin_up(&spec, h, duration, 0.01).unwrap();
    if let Some(st) = &hist.static_start {
        println!(
            "static start: {} load steps, {} iterations, residual {:.2e}, tip {:?}",
            st.load_steps, st.iterations, st.residual, hist.tip[0]
        );
    }
    let names = ["u_x", "u_y", "u_z"];
    for k in 0..dim.n_trans() {
        println!(
            "{}: min {:.7} max {:.7} final {:.7}",
            names[k],
            hist.min(k),
            hist.max(k),
            hist.tip.last().unwrap()[k]
        );
    }
    let s = &hist.stats;
    println!(
        "{dim} n = {elements}, h = {h}: {} steps, {:.2} Newton it/step, {} accepted unconverged, CPU {:.2} s",
        s.steps,
        s.newton_iterations as f64 / s.steps as f64,
        s.accepted_unconverged,
        hist.cpu_seconds
    );
    if let Some(path) = args.get(5) {
        let mut out = String::from("t,ux,uy,uz,energy\n");
        for (i, t) in hist.t.iter().enumerate() {
            let d = hist.tip[i];
            out += &format!("{t},{},{},{},{}\n", d[0], d[1], d[2], hist.energy[i]);
        }
        std::fs::write(path, out).unwrap();
    }
}
