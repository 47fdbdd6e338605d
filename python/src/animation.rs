//! The animation of a finished run (`flexmbd_viewer`): the frames that
//! [`crate::run::simulate`] recorded while the run went on (`flexmbd_viewer::Recorder`, the
//! bodies' poses and modal coordinates at most `animation_fps` times per simulated second,
//! at the run's own rows), kept with the scene they belong to, and rendered on demand as the
//! glTF binary or the self-contained page that `flexmbd animate` writes.

use flexmbd::model::Scene;
use flexmbd_viewer::{Format, Recording, check_scale, render};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// A run's recorded frames and its scene.
#[pyclass(name = "Animation", module = "flexmbd._native", frozen)]
pub struct PyAnimation {
    pub(crate) recording: Recording,
    pub(crate) scene: Scene,
}

#[pymethods]
impl PyAnimation {
    /// The bytes of the animation as `format` (`"glb"` or `"html"`), the deformation drawn
    /// `scale` times; a format or a scale that is not one is refused (`ValueError`).
    fn render<'py>(
        &self,
        py: Python<'py>,
        format: &str,
        scale: f64,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let format = match format {
            "glb" => Format::Glb,
            "html" => Format::Html,
            other => {
                return Err(PyValueError::new_err(format!(
                    "animation format {other:?}: \"glb\" (glTF binary) or \"html\" (web page)"
                )));
            }
        };
        let scale = check_scale(scale).map_err(PyValueError::new_err)?;
        let bytes = py.detach(|| render(&self.recording, &self.scene, format, scale));
        Ok(PyBytes::new(py, &bytes))
    }

    /// The frames' times (s).
    #[getter]
    fn times(&self) -> Vec<f64> {
        self.recording.times.clone()
    }

    /// The number of bodies drawn.
    #[getter]
    fn n_bodies(&self) -> usize {
        self.recording.bodies.len()
    }
}
