//! The `flexmbd-fuzz` program: a campaign (`--seed S --executions N` or `--seconds T`),
//! a replay of reproducers (`--replay FILE…`), or, hidden, a worker (`--worker`).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use flexmbd_fuzz::campaign::{self, FORMULATIONS, Plan};
use flexmbd_fuzz::corpus::{default_models_dir, load_corpus, workspace_root};
use flexmbd_fuzz::execute::{execute, formulation_name};
use flexmbd_fuzz::findings::read_reproducer;
use flexmbd_fuzz::supervise::{Supervisor, WorkerConfig};
use flexmbd_fuzz::worker;

/// Mutation fuzzer of flexmbd's scene files: load, validate and a short simulation of each
/// mutant in both formulations, under a time and a memory cap. Exit status: 0 no defect,
/// 1 defects found (reproducers written), 2 usage or setup error.
#[derive(Parser, Debug)]
#[command(name = "flexmbd-fuzz", version)]
struct Cli {
    /// Campaign seed: the same seed and count give the same mutants.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Stop after this many executions (a mutant is two: one per formulation).
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
    /// Where reproducers are written (default: target/fuzz/findings in the workspace).
    #[arg(long)]
    findings: Option<PathBuf>,
    /// Log every outcome to this file: mutant index, formulation, milliseconds, class, detail (tab-separated).
    #[arg(long)]
    log: Option<PathBuf>,
    /// Run these reproducers again (each in the formulation its header names, or both).
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
    let models = cli.models.clone().unwrap_or_else(default_models_dir);
    let (corpus, skipped) = load_corpus(&models)?;
    for note in skipped {
        eprintln!("flexmbd-fuzz: {note}");
    }
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
        "flexmbd-fuzz: seed {}, {} scenes from {}, {workers} workers, cap {} s and {} MiB, {} steps",
        plan.seed,
        corpus.len(),
        models.display(),
        cli.timeout,
        cli.memory_mib,
        cli.max_steps
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

/// Run reproducers again and print their outcomes.
fn replay(cli: &Cli) -> Result<ExitCode, String> {
    let mut supervisor = Supervisor::new(worker_config(cli)?);
    let mut defects = 0;
    for path in &cli.replay {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let (formulation, mutant) = read_reproducer(&text);
        let formulations = formulation.map_or(FORMULATIONS.to_vec(), |f| vec![f]);
        for f in formulations {
            let outcome = if cli.in_process {
                execute(mutant, f, cli.max_steps)
            } else {
                supervisor.execute(mutant, f)
            };
            defects += u32::from(outcome.class.is_defect());
            println!(
                "{} ({}): {} {}",
                path.display(),
                formulation_name(f),
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
