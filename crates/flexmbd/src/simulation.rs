//! Running a scene: compile it with the chosen formulation, find its static equilibrium
//! when `solver.initial_state` asks for it (methods.md §5.4 item 4,
//! `flexmbd_integrators::statics`), make the initial conditions consistent and integrate
//! with ALI3-P, reading the sensors as it goes.
//!
//! [`Simulation`] is the stepping interface: the host calls [`Simulation::step`] or
//! [`Simulation::advance_to`] and reads [`Simulation::read_sensors`] in between.
//! [`run`] (and [`Simulation::run`]) goes to the scene's duration, records the sensors at
//! the output interval into a [`History`] and summarises the run in a [`Summary`].
//!
//! A failed step (Newton does not converge, the solution diverges) returns an
//! [`Error`] with the time and the reason and leaves the simulation at its last good
//! state; [`run`] then ends with `status = "failed"`, keeping the rows computed so far.

use std::sync::Arc;
use std::time::Instant;

use flexmbd_core::CompiledScene;
use flexmbd_integrators::{
    Ali3p, Ali3pSettings, Checkpoint as IntegratorCheckpoint, StartFrom, StaticSettings, Stats,
    solve_static,
};
use flexmbd_model::{
    FormulationKind, InitialState, ModelError, PreparedScene, Scene, Solver, Stiffening,
};
use serde::Serialize;

use crate::Error;

/// Everything a run reports (the `--json` summary of `flexmbd simulate`).
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// The scene's name.
    pub scene: String,
    /// `"ok"` or `"failed"`.
    pub status: String,
    /// Time of the failed step (s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed_at: Option<f64>,
    /// Why it failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub message: Option<String>,
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

/// A recorded history: times and sensor values.
#[derive(Clone, Debug, Default)]
pub struct History {
    /// `t` followed by the sensor names.
    pub header: Vec<String>,
    /// One row per output instant: t, then the sensors.
    pub rows: Vec<Vec<f64>>,
}

impl History {
    /// The column of a sensor.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let k = self.header.iter().position(|h| h == name)?;
        Some(self.rows.iter().map(|r| r[k]).collect())
    }
}

/// Compile a scene with the formulation its solver settings name, for tests and benchmarks
/// that evaluate the formulation at chosen states or drive [`Ali3p`] by hand;
/// [`Simulation::new`] is the usual route.
pub fn compile(scene: &Scene) -> Result<Box<dyn CompiledScene>, ModelError> {
    build_formulation(scene)
}

/// The one place where a formulation is built from a scene (every route of the facade
/// comes through here).
fn build_formulation(scene: &Scene) -> Result<Box<dyn CompiledScene>, ModelError> {
    // The prepared scene: validated, rewritten for its stiffening method, bodies reduced and
    // built with their elastic models, names resolved.
    let prepared = PreparedScene::new(scene)?;
    Ok(match scene.solver.formulation {
        FormulationKind::Absolute => Box::new(flexmbd_absolute::compile(&prepared)?),
        FormulationKind::Relative => Box::new(flexmbd_relative::compile(&prepared)?),
    })
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
    preprocessing_seconds: f64,
    static_seconds: f64,
    static_iterations: usize,
    /// CPU time of the consistent initial conditions (part of the run's `cpu_seconds`).
    start_seconds: f64,
}

