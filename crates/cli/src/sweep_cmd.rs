//! `flexmbd sweep` and `flexmbd tune`: a work–precision sweep of a scene over a grid of
//! model and solver choices ([`flexmbd::sweep`]), printed as a table of runs with the
//! Pareto front marked, or the cheapest run that meets a tolerance with the `flexmbd
//! simulate` arguments that reproduce it.

use std::io::Write as _;
use std::path::PathBuf;

use clap::Args;
use flexmbd::body::{InertiaMethod, InertiaTerms};
use flexmbd::model::{FormulationKind, Scene};
use flexmbd::sweep::{
    Axis, Grid, Reference, ReferenceKind, RunRecord, RunStatus, Sweep, SweepError, SweepReport,
    Timing, Tuning, parse_basis,
};
use serde::Serialize;

use crate::{CliResult, exit, load_scene, parse_stiffening, stop_on_signals};

/// The default grid as `--help` describes it.
pub const DEFAULT_GRID_HELP: &str = "\
Default grid (without --grid): both formulations; for a scene with flexible beams also both
inertia routes, the stiffening methods linear, fnl1, fnl2 and foreshortening (the scene's own
first) and 1 to max(4, the scene's) normal modes per flexible beam; the steps 2h, h, h/2
about the scene's step h. On the 2D spin-up beam: 2 x 2 x 4 x 4 x 3 = 192 runs of 20 s, about
a minute on two cores.

Grid axes (--grid NAME=V1,V2,...; repeat --grid for more axes):
  formulation=absolute,relative   inertia=b-matrix,shape-integrals
  stiffening=linear,fnl1,fnl2,foreshortening,substructuring:N
  modes=1,2,3   modes.BODY=1,2 (one beam body)   elements=10,20   elements.BODY=...
  basis=lowest,participation,ritz,pod   basis.BODY=... (the kind of the modes: the lowest
    normal modes, those the body's loads excite most, load-dependent Ritz vectors, or the
    proper orthogonal modes of a pilot run of the scene on its lowest max(2n, 4) modes,
    which is part of the run's preprocessing)
  terms=full,o2-nv,o1,o1-nc,o0,o0-nc   terms.BODY=... (the inertia terms kept, shape
    integrals, either formulation)   terms=auto@1e-2,auto@1e-3 (the terms that meet X on
    one pilot run of the scene with every term, `flexmbd terms`: the weights' choices run in
    place of the full model, the first whose judged sensors move by at most X of their range
    over the pilot; chosen once, set at every point, labelled with that pilot error)
  step=1e-3,5e-4

Errors: the largest |run - reference| over time (and the RMS) on each judged sensor, the
reference interpolated linearly to the run's output times; without --reference the reference
is the most faithful model flexmbd has for the scene (see --reference), and its own error
estimate (its difference from the same model less refined) is reported; where it falls back
to the grid's richest model (first formulation, inertia and stiffening listed, most modes and
elements) at a quarter of the smallest step, a warning says so and why.
CPU time: of the integration (preprocessing excluded); the runs go in parallel over the
cores, and the runs on the Pareto front (and the candidates tune compares) are timed again
alone, one after another, median of 3 (of 7 for runs under 0.2 s).
Tune's choice: among the ok runs whose error is at most the tolerance, the least CPU time
timed alone; a run that differs from another such run only by a smaller step or more modes or
elements counts as costlier without being timed; times within 25 % of the least tie, and then
fewer coordinates win, then the lower grid index.";

/// The text after the options in `flexmbd sweep --help` and `flexmbd tune --help`.
pub fn help() -> String {
    format!("{DEFAULT_GRID_HELP}\n\n{}", exit::HELP)
}

/// The arguments `flexmbd sweep` and `flexmbd tune` share.
#[derive(Args)]
pub struct SweepInput {
    /// A scene file (RON), e.g. models/spin_up_beam_2d.ron.
    scene: PathBuf,
    /// The sensors to judge, comma-separated.
    #[arg(long = "sensor", value_delimiter = ',', required = true)]
    sensors: Vec<String>,
    /// A reference CSV: `t`, then a column per judged sensor (e.g. written by
    /// `flexmbd simulate --output`). Default: the most faithful model flexmbd has for the
    /// scene (the large-deformation ANCF cable for a beam on a spun-up hub, the beams
    /// substructured in a mechanism, the scene at a far smaller step when it is rigid, else
    /// the grid's richest model at a quarter of its smallest step), kept in the reference
    /// cache.
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Compute the default reference even if the cache holds it, and do not keep it. The
    /// cache is $FLEXMBD_CACHE_DIR, else $XDG_CACHE_HOME/flexmbd, else ~/.cache/flexmbd.
    #[arg(long)]
    no_reference_cache: bool,
    /// A grid axis NAME=V1,V2,... (see below); repeat for more axes. Default: see below.
    #[arg(long = "grid", value_name = "NAME=VALUES")]
    grid: Vec<String>,
    /// Override any scalar of the scene in every run: PATH=VALUE (e.g. solver.duration=5).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    sets: Vec<String>,
    /// An error above which a finished run counts as unstable (default: 10 times the
    /// largest |reference value| of the judged sensors).
    #[arg(long)]
    error_cap: Option<f64>,
    /// Print one JSON object on stdout instead of a table.
    #[arg(long)]
    json: bool,
}

/// The arguments of `flexmbd tune`.
#[derive(Args)]
pub struct TuneArgs {
    #[command(flatten)]
    input: SweepInput,
    /// The largest error allowed on every named sensor (in the sensors' unit, e.g. m).
    #[arg(long, allow_hyphen_values = true)]
    tolerance: f64,
}

/// Parse a list of values of axis `name`.
fn values<T>(name: &str, list: &str, parse: impl Fn(&str) -> Option<T>) -> Result<Vec<T>, String> {
    list.split(',')
        .map(str::trim)
        .filter(|v| !v.is_empty())
        .map(|v| {
            parse(v).ok_or_else(|| format!("--grid {name}: `{v}` is not a value of this axis"))
        })
        .collect()
}

/// Parse one `--grid NAME=V1,V2,...`.
fn parse_axis(arg: &str) -> Result<Axis, String> {
    let (name, list) = arg
        .split_once('=')
        .ok_or_else(|| format!("--grid {arg}: expected NAME=V1,V2,..."))?;
    let (kind, body) = match name.split_once('.') {
        Some((k, b)) => (k, Some(b.to_string())),
        None => (name, None),
    };
    let count = |v: &str| v.parse::<usize>().ok();
    let axis = match (kind, &body) {
        ("formulation", None) => Axis::Formulation(values(name, list, |v| match v {
            "absolute" => Some(FormulationKind::Absolute),
            "relative" => Some(FormulationKind::Relative),
            _ => None,
        })?),
        ("inertia", None) => Axis::Inertia(values(name, list, |v| match v {
            "b-matrix" => Some(InertiaMethod::BMatrix),
            "shape-integrals" => Some(InertiaMethod::ShapeIntegrals),
            _ => None,
        })?),
        ("stiffening", None) => Axis::Stiffening(values(name, list, |v| parse_stiffening(v).ok())?),
        ("modes", _) => Axis::Modes {
            body,
            counts: values(name, list, count)?,
        },
        ("basis", _) => Axis::Basis {
            body,
            kinds: values(name, list, parse_basis)?,
        },
        ("elements", _) => Axis::Elements {
            body,
            counts: values(name, list, count)?,
        },
        ("terms", _) if list.contains("auto@") => Axis::AutoTerms {
            body,
            thresholds: values(name, list, |v| v.strip_prefix("auto@")?.parse().ok()).map_err(
                |e| format!("{e} (auto@X and fixed choices cannot share an axis; auto@1e-9 keeps every term)"),
            )?,
        },
        ("terms", _) => Axis::Terms {
            body,
            terms: values(name, list, InertiaTerms::parse)?,
        },
        ("step", None) => Axis::Step(values(name, list, |v| v.parse::<f64>().ok())?),
        _ => {
            return Err(format!(
                "--grid {arg}: unknown axis `{name}` (axes: formulation, inertia, stiffening, modes[.BODY], basis[.BODY], elements[.BODY], terms[.BODY], step)"
            ));
        }
    };
    Ok(axis)
}

impl SweepInput {
    /// The sweep the command line describes; without `--grid`, the default grid of the
    /// scene with the `--set` overrides applied.
    fn sweep(&self) -> Result<Sweep, Box<dyn std::error::Error>> {
        let mut names = Vec::new();
        let mut axes = Vec::new();
        for g in &self.grid {
            let axis = parse_axis(g)?;
            let name = g.split('=').next().unwrap_or_default().to_string();
            if names.contains(&name) {
                return Err(format!("--grid {name} is given twice").into());
            }
            names.push(name);
            axes.push(axis);
        }
        let grid = if self.grid.is_empty() {
            Grid::default_for(&self.base_scene()?)
        } else {
            Grid { axes }
        };
        Ok(Sweep {
            scene: self.scene.clone(),
            sets: self.sets.clone(),
            sensors: self.sensors.clone(),
            reference: match &self.reference {
                Some(p) => Reference::Csv(p.clone()),
                None => Reference::Faithful,
            },
            grid,
            error_cap: self.error_cap,
            reference_cache: (!self.no_reference_cache)
                .then(reference_cache_dir)
                .flatten(),
        })
    }

    /// The scene with the `--set` overrides applied.
    fn base_scene(&self) -> Result<Scene, Box<dyn std::error::Error>> {
        let mut scene = load_scene(&self.scene)?;
        let sets = self
            .sets
            .iter()
            .map(|s| flexmbd::model::parse_set(s))
            .collect::<Result<Vec<_>, _>>()?;
        scene.apply_sets(&sets)?;
        Ok(scene)
    }

    /// Check the sweep, tell stderr what runs, and run it until Ctrl-C or SIGTERM.
    fn run(&self, sweep: &Sweep) -> Result<SweepReport, SweepError> {
        if let Some(cap) = self.error_cap
            && !(cap.is_finite() && cap > 0.0)
        {
            return Err(SweepError::Grid {
                axis: "--error-cap".into(),
                message: format!("{cap}: must be a positive finite number"),
            });
        }
        eprintln!("sweeping {}…", self.scene.display());
        match stop_on_signals() {
            Ok(stop) => sweep.run_or_stop(&stop),
            // Without the handlers a signal ends the program, as before they existed.
            Err(_) => sweep.run(),
        }
    }
}

/// The exit code of a refused sweep: a failed reference run is a failed run, the rest
/// invalid input.
fn refused(e: &SweepError) -> u8 {
    eprintln!("error: {e}");
    match e {
        SweepError::ReferenceRun { .. } => exit::RUN_FAILED,
        SweepError::Interrupted { .. } => exit::INTERRUPTED,
        _ => exit::INVALID_INPUT,
    }
}

/// `flexmbd sweep`: every run of the grid, the Pareto front marked.
pub fn sweep(input: &SweepInput) -> CliResult {
    let sweep = input.sweep()?;
    let report = match input.run(&sweep) {
        Ok(r) => r,
        Err(e) => return Ok(refused(&e)),
    };
    print_report(input, &report)?;
    Ok(interrupted(&report).unwrap_or(exit::SUCCESS))
}

/// The sweep's report on stdout: one JSON object with `--json`, else the table.
fn print_report(input: &SweepInput, report: &SweepReport) -> std::io::Result<()> {
    let mut out = std::io::stdout().lock();
    if input.json {
        writeln!(out, "{}", serde_json::to_string(report)?)
    } else {
        write!(out, "{}", table(report))
    }
}

/// For a sweep the stop flag ended: say so on stderr and give its exit code.
fn interrupted(report: &SweepReport) -> Option<u8> {
    if !report.interrupted {
        return None;
    }
    let finished = report
        .runs
        .iter()
        .filter(|r| r.status != RunStatus::Interrupted)
        .count();
    eprintln!(
        "interrupted: {finished} of {} runs finished (the others are marked interrupted); the Pareto front is of the finished runs, timed in parallel",
        report.runs.len()
    );
    Some(exit::INTERRUPTED)
}

/// The folder of the reference cache: $FLEXMBD_CACHE_DIR, else $XDG_CACHE_HOME/flexmbd,
/// else $HOME/.cache/flexmbd (`None` without any of them).
fn reference_cache_dir() -> Option<PathBuf> {
    let var = |name: &str| {
        std::env::var_os(name)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    let base = var("FLEXMBD_CACHE_DIR")
        .or_else(|| var("XDG_CACHE_HOME").map(|d| d.join("flexmbd")))
        .or_else(|| var("HOME").map(|d| d.join(".cache").join("flexmbd")))?;
    Some(base.join("references"))
}

/// What `flexmbd tune --json` prints: the choice, then the sweep it was made from.
#[derive(Serialize)]
struct TuneOutput<'a> {
    scene: &'a str,
    sensors: &'a [String],
    #[serde(flatten)]
    tuning: &'a Tuning,
    reference: &'a str,
    reference_kind: flexmbd::sweep::ReferenceKind,
    #[serde(skip_serializing_if = "Option::is_none")]
    reference_fallback: &'a Option<String>,
    reference_seconds: f64,
    reference_cached: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    reference_margin: &'a Option<Vec<flexmbd::sweep::SensorError>>,
    timing: &'a str,
    pareto: &'a [usize],
    candidates: &'a [RunRecord],
}

/// `flexmbd tune`: the cheapest run of the sweep that meets the tolerance.
pub fn tune(args: &TuneArgs) -> CliResult {
    let tolerance = args.tolerance;
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Ok(refused(&SweepError::Tolerance(tolerance)));
    }
    let sweep = args.input.sweep()?;
    let mut report = match args.input.run(&sweep) {
        Ok(r) => r,
        Err(e) => return Ok(refused(&e)),
    };
    if report.interrupted {
        // No choice from part of the grid: the cheapest run that meets the tolerance may
        // be one that did not finish.
        print_report(&args.input, &report)?;
        eprintln!("tune: no choice is made from an interrupted sweep");
        return Ok(interrupted(&report).unwrap_or(exit::INTERRUPTED));
    }
    let tuning = match flexmbd::sweep::tune(&sweep, &mut report, tolerance) {
        Ok(t) => t,
        Err(e) => return Ok(refused(&e)),
    };
    let mut out = std::io::stdout().lock();
    if args.input.json {
        let output = TuneOutput {
            scene: &report.scene,
            sensors: &report.sensors,
            tuning: &tuning,
            reference: &report.reference,
            reference_kind: report.reference_kind,
            reference_fallback: &report.reference_fallback,
            reference_seconds: report.reference_seconds,
            reference_cached: report.reference_cached,
            reference_margin: &report.reference_margin,
            timing: &report.timing,
            pareto: &report.pareto,
            candidates: &report.runs,
        };
        writeln!(out, "{}", serde_json::to_string(&output)?)?;
    } else {
        write!(out, "{}", table(&report))?;
        write!(out, "{}", choice_text(&report, &tuning))?;
    }
    if tuning.recommended.is_none() {
        eprintln!(
            "error: {}: no candidate meets the tolerance {tolerance:e} on {} (the smallest error of an ok run is {:e}); widen the grid or the tolerance",
            args.input.scene.display(),
            report.sensors.join(", "),
            report
                .runs
                .iter()
                .filter(|r| r.status == RunStatus::Ok)
                .map(|r| r.error)
                .fold(f64::INFINITY, f64::min)
        );
        return Ok(exit::NO_CANDIDATE);
    }
    Ok(exit::SUCCESS)
}

