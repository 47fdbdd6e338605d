//! The force and moment that the rest of the system exerts on a body at one of its markers
//! P, through every joint, scene constraint and force element attached there (an
//! `InterfaceForce` sensor): a bearing's force on a rotor, a pin's force on a link.
//!
//! The body's balance of momentum (Newton–Euler, for a flexible body the rigid rows of its
//! floating-frame equations, docs/methods.md §2.4) gives the sum of everything that acts on
//! it; what acts at P is that sum less gravity and less the force elements at its other
//! markers:
//!
//! ```text
//! {F; M_O} = [M̄_0 {r̈0; ω̇; ÿ} − Q̄_v0]_rigid − {m g; A m̄(y) × g} − Σ_{k ≠ P} {f_k; (r_k − r0) × f_k}
//! M_P = M_O − (r_P − r0) × F
//! ```
//!
//! with M̄_0, Q̄_v0 the body's mass matrix and velocity-dependent inertia force in the origin
//! form {ṙ0, ω, ẏ} (`FlexibleBody::inertia_origin`, moments about the frame origin r0), the
//! frame's accelerations exact from the formulation's q̈ ([`SensorQuery::frame_motion`]), and
//! m̄(y) the body's first moment (its deformed centre of mass). The elastic and damping
//! forces are internal to the body: they have no rigid rows. The force elements are the
//! compiled ones of [`crate::force_elements`] evaluated over the markers' positions as
//! coordinates ([`MarkerPoints`]): the generalised force on a marker's three coordinates
//! is the force on that marker. A link's axis marker and a load's couple points belong to
//! their element: at P when the element acts at P.
//!
//! When every joint and scene constraint on the body acts at P this is the whole answer.
//! Otherwise (a connecting rod, pinned at both ends) the joints' reactions at its other
//! markers are not known from its balance alone, and every joint's reaction is found from
//! every moving body's balance together (`interface_system.rs`); the sensor adds the
//! reactions of the joints at P to the force elements there. In a static state
//! (q̇ = q̈ = 0) the balance is that of `flexmbd equilibrium`'s reactions.

use flexmbd_body::{BodyState, FlexibleBody, InertiaMethod};
use flexmbd_core::{Dim, MarkerKinematics, SensorQuery, SystemTerms};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use crate::error::ModelError;
use crate::force_elements::ForceElements;
use crate::prepared::{BodyId, MarkerId, PreparedScene};
use crate::scene::InterfaceQuantity;

/// Markers' positions taken as coordinates, three per marker (slot s at 3 s): the
/// generalised force a force element puts on a marker's coordinates is its force there.
pub struct MarkerPoints;

impl MarkerKinematics for MarkerPoints {
    type Marker = usize;

    fn marker_state(
        &self,
        marker: &usize,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let k = 3 * marker;
        (
            Vector3::new(q[k], q[k + 1], q[k + 2]),
            Vector3::new(qd[k], qd[k + 1], qd[k + 2]),
        )
    }

    fn marker_jacobian(
        &mut self,
        marker: &usize,
        _: &DVector<f64>,
        visit: &mut dyn FnMut(usize, Vector3<f64>),
    ) {
        for (a, e) in [Vector3::x(), Vector3::y(), Vector3::z()]
            .into_iter()
            .enumerate()
        {
            visit(3 * marker + a, e);
        }
    }
}

/// Where a marker is at the start: its body's placement applied to its body-frame position.
pub fn start_position(prepared: &PreparedScene, id: MarkerId) -> Vector3<f64> {
    match id.body {
        None => prepared.marker_position(id),
        Some(body) => {
            let body = &prepared.scene().bodies[body.0];
            body.origin.vec() + body.orientation.matrix() * prepared.marker_position(id)
        }
    }
}

/// The force elements evaluated over their markers' positions, with the storage to do so.
#[derive(Clone, Debug)]
pub(crate) struct MarkerForces<M> {
    /// The formulation's handle of the marker in each slot.
    handles: Vec<M>,
    elements: ForceElements<usize>,
    q: DVector<f64>,
    qd: DVector<f64>,
    terms: SystemTerms,
}

