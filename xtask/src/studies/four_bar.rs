//! Thesis ch. 2, first example: the 2D double four-bar (docs/scenes.md §1) with 0 to 5
//! flexible bars, both inertia routes, both formulations, 5 s at h = 1 ms. Beside
//! the thesis's tables of coordinate counts and CPU times (docs/scenes.md §7.1): our counts,
//! the median CPU time of the 5 s run, the real-time factor, Newton iterations per step,
//! the split of time by phase, the agreement of the two inertia routes, and the rigid
//! check against the converged 10 s reference of docs/scenes.md §1.

use std::path::PathBuf;

use flexmbd::body::InertiaMethod;
use flexmbd::model::{Axis, FormulationKind, Scene, Sensor, SensorKind};
use flexmbd::simulation::{self, History, Summary};

use super::StudyResult;
use crate::Settings;
use crate::chart::{LineChart, Series};
use crate::report::Report;

mod sections;

/// The bars made flexible, in this order (docs/scenes.md §1 "Outputs": CHOSEN bars 1, 2, …, k).
pub const BARS: [&str; 5] = ["crank1", "coupler1", "crank2", "coupler2", "crank3"];
/// Thesis, absolute formulation: coordinates for k = 0..5 (docs/scenes.md §7.1).
const THESIS_ABS_COORDS: [usize; 6] = [6, 13, 20, 27, 34, 41];
/// Thesis, relative formulation: coordinates for k = 0..5 (docs/scenes.md §7.1).
const THESIS_REL_COORDS: [usize; 6] = [5, 8, 11, 14, 17, 20];
/// Thesis, absolute formulation: CPU time (s) of the 5 s run, 2008 hardware (docs/scenes.md §7.1).
const THESIS_ABS_CPU: [f64; 6] = [0.91, 3.30, 6.24, 9.61, 11.51, 15.22];
/// Thesis, relative formulation: CPU time (s) of the 5 s run (docs/scenes.md §7.1).
const THESIS_REL_CPU: [f64; 6] = [4.85, 9.11, 12.62, 15.74, 17.74, 20.92];
/// Converged rigid B0 position and velocity at t = 10 s (docs/scenes.md §1 "Reference values
/// for the rigid case", from S3).
const REF_B0_10S: (f64, f64) = (0.32846, 0.94452);
const REF_B0_VEL_10S: (f64, f64) = (1.42305, -0.49487);
/// Initial kinetic energy (J), docs/scenes.md §1 "Loads and initial conditions" (DERIVED).
const KINETIC_0: f64 = 1.5;
/// Time window (s) of the chart of the flexible deviation of B0.
const DEV_WINDOW: (f64, f64) = (0.5, 1.5);

const FORMS: [(FormulationKind, &str); 2] = [
    (FormulationKind::Absolute, "absolute"),
    (FormulationKind::Relative, "relative"),
];

const METHODS: [(InertiaMethod, &str); 2] = [
    (InertiaMethod::BMatrix, "b-matrix"),
    (InertiaMethod::ShapeIntegrals, "shape-integrals"),
];

type Error = Box<dyn std::error::Error>;

fn scene_path() -> PathBuf {
    crate::workspace_root().join("models/double_four_bar.ron")
}

/// The double four-bar with the first `k` bars of [`BARS`] flexible, the given formulation
/// and inertia route, `duration` seconds, and a history row at every step.
pub fn scene(
    k: usize,
    form: FormulationKind,
    method: InertiaMethod,
    duration: f64,
) -> Result<Scene, Error> {
    let mut scene = Scene::load(scene_path())?;
    let sets: Vec<(String, String)> = BARS[..k]
        .iter()
        .map(|b| (format!("bodies.{b}.flexible"), "true".to_string()))
        .collect();
    scene.apply_sets(&sets)?;
    scene.solver.formulation = form;
    scene.solver.inertia = method;
    scene.solver.duration = duration;
    scene.solver.output_interval = None;
    Ok(scene)
}

