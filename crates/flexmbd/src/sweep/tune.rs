//! The tuning rule: the cheapest run of a sweep whose error meets a tolerance
//! (docs/methods.md §8.3).
//!
//! A candidate meets tolerance X when its status is ok and its error (the largest absolute
//! difference over time, largest over the judged sensors) is at most X. The candidates
//! compared are timed alone ([`Sweep::retime`]): first the one the parallel sweep found
//! cheapest, then every meeting candidate whose parallel time is below the cheapest
//! alone time times 1 + [`TIMING_TIE`], until none is left. CPU times within
//! [`TIMING_TIE`] of the cheapest count as tied (timing noise between runs is of that
//! order); among the tied, fewer coordinates win, then the lower grid index. The
//! runner-up is the next candidate by CPU time (then coordinates, then index).

use serde::Serialize;

use super::{RunRecord, RunStatus, Sweep, SweepError, SweepReport, Timing};

/// CPU times within this fraction of the cheapest count as tied.
pub const TIMING_TIE: f64 = 0.2;

/// What [`tune`] recommends.
#[derive(Clone, Debug, Serialize)]
pub struct Tuning {
    /// The tolerance on the judged sensors' largest absolute error.
    pub tolerance: f64,
    /// The recommended run (its `args` reproduce it with `flexmbd simulate`); `None` when
    /// no candidate meets the tolerance.
    pub recommended: Option<RunRecord>,
    /// The next cheapest candidate that meets the tolerance.
    pub runner_up: Option<RunRecord>,
    /// The rule the choice follows.
    pub rule: String,
}

/// Whether `run` meets `tolerance`.
fn meets(run: &RunRecord, tolerance: f64) -> bool {
    run.status == RunStatus::Ok && run.error <= tolerance
}

/// The cheapest candidate of `report` meeting `tolerance` by the rule of this module, the
/// candidates it compares timed alone (recorded in `report`). Refused: a tolerance that is
/// not positive and finite.
pub fn tune(sweep: &Sweep, report: &mut SweepReport, tolerance: f64) -> Result<Tuning, SweepError> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(SweepError::Tolerance(tolerance));
    }
    let rule = format!(
        "the least CPU time (timed alone, median of {}) among ok runs whose error is at most \
         the tolerance; times within {:.0} % of the least count as tied, and then fewer \
         coordinates win, then the lower grid index",
        super::RETIME_REPEATS,
        TIMING_TIE * 100.0
    );
    loop {
        let cheapest_alone = report
            .runs
            .iter()
            .filter(|r| meets(r, tolerance) && r.timed == Timing::Alone)
            .map(|r| r.cpu_seconds)
            .min_by(f64::total_cmp);
        let parallel = report
            .runs
            .iter()
            .filter(|r| meets(r, tolerance) && r.timed == Timing::InParallel);
        let pending: Vec<usize> = match cheapest_alone {
            Some(c) => parallel
                .filter(|r| r.cpu_seconds < c * (1.0 + TIMING_TIE))
                .map(|r| r.index)
                .collect(),
            None => parallel
                .min_by(|a, b| a.cpu_seconds.total_cmp(&b.cpu_seconds))
                .map(|r| vec![r.index])
                .unwrap_or_default(),
        };
        if pending.is_empty() {
            break;
        }
        sweep.retime(report, &pending)?;
    }
    let (recommended, runner_up) = choose(&report.runs, tolerance);
    Ok(Tuning {
        tolerance,
        recommended: recommended.cloned(),
        runner_up: runner_up.cloned(),
        rule,
    })
}

/// The recommended run and the runner-up among `runs` for `tolerance` (see the module
/// documentation), from the CPU times recorded.
fn choose(runs: &[RunRecord], tolerance: f64) -> (Option<&RunRecord>, Option<&RunRecord>) {
    let mut candidates: Vec<&RunRecord> = runs.iter().filter(|r| meets(r, tolerance)).collect();
    let key = |r: &RunRecord| (r.n_coordinates.unwrap_or(usize::MAX), r.index);
    candidates.sort_by(|a, b| {
        a.cpu_seconds
            .total_cmp(&b.cpu_seconds)
            .then(key(a).cmp(&key(b)))
    });
    let Some(cheapest) = candidates.first().map(|r| r.cpu_seconds) else {
        return (None, None);
    };
    let recommended = candidates
        .iter()
        .copied()
        .filter(|r| r.cpu_seconds <= cheapest * (1.0 + TIMING_TIE))
        .min_by_key(|r| key(r));
    let runner_up = candidates
        .iter()
        .copied()
        .find(|r| Some(r.index) != recommended.map(|c| c.index));
    (recommended, runner_up)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(index: usize, error: f64, cpu: f64, n: usize) -> RunRecord {
        RunRecord {
            index,
            label: format!("run {index}"),
            args: Vec::new(),
            status: RunStatus::Ok,
            reason: None,
            n_coordinates: Some(n),
            errors: Vec::new(),
            error,
            cpu_seconds: cpu,
            timed: Timing::Alone,
            realtime_factor: 1.0,
            simulated_seconds: 1.0,
        }
    }

    #[test]
    fn the_cheapest_meeting_run_wins_and_failed_runs_are_never_chosen() {
        let mut failed = run(0, 0.0, 0.001, 1);
        failed.status = RunStatus::Failed;
        let runs = [
            failed,
            run(1, 2e-3, 1.0, 8),
            run(2, 0.5e-3, 3.0, 8),
            run(3, 9e-3, 0.1, 8),
        ];
        let (rec, next) = choose(&runs, 5e-3);
        assert_eq!((rec.unwrap().index, next.unwrap().index), (1, 2));
        let (rec, next) = choose(&runs, 1e-3);
        assert_eq!((rec.unwrap().index, next.map(|r| r.index)), (2, None));
        assert!(choose(&runs, 1e-4).0.is_none());
    }

    #[test]
    fn near_ties_in_cpu_time_go_to_fewer_coordinates_then_the_lower_index() {
        // 1.1 is within 20 % of 1.0: tied, and run 2 has fewer coordinates.
        let runs = [
            run(0, 1e-3, 1.05, 8),
            run(1, 1e-3, 1.0, 8),
            run(2, 1e-3, 1.1, 6),
        ];
        assert_eq!(choose(&runs, 5e-3).0.unwrap().index, 2);
        // Equal coordinates: the lower index among the tied.
        let runs = [
            run(0, 1e-3, 1.05, 8),
            run(1, 1e-3, 1.0, 8),
            run(2, 1e-3, 1.5, 6),
        ];
        assert_eq!(choose(&runs, 5e-3).0.unwrap().index, 0);
    }
}