/// One body's balance: the rigid rows of its floating-frame equations at (q, q̇, q̈) less
/// gravity, with the storage to evaluate them (no allocation per read).
#[derive(Clone, Debug)]
pub(crate) struct BodyBalance {
    body: usize,
    dim: Dim,
    gravity: Vector3<f64>,
    /// The coordinate index of each mode of the body.
    modes: Vec<Option<usize>>,
    inertia: FlexibleBody,
    method: InertiaMethod,
    mass: DMatrix<f64>,
    velocity_forces: DVector<f64>,
    accelerations: DVector<f64>,
    y: Vec<f64>,
    y_rate: Vec<f64>,
    /// The orientation A(0) the scene gives the body (its turn since the start is A A(0)ᵀ).
    pub(crate) start: Matrix3<f64>,
}

/// What a body's balance leaves for the forces on it: the frame {r0, A} and the wrench
/// {F; M_O} about r0 (ground components) the rest of the system must apply.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Wrench {
    pub(crate) origin: Vector3<f64>,
    pub(crate) rotation: Matrix3<f64>,
    pub(crate) force: Vector3<f64>,
    pub(crate) moment: Vector3<f64>,
}

impl BodyBalance {
    pub(crate) fn new(
        prepared: &PreparedScene,
        body: BodyId,
        mode: &mut impl FnMut(BodyId, usize) -> Option<usize>,
    ) -> Self {
        let scene = prepared.scene();
        let prepared_body = prepared.body(body);
        let n_modes = prepared_body.body.n_modes();
        let n_coords = prepared_body.body.n_coords();
        BodyBalance {
            body: body.0,
            dim: scene.dim,
            gravity: scene.gravity.vec(),
            modes: (0..n_modes).map(|k| mode(body, k)).collect(),
            inertia: prepared_body.body.clone(),
            method: scene.solver.inertia,
            mass: DMatrix::zeros(n_coords, n_coords),
            velocity_forces: DVector::zeros(n_coords),
            accelerations: DVector::zeros(n_coords),
            y: vec![0.0; n_modes],
            y_rate: vec![0.0; n_modes],
            start: scene.bodies[body.0].orientation.matrix(),
        }
    }

    /// [M̄_0 Ż − Q̄_v0]_rigid − {m g; A m̄(y) × g} at (q, q̇, q̈).
    pub(crate) fn wrench<K: SensorQuery>(
        &mut self,
        query: &K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        qdd: &DVector<f64>,
    ) -> Wrench {
        let motion = query.frame_motion(self.body, q, qd, qdd);
        let rigid = self.dim.n_rigid();
        for (k, index) in self.modes.iter().enumerate() {
            let (y, rate, acceleration) = index.map_or((0.0, 0.0, 0.0), |i| (q[i], qd[i], qdd[i]));
            self.y[k] = y;
            self.y_rate[k] = rate;
            self.accelerations[rigid + k] = acceleration;
        }
        let (r0, a, omega) = (motion.origin, motion.rotation, motion.angular_velocity);
        let state =
            BodyState::from_origin_velocity(r0, a, omega, motion.velocity, &self.y, &self.y_rate);
        self.inertia.inertia_origin(
            &state,
            self.method,
            &mut self.mass,
            &mut self.velocity_forces,
        );
        match self.dim {
            Dim::Spatial => {
                for i in 0..3 {
                    self.accelerations[i] = motion.acceleration[i];
                    self.accelerations[3 + i] = motion.angular_acceleration[i];
                }
            }
            Dim::Planar => {
                self.accelerations[0] = motion.acceleration.x;
                self.accelerations[1] = motion.acceleration.y;
                self.accelerations[2] = motion.angular_acceleration.z;
            }
        }
        // The rigid rows of M̄_0 Ż − Q̄_v0: the sum of the external wrench about r0.
        let row = |i: usize| {
            let m = &self.mass;
            (0..m.ncols())
                .map(|j| m[(i, j)] * self.accelerations[j])
                .sum::<f64>()
                - self.velocity_forces[i]
        };
        let (mut force, mut moment) = match self.dim {
            Dim::Spatial => (
                Vector3::new(row(0), row(1), row(2)),
                Vector3::new(row(3), row(4), row(5)),
            ),
            Dim::Planar => (
                Vector3::new(row(0), row(1), 0.0),
                Vector3::new(0.0, 0.0, row(2)),
            ),
        };
        force -= self.inertia.mass() * self.gravity;
        moment -= (a * self.inertia.first_moment_at(&self.y)).cross(&self.gravity);
        Wrench {
            origin: r0,
            rotation: a,
            force,
            moment,
        }
    }
}

