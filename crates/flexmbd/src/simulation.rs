//! Running a scene: compile it with the chosen formulation, find its static equilibrium
//! when `solver.initial_state` asks for it (methods.md §5.4 item 4,
//! `flexmbd_integrators::statics`), make the initial conditions consistent and integrate
//! with ALI3-P, reading the sensors as it goes.
//!
//! [`Simulation`] is the stepping interface: the host calls [`Simulation::step`] or
//! [`Simulation::advance_to`] and reads [`Simulation::read_sensors`] in between.
//! [`run`] (and [`Simulation::run`]) goes to the scene's duration, records the sensors at
//! the output interval into a [`History`] and summarises the run in a [`Summary`];
//! [`run_into`] (and [`Simulation::run_into`]) hands each row to a
//! [`RowSink`](crate::output::RowSink) as soon as it is computed, and stops between two
//! steps when asked to (a flag, set e.g. by a signal handler).
//!
//! Between steps a host program sets the scene's named inputs
//! ([`Simulation::set_input`]), reads sensors by name, reads and writes the state, and asks
//! for the equilibrium and vibration analyses ([`host`]).
//!
//! A failed step (Newton does not converge, the solution diverges) returns an
//! [`Error`] with the time and the reason and leaves the simulation at its last good
//! state; [`run`] then ends with `status = "failed"`, keeping the rows computed so far.
//!
//! A run is bounded: more than [`MAX_STEPS`] steps are refused when the scene is compiled
//! ([`Simulation::new`], [`run`], [`run_into`]), and a [`History`] refuses to hold more than
//! [`HISTORY_MEMORY_LIMIT`](crate::output::HISTORY_MEMORY_LIMIT).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use flexmbd_core::{CompiledScene, DrivenEliminated};
use flexmbd_integrators::{
    Ali3p, Ali3pSettings, Checkpoint as IntegratorCheckpoint, StartFrom, StaticSettings, Stats,
    solve_static,
};
use flexmbd_model::inputs::InputTable;
use flexmbd_model::{
    DriverHandling, FormulationKind, InitialState, PreparedScene, Scene, Solver, Stiffening,
};
use serde::Serialize;

use crate::Error;
pub use crate::output::History;

pub mod host;
mod plan;
mod poses;
mod run;

pub use host::InputId;
pub use plan::MAX_STEPS;
use plan::RunPlan;
pub use run::{run, run_into, run_observed};

/// A stop flag never set, for the callers that cannot be interrupted: their runs, pilots
/// and advances go to their end.
pub(crate) static NO_STOP: AtomicBool = AtomicBool::new(false);

/// Everything a run reports (the `--json` summary of `flexmbd simulate`).
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// The scene's name.
    pub scene: String,
    /// `"ok"`, `"failed"` (a step, the static start, the consistent initial conditions or
    /// the pilot run of proper orthogonal modes failed) or `"interrupted"` (the run, or its
    /// pilot run, was asked to stop between two steps).
    pub status: String,
    /// Time of the failed step (s); none when the pilot run of proper orthogonal modes
    /// failed (the run took no step: the pilot's time is in `message`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed_at: Option<f64>,
    /// Why it failed, or when it was interrupted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub message: Option<String>,
    /// What a reader of an `"ok"` status should know: the duration or output interval
    /// rounded to whole steps, steps accepted unconverged.
    pub warnings: Vec<String>,
    /// `absolute` or `relative`.
    pub formulation: String,
    /// `b-matrix` or `shape-integrals`.
    pub inertia: String,
    /// Stiffening method.
    pub stiffening: String,
    /// Coordinates n.
    pub n_coordinates: usize,
    /// Constraint equations m.
    pub n_constraints: usize,
    /// Time step h (s).
    pub step: f64,
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Factorisations of the leading matrix.
    pub factorizations: usize,
    /// Of those, by a structured Cholesky: the arrow form of a tree in relative coordinates
    /// or the sparse one of a large system (docs/methods.md §5.2, "Factorising f_q").
    pub structured_factorizations: usize,
    /// Steps accepted at the iteration limit with small ‖Φ‖ (singular configurations).
    pub accepted_unconverged: usize,
    /// Failed steps (0 or 1).
    pub failed_steps: usize,
    /// Simulated time reached (s).
    pub simulated_seconds: f64,
    /// CPU (wall-clock, one thread) time of the integration, preprocessing excluded (s).
    pub cpu_seconds: f64,
    /// CPU time of compiling the scene (FE reduction included) (s).
    pub preprocessing_seconds: f64,
    /// CPU time of the static-equilibrium start, 0 without one (s); not in `cpu_seconds`.
    pub static_seconds: f64,
    /// Newton iterations of the static-equilibrium start (0 without one).
    pub static_iterations: usize,
    /// Simulated seconds per CPU second.
    pub realtime_factor: f64,
    /// Time in formulation evaluations (s).
    pub time_evaluation: f64,
    /// Time forming and factorising the leading matrix (s).
    pub time_factorization: f64,
    /// Time in the velocity and acceleration projections (s).
    pub time_projection: f64,
    /// Rows recorded.
    pub rows: usize,
    /// The typed error behind `status = "failed"` and `message` (not serialised).
    #[serde(skip)]
    pub error: Option<Arc<Error>>,
}

