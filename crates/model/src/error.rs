//! Errors of scene loading: each names the file and the item or field, and the validation
//! errors the line of the field where it can be found in the file ([`crate::lines`]).

use flexmbd_core::InvalidValue;
use flexmbd_fe::FeError;

/// Why a scene was refused.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The file could not be read.
    #[error("cannot read {file}: {source}")]
    Io {
        /// The file.
        file: String,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// RON syntax or schema error (misspelt field, wrong type).
    #[error("{file}:{line}:{column}: {message}")]
    Parse {
        /// The file.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong (names the field).
        message: String,
    },
    /// A value is not physical or not consistent.
    #[error("{}: {error}", at(.file, *.line))]
    Invalid {
        /// The file.
        file: String,
        /// 1-based line of the field in the file, when it was found there.
        line: Option<u32>,
        /// Field path, value and reason.
        error: InvalidValue,
    },
    /// An item names another that does not exist.
    #[error("{}: {item} names {kind} `{name}`, which does not exist{hint}", at(.file, *.line))]
    Missing {
        /// The file.
        file: String,
        /// 1-based line of the referring field in the file, when it was found there.
        line: Option<u32>,
        /// The referring field (e.g. `joints[A0].body2`).
        item: String,
        /// What kind of thing was named (body, marker, joint).
        kind: &'static str,
        /// The missing name.
        name: String,
        /// The known names, if few.
        hint: String,
    },
    /// A `--set PATH=VALUE` override could not be applied.
    #[error("--set {path}: {message}")]
    Set {
        /// The path given.
        path: String,
        /// Why.
        message: String,
    },
    /// A flexible body's FE model was refused.
    #[error("{}: body `{body}`: {source}", at(.file, *.line))]
    Fe {
        /// The file.
        file: String,
        /// 1-based line of the refused field in the file, when it was found there.
        line: Option<u32>,
        /// The body.
        body: String,
        /// The cause (boxed: FE errors carry a lot of context).
        #[source]
        source: Box<FeError>,
    },
    /// The requested formulation or option cannot run this scene.
    #[error("{0}")]
    Unsupported(String),
}

/// `file:line`, or `file` when the line is not known.
fn at(file: &str, line: Option<u32>) -> String {
    match line {
        Some(l) => format!("{file}:{l}"),
        None => file.to_string(),
    }
}
