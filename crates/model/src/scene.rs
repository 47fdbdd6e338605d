//! The scene: the physics described once, independent of the formulation that
//! will run it. Units are SI throughout (m, kg, s, N, rad); vectors are written
//! `(x, y)` in 2D scenes and `(x, y, z)` in 3D scenes.

use flexmbd_body::{InertiaMethod, InertiaTerms};
use flexmbd_core::Dim;
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use serde::{Deserialize, Serialize};

pub use crate::scene_constraints::{CONSTRAINT_TOLERANCE, Constraint};
pub use crate::sensor_spec::{
    ElementQuantity, InterfaceQuantity, Sensor, SensorKind, StressQuantity,
};
pub use flexmbd_fe::import::{ImportOptions, PointMass};
/// The beam body of a scene, its nodal DOFs and the imported FE body are FE
/// preprocessing's own types.
pub use flexmbd_fe::imported::{
    Coupling, ImportSource, ImportedBodySpec, ImportedFrame, InterfaceSpec, NodeSelection, Xyz,
};
pub use flexmbd_fe::{BeamBodySpec, Dof, NodeDof, ReferenceCondition};

/// A vector written with 2 (planar) or 3 numbers; stored with z = 0 in 2D.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<f64>", into = "Vec<f64>")]
pub struct V3(pub [f64; 3]);

impl TryFrom<Vec<f64>> for V3 {
    type Error = String;
    fn try_from(v: Vec<f64>) -> Result<Self, String> {
        match v.as_slice() {
            [x, y] => Ok(V3([*x, *y, 0.0])),
            [x, y, z] => Ok(V3([*x, *y, *z])),
            _ => Err(format!(
                "expected a vector of 2 or 3 numbers, found {} numbers",
                v.len()
            )),
        }
    }
}

impl From<V3> for Vec<f64> {
    fn from(v: V3) -> Self {
        v.0.to_vec()
    }
}

impl V3 {
    /// As a nalgebra vector.
    pub fn vec(&self) -> Vector3<f64> {
        Vector3::from(self.0)
    }
}

/// The name of the implicit fixed body; its markers are [`Scene::ground`].
pub const GROUND: &str = "ground";

/// A whole scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Short name.
    pub name: String,
    /// Free text: what the scene is and where its data come from.
    #[serde(default)]
    pub description: String,
    /// Planar (x–y) or spatial.
    pub dim: Dim,
    /// Gravitational acceleration (m/s²), ground components.
    #[serde(default)]
    pub gravity: V3,
    /// Named points of the fixed ground (ground components, m).
    #[serde(default)]
    pub ground: Vec<Marker>,
    /// A velocity every body has at the start, beside its own `velocity` (m/s, ground
    /// components): a whole vehicle driving forward. With `solver.initial_state:
    /// StaticEquilibrium` the equilibrium is found at rest and then every body moves at
    /// this velocity ([`Scene::with_initial_velocity`]). `--set initial_velocity.0=10` sets
    /// its x component.
    #[serde(default)]
    pub initial_velocity: V3,
    /// The moving bodies.
    pub bodies: Vec<Body>,
    /// Joints between bodies (or a body and the ground).
    #[serde(default)]
    pub joints: Vec<Joint>,
    /// Force elements.
    #[serde(default)]
    pub forces: Vec<Force>,
    /// Constraints between two markers that are not joints: distances, points in planes
    /// ([`crate::scene_constraints`]).
    #[serde(default)]
    pub constraints: Vec<Constraint>,
    /// Road profiles the tyres roll on ([`crate::roads`]).
    #[serde(default)]
    pub roads: Vec<crate::roads::Road>,
    /// Prescribed joint motions.
    #[serde(default)]
    pub drivers: Vec<Driver>,
    /// Named outputs, one CSV column each.
    #[serde(default)]
    pub sensors: Vec<Sensor>,
    /// Named inputs a host sets between steps ([`crate::inputs`]).
    #[serde(default)]
    pub inputs: Vec<crate::inputs::Input>,
    /// Solver settings.
    pub solver: Solver,
    /// File the scene was read from (named in errors).
    #[serde(skip)]
    pub origin: String,
    /// The text the scene was read from (empty for a scene built in code): validation
    /// errors find the line of their field in it ([`crate::lines`]).
    #[serde(skip)]
    pub source: String,
}

