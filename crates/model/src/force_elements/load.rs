//! The **load**: an external force F and torque τ (ground components) on a marker P of a
//! body, constant or set by a `Load` input ([`crate::inputs`]).
//!
//! The force adds its virtual work, Q_i += ∂r_P/∂q_i · F. The torque acts on P's body as
//! a couple on body points written as markers, so that every formulation applies it through
//! the marker Jacobians it already has: the prepared scene adds to a rigid body the points
//! A_k = P + e_k (body axes e_k, unit distance; two in a planar scene, three in a spatial
//! one), and with d_k = r_{A_k} − r_P the forces F_k = τ × d_k / (2 |d_k|²) act at A_k
//! and −Σ F_k at P. Their moment about P is Σ d_k × F_k = ½ Σ (τ − d_k (d_k·τ)/|d_k|²) = τ
//! for orthogonal d_k (in a plane: τ ⊥ d_k), so the virtual work is τ · δθ of the rigid body
//! exactly. A torque on a flexible body is refused (its markers sit on FE nodes).
//!
//! F and τ are given in ground axes and do not follow the body: the tangent K of the force
//! is zero, and the couple's dependence on the orientation is left out of K (a tangent only
//! steers Newton). A load stores no energy.

use flexmbd_core::{Dim, ElementReading, InvalidValue, MarkerKinematics, SystemTerms};
use nalgebra::{DVector, Vector3};

use crate::error::ModelError;
use crate::inputs::{InputSlots, LOAD};
use crate::scene::{Body, Force, GROUND, Marker, Scene, V3};

/// A compiled load, `M` being the formulation's marker handle.
#[derive(Clone, Debug)]
pub struct Load<M> {
    /// The marker P the force acts at.
    pub at: M,
    /// The body points P + e_k the torque's couple acts at (none on a flexible body).
    pub axes: Vec<M>,
    /// Force F (N), ground components, while no input sets it.
    pub force: Vector3<f64>,
    /// Torque τ (N·m), ground components, while no input sets it.
    pub torque: Vector3<f64>,
    /// The `Load` input that sets F and τ, if any.
    pub input: Option<InputSlots>,
}

impl<M> Load<M> {
    /// Compile `force` (a `Load`) over the handles of P and of its axis points.
    pub(super) fn new(force: &Force, at: M, axes: Vec<M>) -> Self {
        let Force::Load { force, torque, .. } = force else {
            unreachable!("Load::new is given loads")
        };
        Load {
            at,
            axes,
            force: force.vec(),
            torque: torque.vec(),
            input: None,
        }
    }

    /// F and τ now: the input's values, or the scene's.
    fn values(&self) -> (Vector3<f64>, Vector3<f64>) {
        match &self.input {
            Some(slots) => (slots.vector(0), slots.vector(3)),
            None => (self.force, self.torque),
        }
    }

    /// Q of the load at q (it has no tangents).
    pub(super) fn add_forces<K>(
        &self,
        kinematics: &mut K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        out: &mut SystemTerms,
    ) where
        K: MarkerKinematics<Marker = M>,
    {
        let (force, torque) = self.values();
        let mut at_p = force;
        if torque != Vector3::zeros() {
            let (rp, _) = kinematics.marker_state(&self.at, q, qd);
            for axis in &self.axes {
                let (ra, _) = kinematics.marker_state(axis, q, qd);
                let d = ra - rp;
                let fk = torque.cross(&d) / (2.0 * d.norm_squared());
                at_p -= fk;
                add_marker_force(kinematics, axis, q, &fk, out);
            }
        }
        add_marker_force(kinematics, &self.at, q, &at_p, out);
    }

    /// A sensor's reading: |F| as the force, 0 as the length.
    pub(super) fn reading(&self) -> ElementReading {
        ElementReading {
            force: self.values().0.norm(),
            length: 0.0,
        }
    }
}

