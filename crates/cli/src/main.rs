//! The `flexmbd` command-line program.
//!
//! - `flexmbd modes MODEL.ron [--json]` prints the mode inventory of a flexible body:
//!   each static mode with the boundary DOF it belongs to, each normal mode with its
//!   frequency, and the DOFs the floating frame takes; `flexmbd modes SCENE.ron --body
//!   NAME` that of a flexible body of a scene (given a scene alone, it lists its bodies).
//! - `flexmbd simulate SCENE.ron [options]` runs a scene, streams the sensor histories to
//!   a CSV file as they are computed and prints a run summary; Ctrl-C or SIGTERM ends the
//!   run between two steps with status `interrupted`.
//! - `flexmbd equilibrium SCENE.ron [--json]` prints the scene's static equilibrium: the
//!   solve, the sensors, every force element's force, every joint's and constraint's
//!   reaction (force and moment on its body2, ground components), every coordinate and
//!   constraint multiplier.
//! - `flexmbd eigen SCENE.ron [--json]` prints the linearised free vibration about that
//!   equilibrium: each mode's frequency, damped frequency, damping ratio and kind, and the
//!   sensors it moves most.
//!
//! - `flexmbd sweep SCENE.ron --sensor NAME[,NAME…] [--reference CSV] [--grid …]` runs the
//!   scene over a grid of formulations, inertia routes, stiffening methods, modes, elements
//!   and steps in parallel and prints each run's error against the reference and CPU time,
//!   the Pareto front marked ([`sweep_cmd`]).
//! - `flexmbd tune SCENE.ron --sensor NAME[,NAME…] --tolerance X` prints the cheapest run
//!   of that sweep whose error is at most X, and the `flexmbd simulate` arguments that
//!   reproduce it.
//! - `flexmbd terms SCENE.ron [--threshold X] [--duration T] [--sensor S,…]` weighs each
//!   flexible body's inertia terms over a pilot run of the full model and prints the terms
//!   that meet tolerance X on the pilot: the weights' choices run in place of the full
//!   model, the first whose sensors move by at most X of their range ([`terms_cmd`]).
//! - `flexmbd fmu SCENE.ron --output NAME.fmu` writes the scene's FMI 3.0 co-simulation
//!   FMU ([`fmu_cmd`]).
//! - `flexmbd animate SCENE.ron --output run.glb|run.html [--fps F] [--scale S]` runs the
//!   scene and writes its animation, a glTF 2.0 binary or a web page that plays it
//!   ([`animate_cmd`]).
//!
//! Each kind of outcome has its exit code ([`exit`]); a panic is reported as one line
//! with [`exit::INTERNAL_ERROR`].

#![warn(missing_docs)]

mod animate_cmd;
mod csv_output;
mod exit;
mod fmu_cmd;
mod jsonl_output;
mod output_file;
mod sweep_cmd;
mod terms_cmd;

#[cfg(test)]
#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

use std::io::{IsTerminal, Write as _};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use clap::{Args, Parser, Subcommand, ValueEnum};
use csv_output::CsvFile;
use flexmbd::body::InertiaMethod;
use flexmbd::fe::BeamBodySpec;
use flexmbd::inventory::{BodyModelFile, Inventory};
use flexmbd::model::{BodyModel, FormulationKind, PreparedScene, Scene, Stiffening, parse_set};
use flexmbd::output::RowSink;
use flexmbd::simulation::{self, Summary};
use jsonl_output::JsonlFile;
use output_file::OutputFile;

#[derive(Parser)]
#[command(
    name = "flexmbd",
    version,
    about = "Real-time flexible multibody dynamics",
    after_help = exit::HELP
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum FormulationArg {
    Absolute,
    Relative,
}

#[derive(Clone, Copy, ValueEnum)]
enum InertiaArg {
    BMatrix,
    ShapeIntegrals,
}

