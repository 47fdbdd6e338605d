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
    /// Reading or writing a file failed.
    #[error(transparent)]
    Io(#[from] std::io::Error),
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

impl Error {
    /// The time of the step that failed (s), for a failed time step; `None` otherwise.
    pub fn failed_at(&self) -> Option<f64> {
        match self {
            Error::Integrator(
                IntegratorError::NoConvergence { t, .. }
                | IntegratorError::Diverged { t }
                | IntegratorError::Singular { t, .. },
            ) => Some(*t),
            _ => None,
        }
    }
}
