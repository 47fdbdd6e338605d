//! `Scene`: a scene loaded from a RON file or from JSON (a Python dict), validated as the
//! `flexmbd` program validates it; `--set`-style overrides, the `simulate` options, and the
//! scene as RON or JSON text.

use flexmbd::body::InertiaMethod;
use flexmbd::fe::BeamBodySpec;
use flexmbd::model::{FormulationKind, ModelError, Scene, Stiffening, parse_set};
use pyo3::prelude::*;

use crate::errors::{SceneFields, model_error, model_fields, named_field, scene_error};

/// The origin a scene given as a dict is named by in errors.
const DICT_ORIGIN: &str = "<dict>";

/// A validated scene (the Rust `flexmbd::model::Scene`).
#[pyclass(name = "Scene", module = "flexmbd._native")]
#[derive(Clone)]
pub struct PyScene {
    /// The scene.
    pub scene: Scene,
}

/// Read, parse and validate the scene file at `path`. A body model (the input of
/// `modes`) is refused with a message that says so, as `flexmbd simulate` does.
#[pyfunction]
pub fn load_file(py: Python<'_>, path: &str) -> PyResult<PyScene> {
    match Scene::load(path) {
        Ok(scene) => Ok(PyScene { scene }),
        Err(e) => {
            let is_body_model = std::fs::read_to_string(path)
                .is_ok_and(|text| BeamBodySpec::from_ron_str(&text, path).is_ok());
            if is_body_model {
                let message = format!(
                    "{path}: this is a body model, not a scene (`flexmbd.modes(\"{path}\")` reads it; a scene lists bodies, joints and a solver)"
                );
                let fields = SceneFields {
                    file: Some(path.to_string()),
                    ..SceneFields::default()
                };
                Err(scene_error(py, &message, fields))
            } else {
                Err(model_error(py, &e))
            }
        }
    }
}

/// Parse and validate a scene from JSON text in the shape the RON scene has (structs as
/// objects, enums externally tagged: `{"Beam": {...}}`); errors name `<dict>` and the
/// dotted path of the refused field.
#[pyfunction]
pub fn from_json(py: Python<'_>, text: &str) -> PyResult<PyScene> {
    let deserializer = &mut serde_json::Deserializer::from_str(text);
    let mut scene: Scene = serde_path_to_error::deserialize(deserializer).map_err(|e| {
        let path = e.path().to_string();
        // serde_json's position in the JSON text means nothing to the dict's author.
        let inner = e.inner().to_string();
        let inner = match inner.rfind(" at line ") {
            Some(at) => inner[..at].to_string(),
            None => inner,
        };
        let field = match named_field(&inner) {
            Some(name) if path == "." || path.is_empty() => name,
            Some(name) if !path.ends_with(&name) => format!("{path}.{name}"),
            _ => path.clone(),
        };
        let message = format!("{DICT_ORIGIN}: {field}: {inner}");
        let fields = SceneFields {
            file: Some(DICT_ORIGIN.into()),
            field: Some(field),
            reason: Some(inner),
            ..SceneFields::default()
        };
        scene_error(py, &message, fields)
    })?;
    scene.origin = DICT_ORIGIN.into();
    scene.validate().map_err(|e| model_error(py, &e))?;
    Ok(PyScene { scene })
}

/// A `SceneError` for a `simulate` option `name` that does not hold one of `expected`.
fn bad_option(py: Python<'_>, name: &str, value: &str, expected: &str) -> PyErr {
    let reason = format!("expected {expected}");
    scene_error(
        py,
        &format!("{name}={value}: {reason}"),
        SceneFields {
            field: Some(name.into()),
            value: Some(value.into()),
            reason: Some(reason),
            ..SceneFields::default()
        },
    )
}

/// The stiffening method named as `flexmbd simulate --stiffening` names it.
fn parse_stiffening(py: Python<'_>, s: &str) -> PyResult<Stiffening> {
    const EXPECTED: &str = "linear, fnl1, fnl2, foreshortening or substructuring:N";
    Ok(match s {
        "linear" => Stiffening::Linear,
        "fnl1" => Stiffening::Fnl1,
        "fnl2" => Stiffening::Fnl2,
        "foreshortening" | "fs0" => Stiffening::Foreshortening,
        _ => match s.strip_prefix("substructuring:").map(str::parse) {
            Some(Ok(n)) => Stiffening::Substructuring(n),
            _ => return Err(bad_option(py, "stiffening", s, EXPECTED)),
        },
    })
}

#[pymethods]
impl PyScene {
    /// The scene's name.
    #[getter]
    fn name(&self) -> String {
        self.scene.name.clone()
    }

    /// The file the scene was read from (`<dict>` for a dict).
    #[getter]
    fn origin(&self) -> String {
        self.scene.origin.clone()
    }

    /// Apply `PATH=VALUE` overrides (all parsed first, then applied, then the scene
    /// validated again), as `flexmbd simulate --set` does; on error the scene is unchanged.
    fn set_all(&mut self, py: Python<'_>, sets: Vec<String>) -> PyResult<()> {
        let parsed = sets
            .iter()
            .map(|s| parse_set(s))
            .collect::<Result<Vec<_>, ModelError>>()
            .map_err(|e| model_error(py, &e))?;
        self.scene.apply_sets(&parsed).map_err(|e| {
            let mut fields = model_fields(&e);
            if let ModelError::Set { path, .. } = &e {
                // The refused value is the one this override gives the field.
                let given = parsed.iter().find(|(p, _)| p == path);
                fields.value = fields.value.or(given.map(|(_, v)| v.clone()));
            }
            scene_error(py, &e.to_string(), fields)
        })
    }

    /// The options of `flexmbd simulate` (each `None` keeps the scene's), applied after
    /// the overrides as the program applies them; the scene is validated afterwards.
    #[pyo3(signature = (formulation=None, inertia=None, stiffening=None, step=None, duration=None))]
    fn set_options(
        &mut self,
        py: Python<'_>,
        formulation: Option<&str>,
        inertia: Option<&str>,
        stiffening: Option<&str>,
        step: Option<f64>,
        duration: Option<f64>,
    ) -> PyResult<()> {
        let mut scene = self.scene.clone();
        let solver = &mut scene.solver;
        if let Some(f) = formulation {
            solver.formulation = match f {
                "absolute" => FormulationKind::Absolute,
                "relative" => FormulationKind::Relative,
                _ => return Err(bad_option(py, "formulation", f, "absolute or relative")),
            };
        }
        if let Some(i) = inertia {
            solver.inertia = match i {
                "b-matrix" => InertiaMethod::BMatrix,
                "shape-integrals" => InertiaMethod::ShapeIntegrals,
                _ => {
                    return Err(bad_option(py, "inertia", i, "b-matrix or shape-integrals"));
                }
            };
        }
        if let Some(s) = stiffening {
            solver.stiffening = parse_stiffening(py, s)?;
        }
        if let Some(h) = step {
            solver.step = h;
        }
        if let Some(d) = duration {
            solver.duration = d;
        }
        scene.validate().map_err(|e| model_error(py, &e))?;
        self.scene = scene;
        Ok(())
    }

    /// The scene as RON text (loads back to the same scene).
    fn to_ron(&self) -> PyResult<String> {
        ron::ser::to_string_pretty(&self.scene, ron::ser::PrettyConfig::default())
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))
    }

    /// The scene as JSON text (the shape `from_json` reads).
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.scene)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))
    }

    /// A copy.
    fn copy(&self) -> PyScene {
        self.clone()
    }
}
