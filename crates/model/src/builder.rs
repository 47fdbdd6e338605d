//! Scenes built in code: typed builders that produce the same [`Scene`] the RON loader
//! produces, checked by the same [`Scene::validate`] (errors name the field and the value; the
//! file is the label given to [`SceneBuilder::new`]).
//!
//! ```
//! use flexmbd_model::builder::{BodyBuilder, SceneBuilder};
//! use flexmbd_model::{Inertia, Joint, JointKind, Sensor, SensorKind, Axis, Solver, GROUND};
//! use flexmbd_core::Dim;
//!
//! // A rigid pendulum: a 1 kg, 1 m bar on a pin at the ground origin, released horizontal.
//! let scene = SceneBuilder::new("pendulum", Dim::Planar)
//!     .gravity([0.0, -9.81, 0.0])
//!     .ground_marker("O", [0.0, 0.0, 0.0])
//!     .body(
//!         BodyBuilder::rigid("bar", 1.0, [0.5, 0.0, 0.0], Inertia::Planar(1.0 / 12.0))
//!             .marker("pin", [0.0, 0.0, 0.0])
//!             .marker("tip", [1.0, 0.0, 0.0]),
//!     )
//!     .joint(Joint::new("pin", JointKind::Revolute { axis: None }, (GROUND, "O"), ("bar", "pin")))
//!     .sensor(Sensor::new("tip_y", SensorKind::position("bar", "tip", Axis::Y)))
//!     .solver(Solver::new(1e-3, 1.0))
//!     .build()
//!     .unwrap();
//! assert_eq!(scene.bodies.len(), 1);
//! // The same scene as RON text, which loads back equal.
//! let text = scene.to_ron().unwrap();
//! let loaded = flexmbd_model::Scene::from_ron_str(&text, "pendulum.ron").unwrap();
//! assert!(loaded.same_as(&scene));
//! ```

use flexmbd_core::Dim;
use flexmbd_fe::BeamBodySpec;

use crate::error::ModelError;
use crate::scene::{
    Axis, Body, BodyModel, Driver, DriverHandling, Force, FormulationKind, Inertia, InitialState,
    Joint, JointKind, Marker, MotionLaw, Orientation, Scene, Sensor, SensorKind, Solver,
    Stiffening, V3, Velocity,
};
use flexmbd_body::InertiaMethod;

mod vehicle;
pub use vehicle::{LinkBuilder, TyreBuilder};

/// Builds a [`Scene`]; [`SceneBuilder::build`] validates it.
#[derive(Clone, Debug)]
pub struct SceneBuilder {
    scene: Scene,
}

impl SceneBuilder {
    /// An empty scene named `name` (also the label its validation errors carry) in `dim`,
    /// without gravity, with [`Solver::new`]`(1e-3, 1.0)` until [`SceneBuilder::solver`].
    pub fn new(name: &str, dim: Dim) -> Self {
        SceneBuilder {
            scene: Scene {
                name: name.to_string(),
                description: String::new(),
                dim,
                gravity: V3::default(),
                ground: Vec::new(),
                initial_velocity: V3::default(),
                bodies: Vec::new(),
                joints: Vec::new(),
                forces: Vec::new(),
                constraints: Vec::new(),
                roads: Vec::new(),
                drivers: Vec::new(),
                sensors: Vec::new(),
                inputs: Vec::new(),
                solver: Solver::new(1e-3, 1.0),
                origin: format!("{name} (built in code)"),
                source: String::new(),
            },
        }
    }

    /// Free text: what the scene is and where its data come from.
    pub fn description(mut self, text: &str) -> Self {
        self.scene.description = text.to_string();
        self
    }

    /// Gravitational acceleration (m/s²), ground components.
    pub fn gravity(mut self, g: [f64; 3]) -> Self {
        self.scene.gravity = V3(g);
        self
    }

    /// A named point of the ground (m).
    pub fn ground_marker(mut self, name: &str, position: [f64; 3]) -> Self {
        self.scene.ground.push(Marker::new(name, position));
        self
    }

    /// A velocity every body has at the start (m/s): [`Scene::initial_velocity`].
    pub fn initial_velocity(mut self, v: [f64; 3]) -> Self {
        self.scene.initial_velocity = V3(v);
        self
    }

    /// A moving body.
    pub fn body(mut self, body: BodyBuilder) -> Self {
        self.scene.bodies.push(body.body);
        self
    }

    /// A joint.
    pub fn joint(mut self, joint: Joint) -> Self {
        self.scene.joints.push(joint);
        self
    }

