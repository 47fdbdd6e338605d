//! The tuning rule: the cheapest run of a sweep whose error meets a tolerance
//! (docs/methods.md §10.3).
//!
//! A candidate meets tolerance X when its status is ok and its error (the largest absolute
//! difference over time, largest over the judged sensors) is at most X − e_ref, e_ref the
//! reference's own error estimate (largest over the sensors; 0 for a reference given as a
//! file or table): |run − truth| ≤ |run − reference| + |reference − truth|, so a run that
//! meets it is within X of the physics as far as the estimate holds. The candidates
//! compared are timed alone ([`Sweep::retime`]), all of them, except a run that differs
//! from another meeting candidate only by a smaller step or more modes or elements
//! ([`structurally_cheaper`]): it is taken as costlier without timing it (times measured
//! during the parallel sweep are no guide on a loaded machine). CPU times within
//! [`TIMING_TIE`] of the cheapest count as tied (timing noise between runs is of that
//! order); among the tied, fewer coordinates win, then the lower grid index. The
//! runner-up is the next candidate by CPU time (then coordinates, then index).

use serde::Serialize;

use super::{ReferenceKind, RunRecord, RunStatus, Setting, Sweep, SweepError, SweepReport, Timing};

/// CPU times within this fraction of the cheapest count as tied.
pub const TIMING_TIE: f64 = 0.25;

/// What [`tune`] recommends.
#[derive(Clone, Debug, Serialize)]
pub struct Tuning {
    /// The tolerance on the judged sensors' largest absolute error.
    pub tolerance: f64,
    /// The reference's own error estimate e_ref (its margin, largest over the sensors; 0
    /// without one): a candidate meets the tolerance when its error is at most
    /// `tolerance − reference_error`.
    pub reference_error: f64,
    /// The recommended run (its `args` reproduce it with `flexmbd simulate`); `None` when
    /// no candidate meets the tolerance.
    pub recommended: Option<RunRecord>,
    /// The next cheapest candidate that meets the tolerance.
    pub runner_up: Option<RunRecord>,
    /// The rule the choice follows.
    pub rule: String,
    /// What limits the answer's truth ([`reference_warnings`]): a reference of the grid's
    /// own model family, a tolerance within the reference's own error estimate.
    pub warnings: Vec<String>,
}

/// The warnings a tuning at `tolerance` carries about its reference (issue 27 item 2):
/// a reference of the grid's own richest model ([`ReferenceKind::GridRichest`]: given, or
/// the default where the scene has no large-deformation model) has a margin that covers
/// its step, not its own modelling error (a stiffening method, truncated modes, a coarse
/// mesh), so the answer is only as true as that model; and a tolerance at or below the
/// reference's own error estimate cannot be judged.
pub fn reference_warnings(report: &SweepReport, tolerance: f64) -> Vec<String> {
    let mut warnings = Vec::new();
    if report.reference_kind == ReferenceKind::GridRichest {
        let why = report
            .reference_fallback
            .as_ref()
            .map_or(String::new(), |why| {
                format!(" (no large-deformation reference for this scene: {why})")
            });
        warnings.push(format!(
            "the reference is the grid's own richest model ({}){why}: its margin (against a \
             coarser step) covers the step only, not the modelling error of its stiffening method, \
             modes or elements, so the runs are judged against a model of their own family and \
             may be further from the physics than their errors say; give --reference a more \
             faithful solution (a large-deformation model, a finer mesh) to judge against",
            report.reference
        ));
    }
    if let Some(margin) = &report.reference_margin {
        let bound = margin.iter().map(|m| m.max_abs).fold(0.0f64, f64::max);
        if tolerance <= bound {
            warnings.push(format!(
                "the tolerance {tolerance:e} is within the reference's own error estimate \
                 {bound:.3e} (its difference from the same refined): the answer cannot be \
                 trusted at this tolerance"
            ));
        }
    }
    warnings
}

/// The reference's own error estimate: its margin's largest entry (0 without a margin).
fn reference_error(report: &SweepReport) -> f64 {
    report
        .reference_margin
        .iter()
        .flatten()
        .map(|m| m.max_abs)
        .fold(0.0f64, f64::max)
}

/// Whether `run` meets `tolerance`.
fn meets(run: &RunRecord, tolerance: f64) -> bool {
    run.status == RunStatus::Ok && run.error <= tolerance
}

/// Whether the settings `a` make a run no costlier than `b` by construction: the same
/// choices except a step at least as large, or no more modes or elements, and not all
/// equal.
pub fn structurally_cheaper(a: &[Setting], b: &[Setting]) -> bool {
    if a.len() != b.len() || a == b {
        return false;
    }
    a.iter().zip(b).all(|(x, y)| match (x, y) {
        (Setting::Step(ha), Setting::Step(hb)) => ha >= hb,
        (
            Setting::Modes {
                bodies: ba,
                count: na,
            },
            Setting::Modes {
                bodies: bb,
                count: nb,
            },
        )
        | (
            Setting::Elements {
                bodies: ba,
                count: na,
            },
            Setting::Elements {
                bodies: bb,
                count: nb,
            },
        ) => ba == bb && na <= nb,
        _ => x == y,
    })
}

