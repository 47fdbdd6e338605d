//! The spatial (3D) natural-coordinate formulation (docs/methods.md §3, §2.5–§2.6).
//!
//! **Coordinates (the choice).** Every body has its own frame coordinates
//! `q_b = {r0; u; v; w; y}`: the origin, the three body axes `A = [u v w]` in ground
//! components, and the modal coordinates of a flexible body (12 + n per body, n = 0 for
//! rigid bodies and for beams run rigid). Six orthonormality constraints per body
//! (`u·u = v·v = w·w = 1`, `u·v = v·w = w·u = 0`) leave 6 + n freedoms. This is the same
//! set for rigid and flexible bodies, so the body crate's natural-set inertia
//! (`inertia_natural`, both routes) and gravity (`gravity_natural`) apply unchanged; a
//! rigid body's 12 × 12 mass matrix and gravity force are constant and computed once at
//! compile time. Points and vectors are **not** shared between bodies (the classical
//! fully-Cartesian economy): every joint is a set of constraint equations between the
//! bodies' markers. It costs more coordinates (12 per rigid body against 6–9 with shared
//! points) but treats every joint, body and marker alike; the counts are below.
//!
//! **Body vectors.** A joint uses body points and body-fixed directions, both of the form
//!
//! ```text
//! x(q) = δ r0 + A (x̄ + V y),  δ = 1 for a point, 0 for a direction,
//! ```
//!
//! bilinear in (A, y) (docs/methods.md §3.3): a marker point on a flexible body sits on an FE
//! node P, `x̄ = r̄_P`, `V = X_P` (translation rows); a direction ā at a node P turns with
//! the node, `a_P = A (I + θ̃_P) ā` with `θ̄_P = X^r_P y`, i.e. `V = [X^r_j × ā]_j`. On a
//! rigid body V is empty. The Jacobian is `[δ I  x̃_1 I  x̃_2 I  x̃_3 I  A V]` with
//! `x̃ = x̄ + V y`, the velocity `δ ṙ0 + Ȧ x̃ + A V ẏ` and the bias (the second derivative
//! at q̈ = 0) `2 Ȧ V ẏ`. Ground markers and ground directions are constants.
//!
//! **Joints** (body 1 carries the joint axis a; `n1 ⟂ n2 ⟂ a` are fixed unit vectors built
//! from the axis at t = 0, the same global vectors fixed in both bodies):
//!
//! | joint | equations | rows |
//! |---|---|---|
//! | spherical | `r_P2 − r_P1 = 0` | 3 |
//! | revolute | point + `a¹·n²₁ = 0`, `a¹·n²₂ = 0` | 5 |
//! | universal | point + `a¹₁·a²₂ = 0` (cross arms) | 4 |
//! | cylindrical | `a¹·n²₁ = a¹·n²₂ = 0`, `(r_P2 − r_P1)·n¹₁ = c₁`, `(r_P2 − r_P1)·n¹₂ = c₂` | 4 |
//! | prismatic | cylindrical + `n¹₁·n²₂ = 0` (φ₀ = 90°, docs/methods.md §3.2 correction) | 5 |
//! | rigid | point + `e¹_x·e²_y = e¹_y·e²_z = e¹_z·e²_x = 0` | 6 |
//!
//! (superscripts: the body the vector is fixed in; `c₁, c₂` are the values at t = 0, so a
//! sliding joint's markers need not coincide). Two free bodies joined by one of these
//! have mobility 9, 7, 8, 8, 7, 6 (tested by the rank of Φ_q).
//!
//! **Scene constraints** (`Scene::constraints`, docs/methods.md §3.4), after the joints and
//! drivers, one row each: a `Distance` `½(|r_P2 − r_P1|² − L²) = 0`, a `PointInPlane`
//! `n¹·(r_P2 − r_P1) = 0` (the dot row above, `n¹` the body1-fixed normal at marker P1).
//!
//! **Drivers.** A revolute joint is driven by `Φ = σ cos θ(t) − κ sin θ(t) = sin(φ − θ)`
//! with `σ = (p¹ × p²)·a¹`, `κ = p¹·p²`, `p = n₁` fixed in each body (docs/methods.md §3.2);
//! a prismatic joint by `(r_P2 − r_P1)·a¹ = s₀ + s(t)`. Other drivers are refused.
//!
//! **Coordinate counts.** n = Σ (12 + n_b); m = 6 · (bodies) + Σ joint rows + drivers +
//! scene constraints.
//! The rigid 3D double pendulum (spherical + revolute): 24 coordinates, 20 constraints.
//! The flexible 3D pendulum (6 modes, spherical): 18 and 9. The double four-bar written
//! in 3D (5 bodies, 7 revolutes about z): 60 and 65 (Φ_q rank 59: each closed planar loop
//! of revolutes brings 3 redundant out-of-plane rows, which ALI3-P tolerates).
//!
//! **Sensors**, as the planar code reports them: a marker's position and velocity in
//! ground components or in a body frame (`Aᵀ (r − r0)`, `Aᵀ ṙ`), the angle of a revolute
//! joint (`atan2(σ, κ)`, unwrapped, relative to t = 0) or the slide of a prismatic joint,
//! a modal coordinate, and the total energy (kinetic `½ q̇ᵀ M q̇`, gravity, elastic).
//!
//! **Foreshortening (FS0, methods.md §6.3).** A foreshortened beam's inertia comes from the body
//! crate like any other (either route); a point term at an FE node of such a body adds the node's
//! axial shift −½ ē₁ yᵀF y to `x̃`, its rate −ē₁ (F y)·ẏ to the velocity, `A (−ē₁ ẏᵀF ẏ)` to the
//! bias and −A ē₁ (F y)ᵀ to the y columns of the Jacobian (joints sit at the root, where F = 0;
//! the tip sensors see the shift).
//!
//! **Allocation.** `evaluate` allocates nothing: every workspace is sized at compile time.
//!
//! **Layout.** `build` compiles the scene (bodies and their coordinates, then `lookup` for
//! the marker terms, `joints` for the joint and driver equations,
//! `marker_constraints` for the scene's distance and point-in-plane rows, `sensors`, the reference
//! angles, the force elements); `kinematics` evaluates a term (value, rate, bias, Jacobian)
//! and implements `MarkerKinematics`; `dynamics` fills M, Q, K and C; `constraints` fills
//! Φ, Φ_q, Φ_t and the acceleration term; `sensors` and `energy` report what is measured.