/// Compile a scene with the formulation its solver settings name, for tests and benchmarks
/// that evaluate the formulation at chosen states or drive [`Ali3p`] by hand;
/// [`Simulation::new`] is the usual route.
///
/// A refused scene is an [`Error::Model`]; a scene with proper orthogonal modes whose
/// pilot run fails is an [`Error::Pilot`].
pub fn compile(scene: &Scene) -> Result<Box<dyn CompiledScene>, Error> {
    Ok(build_formulation(scene, &NO_STOP)?.0)
}

/// A compiled formulation with the table of the scene's inputs it reads and the prepared
/// scene it was compiled from.
type Built = (Box<dyn CompiledScene>, InputTable, Arc<PreparedScene>);

/// The one place where a formulation is built from a scene (every route of the facade
/// comes through here), with the table of the scene's inputs its elements and drivers read.
/// A pilot run (proper orthogonal modes) stops between two steps when `stop` is set.
fn build_formulation(scene: &Scene, stop: &AtomicBool) -> Result<Built, Error> {
    // The prepared scene: validated, rewritten for its stiffening method, bodies reduced and
    // built with their elastic models, names resolved.
    // With proper orthogonal modes, first their pilot run (crate::pilot).
    let prepared = crate::pilot::prepared_scene(scene, stop)?;
    let formulation: Box<dyn CompiledScene> = match scene.solver.formulation {
        FormulationKind::Absolute => Box::new(flexmbd_absolute::compile(&prepared)?),
        FormulationKind::Relative => Box::new(flexmbd_relative::compile(&prepared)?),
    };
    let formulation = match scene.solver.drivers {
        DriverHandling::Eliminated => DrivenEliminated::wrap(formulation),
        DriverHandling::Constraint => formulation,
    };
    Ok((formulation, prepared.inputs().clone(), Arc::new(prepared)))
}

fn names(scene: &Scene) -> (String, String, String) {
    let formulation = match scene.solver.formulation {
        FormulationKind::Absolute => "absolute",
        FormulationKind::Relative => "relative",
    };
    let inertia = match scene.solver.inertia {
        flexmbd_body::InertiaMethod::BMatrix => "b-matrix",
        flexmbd_body::InertiaMethod::ShapeIntegrals => "shape-integrals",
    };
    let stiffening = match scene.solver.stiffening {
        Stiffening::Linear => "linear".to_string(),
        Stiffening::Fnl1 => "fnl1".into(),
        Stiffening::Fnl2 => "fnl2".into(),
        Stiffening::Foreshortening => "foreshortening".into(),
        Stiffening::Substructuring(n) => format!("substructuring:{n}"),
    };
    (formulation.into(), inertia.into(), stiffening)
}