/// One configuration, run several times.
struct Case {
    k: usize,
    form: &'static str,
    method: &'static str,
    /// CPU seconds of every repetition, sorted.
    cpu: Vec<f64>,
    /// The summary of the median repetition.
    median: Summary,
    /// The history of the first repetition (the runs are deterministic).
    history: History,
    /// `failed at t = … s` when the run failed (then it is not repeated).
    failed: Option<String>,
}

impl Case {
    fn cpu_median(&self) -> f64 {
        if self.failed.is_some() {
            return f64::NAN;
        }
        self.cpu[self.cpu.len() / 2]
    }
    fn b0_end(&self) -> (f64, f64) {
        let last = |name: &str| {
            self.history
                .column(name)
                .and_then(|c| c.last().copied())
                .unwrap_or(f64::NAN)
        };
        (last("B0_x"), last("B0_y"))
    }
    fn energy_drift(&self) -> f64 {
        energy_drift(&self.history)
    }
    fn newton_per_step(&self) -> f64 {
        self.median.newton_iterations as f64 / self.median.steps.max(1) as f64
    }
}

/// Largest |E(t) − E(0)| relative to the initial kinetic energy.
fn energy_drift(h: &History) -> f64 {
    let e = h.column("energy").unwrap_or_default();
    let e0 = e.first().copied().unwrap_or(f64::NAN);
    e.iter().map(|v| (v - e0).abs()).fold(0.0, f64::max) / KINETIC_0
}

/// Largest distance between the two runs' B0 at the same instants.
fn largest_b0_difference(a: &History, b: &History) -> f64 {
    let col = |h: &History, n: &str| h.column(n).unwrap_or_default();
    let (ax, ay, bx, by) = (
        col(a, "B0_x"),
        col(a, "B0_y"),
        col(b, "B0_x"),
        col(b, "B0_y"),
    );
    // Every step is recorded, so row i is the same instant in both (up to a failure).
    let n = ax.len().min(bx.len());
    if n == 0 {
        return f64::NAN;
    }
    (0..n)
        .map(|i| (ax[i] - bx[i]).hypot(ay[i] - by[i]))
        .fold(0.0, f64::max)
}

/// Run every configuration `reps` times, round by round (one run of each configuration
/// per round), so a burst of load on the shared machine spoils at most one repetition of
/// each and the median discards it.
fn measure_all(reps: usize) -> Result<Vec<Case>, Error> {
    let mut configs = Vec::new();
    for &(fk, form) in &FORMS {
        for k in 0..=5 {
            for &(method, name) in &METHODS {
                configs.push((k, form, name, scene(k, fk, method, 5.0)?));
            }
        }
    }
    let mut runs: Vec<Vec<Summary>> = vec![Vec::with_capacity(reps); configs.len()];
    let mut histories: Vec<Option<History>> = vec![None; configs.len()];
    let mut failed: Vec<Option<(Summary, History)>> = vec![None; configs.len()];
    for round in 1..=reps {
        eprintln!("   round {round}/{reps}");
        for (i, (k, form, name, sc)) in configs.iter().enumerate() {
            if failed[i].is_some() {
                continue;
            }
            let (summary, h) = simulation::run(sc, |_| {})?;
            if let Err(e) = super::check_run(&summary, &format!("{form}, k = {k}, {name}")) {
                eprintln!("   {e}");
                failed[i] = Some((summary, h));
                continue;
            }
            if histories[i].is_none() {
                histories[i] = Some(h);
            }
            runs[i].push(summary);
        }
    }
    let mut cases = Vec::with_capacity(configs.len());
    for (i, (k, form, name, _)) in configs.into_iter().enumerate() {
        if let Some((summary, history)) = failed[i].take() {
            cases.push(Case {
                k,
                form,
                method: name,
                cpu: vec![summary.cpu_seconds],
                failed: Some(format!(
                    "failed at t = {:.3} s",
                    summary.failed_at.unwrap_or(f64::NAN)
                )),
                median: summary,
                history,
            });
            continue;
        }
        let mut r = std::mem::take(&mut runs[i]);
        r.sort_by(|a, b| a.cpu_seconds.total_cmp(&b.cpu_seconds));
        let cpu: Vec<f64> = r.iter().map(|s| s.cpu_seconds).collect();
        let median = r.swap_remove(r.len() / 2);
        eprintln!(
            "   {form:8} k = {k} {name:15} n = {:2}, m = {:2}: {:.3} s (median of {reps}), {:.2} Newton it./step",
            median.n_coordinates,
            median.n_constraints,
            cpu[cpu.len() / 2],
            median.newton_iterations as f64 / median.steps.max(1) as f64
        );
        cases.push(Case {
            k,
            form,
            method: name,
            cpu,
            median,
            history: histories[i].take().expect("at least one repetition"),
            failed: None,
        });
    }
    Ok(cases)
}