/// One candidate for a reader: label, error, CPU time, coordinates, the arguments.
fn describe(title: &str, run: &RunRecord) -> String {
    let timed = match run.timed {
        Timing::Alone => "timed alone",
        Timing::InParallel => "timed in parallel",
    };
    format!(
        "{title}: {}\n  error {:.3e}, CPU {:.4} s ({timed}), real-time factor {:.1}, {} coordinates\n  flexmbd simulate {}\n",
        run.label,
        run.error,
        run.cpu_seconds,
        run.realtime_factor,
        run.n_coordinates.map_or("?".into(), |n| n.to_string()),
        run.args.join(" ")
    )
}

/// The recommendation and runner-up of `flexmbd tune`, as text.
fn choice_text(report: &SweepReport, tuning: &Tuning) -> String {
    let mut s = format!(
        "\n{}: the cheapest run with an error of at most {:e} on {}\n",
        report.scene,
        tuning.tolerance,
        report.sensors.join(", ")
    );
    if tuning.reference_error > 0.0 {
        s += &format!(
            "  (an error against the reference of at most {:e}: the tolerance less the reference's own error estimate {:e})\n",
            tuning.tolerance - tuning.reference_error,
            tuning.reference_error
        );
    }
    match &tuning.recommended {
        Some(r) => s += &describe("recommended", r),
        None => s += "recommended: none — no candidate meets the tolerance\n",
    }
    if let Some(r) = &tuning.runner_up {
        s += &describe("runner-up", r);
    }
    s += &format!("rule: {}\n", tuning.rule);
    for w in &tuning.warnings {
        s += &format!("warning: {w}\n");
    }
    s
}

