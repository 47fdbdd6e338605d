//! Running to the scene's duration: each row handed to a [`RowSink`] as soon as it is
//! computed (outside [`Simulation::step`], into a row buffer allocated once), a stop flag
//! looked at between two steps, and the [`Summary`] with its status and warnings.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use flexmbd_model::Scene;

use super::plan::RunPlan;
use super::{Setup, Simulation, Summary, columns, compile_scene};
use crate::output::{History, RowSink};
use crate::{Error, PilotError};

impl Simulation {
    /// Run from the current state to the scene's duration (or to the first failed step),
    /// recording the sensors at the current state and then at the output interval into a
    /// [`History`], and summarise the run. `progress` is called with the fraction done now
    /// and then.
    ///
    /// Refused ([`Error::HistoryTooLarge`]) when the history would take more than
    /// [`HISTORY_MEMORY_LIMIT`](crate::output::HISTORY_MEMORY_LIMIT); [`run_into`](Simulation::run_into)
    /// streams the rows instead.
    pub fn run(&mut self, progress: impl FnMut(f64)) -> Result<(Summary, History), Error> {
        let mut history = History::default();
        let summary = self.run_into(&mut history, &super::NO_STOP, progress)?;
        Ok((summary, history))
    }

    /// Run from the current state to the scene's duration, to the first failed step
    /// (`status = "failed"`), or until `stop` is set (looked at before each step:
    /// `status = "interrupted"`), handing the columns and then each row (the current state,
    /// then one per output interval) to `sink` as soon as it is computed.
    ///
    /// An error of the sink ends the run with that error.
    pub fn run_into(
        &mut self,
        sink: &mut dyn RowSink,
        stop: &AtomicBool,
        progress: impl FnMut(f64),
    ) -> Result<Summary, Error> {
        let rows = self.setup.plan.rows(self.integrator.stats.steps);
        sink.header(&columns(self.sensor_names()), rows)?;
        self.stream(sink, stop, progress, &mut |_| {})
    }

    /// The run loop of [`run_into`](Simulation::run_into), after the header; `observe`
    /// sees the simulation after each row is handed to `sink` (at that row's state).
    fn stream(
        &mut self,
        sink: &mut dyn RowSink,
        stop: &AtomicBool,
        mut progress: impl FnMut(f64),
        observe: &mut dyn FnMut(&mut Simulation),
    ) -> Result<Summary, Error> {
        let (steps, every) = (self.setup.plan.steps, self.setup.plan.every);
        let mut summary = self
            .setup
            .summary(self.n_coordinates(), self.n_constraints());
        let mut row = vec![0.0; self.sensor_names().len() + 1];
        let mut rows = 0;
        let mut cpu = self.setup.start_seconds;
        if let Err(e) = self.read_row(&mut row) {
            summary.fail(self.time(), e);
            self.finish(&mut summary, rows, cpu);
            return Ok(summary);
        }
        sink.row(&row)?;
        observe(self);
        rows += 1;
        let report_every = (steps / 200).max(1);
        // The clock is read where the loop leaves the integration (rows, progress), not
        // around every step: two reads a step were 5–8 % of a 5-coordinate step (perf).
        let mut clock = Instant::now();
        for k in self.integrator.stats.steps + 1..=steps {
            if stop.load(Ordering::Relaxed) {
                summary.interrupt(self.time(), k - 1, steps);
                break;
            }
            if let Err(e) = self.step() {
                summary.fail(e.failed_at().unwrap_or(self.time()), e);
                break;
            }
            let (output, report) = (k % every == 0 || k == steps, k % report_every == 0);
            if !(output || report) {
                continue;
            }
            cpu += clock.elapsed().as_secs_f64();
            if output {
                if let Err(e) = self.read_row(&mut row) {
                    summary.fail(self.time(), e);
                    clock = Instant::now();
                    break;
                }
                sink.row(&row)?;
                observe(self);
                rows += 1;
            }
            if report {
                progress(k as f64 / steps as f64);
            }
            clock = Instant::now();
        }
        cpu += clock.elapsed().as_secs_f64();
        self.finish(&mut summary, rows, cpu);
        Ok(summary)
    }

    /// Fill `row` with the current state's row (t, then the sensors); refused when a sensor
    /// is not finite.
    fn read_row(&mut self, row: &mut [f64]) -> Result<(), Error> {
        row[0] = self.time();
        self.read_sensors(&mut row[1..]);
        match row[1..].iter().position(|v| !v.is_finite()) {
            None => Ok(()),
            Some(i) => Err(Error::NonFiniteSensor {
                t: row[0],
                sensor: self.sensor_names()[i].clone(),
                value: row[1 + i],
            }),
        }
    }

