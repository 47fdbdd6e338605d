//! `Simulation`: a scene under way, stepped by the host — one step, or to a time; the
//! sensors read between steps; checkpoints to return to.
//!
//! The Rust `Simulation` is not `Send` (its formulation is a trait object without that
//! bound), so the class is `unsendable`: it is used from the thread that made it, and a
//! step holds the GIL (one step is short; whole runs, `simulate`, release it).
//!
//! Inputs between steps (driver values, external forces, parameters: issue 15 item 2) are
//! not in the Rust API yet, so not here either.

use std::sync::atomic::{AtomicU64, Ordering};

use flexmbd::Simulation;
use flexmbd::integrators::Checkpoint;
use pyo3::exceptions::{PyKeyError, PyValueError};
use pyo3::prelude::*;

use crate::errors::to_py;
use crate::scene::PyScene;

/// The identity of the next simulation made, so that a checkpoint is restored only into
/// the simulation it was taken from (the Rust restore panics on another size).
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

/// A stepping simulation of a scene, at t = 0 in consistent initial conditions when made.
#[pyclass(name = "Simulation", module = "flexmbd._native", unsendable)]
pub struct PySimulation {
    simulation: Simulation,
    id: u64,
    /// A buffer for the sensors, allocated once.
    sensors: Vec<f64>,
}

/// A saved state of one simulation (time, positions, velocities, accelerations,
/// multipliers and the integrator's history).
#[pyclass(name = "Checkpoint", module = "flexmbd._native", frozen)]
pub struct PyCheckpoint {
    checkpoint: Checkpoint,
    simulation: u64,
    time: f64,
}

#[pymethods]
impl PyCheckpoint {
    /// The time of the saved state (s).
    #[getter]
    fn time(&self) -> f64 {
        self.time
    }
}

#[pymethods]
impl PySimulation {
    /// Compile `scene`, find its static equilibrium if it asks for one, and make the
    /// initial conditions consistent.
    #[new]
    fn new(py: Python<'_>, scene: &PyScene) -> PyResult<Self> {
        let simulation = Simulation::new(&scene.scene).map_err(|e| to_py(py, &e))?;
        let sensors = vec![0.0; simulation.sensor_names().len()];
        Ok(PySimulation {
            simulation,
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            sensors,
        })
    }

    /// Advance one time step; a failed step raises `RunError` (with its `time`) and leaves
    /// the simulation at its last good state.
    fn step(&mut self, py: Python<'_>) -> PyResult<()> {
        self.simulation.step().map_err(|e| to_py(py, &e))
    }

    /// Step until the time reaches `t` (s), as `flexmbd::Simulation::advance_to`.
    fn advance_to(&mut self, py: Python<'_>, t: f64) -> PyResult<()> {
        self.simulation.advance_to(t).map_err(|e| to_py(py, &e))
    }

    /// The current time (s).
    #[getter]
    fn time(&self) -> f64 {
        self.simulation.time()
    }

    /// The time step h (s).
    #[getter]
    fn step_size(&self) -> f64 {
        self.simulation.step_size()
    }

    /// The sensor names, in the order of `sensors()`.
    #[getter]
    fn sensor_names(&self) -> Vec<String> {
        self.simulation.sensor_names().to_vec()
    }

    /// The sensors at the current state, in `sensor_names` order.
    fn sensors(&mut self) -> Vec<f64> {
        self.simulation.read_sensors(&mut self.sensors);
        self.sensors.clone()
    }

    /// One sensor at the current state; `KeyError` for a name the scene does not have.
    fn sensor(&mut self, name: &str) -> PyResult<f64> {
        let k = self
            .simulation
            .sensor_names()
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| PyKeyError::new_err(name.to_string()))?;
        self.simulation.read_sensors(&mut self.sensors);
        Ok(self.sensors[k])
    }

    /// Save the current state.
    fn checkpoint(&self) -> PyCheckpoint {
        PyCheckpoint {
            checkpoint: self.simulation.checkpoint(),
            simulation: self.id,
            time: self.simulation.time(),
        }
    }

    /// Return to a state saved by `checkpoint()` of this simulation; the next step is
    /// then the step taken from there before. A checkpoint of another simulation is
    /// refused (`ValueError`).
    fn restore(&mut self, checkpoint: &PyCheckpoint) -> PyResult<()> {
        if checkpoint.simulation != self.id {
            return Err(PyValueError::new_err(
                "this checkpoint was taken from another simulation",
            ));
        }
        self.simulation.restore(&checkpoint.checkpoint);
        Ok(())
    }

    /// Steps taken, Newton iterations and factorisations so far.
    fn counters(&self) -> (usize, usize, usize) {
        let stats = self.simulation.stats();
        (stats.steps, stats.newton_iterations, stats.factorizations)
    }
}