mod build;
mod constraints;
mod driven;
mod dynamics;
mod energy;
mod joints;
mod kinematics;
mod lookup;
mod marker_constraints;
mod pattern;
mod sensors;

use flexmbd_body::{ElasticTangents, FlexibleBody, InertiaMethod, NaturalWorkspace};
use flexmbd_core::{Coordinates, Request, State, SystemTerms};
use flexmbd_model::force_elements::ForceElements;
use nalgebra::{DMatrix, DVector, Vector3};

pub use kinematics::Term;

use constraints::Constraint;
pub use sensors::SpatialJointCoordinate;
use sensors::SpatialSensors;

/// Scratch of one flexible body, sized once.
struct FlexibleScratch {
    /// The body crate's natural-set inertia workspace.
    natural: NaturalWorkspace,
    /// Gravity force on `{r0; u; v; w; y}` (12 + n).
    gravity: Vec<f64>,
    /// Elastic force on y (n).
    elastic: Vec<f64>,
    /// Mass matrix and inertia forces for the energy sensor (12 + n).
    energy_mass: DMatrix<f64>,
    energy_forces: DVector<f64>,
}

/// A marker on a body.
struct MarkerSite {
    /// Undeformed position, body components (m).
    position: Vector3<f64>,
    /// The FE node it sits on (flexible bodies only).
    node: Option<usize>,
}

/// One body and where its coordinates sit in q.
struct SpatialBody {
    body: FlexibleBody,
    /// Index of r0 in q; u, v, w follow, then y at `offset + 12`.
    offset: usize,
    /// Modal coordinates n (0 for a rigid body).
    n_modes: usize,
    /// Rigid bodies: the constant 12 × 12 mass matrix and gravity force (empty otherwise).
    rigid_mass: DMatrix<f64>,
    rigid_gravity: DVector<f64>,
    markers: Vec<MarkerSite>,
    /// Flexible bodies: their scratch.
    flexible: Option<FlexibleScratch>,
}

/// The compiled spatial scene.
pub struct Spatial {
    /// Number, constraint count, coordinates and rates at t = 0, specified ones (none).
    coordinates: Coordinates,
    /// Gravity, ground components (m/s²).
    gravity: Vector3<f64>,
    bodies: Vec<SpatialBody>,
    /// Orthonormality blocks of every body, then the joint and driver equations.
    constraints: Vec<Constraint>,
    sensors: SpatialSensors,
    inertia_method: InertiaMethod,
    force_elements: ForceElements<Term>,
    /// Zero rates (n), to evaluate a term's position alone.
    zero_rates: DVector<f64>,
    /// The bodies a driven revolute to the ground turns (`driven.rs`).
    driven_frames: Vec<driven::DrivenFrame>,
}

impl flexmbd_core::Formulation for Spatial {
    fn coordinates(&self) -> &Coordinates {
        &self.coordinates
    }
    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        if req.dynamics {
            self.dynamics(state, req.tangents, out);
        }
        if req.constraints || req.jacobian || req.accel_term {
            self.constraint_terms(state, req, out);
        }
    }
    fn constant_tangents(&self) -> bool {
        // Rigid bodies and linear elasticity: K = K_ff and C = C_ff blocks only; spring
        // tangents turn with the spring's direction.
        self.force_elements.is_empty()
            && ElasticTangents::of(self.bodies.iter().map(|b| &b.body)).linear
    }
    fn symmetric_tangent(&self) -> bool {
        ElasticTangents::of(self.bodies.iter().map(|b| &b.body)).symmetric
    }
    fn declared_pattern(&self) -> Option<flexmbd_core::DeclaredPattern> {
        Some(self.pattern())
    }
    fn driven_coordinates(&self) -> Option<flexmbd_core::DrivenCoordinates> {
        self.driven_declaration()
    }
    fn driven_motion(&self, t: f64, out: &mut [[f64; 3]]) {
        self.driven_frame_motion(t, out)
    }
}

impl flexmbd_core::Observe for Spatial {
    fn sensor_names(&self) -> &[String] {
        self.sensors.names()
    }
    fn sensors(&mut self, state: State<'_>, out: &mut [f64]) {
        let mut sensors = std::mem::take(&mut self.sensors);
        sensors.read(self, state.q, state.qd, state.qdd, out);
        self.sensors = sensors;
    }
    fn body_poses(&mut self, state: State<'_>, out: &mut [flexmbd_core::BodyPose]) {
        for (b, pose) in out.iter_mut().enumerate() {
            (pose.origin, pose.rotation) = self.frame(b, state.q);
            let first = self.bodies[b].offset + 12;
            pose.modes.clear();
            pose.modes
                .extend_from_slice(&state.q.as_slice()[first..first + self.bodies[b].n_modes]);
        }
    }
}