/// The cheapest candidate of `report` meeting `tolerance` by the rule of this module, the
/// candidates it compares timed alone (recorded in `report`). Refused: a tolerance that is
/// not positive and finite.
pub fn tune(sweep: &Sweep, report: &mut SweepReport, tolerance: f64) -> Result<Tuning, SweepError> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(SweepError::Tolerance(tolerance));
    }
    let rule = format!(
        "the least CPU time (timed alone, median of {} or of {} for runs under {} s) among ok runs whose error is at most \
         the tolerance less the reference's own error estimate; a run that differs from another such run only by a smaller step or \
         more modes or elements is taken as costlier and not timed (`costlier_than`); times \
         within {:.0} % of the least count as tied, and then fewer coordinates win, then the \
         lower grid index",
        super::RETIME_REPEATS,
        super::RETIME_REPEATS_SHORT,
        super::SHORT_RUN,
        TIMING_TIE * 100.0
    );
    let reference_error = reference_error(report);
    let limit = tolerance - reference_error;
    let settings = sweep.point_settings()?;
    let meeting: Vec<usize> = (0..report.runs.len())
        .filter(|&i| meets(&report.runs[i], limit))
        .collect();
    let minimal: Vec<usize> = meeting
        .iter()
        .copied()
        .filter(|&i| {
            !meeting
                .iter()
                .any(|&j| structurally_cheaper(&settings[j], &settings[i]))
        })
        .collect();
    for &i in &meeting {
        report.runs[i].costlier_than = minimal
            .iter()
            .copied()
            .find(|&j| structurally_cheaper(&settings[j], &settings[i]));
    }
    let pending: Vec<usize> = minimal
        .iter()
        .copied()
        .filter(|&i| report.runs[i].timed == Timing::InParallel)
        .collect();
    sweep.retime(report, &pending)?;
    let compared: Vec<RunRecord> = minimal.iter().map(|&i| report.runs[i].clone()).collect();
    let (recommended, runner_up) = choose(&compared, limit);
    Ok(Tuning {
        tolerance,
        reference_error,
        recommended: recommended.cloned(),
        runner_up: runner_up.cloned(),
        rule,
        warnings: reference_warnings(report, tolerance),
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
            costlier_than: None,
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

    /// A run meets the tolerance only with the reference's own error estimate to spare: at
    /// 5 mm against a reference good to 1 mm, 4.5 mm does not meet it and 3.5 mm does.
    #[test]
    fn the_reference_s_own_error_is_taken_off_the_tolerance() {
        let margin = |max_abs: f64| super::super::SensorError {
            sensor: "s".into(),
            max_abs,
            rms: 0.0,
        };
        let report = SweepReport {
            scene: "s".into(),
            sensors: vec!["s".into(), "t".into()],
            reference: String::new(),
            reference_kind: ReferenceKind::Substructured,
            reference_fallback: None,
            reference_seconds: 0.0,
            reference_cached: false,
            reference_margin: Some(vec![margin(1e-3), margin(0.4e-3)]),
            error_cap: 1.0,
            runs: Vec::new(),
            pareto: Vec::new(),
            timing: String::new(),
            threads: 1,
            parallel_wall_seconds: 0.0,
            sum_run_seconds: 0.0,
            interrupted: false,
        };
        assert_eq!(reference_error(&report), 1e-3);
        let limit = 5e-3 - reference_error(&report);
        let runs = [run(0, 4.5e-3, 0.001, 1), run(1, 3.5e-3, 0.002, 1)];
        assert_eq!(choose(&runs, limit).0.map(|r| r.index), Some(1));
        assert_eq!(choose(&runs, 5e-3).0.map(|r| r.index), Some(0));
        let given = SweepReport {
            reference_margin: None,
            ..report
        };
        assert_eq!(reference_error(&given), 0.0);
    }

    #[test]
    fn near_ties_in_cpu_time_go_to_fewer_coordinates_then_the_lower_index() {
        // 1.1 is within 25 % of 1.0: tied, and run 2 has fewer coordinates.
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

#[cfg(test)]
mod structure_tests {
    use super::*;
    use flexmbd_model::FormulationKind::{Absolute, Relative};

    fn point(f: flexmbd_model::FormulationKind, modes: usize, h: f64) -> Vec<Setting> {
        vec![
            Setting::Formulation(f),
            Setting::Modes {
                bodies: vec!["beam".into()],
                count: modes,
            },
            Setting::Step(h),
        ]
    }

    #[test]
    fn a_larger_step_or_fewer_modes_is_structurally_cheaper_and_nothing_else_is() {
        let base = point(Relative, 2, 2e-3);
        assert!(structurally_cheaper(&base, &point(Relative, 2, 1e-3)));
        assert!(structurally_cheaper(&base, &point(Relative, 3, 2e-3)));
        assert!(structurally_cheaper(&base, &point(Relative, 3, 1e-3)));
        assert!(
            !structurally_cheaper(&base, &base),
            "not cheaper than itself"
        );
        assert!(!structurally_cheaper(
            &point(Relative, 3, 2e-3),
            &point(Relative, 2, 1e-3)
        ));
        assert!(!structurally_cheaper(&base, &point(Absolute, 3, 1e-3)));
    }
}
