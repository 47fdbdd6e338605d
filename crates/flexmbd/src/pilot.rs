//! The pilot run of proper orthogonal modes (`mode_selection: ProperOrthogonal`,
//! docs/methods.md §1.6, [`flexmbd_fe::pod`]).
//!
//! Before a scene is prepared, every flexible beam that asks for proper orthogonal modes is
//! given the modal coordinates of a **pilot run**: the same scene (stiffening, step, start;
//! in relative coordinates with shape integrals, the cheapest route to the same motion,
//! unless that formulation cannot start the scene, so that the routes of a sweep share one
//! pilot) in which those bodies keep their lowest K fixed-interface
//! normal modes ([`flexmbd_fe::pod::pilot_spec`]), its sensors replaced by one `Modal`
//! sensor per dynamic mode of each such body, run to the longest of their pilot durations
//! ([`flexmbd_fe::pod::pilot_duration`], at most the scene's) with every step recorded (every
//! k-th beyond `MAX_PILOT_SAMPLES` steps, so that the record's memory is bounded). All the bodies share
//! that one run; each keeps the samples up to its own duration. The FE stage then builds
//! the body's basis from the record ([`flexmbd_fe::BeamBodySpec::pilot`]). The pilot is
//! part of preparing the scene: its time is in a run's `preprocessing_seconds`.
//!
//! The bodies are found in the scene as its stiffening method rewrites it, so that the
//! pilot's basis is that of the final reduction: FNL2 and FS0 drop the axial modes (and
//! FNL2 turns the axial DOFs into static modes, re-pointing the `Modal` sensors), and SBn's
//! substructures keep the lowest modes (no pilot). Deterministic: the same scene gives the
//! same record, bit for bit.
//!
//! A pilot that fails, or that the caller's stop flag ends between two of its steps (the
//! flag a run looks at: [`crate::simulation::run_into`]), is an [`Error::Pilot`]: the
//! scene is valid, its run failed or was stopped. Its record is dropped whole: no basis is
//! built from part of a pilot, and only a finished pilot enters the process's cache.

use std::borrow::Cow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use flexmbd_body::InertiaMethod;
use flexmbd_fe::imported::ImportedBodySpec;
use flexmbd_fe::pod::{PilotRecord, candidate_count, pilot_duration, pilot_spec};
use flexmbd_fe::{BeamBodySpec, ModeSelection};
use flexmbd_model::rewrite::rewrite_for_stiffening;
use flexmbd_model::scene::{BodyModel, Sensor, SensorKind};
use flexmbd_model::{FormulationKind, ModelError, PreparedScene, Scene};
use nalgebra::DMatrix;

use crate::{Error, PilotError, PilotOutcome, Simulation};

/// One body that needs a pilot, as the final reduction sees it (the rewritten spec).
struct PilotBody {
    /// Index in `Scene::bodies`.
    index: usize,
    /// K, the candidate normal modes the pilot keeps.
    candidates: usize,
    /// The axial modes kept beside them.
    axial: usize,
    /// How long its pilot runs (s).
    duration: f64,
}

impl PilotBody {
    /// The rows of its record: the pilot basis' dynamic modes.
    fn modes(&self) -> usize {
        self.candidates + self.axial
    }
}

/// The scene prepared with its pilot records ([`with_pilot_records`]), the pilot ended
/// between two steps when `stop` is set.
pub(crate) fn prepared_scene(scene: &Scene, stop: &AtomicBool) -> Result<PreparedScene, Error> {
    Ok(PreparedScene::new(&*with_pilot_records(scene, stop)?)?)
}

/// `scene` with the pilot record of every flexible beam that asks for proper orthogonal
/// modes, from one pilot run (borrowed unchanged when no body asks), ended between two
/// steps when `stop` is set ([`PilotOutcome::Interrupted`]).
pub(crate) fn with_pilot_records<'a>(
    scene: &'a Scene,
    stop: &AtomicBool,
) -> Result<Cow<'a, Scene>, Error> {
    let bodies = pilot_bodies(scene)?;
    if bodies.is_empty() {
        return Ok(Cow::Borrowed(scene));
    }
    let pilot = pilot_scene(scene, &bodies);
    let records = cached_pilot(scene, &pilot, &bodies, stop)?;
    let mut out = scene.clone();
    for (b, record) in bodies.iter().zip(records) {
        match &mut out.bodies[b.index].model {
            BodyModel::Beam(spec) => spec.pilot = Some(Arc::new(record)),
            BodyModel::Imported(spec) => spec.pilot = Some(Arc::new(record)),
            BodyModel::Rigid { .. } => {}
        }
    }
    Ok(Cow::Owned(out))
}

/// A beam of `scene` that runs flexible with proper orthogonal modes.
fn asks_for_pilot(spec: &BeamBodySpec, flexible: bool) -> bool {
    flexible && spec.mode_selection == ModeSelection::ProperOrthogonal && spec.normal_modes > 0
}