    /// Fill in the counters and times of the run, `rows` rows written, `cpu` seconds of
    /// integration; warn of steps accepted unconverged.
    fn finish(&self, summary: &mut Summary, rows: usize, cpu: f64) {
        let h = self.setup.solver.step;
        let st = &self.integrator.stats;
        summary.steps = st.steps;
        summary.newton_iterations = st.newton_iterations;
        summary.factorizations = st.factorizations;
        summary.structured_factorizations = st.structured_factorizations;
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
        summary.rows = rows;
        if st.accepted_unconverged > 0 {
            summary.warnings.push(format!(
                "{} of {} steps accepted at the iteration limit (‖Φ‖ small, residual not converged)",
                st.accepted_unconverged, st.steps
            ));
        }
    }
}

impl Summary {
    /// The summary of a run whose pilot of proper orthogonal modes gave no record: no
    /// step taken, no row; `status = "interrupted"` when `stop` ended the pilot, else
    /// `"failed"` with the pilot's error (no `failed_at`: the run itself took no step; the
    /// pilot's time is in the message).
    fn of_pilot(
        scene: &Scene,
        pilot: Box<PilotError>,
        preprocessing_seconds: f64,
    ) -> Result<Self, Error> {
        let setup = Setup::of(scene, RunPlan::of(scene)?, preprocessing_seconds);
        let mut summary = setup.summary(0, 0);
        summary.message = Some(pilot.to_string());
        if pilot.interrupted() {
            summary.status = "interrupted".into();
        } else {
            summary.status = "failed".into();
            summary.error = Some(std::sync::Arc::new(Error::Pilot(pilot)));
        }
        Ok(summary)
    }

    /// Mark the run interrupted at time `t` (s), after `done` of `steps` steps.
    fn interrupt(&mut self, t: f64, done: usize, steps: usize) {
        self.status = "interrupted".into();
        self.message = Some(format!(
            "interrupted at t = {} s, after {done} of {steps} steps",
            super::plan::number(t)
        ));
    }
}

/// Run a scene to its duration (or to the first failure): [`Simulation::new`] then
/// [`Simulation::run`]. `progress` is called with the fraction done now and then.
///
/// A scene that does not compile, a run longer than [`MAX_STEPS`](super::MAX_STEPS) and a
/// history larger than [`HISTORY_MEMORY_LIMIT`](crate::output::HISTORY_MEMORY_LIMIT) are an
/// `Err`; a run that fails to start (no static equilibrium, no consistent initial conditions)
/// or fails a step is an `Ok` whose summary says `status = "failed"` with the time, the
/// message and the typed error, and whose history keeps the rows computed so far. A failed
/// pilot run of proper orthogonal modes is an `Ok` too, `status = "failed"` with the
/// pilot's [`Error::Pilot`] and no row (the scene is valid, its run failed).
pub fn run(scene: &Scene, progress: impl FnMut(f64)) -> Result<(Summary, History), Error> {
    let mut history = History::default();
    let summary = run_into(scene, &mut history, &super::NO_STOP, progress)?;
    Ok((summary, history))
}

/// Run a scene as [`run`] does, handing the columns to `sink` once the scene is compiled
/// (before the static start and the first step) and each row as soon as it is computed;
/// stop between two steps when `stop` is set (`status = "interrupted"`, the rows so far
/// written). Nothing is kept in memory but what `sink` keeps.
///
/// The pilot run of proper orthogonal modes, part of compiling the scene, looks at `stop`
/// between its steps too: stopped, it ends the run with `status = "interrupted"`, a
/// message that names the pilot, no header and no row (the columns are known once the
/// scene is compiled, and it is not), and nothing of it kept. A failed pilot is a failed
/// run, as in [`run`].
///
/// The errors are [`run`]'s, and the sink's: an error of the sink ends the run with it.
pub fn run_into(
    scene: &Scene,
    sink: &mut dyn RowSink,
    stop: &AtomicBool,
    progress: impl FnMut(f64),
) -> Result<Summary, Error> {
    run_observed(scene, sink, stop, progress, &mut |_| {})
}

/// [`run_into`], `observe` called with the simulation after each row is handed to `sink`,
/// at that row's state (a viewer reads the bodies' poses there,
/// [`Simulation::body_poses`]); what it does with the simulation must not change the
/// state (reading it does not), or the rows that follow are another run's.
pub fn run_observed(
    scene: &Scene,
    sink: &mut dyn RowSink,
    stop: &AtomicBool,
    progress: impl FnMut(f64),
    observe: &mut dyn FnMut(&mut Simulation),
) -> Result<Summary, Error> {
    let clock = Instant::now();
    let compiled = match compile_scene(scene, stop) {
        Ok(compiled) => compiled,
        Err(Error::Pilot(pilot)) => {
            return Summary::of_pilot(scene, pilot, clock.elapsed().as_secs_f64());
        }
        Err(e) => return Err(e),
    };
    let rows = compiled.setup.plan.rows(0);
    sink.header(&columns(compiled.formulation.sensor_names()), rows)?;
    match Simulation::start(compiled) {
        Ok(mut simulation) => simulation.stream(sink, stop, progress, observe),
        Err(failure) => Ok(failure.report()),
    }
}
