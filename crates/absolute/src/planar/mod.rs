//! The planar natural-coordinate formulation (docs/methods.md §3, thesis ch. 2).
//!
//! **Coordinates.** Basic points are shared by the bodies they join: every group of
//! markers connected by revolute or rigid (bracket) joints is one point, fixed when it
//! touches the ground and two coordinates otherwise. Each body is described by a basis
//! x_b = (a, b) of two 2-vectors taken from the coordinates (or the fixed points):
//!
//! - a rigid body with two distinct joint points uses the first two (i, j), with the
//!   constant-distance constraint |r_j − r_i|² = L² (the classical natural-coordinate bar);
//! - any other rigid body, and every flexible body, uses a point and its own unit vector u
//!   along the body x axis, with |u|² = 1; the point is its joint point at the frame's
//!   reference node (flexible beams), else its first joint point, else a point of its own
//!   at the reference node or the frame origin;
//! - a flexible body adds its modal coordinates y.
//!
//! The body frame (r0, u), A = [u  E u], is a constant linear map of the basis,
//! f = T x_b (two points: u = R(−φ)(r_j − r_i)/L, r0 = r_i − (r̄_i1 I + r̄_i2 E) u), so the
//! body's natural-set mass matrix and forces (docs/methods.md §2.5–§2.6) are projected with
//! the constant T: M_b = Tᵀ M_f T, Q_b = Tᵀ Q_f, and no velocity terms arise from T.
//!
//! **Constraints.** Joint points of a body that are not in its basis are tied to it by
//! r0 + A (r̄_P + X_P y) − r_point = 0 (linear for rigid bodies, bilinear for flexible
//! ones, docs/methods.md §3.3). Angle drivers and brackets use Φ = σ cos θ − κ sin θ
//! = sin(φ − θ) with σ = d₁ × d₂, κ = d₁ · d₂ and θ = φ₀ + θ(t) (φ₀ the angle at t = 0,
//! θ ≡ 0 for a bracket; docs/methods.md §3.2), never singular at its root. A body-fixed direction is d = A (I + θ_P E) ā (θ_P the node rotation at a
//! flexible node, docs/methods.md §3.3).
//!
//! **Prismatic joints.** The markers are not shared points: the marker P2 of body 2 slides
//! along the axis d₁ fixed in body 1 through its marker P1, (r_P2 − r_P1) × d₁ = 0, and the
//! relative rotation is locked by the angle constraint with θ ≡ 0. A driver adds
//! (r_P2 − r_P1) · d₁ − s₀ − s(t) = 0; the joint-coordinate sensor reports
//! (r_P2 − r_P1) · d₁ − s₀.
//!
//! **Scene constraints** (`Scene::constraints`, docs/methods.md §3.4): a `Distance` between
//! two markers is the row ½(|r_P2 − r_P1|² − L²) = 0 after the joints and drivers (the
//! equation of `flexmbd_model::constraint_equations`, through the markers' columns);
//! `PointInPlane` is 3D only.
//!
//! **Spring–dampers** between two markers add Q −= Jᵀ f n with J = ∂(r_P2 − r_P1)/∂q and
//! f = k (l − l₀) + c l̇, and their (state-dependent) tangents to K and C; they are the
//! shared `flexmbd_model::force_elements` over `impl MarkerKinematics for Planar`.
//!
//! **Layout.** `build` compiles the scene (marker table, shared points, bodies and
//! their bases, joints and drivers, force elements, sensors, constant rigid terms); `body`
//! holds a body's basis and local points; `kinematics` frames, markers and directions;
//! `dynamics` the mass matrix and forces; `constraints` Φ, Φ_q, Φ_t and the bias; `sensors`
//! and `energy` what is read out.

mod algebra;
mod body;
mod build;
mod constraints;
mod driven;
mod dynamics;
mod energy;
mod kinematics;
mod sensors;

use flexmbd_body::{ElasticTangents, InertiaMethod};
use flexmbd_core::{Coordinates, MarkerKinematics, Request, State, SystemTerms};
use flexmbd_model::force_elements::ForceElements;
use nalgebra::{DMatrix, DVector, Vector2, Vector3};