/// The ALI3-P settings a scene's solver block asks for: its step h, penalty α (`None`:
/// the default 4·10⁴ m_ref / h²), Newton tolerance (as both ε_q and ε_Φ) and iteration
/// limit; everything else at [`Ali3pSettings::default`].
pub fn integrator_settings(solver: &Solver) -> Ali3pSettings {
    Ali3pSettings {
        step: solver.step,
        penalty: solver.penalty,
        tol_q: solver.newton_tolerance,
        tol_phi: solver.newton_tolerance,
        max_iterations: solver.max_iterations,
        ..Default::default()
    }
}

/// What a run reports besides the integrator's counters: the scene's name and options, and
/// the CPU time spent before the first step.
#[derive(Clone, Debug)]
struct Setup {
    scene: String,
    solver: Solver,
    formulation: String,
    inertia: String,
    stiffening: String,
    /// The steps and output instants of a run to the scene's duration.
    plan: RunPlan,
    preprocessing_seconds: f64,
    static_seconds: f64,
    static_iterations: usize,
    /// CPU time of the consistent initial conditions (part of the run's `cpu_seconds`).
    start_seconds: f64,
    /// The scene gives every body a start velocity (`Scene::initial_velocity`).
    moving_start: bool,
}

impl Setup {
    /// The summary of a run that has not taken a step yet.
    fn summary(&self, n_coordinates: usize, n_constraints: usize) -> Summary {
        Summary {
            scene: self.scene.clone(),
            status: "ok".into(),
            failed_at: None,
            message: None,
            warnings: self.plan.warnings.clone(),
            formulation: self.formulation.clone(),
            inertia: self.inertia.clone(),
            stiffening: self.stiffening.clone(),
            n_coordinates,
            n_constraints,
            step: self.solver.step,
            steps: 0,
            newton_iterations: 0,
            factorizations: 0,
            structured_factorizations: 0,
            accepted_unconverged: 0,
            failed_steps: 0,
            simulated_seconds: 0.0,
            cpu_seconds: 0.0,
            preprocessing_seconds: self.preprocessing_seconds,
            static_seconds: self.static_seconds,
            static_iterations: self.static_iterations,
            realtime_factor: 0.0,
            time_evaluation: 0.0,
            time_factorization: 0.0,
            time_projection: 0.0,
            rows: 0,
            error: None,
        }
    }
}

impl Summary {
    /// Mark the run failed at time `t` (s) because of `error`.
    fn fail(&mut self, t: f64, error: Error) {
        self.status = "failed".into();
        self.failed_at = Some(t);
        self.message = Some(error.to_string());
        self.error = Some(Arc::new(error));
    }
}

/// The columns of a run's rows: `t`, then the sensors.
fn columns(sensors: &[String]) -> Vec<String> {
    std::iter::once("t".to_string())
        .chain(sensors.iter().cloned())
        .collect()
}

/// A scene compiled into its formulation, not yet started.
struct Compiled {
    formulation: Box<dyn CompiledScene>,
    setup: Setup,
    inputs: InputTable,
    scene: Scene,
    prepared: Arc<PreparedScene>,
}

/// Compile `scene` (timed as preprocessing) and note its options for the summary. A run
/// longer than [`MAX_STEPS`] is refused first; a pilot run stops when `stop` is set.
fn compile_scene(scene: &Scene, stop: &AtomicBool) -> Result<Compiled, Error> {
    let plan = RunPlan::of(scene)?;
    let clock = Instant::now();
    let (formulation, inputs, prepared) = build_formulation(scene, stop)?;
    let preprocessing_seconds = clock.elapsed().as_secs_f64();
    Ok(Compiled {
        formulation,
        inputs,
        scene: scene.clone(),
        prepared,
        setup: Setup::of(scene, plan, preprocessing_seconds),
    })
}

impl Setup {
    /// The options of `scene` run by `plan`, `preprocessing_seconds` spent compiling it.
    fn of(scene: &Scene, plan: RunPlan, preprocessing_seconds: f64) -> Setup {
        let (formulation_name, inertia, stiffening) = names(scene);
        Setup {
            scene: scene.name.clone(),
            solver: scene.solver.clone(),
            formulation: formulation_name,
            inertia,
            stiffening,
            plan,
            preprocessing_seconds,
            static_seconds: 0.0,
            static_iterations: 0,
            start_seconds: 0.0,
            moving_start: scene.moves_at_start(),
        }
    }
}

