//! The error type of FE preprocessing.
//!
//! Every variant names the input it refers to (the spec's origin, a file, a
//! field path), following the architecture rule "every public function that can
//! fail on user input returns a `Result` with an error that names the input".

use flexmbd_core::InvalidValue;

/// Why FE preprocessing refused a model.
#[derive(Debug, thiserror::Error)]
pub enum FeError {
    /// A value of the model is not physical or not consistent (names the field and value).
    #[error(transparent)]
    Invalid(#[from] InvalidValue),

    /// The RON text could not be parsed into a [`crate::BeamBodySpec`].
    #[error("{file}:{line}:{column}: {message}")]
    Parse {
        /// File (or origin name) of the text.
        file: String,
        /// 1-based line of the error.
        line: usize,
        /// 1-based column of the error.
        column: usize,
        /// The parser's message (names the offending field where serde knows it).
        message: String,
    },

    /// A model file could not be read.
    #[error("cannot read {file}: {source}")]
    Io {
        /// The file.
        file: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },

    /// The interior stiffness K_ii of the Craig–Bampton split is singular: the
    /// frame DOFs together with the boundary DOFs do not hold all rigid motion
    /// (docs/methods.md §1.4).
    #[error(
        "{spec}: interior stiffness K_ii is singular ({detail}); the frame DOFs {frame} \
         do not remove all rigid-body motion (methods.md §1.4: the r set must be an isostatic support)"
    )]
    SingularInterior {
        /// The spec's origin name.
        spec: String,
        /// The frame (reference) DOFs, formatted.
        frame: String,
        /// Which pivot failed and by how much.
        detail: String,
    },

    /// The reduced stiffness K_ff has an eigenvalue ≤ 0: a static mode is a
    /// rigid-body motion (docs/methods.md §1.4, "Pitfall").
    #[error(
        "{spec}: reduced stiffness K_ff has eigenvalue {eigenvalue:e} <= 0 (largest {largest:e}); \
         the frame DOFs {frame} do not hold all rigid-body motion, so a static mode moves the body rigidly \
         (methods.md §1.4, Pitfall)"
    )]
    RigidStaticMode {
        /// The spec's origin name.
        spec: String,
        /// The frame (reference) DOFs, formatted.
        frame: String,
        /// The smallest eigenvalue of K_ff.
        eigenvalue: f64,
        /// The largest eigenvalue of K_ff.
        largest: f64,
    },

    /// More normal modes were requested than the (interior) model has DOFs.
    #[error("{requested} normal modes requested, but the model has only {available} interior DOFs")]
    TooManyModes {
        /// Requested number of modes.
        requested: usize,
        /// Number of DOFs available.
        available: usize,
    },

    /// A matrix that must be symmetric positive definite is not (e.g. a mass matrix).
    #[error("{what} is not positive definite (pivot {pivot} failed)")]
    NotPositiveDefinite {
        /// Which matrix.
        what: String,
        /// Index of the failing pivot.
        pivot: usize,
    },

    /// The dense symmetric eigensolver did not converge.
    #[error("eigensolver did not converge on {what}")]
    EigenNoConvergence {
        /// Which problem.
        what: String,
    },

    /// An FE export (crate::import) is malformed at one line: names the file, the
    /// 1-based line, the field and what was found.
    #[error("{file}:{line}: {field}: {message}")]
    Format {
        /// The file (or the name given to the text).
        file: String,
        /// 1-based line of the offence.
        line: usize,
        /// Which field of the line (or which keyword) is wrong.
        field: String,
        /// What was found and what was expected.
        message: String,
    },

    /// An FE export (crate::import) is well formed but not a usable model: a matrix
    /// that is not symmetric, a mass diagonal that is not positive, a DOF map that does
    /// not match the matrix size, an unknown node. Names the file and the quantity.
    #[error("{file}: {field}: {message}")]
    Import {
        /// The file (or files) the quantity came from.
        file: String,
        /// Which quantity is wrong (e.g. `K[12, 40]`, `point_masses[0].node`).
        field: String,
        /// What is wrong, with the values.
        message: String,
    },

    /// Matrix sizes do not agree.
    #[error("{what}: dimension mismatch ({detail})")]
    Dimension {
        /// Which operation.
        what: String,
        /// The sizes.
        detail: String,
    },

    // --- the sparse eigen-solver (crate::sparse, crate::sparse_eigen) ---
    /// A matrix that must be symmetric is not, or holds a value that is not finite.
    #[error("{what} is not symmetric: entry ({row}, {col}): {detail}")]
    NotSymmetric {
        /// Which matrix.
        what: String,
        /// Row of the offending entry.
        row: usize,
        /// Column of the offending entry.
        col: usize,
        /// The values found.
        detail: String,
    },

    /// The shifted pencil K − σM could not be factorised: with σ < 0 it is positive
    /// definite whenever K is positive semi-definite and M positive definite.
    #[error(
        "K - sigma M with shift sigma = {shift:e} is not positive definite (pivot {pivot} of the \
         permuted matrix failed): K must be positive semi-definite and M positive definite"
    )]
    ShiftedNotPositiveDefinite {
        /// The shift σ.
        shift: f64,
        /// Index of the failing pivot, in faer's fill-reducing order.
        pivot: usize,
    },

    /// The sparse eigen-solver did not converge within its bound on restarts.
    #[error(
        "sparse eigen-solver: {converged} of {requested} eigenpairs converged to {tol:e} after \
         {restarts} restarts ({solves} solves); raise max_restarts or the basis size"
    )]
    SparseEigenNoConvergence {
        /// Eigenpairs converged.
        converged: usize,
        /// Eigenpairs requested.
        requested: usize,
        /// The bound on the backward error of each pair.
        tol: f64,
        /// Restarts done.
        restarts: usize,
        /// Solves with the factor done.
        solves: usize,
    },
}
