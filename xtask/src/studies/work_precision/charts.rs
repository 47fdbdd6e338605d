//! The work–precision section's charts: error against CPU time (log–log) with per method
//! its own front and the Pareto front of all runs, and per kind of modes the front of its
//! runs; and what the charts and tables read off a run's settings.

use std::path::Path;

use flexmbd::fe::ModeSelection;
use flexmbd::sweep::{
    RunStatus, Setting, SweepReport, basis_name,
    grid::{formulation_name, inertia_name, stiffening_name},
    pareto_front,
};

use super::Case;
use crate::chart::{LineChart, Series};
use crate::studies::StudyResult;

/// The label of a run's method: formulation, inertia, stiffening.
pub(super) fn method_of(settings: &[Setting]) -> String {
    let parts: Vec<String> = settings
        .iter()
        .filter_map(|s| match s {
            Setting::Formulation(f) => Some(formulation_name(*f).to_string()),
            Setting::Inertia(i) => Some(inertia_name(*i).to_string()),
            Setting::Stiffening(m) => Some(stiffening_name(*m)),
            _ => None,
        })
        .collect();
    parts.join(" ")
}

/// A method's label without its inertia route: the runs of one colour.
fn colour_key(method: &str) -> String {
    method
        .replace(" b-matrix", "")
        .replace(" shape-integrals", "")
}

/// The chart: per method its own front of (CPU, error) over steps and modes, and the front
/// of all runs.
pub(super) fn chart(
    case: &Case,
    report: &SweepReport,
    settings: &[Vec<Setting>],
    path: &Path,
) -> StudyResult {
    let mut methods: Vec<String> = settings.iter().map(|s| method_of(s)).collect();
    methods.sort();
    methods.dedup();
    let ok = |i: usize| plotted(report, i);
    let front_of = |members: Vec<usize>| front(report, &members);
    // One colour per formulation and stiffening method; the B-matrix route dashed.
    let mut colours: Vec<String> = methods.iter().map(|m| colour_key(m)).collect();
    colours.sort();
    colours.dedup();
    let mut series: Vec<Series> = methods
        .iter()
        .map(|m| Series {
            label: m.clone(),
            points: front_of(
                (0..settings.len())
                    .filter(|&i| ok(i) && method_of(&settings[i]) == *m)
                    .collect(),
            ),
            dashed: m.contains("b-matrix"),
            colour: colours
                .iter()
                .position(|c| *c == colour_key(m))
                .unwrap_or(0),
        })
        .collect();
    series.push(Series {
        label: "Pareto front (all runs)".into(),
        points: front_of((0..settings.len()).filter(|&i| ok(i)).collect()),
        dashed: false,
        colour: 8,
    });
    error_against_cpu(format!("Work–precision: {}", case.title), series).write_svg(path)
}

/// A log–log chart of the largest error over time against the run's CPU time, the error in
/// mm (the unit the tolerances of these cases are given in).
pub(crate) fn error_against_cpu(title: String, series: Vec<Series>) -> LineChart {
    let series = series
        .into_iter()
        .map(|s| Series {
            points: s.points.iter().map(|&(cpu, e)| (cpu, e * 1e3)).collect(),
            ..s
        })
        .collect();
    LineChart {
        title,
        x_label: "CPU time of the run (s)".into(),
        y_label: "largest error over time (mm)".into(),
        log_x: true,
        log_y: true,
        series,
    }
}

/// Run `i` finished with a positive error (a point of a log–log chart).
fn plotted(report: &SweepReport, i: usize) -> bool {
    report.runs[i].status == RunStatus::Ok && report.runs[i].error > 0.0
}

/// The Pareto front of the runs `members` as (CPU time, error), by CPU time.
fn front(report: &SweepReport, members: &[usize]) -> Vec<(f64, f64)> {
    let points: Vec<(f64, f64)> = members
        .iter()
        .map(|&i| (report.runs[i].error, report.runs[i].cpu_seconds))
        .collect();
    let mut front: Vec<(f64, f64)> = pareto_front(&points)
        .into_iter()
        .map(|k| (points[k].1, points[k].0))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    front
}

/// The kind of modes of a run (the lowest normal modes without a basis axis).
pub(super) fn basis_of(settings: &[Setting]) -> ModeSelection {
    settings
        .iter()
        .find_map(|s| match s {
            Setting::Basis { kind, .. } => Some(*kind),
            _ => None,
        })
        .unwrap_or_default()
}

/// The mode count of a run.
pub(super) fn modes_of(settings: &[Setting]) -> Option<usize> {
    settings.iter().find_map(|s| match s {
        Setting::Modes { count, .. } => Some(*count),
        _ => None,
    })
}

/// The chart of the kinds of modes: per kind the front of all its runs (every method,
/// step and mode count).
pub(super) fn basis_chart(
    case: &Case,
    report: &SweepReport,
    settings: &[Vec<Setting>],
    path: &Path,
) -> StudyResult {
    let series = case
        .bases
        .iter()
        .enumerate()
        .map(|(k, &kind)| Series {
            label: format!("{} modes", basis_name(kind)),
            points: front(
                report,
                &(0..settings.len())
                    .filter(|&i| plotted(report, i) && basis_of(&settings[i]) == kind)
                    .collect::<Vec<_>>(),
            ),
            dashed: false,
            colour: k,
        })
        .collect();
    error_against_cpu(format!("Kind of modes: {}", case.title), series).write_svg(path)
}
