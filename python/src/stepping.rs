//! `Simulation`: a scene under way, stepped by the host — one step, or to a time; the
//! sensors read between steps; checkpoints to return to.
//!
//! The Rust `Simulation` is not `Send` (its formulation is a `Box<dyn CompiledScene>`
//! without that bound), while a Python object may be used, and is dropped by the garbage
//! collector, on any thread. So each simulation lives on a thread of its own ([`serve`]),
//! made with it; the Python object sends it [`Request`]s and waits for the [`Reply`] with
//! the GIL released. It ends when the Python object is dropped.
//!
//! The scene's named inputs are set between steps by name (`set_input`), as
//! `flexmbd::Simulation::set_input_by_name`.
//!
//! Ctrl-C while the Python object waits (`crate::interrupt`) sets the simulation's stop
//! flag: an `advance_to` under way stops between two steps, the simulation stays usable
//! where it is, and the KeyboardInterrupt is raised.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::sync::{Arc, Mutex};

use flexmbd::integrators::Checkpoint;
use flexmbd::model::Scene;
use flexmbd::{Error, Simulation};
use pyo3::exceptions::{PyKeyError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use crate::errors::to_py;
use crate::interrupt::wait_for_answer;
use crate::scene::PyScene;

/// The identity of the next simulation made, so that a checkpoint is restored only into
/// the simulation it was taken from (the Rust restore panics on another size).
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

/// What the Python object asks of its simulation's thread.
enum Request {
    Step,
    AdvanceTo(f64),
    SetInput(String, Vec<f64>),
    Sensors,
    Checkpoint,
    Restore(Box<Checkpoint>),
    Counters,
}

/// The answer to a [`Request`], with the time after it.
struct Reply {
    time: f64,
    outcome: Outcome,
}

/// What a [`Request`] gives back.
enum Outcome {
    Stepped(Result<(), Error>),
    Sensors(Vec<f64>),
    Checkpoint(Box<Checkpoint>),
    Restored,
    Counters(usize, usize, usize),
}

/// What the simulation's thread reports once the simulation is made: its sensor names
/// and step size, or why it could not be made.
type Started = Result<(Vec<String>, Vec<String>, f64), Error>;

/// The simulation's thread: make the simulation from `scene`, report on `started`, then
/// answer each request until the Python object (the sender of `requests`) is gone.
fn serve(
    scene: Scene,
    stop: Arc<AtomicBool>,
    started: Sender<Started>,
    requests: Receiver<Request>,
    replies: Sender<Reply>,
) {
    let mut simulation = match Simulation::new_or_stop(&scene, &stop) {
        Ok(s) => s,
        Err(e) => {
            let _ = started.send(Err(e));
            return;
        }
    };
    let names = simulation.sensor_names().to_vec();
    let inputs = simulation.input_names().map(String::from).collect();
    let mut sensors = vec![0.0; names.len()];
    if started
        .send(Ok((names, inputs, simulation.step_size())))
        .is_err()
    {
        return;
    }
    for request in requests {
        let outcome = match request {
            Request::Step => Outcome::Stepped(simulation.step()),
            Request::AdvanceTo(t) => {
                Outcome::Stepped(simulation.advance_to_or_stop(t, &stop).map(|_| ()))
            }
            Request::SetInput(name, values) => {
                Outcome::Stepped(simulation.set_input_by_name(&name, &values))
            }
            Request::Sensors => {
                simulation.read_sensors(&mut sensors);
                Outcome::Sensors(sensors.clone())
            }
            Request::Checkpoint => Outcome::Checkpoint(Box::new(simulation.checkpoint())),
            Request::Restore(checkpoint) => {
                simulation.restore(&checkpoint);
                Outcome::Restored
            }
            Request::Counters => {
                let s = simulation.stats();
                Outcome::Counters(s.steps, s.newton_iterations, s.factorizations)
            }
        };
        let reply = Reply {
            time: simulation.time(),
            outcome,
        };
        if replies.send(reply).is_err() {
            return;
        }
    }
}

/// A stepping simulation of a scene, at t = 0 in consistent initial conditions when made
/// (Ctrl-C while it is made stops the pilot run of proper orthogonal modes, if any, and
/// raises KeyboardInterrupt).
#[pyclass(name = "Simulation", module = "flexmbd._native")]
pub struct PySimulation {
    requests: Sender<Request>,
    /// Set on Ctrl-C while a request is under way; cleared when it is answered.
    stop: Arc<AtomicBool>,
    /// In a mutex only to make the class `Sync` (the object's `&mut self` already
    /// serialises the requests).
    replies: Mutex<Receiver<Reply>>,
    id: u64,
    names: Vec<String>,
    inputs: Vec<String>,
    step_size: f64,
    time: f64,
}

/// A saved state of one simulation (time, positions, velocities, accelerations,
/// multipliers and the integrator's history).
#[pyclass(name = "Checkpoint", module = "flexmbd._native", frozen)]
pub struct PyCheckpoint {
    checkpoint: Box<Checkpoint>,
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

impl PySimulation {
    /// Send `request` to the simulation's thread and wait for its outcome, the GIL released.
    /// An exception of a signal handler while waiting (KeyboardInterrupt) stops an advance
    /// between two steps and is raised once the thread has answered, the time updated.
    fn ask(&mut self, py: Python<'_>, request: Request) -> PyResult<Outcome> {
        let ended = || PyRuntimeError::new_err("the simulation's thread has ended");
        self.requests.send(request).map_err(|_| ended())?;
        let stop = &self.stop;
        let (reply, raised) =
            wait_for_answer(py, &self.replies, || stop.store(true, Ordering::Relaxed));
        self.stop.store(false, Ordering::Relaxed);
        let reply = reply.ok_or_else(ended)?;
        self.time = reply.time;
        match raised {
            Some(e) => Err(e),
            None => Ok(reply.outcome),
        }
    }

    /// Step as `request` asks; a failed step as `RunError`.
    fn stepped(&mut self, py: Python<'_>, request: Request) -> PyResult<()> {
        match self.ask(py, request)? {
            Outcome::Stepped(result) => result.map_err(|e| to_py(py, &e)),
            _ => Err(unexpected()),
        }
    }
}

/// The error of a reply that does not answer its request (a defect of this module).
fn unexpected() -> PyErr {
    PyRuntimeError::new_err("the simulation's thread answered another request")
}

#[pymethods]
impl PySimulation {
    /// Compile `scene`, find its static equilibrium if it asks for one, and make the
    /// initial conditions consistent (on the simulation's thread, the GIL released).
    #[new]
    fn new(py: Python<'_>, scene: &PyScene) -> PyResult<Self> {
        let scene = scene.scene.clone();
        let (started_tx, started_rx) = channel();
        let (requests, requests_rx) = channel();
        let (replies_tx, replies) = channel();
        let stop = Arc::new(AtomicBool::new(false));
        let stop_of_thread = Arc::clone(&stop);
        std::thread::Builder::new()
            .name("flexmbd-simulation".into())
            .spawn(move || serve(scene, stop_of_thread, started_tx, requests_rx, replies_tx))
            .map_err(|e| {
                PyRuntimeError::new_err(format!("cannot start the simulation's thread: {e}"))
            })?;
        let (started, raised) = wait_for_answer(py, &Mutex::new(started_rx), || {
            stop.store(true, Ordering::Relaxed)
        });
        if let Some(raised) = raised {
            return Err(raised);
        }
        let started =
            started.ok_or_else(|| PyRuntimeError::new_err("the simulation's thread has ended"))?;
        let (names, inputs, step_size) = started.map_err(|e| to_py(py, &e))?;
        Ok(PySimulation {
            requests,
            stop,
            replies: Mutex::new(replies),
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            names,
            inputs,
            step_size,
            time: 0.0,
        })
    }

    /// Advance one time step; a failed step raises `RunError` (with its `time`) and leaves
    /// the simulation at its last good state.
    fn step(&mut self, py: Python<'_>) -> PyResult<()> {
        self.stepped(py, Request::Step)
    }

    /// Step until the time reaches `t` (s), as `flexmbd::Simulation::advance_to`.
    fn advance_to(&mut self, py: Python<'_>, t: f64) -> PyResult<()> {
        self.stepped(py, Request::AdvanceTo(t))
    }

    /// The current time (s).
    #[getter]
    fn time(&self) -> f64 {
        self.time
    }

    /// The time step h (s).
    #[getter]
    fn step_size(&self) -> f64 {
        self.step_size
    }

    /// The sensor names, in the order of `sensors()`.
    #[getter]
    fn sensor_names(&self) -> Vec<String> {
        self.names.clone()
    }

    /// The names of the scene's inputs.
    #[getter]
    fn input_names(&self) -> Vec<String> {
        self.inputs.clone()
    }

    /// Set the input `name` to `values` for the steps that follow; a refused name or value
    /// raises `SceneError` (with `field`, `value`, `reason`) and changes nothing.
    fn set_input(&mut self, py: Python<'_>, name: &str, values: Vec<f64>) -> PyResult<()> {
        self.stepped(py, Request::SetInput(name.to_string(), values))
    }

    /// The sensors at the current state, in `sensor_names` order.
    fn sensors(&mut self, py: Python<'_>) -> PyResult<Vec<f64>> {
        match self.ask(py, Request::Sensors)? {
            Outcome::Sensors(values) => Ok(values),
            _ => Err(unexpected()),
        }
    }

    /// One sensor at the current state; `KeyError` for a name the scene does not have.
    fn sensor(&mut self, py: Python<'_>, name: &str) -> PyResult<f64> {
        let k = self
            .names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| PyKeyError::new_err(name.to_string()))?;
        Ok(self.sensors(py)?[k])
    }

    /// Save the current state.
    fn checkpoint(&mut self, py: Python<'_>) -> PyResult<PyCheckpoint> {
        match self.ask(py, Request::Checkpoint)? {
            Outcome::Checkpoint(checkpoint) => Ok(PyCheckpoint {
                checkpoint,
                simulation: self.id,
                time: self.time,
            }),
            _ => Err(unexpected()),
        }
    }

    /// Return to a state saved by `checkpoint()` of this simulation; the next step is
    /// then the step taken from there before. A checkpoint of another simulation is
    /// refused (`ValueError`).
    fn restore(&mut self, py: Python<'_>, checkpoint: &PyCheckpoint) -> PyResult<()> {
        if checkpoint.simulation != self.id {
            return Err(PyValueError::new_err(
                "this checkpoint was taken from another simulation",
            ));
        }
        let request = Request::Restore(checkpoint.checkpoint.clone());
        match self.ask(py, request)? {
            Outcome::Restored => Ok(()),
            _ => Err(unexpected()),
        }
    }

    /// Steps taken, Newton iterations and factorisations so far.
    fn counters(&mut self, py: Python<'_>) -> PyResult<(usize, usize, usize)> {
        match self.ask(py, Request::Counters)? {
            Outcome::Counters(steps, iterations, factorizations) => {
                Ok((steps, iterations, factorizations))
            }
            _ => Err(unexpected()),
        }
    }
}
