//! `flexmbd._native`, the Rust half of the Python package `flexmbd`: scenes loaded from a
//! file or from JSON (the Python package turns a dict into it), `--set`-style overrides,
//! whole runs with the GIL released, a stepping simulation with checkpoints, the static
//! equilibrium and the linearised free vibration of a scene, the mode inventory of a
//! body model, and the animation of a run (its frames recorded as it runs). The Python
//! package (`python/flexmbd/`) wraps these in documented classes that hand out NumPy
//! arrays; errors are raised as its exception classes (`flexmbd._errors`), filled from the
//! Rust errors' fields ([`errors`]).
//!
//! Built with maturin as an abi3 wheel (one wheel for CPython 3.9 and later); see
//! `docs/design.md`, "The Python package".

use pyo3::prelude::*;

mod animation;
mod errors;
mod interrupt;
mod run;
mod scene;
mod stepping;

/// The extension module: its classes and functions.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scene::PyScene>()?;
    m.add_class::<stepping::PySimulation>()?;
    m.add_class::<stepping::PyCheckpoint>()?;
    m.add_class::<animation::PyAnimation>()?;
    m.add_function(wrap_pyfunction!(scene::load_file, m)?)?;
    m.add_function(wrap_pyfunction!(scene::from_json, m)?)?;
    m.add_function(wrap_pyfunction!(run::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(run::equilibrium, m)?)?;
    m.add_function(wrap_pyfunction!(run::eigen, m)?)?;
    m.add_function(wrap_pyfunction!(run::modes, m)?)?;
    Ok(())
}