/// A named point of a body, in body-frame components (m). On a flexible body it
/// must sit on an FE node (joints attach to nodes).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Marker {
    /// Name, unique within its body.
    pub name: String,
    /// Position (m), body components (ground components for ground markers).
    pub position: V3,
}

/// Orientation of a body frame in the ground at t = 0.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum Orientation {
    /// Body axes parallel to the ground axes.
    #[default]
    Identity,
    /// Planar rotation by an angle about z (rad).
    Angle(f64),
    /// Rotation by `angle` (rad) about `axis` (ground components).
    AxisAngle {
        /// Rotation axis (normalised on use).
        axis: V3,
        /// Angle (rad).
        angle: f64,
    },
    /// Body x and y axes in ground components (orthonormalised: z = x × y, y = z × x).
    Axes {
        /// Body x axis.
        x: V3,
        /// Body y axis (approximately).
        y: V3,
    },
}

impl Orientation {
    /// The rotation matrix A (columns: body axes in ground components).
    pub fn matrix(&self) -> Matrix3<f64> {
        match self {
            Orientation::Identity => Matrix3::identity(),
            Orientation::Angle(a) => *Rotation3::from_axis_angle(&Vector3::z_axis(), *a).matrix(),
            Orientation::AxisAngle { axis, angle } => {
                *Rotation3::from_axis_angle(&Unit::new_normalize(axis.vec()), *angle).matrix()
            }
            Orientation::Axes { x, y } => {
                let ex = x.vec().normalize();
                let ez = ex.cross(&y.vec()).normalize();
                let ey = ez.cross(&ex);
                Matrix3::from_columns(&[ex, ey, ez])
            }
        }
    }
}

/// Initial velocity of a body frame: its origin's velocity and its angular velocity, ground components.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Velocity {
    /// Velocity of the frame origin (m/s).
    #[serde(default)]
    pub linear: V3,
    /// Angular velocity (rad/s); in 2D only z is used.
    #[serde(default)]
    pub angular: V3,
}

/// One moving body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// Name, unique in the scene (not `ground`).
    pub name: String,
    /// Frame origin at t = 0, ground components (m).
    #[serde(default)]
    pub origin: V3,
    /// Frame orientation at t = 0.
    #[serde(default)]
    pub orientation: Orientation,
    /// Mass model.
    pub model: BodyModel,
    /// For a beam model: run it flexible (`true`, the default) or as the rigid body with
    /// the beam's mass properties (`false`). Ignored for rigid models.
    #[serde(default = "yes")]
    pub flexible: bool,
    /// Named points (body components).
    #[serde(default)]
    pub markers: Vec<Marker>,
    /// Initial velocity guess (made consistent with the joints before the first step).
    #[serde(default)]
    pub velocity: Velocity,
    /// Initial modal coordinates y(0) of a flexible body (the rest are zero).
    #[serde(default)]
    pub initial_modes: Vec<f64>,
    /// The inertia terms a flexible body keeps (issue 31): `(order: 0|1|2, velocity: bool,
    /// coupling: bool)`, every term by default; both formulations, shape integrals
    /// (`flexmbd_body::InertiaTerms`, docs/design.md "Inertia terms as a model choice").
    #[serde(default)]
    pub inertia_terms: InertiaTerms,
}

fn yes() -> bool {
    true
}

/// The mass model of a body.
// A scene holds a few bodies, read once at setup: a beam's 320 bytes inline cost nothing,
// and a Box would show in every `BodyModel::Beam(spec)` a user writes.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum BodyModel {
    /// A rigid body.
    Rigid {
        /// Mass (kg).
        mass: f64,
        /// Centre of mass, body components (m).
        center_of_mass: V3,
        /// Inertia about the centre of mass, body axes.
        inertia: Inertia,
    },
    /// A flexible Euler–Bernoulli beam body (FE model, Craig–Bampton modes).
    Beam(BeamBodySpec),
    /// A flexible body from an FE export (Abaqus, Ansys, CalculiX, Matrix Market; 3D
    /// scenes): its files relative to the scene file, interfaces, frame and modes
    /// (docs/import.md). Its markers sit on interface points or FE nodes.
    Imported(ImportedBodySpec),
}

