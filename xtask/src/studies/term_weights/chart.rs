//! Work–precision with the inertia terms as an axis (issue 31 item 4): the 2D spin-up beam
//! (20 s) swept over the terms kept × the step h ([`flexmbd::sweep`], `--grid terms=…
//! --grid step=…`), each run judged against the large-deformation ANCF cable that is
//! `flexmbd tune`'s default reference for the scene ([`Reference::Faithful`]: 16 elements
//! at h = 1 ms), taken as a table from the run the spin-up studies share
//! ([`super::super::spin_up::cable_2d`]: the faithful reference's two refinements, which
//! only estimate its error, 6.7e-6 m on u_y, would cost 9.7 s), and charted as error
//! against CPU time with one line per choice of terms through its steps. The pieces every
//! terms × step chart shares (the runs timed alone, the lines, the table) are here too;
//! [`four_bar`] charts the double four-bar with them.

pub mod four_bar;

use flexmbd::body::InertiaTerms;
use flexmbd::model::FormulationKind;
use flexmbd::sweep::{
    Axis, Grid, Reference, ReferenceTable, RunRecord, RunStatus, Setting, Sweep, SweepReport,
    Timing,
};

use crate::Settings;
use crate::chart::Series;
use crate::report::Report;
use crate::studies::StudyResult;
use crate::studies::work_precision::charts::error_against_cpu;

/// The chart's file in the report's folder.
pub const FILE: &str = "work_precision_terms_spin_up_2d.svg";

/// How the runs of a terms × step chart are timed (for the text).
const TIMING: &str = "timed alone (median of 3 runs, 7 for runs under 0.2 s)";

/// The sweep: relative coordinates (shape integrals, the scene's FNL1), the terms `terms`,
/// the steps `steps`, judged on `tip_uy` against `reference`.
fn sweep(terms: &[InertiaTerms], steps: &[f64], reference: Reference) -> Sweep {
    Sweep {
        scene: crate::workspace_root().join("models/spin_up_beam_2d.ron"),
        sets: Vec::new(),
        sensors: vec!["tip_uy".into()],
        reference,
        grid: Grid {
            axes: vec![
                Axis::Formulation(vec![FormulationKind::Relative]),
                Axis::Terms {
                    body: None,
                    terms: terms.to_vec(),
                },
                Axis::Step(steps.to_vec()),
            ],
        },
        error_cap: None,
        reference_cache: None,
    }
}

/// A run of a terms × step chart: its line (the terms' label, or the confirmed choice's,
/// [`line_label`]), its step and its record.
pub(super) struct Cell {
    line: String,
    step: f64,
    run: RunRecord,
}

/// The label of a confirmed choice ([`Setting::ChosenTerms`]): `confirmed at 1e-2: o1 ×3,
/// o1-nv ×2` (each distinct choice and on how many bodies, in the bodies' order).
fn confirmed_label(threshold: f64, choices: &[(String, InertiaTerms)]) -> String {
    let mut counts: Vec<(String, usize)> = Vec::new();
    for (_, t) in choices {
        match counts.iter_mut().find(|(l, _)| *l == t.label()) {
            Some(c) => c.1 += 1,
            None => counts.push((t.label(), 1)),
        }
    }
    let parts: Vec<String> = counts
        .iter()
        .map(|(l, n)| {
            if *n == 1 && choices.len() == 1 {
                l.clone()
            } else {
                format!("{l} ×{n}")
            }
        })
        .collect();
    format!("confirmed at {threshold:.0e}: {}", parts.join(", "))
}

/// The line and the step of a run's settings.
fn line_label(settings: &[Setting]) -> (String, f64) {
    let mut out = (InertiaTerms::FULL.label(), 0.0);
    for s in settings {
        match s {
            Setting::Terms { terms, .. } => out.0 = terms.label(),
            Setting::ChosenTerms {
                threshold, choices, ..
            } => out.0 = confirmed_label(*threshold, choices),
            Setting::Step(h) => out.1 = *h,
            _ => {}
        }
    }
    out
}

/// Run `sweep` (its CPU times measured beside other runs) and return its runs as cells.
pub(super) fn untimed_cells(sweep: &Sweep) -> Result<Vec<Cell>, Box<dyn std::error::Error>> {
    let result = sweep.run()?;
    cells_of(sweep, result.runs)
}

/// The cells of `runs`, the runs of `sweep`'s points in grid order.
fn cells_of(sweep: &Sweep, runs: Vec<RunRecord>) -> Result<Vec<Cell>, Box<dyn std::error::Error>> {
    let points = sweep.point_settings()?;
    Ok(points
        .iter()
        .zip(runs)
        .map(|(p, run)| {
            let (line, step) = line_label(p);
            Cell { line, step, run }
        })
        .collect())
}

/// Run `sweep`, time every finished run alone (not only the front: each line is a
/// choice's own cost), and return its report and its runs as cells.
pub(super) fn timed_cells(
    sweep: &Sweep,
) -> Result<(SweepReport, Vec<Cell>), Box<dyn std::error::Error>> {
    let mut result = sweep.run()?;
    let pending: Vec<usize> = (0..result.runs.len())
        .filter(|&i| {
            result.runs[i].status == RunStatus::Ok && result.runs[i].timed != Timing::Alone
        })
        .collect();
    sweep.retime(&mut result, &pending)?;
    let cells = cells_of(sweep, result.runs.clone())?;
    Ok((result, cells))
}

