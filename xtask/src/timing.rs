//! Wall-clock timing for the report's tables: the median over several batches,
//! each batch long enough (≈ `batch_ms`) for the clock to resolve it.

use std::time::{Duration, Instant};

/// Median time of one call of `f`, in seconds, over `batches` batches.
pub fn median_seconds(mut f: impl FnMut(), batches: usize, batch_ms: f64) -> f64 {
    // Warm up and size the batch.
    let mut n = 1usize;
    loop {
        let t = Instant::now();
        for _ in 0..n {
            f();
        }
        let el = t.elapsed();
        if el >= Duration::from_secs_f64(batch_ms * 1e-3 / 4.0) || n >= 1 << 30 {
            let per = el.as_secs_f64() / n as f64;
            n = ((batch_ms * 1e-3 / per.max(1e-12)).ceil() as usize).max(1);
            break;
        }
        n *= 4;
    }
    let mut samples: Vec<f64> = (0..batches.max(1))
        .map(|_| {
            let t = Instant::now();
            for _ in 0..n {
                f();
            }
            t.elapsed().as_secs_f64() / n as f64
        })
        .collect();
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2]
}

/// The CPU model of this machine, for the report header.
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    format!("{cpu}, {cores} logical cores available, one used per measurement")
}