impl Body {
    /// The body runs with modal coordinates: a beam or an imported FE model with
    /// `flexible: true` (its markers sit on nodes).
    pub fn runs_flexible(&self) -> bool {
        self.flexible && !matches!(self.model, BodyModel::Rigid { .. })
    }

    /// The modal coordinates the scene declares for the body (a flexible beam's boundary,
    /// normal and axial modes; an imported body's six per boundary interface and its normal
    /// modes; none when it runs rigid). The stiffening rewrite may add more (FNL2).
    pub fn declared_modes(&self) -> usize {
        if !self.flexible {
            return 0;
        }
        match &self.model {
            BodyModel::Rigid { .. } => 0,
            BodyModel::Beam(spec) => spec
                .boundary
                .len()
                .saturating_add(spec.normal_modes)
                .saturating_add(spec.axial_modes),
            BodyModel::Imported(spec) => spec.n_modes(),
        }
    }
}

/// Inertia about the centre of mass (kg·m²), body axes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Inertia {
    /// Planar: I_zz only.
    Planar(f64),
    /// Principal values along the body axes (I_xx, I_yy, I_zz).
    Diagonal(V3),
    /// Full symmetric tensor, rows.
    Full([[f64; 3]; 3]),
}

impl Inertia {
    /// The 3×3 tensor (planar: diag(0, 0, I_zz) — a planar body is a thin sheet in z = 0
    /// whose out-of-plane inertia does not enter 2D dynamics).
    pub fn tensor(&self) -> Matrix3<f64> {
        match self {
            Inertia::Planar(izz) => Matrix3::from_diagonal(&Vector3::new(0.0, 0.0, *izz)),
            Inertia::Diagonal(d) => Matrix3::from_diagonal(&d.vec()),
            Inertia::Full(r) => Matrix3::from_row_slice(&[
                r[0][0], r[0][1], r[0][2], r[1][0], r[1][1], r[1][2], r[2][0], r[2][1], r[2][2],
            ]),
        }
    }
}

/// A joint between marker `marker1` of `body1` and marker `marker2` of `body2`
/// (`ground` for the fixed body). The two markers coincide at t = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Joint {
    /// Name, unique among joints.
    pub name: String,
    /// Type and axes.
    pub kind: JointKind,
    /// First body (the parent, when the tree is built from the ground).
    pub body1: String,
    /// Marker on the first body.
    pub marker1: String,
    /// Second body.
    pub body2: String,
    /// Marker on the second body.
    pub marker2: String,
}

/// Joint types. Axes are ground components at t = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum JointKind {
    /// Rotation about one axis (2D: about z; the axis is implied).
    Revolute {
        /// Axis (3D only).
        #[serde(default)]
        axis: Option<V3>,
    },
    /// Ball joint (3D).
    Spherical,
    /// Cardan joint with cross arms `axis1` (fixed in body 1) and `axis2` (fixed in body 2), 3D.
    Universal {
        /// Arm fixed in body 1.
        axis1: V3,
        /// Arm fixed in body 2, perpendicular to `axis1`.
        axis2: V3,
    },
    /// Sliding along an axis.
    Prismatic {
        /// Sliding axis.
        axis: V3,
    },
    /// Sliding along and turning about an axis (3D).
    Cylindrical {
        /// Axis.
        axis: V3,
    },
    /// Rigid connection (bracket): no relative motion.
    Rigid,
    /// No constraint: the six (2D: three) degrees of freedom of a floating base body
    /// (`body2`) relative to the ground (`body1` must be `ground`). The relative formulation
    /// gives it its frame translation and three intrinsic Cardan angles x, y′, z″ (2D: one
    /// angle) as joint coordinates (singular when the middle angle reaches ±90°); the
    /// absolute one adds no equation.
    Free,
}

