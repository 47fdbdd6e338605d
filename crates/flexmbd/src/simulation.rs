//! Running a scene: compile it with the chosen formulation, find its static equilibrium
//! when `solver.initial_state` asks for it (methods.md §5.4 item 4,
//! `flexmbd_integrators::statics`), integrate it with ALI3-P, record the sensors at the
//! output interval, and summarise the run.
//!
//! A failed step (Newton does not converge, the solution diverges) ends the run
//! with `status = "failed"`, the time and the reason; the rows computed so far
//! are kept.

use std::time::Instant;

use flexmbd_core::{Formulation, Request, SystemTerms};
use flexmbd_integrators::{
    Ali3p, Ali3pSettings, IntegratorError, StartFrom, StaticError, StaticSettings, solve_static,
};
use flexmbd_model::{FormulationKind, InitialState, ModelError, Scene, Stiffening};
use nalgebra::DVector;
use serde::Serialize;

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

/// Compile a scene with the formulation its solver settings name.
pub fn compile(scene: &Scene) -> Result<Box<dyn Formulation>, ModelError> {
    // Stiffening (flexmbd-stiffening): FNL1/FNL2 models are installed by the
    // formulations; the scene transformation (FNL2 axial basis) is done here.
    let scene = &*flexmbd_stiffening::prepare_scene(scene)?;
    let inner: Box<dyn Formulation> = match scene.solver.formulation {
        FormulationKind::Absolute => Box::new(flexmbd_absolute::compile(scene)?),
        FormulationKind::Relative => Box::new(flexmbd_relative::compile(scene)?),
    };
    let offsets = scene.sensor_offsets();
    if offsets.iter().all(|&o| o == 0.0) {
        return Ok(inner);
    }
    Ok(Box::new(Displacements { inner, offsets }))
}

/// A formulation whose `displacement` sensors report the position minus the undeformed
/// position (`Scene::sensor_offsets`), the same way for every formulation.
struct Displacements {
    inner: Box<dyn Formulation>,
    offsets: Vec<f64>,
}

