//! `flexmbd terms SCENE.ron [--threshold X] [--duration T] [--json]`: the weight of each
//! flexible body's inertia terms over a pilot run of the full model, and the cheapest
//! terms whose dropped groups weigh at most the threshold
//! ([`flexmbd::term_weights`], docs/design.md "Inertia terms by weight").

use std::fmt::Write as _;

use clap::Args;
use flexmbd::body::InertiaMethod;
use flexmbd::body::weights::kernel_work;
use flexmbd::model::FormulationKind;
use flexmbd::term_weights::{BodyWeights, weigh_terms};
use serde_json::json;

use crate::{CliResult, SceneInput, exit, print_json_or_table};

/// The arguments of `flexmbd terms`.
#[derive(Args)]
pub(crate) struct TermsArgs {
    #[command(flatten)]
    input: SceneInput,
    /// The largest weight, relative to the full inertia force, of the terms that may be
    /// dropped (in (0, 1)).
    #[arg(long, default_value_t = 1e-3, allow_negative_numbers = true)]
    threshold: f64,
    /// The pilot run's duration (s; default and at most the scene's).
    #[arg(long, allow_negative_numbers = true)]
    duration: Option<f64>,
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
    let _ = writeln!(s, "  chosen at {threshold:.0e}: {chosen}");
    Ok(s)
}

/// `flexmbd terms`.
pub(crate) fn terms(args: &TermsArgs) -> CliResult {
    flexmbd::body::weights::check_threshold(args.threshold).map_err(|e| format!("--{e}"))?;
    let scene = args.input.load()?;
    scene.validate()?;
    let weights = match weigh_terms(&scene, args.duration) {
        Ok(w) => w,
        Err(e @ (flexmbd::Error::Integrator(_) | flexmbd::Error::Static(_))) => {
            eprintln!(
                "error: {}: the pilot run failed: {e}",
                args.input.scene.display()
            );
            return Ok(exit::RUN_FAILED);
        }
        Err(e) => return Err(e.into()),
    };
    let bodies: Vec<serde_json::Value> = weights
        .iter()
        .map(|w| body_json(w, args.threshold))
        .collect::<Result<_, _>>()?;
    // Terms are dropped in relative coordinates with shape integrals only (the B-matrix
    // route sums a mass cloud with no named terms; the absolute set keeps them all).
    let applies = scene.solver.formulation == FormulationKind::Relative
        && scene.solver.inertia == InertiaMethod::ShapeIntegrals;
    let report = json!({"scene": scene.name, "threshold": args.threshold,
                        "applies_as_given": applies, "bodies": bodies});
    print_json_or_table(&report, args.json, |_| {
        let mut s = format!(
            "inertia-term weights of {} (pilot: full model, relative, shape integrals)\n",
            scene.name
        );
        if !applies {
            s += "note: the scene runs another formulation or inertia route; the chosen terms \
                  apply with --formulation relative --inertia shape-integrals\n";
        }
        for w in &weights {
            s += &body_text(w, args.threshold).unwrap_or_default();
        }
        s
    })
}