/// Force elements.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Force {
    /// Linear spring and damper between two markers, acting along the line joining them.
    SpringDamper {
        /// Name.
        name: String,
        /// First body.
        body1: String,
        /// Marker on the first body.
        marker1: String,
        /// Second body.
        body2: String,
        /// Marker on the second body.
        marker2: String,
        /// Stiffness (N/m).
        stiffness: f64,
        /// Damping (N·s/m).
        damping: f64,
        /// Free length (m); the initial distance when omitted.
        #[serde(default)]
        free_length: Option<f64>,
    },
    /// A spring and a damper of nonlinear laws ([`crate::laws`]) between two markers,
    /// tension positive: F = spring(l) + damper(l̇), along the line of the markers
    /// (l = |r₂ − r₁|) or along a body1-fixed axis a (l = a·(r₂ − r₁)).
    Link {
        /// Name.
        name: String,
        /// First body.
        body1: String,
        /// Marker on the first body.
        marker1: String,
        /// Second body.
        body2: String,
        /// Marker on the second body.
        marker2: String,
        /// The spring's tension F_s(l) (N) of the length l (m).
        #[serde(default)]
        spring: crate::laws::Law,
        /// The damper's tension F_d(l̇) (N) of the rate l̇ (m/s).
        #[serde(default)]
        damper: crate::laws::Law,
        /// `None`: along the line of the markers; `Some(a)`: along the axis a fixed in
        /// body1 (body1 components, normalised; body1 rigid or the ground).
        #[serde(default)]
        axis: Option<crate::direction::Direction>,
    },
    /// A tyre: the contact of a wheel-centre marker with a road ([`crate::roads`]), and a
    /// lateral damper F_y = −c ẏ_W at the wheel centre (ground y). 3D scenes only.
    Tyre {
        /// Name.
        name: String,
        /// The wheel's body.
        body: String,
        /// The wheel-centre marker W.
        marker: String,
        /// The road it rolls on.
        road: String,
        /// Unloaded radius R (m).
        radius: f64,
        /// Radial stiffness K (N/m).
        stiffness: f64,
        /// The contact model (`Vertical` when omitted).
        #[serde(default)]
        contact: crate::roads::Contact,
        /// Lateral damping c (N·s/m, 0 when omitted).
        #[serde(default)]
        lateral_damping: f64,
    },
    /// An external force and torque on a marker (ground components; constant, or set by a
    /// `Load` input): the torque needs a rigid body (`crate::force_elements::Load`). A
    /// planar scene's load is F_x, F_y and τ_z (its torque written `[0, 0, τ_z]`).
    Load {
        /// Name.
        name: String,
        /// The body (not the ground).
        body: String,
        /// The marker the force acts at.
        marker: String,
        /// Force F (N; 0 when omitted).
        #[serde(default)]
        force: V3,
        /// Torque τ (N·m; 0 when omitted).
        #[serde(default)]
        torque: V3,
    },
}

/// A prescribed motion of a joint coordinate, relative to its value at t = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Driver {
    /// Name.
    pub name: String,
    /// The driven joint (revolute: angle; prismatic: distance).
    pub joint: String,
    /// The law θ(t).
    pub law: MotionLaw,
}

/// Closed-form motion laws θ(t) with θ(0) = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum MotionLaw {
    /// A driver input's law ([`crate::inputs::DriverInput`]), put in the prepared scene by
    /// [`crate::PreparedScene::new`]; never in a scene file.
    #[serde(skip)]
    Input(crate::inputs::DriverInput),
    /// Held at its initial value.
    Locked,
    /// Constant rate: θ = rate · t.
    ConstantRate(f64),
    /// The spin-up manoeuvre (thesis ch. 4, docs/methods.md §6.5):
    /// ω(t) = Ωs/Ts [t − Ts/(2π) sin(2πt/Ts)] for t < Ts, Ωs after.
    SpinUp {
        /// Final angular speed Ωs (rad/s).
        omega_s: f64,
        /// Spin-up time Ts (s).
        t_s: f64,
    },
    /// θ = amplitude · sin(2π frequency t + phase) − amplitude · sin(phase).
    Harmonic {
        /// Amplitude (rad or m).
        amplitude: f64,
        /// Frequency (Hz).
        frequency: f64,
        /// Phase (rad).
        #[serde(default)]
        phase: f64,
    },
}

