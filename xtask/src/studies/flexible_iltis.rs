//! The flexible Iltis (thesis ch. 2, examples 2 and 3; docs/scenes.md §2.7, §3.6, §4, §7.2):
//! scene B's drop (`models/iltis_suspension.ron`) with 0 … 3 flexible bodies and scene C's run
//! over the ramp and steps (`models/iltis_vehicle.ron`) with 0, 4, 8, 12, both formulations ×
//! both inertia routes: the histories as the thesis's figures (chassis and front-left wheel
//! centre, the A-arm's deflection, whether the leaf bump stop closes), the CPU time and
//! real-time factor against the number of flexible bodies with the split by phase, the slope of
//! the cost per step against the coordinate count ([`scaling`]), and the mesh-size study on the
//! 12-flexible-body vehicle ([`sections::mesh_study`]). Every CPU figure is the median of 3 runs
//! (one run in `--quick`, and the text says which).

use flexmbd::body::InertiaMethod;
use flexmbd::model::{FormulationKind, Scene, parse_set};
use flexmbd::simulation::{self, History, Summary};
use flexmbd_test_support::iltis::{suspension_flexible, vehicle_flexible};

use super::StudyResult;
use crate::Settings;
use crate::report::Report;

mod scaling;
mod sections;

const FORMS: [(FormulationKind, &str); 2] = [
    (FormulationKind::Absolute, "absolute"),
    (FormulationKind::Relative, "relative"),
];

const METHODS: [(InertiaMethod, &str); 2] = [
    (InertiaMethod::BMatrix, "b-matrix"),
    (InertiaMethod::ShapeIntegrals, "shape-integrals"),
];

/// The leaf element's force when its bump stop closes (70 mm of jounce: k (0.006 − 0.152),
/// docs/scenes.md §2.4); beyond it (more negative) the stop's stiff branch carries the load.
const LEAF_AT_STOP: f64 = -5242.3;

type Failure = Box<dyn std::error::Error>;

/// Which scene a case runs.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Which {
    /// Scene B, the suspension's drop (5 s).
    Suspension,
    /// Scene C, the vehicle over the ramp and steps (8 s, or shortened in `--quick`).
    Vehicle,
}

impl Which {
    fn label(self) -> &'static str {
        match self {
            Which::Suspension => "B",
            Which::Vehicle => "C",
        }
    }
}

/// Scene B or C with its first `k` beam bodies flexible (docs/scenes.md §2.8, §3.4), the given
/// formulation and inertia route; `duration` replaces the file's when given.
fn scene(
    which: Which,
    k: usize,
    form: FormulationKind,
    method: InertiaMethod,
    duration: Option<f64>,
) -> Result<Scene, Failure> {
    let (file, sets) = match which {
        Which::Suspension => ("iltis_suspension.ron", suspension_flexible(k)),
        Which::Vehicle => ("iltis_vehicle.ron", vehicle_flexible(k)),
    };
    let mut scene = Scene::load(crate::workspace_root().join("models").join(file))?;
    let sets = sets
        .iter()
        .map(|s| parse_set(s))
        .collect::<Result<Vec<_>, _>>()?;
    scene.apply_sets(&sets)?;
    scene.solver.formulation = form;
    scene.solver.inertia = method;
    if let Some(d) = duration {
        scene.solver.duration = d;
    }
    Ok(scene)
}

/// One configuration, run `reps` times.
struct Case {
    which: Which,
    k: usize,
    form: &'static str,
    method: &'static str,
    /// CPU seconds of every repetition, sorted.
    cpu: Vec<f64>,
    /// The summary of the median repetition.
    median: Summary,
    /// The history of the first repetition (the runs are deterministic).
    history: History,
}

impl Case {
    fn cpu_median(&self) -> f64 {
        self.cpu[self.cpu.len() / 2]
    }
    /// Median CPU seconds per simulated second.
    fn cpu_per_second(&self) -> f64 {
        self.cpu_median() / self.median.simulated_seconds
    }
}

/// A configuration to measure: scene, flexible bodies, formulation, inertia route, the scene.
type Config = (Which, usize, &'static str, &'static str, Scene);

/// Run every configuration `reps` times, round by round (one run of each per round), so that a
/// burst of load on the shared machine spoils at most one repetition of each.
fn measure_all(configs: Vec<Config>, reps: usize) -> Result<Vec<Case>, Failure> {
    let mut runs: Vec<Vec<Summary>> = vec![Vec::with_capacity(reps); configs.len()];
    let mut histories: Vec<Option<History>> = vec![None; configs.len()];
    for round in 1..=reps {
        eprintln!("   round {round}/{reps}");
        for (i, (which, k, form, method, sc)) in configs.iter().enumerate() {
            let (summary, h) = simulation::run(sc, |_| {})?;
            let what = format!("scene {}, k = {k}, {form}, {method}", which.label());
            super::check_run(&summary, &what)?;
            eprintln!(
                "   {what}: n = {}, {:.3} s",
                summary.n_coordinates, summary.cpu_seconds
            );
            if histories[i].is_none() {
                histories[i] = Some(h);
            }
            runs[i].push(summary);
        }
    }
    let mut cases = Vec::with_capacity(configs.len());
    for (i, (which, k, form, method, _)) in configs.into_iter().enumerate() {
        let mut r = std::mem::take(&mut runs[i]);
        r.sort_by(|a, b| a.cpu_seconds.total_cmp(&b.cpu_seconds));
        let cpu: Vec<f64> = r.iter().map(|s| s.cpu_seconds).collect();
        let median = r.swap_remove(r.len() / 2);
        cases.push(Case {
            which,
            k,
            form,
            method,
            cpu,
            median,
            history: histories[i].take().ok_or("no repetition")?,
        });
    }
    Ok(cases)
}

