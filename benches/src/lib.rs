//! Criterion benchmarks of flexmbd live in `benches/`; run `cargo bench -p flexmbd-benches`.
//! This library holds what several of them share.

use std::time::{Duration, Instant};

use flexmbd::Simulation;
use flexmbd::integrators::Checkpoint as IntegratorCheckpoint;

/// The time of `iters` whole runs of `simulation` from `start` to `duration` (s), restoring
/// `start` before each: the start itself (static equilibrium, consistent initial
/// conditions) is done once, outside the timing (criterion's `iter_custom`).
pub fn time_whole_runs(
    simulation: &mut Simulation,
    start: &IntegratorCheckpoint,
    duration: f64,
    iters: u64,
) -> Duration {
    let mut total = Duration::ZERO;
    for _ in 0..iters {
        simulation.restore(start);
        let t = Instant::now();
        simulation.advance_to(duration).expect("the run completes");
        total += t.elapsed();
    }
    total
}
