//! The sparse eigen-solver on a free-free steel bar of hex8 bricks (0.4 m × 0.1 m × 0.1 m,
//! 4n × n × n bricks), for the side-by-side measurement with SciPy's `eigsh`
//! (`benches/scipy_eigsh.py`).
//!
//! ```sh
//! # write K and M as Matrix Market files (and the shift) for SciPy
//! cargo run --release -p flexmbd-fe --example eigen_vs_scipy -- write 9 /tmp/box9
//! # solve: time of factorisation + iteration only, peak RSS, frequencies to a file
//! cargo run --release -p flexmbd-fe --example eigen_vs_scipy -- solve 9 /tmp/box9/rust.txt
//! ```
//!
//! Options after the positional arguments: `--modes N` (default 20), `--block P`,
//! `--basis M`, `--tol T`.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use flexmbd_fe::solid_box::SolidBox;
use flexmbd_fe::sparse::write_matrix_market;
use flexmbd_fe::sparse_eigen::{SparseEigenOptions, default_shift, lowest_modes_with_stats};

fn bar(n: usize) -> SolidBox {
    SolidBox::steel([0.4, 0.1, 0.1], [4 * n, n, n])
}

/// This process's resident set (current, peak) in MiB, from /proc/self/status.
fn rss_mib() -> (f64, f64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| {
        status
            .lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse::<f64>().ok())
            .map_or(f64::NAN, |kib| kib / 1024.0)
    };
    (field("VmRSS:"), field("VmHWM:"))
}

fn flag(args: &[String], name: &str) -> Option<String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1).cloned())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: eigen_vs_scipy (write N DIR | solve N OUT) [--modes K] [--block P] [--basis M] [--tol T]";
    let (mode, n, target) = match args.as_slice() {
        [mode, n, target, ..] => (mode.as_str(), n.parse::<usize>()?, target.clone()),
        _ => return Err(usage.into()),
    };
    let b = bar(n);
    let t = Instant::now();
    let (k, m) = b.assemble()?;
    let assembly = t.elapsed();
    let shift = default_shift(&k, &m)?;
    match mode {
        "write" => {
            let dir = Path::new(&target);
            std::fs::create_dir_all(dir)?;
            write_matrix_market(&dir.join("K.mtx"), &k)?;
            write_matrix_market(&dir.join("M.mtx"), &m)?;
            std::fs::write(dir.join("shift.txt"), format!("{shift:e}\n"))?;
            println!("N {} nnz {} shift {shift:e}", b.n_dofs(), k.nnz());
        }
        "solve" => {
            let mut options = SparseEigenOptions::default();
            if let Some(p) = flag(&args, "--block") {
                options.block_size = p.parse()?;
            }
            if let Some(mm) = flag(&args, "--basis") {
                options.basis_size = Some(mm.parse()?);
            }
            if let Some(tol) = flag(&args, "--tol") {
                options.tol = tol.parse()?;
            }
            let modes: usize = flag(&args, "--modes").map_or(Ok(20), |s| s.parse())?;
            let (rss_before, _) = rss_mib();
            let t = Instant::now();
            let (pairs, stats) = lowest_modes_with_stats(&k, &m, modes, &options)?;
            let seconds = t.elapsed().as_secs_f64();
            let (_, peak) = rss_mib();
            let mut out = std::fs::File::create(&target)?;
            for w in &pairs.omega_sq {
                writeln!(out, "{w:e}")?;
            }
            let max_residual = stats.residuals.iter().fold(0.0_f64, |a, &r| a.max(r));
            let ts = stats.times;
            println!(
                "N {} nnz {} assembly_s {:.3} solve_s {seconds:.3} rss_before_mib {rss_before:.0} \
                 peak_rss_mib {peak:.0} factor_entries {} solves {} restarts {} max_residual {max_residual:.2e} \
                 checks_s {:.3} symbolic_s {:.3} numeric_s {:.3} solves_s {:.3} orth_s {:.3} rr_s {:.3} shift {:e}",
                b.n_dofs(),
                k.nnz(),
                assembly.as_secs_f64(),
                stats.factor_entries,
                stats.solves,
                stats.restarts,
                ts.checks.as_secs_f64(),
                ts.symbolic.as_secs_f64(),
                ts.numeric.as_secs_f64(),
                ts.solves.as_secs_f64(),
                ts.orthogonalisation.as_secs_f64(),
                ts.rayleigh_ritz.as_secs_f64(),
                stats.shift,
            );
        }
        _ => return Err(usage.into()),
    }
    Ok(())
}
