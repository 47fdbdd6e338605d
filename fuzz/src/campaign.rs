//! A campaign: the mutants `0, 1, 2, …` of a seed — of the scenes, each run in both
//! formulations, or of the reader inputs, each run once — by a pool of supervised
//! workers, until an execution count or a time budget is spent.

use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use flexmbd::model::FormulationKind;

use std::io::Write;

use crate::corpus::SeedScene;
use crate::findings::{Reproducer, SceneExecution, Tally};
use crate::mutate::mutant;
use crate::readers::corpus::ReaderSeed;
use crate::readers::mutate::reader_mutant;
use crate::supervise::{Supervisor, WorkerConfig};
use crate::worker::Request;

/// The formulations every mutant runs in.
pub const FORMULATIONS: [FormulationKind; 2] =
    [FormulationKind::Absolute, FormulationKind::Relative];

/// What a campaign mutates.
#[derive(Clone, Debug)]
pub enum Corpus {
    /// Scenes, each mutant run in both [`FORMULATIONS`].
    Scenes(Vec<SeedScene>),
    /// Reader inputs, each mutant run once.
    Readers(Vec<ReaderSeed>),
}

/// One execution of a mutant: the worker's request and the reproducer of a defect.
pub struct Job {
    /// What the worker runs.
    pub request: Request,
    /// Its place among the executions of its mutant.
    pub rank: usize,
    /// Writes its reproducer.
    pub reproducer: Box<dyn Reproducer + Send>,
}

impl Corpus {
    /// The executions of one mutant.
    pub fn executions_per_mutant(&self) -> u64 {
        match self {
            Corpus::Scenes(_) => FORMULATIONS.len() as u64,
            Corpus::Readers(_) => 1,
        }
    }

    /// The executions of mutant `index` of campaign `seed`.
    pub fn jobs(&self, seed: u64, index: u64) -> Vec<Job> {
        match self {
            Corpus::Scenes(scenes) => {
                let m = mutant(scenes, seed, index);
                FORMULATIONS
                    .iter()
                    .enumerate()
                    .map(|(rank, &formulation)| Job {
                        request: Request::Scene {
                            formulation,
                            text: m.text.clone(),
                        },
                        rank,
                        reproducer: Box::new(SceneExecution {
                            mutant: m.clone(),
                            formulation,
                        }),
                    })
                    .collect()
            }
            Corpus::Readers(seeds) => {
                let m = reader_mutant(seeds, seed, index);
                vec![Job {
                    request: Request::Reader(m.input.clone()),
                    rank: 0,
                    reproducer: Box::new(m),
                }]
            }
        }
    }
}

/// What a campaign runs and where it writes.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The campaign's seed.
    pub seed: u64,
    /// Stop after this many executions (rounded up to whole mutants).
    pub executions: Option<u64>,
    /// Stop taking new mutants after this long.
    pub seconds: Option<f64>,
    /// Parallel workers.
    pub workers: usize,
    /// How a worker runs.
    pub worker: WorkerConfig,
    /// Where reproducers go.
    pub findings: PathBuf,
    /// Where every outcome is logged, one line each (`--log`), if anywhere.
    pub log: Option<PathBuf>,
}

/// What a campaign did.
#[derive(Debug)]
pub struct Report {
    /// The outcomes.
    pub tally: Tally,
    /// Wall-clock time.
    pub elapsed: Duration,
    /// Workers started (the pool plus restarts after hangs and deaths).
    pub worker_starts: u64,
}

/// Run `plan` over `corpus`, printing progress to stderr every `progress_every`.
pub fn run(plan: &Plan, corpus: &Corpus, progress_every: Duration) -> std::io::Result<Report> {
    let start = Instant::now();
    let mutants = plan
        .executions
        .map(|n| n.div_ceil(corpus.executions_per_mutant()));
    let deadline = plan.seconds.map(|s| start + Duration::from_secs_f64(s));
    let next = AtomicU64::new(0);
    let tally = Mutex::new(Tally::default());
    let starts = AtomicU64::new(0);
    let last_progress = Mutex::new(start);
    let log = match &plan.log {
        Some(path) => Some(Mutex::new(std::io::BufWriter::new(std::fs::File::create(
            path,
        )?))),
        None => None,
    };
    std::thread::scope(|scope| -> std::io::Result<()> {
        let handles: Vec<_> = (0..plan.workers)
            .map(|_| {
                scope.spawn(|| -> std::io::Result<()> {
                    let mut supervisor = Supervisor::new(plan.worker.clone());
                    loop {
                        let index = next.fetch_add(1, Ordering::Relaxed);
                        let done = mutants.is_some_and(|m| index >= m)
                            || deadline.is_some_and(|d| Instant::now() >= d);
                        if done {
                            break;
                        }
                        for job in corpus.jobs(plan.seed, index) {
                            let clock = Instant::now();
                            let outcome = supervisor.run(&job.request);
                            if let Some(log) = &log {
                                let ms = clock.elapsed().as_secs_f64() * 1e3;
                                let line = format!(
                                    "{index}\t{}\t{ms:.1}\t{}\t{}\n",
                                    job.reproducer.label(),
                                    outcome.class.name(),
                                    outcome.detail
                                );
                                log.lock().expect("log").write_all(line.as_bytes())?;
                            }
                            let mut t = tally.lock().expect("tally");
                            let order = (plan.seed, index, job.rank);
                            t.record(job.reproducer.as_ref(), order, &outcome, &plan.findings)?;
                            report_progress(&t, start, &last_progress, progress_every);
                        }
                    }
                    starts.fetch_add(supervisor.starts, Ordering::Relaxed);
                    Ok(())
                })
            })
            .collect();
        for h in handles {
            h.join().expect("a campaign thread panicked")?;
        }
        Ok(())
    })?;
    if let Some(log) = log {
        log.into_inner().expect("log").flush()?;
    }
    Ok(Report {
        tally: tally.into_inner().expect("tally"),
        elapsed: start.elapsed(),
        worker_starts: starts.into_inner(),
    })
}

/// One progress line on stderr when `every` has passed since the last.
fn report_progress(t: &Tally, start: Instant, last: &Mutex<Instant>, every: Duration) {
    let mut last = last.lock().expect("progress clock");
    if last.elapsed() < every {
        return;
    }
    *last = Instant::now();
    let seconds = start.elapsed().as_secs_f64();
    let n = t.executions();
    eprintln!(
        "[{seconds:>7.0} s] {n} executions ({:.1}/s), {} defects",
        n as f64 / seconds,
        t.defects()
    );
}