/// A start that failed (no static equilibrium, no consistent initial conditions), with the
/// compiled scene that the failed run's summary and history describe.
struct StartFailure {
    compiled: Compiled,
    error: Error,
}

impl StartFailure {
    /// The summary of the failed start: `status = "failed"` at t = 0, no row.
    fn report(self: Box<Self>) -> Summary {
        let f = &self.compiled.formulation;
        let mut summary = self
            .compiled
            .setup
            .summary(f.n_coordinates(), f.n_constraints());
        summary.cpu_seconds = self.compiled.setup.start_seconds;
        summary.fail(0.0, self.error);
        summary
    }
}

/// A scene under way: its compiled formulation and the ALI3-P integrator that advances it.
///
/// Built by [`Simulation::new`] at t = 0 in consistent initial conditions; the host then
/// calls [`step`](Simulation::step) or [`advance_to`](Simulation::advance_to) and reads
/// the scene's sensors with [`read_sensors`](Simulation::read_sensors) in between, or
/// runs to the scene's duration with [`run`](Simulation::run). Stepping allocates nothing.
///
/// When a step fails the simulation stays at its last good state (time, positions,
/// velocities, multipliers; the counters keep the failed attempt). Another `step` from
/// there with the same inputs would fail the same way: the caller can read the sensors,
/// take the failure into its output, set saner inputs and step on
/// ([`set_input`](Simulation::set_input)), or [`restore`](Simulation::restore) an earlier
/// [`checkpoint`](Simulation::checkpoint).
/// A different step size, tolerance or model means a new simulation from a changed scene.
pub struct Simulation {
    formulation: Box<dyn CompiledScene>,
    integrator: Ali3p,
    /// The state before the step under way; a failed step returns here.
    last_good: IntegratorCheckpoint,
    setup: Setup,
    /// The scene's inputs and the table of values the formulation reads ([`host`]).
    inputs: InputTable,
    /// The scene as given, for the analyses about its equilibrium ([`host`]).
    scene: Scene,
    /// Room for every sensor's value, for [`Simulation::sensor`] (no allocation).
    sensor_values: Vec<f64>,
    /// t₀ of the integrator: 0, or the time a state was written ([`Simulation::set_state`]).
    start_time: f64,
    /// The scene as compiled: its bodies' reduced data, for [`Simulation::body_poses`].
    prepared: Arc<PreparedScene>,
}

impl Simulation {
    /// Compile `scene` with the formulation its solver settings name, find its static
    /// equilibrium when `solver.initial_state` asks for one, and make the initial
    /// conditions consistent (methods.md §5.4). The scene should be validated (as
    /// [`Scene::load`] does).
    pub fn new(scene: &Scene) -> Result<Simulation, Error> {
        Self::new_or_stop(scene, &NO_STOP)
    }

    /// [`new`](Simulation::new), with the pilot run of proper orthogonal modes (part of
    /// compiling a scene that asks for them, docs/methods.md §1.6) looking at `stop` between its
    /// steps: once it is set, the pilot ends and so does this, with [`Error::Pilot`]
    /// ([`PilotError::interrupted`](crate::PilotError::interrupted)).
    pub fn new_or_stop(scene: &Scene, stop: &AtomicBool) -> Result<Simulation, Error> {
        Self::start(compile_scene(scene, stop)?).map_err(|failure| failure.error)
    }