pub(crate) use algebra::c_of;
pub use kinematics::PlanarMarker;

use body::PlanarBody;
use constraints::Constraint;
pub use sensors::PlanarJointCoordinate;
use sensors::PlanarSensors;

/// The compiled planar scene.
pub struct Planar {
    /// Number, constraint count, initial coordinates and rates, specified ones (none).
    coordinates: Coordinates,
    /// Gravity (m/s², ground components).
    gravity: Vector2<f64>,
    bodies: Vec<PlanarBody>,
    /// The constraints in row order.
    constraints: Vec<Constraint>,
    force_elements: ForceElements<PlanarMarker>,
    /// Σ over rigid bodies of Tᵀ M_f T, scattered (constant).
    rigid_mass: DMatrix<f64>,
    /// Σ over rigid bodies of Tᵀ Q_gravity, scattered (constant).
    rigid_forces: DVector<f64>,
    sensors: PlanarSensors,
    /// Zero rates (n), to evaluate positions alone.
    zero_rates: DVector<f64>,
    inertia_method: InertiaMethod,
    /// Scratch for one body's local dense terms (basis order, then modes), sized for the
    /// largest body.
    local_mass: DMatrix<f64>,
    local_forces: DVector<f64>,
    /// Coordinate of each local row (`None`: a fixed basis value).
    local_to_global: Vec<Option<usize>>,
    /// The unit vectors a driven angle prescribes (`driven.rs`).
    driven_frames: Vec<driven::DrivenFrame>,
}

impl flexmbd_core::Formulation for Planar {
    fn coordinates(&self) -> &Coordinates {
        &self.coordinates
    }
    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        if req.dynamics {
            self.dynamics(state, req.tangents, out);
        }
        if req.constraints || req.jacobian || req.accel_term {
            self.constraints(state, req, out);
        }
    }
    fn constant_mass(&self) -> bool {
        // Natural coordinates: a rigid body's mass matrix is constant.
        self.bodies.iter().all(|b| b.n_modes == 0)
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
    fn predictor_repeats_miss(&self) -> bool {
        // The projections onto the nonlinear rows (|u|² = 1, angles, a rigid bar's constant
        // distance) kick q̈ by an offset that persists while the motion is steady; M passes
        // it to a flexible body's modes (the spin-up beam's first mode missed by 1.3e-8
        // every step, 13× ε_q), and the rigid double four-bar's points miss likewise.
        true
    }
    fn driven_coordinates(&self) -> Option<flexmbd_core::DrivenCoordinates> {
        self.driven_declaration()
    }
    fn driven_motion(&self, t: f64, out: &mut [[f64; 3]]) {
        self.driven_frame_motion(t, out)
    }
}

impl flexmbd_core::Observe for Planar {
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
            (pose.origin, pose.rotation) = flexmbd_core::SensorQuery::body_frame(self, b, state.q);
            let first = self.bodies[b].first_mode;
            pose.modes.clear();
            pose.modes
                .extend_from_slice(&state.q.as_slice()[first..first + self.bodies[b].n_modes]);
        }
    }
}

impl MarkerKinematics for Planar {
    type Marker = PlanarMarker;

    fn marker_state(
        &self,
        marker: &PlanarMarker,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let (r, v, _) = self.marker_motion(marker, q, qd);
        (Vector3::new(r.x, r.y, 0.0), Vector3::new(v.x, v.y, 0.0))
    }

    fn marker_jacobian(
        &mut self,
        marker: &PlanarMarker,
        q: &DVector<f64>,
        visit: &mut dyn FnMut(usize, Vector3<f64>),
    ) {
        self.marker_columns(marker, q, |i, c| visit(i, Vector3::new(c.x, c.y, 0.0)));
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use flexmbd_model::{PreparedScene, Scene};

    use super::Planar;

    /// A scene of `models/`.
    pub(crate) fn model(file: &str) -> Scene {
        Scene::load(format!(
            "{}/../../models/{file}",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap()
    }

    /// The compiled planar scene.
    pub(crate) fn compiled(scene: &Scene) -> Planar {
        Planar::compile(&PreparedScene::new(scene).unwrap()).unwrap()
    }
}