/// An imported body of `scene` that runs flexible with proper orthogonal modes.
fn imported_asks_for_pilot(spec: &ImportedBodySpec, flexible: bool) -> bool {
    flexible && spec.mode_selection == ModeSelection::ProperOrthogonal && spec.normal_modes > 0
}

/// The bodies that need a pilot, judged on the scene as its stiffening method rewrites it.
fn pilot_bodies(scene: &Scene) -> Result<Vec<PilotBody>, ModelError> {
    let asks = scene.bodies.iter().any(|b| match &b.model {
        BodyModel::Beam(spec) => asks_for_pilot(spec, b.flexible),
        BodyModel::Imported(spec) => imported_asks_for_pilot(spec, b.flexible),
        BodyModel::Rigid { .. } => false,
    });
    if !asks {
        return Ok(Vec::new());
    }
    let rewritten = rewrite_for_stiffening(scene)?;
    let mut bodies = Vec::new();
    for b in &rewritten.bodies {
        let (candidates, axial, duration) = match &b.model {
            BodyModel::Beam(spec) if asks_for_pilot(spec, b.flexible) => (
                candidate_count(spec),
                spec.axial_modes,
                pilot_duration(spec, scene.solver.duration),
            ),
            BodyModel::Imported(spec) if imported_asks_for_pilot(spec, b.flexible) => (
                spec.pilot_candidates(),
                0,
                spec.pilot_duration
                    .unwrap_or(flexmbd_fe::pod::DEFAULT_PILOT_FRACTION * scene.solver.duration),
            ),
            _ => continue,
        };
        let Some(index) = scene.bodies.iter().position(|o| o.name == b.name) else {
            continue;
        };
        if !b.initial_modes.is_empty() {
            let field = format!("bodies[{}].initial_modes", b.name);
            return Err(ModelError::Invalid {
                file: scene.origin.clone(),
                line: flexmbd_model::lines::line_of(&scene.source, &field),
                error: flexmbd_core::InvalidValue::new(
                    field,
                    format!("{:?}", b.initial_modes),
                    "a body with mode_selection: ProperOrthogonal starts undeformed: its modes \
                     are known only after the pilot run, which would read these coordinates in \
                     another basis",
                ),
            });
        }
        bodies.push(PilotBody {
            index,
            candidates,
            axial,
            // A pilot runs the scene: never past its end (a `--duration` may shorten it).
            duration: duration.min(scene.solver.duration),
        });
    }
    Ok(bodies)
}

/// The pilot scene: each pilot body on its lowest K modes (and its axial modes as the
/// stiffening method keeps them), one `Modal` sensor per dynamic mode, every step recorded,
/// to the longest pilot duration.
fn pilot_scene(scene: &Scene, bodies: &[PilotBody]) -> Scene {
    let mut pilot = scene.clone();
    pilot.sensors.clear();
    pilot.solver.output_interval = None;
    pilot.solver.duration = bodies.iter().map(|b| b.duration).fold(0.0, f64::max);
    for b in bodies {
        let body = &mut pilot.bodies[b.index];
        let n_static = match &mut body.model {
            BodyModel::Beam(spec) => {
                *spec = BeamBodySpec {
                    normal_modes: b.candidates,
                    axial_modes: b.axial,
                    ..pilot_spec(spec)
                };
                spec.boundary.len()
            }
            BodyModel::Imported(spec) => {
                *spec = spec.pilot_spec();
                spec.n_modes() - spec.normal_modes
            }
            BodyModel::Rigid { .. } => continue,
        };
        for j in 0..b.modes() {
            pilot.sensors.push(Sensor {
                name: format!("pilot_{}_{j}", body.name),
                kind: SensorKind::Modal {
                    body: body.name.clone(),
                    index: n_static + j,
                },
                displacement: false,
            });
        }
    }
    pilot
}

/// The most snapshots a pilot keeps (its record is K × this at most).
const MAX_PILOT_SAMPLES: usize = 100_000;

/// How many pilot runs [`cached_pilot`] keeps.
const CACHED_PILOTS: usize = 16;

/// The records of the last pilot runs, by their pilot scene and durations (most recent last).
type PilotCache = Vec<(String, Arc<Vec<PilotRecord>>)>;
static PILOT_CACHE: Mutex<PilotCache> = Mutex::new(Vec::new());

