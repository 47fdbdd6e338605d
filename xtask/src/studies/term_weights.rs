//! Inertia terms by weight (issue 31 items 2 and 4; docs/design.md "Inertia terms by
//! weight"): on the spin-up beams, the double four-bar with five flexible bars and the Iltis
//! vehicle with its 12 beam bodies flexible (relative formulation, shape integrals), each
//! flexible body's term groups weighed over a pilot run of the full model
//! ([`flexmbd::term_weights`]), the choices at two thresholds, and what they save and cost:
//! CPU time of the run against the full model's, and the error they add against it (largest
//! |Δ| over the judged sensors, relative to the sensor's range); the weights' choice and the
//! choice confirmed at the same tolerance ([`flexmbd::term_weights::Pilot::confirm`]); and
//! work–precision charts with the terms as an axis: the 2D spin-up beam against the ANCF
//! cable ([`chart`]) and the double four-bar against its full model at a sixteenth of the
//! step ([`chart::four_bar`]).

mod chart;

use flexmbd::body::weights::{TermGroup, Weight};
use flexmbd::model::{FormulationKind, Scene};
use flexmbd::simulation::{self, History};
use flexmbd::term_weights::{BodyWeights, TermChoice, apply_choice, pilot};
use flexmbd_test_support::iltis::vehicle_flexible;

use super::{StudyResult, check_run, model_with_sets};
use crate::Settings;
use crate::report::Report;

/// The thresholds of the choices reported.
const THRESHOLDS: [f64; 2] = [1e-2, 1e-3];

/// One scene of the section.
struct Case {
    label: &'static str,
    scene: Scene,
    sensors: &'static [&'static str],
}

fn load(file: &str, sets: &[String], duration: f64) -> Result<Scene, Box<dyn std::error::Error>> {
    let mut scene = model_with_sets(file, sets)?;
    scene.solver.formulation = FormulationKind::Relative;
    scene.solver.duration = duration;
    scene.validate()?;
    Ok(scene)
}

fn cases(quick: bool) -> Result<Vec<Case>, Box<dyn std::error::Error>> {
    let bars: Vec<String> = ["crank1", "coupler1", "crank2", "coupler2", "crank3"]
        .iter()
        .map(|b| format!("bodies.{b}.flexible=true"))
        .collect();
    Ok(vec![
        Case {
            label: "spin-up beam 2D (20 s)",
            scene: load("spin_up_beam_2d.ron", &[], 20.0)?,
            sensors: &["tip_ux", "tip_uy"],
        },
        Case {
            label: if quick {
                "spin-up beam 3D (10 s)"
            } else {
                "spin-up beam 3D (20 s)"
            },
            scene: load("spin_up_beam_3d.ron", &[], if quick { 10.0 } else { 20.0 })?,
            sensors: &["tip_ux", "tip_uy", "tip_uz"],
        },
        Case {
            label: if quick {
                "double four-bar, 5 flexible bars (1 s)"
            } else {
                "double four-bar, 5 flexible bars (5 s)"
            },
            scene: load("double_four_bar.ron", &bars, if quick { 1.0 } else { 5.0 })?,
            sensors: &["B0_x", "B0_y"],
        },
        Case {
            label: if quick {
                "Iltis vehicle, 12 flexible bodies (1 s; on the ramp from 0.65 s)"
            } else {
                "Iltis vehicle, 12 flexible bodies (3 s; on the ramp from 0.65 s)"
            },
            scene: load(
                "iltis_vehicle.ron",
                &vehicle_flexible(12),
                if quick { 1.0 } else { 3.0 },
            )?,
            sensors: &["chassis_z", "wheel_fl_z"],
        },
    ])
}

/// A run's history and its CPU time (median of `reps`).
fn timed(
    scene: &Scene,
    reps: usize,
    what: &str,
) -> Result<(History, f64), Box<dyn std::error::Error>> {
    let mut cpu = Vec::new();
    let mut last = None;
    for _ in 0..reps {
        let (summary, h) = simulation::run(scene, |_| {})?;
        check_run(&summary, what)?;
        cpu.push(summary.cpu_seconds);
        last = Some(h);
    }
    cpu.sort_by(f64::total_cmp);
    Ok((last.expect("at least one run"), cpu[cpu.len() / 2]))
}

/// max over `sensors` of max |a − b| / range(b).
fn error(a: &History, b: &History, sensors: &[&str]) -> f64 {
    sensors
        .iter()
        .filter_map(|s| Some((a.column(s)?, b.column(s)?)))
        .map(|(x, y)| {
            let hi = y.iter().cloned().fold(f64::MIN, f64::max);
            let lo = y.iter().cloned().fold(f64::MAX, f64::min);
            let d = x
                .iter()
                .zip(&y)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            d / (hi - lo).max(f64::MIN_POSITIVE)
        })
        .fold(0.0, f64::max)
}

fn group(w: &BodyWeights, g: TermGroup) -> Weight {
    w.table
        .groups
        .iter()
        .find(|(x, _)| *x == g)
        .map_or(Weight::default(), |x| x.1)
}

fn weights_table(report: &mut Report, weights: &[BodyWeights]) -> StudyResult {
    let mut rows = Vec::new();
    for w in weights {
        let mut row = vec![format!("{} ({} modes)", w.body, w.modes)];
        for g in TermGroup::ALL {
            let x = group(w, g);
            row.push(format!(
                "{:.1e} / {:.1e} / {:.1e}",
                x.rigid_max, x.modal_max, x.deformation_max
            ));
        }
        for t in THRESHOLDS {
            row.push(w.choose(t)?.label());
        }
        rows.push(row);
    }
    report.table(
        &[
            "body",
            "second order",
            "first order",
            "coupling",
            "gyroscopic",
            "chosen at 1e-2",
            "chosen at 1e-3",
        ],
        &rows,
    );
    Ok(())
}

