//! The work–precision section's tables: the cheapest model per tolerance (`flexmbd tune`'s
//! choice) and, on a scene with a basis axis, the fewest modes per kind that meet a
//! tolerance, with the kinds chart and how much the modes and the step change the error.

use std::collections::BTreeMap;

use flexmbd::fe::ModeSelection;
use flexmbd::sweep::{RunStatus, Setting, SweepReport, Tuning, basis_name};

use super::Case;
use super::charts::{basis_chart, basis_of, method_of, modes_of};
use crate::report::Report;
use crate::studies::StudyResult;

/// The run of kind `kind` that meets `tolerance` with the fewest modes (then the fewest
/// coordinates, then the smallest error), if any.
fn fewest(
    report: &SweepReport,
    settings: &[Vec<Setting>],
    tolerance: f64,
    kind: ModeSelection,
) -> Option<usize> {
    (0..settings.len())
        .filter(|&i| {
            let r = &report.runs[i];
            r.status == RunStatus::Ok && r.error <= tolerance && basis_of(&settings[i]) == kind
        })
        .min_by(|&a, &b| {
            let key = |i: usize| (modes_of(&settings[i]), report.runs[i].n_coordinates);
            key(a)
                .cmp(&key(b))
                .then(report.runs[a].error.total_cmp(&report.runs[b].error))
        })
}

/// Per tolerance of the case's kinds table and kind of modes: the fewest modes with which
/// some run of that kind meets the tolerance (that run: the fewest coordinates, then the
/// smallest error).
fn basis_rows(case: &Case, report: &SweepReport, settings: &[Vec<Setting>]) -> Vec<Vec<String>> {
    let mut rows = Vec::new();
    for &tolerance in case.basis_tolerances {
        let mut row = vec![mm(tolerance)];
        for &kind in &case.bases {
            row.push(fewest(report, settings, tolerance, kind).map_or(
                "none on the grid".into(),
                |i| {
                    let r = &report.runs[i];
                    format!(
                        "{}: {} ({} mm, {} coordinates)",
                        match modes_of(&settings[i]) {
                            Some(1) => "1 mode".to_string(),
                            Some(n) => format!("{n} modes"),
                            None => "–".into(),
                        },
                        method_of(&settings[i]),
                        millimetres(r.error),
                        r.n_coordinates.map_or("–".into(), |n| n.to_string())
                    )
                },
            ));
        }
        rows.push(row);
    }
    rows
}

/// Per tolerance, whether `kind` meets it with fewer, as many or more coordinates than the
/// lowest normal modes (issue 16's check), in one sentence.
fn against_lowest(
    case: &Case,
    report: &SweepReport,
    settings: &[Vec<Setting>],
    kind: ModeSelection,
) -> String {
    // (coordinates, modes) of the run of `kind` with the fewest modes that meets `tolerance`.
    let coordinates = |tolerance: f64, kind: ModeSelection| {
        fewest(report, settings, tolerance, kind).and_then(|i| {
            let modes = match modes_of(&settings[i]) {
                Some(1) => "1 mode".to_string(),
                Some(m) => format!("{m} modes"),
                None => "–".into(),
            };
            report.runs[i].n_coordinates.map(|c| (c, modes))
        })
    };
    let verdicts: Vec<String> = case
        .basis_tolerances
        .iter()
        .map(|&tolerance| {
            let verdict = match (
                coordinates(tolerance, kind),
                coordinates(tolerance, ModeSelection::LowestFrequency),
            ) {
                (Some((a, ma)), Some((b, mb))) if a < b => {
                    format!("fewer ({a} with {ma}, against {b} with {mb})")
                }
                (Some((a, ma)), Some((b, _))) if a == b => format!("as many ({a}, {ma})"),
                (Some((a, ma)), Some((b, mb))) => {
                    format!("more ({a} with {ma}, against {b} with {mb})")
                }
                (Some((a, ma)), None) => {
                    format!("{a} with {ma}, where the lowest modes do not meet it")
                }
                (None, Some((b, mb))) => {
                    format!("not met, where the lowest modes need {b} ({mb})")
                }
                (None, None) => "met by neither".into(),
            };
            format!("{}: {verdict}", mm(tolerance))
        })
        .collect();
    format!(
        "Coordinates with which the {} modes meet each tolerance here, against the lowest \
         normal modes: {}.",
        basis_name(kind),
        verdicts.join("; ")
    )
}

