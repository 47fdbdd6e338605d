//! The weights of every flexible body's inertia terms over a pilot run, and the terms
//! chosen by them (issue 31 item 2; `flexmbd terms`; docs/design.md "Inertia terms by
//! weight").
//!
//! The **pilot** is the scene itself with every term kept, in relative coordinates with
//! shape integrals (the route that can drop terms; the motion does not depend on the route),
//! run to the scene's duration or a shorter one. At each output instant (every step without
//! `solver.output_interval`; t = 0 included) each flexible body's motion — frame, modal
//! coordinates, their rates and accelerations, read from the integrator's state — is handed
//! to a [`WeightMeter`], which evaluates `F = M̄Ż − Q̄_v` for every choice of terms and
//! weighs what each group of terms adds, in the body's kinetic-energy norms
//! ([`flexmbd_body::weights`]), and the scene's sensors are recorded. The weights are a
//! property of the motion, so one pilot serves every threshold: [`BodyWeights::choose`]
//! (the weights alone) and [`Pilot::confirm`] (the weights' ladder, each step run in place of
//! the full model and judged against the pilot's sensors: the choice that meets the
//! tolerance on the pilot's horizon, `term_weights/confirm.rs`).

mod confirm;

pub use confirm::{Ladder, TermChoice, Trial, cached_pilot, ladder};

use flexmbd_body::InertiaMethod;
use flexmbd_body::InertiaTerms;
use flexmbd_body::weights::{MotionSample, WeightMeter, WeightTable};
use flexmbd_core::{BodyMotion, InvalidValue};
use flexmbd_model::{FormulationKind, Scene, SensorKind};

use crate::{Error, Simulation};

/// One flexible body's weights.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyWeights {
    /// The body's name in the prepared scene (a substructured beam's pieces have their own).
    pub body: String,
    /// Its modal coordinates.
    pub modes: usize,
    /// The weights of its terms over the pilot.
    pub table: WeightTable,
}

impl BodyWeights {
    /// The cheapest terms whose dropped groups weigh at most `threshold`
    /// ([`WeightTable::choose`]); a threshold outside (0, 1) is refused by name.
    pub fn choose(&self, threshold: f64) -> Result<InertiaTerms, Error> {
        self.table.choose(threshold).map_err(Error::Input)
    }
}

/// The pilot's scene: `scene` with every term kept, relative, shape integrals, run for
/// `duration` (the scene's when `None`).
fn pilot_scene(scene: &Scene, duration: Option<f64>) -> Result<Scene, Error> {
    let mut pilot = scene.clone();
    if let Some(d) = duration {
        if !(d.is_finite() && d > 0.0) {
            return Err(Error::Input(InvalidValue::new(
                "duration",
                d,
                "the pilot's duration must be a positive number of seconds",
            )));
        }
        pilot.solver.duration = pilot.solver.duration.min(d);
    }
    pilot.solver.formulation = FormulationKind::Relative;
    pilot.solver.inertia = InertiaMethod::ShapeIntegrals;
    for b in &mut pilot.bodies {
        b.inertia_terms = InertiaTerms::FULL;
    }
    Ok(pilot)
}

/// A pilot run: the weights of every flexible body's terms and the full model's sensor
/// histories, which [`Pilot::confirm`] judges a choice's run against.
#[derive(Debug)]
pub struct Pilot {
    /// Each weighed body's weights.
    pub weights: Vec<BodyWeights>,
    /// The pilot's scene: every term kept, relative, shape integrals, the pilot's duration.
    pub scene: Scene,
    /// The judged sensors ([`pilot`]).
    pub sensors: Vec<String>,
    /// The output instants (s): t = 0, then every output interval (every step without one).
    pub times: Vec<f64>,
    /// Each judged sensor's values at [`times`](Self::times).
    pub columns: Vec<Vec<f64>>,
    /// The CPU time of the pilot's steps (s; the weighing excluded).
    pub cpu_seconds: f64,
    /// The runs of the ladder made so far, shared by every threshold ([`Pilot::confirm`]).
    trials: std::sync::Mutex<Vec<Trial>>,
}

/// Weigh the inertia terms of every flexible body of `scene` over its pilot run (module
/// doc), to `duration` when given (at most the scene's). A scene without a flexible body,
/// or whose flexible bodies cannot drop terms (FS0), is refused by name; a pilot that fails
/// is the step's error.
pub fn weigh_terms(scene: &Scene, duration: Option<f64>) -> Result<Vec<BodyWeights>, Error> {
    Ok(pilot(scene, duration, &[])?.weights)
}

/// The sensors of `scene` a confirmation judges: `judged` when given (each must be a
/// sensor of the scene), else every sensor but the energy (a truncated model's energy is
/// its own truncated T, not a quantity the full model's run has).
fn judged_sensors(scene: &Scene, judged: &[String]) -> Result<Vec<String>, Error> {
    if judged.is_empty() {
        return Ok(scene
            .sensors
            .iter()
            .filter(|s| !matches!(s.kind, SensorKind::Energy))
            .map(|s| s.name.clone())
            .collect());
    }
    for name in judged {
        if !scene.sensors.iter().any(|s| &s.name == name) {
            let known: Vec<&str> = scene.sensors.iter().map(|s| s.name.as_str()).collect();
            return Err(Error::Input(InvalidValue::new(
                "sensor",
                name,
                format!(
                    "is not a sensor of scene `{}` (its sensors: {})",
                    scene.name,
                    known.join(", ")
                ),
            )));
        }
    }
    Ok(judged.to_vec())
}

