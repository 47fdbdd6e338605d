//! The `flexmbd-fuzz` program: a campaign over the scenes or the FE import readers
//! (`--target`, `--seed S --executions N` or `--seconds T`), a replay of reproducers
//! (`--replay FILE…`), or, hidden, a worker (`--worker`).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::{Parser, ValueEnum};
use flexmbd_fuzz::campaign::{self, Corpus, FORMULATIONS, Plan};
use flexmbd_fuzz::corpus::{default_models_dir, load_corpus, workspace_root};
use flexmbd_fuzz::execute::{Outcome, formulation_name};
use flexmbd_fuzz::findings::read_reproducer;
use flexmbd_fuzz::readers::corpus::{default_import_data_dir, load_reader_corpus};
use flexmbd_fuzz::readers::reproducer::read_reader_reproducer;
use flexmbd_fuzz::supervise::{Supervisor, WorkerConfig};
use flexmbd_fuzz::worker::{self, Request};

/// What a campaign mutates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Target {
    /// The scenes of models/, each mutant run in both formulations.
    Scenes,
    /// The FE import readers on their test exports (some mutants also reduced).
    Readers,
}

/// Mutation fuzzer of flexmbd's scene files (load, validate and a short simulation of each
/// mutant in both formulations) or of its FE import readers (each mutant read, sometimes
/// reduced), under a time and a memory cap. Exit status: 0 no defect, 1 defects found
/// (reproducers written), 2 usage or setup error.
#[derive(Parser, Debug)]
#[command(name = "flexmbd-fuzz", version)]
struct Cli {
    /// What to fuzz: the scenes, or the FE import readers.
    #[arg(long, value_enum, default_value_t = Target::Scenes)]
    target: Target,
    /// Campaign seed: the same seed and count give the same mutants.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Stop after this many executions (a scene mutant is two: one per formulation; a
    /// reader mutant is one).
    #[arg(long)]
    executions: Option<u64>,
    /// Stop after this many seconds (with --executions: whichever comes first).
    #[arg(long)]
    seconds: Option<f64>,
    /// Parallel workers (default: one per core).
    #[arg(long)]
    workers: Option<usize>,
    /// Wall-clock cap of one execution (s); over it is a hang. Above the slowest clean
    /// execution the bounds allow: reducing a beam of the largest size (2400 FE DOFs) takes
    /// about 5 s on one core (docs/fuzzing.md).
    #[arg(long, default_value_t = 20.0)]
    timeout: f64,
    /// Address-space cap of a worker (MiB); an allocation over it is an oom.
    #[arg(long, default_value_t = 2048)]
    memory_mib: u64,
    /// Steps simulated per execution, whatever the mutant's duration.
    #[arg(long, default_value_t = 20)]
    max_steps: usize,
    /// The seed scenes (default: the workspace's models/).
    #[arg(long)]
    models: Option<PathBuf>,
    /// The seed exports of the readers (default: the workspace's crates/fe/tests/data/import).
    #[arg(long)]
    import_data: Option<PathBuf>,
    /// Where reproducers are written (default: target/fuzz/findings in the workspace).
    #[arg(long)]
    findings: Option<PathBuf>,
    /// Log every outcome to this file: mutant index, formulation, milliseconds, class, detail (tab-separated).
    #[arg(long)]
    log: Option<PathBuf>,
    /// Run these reproducers again: a scene file (in the formulation its footer names, or
    /// both) or a reader reproducer directory.
    #[arg(long, num_args = 1.., value_name = "FILE")]
    replay: Vec<PathBuf>,
    /// With --replay: run in this process, unsupervised, so a panic shows its backtrace
    /// (RUST_BACKTRACE=1) and a debugger can attach.
    #[arg(long, requires = "replay")]
    in_process: bool,
    /// Serve executions on stdin (started by the supervisor).
    #[arg(long, hide = true)]
    worker: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = if cli.worker {
        worker::serve(cli.memory_mib, cli.max_steps)
            .map(|()| ExitCode::SUCCESS)
            .map_err(|e| e.to_string())
    } else if !cli.replay.is_empty() {
        replay(&cli)
    } else {
        fuzz(&cli)
    };
    result.unwrap_or_else(|message| {
        eprintln!("flexmbd-fuzz: {message}");
        ExitCode::from(2)
    })
}

