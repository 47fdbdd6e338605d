//! **flexmbd** — real-time flexible multibody dynamics after U. Lugrís, *Real-time methods
//! in flexible multibody dynamics* (PhD thesis, University of La Coruña, 2008): mechanisms
//! of rigid and flexible bodies, the flexible ones floating-frame bodies reduced by
//! Craig–Bampton from finite-element beams, simulated in natural (absolute) or
//! semi-recursive (relative) coordinates by the ALI3-P integrator.
//!
//! # A first simulation
//!
//! Load a scene, build a [`Simulation`], step it and read a sensor. The flexible pendulum
//! (a 1 m, 1 kg steel bar pinned at one end and released from horizontal) swings down
//! for half a second; its tip stays on the circle the pin allows (the bar stretches by
//! far less than a millimetre) and its total energy stays at its initial 0 J:
//!
//! ```
//! use flexmbd::{Simulation, model::Scene};
//!
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/flexible_pendulum.ron");
//! let scene = Scene::load(path)?;
//! let mut sim = Simulation::new(&scene)?;
//! sim.advance_to(0.5)?; // 500 steps of h = 1 ms
//!
//! let names = sim.sensor_names().to_vec();
//! let values = sim.sensors();
//! let sensor = |name: &str| values[names.iter().position(|n| n == name).unwrap()];
//! let (x, y) = (sensor("tip_x"), sensor("tip_y"));
//! assert!(y < -0.9, "the bar has swung down: tip at y = {y} m");
//! assert!((x.hypot(y) - 1.0).abs() < 1e-3, "tip {} m from the pin", x.hypot(y));
//! // Within 0.1 % of m g L/2 = 4.9 J, the potential energy the swing has released.
//! assert!(sensor("energy").abs() < 1e-3 * 4.9, "energy {} J", sensor("energy"));
//! # Ok::<(), flexmbd::Error>(())
//! ```
//!
//! [`simulation::run`] does the same to the scene's duration and returns a [`Summary`]
//! and the sensor [`History`] at the output interval; [`simulation::run_into`] hands each
//! row to an [`output::RowSink`] as soon as it is computed instead, and stops between two
//! steps when a flag is set. The `flexmbd` command-line program (crate `flexmbd-cli`)
//! streams the rows to a CSV file and prints the summary as text or JSON.
//!
//! # Inputs between steps
//!
//! A scene declares named **inputs** ([`model::inputs`]): a `Load`'s force and torque on a
//! marker, a driver's θ, θ̇, θ̈ (instead of its law), a road's offset, a spring's or link's
//! stiffness and damping scale. The host looks an input up once and sets it before every
//! step, allocation-free ([`Simulation::input`], [`Simulation::set_input`]); sensors are
//! read by name or all at once, the state read and written, and a failed step leaves the
//! last good state to go on from ([`simulation::host`]). A torque does the work τ Δθ:
//!
//! ```
//! use flexmbd::model::{Axis, Force, Input, InputKind, Scene, Sensor, SensorKind, V3};
//! use flexmbd::Simulation;
//!
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/double_four_bar.ron");
//! let mut scene = Scene::load(path)?;
//! // A motor on the first crank at its pin: no torque until the host sets one.
//! scene.forces.push(Force::Load {
//!     name: "motor".into(),
//!     body: "crank1".into(),
//!     marker: "A".into(),
//!     force: V3([0.0; 3]),
//!     torque: V3([0.0; 3]),
//! });
//! scene.sensors.push(Sensor {
//!     name: "crank1_angle".into(),
//!     kind: SensorKind::Angle { body: "crank1".into(), axis: Axis::Z },
//!     displacement: false,
//! });
//! scene.inputs.push(Input {
//!     name: "motor".into(),
//!     kind: InputKind::Load { force: "motor".into() },
//! });
//! let mut sim = Simulation::new(&scene)?;
//! let motor = sim.input("motor")?; // once
//! let (e0, a0) = (sim.sensor("energy")?, sim.sensor("crank1_angle")?);
//! while sim.time() < 0.5 {
//!     // Planar: F_x, F_y, 0, 0, 0, τ_z (N, N·m), ground components.
//!     sim.set_input(motor, &[0.0, 0.0, 0.0, 0.0, 0.0, 2.0])?; // every step, no allocation
//!     sim.step()?;
//! }
//! // The mechanical energy changed by the torque's work τ Δθ (to 0.2 %).
//! let work = 2.0 * (sim.sensor("crank1_angle")? - a0);
//! let gained = sim.sensor("energy")? - e0;
//! assert!((gained - work).abs() < 2e-3 * work.abs(), "{gained} J, τ Δθ = {work} J");
//! assert!(sim.input("motr").is_err()); // a name the scene does not declare
//! # Ok::<(), flexmbd::Error>(())
//! ```
//!
//! # The principal types
//!
//! - [`model::Scene`]: the physics once — bodies, joints, forces, constraints between
//!   markers (distance, point in plane), drivers, sensors and solver settings, from a RON file in `models/` or built in code; validated on loading.
//! - [`Simulation`]: a scene compiled and under way — [`Simulation::step`],
//!   [`Simulation::advance_to`], [`Simulation::read_sensors`] (no allocation),
//!   [`Simulation::set_input`], [`Simulation::checkpoint`] / [`Simulation::restore`],
//!   [`Simulation::set_state`], [`Simulation::run`]; a host whose user may cancel passes a
//!   stop flag to [`Simulation::new_or_stop`], [`Simulation::advance_to_or_stop`] or
//!   [`simulation::run_into`]; [`Simulation::body_poses`] gives every body's frame and
//!   modal coordinates (what the `flexmbd-viewer` crate animates).
//! - [`Summary`] and [`History`]: what a run reports (counters, CPU times, status) and the
//!   sensor values it recorded.
//! - [`Error`]: every failure, from a refused scene to a step that does not converge, with
//!   the lower crates' errors kept whole.
//! - [`core::Formulation`], [`integrators::Ali3p`], [`integrators::Ali3pSettings`]: the
//!   interface between a formulation and the integrator, for driving them by hand;
//!   [`integrator_settings`] maps a scene's solver block to the settings.
//!
//! # Data flow
//!
//! One way, each stage handing the next plain data:
//!
//! ```text
//! scene  ──►  prepared scene  ──►  formulation  ──►  integrator  ──►  Simulation  ──►  outputs
//! (RON)       scene rewrites       absolute |        ALI3-P           step, sensors,   Summary,
//!             (FNL2 basis, SBn)    relative                           checkpoint       History
//! ```
//!
//! The crates, re-exported here in that order:
//!
//! - [`core`]: shared vocabulary — dimension, skew helpers, the error that names a bad
//!   input, and the [`core::Formulation`] trait the integrators drive;
//! - [`fe`]: finite-element preprocessing — beams, modal analysis, Craig–Bampton, the mass
//!   cloud and the 13 inertia shape integrals;
//! - [`body`]: the reduced flexible body at run time, its inertia terms by B-matrix
//!   projection or by shape integrals, and its elastic forces;
//! - [`stiffening`]: geometric stiffening — the FNL1 and FNL2 elastic models,
//!   foreshortening, and the scene rewrites that prepare a scene for them (FNL2's axial
//!   basis, substructuring);
//! - [`model`]: the scene format (RON) with its validation;
//! - [`absolute`]: the natural-coordinate formulation;
//! - [`relative`]: the semi-recursive relative-coordinate formulation;
//! - [`ancf`]: the large-deformation reference of the spin-up beam (ANCF cables);
//! - [`integrators`]: ALI3-P on the trapezoidal rule, its consistent initial conditions and
//!   the static-equilibrium start;
//! - [`simulation`]: [`Simulation`], [`simulation::run`], [`simulation::run_into`] and
//!   [`Summary`];
//! - [`output`]: [`output::RowSink`], where a run's rows go, and [`History`], the sink that
//!   keeps them in memory;
//! - [`equilibrium()`] and [`vibration()`]: a scene's static equilibrium (coordinates,
//!   multipliers, sensors, force elements' forces, joint reactions) and its linearised free vibration about it (frequencies, damping
//!   ratios, the sensors each mode moves), the `flexmbd equilibrium` and `flexmbd eigen`
//!   commands.
//!
//! `docs/design.md` records the design and its choices.

#![warn(missing_docs)]

pub use flexmbd_absolute as absolute;
pub use flexmbd_ancf as ancf;
pub use flexmbd_body as body;
pub use flexmbd_core as core;
pub use flexmbd_fe as fe;
pub use flexmbd_integrators as integrators;
pub use flexmbd_model as model;
pub use flexmbd_relative as relative;
pub use flexmbd_stiffening as stiffening;

pub mod equilibrium;
mod error;
pub mod inventory;
pub mod output;
mod pilot;
pub mod simulation;
pub mod sweep;
pub mod term_weights;
pub mod vibration;

pub use equilibrium::{Equilibrium, equilibrium};
pub use error::{Error, PilotError, PilotOutcome};
pub use simulation::{History, Simulation, Summary, integrator_settings};
pub use vibration::{Vibration, vibration};
