//! Rust errors as the Python package's exceptions (`flexmbd._errors`): a refused scene or
//! body model, or a refused input of a running simulation, is a `SceneError` (a
//! `ValueError`) with the `file`, `line`, `column`,
//! `field`, `value` and `reason` the Rust error knows (`None` for the others), a failed
//! step, static start or static equilibrium a `RunError` with its `time`, anything else a
//! `FlexmbdError`.

use flexmbd::Error;
use flexmbd::core::InvalidValue;
use flexmbd::fe::FeError;
use flexmbd::model::ModelError;
use pyo3::prelude::*;

/// The attributes of a `SceneError` that a Rust error can fill.
#[derive(Default)]
pub struct SceneFields {
    /// The scene or model file (`<dict>` for a scene given as a dict).
    pub file: Option<String>,
    /// 1-based line of the field in the file.
    pub line: Option<u64>,
    /// 1-based column (parse errors).
    pub column: Option<u64>,
    /// Dotted path of the refused field.
    pub field: Option<String>,
    /// The refused value, as written.
    pub value: Option<String>,
    /// Why it is refused.
    pub reason: Option<String>,
}

impl SceneFields {
    /// The fields of an [`InvalidValue`] in `file` at `line`.
    fn invalid(file: &str, line: Option<u32>, e: &InvalidValue) -> Self {
        SceneFields {
            file: Some(file.to_string()),
            line: line.map(u64::from),
            field: Some(e.field.clone()),
            value: Some(e.value.clone()),
            reason: Some(e.reason.clone()),
            ..Self::default()
        }
    }

    /// The file and position of a parse error; the field where the parser's message
    /// names one (`unknown field `stpe``).
    fn parse(file: &str, line: usize, column: usize, message: &str) -> Self {
        SceneFields {
            file: Some(file.to_string()),
            line: Some(line as u64),
            column: Some(column as u64),
            field: named_field(message),
            reason: Some(message.to_string()),
            ..Self::default()
        }
    }
}

/// The field a serde message names: the first name in backquotes after `field`
/// (`unknown field `stpe`, expected one of …`, `missing field `step``).
pub fn named_field(message: &str) -> Option<String> {
    let rest = &message[message.find("field `")? + "field `".len()..];
    Some(rest[..rest.find('`')?].to_string())
}

/// The fields of a scene refusal.
pub fn model_fields(e: &ModelError) -> SceneFields {
    match e {
        ModelError::Io { file, .. } => SceneFields {
            file: Some(file.clone()),
            ..SceneFields::default()
        },
        ModelError::Parse {
            file,
            line,
            column,
            message,
        } => SceneFields::parse(file, *line, *column, message),
        ModelError::Invalid { file, line, error } => SceneFields::invalid(file, *line, error),
        ModelError::Missing {
            file,
            line,
            item,
            name,
            ..
        } => SceneFields {
            file: Some(file.clone()),
            line: line.map(u64::from),
            field: Some(item.clone()),
            value: Some(name.clone()),
            ..SceneFields::default()
        },
        ModelError::Set { path, message } => SceneFields {
            field: Some(
                path.split_once('=')
                    .map_or(path.as_str(), |(p, _)| p)
                    .to_string(),
            ),
            value: path.split_once('=').map(|(_, v)| v.to_string()),
            reason: Some(message.clone()),
            ..SceneFields::default()
        },
        ModelError::Fe {
            file, line, source, ..
        } => {
            let mut fields = fe_fields(source);
            fields.file = Some(file.clone());
            fields.line = line.map(u64::from);
            fields
        }
        ModelError::Unsupported(_) => SceneFields::default(),
    }
}

/// The fields of a body model's refusal.
pub fn fe_fields(e: &FeError) -> SceneFields {
    match e {
        FeError::Invalid(error) => SceneFields {
            field: Some(error.field.clone()),
            value: Some(error.value.clone()),
            reason: Some(error.reason.clone()),
            ..SceneFields::default()
        },
        FeError::Parse {
            file,
            line,
            column,
            message,
        } => SceneFields::parse(file, *line, *column, message),
        FeError::Io { file, .. } => SceneFields {
            file: Some(file.clone()),
            ..SceneFields::default()
        },
        _ => SceneFields::default(),
    }
}