/// The labels of a choice's distinct terms (`o1, o1-nv`).
fn labels(choices: &[(String, flexmbd::body::InertiaTerms)]) -> String {
    let mut labels: Vec<String> = choices.iter().map(|(_, c)| c.label()).collect();
    labels.dedup();
    labels.join(", ")
}

/// The row of the confirmed choice: its terms, the rungs rejected before it, its error over
/// the pilot (the same run as the full model's horizon here).
fn confirmed_row(label: &str, c: &TermChoice, steps: f64) -> Vec<String> {
    let rejected: Vec<String> = c
        .rejected
        .iter()
        .map(|t| format!("{} {:.1e}", labels(&t.choices), t.error))
        .collect();
    vec![
        label.to_string(),
        format!(
            "confirmed at {:.0e}: {}{}",
            c.tolerance,
            labels(&c.chosen.choices),
            if rejected.is_empty() {
                String::new()
            } else {
                format!(" (rejected: {})", rejected.join("; "))
            }
        ),
        format!("{:.3}", c.chosen.cpu_seconds),
        format!("{:.2}", 1e6 * c.chosen.cpu_seconds / steps),
        format!("{:.1e}", c.chosen.error),
    ]
}

/// The section.
pub fn run(settings: &Settings, report: &mut Report) -> StudyResult {
    let reps = if settings.quick { 1 } else { 3 };
    report.text(
        "Each flexible body's inertia terms weighed over a pilot run of the full model \
         (`flexmbd terms`, relative formulation, shape integrals): for each group, the largest \
         change its removal makes to the body's inertia force over the run, relative to the \
         largest full force, in the rigid part / the modal part (kinetic-energy norms) / the \
         deformation it would cause against the deformation (strain-energy norm). The weights' \
         choice at a threshold is the cheapest set of terms whose dropped groups all weigh at \
         most it. The threshold bounds forces, not the trajectory: the second table judges each \
         choice against the full model's run (largest |Δ| on the sensors named, relative to the \
         sensor's range) and gives its CPU time (median of {reps} run(s)). The **confirmed** \
         choice at tolerance X (`flexmbd terms --threshold X`, `--grid terms=auto@X`) runs the \
         weights' choices in place of the full model over the pilot, from the weights' choice at \
         X down to every term kept, and takes the first whose judged sensors move by at most X \
         of their range: X is met on the pilot's horizon and sensors (here the whole run), not \
         beyond; its CPU is one run's.\n"
            .replace("{reps}", &reps.to_string())
            .as_str(),
    );
    let mut cost_rows = Vec::new();
    let mut spin_up_2d = String::new();
    for case in cases(settings.quick)? {
        let clock = std::time::Instant::now();
        let judged: Vec<String> = case.sensors.iter().map(|s| s.to_string()).collect();
        let pilot = pilot(&case.scene, None, &judged)?;
        let weights = &pilot.weights;
        let elapsed = clock.elapsed().as_secs_f64();
        report.text(&format!(
            "**{}** (pilot {elapsed:.2} s; rigid / modal / deformation weights, max over the run):\n",
            case.label
        ));
        weights_table(report, weights)?;
        let (full, full_cpu) = timed(&case.scene, reps, case.label)?;
        let steps = (case.scene.solver.duration / case.scene.solver.step).round();
        cost_rows.push(vec![
            case.label.to_string(),
            "full".into(),
            format!("{full_cpu:.3}"),
            format!("{:.2}", 1e6 * full_cpu / steps),
            "0".into(),
        ]);
        for t in THRESHOLDS {
            let (scene, choices) = apply_choice(&case.scene, weights, t)?;
            let (h, cpu) = timed(&scene, reps, case.label)?;
            cost_rows.push(vec![
                case.label.to_string(),
                format!("weights at {t:.0e}: {}", labels(&choices)),
                format!("{cpu:.3}"),
                format!("{:.2}", 1e6 * cpu / steps),
                format!("{:.1e}", error(&h, &full, case.sensors)),
            ]);
            let confirmed = pilot.confirm(t, None)?;
            if case.label.starts_with("spin-up beam 2D") {
                spin_up_2d += &format!(
                    "Confirmed at {t:.0e} on this scene: {}. ",
                    labels(&confirmed.chosen.choices)
                );
            }
            cost_rows.push(confirmed_row(case.label, &confirmed, steps));
        }
    }
    report.text(
        "**Cost saved against error added** (the choices above run in place of the full model):\n",
    );
    report.table(
        &[
            "scene",
            "terms",
            "CPU (s)",
            "CPU per step (µs)",
            "error vs full / range",
        ],
        &cost_rows,
    );
    report.text(
        "The inertia kernels are a small part of a step (the constraints, the leading matrix \
         and its factorisation are most of it), so what a dropped term saves per step is within \
         the timing noise of these runs; `cargo bench -p flexmbd-benches --bench inertia` \
         (`inertia_terms_*`) times the kernels alone. A pilot costs one run of the full model, \
         a confirmation one run per rung it tries.\n",
    );
    chart::run(settings, report, &spin_up_2d)?;
    chart::four_bar::run(settings, report)?;
    Ok(())
}