fn pct(part: f64, whole: f64) -> String {
    format!("{:.0} %", 100.0 * part / whole)
}

/// `12×`, or a dash when a run failed.
fn times(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.0}×")
    } else {
        dash()
    }
}

fn dash() -> String {
    "—".into()
}

/// Rigid check of one formulation: k = 0 extended to 10 s, B0 velocity recorded too.
struct Rigid {
    b0: (f64, f64),
    v0: (f64, f64),
    pos_err: f64,
    vel_err: f64,
    /// Position error along the path (the reference velocity's direction); < 0: lags.
    along: f64,
    drift: f64,
}

fn rigid_check(form: FormulationKind) -> Result<Rigid, Error> {
    let mut rigid = scene(0, form, InertiaMethod::ShapeIntegrals, 10.0)?;
    for (name, component) in [("B0_vx", Axis::X), ("B0_vy", Axis::Y)] {
        rigid.sensors.push(Sensor {
            name: name.into(),
            kind: SensorKind::Velocity {
                body: "crank1".into(),
                marker: "B".into(),
                component,
                frame: None,
            },
            displacement: false,
        });
    }
    let (summary, history) = simulation::run(&rigid, |_| {})?;
    super::check_run(&summary, "rigid 10 s run")?;
    let last = |n: &str| {
        history
            .column(n)
            .and_then(|c| c.last().copied())
            .unwrap_or(f64::NAN)
    };
    let (bx, by, vx, vy) = (last("B0_x"), last("B0_y"), last("B0_vx"), last("B0_vy"));
    let (ex, ey) = (bx - REF_B0_10S.0, by - REF_B0_10S.1);
    Ok(Rigid {
        b0: (bx, by),
        v0: (vx, vy),
        pos_err: ex.hypot(ey),
        vel_err: (vx - REF_B0_VEL_10S.0).hypot(vy - REF_B0_VEL_10S.1),
        along: (ex * REF_B0_VEL_10S.0 + ey * REF_B0_VEL_10S.1)
            / REF_B0_VEL_10S.0.hypot(REF_B0_VEL_10S.1),
        drift: energy_drift(&history),
    })
}

fn thesis_cpu(form: &str) -> &'static [f64; 6] {
    if form == "absolute" {
        &THESIS_ABS_CPU
    } else {
        &THESIS_REL_CPU
    }
}

/// Stills of the double four-bar with its five bars flexible, at 0.6 s and 1.2 s, the
/// deformation drawn 100 times (the page of `flexmbd animate`, [`crate::stills`]).
fn stills(report: &mut Report) -> StudyResult {
    let mut scene = Scene::load(scene_path())?;
    let sets: Vec<(String, String)> = BARS
        .iter()
        .map(|b| (format!("bodies.{b}.flexible"), "true".to_string()))
        .collect();
    scene.apply_sets(&sets)?;
    crate::stills::add(
        report,
        &scene,
        "double_four_bar_5_flexible",
        &[0.6, 1.2],
        100.0,
        "The double four-bar with its five bars flexible, as `flexmbd animate` draws it.",
    );
    Ok(())
}