    /// [`new`](Simulation::new), with some of the scene's named inputs set before the
    /// start: the static equilibrium (when the scene asks for one) and the consistent
    /// initial conditions are found with them, as with the same values written into the
    /// scene. For a host that sets inputs before the first step and wants them to hold
    /// from t = 0 (an FMU's initialisation mode). An unknown name or a refused value is an
    /// [`Error::Input`] naming it.
    pub fn with_inputs(scene: &Scene, inputs: &[(&str, &[f64])]) -> Result<Simulation, Error> {
        let compiled = compile_scene(scene, &NO_STOP)?;
        for (name, values) in inputs {
            let k = compiled.inputs.find(name).ok_or_else(|| {
                Error::Input(flexmbd_core::InvalidValue::new(
                    "input",
                    name,
                    "the scene declares no such input",
                ))
            })?;
            compiled.inputs.set(k, values).map_err(Error::Input)?;
        }
        Self::start(compiled).map_err(|failure| failure.error)
    }

    /// The static start (if asked for) and ALI3-P's consistent initial conditions.
    fn start(mut compiled: Compiled) -> Result<Simulation, Box<StartFailure>> {
        let setup = &mut compiled.setup;
        let settings = integrator_settings(&setup.solver);
        let mut static_solution = None;
        if setup.solver.initial_state == InitialState::StaticEquilibrium {
            let clock = Instant::now();
            let solution = solve_static(
                compiled.formulation.as_mut(),
                0.0,
                &StaticSettings::default(),
            );
            setup.static_seconds = clock.elapsed().as_secs_f64();
            match solution {
                Ok(solution) => {
                    setup.static_iterations = solution.counters.iterations;
                    static_solution = Some(solution);
                }
                Err(e) => {
                    return Err(Box::new(StartFailure {
                        compiled,
                        error: e.into(),
                    }));
                }
            }
        }
        let clock = Instant::now();
        let f = compiled.formulation.as_mut();
        let integrator = match &static_solution {
            Some(solution) if setup.moving_start => {
                // The equilibrium, every body translating at the scene's initial velocity
                // (the formulation's guess holds only that: flexmbd_model::initial_velocity).
                let (mut q, mut qd) = (solution.q.clone(), solution.q.clone());
                f.initial_guess(&mut q, &mut qd);
                Ali3p::new(
                    &mut StartFrom::new(f, solution.q.clone(), qd),
                    0.0,
                    settings,
                )
            }
            Some(solution) => Ali3p::new(&mut StartFrom::at_rest(f, solution), 0.0, settings),
            None => Ali3p::new(f, 0.0, settings),
        };
        compiled.setup.start_seconds = clock.elapsed().as_secs_f64();
        match integrator {
            Ok(integrator) => Ok(Simulation {
                last_good: integrator.checkpoint(),
                sensor_values: vec![0.0; compiled.formulation.sensor_names().len()],
                formulation: compiled.formulation,
                integrator,
                setup: compiled.setup,
                inputs: compiled.inputs,
                scene: compiled.scene,
                prepared: compiled.prepared,
                start_time: 0.0,
            }),
            Err(e) => Err(Box::new(StartFailure {
                compiled,
                error: e.into(),
            })),
        }
    }

    /// Advance one time step h. On failure the error names the time and the reason, and
    /// the simulation stays at the state before the step (see [`Simulation`]).
    pub fn step(&mut self) -> Result<(), Error> {
        self.integrator.checkpoint_into(&mut self.last_good);
        match self.integrator.step(self.formulation.as_mut()) {
            Ok(()) => Ok(()),
            Err(e) => {
                let stats = self.integrator.stats.clone();
                self.integrator.restore(&self.last_good);
                self.integrator.stats = stats;
                Err(e.into())
            }
        }
    }

    /// Step until the time is the multiple of h nearest to `t` (s) (no step when `t` is
    /// not ahead by at least h/2). Stops at the first failed step.
    ///
    /// A `t` that is NaN or infinite, or more than [`MAX_STEPS`] steps ahead, is refused
    /// ([`Error::Input`] naming `t`) before any step: a host (an FMU master, a script) that
    /// sends one gets an error instead of a loop without end.
    pub fn advance_to(&mut self, t: f64) -> Result<(), Error> {
        self.advance_to_or_stop(t, &NO_STOP).map(|_| ())
    }

