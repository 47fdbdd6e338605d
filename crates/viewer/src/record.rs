//! Sampling a run for an animation: the scene is stepped to each output instant
//! t_k = k Δ (Δ = 1 / frames per second, each instant the multiple of the step h nearest to
//! it, as [`Simulation::advance_to`] takes it; the scene's duration is the last), where every
//! body's pose ([`Simulation::body_poses`]) and the sensors are read. A step that fails
//! ends the recording there, the failure kept to be marked in the files.

use std::sync::atomic::AtomicBool;

use flexmbd::core::BodyPose;
use flexmbd::model::Scene;
use flexmbd::{Error, Simulation, Summary};

use crate::springs::Spring;

/// Frames per second of simulated time when none is asked for.
pub const DEFAULT_FRAMES_PER_SECOND: f64 = 60.0;

/// A run sampled at its output instants: what an animation shows.
pub struct Recording {
    /// The scene's name.
    pub scene: String,
    /// The scene as compiled (its bodies as prepared: nodes, mode rows, sections).
    pub bodies: Vec<crate::shapes::BodyShape>,
    /// The output instants (s), increasing.
    pub times: Vec<f64>,
    /// Per frame, the pose of every body (prepared-scene order).
    pub poses: Vec<Vec<BodyPose>>,
    /// The sensors' names.
    pub sensor_names: Vec<String>,
    /// Per frame, the sensors' values.
    pub sensors: Vec<Vec<f64>>,
    /// What ended the run early, a failed step or an interruption: its time (s) and
    /// message.
    pub failure: Option<(f64, String)>,
    /// The run was interrupted (its stop flag set), not failed.
    pub interrupted: bool,
    /// The springs' and links' names.
    pub springs: Vec<String>,
    /// Per frame, the two ends of each spring (m, ground components).
    pub spring_ends: Vec<Vec<[nalgebra::Vector3<f64>; 2]>>,
    /// A spring's shape: a unit cylinder along y, half as thick as the sticks.
    pub spring_shape: crate::shapes::BodyShape,
    /// The roads the tyres roll on, with the extent their wheel centres covered.
    pub roads: Vec<crate::roads::RoadStrip>,
}

/// Run `scene` to its duration and record a frame every 1 / `frames_per_second` s of
/// simulated time (at most one per step). A rate that is not a positive finite number is
/// refused (naming it); a scene that does not compile or start is the error of
/// [`Simulation::new`]; a step that fails ends the recording with [`Recording::failure`]
/// set, the frames before it kept.
pub fn record(scene: &Scene, frames_per_second: f64) -> Result<Recording, Error> {
    record_or_stop(scene, frames_per_second, &AtomicBool::new(false))
}

/// [`record`], `stop` looked at before each step (and by the pilot run of proper
/// orthogonal modes, [`Simulation::new_or_stop`]): once it is set the recording ends,
/// its frames kept, [`Recording::interrupted`] set and the time in
/// [`Recording::failure`].
pub fn record_or_stop(
    scene: &Scene,
    frames_per_second: f64,
    stop: &AtomicBool,
) -> Result<Recording, Error> {
    check_rate(frames_per_second)?;
    let mut sim = Simulation::new_or_stop(scene, stop)?;
    let interval = (1.0 / frames_per_second).max(sim.step_size());
    let duration = scene.solver.duration;
    let (mut recording, springs) = Recording::start(scene, &mut sim);
    let frames = (duration / interval + 1e-9).floor() as usize;
    let targets = (0..=frames)
        .map(|k| k as f64 * interval)
        .chain(std::iter::once(duration));
    for target in targets {
        match sim.advance_to_or_stop(target, stop) {
            Ok(true) => {}
            Ok(false) => {
                let t = sim.time();
                recording.failure = Some((t, format!("interrupted at t = {t} s")));
                recording.interrupted = true;
                break;
            }
            Err(e) => {
                recording.failure = Some((e.failed_at().unwrap_or(sim.time()), e.to_string()));
                break;
            }
        }
        if recording.times.last().is_some_and(|&t| t >= sim.time()) {
            continue; // an instant nearer to the last step than to the next
        }
        recording.push_frame(&springs, &mut sim);
    }
    Ok(recording)
}