/// The records of `pilot` ([`run_pilot`]), taken from the last [`CACHED_PILOTS`] pilot runs
/// of this process when one ran the same pilot scene in the same route with the same
/// durations: the pilot is deterministic, so the record is the same bit for bit, and a
/// sweep's runs that differ only in what the pilot does not see (the formulation and
/// inertia route, the count of proper orthogonal modes while K stays, a run timed again
/// alone) share one pilot. Only pilots run in relative coordinates are kept: the key names
/// that route, not the scene's own. Only a finished pilot is kept: one that failed or was
/// stopped (`stop`) returns its error before the cache is touched.
fn cached_pilot(
    scene: &Scene,
    pilot: &Scene,
    bodies: &[PilotBody],
    stop: &AtomicBool,
) -> Result<Vec<PilotRecord>, Box<PilotError>> {
    let relative = relative_route(pilot);
    let durations: Vec<u64> = bodies.iter().map(|b| b.duration.to_bits()).collect();
    let key = format!("{relative:?} {durations:?}");
    let lookup = |cache: &PilotCache| {
        cache
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, records)| Arc::clone(records))
    };
    if let Some(records) = lookup(&PILOT_CACHE.lock().unwrap_or_else(|e| e.into_inner())) {
        return Ok(records.as_ref().clone());
    }
    let (records, ran_relative) = run_pilot(scene, &relative, pilot, bodies, stop)?;
    let mut cache = PILOT_CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if ran_relative && lookup(&cache).is_none() {
        if cache.len() == CACHED_PILOTS {
            cache.remove(0);
        }
        cache.push((key, Arc::new(records.clone())));
    }
    Ok(records)
}

/// `pilot` in relative coordinates with shape integrals, the cheapest route to the same
/// motion (docs/design.md "Proper orthogonal modes").
fn relative_route(pilot: &Scene) -> Scene {
    Scene {
        solver: flexmbd_model::Solver {
            formulation: FormulationKind::Relative,
            inertia: InertiaMethod::ShapeIntegrals,
            ..pilot.solver.clone()
        },
        ..pilot.clone()
    }
}

/// Run the pilot, `relative` (or `pilot`, in the scene's own route, when the relative
/// formulation cannot start it), and split its samples into one record per body, each up
/// to its duration; with whether it ran in relative coordinates. `stop` is looked at
/// before each step, as a run does: once set, the pilot ends with
/// [`PilotOutcome::Interrupted`] and what it recorded is dropped.
fn run_pilot(
    scene: &Scene,
    relative: &Scene,
    pilot: &Scene,
    bodies: &[PilotBody],
    stop: &AtomicBool,
) -> Result<(Vec<PilotRecord>, bool), Box<PilotError>> {
    let failed = |e: Error| pilot_failure(scene, bodies, PilotOutcome::Failed(e));
    let (mut sim, ran_relative) = match Simulation::new(relative) {
        Ok(sim) => (sim, true),
        Err(_) => (Simulation::new(pilot).map_err(failed)?, false),
    };
    let h = sim.step_size();
    // Every step, or every k-th of a pilot longer than MAX_PILOT_SAMPLES steps (bounded
    // memory; many more snapshots than candidate modes either way).
    let steps = (pilot.solver.duration / h).round() as usize;
    let stride = steps.div_ceil(MAX_PILOT_SAMPLES).max(1);
    let mut times = vec![sim.time()];
    let mut samples = vec![sim.sensors()];
    let mut taken = 0;
    while sim.time() + 0.5 * h <= pilot.solver.duration {
        if stop.load(Ordering::Relaxed) {
            let (t, done) = (sim.time(), taken);
            let outcome = PilotOutcome::Interrupted { t, done, steps };
            return Err(pilot_failure(scene, bodies, outcome));
        }
        sim.step().map_err(failed)?;
        taken += 1;
        if taken % stride == 0 {
            times.push(sim.time());
            samples.push(sim.sensors());
        }
    }
    if let Some(bad) = samples.iter().flatten().find(|v| !v.is_finite()) {
        return Err(pilot_failure(scene, bodies, PilotOutcome::NotFinite(*bad)));
    }
    let mut first_row = 0;
    let records = bodies
        .iter()
        .map(|b| {
            let kept = times
                .iter()
                .take_while(|&&t| t <= b.duration + 0.5 * h)
                .count();
            let rows = first_row..first_row + b.modes();
            first_row += b.modes();
            PilotRecord {
                coordinates: DMatrix::from_fn(b.modes(), kept, |i, j| samples[j][rows.start + i]),
                times: times[..kept].to_vec(),
            }
        })
        .collect();
    Ok((records, ran_relative))
}

/// The error of a pilot that gave no record: the first pilot body's `mode_selection`,
/// the bodies, the pilot's duration and `outcome`.
fn pilot_failure(scene: &Scene, bodies: &[PilotBody], outcome: PilotOutcome) -> Box<PilotError> {
    let names: Vec<String> = bodies
        .iter()
        .map(|b| scene.bodies[b.index].name.clone())
        .collect();
    let body = names[0].clone();
    let variant = match &scene.bodies[bodies[0].index].model {
        BodyModel::Imported(_) => "Imported",
        _ => "Beam",
    };
    Box::new(PilotError {
        file: scene.origin.clone(),
        line: flexmbd_model::lines::line_of(
            &scene.source,
            &format!("bodies[{body}].model.{variant}.mode_selection"),
        ),
        body,
        bodies: names,
        duration: bodies.iter().map(|b| b.duration).fold(0.0, f64::max),
        outcome,
    })
}