    /// [`advance_to`](Simulation::advance_to), but `stop` is looked at before each step:
    /// once it is set the simulation stays where it is, usable, and `Ok(false)` says that
    /// `t` was not reached (`Ok(true)`: it was). For a host whose user may cancel a long
    /// advance (Ctrl-C in the Python package).
    pub fn advance_to_or_stop(&mut self, t: f64, stop: &AtomicBool) -> Result<bool, Error> {
        let h = self.step_size();
        self.check_target(t, h)?;
        while self.time() + 0.5 * h <= t {
            if stop.load(Ordering::Relaxed) {
                return Ok(false);
            }
            self.step()?;
        }
        Ok(true)
    }

    /// Refuse a target time `t` that is not finite or is more than [`MAX_STEPS`] steps of
    /// `h` ahead of the current time.
    fn check_target(&self, t: f64, h: f64) -> Result<(), Error> {
        let refuse = |reason: String| {
            Err(Error::Input(flexmbd_core::InvalidValue::new(
                "t", t, reason,
            )))
        };
        if !t.is_finite() {
            return refuse("the time to advance to must be a finite number of seconds".into());
        }
        let ahead = (t - self.time()) / h;
        if ahead > MAX_STEPS as f64 {
            return refuse(format!(
                "{ahead:.3e} steps of h = {h} s ahead of t = {} s, more than the limit of {MAX_STEPS} steps",
                self.time()
            ));
        }
        Ok(())
    }

    /// Current time (s): t₀ + k h after k steps.
    pub fn time(&self) -> f64 {
        self.integrator.t
    }

    /// The end time t_{n+1} of the next step, bit for bit as the integrator computes it
    /// (t₀ + (k + 1) h after k steps): where a driver input's values are to hold.
    pub fn next_time(&self) -> f64 {
        self.start_time + (self.integrator.stats.steps + 1) as f64 * self.step_size()
    }

    /// The time step h (s).
    pub fn step_size(&self) -> f64 {
        self.integrator.settings().step
    }

    /// The names of the scene's sensors, in the order [`read_sensors`](Simulation::read_sensors) writes them.
    pub fn sensor_names(&self) -> &[String] {
        self.formulation.sensor_names()
    }

    /// Write the sensors' values at the current state into `out` (SI units; no allocation).
    ///
    /// # Panics
    /// If `out.len()` is not the number of sensors.
    pub fn read_sensors(&mut self, out: &mut [f64]) {
        assert_eq!(
            out.len(),
            self.sensor_names().len(),
            "read_sensors: room for {} values, the scene has {} sensors",
            out.len(),
            self.sensor_names().len()
        );
        let i = &self.integrator;
        self.formulation.sensors(i.state(), out);
    }

    /// The sensors' values at the current state, in [`sensor_names`](Simulation::sensor_names) order (allocates).
    pub fn sensors(&mut self) -> Vec<f64> {
        let mut out = vec![0.0; self.sensor_names().len()];
        self.read_sensors(&mut out);
        out
    }

    /// The integrator's counters since the start (steps, Newton iterations,
    /// factorisations, evaluations, failed steps, time per phase).
    pub fn stats(&self) -> &Stats {
        &self.integrator.stats
    }

    /// The number of coordinates n of the compiled formulation.
    pub fn n_coordinates(&self) -> usize {
        self.formulation.n_coordinates()
    }

    /// The number of constraint equations m of the compiled formulation.
    pub fn n_constraints(&self) -> usize {
        self.formulation.n_constraints()
    }

    /// The integrator, for its state (`q`, `qd`, `qdd`, `lambda`), penalty and last terms.
    pub fn integrator(&self) -> &Ali3p {
        &self.integrator
    }

    /// A copy of the current state, to return to with [`restore`](Simulation::restore)
    /// (allocates).
    pub fn checkpoint(&self) -> IntegratorCheckpoint {
        self.integrator.checkpoint()
    }

    /// Return to a checkpoint of this simulation: the next step is then the step taken
    /// from there before (no allocation).
    ///
    /// # Panics
    /// If the checkpoint was taken from a simulation of another size.
    pub fn restore(&mut self, checkpoint: &IntegratorCheckpoint) {
        self.integrator.restore(checkpoint);
    }
}
