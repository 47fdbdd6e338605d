//! `flexmbd terms SCENE.ron [--threshold X] [--duration T] [--sensor S,…] [--json]`: the
//! weight of each flexible body's inertia terms over a pilot run of the full model, each
//! body's cheapest terms whose dropped groups weigh at most X (the weights' choice), and
//! the choice confirmed at tolerance X: the weights' ladder run rung by rung in place of the
//! full model over the pilot, the first whose judged sensors move by at most X of their
//! range taken, with its measured error and cost ([`flexmbd::term_weights`],
//! docs/design.md "Inertia terms by weight").

use std::fmt::Write as _;

use clap::Args;
use flexmbd::body::InertiaMethod;
use flexmbd::body::weights::kernel_work;
use flexmbd::term_weights::{BodyWeights, TermChoice, Trial, pilot};
use serde_json::json;

use crate::{CliResult, SceneInput, exit, print_json_or_table};

/// The arguments of `flexmbd terms`.
#[derive(Args)]
pub(crate) struct TermsArgs {
    #[command(flatten)]
    input: SceneInput,
    /// The tolerance (in (0, 1)): the largest change of a judged sensor, relative to its
    /// range over the pilot, the chosen terms may make; also the largest weight, relative
    /// to the full inertia force, of the terms the weights' choice drops.
    #[arg(long, default_value_t = 1e-3, allow_negative_numbers = true)]
    threshold: f64,
    /// The pilot run's duration (s; default and at most the scene's): the horizon on which
    /// the choice is confirmed.
    #[arg(long, allow_negative_numbers = true)]
    duration: Option<f64>,
    /// The sensors the choice is judged on, comma-separated (default: every sensor of the
    /// scene but the energy).
    #[arg(long = "sensor", value_delimiter = ',')]
    sensors: Vec<String>,
    /// Print one JSON object on stdout instead of a table.
    #[arg(long)]
    json: bool,
}

/// One body's weights and choice as JSON.
fn body_json(w: &BodyWeights, threshold: f64) -> Result<serde_json::Value, flexmbd::Error> {
    let chosen = w.choose(threshold)?;
    let weight = |x: &flexmbd::body::weights::Weight| {
        json!({"rigid_max": x.rigid_max, "rigid_rms": x.rigid_rms,
               "modal_max": x.modal_max, "modal_rms": x.modal_rms,
               "deformation_max": x.deformation_max, "deformation_rms": x.deformation_rms})
    };
    let groups: Vec<_> = w
        .table
        .groups
        .iter()
        .map(|(g, x)| {
            json!({"group": g.name(), "weight": weight(x), "dropped": g.dropped_by(chosen)})
        })
        .collect();
    let candidates: Vec<_> = w
        .table
        .candidates
        .iter()
        .map(|(t, x)| json!({"terms": t.label(), "kernel_work_n2": kernel_work(*t), "weight": weight(x)}))
        .collect();
    Ok(
        json!({"body": w.body, "modes": w.modes, "samples": w.table.samples,
              "groups": groups, "candidates": candidates, "chosen": chosen.label()}),
    )
}

/// The table of one body.
fn body_text(w: &BodyWeights, threshold: f64) -> Result<String, flexmbd::Error> {
    let chosen = w.choose(threshold)?;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "body {} ({} modes, {} samples)",
        w.body, w.modes, w.table.samples
    );
    let _ = writeln!(
        s,
        "  {:<14}{:>11}{:>11}{:>11}{:>11}{:>11}{:>11}   at {threshold:.0e}",
        "group", "rigid max", "rigid rms", "modal max", "modal rms", "deform max", "deform rms"
    );
    for (g, x) in &w.table.groups {
        let _ = writeln!(
            s,
            "  {:<14}{:>11.2e}{:>11.2e}{:>11.2e}{:>11.2e}{:>11.2e}{:>11.2e}   {}",
            g.name(),
            x.rigid_max,
            x.rigid_rms,
            x.modal_max,
            x.modal_rms,
            x.deformation_max,
            x.deformation_rms,
            if g.dropped_by(chosen) {
                "dropped"
            } else {
                "kept"
            }
        );
    }
    let _ = writeln!(
        s,
        "  {:<14}{:>11}{:>11}{:>11}{:>11}   (what each choice drops, weighed at once; cheapest first)",
        "terms", "work n²", "rigid max", "modal max", "deform max"
    );
    for (t, x) in &w.table.candidates {
        let _ = writeln!(
            s,
            "  {:<14}{:>11}{:>11.2e}{:>11.2e}{:>11.2e}{}",
            t.label(),
            kernel_work(*t),
            x.rigid_max,
            x.modal_max,
            x.deformation_max,
            if *t == chosen { "   ← chosen" } else { "" }
        );
    }
    let _ = writeln!(s, "  weights' choice at {threshold:.0e}: {chosen}");
    Ok(s)
}