/// Q_i += ∂r_M/∂q_i · F.
fn add_marker_force<M, K>(
    kinematics: &mut K,
    marker: &M,
    q: &DVector<f64>,
    force: &Vector3<f64>,
    out: &mut SystemTerms,
) where
    K: MarkerKinematics<Marker = M>,
{
    let forces = &mut out.forces;
    kinematics.marker_jacobian(marker, q, &mut |i, c| forces[i] += c.dot(force));
}

/// A body that runs flexible (its markers sit on nodes, so no axis points can be added to
/// it): [`Body::runs_flexible`].
pub(crate) fn runs_flexible(body: &Body) -> bool {
    body.runs_flexible()
}

/// The prefix of the auxiliary axis markers' names.
const LOAD_AXIS_MARKER: &str = "__load_axis_of_";

/// Add to the rigid body of every load its axis points P + e_k (two in a planar scene,
/// three in a spatial one), and name them per force element (empty for the others and for
/// a load on a flexible body).
pub(crate) fn add_load_axis_markers(mut scene: Scene) -> (Scene, Vec<Vec<(String, String)>>) {
    let axes = match scene.dim {
        Dim::Planar => 2,
        Dim::Spatial => 3,
    };
    let mut names = Vec::with_capacity(scene.forces.len());
    for k in 0..scene.forces.len() {
        let Force::Load {
            name, body, marker, ..
        } = &scene.forces[k]
        else {
            names.push(Vec::new());
            continue;
        };
        let (name, body, marker) = (name.clone(), body.clone(), marker.clone());
        let Some(b) = scene.bodies.iter_mut().find(|b| b.name == body) else {
            names.push(Vec::new());
            continue;
        };
        if runs_flexible(b) {
            names.push(Vec::new());
            continue;
        }
        let p = b
            .markers
            .iter()
            .find(|m| m.name == marker)
            .map_or(Vector3::zeros(), |m| m.position.vec());
        let mut these = Vec::with_capacity(axes);
        for axis in 0..axes {
            let point = format!("{LOAD_AXIS_MARKER}{name}_{axis}");
            let mut position = p;
            position[axis] += 1.0;
            b.markers.push(Marker {
                name: point.clone(),
                position: V3(position.into()),
            });
            these.push((body.clone(), point));
        }
        names.push(these);
    }
    (scene, names)
}

impl Scene {
    /// A load: on a body (not the ground), its numbers in range, in the plane in a planar
    /// scene, and no torque on a flexible body.
    pub(crate) fn check_load(&self, force: &Force) -> Result<(), ModelError> {
        let Force::Load {
            name,
            body,
            force,
            torque,
            ..
        } = force
        else {
            return Ok(());
        };
        let f = |field: &str| format!("forces[{name}].{field}");
        if body == GROUND {
            return Err(self.invalid(InvalidValue::new(
                f("body"),
                body,
                "a load acts on a moving body, not the ground",
            )));
        }
        for (field, v) in [("force", force), ("torque", torque)] {
            for (i, &x) in v.0.iter().enumerate() {
                self.in_range(LOAD, &f(&format!("{field}[{i}]")), x)?;
            }
        }
        if self.dim == Dim::Planar {
            for (field, i, x) in [("force", 2, force.0[2]), ("torque", 0, torque.0[0])]
                .into_iter()
                .chain([("torque", 1, torque.0[1])])
            {
                if x != 0.0 {
                    return Err(self.invalid(InvalidValue::new(
                        f(&format!("{field}[{i}]")),
                        x,
                        "a planar scene's load is F_x, F_y and τ_z",
                    )));
                }
            }
        }
        let flexible = self
            .bodies
            .iter()
            .any(|b| &b.name == body && runs_flexible(b));
        if flexible && torque.0 != [0.0; 3] {
            return Err(self.invalid(InvalidValue::new(
                f("torque"),
                format!("{:?}", torque.0),
                "a torque needs a rigid body (a flexible body's markers sit on FE nodes); apply it to a rigid body or as forces",
            )));
        }
        Ok(())
    }
}