/// Run every labelled scene `reps` times, round by round as [`measure_all`], and return the
/// summary of each one's median repetition (by CPU time), in the order given.
fn median_runs(runs: &[(String, Scene)], reps: usize) -> Result<Vec<Summary>, Failure> {
    let mut all: Vec<Vec<Summary>> = vec![Vec::with_capacity(reps); runs.len()];
    for round in 1..=reps {
        for ((what, sc), summaries) in runs.iter().zip(&mut all) {
            let (summary, _) = simulation::run(sc, |_| {})?;
            super::check_run(&summary, what)?;
            eprintln!(
                "   {what} (round {round}/{reps}): {:.3} s",
                summary.cpu_seconds
            );
            summaries.push(summary);
        }
    }
    all.into_iter()
        .map(|mut r| {
            r.sort_by(|a, b| a.cpu_seconds.total_cmp(&b.cpu_seconds));
            let middle = r.len() / 2;
            (middle < r.len())
                .then(|| r.swap_remove(middle))
                .ok_or_else(|| "no repetition".into())
        })
        .collect()
}

/// The flexible-body counts of each scene, and scene C's duration (None: the file's 8 s).
fn plan(quick: bool) -> (Vec<usize>, Vec<usize>, Option<f64>) {
    if quick {
        (vec![0, 1, 2, 3], vec![0, 4, 12], Some(2.0))
    } else {
        (vec![0, 1, 2, 3], vec![0, 4, 8, 12], None)
    }
}

fn configs(quick: bool) -> Result<Vec<Config>, Failure> {
    let (ks_b, ks_c, c_duration) = plan(quick);
    let mut out = Vec::new();
    for (which, ks, duration) in [
        (Which::Suspension, ks_b, None),
        (Which::Vehicle, ks_c, c_duration),
    ] {
        for &k in &ks {
            for &(fk, form) in &FORMS {
                for &(method, name) in &METHODS {
                    out.push((which, k, form, name, scene(which, k, fk, method, duration)?));
                }
            }
        }
    }
    Ok(out)
}

/// The case of `which`, `k`, `form`, `method` (every one is measured).
fn find<'c>(cases: &'c [Case], which: Which, k: usize, form: &str, method: &str) -> &'c Case {
    cases
        .iter()
        .find(|c| c.which == which && c.k == k && c.form == form && c.method == method)
        .expect("every configuration is measured")
}

/// Run the study and append its section to the report.
pub fn run(settings: &Settings, report: &mut Report) -> StudyResult {
    let reps = if settings.quick { 1 } else { 3 };
    let (_, _, c_duration) = plan(settings.quick);
    report.text(
        "The thesis configurations of the Iltis (docs/scenes.md §2.7 \"Scene B as built\", §3.6 \
         \"Scene C as built\"): scene B, one front corner with a quarter chassis on a vertical \
         slider dropping 20 cm at 0.5 s (`models/iltis_suspension.ron`, 5 s), and scene C, the \
         vehicle at 5 m/s over the ramp and steps (`models/iltis_vehicle.ron`, 8 s), with the \
         A-arm, leaf-spring link and tie rod of each corner switched flexible in the order of §2.8 \
         (`--set bodies.NAME.flexible=true`; rigid, they keep their FE mass properties), both \
         from the static equilibrium, h = 1 ms, one core.",
    );
    if let Some(d) = c_duration {
        report.text(&format!(
            "*Quick run:* scene C is shortened to its first {d} s of 8 (the ramp up, not the steps \
             down) and run with 0, 4 and 12 flexible bodies; CPU is given per simulated second; \
             one run per configuration instead of the median of 3; the mesh-size study runs 0.5 s \
             of the 8 with n = 1, 5, 20."
        ));
    }
    let cases = measure_all(configs(settings.quick)?, reps)?;
    sections::suspension_histories(report, &cases)?;
    sections::vehicle_histories(report, &cases)?;
    sections::cpu_table(report, &cases, reps);
    sections::cpu_chart(report, &cases)?;
    scaling::cost_slope(report, &cases, reps);
    sections::crossover(report, &cases);
    sections::mesh_study(settings, report, reps)?;
    stills(report)
}

/// Stills of scene C with its 12 beam bodies flexible on the ramp: the front wheels
/// climbing it (0.7 s) and the rear wheels (1.1 s), true size (the page of `flexmbd
/// animate`, [`crate::stills`]).
fn stills(report: &mut Report) -> StudyResult {
    let mut scene = Scene::load(crate::workspace_root().join("models/iltis_vehicle.ron"))?;
    let sets = vehicle_flexible(12)
        .iter()
        .map(|s| parse_set(s))
        .collect::<Result<Vec<_>, _>>()?;
    scene.apply_sets(&sets)?;
    crate::stills::add(
        report,
        &scene,
        "iltis_vehicle_12_flexible",
        &[0.7, 1.1],
        1.0,
        "Scene C, the vehicle with its 12 beam bodies flexible, on the ramp.",
    );
    Ok(())
}