/// An exception of class `class` of `flexmbd._errors` with `message` and the attributes
/// `attributes` (name, value) set on it.
fn exception<'py>(
    py: Python<'py>,
    class: &str,
    message: &str,
    attributes: &[(&str, Bound<'py, PyAny>)],
) -> PyErr {
    let made = || -> PyResult<PyErr> {
        let class = py.import("flexmbd._errors")?.getattr(class)?;
        let value = class.call1((message,))?;
        for (name, v) in attributes {
            value.setattr(*name, v)?;
        }
        Ok(PyErr::from_value(value))
    };
    made().unwrap_or_else(|e| e)
}

/// A `SceneError` with `message` and `fields`.
pub fn scene_error(py: Python<'_>, message: &str, fields: SceneFields) -> PyErr {
    let attributes = [
        ("file", fields.file.into_pyobject(py)),
        ("line", fields.line.into_pyobject(py)),
        ("column", fields.column.into_pyobject(py)),
        ("field", fields.field.into_pyobject(py)),
        ("value", fields.value.into_pyobject(py)),
        ("reason", fields.reason.into_pyobject(py)),
    ];
    let attributes: Vec<(&str, Bound<'_, PyAny>)> = attributes
        .into_iter()
        .map(|(name, v)| (name, v.expect("an Option<String or u64> converts")))
        .collect();
    exception(py, "SceneError", message, &attributes)
}

/// The refusal of a scene.
pub fn model_error(py: Python<'_>, e: &ModelError) -> PyErr {
    scene_error(py, &e.to_string(), model_fields(e))
}

/// Any error of the facade as the package's exception.
pub fn to_py(py: Python<'_>, e: &Error) -> PyErr {
    match e {
        Error::Model(model) => model_error(py, model),
        Error::Fe(fe) => scene_error(py, &e.to_string(), fe_fields(fe)),
        Error::Input(refused) => scene_error(
            py,
            &e.to_string(),
            SceneFields {
                field: Some(refused.field.clone()),
                value: Some(refused.value.clone()),
                reason: Some(refused.reason.clone()),
                ..SceneFields::default()
            },
        ),
        // A failed pilot run of proper orthogonal modes: the scene is valid, its run failed
        // (no time: the run took no step; the pilot's is in the message).
        Error::Pilot(_) => run_error(py, &e.to_string(), None),
        Error::Static(_) | Error::Integrator(_) => run_error(
            py,
            &e.to_string(),
            e.failed_at()
                .or(matches!(e, Error::Static(_)).then_some(0.0)),
        ),
        _ => exception(py, "FlexmbdError", &e.to_string(), &[]),
    }
}

/// A `RunError` with `message` and `time` (s; `None` when the failure has no time).
pub fn run_error(py: Python<'_>, message: &str, time: Option<f64>) -> PyErr {
    let time = time.into_pyobject(py).expect("an Option<f64> converts");
    exception(py, "RunError", message, &[("time", time)])
}

/// An error of the static equilibrium or of the linearised vibration of the scene from
/// `origin`: no equilibrium found, or no modes computed, is a `RunError` at t = 0 naming
/// the scene (as `flexmbd equilibrium` and `flexmbd eigen` report it); a refusal is a
/// `SceneError`, as for any run ([`to_py`]).
pub fn static_error(py: Python<'_>, origin: &str, e: &Error) -> PyErr {
    match e {
        Error::Static(s) => run_error(
            py,
            &format!("{origin}: no static equilibrium: {s}"),
            Some(0.0),
        ),
        Error::Vibration(v) => run_error(py, &format!("{origin}: {v}"), Some(0.0)),
        _ => to_py(py, e),
    }
}