impl Formulation for Displacements {
    fn n_coordinates(&self) -> usize {
        self.inner.n_coordinates()
    }
    fn n_constraints(&self) -> usize {
        self.inner.n_constraints()
    }
    fn initial_guess(&self, q: &mut DVector<f64>, qd: &mut DVector<f64>) {
        self.inner.initial_guess(q, qd)
    }
    fn specified_coordinates(&self) -> &[usize] {
        self.inner.specified_coordinates()
    }
    fn evaluate(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        req: Request,
        out: &mut SystemTerms,
    ) {
        self.inner.evaluate(t, q, qd, req, out)
    }
    fn constant_tangents(&self) -> bool {
        self.inner.constant_tangents()
    }
    fn constant_mass(&self) -> bool {
        self.inner.constant_mass()
    }
    fn symmetric_tangent(&self) -> bool {
        self.inner.symmetric_tangent()
    }
    fn sensor_names(&self) -> &[String] {
        self.inner.sensor_names()
    }
    fn sensors(&mut self, t: f64, q: &DVector<f64>, qd: &DVector<f64>, out: &mut [f64]) {
        self.inner.sensors(t, q, qd, out);
        for (v, o) in out.iter_mut().zip(&self.offsets) {
            *v -= o;
        }
    }
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

/// Why a run could not start.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StartError {
    /// No static equilibrium (`solver.initial_state: StaticEquilibrium`).
    #[error("static start: {0}")]
    Static(#[from] StaticError),
    /// The integrator's consistent initial conditions failed.
    #[error(transparent)]
    Integrator(#[from] IntegratorError),
}

/// Run a scene to its duration (or to the first failure). `progress` is called with the
/// fraction done now and then.
pub fn run(scene: &Scene, mut progress: impl FnMut(f64)) -> Result<(Summary, History), ModelError> {
    let t0 = Instant::now();
    let mut f = compile(scene)?;
    let preprocessing_seconds = t0.elapsed().as_secs_f64();
    let s = &scene.solver;
    let settings = Ali3pSettings {
        step: s.step,
        penalty: s.penalty,
        tol_q: s.newton_tolerance,
        tol_phi: s.newton_tolerance,
        max_iterations: s.max_iterations,
        ..Default::default()
    };
    let steps = (s.duration / s.step).round().max(1.0) as usize;
    let every = s
        .output_interval
        .map_or(1, |o| ((o / s.step).round() as usize).max(1));
    let (formulation, inertia, stiffening) = names(scene);
    let mut history = History {
        header: std::iter::once("t".to_string())
            .chain(f.sensor_names().iter().cloned())
            .collect(),
        rows: Vec::with_capacity(steps / every + 2),
    };
    let ns = f.sensor_names().len();
    let mut summary = Summary {
        scene: scene.name.clone(),
        status: "ok".into(),
        failed_at: None,
        message: None,
        formulation,
        inertia,
        stiffening,
        n_coordinates: f.n_coordinates(),
        n_constraints: f.n_constraints(),
        step: s.step,
        steps: 0,
        newton_iterations: 0,
        factorizations: 0,
        accepted_unconverged: 0,
        failed_steps: 0,
        simulated_seconds: 0.0,
        cpu_seconds: 0.0,
        preprocessing_seconds,
        static_seconds: 0.0,
        static_iterations: 0,
        realtime_factor: 0.0,
        time_evaluation: 0.0,
        time_factorization: 0.0,
        time_projection: 0.0,
        rows: 0,
    };
    let fail = |summary: &mut Summary, t: f64, e: &dyn std::error::Error| {
        summary.status = "failed".into();
        summary.failed_at = Some(t);
        summary.message = Some(e.to_string());
    };
    // The static start is timed apart; the consistent initial conditions count in the run.
    let mut static_q = None;
    if scene.solver.initial_state == InitialState::StaticEquilibrium {
        let t_static = Instant::now();
        let r = solve_static(f.as_mut(), 0.0, &StaticSettings::default());
        summary.static_seconds = t_static.elapsed().as_secs_f64();
        match r {
            Ok(sol) => {
                summary.static_iterations = sol.iterations;
                static_q = Some(sol);
            }
            Err(e) => {
                fail(&mut summary, 0.0, &StartError::from(e));
                return Ok((summary, history));
            }
        }
    }
    let start_clock = Instant::now();
    let integ = match &static_q {
        Some(sol) => Ali3p::new(&mut StartFrom::at_rest(f.as_mut(), sol), 0.0, settings),
        None => Ali3p::new(f.as_mut(), 0.0, settings),
    };
    let mut integ = match integ {
        Ok(i) => i,
        Err(e) => {
            fail(&mut summary, 0.0, &e);
            summary.cpu_seconds = start_clock.elapsed().as_secs_f64();
            return Ok((summary, history));
        }
    };
    let record = |integ: &Ali3p, f: &mut dyn Formulation, history: &mut History| {
        let mut row = vec![0.0; ns + 1];
        row[0] = integ.t;
        f.sensors(integ.t, &integ.q, &integ.qd, &mut row[1..]);
        history.rows.push(row);
    };
    record(&integ, f.as_mut(), &mut history);
    let mut cpu = start_clock.elapsed().as_secs_f64();
    let report_every = (steps / 200).max(1);
    for k in 1..=steps {
        let t_step = Instant::now();
        let r = integ.step(f.as_mut());
        cpu += t_step.elapsed().as_secs_f64();
        if let Err(e) = r {
            fail(&mut summary, integ.t, &e);
            break;
        }
        if k % every == 0 || k == steps {
            record(&integ, f.as_mut(), &mut history);
        }
        if k % report_every == 0 {
            progress(k as f64 / steps as f64);
        }
    }
    let st = &integ.stats;
    summary.steps = st.steps;
    summary.newton_iterations = st.newton_iterations;
    summary.factorizations = st.factorizations;
    summary.accepted_unconverged = st.accepted_unconverged;
    summary.failed_steps = st.failed_steps;
    summary.simulated_seconds = st.steps as f64 * s.step;
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
    Ok((summary, history))
}
