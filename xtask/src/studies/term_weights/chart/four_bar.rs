//! Work–precision with the inertia terms as an axis on the double four-bar with its five bars
//! flexible (docs/scenes.md §1; relative coordinates, shape integrals, 2 static + 2 normal
//! modes per bar), over the horizon of the section's case (1 s quick, 5 s full): the terms
//! (every term, the choices confirmed at 1e-2 and 1e-3 by one pilot of the scene at its
//! step, `--grid terms=auto@…`, every bar at order 1, and every bar at order 1 without the
//! rigid–elastic couplings) × the steps 2, 1 and 0.5 ms. Each run's error is
//! the largest |Δ| over time of the joint B0's position (`B0_x`, `B0_y`, m) against the
//! **full model at h/16** (62.5 µs; h/32 over the full report's 5 s, where the full model
//! at h/8 and at h/16 differ by 4.9e-4 m, against 1.1e-6 m over 1 s) in the same
//! formulation: the chart separates the step's
//! error from the terms' within the floating frame's model; it does not judge that model
//! against a large-deformation one (the default reference of `flexmbd sweep` here, the bars
//! substructured at a quarter of the smallest step, is over the quick run's budget). The
//! reference's own error is estimated by its difference from the same model at h/8. The
//! terms' own error, each choice against the full model at the same step (the same sweeps,
//! one step each, judged against the full model's run at that step), is tabled beside it.

use flexmbd::body::InertiaTerms;
use flexmbd::model::{FormulationKind, Scene};
use flexmbd::simulation::{self, History};
use flexmbd::sweep::{Axis, Grid, Reference, ReferenceTable, RunStatus, Sweep};

use super::{Cell, TIMING, command, series, steps_text, timed_cells, untimed_cells, write_table};
use crate::Settings;
use crate::report::Report;
use crate::studies::work_precision::charts::error_against_cpu;
use crate::studies::{StudyResult, check_run, model_with_sets};

/// The chart's file in the report's folder.
pub const FILE: &str = "work_precision_terms_four_bar.svg";

/// The scene's file.
const SCENE: &str = "double_four_bar.ron";

/// The judged sensors: the position of the joint B0 (crank1's tip).
const SENSORS: [&str; 2] = ["B0_x", "B0_y"];

/// The scene's step over the reference's (quick, full report); the reference's error is
/// estimated against the full model at twice the reference's step.
const REFERENCE_REFINEMENT: [f64; 2] = [16.0, 32.0];

/// The scene's overrides: the five bars flexible, the horizon `duration`.
fn sets(duration: f64) -> Vec<String> {
    ["crank1", "coupler1", "crank2", "coupler2", "crank3"]
        .iter()
        .map(|b| format!("bodies.{b}.flexible=true"))
        .chain([format!("solver.duration={duration}")])
        .collect()
}

/// The scene with every term (relative formulation) at step `h`.
fn scene_at(duration: f64, h: f64) -> Result<Scene, Box<dyn std::error::Error>> {
    let mut scene = model_with_sets(SCENE, &sets(duration))?;
    scene.solver.formulation = FormulationKind::Relative;
    scene.solver.step = h;
    scene.validate()?;
    Ok(scene)
}

/// The full model's run at step `h`.
fn full_run(duration: f64, h: f64) -> Result<History, Box<dyn std::error::Error>> {
    let (summary, history) = simulation::run(&scene_at(duration, h)?, |_| {})?;
    check_run(&summary, "double four-bar reference")?;
    Ok(history)
}