/// The worker settings of the command line.
fn worker_config(cli: &Cli) -> Result<WorkerConfig, String> {
    if !(cli.timeout.is_finite() && cli.timeout > 0.0) {
        return Err(format!("--timeout {}: must be finite and > 0", cli.timeout));
    }
    Ok(WorkerConfig {
        program: std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?,
        directory: Some(cli.models.clone().unwrap_or_else(default_models_dir)),
        memory_mib: cli.memory_mib,
        max_steps: cli.max_steps,
        timeout: Duration::from_secs_f64(cli.timeout),
    })
}

/// A campaign and its summary.
fn fuzz(cli: &Cli) -> Result<ExitCode, String> {
    if cli.executions.is_none() && cli.seconds.is_none() {
        return Err("give a budget: --executions N and/or --seconds T".into());
    }
    let (corpus, source) = load_target(cli)?;
    let workers = cli
        .workers
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let plan = Plan {
        seed: cli.seed,
        executions: cli.executions,
        seconds: cli.seconds,
        workers,
        worker: worker_config(cli)?,
        findings: cli
            .findings
            .clone()
            .unwrap_or_else(|| workspace_root().join("target/fuzz/findings")),
        log: cli.log.clone(),
    };
    eprintln!(
        "flexmbd-fuzz: seed {}, {source}, {workers} workers, cap {} s and {} MiB, {} steps",
        plan.seed, cli.timeout, cli.memory_mib, cli.max_steps
    );
    let report = campaign::run(&plan, &corpus, Duration::from_secs(30))
        .map_err(|e| format!("writing findings: {e}"))?;
    let n = report.tally.executions();
    let seconds = report.elapsed.as_secs_f64();
    println!(
        "flexmbd-fuzz: seed {}: {n} executions in {seconds:.1} s ({:.1} executions/s, {workers} workers, {} worker starts)",
        plan.seed,
        n as f64 / seconds,
        report.worker_starts
    );
    for line in report.tally.summary() {
        println!("{line}");
    }
    let defects = report.tally.defects();
    if defects == 0 {
        println!("no defect");
        Ok(ExitCode::SUCCESS)
    } else {
        println!(
            "{defects} defects; reproducers in {}",
            plan.findings.display()
        );
        Ok(ExitCode::from(1))
    }
}

/// The corpus of the campaign's target and a description of it.
fn load_target(cli: &Cli) -> Result<(Corpus, String), String> {
    match cli.target {
        Target::Scenes => {
            let models = cli.models.clone().unwrap_or_else(default_models_dir);
            let (scenes, skipped) = load_corpus(&models)?;
            for note in skipped {
                eprintln!("flexmbd-fuzz: {note}");
            }
            let source = format!("{} scenes from {}", scenes.len(), models.display());
            Ok((Corpus::Scenes(scenes), source))
        }
        Target::Readers => {
            let dir = cli
                .import_data
                .clone()
                .unwrap_or_else(default_import_data_dir);
            let seeds = load_reader_corpus(&dir)?;
            let source = format!("{} reader inputs from {}", seeds.len(), dir.display());
            Ok((Corpus::Readers(seeds), source))
        }
    }
}

/// The requests a reproducer records, each with its label: a directory is a reader's,
/// a file a scene's (in the formulation its footer names, or both).
fn replay_requests(path: &std::path::Path) -> Result<Vec<(String, Request)>, String> {
    if path.is_dir() {
        let input = read_reader_reproducer(path)?;
        return Ok(vec![(
            input.reader.name().to_string(),
            Request::Reader(input),
        )]);
    }
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let (formulation, mutant) = read_reproducer(&text);
    let formulations = formulation.map_or(FORMULATIONS.to_vec(), |f| vec![f]);
    Ok(formulations
        .into_iter()
        .map(|f| {
            let request = Request::Scene {
                formulation: f,
                text: mutant.to_string(),
            };
            (formulation_name(f).to_string(), request)
        })
        .collect())
}

/// Run reproducers again and print their outcomes.
fn replay(cli: &Cli) -> Result<ExitCode, String> {
    let mut supervisor = Supervisor::new(worker_config(cli)?);
    let mut defects = 0;
    for path in &cli.replay {
        for (label, request) in replay_requests(path)? {
            let outcome: Outcome = if cli.in_process {
                worker::run_request(&request, cli.max_steps)
            } else {
                supervisor.run(&request)
            };
            defects += u32::from(outcome.class.is_defect());
            println!(
                "{} ({label}): {} {}",
                path.display(),
                outcome.class.name(),
                outcome.detail
            );
        }
    }
    Ok(if defects == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