    /// A force element: a [`Force`], or a [`LinkBuilder`] or [`TyreBuilder`].
    pub fn force(mut self, force: impl Into<Force>) -> Self {
        self.scene.forces.push(force.into());
        self
    }

    /// A constraint between two markers ([`crate::scene_constraints::Constraint::distance`],
    /// [`point_in_plane`](crate::scene_constraints::Constraint::point_in_plane)).
    pub fn constraint(mut self, constraint: crate::scene_constraints::Constraint) -> Self {
        self.scene.constraints.push(constraint);
        self
    }

    /// A road the tyres roll on ([`crate::Road::new`]).
    pub fn road(mut self, road: crate::roads::Road) -> Self {
        self.scene.roads.push(road);
        self
    }

    /// A prescribed motion of the joint `joint`.
    pub fn driver(mut self, name: &str, joint: &str, law: MotionLaw) -> Self {
        self.scene.drivers.push(Driver {
            name: name.to_string(),
            joint: joint.to_string(),
            law,
        });
        self
    }

    /// A named output.
    pub fn sensor(mut self, sensor: Sensor) -> Self {
        self.scene.sensors.push(sensor);
        self
    }

    /// The solver settings.
    pub fn solver(mut self, solver: Solver) -> Self {
        self.scene.solver = solver;
        self
    }

    /// The scene, validated as a loaded one is ([`Scene::validate`]).
    pub fn build(self) -> Result<Scene, ModelError> {
        self.scene.validate()?;
        Ok(self.scene)
    }
}

/// Builds a [`Body`] for [`SceneBuilder::body`].
#[derive(Clone, Debug)]
pub struct BodyBuilder {
    body: Body,
}

impl BodyBuilder {
    fn with_model(name: &str, model: BodyModel) -> Self {
        BodyBuilder {
            body: Body {
                name: name.to_string(),
                origin: V3::default(),
                orientation: Orientation::Identity,
                model,
                flexible: true,
                markers: Vec::new(),
                velocity: Velocity::default(),
                initial_modes: Vec::new(),
                inertia_terms: Default::default(),
            },
        }
    }

    /// A rigid body: mass (kg), centre of mass (body components, m), inertia about it.
    pub fn rigid(name: &str, mass: f64, center_of_mass: [f64; 3], inertia: Inertia) -> Self {
        Self::with_model(
            name,
            BodyModel::Rigid {
                mass,
                center_of_mass: V3(center_of_mass),
                inertia,
            },
        )
    }

    /// A flexible Euler–Bernoulli beam body from its FE specification (run flexible unless
    /// [`BodyBuilder::flexible`]`(false)`): a straight beam ([`BeamBodySpec::straight`]), a
    /// polyline, or a beam frame of named nodes and members ([`BeamBodySpec::frame`]).
    pub fn beam(name: &str, spec: BeamBodySpec) -> Self {
        Self::with_model(name, BodyModel::Beam(spec))
    }

    /// Frame origin at t = 0 (ground components, m).
    pub fn origin(mut self, origin: [f64; 3]) -> Self {
        self.body.origin = V3(origin);
        self
    }

    /// Frame orientation at t = 0.
    pub fn orientation(mut self, orientation: Orientation) -> Self {
        self.body.orientation = orientation;
        self
    }

    /// A named point (body components, m).
    pub fn marker(mut self, name: &str, position: [f64; 3]) -> Self {
        self.body.markers.push(Marker::new(name, position));
        self
    }

    /// Initial velocity guess: of the frame origin (m/s) and angular (rad/s), ground components.
    pub fn velocity(mut self, linear: [f64; 3], angular: [f64; 3]) -> Self {
        self.body.velocity = Velocity {
            linear: V3(linear),
            angular: V3(angular),
        };
        self
    }

    /// Run a beam body flexible (`true`, the default) or as the rigid body of its mass.
    pub fn flexible(mut self, flexible: bool) -> Self {
        self.body.flexible = flexible;
        self
    }

    /// Initial modal coordinates of a flexible body.
    pub fn initial_modes(mut self, modes: Vec<f64>) -> Self {
        self.body.initial_modes = modes;
        self
    }

    /// The inertia terms a flexible body keeps (every term by default).
    pub fn inertia_terms(mut self, terms: flexmbd_body::InertiaTerms) -> Self {
        self.body.inertia_terms = terms;
        self
    }
}

impl Marker {
    /// A named point (m).
    pub fn new(name: &str, position: [f64; 3]) -> Self {
        Marker {
            name: name.to_string(),
            position: V3(position),
        }
    }
}

