//! The supervisor's side of a worker: start it, send an execution, wait for its outcome
//! at most the wall-clock cap, and when the worker hangs (killed) or dies (an abort under
//! the memory cap, a signal), turn that into the outcome of the execution in flight; the
//! next execution starts a new worker.

use std::io::{BufRead, BufReader, Read};
use std::os::unix::process::ExitStatusExt;
use std::path::PathBuf;
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::thread::JoinHandle;
use std::time::Duration;

use flexmbd::model::FormulationKind;

use crate::execute::{Class, Outcome};
use crate::worker::{Request, parse_reply, write_any_request};

/// How to start a worker and how long to wait for it.
#[derive(Clone, Debug)]
pub struct WorkerConfig {
    /// This program.
    pub program: PathBuf,
    /// The worker's address-space cap (MiB).
    pub memory_mib: u64,
    /// The steps per execution.
    pub max_steps: usize,
    /// The wall-clock cap of one execution.
    pub timeout: Duration,
    /// The worker's working directory (`None`: the supervisor's). The campaign gives
    /// the corpus's, so that the files a scene names relative to itself (an imported
    /// body's FE export) are found as they are for the seed scene: a mutant is loaded
    /// from text, and its relative paths are taken from the working directory.
    pub directory: Option<PathBuf>,
}

/// A running worker: its pipes and the threads that read them.
struct Running {
    child: Child,
    stdin: ChildStdin,
    replies: Receiver<String>,
    stderr: JoinHandle<String>,
}

/// One supervised worker, restarted after each death.
pub struct Supervisor {
    config: WorkerConfig,
    running: Option<Running>,
    /// How many workers were started (1 + restarts).
    pub starts: u64,
}

impl Supervisor {
    /// A supervisor; the worker starts with the first execution.
    pub fn new(config: WorkerConfig) -> Supervisor {
        Supervisor {
            config,
            running: None,
            starts: 0,
        }
    }

    /// Run the scene `text` in `formulation` in the worker and classify the outcome.
    pub fn execute(&mut self, text: &str, formulation: FormulationKind) -> Outcome {
        self.run(&Request::Scene {
            formulation,
            text: text.to_string(),
        })
    }

    /// Run `request` in the worker and classify the outcome.
    pub fn run(&mut self, request: &Request) -> Outcome {
        if self.running.is_none() {
            match self.start() {
                Ok(r) => self.running = Some(r),
                Err(e) => {
                    return Outcome::new(Class::Crash, format!("cannot start the worker: {e}"));
                }
            }
        }
        let running = self.running.as_mut().expect("started above");
        if write_any_request(&mut running.stdin, request).is_err() {
            return self.death();
        }
        match running.replies.recv_timeout(self.config.timeout) {
            Ok(line) => match parse_reply(&line) {
                Some(outcome) => outcome,
                None => Outcome::new(Class::Crash, format!("unreadable worker reply: {line}")),
            },
            Err(RecvTimeoutError::Timeout) => {
                let mut r = self.running.take().expect("running");
                // Our own child, by its handle: SIGKILL, then reap it.
                let _ = r.child.kill();
                let _ = r.child.wait();
                let seconds = self.config.timeout.as_secs_f64();
                Outcome::new(
                    Class::Hang,
                    format!("no outcome within {seconds} s (worker killed)"),
                )
            }
            Err(RecvTimeoutError::Disconnected) => self.death(),
        }
    }

    /// The outcome of the execution in flight when the worker died.
    fn death(&mut self) -> Outcome {
        let mut r = self.running.take().expect("running");
        drop(r.stdin);
        let status = r.child.wait();
        let stderr = r.stderr.join().unwrap_or_default();
        match status {
            Ok(status) => died(status, stderr.trim()),
            Err(e) => Outcome::new(Class::Crash, format!("worker lost: {e}")),
        }
    }

    /// Start a worker.
    fn start(&mut self) -> std::io::Result<Running> {
        let c = &self.config;
        let mut command = Command::new(&c.program);
        if let Some(dir) = &c.directory {
            command.current_dir(dir);
        }
        let mut child = command
            .arg("--worker")
            .args(["--memory-mib", &c.memory_mib.to_string()])
            .args(["--max-steps", &c.max_steps.to_string()])
            // A short stderr: an abort's message without a backtrace.
            .env_remove("RUST_BACKTRACE")
            .env_remove("RUST_LIB_BACKTRACE")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()?;
        self.starts += 1;
        let stdin = child.stdin.take().expect("piped");
        let stdout = child.stdout.take().expect("piped");
        let mut stderr_pipe = child.stderr.take().expect("piped");
        let (send, replies) = channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if send.send(line).is_err() {
                    break;
                }
            }
        });
        let stderr = std::thread::spawn(move || {
            let mut bytes = Vec::new();
            let _ = stderr_pipe.read_to_end(&mut bytes);
            bytes.truncate(4000);
            String::from_utf8_lossy(&bytes).into_owned()
        });
        Ok(Running {
            child,
            stdin,
            replies,
            stderr,
        })
    }
}

impl Drop for Supervisor {
    fn drop(&mut self) {
        if let Some(r) = self.running.take() {
            // Closing stdin ends the worker's loop; reap it.
            let Running {
                mut child, stdin, ..
            } = r;
            drop(stdin);
            let _ = child.wait();
        }
    }
}

/// The class of a worker's death: an allocation failure, another abort, or a crash.
fn died(status: ExitStatus, stderr: &str) -> Outcome {
    // The first line that says something (not a backtrace's header or note).
    let first = stderr
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with("stack backtrace") && !l.starts_with("note:"))
        .unwrap_or("(nothing on stderr)");
    match status.signal() {
        _ if stderr.contains("memory allocation of") => {
            Outcome::new(Class::Oom, format!("worker aborted: {first}"))
        }
        Some(libc::SIGABRT) => {
            Outcome::new(Class::Abort, format!("worker aborted (SIGABRT): {first}"))
        }
        Some(signal) => Outcome::new(
            Class::Crash,
            format!("worker killed by signal {signal}: {first}"),
        ),
        None => Outcome::new(
            Class::Crash,
            format!("worker exited ({status}) mid-execution: {first}"),
        ),
    }
}
