//! The convergence study of docs/methods.md §7.3: the spin-up beam (docs/scenes.md §5) with 8, 16,
//! 32 and 64 elements at h = 1e-3 s, and 16 elements at h = 5e-4 s, over 20 s.
//!
//! `cargo run --release -p flexmbd-ancf --example convergence -- [2d|3d] [max_elements]`
//!
//! Prints, per mesh, min/max of the tip components and the CPU time, then the largest
//! difference over t between successive meshes and against the finest, with the observed
//! rate log₂(Δ_{n/2,n} / Δ_{n,2n}).

use flexmbd_ancf::{CableSpec, History, run_spin_up};
use flexmbd_core::Dim;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dim = match args.get(1).map(String::as_str) {
        Some("3d") => Dim::Spatial,
        _ => Dim::Planar,
    };
    let max_el: usize = args.get(2).map_or(64, |s| s.parse().unwrap());
    let duration: f64 = args.get(3).map_or(20.0, |s| s.parse().unwrap());
    let nk = dim.n_trans();
    let names = ["u_x", "u_y", "u_z"];
    let meshes: Vec<usize> = [8, 16, 32, 64]
        .into_iter()
        .filter(|&n| n <= max_el)
        .collect();
    let mut runs: Vec<(usize, History)> = Vec::new();
    for &n in &meshes {
        let h = run_spin_up(&CableSpec::spin_up_beam(dim, n), 1e-3, duration, 1e-2).unwrap();
        print!("{dim} n = {n:2}, h = 1e-3:");
        for k in 0..nk {
            print!(" {} [{:.7}, {:.7}]", names[k], h.min(k), h.max(k));
        }
        println!(
            "  {:.2} it/step, CPU {:.2} s",
            h.stats.newton_iterations as f64 / h.stats.steps as f64,
            h.cpu_seconds
        );
        runs.push((n, h));
    }
    println!("max over t of |Δ| between successive meshes (m):");
    let mut prev: Option<[f64; 3]> = None;
    for w in runs.windows(2) {
        let mut diff = [0.0; 3];
        print!("  {:2} vs {:2}:", w[0].0, w[1].0);
        for k in 0..nk {
            diff[k] = w[0].1.max_difference(&w[1].1, k);
            print!(" {} {:.3e}", names[k], diff[k]);
        }
        if let Some(p) = prev {
            print!("   rate");
            for k in 0..nk {
                print!(" {} {:.2}", names[k], (p[k] / diff[k]).log2());
            }
        }
        println!();
        prev = Some(diff);
    }
    if let Some((nf, fine)) = runs.last() {
        println!("against n = {nf}:");
        for (n, h) in &runs[..runs.len() - 1] {
            print!("  {n:2}:");
            for k in 0..nk {
                print!(" {} {:.3e}", names[k], h.max_difference(fine, k));
            }
            println!();
        }
    }
    let fine_h = run_spin_up(&CableSpec::spin_up_beam(dim, 16), 5e-4, duration, 1e-2).unwrap();
    let base = &runs.iter().find(|(n, _)| *n == 16).unwrap().1;
    print!("n = 16, h = 5e-4 vs 1e-3:");
    for k in 0..nk {
        print!(" {} {:.3e}", names[k], fine_h.max_difference(base, k));
    }
    println!("  (CPU {:.2} s)", fine_h.cpu_seconds);
}