impl Joint {
    /// A joint of `kind` between (body, marker) `first` and `second` (`GROUND` for the ground).
    pub fn new(name: &str, kind: JointKind, first: (&str, &str), second: (&str, &str)) -> Self {
        Joint {
            name: name.to_string(),
            kind,
            body1: first.0.to_string(),
            marker1: first.1.to_string(),
            body2: second.0.to_string(),
            marker2: second.1.to_string(),
        }
    }
}

impl Force {
    /// A linear spring–damper between (body, marker) `first` and `second`: stiffness (N/m),
    /// damping (N·s/m), free length (m; the start distance when `None`).
    pub fn spring_damper(
        name: &str,
        first: (&str, &str),
        second: (&str, &str),
        stiffness: f64,
        damping: f64,
        free_length: Option<f64>,
    ) -> Self {
        Force::SpringDamper {
            name: name.to_string(),
            body1: first.0.to_string(),
            marker1: first.1.to_string(),
            body2: second.0.to_string(),
            marker2: second.1.to_string(),
            stiffness,
            damping,
            free_length,
        }
    }
}

impl Sensor {
    /// A sensor reporting `kind` under `name` (its value, not a displacement).
    pub fn new(name: &str, kind: SensorKind) -> Self {
        Sensor {
            name: name.to_string(),
            kind,
            displacement: false,
        }
    }

    /// Report a position sensor's displacement from the undeformed position instead.
    pub fn displacement(mut self) -> Self {
        self.displacement = true;
        self
    }
}

impl SensorKind {
    /// A marker's position component in ground axes.
    pub fn position(body: &str, marker: &str, component: Axis) -> Self {
        SensorKind::Position {
            body: body.to_string(),
            marker: marker.to_string(),
            component,
            frame: None,
        }
    }

    /// A marker's velocity component in ground axes.
    pub fn velocity(body: &str, marker: &str, component: Axis) -> Self {
        SensorKind::Velocity {
            body: body.to_string(),
            marker: marker.to_string(),
            component,
            frame: None,
        }
    }
}

impl Solver {
    /// Step h and duration (s) with every other setting at its default (the same defaults a
    /// scene file that omits them gets): output every step, the absolute formulation, shape
    /// integrals, linear elasticity, Newton tolerance 10⁻⁹ and 20 iterations, the penalty
    /// 4·10⁴ m_ref/h², the given start.
    pub fn new(step: f64, duration: f64) -> Self {
        Solver {
            step,
            duration,
            output_interval: None,
            formulation: FormulationKind::Absolute,
            inertia: InertiaMethod::ShapeIntegrals,
            stiffening: Stiffening::Linear,
            newton_tolerance: 1e-9,
            max_iterations: 20,
            penalty: None,
            drivers: DriverHandling::Eliminated,
            initial_state: InitialState::Given,
        }
    }

    /// Output interval (s).
    pub fn output_interval(mut self, interval: f64) -> Self {
        self.output_interval = Some(interval);
        self
    }

    /// The formulation.
    pub fn formulation(mut self, formulation: FormulationKind) -> Self {
        self.formulation = formulation;
        self
    }

    /// The inertia route of the flexible bodies.
    pub fn inertia(mut self, inertia: InertiaMethod) -> Self {
        self.inertia = inertia;
        self
    }

    /// The geometric stiffening method.
    pub fn stiffening(mut self, stiffening: Stiffening) -> Self {
        self.stiffening = stiffening;
        self
    }

    /// How the run starts.
    pub fn initial_state(mut self, initial_state: InitialState) -> Self {
        self.initial_state = initial_state;
        self
    }
}

impl Scene {
    /// The scene as RON text, which [`Scene::from_ron_str`] reads back equal
    /// ([`Scene::same_as`]).
    pub fn to_ron(&self) -> Result<String, ModelError> {
        let config = ron::ser::PrettyConfig::new().depth_limit(4);
        ron::ser::to_string_pretty(self, config).map_err(|e| {
            ModelError::Unsupported(format!("the scene cannot be written as RON: {e}"))
        })
    }

    /// Equal as physics: every field but where the scene was read from (`origin`, `source`,
    /// and the FE specs' origins).
    pub fn same_as(&self, other: &Scene) -> bool {
        let strip = |s: &Scene| {
            let mut s = s.clone();
            s.origin.clear();
            s.source.clear();
            for b in &mut s.bodies {
                if let BodyModel::Beam(spec) = &mut b.model {
                    spec.origin.clear();
                }
            }
            s
        };
        strip(self) == strip(other)
    }
}
