//! The one error of the facade: every failure a library user can meet, from reading a body
//! model to a time step that does not converge, with the lower crates' errors kept whole
//! (their data, not their message) so a program can match on them.

use flexmbd_fe::FeError;
use flexmbd_integrators::{IntegratorError, StaticError, VibrationError};
use flexmbd_model::ModelError;

/// Why flexmbd could not load, compile, start or advance a simulation.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene was refused: unreadable, malformed, inconsistent, or a formulation cannot
    /// run it (names the file, line, item and field). Boxed: a scene error carries its
    /// file, field and names, and the error of every step need not be that large.
    #[error(transparent)]
    Model(Box<ModelError>),
    /// FE preprocessing refused a body model (e.g. [`crate::fe::reduce`] of a model file).
    #[error(transparent)]
    Fe(#[from] FeError),
    /// No static equilibrium was found for a scene that asks to start in one
    /// (`solver.initial_state: StaticEquilibrium`).
    #[error("static start: {0}")]
    Static(#[from] StaticError),
    /// The linearised vibration about the static equilibrium could not be computed
    /// ([`crate::vibration()`]).
    #[error("linearised vibration: {0}")]
    Vibration(#[from] VibrationError),
    /// ALI3-P could not make the initial conditions consistent, or a step failed (the
    /// variants of a step carry its time `t`; see [`Error::failed_at`]).
    #[error(transparent)]
    Integrator(#[from] IntegratorError),
    /// A value a host handed a running simulation was refused: an unknown input or sensor,
    /// an input's values out of range, a state that violates the constraints
    /// ([`crate::simulation::host`]). Names the field, the value and the reason.
    #[error("refused: {0}")]
    Input(flexmbd_core::InvalidValue),
    /// The pilot run of a scene's proper orthogonal modes (`mode_selection:
    /// ProperOrthogonal`, [`crate::simulation`]) failed or was stopped, so the scene, valid,
    /// could not be prepared: a failure of the run, not a refusal of the input. Boxed, as
    /// [`Error::Model`] is.
    #[error(transparent)]
    Pilot(#[from] Box<PilotError>),
    /// Reading or writing a file failed.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// A sensor read a value that is not finite at an output row: the run fails there, the
    /// rows before it kept (a step can end in a finite state whose energy or a force
    /// overflows).
    #[error(
        "sensor `{sensor}` is not finite ({value}) at t = {t:.6} s: the motion left what the model can represent; try a smaller step"
    )]
    NonFiniteSensor {
        /// Time of the row (s).
        t: f64,
        /// The sensor's name.
        sensor: String,
        /// Its value.
        value: f64,
    },
    /// Writing a run's output (a [`crate::output::RowSink`] streaming to `path`) failed.
    #[error("cannot write {}: {source}", path.display())]
    Output {
        /// The output file.
        path: std::path::PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// A run to the scene's duration would keep more rows in memory (a
    /// [`crate::History`]) than [`crate::output::HISTORY_MEMORY_LIMIT`] allows.
    #[error(
        "the run's in-memory history would hold {rows} rows × {columns} columns × 8 bytes = {bytes} bytes ({:.1} GiB), more than the limit of {} GiB: raise solver.output_interval, shorten solver.duration, or stream the rows (`flexmbd simulate --output`, `simulation::run_into`)",
        *bytes as f64 / (1u64 << 30) as f64,
        crate::output::HISTORY_MEMORY_LIMIT >> 30
    )]
    HistoryTooLarge {
        /// Rows the run would record.
        rows: usize,
        /// Columns of a row (t and the sensors).
        columns: usize,
        /// rows × columns × 8.
        bytes: u128,
    },
}

impl From<ModelError> for Error {
    fn from(error: ModelError) -> Self {
        Error::Model(Box::new(error))
    }
}

/// A pilot run of proper orthogonal modes that gave no record ([`Error::Pilot`]): the
/// body whose `mode_selection` asked for it (the first of the bodies that share the
/// pilot), where the scene names it, and what stopped the pilot.
#[derive(Debug, thiserror::Error)]
#[error(
    "{}: body `{body}`: mode_selection = ProperOrthogonal: the pilot run of the proper orthogonal modes (bodies {} on their lowest normal modes, {duration} s) {outcome}",
    at(.file, *.line),
    .bodies.join(", ")
)]
pub struct PilotError {
    /// The scene's file.
    pub file: String,
    /// 1-based line of the body's `mode_selection` in the file, when it is written there.
    pub line: Option<u32>,
    /// The first body that asked for the pilot.
    pub body: String,
    /// Every body that shares the pilot.
    pub bodies: Vec<String>,
    /// How long the pilot was to run (s).
    pub duration: f64,
    /// What stopped it.
    #[source]
    pub outcome: PilotOutcome,
}

impl PilotError {
    /// Whether the pilot was stopped by the caller's stop flag rather than failing.
    pub fn interrupted(&self) -> bool {
        matches!(self.outcome, PilotOutcome::Interrupted { .. })
    }
}

/// Why a pilot run gave no record ([`PilotError`]).
#[derive(Debug, thiserror::Error)]
pub enum PilotOutcome {
    /// It could not start, or a step failed: the pilot's own error (time, residual, hint).
    #[error("failed: {0}")]
    Failed(#[source] Error),
    /// A modal coordinate of its record is not finite.
    #[error("failed: a modal coordinate is {0}")]
    NotFinite(f64),
    /// The stop flag was set: the pilot ended between two steps, its record dropped.
    #[error(
        "was interrupted at t = {t} s of the pilot, after {done} of {steps} steps; the run did not start"
    )]
    Interrupted {
        /// The pilot's time when it stopped (s).
        t: f64,
        /// The pilot steps taken.
        done: usize,
        /// The pilot steps it was to take.
        steps: usize,
    },
}

/// `file:line`, or `file` when the line is not known.
fn at(file: &str, line: Option<u32>) -> String {
    match line {
        Some(l) => format!("{file}:{l}"),
        None => file.to_string(),
    }
}

impl Error {
    /// The time of the step that failed (s), for a failed time step; `None` otherwise.
    pub fn failed_at(&self) -> Option<f64> {
        match self {
            Error::Integrator(
                IntegratorError::NoConvergence { t, .. }
                | IntegratorError::Diverged { t }
                | IntegratorError::Singular { t, .. },
            ) => Some(*t),
            Error::NonFiniteSensor { t, .. } => Some(*t),
            _ => None,
        }
    }
}