/// Every run of the sweep as a table (`*`: on the Pareto front), with the reference and
/// how the times were measured.
fn table(report: &SweepReport) -> String {
    let mut s = format!(
        "{}: {} runs judged on {} against {}\n",
        report.scene,
        report.runs.len(),
        report.sensors.join(", "),
        report.reference
    );
    if let Some(why) = &report.reference_fallback {
        s += &format!("  no large-deformation reference for this scene: {why}\n");
    }
    s += &format!(
        "  reference {} in {:.2} s (apart from the runs)\n",
        if report.reference_cached {
            "read from the cache"
        } else {
            "made"
        },
        report.reference_seconds
    );
    if let Some(margin) = &report.reference_margin {
        let against = match report.reference_kind {
            ReferenceKind::LargeDeformation => "twice the elements or half the step",
            ReferenceKind::Substructured => "half the substructures or twice the step",
            ReferenceKind::SmallStep => "twice the step",
            _ => "half its step",
        };
        for m in margin {
            s += &format!(
                "  reference's error estimate (difference from {against}): {} max {:.3e}, rms {:.3e}\n",
                m.sensor, m.max_abs, m.rms
            );
        }
    }
    s += &format!(
        "  parallel phase: {:.2} s wall on {} threads for {:.2} s of runs\n",
        report.parallel_wall_seconds, report.threads, report.sum_run_seconds
    );
    s += &format!("  {}\n\n", report.timing);
    s += &format!(
        "{:>5} {:1} {:<48} {:<11} {:>6} {:>11} {:>11} {:>10} {:>8}  reason\n",
        "index", "", "run", "status", "coords", "max error", "rms", "CPU (s)", "timed"
    );
    for r in &report.runs {
        let rms = r.errors.iter().map(|e| e.rms).fold(0.0f64, f64::max);
        let status = match r.status {
            RunStatus::Ok => "ok",
            RunStatus::Failed => "failed",
            RunStatus::Unstable => "unstable",
            RunStatus::Interrupted => "interrupted",
        };
        let (error, rms) = if r.status == RunStatus::Ok {
            (format!("{:.3e}", r.error), format!("{rms:.3e}"))
        } else {
            ("–".into(), "–".into())
        };
        s += &format!(
            "{:>5} {:1} {:<48} {:<11} {:>6} {:>11} {:>11} {:>10.4} {:>8}  {}\n",
            r.index,
            if report.pareto.contains(&r.index) {
                "*"
            } else {
                ""
            },
            r.label,
            status,
            r.n_coordinates.map_or("–".into(), |n| n.to_string()),
            error,
            rms,
            r.cpu_seconds,
            match r.timed {
                Timing::Alone => "alone",
                Timing::InParallel => "parallel",
            },
            match (&r.reason, r.costlier_than) {
                (Some(reason), _) => reason.chars().take(100).collect::<String>(),
                (None, Some(i)) =>
                    format!("meets the tolerance; not timed alone: costlier than {i}"),
                (None, None) => String::new(),
            }
        );
    }
    s += "(* on the Pareto front of error against CPU time)\n";
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd::model::Stiffening;

    /// `Axis::arg` is what `--grid` reads back: the report prints `flexmbd tune` command
    /// lines from it, so an axis written and parsed again must be the same axis.
    #[test]
    fn every_axis_reads_back_from_its_argument() {
        let axes = [
            Axis::Formulation(vec![FormulationKind::Absolute, FormulationKind::Relative]),
            Axis::Inertia(vec![InertiaMethod::ShapeIntegrals, InertiaMethod::BMatrix]),
            Axis::Stiffening(vec![
                Stiffening::Linear,
                Stiffening::Fnl1,
                Stiffening::Fnl2,
                Stiffening::Foreshortening,
                Stiffening::Substructuring(8),
            ]),
            Axis::Modes {
                body: None,
                counts: vec![0, 1, 4],
            },
            Axis::Modes {
                body: Some("crank1".into()),
                counts: vec![2],
            },
            Axis::Basis {
                body: Some("beam".into()),
                kinds: flexmbd::fe::ModeSelection::ALL.to_vec(),
            },
            Axis::Elements {
                body: None,
                counts: vec![10, 20],
            },
            Axis::Terms {
                body: None,
                terms: ["full", "o2-nv", "o1", "o1-nc", "o0", "o0-nv-nc"]
                    .map(|l| InertiaTerms::parse(l).unwrap())
                    .to_vec(),
            },
            Axis::Terms {
                body: Some("beam".into()),
                terms: vec![InertiaTerms::FULL],
            },
            Axis::Step(vec![2e-3, 1e-3, 5e-4, 1.0 / 3.0 * 1e-3]),
        ];
        for axis in axes {
            let arg = axis.arg();
            assert_eq!(parse_axis(&arg), Ok(axis), "{arg}");
        }
    }
}