#[derive(Subcommand)]
enum Command {
    /// Reduce a flexible body model and print its mode inventory.
    Modes {
        /// A body model file (RON), e.g. models/cantilever_2d.ron, or a scene with --body.
        model: PathBuf,
        /// The flexible body of a scene to reduce (given a scene without it, `modes` lists
        /// the scene's bodies).
        #[arg(long)]
        body: Option<String>,
        /// Print one JSON object on stdout instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Run a scene and write its sensor histories.
    #[command(after_help = exit::HELP)]
    Simulate(SimulateArgs),
    /// Find a scene's static equilibrium and print its sensors, force elements' forces, joint
    /// reactions, coordinates and constraint multipliers.
    #[command(after_help = exit::HELP)]
    Equilibrium(StaticArgs),
    /// Linearise a scene about its static equilibrium and print the modes of its free
    /// vibration (frequency, damping ratio, the sensors each moves most).
    #[command(after_help = exit::HELP)]
    Eigen(StaticArgs),
    /// Run a scene over a grid of model and solver choices in parallel and print each run's
    /// error against a reference and CPU time, the Pareto front marked.
    #[command(after_help = sweep_cmd::help())]
    Sweep(sweep_cmd::SweepInput),
    /// The cheapest model and step whose error on the named sensors is at most the
    /// tolerance, with the `flexmbd simulate` arguments that reproduce it.
    #[command(after_help = sweep_cmd::help())]
    Tune(sweep_cmd::TuneArgs),
    /// Weigh each flexible body's inertia terms over a pilot run of the full model and
    /// print the cheapest terms whose dropped groups weigh at most a threshold.
    #[command(after_help = exit::HELP)]
    Terms(terms_cmd::TermsArgs),
    /// Export a scene as an FMI 3.0 co-simulation FMU (a shared library and the scene
    /// with the files it reads), to run it in another simulator.
    Fmu(fmu_cmd::FmuArgs),
    /// Run a scene and write its animation: a glTF 2.0 binary (.glb) or a self-contained
    /// web page that plays it (.html).
    #[command(after_help = exit::HELP)]
    Animate(animate_cmd::AnimateArgs),
}

/// The scene and the options that change it, shared by `simulate`, `equilibrium` and
/// `eigen`.
#[derive(Args)]
struct SceneInput {
    /// A scene file (RON), e.g. models/double_four_bar.ron.
    scene: PathBuf,
    /// Formulation (default: the scene's).
    #[arg(long, value_enum)]
    formulation: Option<FormulationArg>,
    /// Inertia route of the flexible bodies (default: the scene's).
    #[arg(long, value_enum)]
    inertia: Option<InertiaArg>,
    /// Geometric stiffening: linear, fnl1, fnl2, foreshortening or substructuring:N.
    #[arg(long)]
    stiffening: Option<String>,
    /// Override any scalar of the scene: PATH=VALUE (e.g. bodies.crank1.flexible=true).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    sets: Vec<String>,
}

/// The arguments of `flexmbd equilibrium` and `flexmbd eigen`: the scene, the options
/// that change it, and the output form.
#[derive(Args)]
struct StaticArgs {
    #[command(flatten)]
    input: SceneInput,
    /// Print one JSON object on stdout instead of a table.
    #[arg(long)]
    json: bool,
}

/// The arguments of `flexmbd simulate`: the scene, the options that override its
/// solver settings, and where the results go.
#[derive(Args)]
struct SimulateArgs {
    #[command(flatten)]
    input: SceneInput,
    /// Time step (s).
    #[arg(long, allow_negative_numbers = true)]
    step: Option<f64>,
    /// Simulated time (s).
    #[arg(long, allow_negative_numbers = true)]
    duration: Option<f64>,
    /// CSV output (default: no CSV), written row by row as the run goes. Checked before
    /// the scene is loaded; an existing file is replaced when the run writes its header.
    #[arg(long)]
    output: Option<PathBuf>,
    /// JSON-lines output (default: none): one object {"t":…,"sensor":…} per row, written
    /// as the run goes (non-finite values as null). Checked and replaced as --output is.
    #[arg(long)]
    jsonl: Option<PathBuf>,
    /// Print the run summary as one JSON object on stdout.
    #[arg(long)]
    json: bool,
}

fn main() -> ExitCode {
    std::panic::set_hook(Box::new(exit::report_panic));
    let code = std::panic::catch_unwind(|| {
        // Only for the test of the panic path: a panic no input can be relied on to cause.
        if std::env::var_os("FLEXMBD_TEST_INTERNAL_ERROR").is_some() {
            panic!("FLEXMBD_TEST_INTERNAL_ERROR is set");
        }
        let cli = match Cli::try_parse() {
            Ok(cli) => cli,
            Err(e) => {
                let _ = e.print();
                return if e.use_stderr() {
                    exit::USAGE
                } else {
                    exit::SUCCESS
                };
            }
        };
        let result = match cli.command {
            Command::Modes { model, body, json } => modes(&model, body.as_deref(), json),
            Command::Simulate(args) => simulate(&args),
            Command::Equilibrium(args) => equilibrium(&args),
            Command::Eigen(args) => eigen(&args),
            Command::Sweep(args) => sweep_cmd::sweep(&args),
            Command::Tune(args) => sweep_cmd::tune(&args),
            Command::Terms(args) => terms_cmd::terms(&args),
            Command::Fmu(args) => fmu_cmd::fmu(&args),
            Command::Animate(args) => animate_cmd::animate(&args),
        };
        result.unwrap_or_else(|e| {
            eprintln!("error: {e}");
            exit::INVALID_INPUT
        })
    });
    ExitCode::from(code.unwrap_or(exit::INTERNAL_ERROR))
}

/// The exit code of a command that ran, or why its input was refused ([`exit::INVALID_INPUT`]).
type CliResult = Result<u8, Box<dyn std::error::Error>>;

fn modes(model: &Path, body: Option<&str>, json: bool) -> CliResult {
    let name = model.display().to_string();
    let text = std::fs::read_to_string(model).map_err(|e| format!("cannot read {name}: {e}"))?;
    match BodyModelFile::parse(&text, model) {
        Ok(_) if body.is_some() => Err(format!(
            "{name}: this is a body model, not a scene; --body picks a body of a scene"
        )
        .into()),
        Ok(file) => {
            let reduced = file.reduce(model).map_err(|e| format!("{name}: {e}"))?;
            let inv = Inventory::of(&name, &reduced);
            print_json_or_table(&inv, json, Inventory::to_text)
        }
        Err(body_error) => match Scene::load(model) {
            Ok(scene) => scene_body_modes(&scene, &name, body, json),
            Err(scene_error) if looks_like_a_scene(&text) => Err(scene_error.into()),
            Err(_) => Err(body_error.into()),
        },
    }
}

/// A text that names a scene's own fields is read as a scene when it parses as neither,
/// so its error is the scene parser's.
fn looks_like_a_scene(text: &str) -> bool {
    ["bodies:", "joints:", "solver:"]
        .iter()
        .any(|field| text.contains(field))
}

/// `flexmbd modes SCENE --body NAME`: the inventory of one flexible body of a scene as the
/// scene runs it (prepared: its stiffening method's rewrite applied). Without `--body`,
/// the scene's bodies are listed in the error.
fn scene_body_modes(scene: &Scene, file: &str, body: Option<&str>, json: bool) -> CliResult {
    let listing = || {
        scene
            .bodies
            .iter()
            .map(|b| {
                let kind = match (&b.model, b.flexible) {
                    (BodyModel::Rigid { .. }, _) => "rigid",
                    (BodyModel::Beam(_), true) => "flexible beam",
                    (BodyModel::Beam(_), false) => "beam run rigid",
                    (BodyModel::Imported(_), true) => "flexible FE import",
                    (BodyModel::Imported(_), false) => "FE import run rigid",
                };
                format!("{} ({kind})", b.name)
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let Some(name) = body else {
        return Err(format!(
            "{file}: this is a scene, not a body model; its bodies: {}. \
             `flexmbd modes {file} --body NAME` prints the modes of one flexible body",
            listing()
        )
        .into());
    };
    let prepared = PreparedScene::new(scene)?;
    let index = prepared.scene().bodies.iter().position(|b| b.name == name);
    let Some(prep) = index.map(|i| &prepared.bodies()[i]) else {
        return Err(format!(
            "--body {name}: {file} has no such body; its bodies: {}",
            listing()
        )
        .into());
    };
    if !prep.flexible {
        return Err(format!(
            "--body {name}: the body is rigid in {file}: it has no modes (a beam body runs \
             flexible with `flexible: true`)"
        )
        .into());
    }
    let inv = Inventory::of(&format!("{file}, body {name}"), &prep.reduced);
    print_json_or_table(&inv, json, Inventory::to_text)
}

/// Print `value` on stdout as one JSON object (`--json`) or as its table.
fn print_json_or_table<T: serde::Serialize>(
    value: &T,
    json: bool,
    table: impl FnOnce(&T) -> String,
) -> CliResult {
    let mut stdout = std::io::stdout().lock();
    if json {
        writeln!(stdout, "{}", serde_json::to_string(value)?)?;
    } else {
        write!(stdout, "{}", table(value))?;
    }
    Ok(exit::SUCCESS)
}

fn parse_stiffening(s: &str) -> Result<Stiffening, String> {
    Ok(match s {
        "linear" => Stiffening::Linear,
        "fnl1" => Stiffening::Fnl1,
        "fnl2" => Stiffening::Fnl2,
        "foreshortening" | "fs0" => Stiffening::Foreshortening,
        _ => match s.strip_prefix("substructuring:") {
            Some(n) => Stiffening::Substructuring(
                n.parse()
                    .map_err(|_| format!("--stiffening {s}: N must be a positive integer"))?,
            ),
            None => {
                return Err(format!(
                    "--stiffening {s}: expected linear, fnl1, fnl2, foreshortening or substructuring:N"
                ));
            }
        },
    })
}

/// `flexmbd simulate`: check the output path, load the scene, apply the command line to
/// it, run it with the rows streamed to the CSV file and Ctrl-C / SIGTERM as a stop
/// request, and report the summary. The exit code is the summary's status's
/// ([`exit::of_status`]).
fn simulate(args: &SimulateArgs) -> CliResult {
    let mut sinks = args.output_files()?;
    let mut scene = args.input.load()?;
    args.apply_to(&mut scene);
    scene.validate()?;
    let stop = stop_on_signals()?;
    let summary = run_with_progress_bar(&scene, args.json, &mut sinks, &stop)?;
    if args.json {
        writeln!(std::io::stdout(), "{}", serde_json::to_string(&summary)?)?;
    } else {
        print_summary(&summary, [args.output.as_deref(), args.jsonl.as_deref()]);
    }
    Ok(exit::of_status(&summary.status))
}

/// The scene of `flexmbd equilibrium` or `flexmbd eigen`, loaded, changed by the command
/// line and validated.
fn static_scene(args: &StaticArgs) -> Result<Scene, Box<dyn std::error::Error>> {
    let scene = args.input.load()?;
    scene.validate()?;
    Ok(scene)
}

/// The result of `flexmbd equilibrium` or `flexmbd eigen`; no equilibrium, no modes or a
/// failed pilot run of proper orthogonal modes is reported on stderr, naming the scene, as
/// a failed run ([`exit::RUN_FAILED`]), a refused scene as invalid input.
fn solved<T>(
    args: &StaticArgs,
    result: Result<T, flexmbd::Error>,
) -> Result<Result<T, u8>, flexmbd::Error> {
    match result {
        Ok(v) => Ok(Ok(v)),
        Err(flexmbd::Error::Static(e)) => {
            eprintln!(
                "error: {}: no static equilibrium: {e}",
                args.input.scene.display()
            );
            Ok(Err(exit::RUN_FAILED))
        }
        Err(flexmbd::Error::Vibration(e)) => {
            eprintln!("error: {}: {e}", args.input.scene.display());
            Ok(Err(exit::RUN_FAILED))
        }
        // The pilot run of proper orthogonal modes failed (it names the scene's file).
        Err(flexmbd::Error::Pilot(e)) => {
            eprintln!("error: {e}");
            Ok(Err(if e.interrupted() {
                exit::INTERRUPTED
            } else {
                exit::RUN_FAILED
            }))
        }
        Err(e) => Err(e),
    }
}

/// `flexmbd equilibrium`: the static equilibrium as a table or one JSON object.
fn equilibrium(args: &StaticArgs) -> CliResult {
    match solved(args, flexmbd::equilibrium(&static_scene(args)?))? {
        Ok(e) => print_json_or_table(&e, args.json, |e| e.to_text()),
        Err(code) => Ok(code),
    }
}

/// `flexmbd eigen`: the modes about the static equilibrium as a table or one JSON object.
fn eigen(args: &StaticArgs) -> CliResult {
    match solved(args, flexmbd::vibration(&static_scene(args)?))? {
        Ok(v) => print_json_or_table(&v, args.json, |v| v.to_text()),
        Err(code) => Ok(code),
    }
}

/// Set the formulation, inertia route and stiffening of `scene` where the command line
/// names them.
fn apply_solver_options(
    scene: &mut Scene,
    formulation: Option<FormulationArg>,
    inertia: Option<InertiaArg>,
    stiffening: Option<&str>,
) -> Result<(), String> {
    let solver = &mut scene.solver;
    if let Some(f) = formulation {
        solver.formulation = match f {
            FormulationArg::Absolute => FormulationKind::Absolute,
            FormulationArg::Relative => FormulationKind::Relative,
        };
    }
    if let Some(i) = inertia {
        solver.inertia = match i {
            InertiaArg::BMatrix => InertiaMethod::BMatrix,
            InertiaArg::ShapeIntegrals => InertiaMethod::ShapeIntegrals,
        };
    }
    if let Some(s) = stiffening {
        solver.stiffening = parse_stiffening(s)?;
    }
    Ok(())
}

/// A flag that the first SIGINT or SIGTERM sets (the run stops at the next step); a
/// second one ends the program at once with [`exit::INTERRUPTED`].
pub(crate) fn stop_on_signals() -> std::io::Result<Arc<AtomicBool>> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let stop = Arc::new(AtomicBool::new(false));
    for signal in [SIGINT, SIGTERM] {
        // The shutdown first: it acts only once the flag is already set.
        signal_hook::flag::register_conditional_shutdown(
            signal,
            exit::INTERRUPTED.into(),
            Arc::clone(&stop),
        )?;
        signal_hook::flag::register(signal, Arc::clone(&stop))?;
    }
    Ok(stop)
}

/// Load the scene at `path`. When it does not load but is a body model (the input
/// of `flexmbd modes`), say so instead of reporting the scene parser's complaint.
fn load_scene(path: &Path) -> Result<Scene, Box<dyn std::error::Error>> {
    Scene::load(path).map_err(|e| -> Box<dyn std::error::Error> {
        let is_body_model = std::fs::read_to_string(path).is_ok_and(|text| {
            BeamBodySpec::from_ron_str(&text, &path.display().to_string()).is_ok()
        });
        if is_body_model {
            format!(
                "{}: this is a body model, not a scene (`flexmbd modes {}` reads it; a scene lists bodies, joints and a solver)",
                path.display(),
                path.display()
            )
            .into()
        } else {
            e.into()
        }
    })
}

impl SimulateArgs {
    /// The output files asked for, checked before the scene is loaded: neither is the
    /// scene, nor the other.
    fn output_files(&self) -> Result<Sinks, String> {
        let mut sinks = Sinks(Vec::new());
        if let Some(out) = &self.output {
            let file =
                OutputFile::check("--output", out, &[("the scene file", &self.input.scene)])?;
            sinks.0.push(Box::new(CsvFile::new(file)));
        }
        if let Some(out) = &self.jsonl {
            let mut others = vec![("the scene file", self.input.scene.as_path())];
            others.extend(self.output.as_deref().map(|o| ("the --output file", o)));
            let file = OutputFile::check("--jsonl", out, &others)?;
            sinks.0.push(Box::new(JsonlFile::new(file)));
        }
        Ok(sinks)
    }

    /// Apply `--step` and `--duration` to `scene` (after [`SceneInput::load`], so that they
    /// win over a `--set` of the same field). The scene is not validated here.
    fn apply_to(&self, scene: &mut Scene) {
        let solver = &mut scene.solver;
        if let Some(h) = self.step {
            solver.step = h;
        }
        if let Some(d) = self.duration {
            solver.duration = d;
        }
    }
}

impl SceneInput {
    /// Load the scene, apply the `--set` overrides, then the named options, so that
    /// `--formulation` and the like win over a `--set` of the same field. Every `--set` is
    /// parsed before any is applied. The scene is not validated here.
    fn load(&self) -> Result<Scene, Box<dyn std::error::Error>> {
        let mut scene = load_scene(&self.scene)?;
        let sets = self
            .sets
            .iter()
            .map(|s| parse_set(s))
            .collect::<Result<Vec<_>, _>>()?;
        scene.apply_sets(&sets)?;
        apply_solver_options(
            &mut scene,
            self.formulation,
            self.inertia,
            self.stiffening.as_deref(),
        )?;
        Ok(scene)
    }
}

/// The output files of a run, each handed every row (none: the rows are dropped).
struct Sinks(Vec<Box<dyn RowSink>>);

impl RowSink for Sinks {
    fn header(&mut self, columns: &[String], rows: usize) -> Result<(), flexmbd::Error> {
        self.0.iter_mut().try_for_each(|s| s.header(columns, rows))
    }

    fn row(&mut self, values: &[f64]) -> Result<(), flexmbd::Error> {
        self.0.iter_mut().try_for_each(|s| s.row(values))
    }
}

/// Run `scene` with its rows into `sink` until `stop` is set, showing a progress bar on
/// stderr for a long run (over 2·10⁴ steps) when stderr is a terminal and the summary is
/// not going to stdout as JSON.
fn run_with_progress_bar(
    scene: &Scene,
    json: bool,
    sink: &mut dyn RowSink,
    stop: &AtomicBool,
) -> Result<Summary, flexmbd::Error> {
    let bar = (!json
        && std::io::stderr().is_terminal()
        && scene.solver.duration / scene.solver.step > 2e4)
        .then(|| {
            let pb = indicatif::ProgressBar::new(1000);
            pb.set_style(
                indicatif::ProgressStyle::with_template(
                    "{bar:40} {percent:>3}% simulated, {elapsed} elapsed, eta {eta}",
                )
                .expect("valid template"),
            );
            pb
        });
    let result = simulation::run_into(scene, sink, stop, |frac| {
        if let Some(pb) = &bar {
            pb.set_position((frac * 1000.0) as u64);
        }
    });
    if let Some(pb) = bar {
        pb.finish_and_clear();
    }
    result
}

/// The run summary for a reader, on stderr: outcome and model size, speed, where
/// the CPU time went, the failure or interruption if any, the warnings, and the files
/// written (`outputs`).
fn print_summary(summary: &Summary, outputs: [Option<&Path>; 2]) {
    if summary.n_coordinates == 0 && summary.steps == 0 {
        // Stopped while the scene was prepared (its pilot run): no model, no step to report.
        eprintln!(
            "{}: {} before the scene was compiled ({} {} {})",
            summary.scene, summary.status, summary.formulation, summary.inertia, summary.stiffening
        );
        print_outcome(summary, outputs);
        return;
    }
    eprintln!(
        "{}: {} — {} coordinates, {} constraints, {} {} {}",
        summary.scene,
        summary.status,
        summary.n_coordinates,
        summary.n_constraints,
        summary.formulation,
        summary.inertia,
        summary.stiffening
    );
    eprintln!(
        "  {:.3} s simulated in {:.4} s CPU (real-time factor {:.1}), {} steps, {:.2} Newton iterations per step",
        summary.simulated_seconds,
        summary.cpu_seconds,
        summary.realtime_factor,
        summary.steps,
        summary.newton_iterations as f64 / summary.steps.max(1) as f64
    );
    eprintln!(
        "  time split: evaluation {:.4} s, factorisation {:.4} s, projections {:.4} s; preprocessing {:.4} s",
        summary.time_evaluation,
        summary.time_factorization,
        summary.time_projection,
        summary.preprocessing_seconds
    );
    print_outcome(summary, outputs);
}

/// The failure or interruption if any, the warnings and the files written.
fn print_outcome(summary: &Summary, outputs: [Option<&Path>; 2]) {
    if let (Some(t), Some(m)) = (summary.failed_at, &summary.message) {
        eprintln!("  failed at t = {t:.6} s: {m}");
    } else if let Some(m) = &summary.message {
        eprintln!("  {m}");
    }
    for w in &summary.warnings {
        eprintln!("  warning: {w}");
    }
    for out in outputs.iter().flatten() {
        eprintln!("  {} rows written to {}", summary.rows, out.display());
    }
}