/// max over the judged sensors of max_t |a − b| (m), on the same output instants.
fn largest_difference(a: &History, b: &History) -> f64 {
    SENSORS
        .iter()
        .filter_map(|s| Some((a.column(s)?, b.column(s)?)))
        .map(|(x, y)| {
            x.iter()
                .zip(&y)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

/// The sweep over the terms axis `terms` × `steps` (relative coordinates), judged on B0
/// against `reference`.
fn sweep(duration: f64, terms: Axis, steps: &[f64], reference: Reference) -> Sweep {
    Sweep {
        scene: crate::workspace_root().join("models").join(SCENE),
        sets: sets(duration),
        sensors: SENSORS.iter().map(|s| s.to_string()).collect(),
        reference,
        grid: Grid {
            axes: vec![
                Axis::Formulation(vec![FormulationKind::Relative]),
                terms,
                Axis::Step(steps.to_vec()),
            ],
        },
        error_cap: None,
        reference_cache: None,
    }
}

/// The error of `line` at step `h` (m), if it finished.
fn error_of(cells: &[Cell], line: &str, h: f64) -> Option<f64> {
    cells
        .iter()
        .find(|c| c.line == line && c.step == h && c.run.status == RunStatus::Ok)
        .map(|c| c.run.error)
}

/// What the chart shows, read off its runs (`cells`, against the reference) and the terms'
/// own errors (`own`, against the full model at the same step): per choice, the steps at
/// which its own error is below the step's (the full model's error), where the step's
/// error dominates and its line lies on the full model's, and those at which it is above.
/// The confirmed choices' own errors are also given relative to `range`, the smallest range
/// of the judged sensors over the reference (their tolerance is relative to the range).
fn reading(cells: &[Cell], own: &[Cell], steps: &[f64], full: &str, range: f64) -> String {
    let step_error: Option<Vec<f64>> = steps.iter().map(|&h| error_of(cells, full, h)).collect();
    let Some(step_error) = step_error else {
        return "The full model did not finish at every step.".into();
    };
    let listed = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.2e}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut text = format!(
        "**What it shows.** The step's error (the full model's) is {} m at h = {} ms; B0's \
         smallest range over the run is {range:.2} m. ",
        listed(&step_error),
        steps
            .iter()
            .map(|h| format!("{}", h * 1e3))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for line in super::lines(cells).iter().filter(|l| *l != full) {
        let own: Vec<Option<f64>> = steps.iter().map(|&h| error_of(own, line, h)).collect();
        if own.iter().any(Option::is_none) {
            text += &format!("**{line}**: did not finish at every step. ");
            continue;
        }
        let own: Vec<f64> = own.into_iter().flatten().collect();
        let above: Vec<String> = (0..steps.len())
            .filter(|&k| own[k] > step_error[k])
            .map(|k| format!("{} ms", steps[k] * 1e3))
            .collect();
        let largest = own.iter().cloned().fold(0.0, f64::max);
        let relative = if line.starts_with("confirmed") {
            format!(" ({:.1e} of the range)", largest / range)
        } else {
            String::new()
        };
        text += &format!(
            "**{line}**: its own error, at most {largest:.1e} m{relative}, is {}. ",
            if above.is_empty() {
                "below the step's at every step: the step's error dominates".to_string()
            } else if above.len() == steps.len() {
                "above the step's at every step: the terms' error dominates".to_string()
            } else {
                format!(
                    "above the step's at h = {}: the terms' error dominates there",
                    above.join(", ")
                )
            }
        );
        // A run nearer the reference than the full model at the same step (by more than a
        // tenth) is no better model: its own error and the step's partly cancel.
        let cancelling: Vec<String> = (0..steps.len())
            .filter(|&k| own[k] > 0.0)
            .filter_map(|k| {
                let e = error_of(cells, line, steps[k])?;
                (e < 0.9 * step_error[k]).then(|| {
                    format!(
                        "{e:.2e} m against {:.2e} m at {} ms",
                        step_error[k],
                        steps[k] * 1e3
                    )
                })
            })
            .collect();
        if !cancelling.is_empty() {
            text += &format!(
                "Its error is below the full model's ({}): the two errors partly cancel, \
                 no better model. ",
                cancelling.join(", ")
            );
        }
    }
    text
}

/// Each choice's own error (`sweeps`' lines against the full model at the same step): one
/// sweep per step and per sweep, judged against the full model's run at that step, untimed.
fn own_errors(
    duration: f64,
    sweeps: &[&Sweep],
    steps: &[f64],
) -> Result<Vec<Cell>, Box<dyn std::error::Error>> {
    let mut cells = Vec::new();
    for &h in steps {
        let full = reference_table(
            &full_run(duration, h)?,
            format!("the full model at h = {h} s"),
        )?;
        for s in sweeps {
            let mut at_h = (*s).clone();
            at_h.reference = Reference::Table(full.clone());
            at_h.grid.axes = at_h
                .grid
                .axes
                .into_iter()
                .map(|a| match a {
                    Axis::Step(_) => Axis::Step(vec![h]),
                    a => a,
                })
                .collect();
            cells.extend(untimed_cells(&at_h)?);
        }
    }
    Ok(cells)
}

/// The judged sensors of `history` as a reference table.
fn reference_table(
    history: &History,
    origin: String,
) -> Result<ReferenceTable, Box<dyn std::error::Error>> {
    Ok(ReferenceTable::new(
        origin,
        history.rows.iter().map(|r| r[0]).collect(),
        SENSORS.iter().map(|s| s.to_string()).collect(),
        SENSORS
            .iter()
            .map(|s| history.column(s).ok_or(format!("no sensor {s}")))
            .collect::<Result<_, _>>()?,
    )?)
}

/// Run the sweeps, write the chart and its table.
pub fn run(settings: &Settings, report: &mut Report) -> StudyResult {
    let duration = if settings.quick { 1.0 } else { 5.0 };
    let h = 1e-3;
    let steps = vec![2.0 * h, h, h / 2.0];
    let clock = std::time::Instant::now();
    let h_ref = h / REFERENCE_REFINEMENT[usize::from(!settings.quick)];
    let reference = full_run(duration, h_ref)?;
    let estimate = largest_difference(&full_run(duration, 2.0 * h_ref)?, &reference);
    let table = reference_table(
        &reference,
        format!(
            "the full model at h = {} µs (its difference from the full model at h = {} µs, \
             {estimate:.1e} m, estimates its error)",
            h_ref * 1e6,
            2.0 * h_ref * 1e6
        ),
    )?;
    let t = |order, velocity, coupling| InertiaTerms {
        order,
        velocity,
        coupling,
    };
    let chosen = vec![InertiaTerms::FULL, t(1, true, true), t(1, true, false)];
    let named = sweep(
        duration,
        Axis::Terms {
            body: None,
            terms: chosen.clone(),
        },
        &steps,
        Reference::Table(table.clone()),
    );
    let auto = sweep(
        duration,
        Axis::AutoTerms {
            body: None,
            thresholds: vec![1e-2, 1e-3],
        },
        &steps,
        Reference::Table(table),
    );
    let (result, mut cells) = timed_cells(&named)?;
    let (_, auto_cells) = timed_cells(&auto)?;
    // Every term first, then the confirmed choices, then the named ones dropping more.
    let rest = cells.split_off(steps.len());
    cells.extend(auto_cells);
    cells.extend(rest);
    let own = own_errors(duration, &[&named, &auto], &steps)?;
    let elapsed = clock.elapsed().as_secs_f64();
    let path = report.chart_path(FILE);
    error_against_cpu(
        format!(
            "Work–precision, inertia terms × step: double four-bar, 5 flexible bars ({duration} s)"
        ),
        series(&cells),
    )
    .write_svg(&path)?;
    report.text(&format!(
        "**Work–precision with the terms as an axis: the double four-bar** (5 flexible bars, \
         {duration} s, relative coordinates with shape integrals; {elapsed:.1} s for the \
         reference, the pilot and every run): each line is one choice of terms through the \
         steps {}; each run's error is the largest |Δ| of B0_x and B0_y over time against {}, \
         its CPU time {TIMING}; its own error is the terms': against the full model at the same \
         step. The reference is of the same model family as the runs: the \
         chart weighs the terms' error against the step's, not the floating frame's model \
         against a large-deformation one. The confirmed choices are made once by a pilot of \
         the scene at h = 1 ms and set at every step; a line's label counts the bars given \
         each choice.",
        steps_text(&steps),
        result.reference,
    ));
    report.image(
        FILE,
        "work–precision, inertia terms × step, double four-bar",
    );
    write_table(
        report,
        &cells,
        &steps,
        |h| format!("h = {} ms: error / own error (m) / CPU (s)", h * 1e3),
        |c| {
            let own = error_of(&own, &c.line, c.step).map_or("—".into(), |e| format!("{e:.1e}"));
            format!("{:.2e} / {own} / {:.3}", c.run.error, c.run.cpu_seconds)
        },
    );
    let range = SENSORS
        .iter()
        .filter_map(|s| reference.column(s))
        .map(|y| {
            y.iter().cloned().fold(f64::MIN, f64::max) - y.iter().cloned().fold(f64::MAX, f64::min)
        })
        .fold(f64::INFINITY, f64::min);
    report.text(&reading(
        &cells,
        &own,
        &steps,
        &InertiaTerms::FULL.label(),
        range,
    ));
    let csv = format!("four_bar_full_h{}us.csv", h_ref * 1e6);
    let simulate = format!(
        "flexmbd simulate models/{SCENE} {} --formulation relative --step {h_ref} --output {csv}",
        sets(duration)
            .iter()
            .map(|s| format!("--set {s}"))
            .collect::<Vec<_>>()
            .join(" ")
    );
    let file = |s: Sweep| {
        command(&Sweep {
            reference: Reference::Csv(csv.clone().into()),
            ..s
        })
    };
    report.text(&format!(
        "The reference is `{simulate}`; the named choices' rows are `{}`, the confirmed \
         choices' `{}`.",
        file(named),
        file(auto)
    ));
    Ok(())
}