impl Setup {
    /// The summary of a run that has not taken a step yet.
    fn summary(&self, n_coordinates: usize, n_constraints: usize) -> Summary {
        Summary {
            scene: self.scene.clone(),
            status: "ok".into(),
            failed_at: None,
            message: None,
            formulation: self.formulation.clone(),
            inertia: self.inertia.clone(),
            stiffening: self.stiffening.clone(),
            n_coordinates,
            n_constraints,
            step: self.solver.step,
            steps: 0,
            newton_iterations: 0,
            factorizations: 0,
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

impl History {
    /// An empty history with the columns `t` and `sensors`.
    fn with_columns(sensors: &[String], capacity: usize) -> Self {
        History {
            header: std::iter::once("t".to_string())
                .chain(sensors.iter().cloned())
                .collect(),
            rows: Vec::with_capacity(capacity),
        }
    }
}

/// A scene compiled into its formulation, not yet started.
struct Compiled {
    formulation: Box<dyn CompiledScene>,
    setup: Setup,
}

/// Compile `scene` (timed as preprocessing) and note its options for the summary.
fn compile_scene(scene: &Scene) -> Result<Compiled, ModelError> {
    let clock = Instant::now();
    let formulation = build_formulation(scene)?;
    let preprocessing_seconds = clock.elapsed().as_secs_f64();
    let (formulation_name, inertia, stiffening) = names(scene);
    Ok(Compiled {
        formulation,
        setup: Setup {
            scene: scene.name.clone(),
            solver: scene.solver.clone(),
            formulation: formulation_name,
            inertia,
            stiffening,
            preprocessing_seconds,
            static_seconds: 0.0,
            static_iterations: 0,
            start_seconds: 0.0,
        },
    })
}

/// A start that failed (no static equilibrium, no consistent initial conditions), with the
/// compiled scene that the failed run's summary and history describe.
struct StartFailure {
    compiled: Compiled,
    error: Error,
}

impl StartFailure {
    /// The summary (`status = "failed"` at t = 0) and the empty history of the failed start.
    fn report(self: Box<Self>) -> (Summary, History) {
        let f = &self.compiled.formulation;
        let mut summary = self
            .compiled
            .setup
            .summary(f.n_coordinates(), f.n_constraints());
        summary.cpu_seconds = self.compiled.setup.start_seconds;
        let history = History::with_columns(f.sensor_names(), 0);
        summary.fail(0.0, self.error);
        (summary, history)
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
/// there would fail the same way: the caller can read the sensors, take the failure into
/// its output, or [`restore`](Simulation::restore) an earlier [`checkpoint`](Simulation::checkpoint).
/// A different step size, tolerance or model means a new simulation from a changed scene.
pub struct Simulation {
    formulation: Box<dyn CompiledScene>,
    integrator: Ali3p,
    /// The state before the step under way; a failed step returns here.
    last_good: IntegratorCheckpoint,
    setup: Setup,
}

impl Simulation {
    /// Compile `scene` with the formulation its solver settings name, find its static
    /// equilibrium when `solver.initial_state` asks for one, and make the initial
    /// conditions consistent (methods.md §5.4). The scene should be validated (as
    /// [`Scene::load`] does).
    pub fn new(scene: &Scene) -> Result<Simulation, Error> {
        Self::start(compile_scene(scene)?).map_err(|failure| failure.error)
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
                    setup.static_iterations = solution.iterations;
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
            Some(solution) => Ali3p::new(&mut StartFrom::at_rest(f, solution), 0.0, settings),
            None => Ali3p::new(f, 0.0, settings),
        };
        compiled.setup.start_seconds = clock.elapsed().as_secs_f64();
        match integrator {
            Ok(integrator) => Ok(Simulation {
                last_good: integrator.checkpoint(),
                formulation: compiled.formulation,
                integrator,
                setup: compiled.setup,
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
    pub fn advance_to(&mut self, t: f64) -> Result<(), Error> {
        let h = self.step_size();
        while self.time() + 0.5 * h <= t {
            self.step()?;
        }
        Ok(())
    }

    /// Current time (s): t₀ + k h after k steps.
    pub fn time(&self) -> f64 {
        self.integrator.t
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

    /// Run from the current state to the scene's duration (or to the first failed step),
    /// recording the sensors at the current state and then at the output interval, and
    /// summarise the run. `progress` is called with the fraction done now and then.
    pub fn run(&mut self, mut progress: impl FnMut(f64)) -> (Summary, History) {
        let h = self.setup.solver.step;
        let steps = (self.setup.solver.duration / h).round().max(1.0) as usize;
        let every = self
            .setup
            .solver
            .output_interval
            .map_or(1, |o| ((o / h).round() as usize).max(1));
        let mut summary = self
            .setup
            .summary(self.n_coordinates(), self.n_constraints());
        let mut history = History::with_columns(self.sensor_names(), steps / every + 2);
        self.record(&mut history);
        let mut cpu = self.setup.start_seconds;
        let report_every = (steps / 200).max(1);
        for k in self.integrator.stats.steps + 1..=steps {
            let clock = Instant::now();
            let r = self.step();
            cpu += clock.elapsed().as_secs_f64();
            if let Err(e) = r {
                summary.fail(e.failed_at().unwrap_or(self.time()), e);
                break;
            }
            if k % every == 0 || k == steps {
                self.record(&mut history);
            }
            if k % report_every == 0 {
                progress(k as f64 / steps as f64);
            }
        }
        let st = &self.integrator.stats;
        summary.steps = st.steps;
        summary.newton_iterations = st.newton_iterations;
        summary.factorizations = st.factorizations;
        summary.accepted_unconverged = st.accepted_unconverged;
        summary.failed_steps = st.failed_steps;
        summary.simulated_seconds = st.steps as f64 * h;
        summary.cpu_seconds = cpu;
        summary.realtime_factor = if cpu > 0.0 {
            summary.simulated_seconds / cpu
        } else {
            0.0
        };
        summary.time_evaluation = st.time_evaluation;
        summary.time_factorization = st.time_factorization;
        summary.time_projection = st.time_projection;
        summary.rows = history.rows.len();
        (summary, history)
    }

    /// Append a row (t, then the sensors) at the current state.
    fn record(&mut self, history: &mut History) {
        let mut row = vec![0.0; self.sensor_names().len() + 1];
        row[0] = self.time();
        self.read_sensors(&mut row[1..]);
        history.rows.push(row);
    }
}

/// Run a scene to its duration (or to the first failure): [`Simulation::new`] then
/// [`Simulation::run`]. `progress` is called with the fraction done now and then.
///
/// A scene that does not compile is an `Err`; a run that fails to start (no static
/// equilibrium, no consistent initial conditions) or fails a step is an `Ok` whose summary
/// says `status = "failed"` with the time, the message and the typed error, and whose
/// history keeps the rows computed so far.
pub fn run(scene: &Scene, progress: impl FnMut(f64)) -> Result<(Summary, History), Error> {
    match Simulation::start(compile_scene(scene)?) {
        Ok(mut simulation) => Ok(simulation.run(progress)),
        Err(failure) => Ok(failure.report()),
    }
}