impl MotionLaw {
    /// θ(t), θ̇(t), θ̈(t).
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        use std::f64::consts::PI;
        match *self {
            MotionLaw::Input(ref input) => input.eval(t),
            MotionLaw::Locked => (0.0, 0.0, 0.0),
            MotionLaw::ConstantRate(r) => (r * t, r, 0.0),
            MotionLaw::SpinUp { omega_s, t_s } => {
                if t < t_s {
                    let k = 2.0 * PI / t_s;
                    let theta = omega_s / t_s * (0.5 * t * t + ((k * t).cos() - 1.0) / (k * k));
                    let omega = omega_s / t_s * (t - (k * t).sin() / k);
                    let alpha = omega_s / t_s * (1.0 - (k * t).cos());
                    (theta, omega, alpha)
                } else {
                    (omega_s * (t - 0.5 * t_s), omega_s, 0.0)
                }
            }
            MotionLaw::Harmonic {
                amplitude,
                frequency,
                phase,
            } => {
                let w = 2.0 * PI * frequency;
                let arg = w * t + phase;
                (
                    amplitude * (arg.sin() - phase.sin()),
                    amplitude * w * arg.cos(),
                    -amplitude * w * w * arg.sin(),
                )
            }
        }
    }
}

/// A ground-frame axis or a body-frame axis, for sensor components.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Axis {
    /// x.
    X,
    /// y.
    Y,
    /// z.
    Z,
}

impl Axis {
    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        self as usize
    }
}

/// Which formulation runs the scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum FormulationKind {
    /// Natural (fully Cartesian) coordinates.
    #[default]
    Absolute,
    /// Semi-recursive relative coordinates.
    Relative,
}

/// Geometric stiffening method for the flexible beams (thesis ch. 4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Stiffening {
    /// Linear floating-frame elasticity (none).
    #[default]
    Linear,
    /// First nonlinear term, K_G.
    Fnl1,
    /// Full Euler–Bernoulli strain energy, K_G + K_H + Q_g.
    Fnl2,
    /// Foreshortening, FS0.
    Foreshortening,
    /// Substructuring into n bodies.
    Substructuring(usize),
}

/// Solver settings (docs/methods.md §5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Solver {
    /// Time step h (s).
    pub step: f64,
    /// Simulated time (s).
    pub duration: f64,
    /// Output interval (s); every step when omitted. Rounded to a whole number of steps.
    #[serde(default)]
    pub output_interval: Option<f64>,
    /// Formulation.
    #[serde(default)]
    pub formulation: FormulationKind,
    /// Inertia route of the flexible bodies.
    #[serde(default = "default_inertia")]
    pub inertia: InertiaMethod,
    /// Geometric stiffening of the flexible beams.
    #[serde(default)]
    pub stiffening: Stiffening,
    /// Newton tolerance ε_q (relative) and ε_Φ.
    #[serde(default = "default_tolerance")]
    pub newton_tolerance: f64,
    /// Newton iteration limit per step.
    #[serde(default = "default_iterations")]
    pub max_iterations: usize,
    /// Penalty α; 4·10⁴ m_ref / h² when omitted (docs/methods.md §5.3).
    #[serde(default)]
    pub penalty: Option<f64>,
    /// How the drivers of tree joints enter the equations (`Eliminated` when omitted).
    #[serde(default)]
    pub drivers: DriverHandling,
    /// How the run starts (`Given` when omitted).
    #[serde(default)]
    pub initial_state: InitialState,
}

/// How a joint driven by a law, z_c = s θ(t), enters the equations of motion
/// (`flexmbd_core::driven`). Both give the same motion to the Newton tolerance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum DriverHandling {
    /// The driven coordinate is taken out of the unknowns: its position, rate and
    /// acceleration come from the law, and it needs no constraint row (the relative
    /// formulation's driven tree joints; a formulation without such coordinates keeps its
    /// driver rows).
    #[default]
    Eliminated,
    /// Every driver is a constraint row, z_c − s θ(t) = 0, enforced with the others.
    Constraint,
}

/// The state a run starts from, before ALI3-P makes it consistent (docs/methods.md §5.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum InitialState {
    /// The positions and velocities the scene gives: the bodies' placements and
    /// `initial_modes`, the `velocity` guesses (undeformed at rest unless they say otherwise).
    #[default]
    Given,
    /// At rest in static equilibrium under the loads at t = 0 (gravity, springs, elasticity
    /// with the chosen stiffening), found from the given positions with the drivers and
    /// joints held (docs/methods.md §5.4 item 4; `flexmbd_integrators::statics`); the velocity
    /// guesses are replaced by zero. docs/scenes.md §5 asks this of the 3D spin-up beam.
    StaticEquilibrium,
}

fn default_inertia() -> InertiaMethod {
    InertiaMethod::ShapeIntegrals
}
fn default_tolerance() -> f64 {
    1e-9
}
fn default_iterations() -> usize {
    20
}