impl Recording {
    /// An empty recording of `sim`'s bodies and springs (shapes from its prepared scene and
    /// the markers of `scene`), and the springs to locate at each frame.
    fn start(scene: &Scene, sim: &mut Simulation) -> (Recording, Vec<Spring>) {
        let springs = Spring::of(sim.prepared());
        let recording = Recording {
            scene: scene.name.clone(),
            bodies: crate::shapes::BodyShape::of(sim.prepared(), scene),
            times: Vec::new(),
            poses: Vec::new(),
            sensor_names: sim.sensor_names().to_vec(),
            sensors: Vec::new(),
            failure: None,
            interrupted: false,
            springs: springs.iter().map(|s| s.name.clone()).collect(),
            spring_ends: Vec::new(),
            spring_shape: crate::shapes::BodyShape::cylinder(
                "spring",
                0.5 * crate::shapes::stick_radius(sim.prepared()),
            ),
            roads: crate::roads::RoadStrip::of(sim.prepared()),
        };
        (recording, springs)
    }

    /// A frame at `sim`'s current state: its time, the bodies' poses, the springs' ends and
    /// the sensors.
    fn push_frame(&mut self, springs: &[Spring], sim: &mut Simulation) {
        let mut poses = Vec::new();
        sim.body_poses(&mut poses);
        self.times.push(sim.time());
        let ends = springs
            .iter()
            .map(|s| s.at(sim.prepared(), &poses))
            .collect();
        self.spring_ends.push(ends);
        for road in &mut self.roads {
            road.observe(sim.prepared(), &poses);
        }
        self.poses.push(poses);
        self.sensors.push(sim.sensors());
    }
}

/// A recording made while a run goes on: handed the simulation after each output row
/// ([`Recorder::observe`], the observer of [`flexmbd::simulation::run_observed`]), it keeps
/// a frame at the first row at or past each instant k Δ (Δ = 1 / frames per second, half a
/// step's tolerance) and at the scene's duration, so the animation of a finished run is
/// made from the states the run went through, at most one frame per row, without running
/// it again. Reading the poses does not change the state: the run's rows are those of a
/// run without a recorder, bit for bit.
pub struct Recorder<'a> {
    scene: &'a Scene,
    interval: f64,
    next: f64,
    springs: Vec<Spring>,
    recording: Option<Recording>,
}

impl<'a> Recorder<'a> {
    /// A recorder of a run of `scene` at `frames_per_second` (a positive finite number,
    /// else refused naming it).
    pub fn new(scene: &'a Scene, frames_per_second: f64) -> Result<Recorder<'a>, Error> {
        check_rate(frames_per_second)?;
        Ok(Recorder {
            scene,
            interval: 1.0 / frames_per_second,
            next: 0.0,
            springs: Vec::new(),
            recording: None,
        })
    }

    /// Look at the run after a row: keep a frame when its time has reached the next
    /// instant or the scene's duration.
    pub fn observe(&mut self, sim: &mut Simulation) {
        let half_step = 0.5 * sim.step_size();
        let t = sim.time() + half_step;
        if self.recording.is_none() {
            let (recording, springs) = Recording::start(self.scene, sim);
            self.recording = Some(recording);
            self.springs = springs;
        }
        if t >= self.next || t >= self.scene.solver.duration {
            let recording = self.recording.as_mut().expect("started above");
            recording.push_frame(&self.springs, sim);
            self.next = ((t / self.interval).floor() + 1.0) * self.interval;
        }
    }

    /// The recording of the run that `summary` ends (its failure or interruption marked);
    /// `None` when the run wrote no row (its pilot run or its start failed).
    pub fn finish(self, summary: &Summary) -> Option<Recording> {
        let mut recording = self.recording?;
        let last = recording.times.last().copied().unwrap_or(0.0);
        match summary.status.as_str() {
            "failed" => {
                let message = summary.message.clone().unwrap_or_default();
                recording.failure = Some((summary.failed_at.unwrap_or(last), message));
            }
            "interrupted" => {
                let message = summary
                    .message
                    .clone()
                    .unwrap_or_else(|| format!("interrupted at t = {last} s"));
                recording.failure = Some((last, message));
                recording.interrupted = true;
            }
            _ => {}
        }
        Some(recording)
    }
}

/// Refuse a frame rate that is not a positive finite number, naming it.
fn check_rate(frames_per_second: f64) -> Result<(), Error> {
    if frames_per_second.is_finite() && frames_per_second > 0.0 {
        Ok(())
    } else {
        Err(Error::Input(flexmbd::core::InvalidValue::new(
            "frames per second",
            frames_per_second,
            "must be a positive finite number",
        )))
    }
}