/// The run of `k` flexible bars in formulation `form` with inertia route `name`.
fn find<'c>(cases: &'c [Case], k: usize, form: &str, name: &str) -> &'c Case {
    cases
        .iter()
        .find(|c| c.k == k && c.form == form && c.method == name)
        .expect("every case was run")
}

/// Run the study and append its section to the report.
pub fn run(settings: &Settings, report: &mut Report) -> StudyResult {
    let reps = if settings.quick { 3 } else { 7 };
    let cases = measure_all(reps)?;
    let mut rigid = Vec::new();
    for &(fk, form) in &FORMS {
        let r = rigid_check(fk)?;
        eprintln!(
            "   {form:8} rigid 10 s: B0 = ({:.5}, {:.5}) m, |error| = {:.1e} m, energy drift {:.1e}",
            r.b0.0, r.b0.1, r.pos_err, r.drift
        );
        rigid.push((form, r));
    }

    // ---- text and tables ----
    report.text(
        "The 2D double four-bar of the thesis's chapter 2 (IFToMM A02 with N = 2: three cranks and two \
         couplers of 1 kg and 1 m, seven revolute joints, gravity, 1 m/s initial velocity; \
         scenes.md §1, `models/double_four_bar.ron`), with k = 0 … 5 flexible bars made flexible in the \
         order crank1, coupler1, crank2, coupler2, crank3 (scenes.md §1 \"Outputs\": CHOSEN bars 1, 2, …, k; \
         the thesis's order is unknown). Each flexible bar is a steel beam of 10 Euler–Bernoulli elements \
         reduced to 2 static + 2 fixed-interface normal modes. Absolute (natural-coordinate) and relative \
         (semi-recursive) formulations, ALI3-P on the trapezoidal rule, h = 1 ms, 5 s (scenes.md §1 \
         \"Run\", §6). The thesis's numbers are those of scenes.md §7.1 (Lugrís 2008, ch. 2).",
    );
    sections::coordinates(report, &cases);
    sections::cpu_times(report, &cases, reps);
    sections::time_split(report, &cases);
    sections::inertia_routes(report, &cases);
    sections::rigid_checks(report, &rigid);
    sections::cpu_chart(report, &cases)?;
    sections::b0_charts(report, &cases)?;
    stills(report)?;

    let failures: Vec<String> = cases
        .iter()
        .filter_map(|c| {
            c.failed.as_ref()?;
            Some(format!(
                "{}, k = {}, {}: {}",
                c.form,
                c.k,
                c.method,
                c.median.message.as_deref().unwrap_or("?")
            ))
        })
        .collect();
    if failures.is_empty() {
        Ok(())
    } else {
        Err(format!("{} run(s) failed: {}", failures.len(), failures.join("; ")).into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 6 + 6k absolute and 5 + 4k relative coordinates; a short run of each inertia route
    /// agrees with the other.
    #[test]
    fn counts_and_short_run_agree() {
        for k in 0..=5 {
            for (form, n) in [
                (FormulationKind::Absolute, 6 + 6 * k),
                (FormulationKind::Relative, 5 + 4 * k),
            ] {
                let sc = scene(k, form, InertiaMethod::ShapeIntegrals, 0.05).unwrap();
                let f = simulation::compile(&sc).unwrap();
                assert_eq!(f.n_coordinates(), n, "{form:?}, k = {k}");
            }
        }
        let run = |m| {
            let sc = scene(5, FormulationKind::Absolute, m, 0.05).unwrap();
            let (s, h) = simulation::run(&sc, |_| {}).unwrap();
            assert_eq!(s.status, "ok");
            h
        };
        let (a, b) = (
            run(InertiaMethod::BMatrix),
            run(InertiaMethod::ShapeIntegrals),
        );
        assert_eq!(a.rows.len(), 51);
        assert!(largest_b0_difference(&a, &b) < 1e-9);
    }
}