/// One rung of the ladder as JSON.
fn trial_json(t: &Trial) -> serde_json::Value {
    let choices: serde_json::Map<String, serde_json::Value> = t
        .choices
        .iter()
        .map(|(b, terms)| (b.clone(), json!(terms.label())))
        .collect();
    let errors: serde_json::Map<String, serde_json::Value> = t
        .errors
        .iter()
        .map(|(s, e)| (s.clone(), json_number(*e)))
        .collect();
    json!({"terms": choices, "weight": t.weight, "pilot_error": json_number(t.error),
           "sensor_errors": errors, "cpu_seconds": t.cpu_seconds,
           "kernel_work_n2": t.kernel_work, "failure": t.failure})
}

/// A number, or the text `inf` for an infinite error (a run that failed).
fn json_number(x: f64) -> serde_json::Value {
    if x.is_finite() {
        json!(x)
    } else {
        json!("inf")
    }
}

/// The confirmed choice as JSON.
fn choice_json(c: &TermChoice) -> serde_json::Value {
    json!({"tolerance": c.tolerance, "horizon_seconds": c.horizon, "sensors": c.sensors,
           "chosen": trial_json(&c.chosen),
           "rejected": c.rejected.iter().map(trial_json).collect::<Vec<_>>(),
           "weights_choice": c.weights_choice().label(),
           "full_cpu_seconds": c.full_cpu_seconds, "full_kernel_work_n2": c.full_kernel_work})
}

/// The confirmed choice as text: each rung run, then the choice.
fn choice_text(c: &TermChoice) -> String {
    let mut s = format!(
        "confirmed at {:.0e}: the weights' ladder run in place of the full model over the pilot \
         ({} s), judged on {} (largest |Δ| / the sensor's range)\n",
        c.tolerance,
        c.horizon,
        c.sensors.join(", ")
    );
    let _ = writeln!(
        s,
        "  {:<24}{:>11}{:>13}{:>10}{:>16}",
        "terms", "weight", "pilot error", "CPU (s)", "kernel work n²"
    );
    for t in c.rejected.iter().chain(std::iter::once(&c.chosen)) {
        let verdict = match &t.failure {
            Some(why) => format!("rejected: failed: {why}"),
            None if t.error <= c.tolerance => "← chosen".into(),
            None => "rejected".into(),
        };
        let _ = writeln!(
            s,
            "  {:<24}{:>11.2e}{:>13.2e}{:>10.3}{:>16}   {verdict}",
            t.label(),
            t.weight,
            t.error,
            t.cpu_seconds,
            t.kernel_work
        );
    }
    let _ = writeln!(
        s,
        "chosen at {:.0e}: {} (pilot error {:.2e}; CPU {:.3} s against the full model's {:.3} s; \
         kernel work {} of {} n² multiply-adds)",
        c.tolerance,
        c.chosen.label(),
        c.chosen.error,
        c.chosen.cpu_seconds,
        c.full_cpu_seconds,
        c.chosen.kernel_work,
        c.full_kernel_work
    );
    s
}

/// `flexmbd terms`.
pub(crate) fn terms(args: &TermsArgs) -> CliResult {
    flexmbd::body::weights::check_threshold(args.threshold).map_err(|e| format!("--{e}"))?;
    let scene = args.input.load()?;
    scene.validate()?;
    let pilot = match pilot(&scene, args.duration, &args.sensors) {
        Ok(p) => p,
        Err(e @ (flexmbd::Error::Integrator(_) | flexmbd::Error::Static(_))) => {
            eprintln!(
                "error: {}: the pilot run failed: {e}",
                args.input.scene.display()
            );
            return Ok(exit::RUN_FAILED);
        }
        Err(e) => return Err(e.into()),
    };
    let weights = &pilot.weights;
    let bodies: Vec<serde_json::Value> = weights
        .iter()
        .map(|w| body_json(w, args.threshold))
        .collect::<Result<_, _>>()?;
    let choice = pilot.confirm(args.threshold, None)?;
    // Terms are dropped with shape integrals only (the B-matrix route sums a mass cloud
    // with no named terms); the choice is confirmed in relative coordinates, and the
    // absolute formulation carries the same physics per truncation.
    let applies = scene.solver.inertia == InertiaMethod::ShapeIntegrals;
    let report = json!({"scene": scene.name, "threshold": args.threshold,
                        "applies_as_given": applies, "bodies": bodies,
                        "confirmed": choice_json(&choice)});
    print_json_or_table(&report, args.json, |_| {
        let mut s = format!(
            "inertia-term weights of {} (pilot: full model, relative, shape integrals)\n",
            scene.name
        );
        if !applies {
            s += "note: the scene runs the B-matrix inertia route, which keeps every term; the \
                  chosen terms apply with --inertia shape-integrals\n";
        }
        for w in weights {
            s += &body_text(w, args.threshold).unwrap_or_default();
        }
        s += &choice_text(&choice);
        s
    })
}