/// The lines of `cells` in their first appearance's order.
pub(super) fn lines(cells: &[Cell]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for c in cells {
        if !out.contains(&c.line) {
            out.push(c.line.clone());
        }
    }
    out
}

/// One series per line of `cells` through its steps: CPU time against error, the finished
/// runs with a positive error.
pub(super) fn series(cells: &[Cell]) -> Vec<Series> {
    lines(cells)
        .iter()
        .enumerate()
        .map(|(k, line)| {
            let mut points: Vec<(f64, f64)> = cells
                .iter()
                .filter(|c| c.line == *line)
                .filter(|c| c.run.status == RunStatus::Ok && c.run.error > 0.0)
                .map(|c| (c.run.cpu_seconds, c.run.error))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            Series {
                label: format!("terms {line}"),
                points,
                dashed: false,
                colour: k,
            }
        })
        .collect()
}

/// The report's table of a terms × step chart: one row per line, one column per step headed
/// `column(h)`, each finished run's cell written by `cell`.
pub(super) fn write_table(
    report: &mut Report,
    cells: &[Cell],
    steps: &[f64],
    column: impl Fn(f64) -> String,
    cell: impl Fn(&Cell) -> String,
) {
    let header: Vec<String> = std::iter::once("terms".to_string())
        .chain(steps.iter().map(|&h| column(h)))
        .collect();
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let rows: Vec<Vec<String>> = lines(cells)
        .iter()
        .map(|line| {
            let mut row = vec![line.clone()];
            for &h in steps {
                row.push(
                    cells
                        .iter()
                        .find(|c| c.line == *line && c.step == h)
                        .map_or("—".to_string(), |c| match c.run.status {
                            RunStatus::Ok => cell(c),
                            s => format!("{s:?}"),
                        }),
                );
            }
            row
        })
        .collect();
    report.table(&header, &rows);
}

/// The steps as text: `2 ms, 1 ms`.
pub(super) fn steps_text(steps: &[f64]) -> String {
    steps
        .iter()
        .map(|h| format!("{} ms", h * 1e3))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `flexmbd sweep`'s arguments for `sweep`, the workspace's root left off the paths.
pub(super) fn command(sweep: &Sweep) -> String {
    format!(
        "flexmbd sweep {}",
        sweep
            .cli_args()
            .expect("a file or the default reference")
            .join(" ")
            .replace(&format!("{}/", crate::workspace_root().display()), "")
    )
}

/// Run the sweep, write the chart and its table; `confirmed` names the choices the
/// confirmation made on this scene (for the text).
pub fn run(settings: &Settings, report: &mut Report, confirmed: &str) -> StudyResult {
    let h = 1e-3;
    let steps: Vec<f64> = if settings.quick {
        vec![2.0 * h, h]
    } else {
        vec![2.0 * h, h, h / 2.0]
    };
    let t = |order, velocity, coupling| InertiaTerms {
        order,
        velocity,
        coupling,
    };
    let terms: Vec<InertiaTerms> = if settings.quick {
        vec![InertiaTerms::FULL, t(2, false, true), t(1, true, true)]
    } else {
        vec![
            InertiaTerms::FULL,
            t(2, false, true),
            t(1, true, true),
            t(1, false, true),
            t(0, true, true),
        ]
    };
    let cable = crate::studies::spin_up::cable_2d()?;
    let table = ReferenceTable::new(
        "the ANCF cable (large deformation), 16 elements, h = 0.001 s: `flexmbd tune`'s \
         default reference for this scene (its error estimate, 6.7e-6 m on u_y, is not \
         recomputed here)",
        cable.t.clone(),
        vec!["tip_uy".into()],
        vec![cable.tip.iter().map(|d| d[1]).collect()],
    )?;
    let sweep = sweep(&terms, &steps, Reference::Table(table));
    let (result, cells) = timed_cells(&sweep)?;
    let path = report.chart_path(FILE);
    error_against_cpu(
        "Work–precision, inertia terms × step: 2D spin-up beam (20 s)".into(),
        series(&cells),
    )
    .write_svg(&path)?;
    report.text(&format!(
        "**Work–precision with the terms as an axis** (2D spin-up beam, 20 s, relative \
         coordinates with shape integrals and FNL1): each line is one choice of terms through \
         the steps {}; each run's error is the largest |Δ tip_uy| over time against {}, its CPU \
         time {TIMING}. {confirmed}",
        steps_text(&steps),
        result.reference,
    ));
    report.image(
        FILE,
        "work–precision, inertia terms × step, 2D spin-up beam",
    );
    write_table(
        report,
        &cells,
        &steps,
        |h| format!("h = {} ms: error (mm) / CPU (s)", h * 1e3),
        |c| format!("{:.4} / {:.3}", c.run.error * 1e3, c.run.cpu_seconds),
    );
    report.text(&format!(
        "Every row is `{}` (whose default reference is this cable, with its error estimate).",
        command(&Sweep {
            reference: Reference::Faithful,
            ..sweep.clone()
        })
    ));
    Ok(())
}