/// How the sensor finds the joints' part: from its body's balance alone, or from every
/// body's together.
#[derive(Clone, Debug)]
enum Route<M> {
    /// Every joint on the body acts at P: the body's balance less the force elements at its
    /// other markers (`others`: their slots).
    Body {
        balance: Box<BodyBalance>,
        others: Vec<usize>,
    },
    /// The reactions of every joint from every moving body's balance (least squares).
    System(Box<crate::interface_system::SystemBalance<M>>),
}

/// One `InterfaceForce` sensor, compiled for a formulation (`M`: its marker handle), with
/// the storage its reads use (a read allocates nothing).
#[derive(Clone, Debug)]
pub struct InterfaceForce<M> {
    marker: M,
    quantity: InterfaceQuantity,
    axis: usize,
    frame: Option<usize>,
    route: Route<M>,
    /// Slots of the force elements' markers at the interface (P and its elements' auxiliary
    /// markers on the body).
    at_interface: Vec<usize>,
    forces: Option<MarkerForces<M>>,
}

impl<M> InterfaceForce<M> {
    /// Compile the sensor at `marker` (on a moving body): `handle` gives the formulation's
    /// marker handles, `mode` the coordinate index of a body's mode.
    pub(crate) fn new(
        prepared: &PreparedScene,
        marker: MarkerId,
        (quantity, axis, frame): (InterfaceQuantity, usize, Option<usize>),
        mut handle: impl FnMut(MarkerId) -> M,
        mut mode: impl FnMut(BodyId, usize) -> Option<usize>,
    ) -> Result<Self, ModelError> {
        let body = marker
            .body
            .expect("an interface force acts on a moving body");
        let forces = marker_forces(prepared, &mut handle)?;
        let slots = force_marker_slots(prepared);
        let interface = interface_markers(prepared, marker);
        let on_body = |want_interface: bool| -> Vec<usize> {
            slots
                .iter()
                .enumerate()
                .filter(|(_, id)| id.body == Some(body) && interface.contains(id) == want_interface)
                .map(|(s, _)| s)
                .collect()
        };
        let route = if crate::interface_system::alone(prepared, marker) {
            Route::Body {
                balance: Box::new(BodyBalance::new(prepared, body, &mut mode)),
                others: on_body(false),
            }
        } else {
            Route::System(Box::new(crate::interface_system::SystemBalance::new(
                prepared,
                marker,
                &slots,
                &mut handle,
                &mut mode,
            )?))
        };
        Ok(InterfaceForce {
            marker: handle(marker),
            quantity,
            axis,
            frame,
            route,
            at_interface: on_body(true),
            forces,
        })
    }