/// The kind-of-modes chart and table of a case with a basis axis.
pub(super) fn basis_section(
    case: &Case,
    report: &SweepReport,
    settings: &[Vec<Setting>],
    out: &mut Report,
) -> StudyResult {
    let file = format!("work_precision_{}_basis.svg", case.file);
    basis_chart(case, report, settings, &out.chart_path(&file))?;
    let note = if case.basis_note.is_empty() {
        String::new()
    } else {
        format!(" {}", case.basis_note)
    };
    out.text(&format!(
        "Kind of modes on {} (docs/methods.md §1.6): {} — the lowest fixed-interface \
         normal modes, the modes the body's inertia and interface loads excite most \
         (participation), load-dependent Ritz vectors of the same loads (ritz), the proper \
         orthogonal modes of a pilot run of the scene (pod). The chart shows per kind the \
         front of all its runs; the table the fewest modes per kind that meet a tolerance, \
         with the run that does.{note}",
        case.basis_where,
        case.bases
            .iter()
            .map(|&k| basis_name(k))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    out.image(&file, &format!("kinds of modes, {}", case.title));
    let mut header = vec!["tolerance".to_string()];
    header.extend(
        case.bases
            .iter()
            .map(|&k| format!("{} modes", basis_name(k))),
    );
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    out.table(&header, &basis_rows(case, report, settings));
    if case.bases.contains(&ModeSelection::ProperOrthogonal) {
        out.text(&against_lowest(
            case,
            report,
            settings,
            ModeSelection::ProperOrthogonal,
        ));
    }
    if case.spreads {
        let modes = spread(report, settings, |s| {
            matches!(s, Setting::Modes { .. } | Setting::Basis { .. })
        });
        let step = spread(report, settings, |s| matches!(s, Setting::Step(_)));
        out.text(&format!(
            "Runs that differ only in the count and kind of their modes differ in error by at \
             most {modes:.1e} m on this scene; runs that differ only in their step, by up to \
             {step:.1e} m."
        ));
    }
    Ok(())
}

/// The largest difference in error between ok runs whose settings differ only in those
/// `varied` picks.
fn spread(report: &SweepReport, settings: &[Vec<Setting>], varied: fn(&Setting) -> bool) -> f64 {
    let mut groups: BTreeMap<String, (f64, f64)> = BTreeMap::new();
    for (run, point) in report.runs.iter().zip(settings) {
        if run.status != RunStatus::Ok {
            continue;
        }
        let fixed: Vec<String> = point
            .iter()
            .filter(|s| !varied(s))
            .map(Setting::label)
            .collect();
        let (low, high) = groups
            .entry(fixed.join(" "))
            .or_insert((f64::INFINITY, f64::NEG_INFINITY));
        *low = low.min(run.error);
        *high = high.max(run.error);
    }
    groups
        .values()
        .map(|(low, high)| high - low)
        .fold(0.0, f64::max)
}

/// An error in mm with two decimals, or three significant digits below 1 mm.
fn millimetres(error: f64) -> String {
    let mm = error * 1e3;
    let decimals = if mm > 0.0 && mm < 1.0 {
        (2.0 - mm.log10().floor()) as usize
    } else {
        2
    };
    format!("{mm:.decimals$}")
}

/// A tolerance in mm for a reader.
fn mm(x: f64) -> String {
    format!("{} mm", x * 1e3)
}

/// The table row of one tolerance.
pub(super) fn tolerance_row(tolerance: f64, tuning: &Tuning, report: &SweepReport) -> Vec<String> {
    match &tuning.recommended {
        Some(r) => vec![
            mm(tolerance),
            r.label.clone(),
            format!("{:.3}", r.error * 1e3),
            format!("{:.4}", r.cpu_seconds),
            r.n_coordinates.map_or("–".into(), |n| n.to_string()),
            tuning.runner_up.as_ref().map_or("–".into(), |u| {
                format!(
                    "{} ({:.3} mm, {:.4} s)",
                    u.label,
                    u.error * 1e3,
                    u.cpu_seconds
                )
            }),
        ],
        None => {
            let best = report
                .runs
                .iter()
                .filter(|r| r.status == RunStatus::Ok)
                .map(|r| r.error)
                .fold(f64::INFINITY, f64::min);
            vec![
                mm(tolerance),
                format!("none on the grid (smallest error {:.3} mm)", best * 1e3),
                "–".into(),
                "–".into(),
                "–".into(),
                "–".into(),
            ]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd::model::FormulationKind::{Absolute, Relative};
    use flexmbd::sweep::{RunRecord, Timing};

    fn run(index: usize, status: RunStatus, error: f64) -> RunRecord {
        RunRecord {
            index,
            label: String::new(),
            args: Vec::new(),
            status,
            reason: None,
            n_coordinates: Some(10),
            errors: Vec::new(),
            error,
            cpu_seconds: 1.0,
            timed: Timing::InParallel,
            realtime_factor: 1.0,
            simulated_seconds: 1.0,
            costlier_than: None,
        }
    }

    fn point(form: flexmbd::model::FormulationKind, modes: usize, h: f64) -> Vec<Setting> {
        vec![
            Setting::Formulation(form),
            Setting::Modes {
                bodies: vec!["beam".into()],
                count: modes,
            },
            Setting::Step(h),
        ]
    }

    #[test]
    fn the_spread_compares_only_runs_that_differ_in_the_varied_settings() {
        let settings = vec![
            point(Absolute, 0, 1e-3),
            point(Absolute, 2, 1e-3),
            point(Relative, 0, 1e-3),
            point(Relative, 2, 1e-3),
            point(Relative, 2, 2e-3),
            point(Relative, 0, 2e-3),
        ];
        let runs = vec![
            run(0, RunStatus::Ok, 1.0e-5),
            run(1, RunStatus::Ok, 1.3e-5),
            run(2, RunStatus::Ok, 2.0e-5),
            run(3, RunStatus::Ok, 2.1e-5),
            run(4, RunStatus::Ok, 9.0e-5),
            // Not ok: left out, its error says nothing.
            run(5, RunStatus::Failed, f64::INFINITY),
        ];
        let report = SweepReport {
            scene: "s".into(),
            sensors: Vec::new(),
            reference: String::new(),
            reference_kind: flexmbd::sweep::ReferenceKind::Table,
            reference_fallback: None,
            reference_seconds: 0.0,
            reference_cached: false,
            reference_margin: None,
            error_cap: 1.0,
            runs,
            pareto: Vec::new(),
            timing: String::new(),
            threads: 1,
            parallel_wall_seconds: 0.0,
            sum_run_seconds: 0.0,
            interrupted: false,
        };
        let modes = spread(&report, &settings, |s| matches!(s, Setting::Modes { .. }));
        assert!((modes - 0.3e-5).abs() < 1e-12, "{modes}");
        let step = spread(&report, &settings, |s| matches!(s, Setting::Step(_)));
        assert!((step - 6.9e-5).abs() < 1e-12, "{step}");
    }

    #[test]
    fn small_errors_keep_three_significant_digits() {
        assert_eq!(millimetres(1.662e-3), "1.66");
        assert_eq!(millimetres(12.34e-3), "12.34");
        assert_eq!(millimetres(1.02e-4), "0.102");
        assert_eq!(millimetres(1.2e-5), "0.0120");
        assert_eq!(millimetres(0.0), "0.00");
    }
}