/// Run `sim` (prepared from `scene`) to the scene's end, reading its sensors `names` (t
/// first) at the start and at every output instant, `observe` called at each of them; with
/// the CPU time of the steps.
fn run_rows(
    mut sim: Simulation,
    scene: &Scene,
    names: &[String],
    mut observe: impl FnMut(&mut Simulation),
) -> Result<(Vec<Vec<f64>>, f64), Error> {
    let index: Vec<usize> = names
        .iter()
        .map(|n| {
            sim.sensor_names()
                .iter()
                .position(|s| s == n)
                .expect("judged sensors are the scene's")
        })
        .collect();
    let h = scene.solver.step;
    let steps = (scene.solver.duration / h).round() as usize;
    let every = scene
        .solver
        .output_interval
        .map_or(1, |dt| ((dt / h).round() as usize).max(1));
    let mut values = vec![0.0; sim.sensor_names().len()];
    let mut rows = Vec::new();
    let mut record = |sim: &mut Simulation, rows: &mut Vec<Vec<f64>>| {
        sim.read_sensors(&mut values);
        rows.push(
            std::iter::once(sim.time())
                .chain(index.iter().map(|&k| values[k]))
                .collect(),
        );
        observe(sim);
    };
    record(&mut sim, &mut rows);
    let mut cpu = 0.0;
    for k in 1..=steps {
        let clock = std::time::Instant::now();
        let r = sim.step();
        cpu += clock.elapsed().as_secs_f64();
        r?;
        if k % every == 0 || k == steps {
            record(&mut sim, &mut rows);
        }
    }
    Ok((rows, cpu))
}

/// The pilot of `scene` (module doc), to `duration` when given (at most the scene's),
/// recording the sensors `judged` (none named: every sensor but the energy; an unknown one
/// is refused by name). A scene without a flexible body, or whose flexible bodies cannot
/// drop terms (FS0), is refused by name; a pilot that fails is the step's error.
pub fn pilot(scene: &Scene, duration: Option<f64>, judged: &[String]) -> Result<Pilot, Error> {
    let pilot = pilot_scene(scene, duration)?;
    let sensors = judged_sensors(&pilot, judged)?;
    let sim = Simulation::new(&pilot)?;
    let mut meters = Vec::new();
    for (k, pb) in sim.prepared().bodies().iter().enumerate() {
        if !pb.flexible || pb.body.n_modes() == 0 {
            continue;
        }
        let name = sim.prepared().scene().bodies[pb.index].name.clone();
        let meter = WeightMeter::new(&pb.body, &format!("bodies[{name}]")).map_err(Error::Input)?;
        meters.push((k, name, pb.body.n_modes(), meter));
    }
    if meters.is_empty() {
        return Err(Error::Input(InvalidValue::new(
            "scene",
            &scene.name,
            "the scene has no flexible body with modes: rigid bodies have no inertia terms to \
             weigh (a beam runs flexible with --set bodies.NAME.flexible=true)",
        )));
    }
    let mut motions: Vec<BodyMotion> = Vec::new();
    let sample = |sim: &mut Simulation| {
        let reported = sim.body_motions(&mut motions);
        debug_assert!(reported, "the relative formulation reports body motions");
        for (k, _, _, meter) in meters.iter_mut() {
            let m = &motions[*k];
            let f = &m.frame;
            meter.add(&MotionSample {
                state: flexmbd_body::BodyState::from_origin_velocity(
                    f.origin,
                    f.rotation,
                    f.angular_velocity,
                    f.velocity,
                    &m.modes,
                    &m.mode_rates,
                ),
                origin_acceleration: f.acceleration,
                angular_acceleration: f.angular_acceleration,
                mode_accelerations: &m.mode_accelerations,
            });
        }
    };
    let (rows, cpu_seconds) = run_rows(sim, &pilot, &sensors, sample)?;
    let times = rows.iter().map(|r| r[0]).collect();
    let columns = (1..=sensors.len())
        .map(|k| rows.iter().map(|r| r[k]).collect())
        .collect();
    Ok(Pilot {
        weights: meters
            .into_iter()
            .map(|(_, body, modes, meter)| BodyWeights {
                body,
                modes,
                table: meter.table(),
            })
            .collect(),
        scene: pilot,
        sensors,
        times,
        columns,
        cpu_seconds,
        trials: std::sync::Mutex::new(Vec::new()),
    })
}

/// `scene` with each weighed body's terms set to its choice at `threshold` (bodies of
/// `weights` the scene does not name, a substructured beam's pieces, are left as they are),
/// and the choices made.
pub fn apply_choice(
    scene: &Scene,
    weights: &[BodyWeights],
    threshold: f64,
) -> Result<(Scene, Vec<(String, InertiaTerms)>), Error> {
    let mut out = scene.clone();
    let mut chosen = Vec::new();
    for w in weights {
        let terms = w.choose(threshold)?;
        if let Some(b) = out.bodies.iter_mut().find(|b| b.name == w.body) {
            b.inertia_terms = terms;
            chosen.push((w.body.clone(), terms));
        }
    }
    Ok((out, chosen))
}