    /// The component at (q, q̇, q̈) (module documentation). A formulation with recursive
    /// kinematics has run its kinematic pass at (q, q̇).
    pub(crate) fn read<K>(
        &mut self,
        query: &mut K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        qdd: &DVector<f64>,
    ) -> f64
    where
        K: SensorQuery<Marker = M>,
    {
        if let Some(f) = &mut self.forces {
            f.evaluate(query, q, qd);
        }
        let (rp, _) = query.marker_state(&self.marker, q, qd);
        let (force, moment) = match &mut self.route {
            Route::Body { balance, others } => {
                let w = balance.wrench(query, q, qd, qdd);
                let (mut force, mut moment) = (w.force, w.moment);
                if let Some(f) = &self.forces {
                    for &s in others.iter() {
                        let (rk, fk) = f.at(s);
                        force -= fk;
                        moment -= (rk - w.origin).cross(&fk);
                    }
                }
                (force, moment - (rp - w.origin).cross(&force))
            }
            Route::System(system) => {
                let (mut force, mut moment) =
                    system.reactions_at(query, q, qd, qdd, self.forces.as_ref(), &rp);
                if let Some(f) = &self.forces {
                    for &s in &self.at_interface {
                        let (rk, fk) = f.at(s);
                        force += fk;
                        moment += (rk - rp).cross(&fk);
                    }
                }
                (force, moment)
            }
        };
        let value = match self.quantity {
            InterfaceQuantity::Force => force,
            InterfaceQuantity::Moment => moment,
        };
        match self.frame {
            None => value[self.axis],
            Some(b) => query.body_frame(b, q).1.column(self.axis).dot(&value),
        }
    }
}

impl<M> MarkerForces<M> {
    /// Evaluate every element at the markers' positions and velocities now.
    fn evaluate<K>(&mut self, query: &K, q: &DVector<f64>, qd: &DVector<f64>)
    where
        K: SensorQuery<Marker = M>,
    {
        for (s, h) in self.handles.iter().enumerate() {
            let (r, v) = query.marker_state(h, q, qd);
            self.q.fixed_rows_mut::<3>(3 * s).copy_from(&r);
            self.qd.fixed_rows_mut::<3>(3 * s).copy_from(&v);
        }
        self.terms.forces.fill(0.0);
        self.elements
            .add_forces(&mut MarkerPoints, &self.q, &self.qd, false, &mut self.terms);
    }

    /// The position of slot `s` and the elements' force on it, from the last evaluation.
    pub(crate) fn at(&self, s: usize) -> (Vector3<f64>, Vector3<f64>) {
        (
            self.q.fixed_rows::<3>(3 * s).into_owned(),
            self.terms.forces.fixed_rows::<3>(3 * s).into_owned(),
        )
    }
}

/// The distinct markers of the force elements (their ends, link axis markers, load couple
/// points), in first-appearance order: slot s holds coordinates 3 s … 3 s + 2.
pub(crate) fn force_marker_slots(prepared: &PreparedScene) -> Vec<MarkerId> {
    let mut slots: Vec<MarkerId> = Vec::new();
    for id in prepared.force_marker_ids() {
        if !slots.contains(&id) {
            slots.push(id);
        }
    }
    slots
}

/// P and the auxiliary markers (a link's axis marker, a load's couple points) of the force
/// elements that act at P.
fn interface_markers(prepared: &PreparedScene, marker: MarkerId) -> Vec<MarkerId> {
    let mut at = vec![marker];
    for (k, pair) in prepared.force_markers().iter().enumerate() {
        if pair.first == marker || pair.second == marker {
            at.extend(prepared.force_axis_markers()[k]);
            at.extend(prepared.load_axis_markers()[k].iter().copied());
        }
    }
    at
}

/// The scene's force elements compiled over their markers' positions, free lengths from the
/// start placement (`None` for a scene without force elements).
fn marker_forces<M>(
    prepared: &PreparedScene,
    handle: &mut impl FnMut(MarkerId) -> M,
) -> Result<Option<MarkerForces<M>>, ModelError> {
    let slots = force_marker_slots(prepared);
    if slots.is_empty() {
        return Ok(None);
    }
    let n = 3 * slots.len();
    let mut q0 = DVector::zeros(n);
    for (s, id) in slots.iter().enumerate() {
        q0.fixed_rows_mut::<3>(3 * s)
            .copy_from(&start_position(prepared, *id));
    }
    let qd = DVector::zeros(n);
    let slot = |id: MarkerId| slots.iter().position(|m| *m == id).unwrap_or(0);
    let elements = ForceElements::new(prepared, slot, &MarkerPoints, &q0, &qd, n)?;
    Ok(Some(MarkerForces {
        handles: slots.iter().map(|&id| handle(id)).collect(),
        elements,
        q: q0,
        qd,
        terms: SystemTerms::new(n, 0),
    }))
}
