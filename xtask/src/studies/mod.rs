//! The studies of the report, in the order they appear.

use crate::Settings;
use crate::report::Report;

pub mod flexible_iltis;
pub mod four_bar;
pub mod iltis;
pub mod inertia_cost;
pub mod mesh_size;
pub mod reference_conditions;
pub mod reference_operations;
pub mod solid_mesh;
pub mod spin_up;
pub mod spin_up_solid;
pub mod stability_map;
pub mod term_weights;
pub mod work_precision;

/// What a study returns when it cannot finish.
pub type StudyResult = Result<(), Box<dyn std::error::Error>>;

/// The run of `what` finished: its status is `ok`, else the failure with its time and message.
fn check_run(
    summary: &flexmbd::simulation::Summary,
    what: &str,
) -> Result<(), Box<dyn std::error::Error>> {
    if summary.status != "ok" {
        return Err(format!(
            "{what}: the run failed at t = {:?} s: {}",
            summary.failed_at,
            summary.message.as_deref().unwrap_or("?")
        )
        .into());
    }
    Ok(())
}

/// The scene of `models/FILE` with the `--set` overrides `sets` applied (not validated: the
/// caller sets what it studies first).
fn model_with_sets(
    file: &str,
    sets: &[String],
) -> Result<flexmbd::model::Scene, Box<dyn std::error::Error>> {
    let mut scene = flexmbd::model::Scene::load(crate::workspace_root().join("models").join(file))?;
    let sets = sets
        .iter()
        .map(|s| flexmbd::model::parse_set(s))
        .collect::<Result<Vec<_>, _>>()?;
    scene.apply_sets(&sets)?;
    Ok(scene)
}

/// One study of the report.
pub struct Study {
    /// Name for `--only`.
    pub name: &'static str,
    /// Section title.
    pub title: &'static str,
    /// Runs the study and appends its section.
    pub run: fn(&Settings, &mut Report) -> StudyResult,
}

/// Every study, in report order.
pub fn all() -> Vec<Study> {
    vec![
        Study {
            name: "inertia-cost",
            title: "Cost of the inertia terms against mesh size (thesis ch. 3)",
            run: inertia_cost::run,
        },
        Study {
            name: "double-four-bar",
            title: "Double four-bar with 0 to 5 flexible bars (thesis ch. 2, first example)",
            run: four_bar::run,
        },
        Study {
            name: "iltis",
            title: "The IAVSD Iltis benchmark vehicle: equilibrium, vibration and the cosine bump (thesis ch. 2)",
            run: iltis::run,
        },
        Study {
            name: "flexible-iltis",
            title: "The flexible Iltis: suspension and vehicle with 0 to 12 flexible bodies (thesis ch. 2 and 3)",
            run: flexible_iltis::run,
        },
        Study {
            name: "mesh-size",
            title: "CPU time against FE mesh size, both formulations (thesis ch. 3)",
            run: mesh_size::run,
        },
        Study {
            name: "solid-mesh",
            title: "CPU time against the mesh size of an imported solid part, both formulations (thesis ch. 3, issue 25)",
            run: solid_mesh::run,
        },
        Study {
            name: "spin-up",
            title: "Spin-up beam: geometric stiffening against a large-deformation reference (thesis ch. 4)",
            run: spin_up::run,
        },
        Study {
            name: "spin-up-solid",
            title: "Spin-up beam as a solid: FNL1 from the stress of each mode (issue 29)",
            run: spin_up_solid::run,
        },
        Study {
            name: "stability-map",
            title: "Where the stiffening methods fail: stability map over Ωs and h (thesis ch. 4)",
            run: stability_map::run,
        },
        Study {
            name: "work-precision",
            title: "Work–precision: error against CPU time, and the cheapest model for a tolerance",
            run: work_precision::run,
        },
        Study {
            name: "term-weights",
            title: "Inertia terms by weight: which terms matter, and what dropping them saves (thesis ch. 5, issue 31)",
            run: term_weights::run,
        },
        Study {
            name: "reference-conditions",
            title: "Reference conditions: interface-fixed against Buckens (thesis ch. 5, issue 31)",
            run: reference_conditions::run,
        },
    ]
}
