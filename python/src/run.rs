//! Whole runs, the static equilibrium, the linearised free vibration and the mode
//! inventory, with the GIL released while Rust computes.

use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::channel;

use flexmbd::History;
use flexmbd::fe::FeError;
use flexmbd::inventory::{BodyModelFile, Inventory};
use flexmbd::simulation;
use flexmbd_viewer::Recorder;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::animation::PyAnimation;
use crate::errors::{SceneFields, fe_fields, scene_error, static_error, to_py};
use crate::interrupt::wait_for_answer;
use crate::scene::PyScene;

/// Values as their native-endian bytes, for `numpy.frombuffer` (no rounding: the bits).
fn as_bytes(values: impl Iterator<Item = f64>) -> Vec<u8> {
    values.flat_map(f64::to_ne_bytes).collect()
}

/// Run `scene` to its duration as `flexmbd simulate` does (`simulation::run_into`), on a
/// thread of its own with the GIL released. Returns the summary as the program's `--json`
/// text, the columns (`t`, then the sensors), the rows as the bytes of a row-major float64
/// array, the number of rows, and the exception a signal handler raised during the run
/// (`None` if none did): Ctrl-C stops the run between two steps (`status = "interrupted"`,
/// the rows so far kept) and its KeyboardInterrupt comes back here for the package to
/// raise with the rows (`crate::interrupt`). A failed step is not an exception: the summary
/// says `failed` and the rows stop there. Refusals before the run raise.
///
/// With `animation_fps`, the run's animation frames are recorded as it goes
/// (`flexmbd_viewer::Recorder`: the bodies' poses at the first row at or past each
/// 1 / `animation_fps` s, reading the state only, so the rows are the same bits) and
/// returned as an [`Animation`](crate::animation::PyAnimation) (`None` without, or when the
/// run wrote no row); a rate that is not positive and finite is refused before the run.
#[pyfunction]
#[pyo3(signature = (scene, animation_fps=None))]
pub fn simulate<'py>(
    py: Python<'py>,
    scene: &PyScene,
    animation_fps: Option<f64>,
) -> PyResult<Simulated<'py>> {
    let scene = scene.scene.clone();
    if let Some(fps) = animation_fps {
        Recorder::new(&scene, fps).map_err(|e| to_py(py, &e))?;
    }
    let stop = AtomicBool::new(false);
    let (answer, answers) = channel();
    let answers = Mutex::new(answers);
    let (outcome, raised) = std::thread::scope(|threads| {
        let (scene, stop) = (&scene, &stop);
        threads.spawn(move || {
            let mut history = History::default();
            let mut recorder = animation_fps.and_then(|fps| Recorder::new(scene, fps).ok());
            let outcome = simulation::run_observed(scene, &mut history, stop, |_| {}, &mut |sim| {
                if let Some(recorder) = recorder.as_mut() {
                    recorder.observe(sim);
                }
            });
            let outcome = outcome.map(|summary| {
                let recording = recorder.and_then(|r| r.finish(&summary));
                (summary, history, recording)
            });
            let _ = answer.send(outcome);
        });
        wait_for_answer(py, &answers, || stop.store(true, Ordering::Relaxed))
    });
    let outcome = match (outcome, raised) {
        (Some(Ok(outcome)), raised) => (outcome, raised),
        (_, Some(raised)) => return Err(raised),
        (Some(Err(e)), None) => return Err(to_py(py, &e)),
        (None, None) => {
            return Err(PyRuntimeError::new_err(
                "the run's thread ended without an answer",
            ));
        }
    };
    let ((summary, history, recording), raised) = outcome;
    let summary_json =
        serde_json::to_string(&summary).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let rows = history.rows.len();
    let bytes = as_bytes(history.rows.iter().flatten().copied());
    let raised = raised.map(|e| e.into_value(py).into_bound(py).into_any());
    let animation = recording
        .map(|recording| Bound::new(py, PyAnimation { recording, scene }))
        .transpose()?;
    Ok((
        summary_json,
        history.header,
        PyBytes::new(py, &bytes),
        rows,
        raised,
        animation,
    ))
}

/// What [`simulate`] returns: summary, columns, rows (bytes), row count, the exception a
/// signal handler raised during the run, the recorded animation.
type Simulated<'py> = (
    String,
    Vec<String>,
    Bound<'py, PyBytes>,
    usize,
    Option<Bound<'py, PyAny>>,
    Option<Bound<'py, PyAnimation>>,
);

/// The static equilibrium of `scene` at t = 0 as JSON text (the `--json` output of
/// `flexmbd equilibrium`), solved with the GIL released. No equilibrium found raises
/// `RunError`.
#[pyfunction]
pub fn equilibrium(py: Python<'_>, scene: &PyScene) -> PyResult<String> {
    let scene = scene.scene.clone();
    let solved = py.detach(|| flexmbd::equilibrium(&scene));
    let equilibrium = solved.map_err(|e| static_error(py, &scene.origin, &e))?;
    serde_json::to_string(&equilibrium).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// The linearised free vibration of `scene` about its static equilibrium as JSON text (the
/// `--json` output of `flexmbd eigen`), solved with the GIL released. No equilibrium found,
/// or no modes computed, raises `RunError`.
#[pyfunction]
pub fn eigen(py: Python<'_>, scene: &PyScene) -> PyResult<String> {
    let scene = scene.scene.clone();
    let solved = py.detach(|| flexmbd::vibration(&scene));
    let vibration = solved.map_err(|e| static_error(py, &scene.origin, &e))?;
    serde_json::to_string(&vibration).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// The mode inventory of the body model at `path` as JSON text (the `--json` output of
/// `flexmbd modes`), reduced with the GIL released.
#[pyfunction]
pub fn modes(py: Python<'_>, path: &str) -> PyResult<String> {
    let file = Path::new(path);
    let text = std::fs::read_to_string(file).map_err(|source| {
        let e = FeError::Io {
            file: path.to_string(),
            source,
        };
        scene_error(py, &e.to_string(), file_fields(path, &e))
    })?;
    let spec = BodyModelFile::parse(&text, file)
        .map_err(|e| scene_error(py, &e.to_string(), file_fields(path, &e)))?;
    let body = py
        .detach(|| spec.reduce(file))
        .map_err(|e| scene_error(py, &format!("{path}: {e}"), file_fields(path, &e)))?;
    let inventory = Inventory::of(path, &body);
    serde_json::to_string(&inventory).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// The fields of a body model's refusal, naming `path` when the error does not.
fn file_fields(path: &str, e: &FeError) -> SceneFields {
    let mut fields = fe_fields(e);
    fields.file.get_or_insert_with(|| path.to_string());
    fields
}
