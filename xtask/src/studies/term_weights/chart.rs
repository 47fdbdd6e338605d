//! Work–precision with the inertia terms as an axis (issue 31 item 4): the 2D spin-up beam
//! (20 s) swept over the terms kept × the step h ([`flexmbd::sweep`], `--grid terms=…
//! --grid step=…`), each run judged against the large-deformation ANCF cable that is
//! `flexmbd tune`'s default reference for the scene ([`Reference::Faithful`]: 16 elements
//! at h = 1 ms), taken as a table from the run the spin-up studies share
//! ([`super::super::spin_up::cable_2d`]: the faithful reference's two refinements, which
//! only estimate its error, 6.7e-6 m on u_y, would cost 9.7 s), and charted as error
//! against CPU time with one line per choice of terms through its steps.

use flexmbd::body::InertiaTerms;
use flexmbd::model::FormulationKind;
use flexmbd::sweep::{
    Axis, Grid, Reference, ReferenceTable, RunStatus, Setting, Sweep, SweepReport, Timing,
};

use crate::Settings;
use crate::chart::Series;
use crate::report::Report;
use crate::studies::StudyResult;
use crate::studies::work_precision::charts::error_against_cpu;

/// The chart's file in the report's folder.
pub const FILE: &str = "work_precision_terms_spin_up_2d.svg";

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

/// The terms and the step of a run.
fn terms_and_step(settings: &[Setting]) -> (InertiaTerms, f64) {
    let mut out = (InertiaTerms::FULL, 0.0);
    for s in settings {
        match s {
            Setting::Terms { terms, .. } => out.0 = *terms,
            Setting::Step(h) => out.1 = *h,
            _ => {}
        }
    }
    out
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
    let mut result = sweep.run()?;
    let points = sweep.point_settings()?;
    // Every point timed alone, not only the front: each line is a choice's own cost.
    let pending: Vec<usize> = (0..result.runs.len())
        .filter(|&i| {
            result.runs[i].status == RunStatus::Ok && result.runs[i].timed != Timing::Alone
        })
        .collect();
    sweep.retime(&mut result, &pending)?;
    let series: Vec<Series> = terms
        .iter()
        .enumerate()
        .map(|(k, choice)| {
            let mut line: Vec<(f64, f64)> = (0..points.len())
                .filter(|&i| terms_and_step(&points[i]).0 == *choice)
                .filter(|&i| result.runs[i].status == RunStatus::Ok && result.runs[i].error > 0.0)
                .map(|i| (result.runs[i].cpu_seconds, result.runs[i].error))
                .collect();
            line.sort_by(|a, b| a.0.total_cmp(&b.0));
            Series {
                label: format!("terms {choice}"),
                points: line,
                dashed: false,
                colour: k,
            }
        })
        .collect();
    let path = report.chart_path(FILE);
    error_against_cpu(
        "Work–precision, inertia terms × step: 2D spin-up beam (20 s)".into(),
        series,
    )
    .write_svg(&path)?;
    report.text(&format!(
        "**Work–precision with the terms as an axis** (2D spin-up beam, 20 s, relative \
         coordinates with shape integrals and FNL1): each line is one choice of terms through \
         the steps {}; each run's error is the largest |Δ tip_uy| over time against {}, its CPU \
         time {}. {confirmed}",
        steps
            .iter()
            .map(|h| format!("{} ms", h * 1e3))
            .collect::<Vec<_>>()
            .join(", "),
        result.reference,
        "timed alone (median of 3 runs, 7 for runs under 0.2 s)",
    ));
    report.image(
        FILE,
        "work–precision, inertia terms × step, 2D spin-up beam",
    );
    let header = table_header(&steps);
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    report.table(&header, &table_rows(&terms, &steps, &points, &result));
    report.text(&format!(
        "Every row is `flexmbd sweep {}` (whose default reference is this cable, with its \
         error estimate).",
        Sweep {
            reference: Reference::Faithful,
            ..sweep.clone()
        }
        .cli_args()
        .expect("the default reference")
        .join(" ")
        .replace(&format!("{}/", crate::workspace_root().display()), "")
    ));
    Ok(())
}

fn table_header(steps: &[f64]) -> Vec<String> {
    std::iter::once("terms".to_string())
        .chain(
            steps
                .iter()
                .map(|h| format!("h = {} ms: error (mm) / CPU (s)", h * 1e3)),
        )
        .collect()
}

fn table_rows(
    terms: &[InertiaTerms],
    steps: &[f64],
    points: &[Vec<Setting>],
    result: &SweepReport,
) -> Vec<Vec<String>> {
    terms
        .iter()
        .map(|choice| {
            let mut row = vec![choice.label()];
            for &h in steps {
                let cell = (0..points.len())
                    .find(|&i| terms_and_step(&points[i]) == (*choice, h))
                    .map(|i| &result.runs[i])
                    .map_or("—".to_string(), |r| match r.status {
                        RunStatus::Ok => format!("{:.4} / {:.3}", r.error * 1e3, r.cpu_seconds),
                        _ => format!("{:?}", r.status),
                    });
                row.push(cell);
            }
            row
        })
        .collect()
}
