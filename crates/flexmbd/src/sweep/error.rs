//! Why a sweep or a tuning was refused before (or instead of) running.

use flexmbd_model::ModelError;

/// A sweep's input refused, or its reference run failed.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The scene, or a base `--set`, was refused (names file, line, field).
    #[error(transparent)]
    Scene(Box<ModelError>),
    /// A judged sensor that the scene does not have.
    #[error("{scene}: no sensor `{sensor}` (sensors: {known})")]
    UnknownSensor {
        /// The scene file.
        scene: String,
        /// The sensor asked for.
        sensor: String,
        /// The scene's sensors, comma-separated.
        known: String,
    },
    /// No sensor to judge.
    #[error("no sensor to judge: name at least one")]
    NoSensor,
    /// The reference table was refused: unreadable, a missing column, times out of order,
    /// a value that is not a finite number, too short for the run.
    #[error("reference {origin}{}: {message}", line.map_or(String::new(), |l| format!(":{l}")))]
    Reference {
        /// The reference file (or label).
        origin: String,
        /// The line, where one is to blame.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// The scene's own converged run (the reference) failed.
    #[error("the converged reference run ({label}) failed: {message}")]
    ReferenceRun {
        /// The grid point of the run.
        label: String,
        /// Why it failed.
        message: String,
    },
    /// An axis of the grid was refused (empty, a bad value, a body that is no flexible
    /// beam).
    #[error("grid axis `{axis}`: {message}")]
    Grid {
        /// The axis (`grid` for the whole grid).
        axis: String,
        /// What is wrong.
        message: String,
    },
    /// The stop flag ended the sweep while its converged reference ran: no run of the grid
    /// was made.
    #[error("interrupted while the converged reference ran ({label}): no run of the grid was made")]
    Interrupted {
        /// The grid point of the reference run.
        label: String,
    },
    /// A tolerance that is not a positive finite number.
    #[error("tolerance {0}: must be a positive finite number")]
    Tolerance(f64),
}
