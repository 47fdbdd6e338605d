//! The spatial formulation's side of the sensors written once (`flexmbd_model::sensors`): the
//! marker terms the sensors read, its joint coordinates (the angle of a revolute joint,
//! `atan2(σ, κ)` from its value at t = 0, or the slide of a prismatic joint) and the
//! [`SensorQuery`] the shared sensors read.

use std::collections::HashMap;

use flexmbd_core::{ElementReading, FrameMotion, JointReading, SensorQuery};
use flexmbd_model::sensors::{SensorHandles, Sensors};
use flexmbd_model::{
    BodyId, JointId, JointKind, MarkerId, ModelError, PreparedScene, SensorTarget,
};
use nalgebra::{DVector, Matrix3, Vector3};

use super::Spatial;
use super::joints::perpendiculars;
use super::kinematics::{Term, frame_of};
use super::lookup::TermLookup;

/// A joint coordinate as the spatial formulation reads it.
#[derive(Clone, Debug)]
pub struct SpatialJointCoordinate(JointCoordinate);

#[derive(Clone, Debug)]
enum JointCoordinate {
    /// A revolute joint's angle from `phi0`, its value at t = 0: the angle about `a` from
    /// `p1` (fixed in body 1) to `p2` (fixed in body 2).
    Angle {
        p1: Term,
        p2: Term,
        a: Term,
        phi0: f64,
    },
    /// A prismatic joint's slide `(x − origin)·z − s0`.
    Slide {
        x: Term,
        origin: Term,
        z: Term,
        s0: f64,
    },
}

/// The spatial formulation's sensors.
pub(super) type SpatialSensors = Sensors<Term, SpatialJointCoordinate>;

/// The terms the sensors read, resolved while the term lookup lives.
pub(super) struct SensorTerms {
    markers: HashMap<MarkerId, Term>,
    joints: HashMap<JointId, SpatialJointCoordinate>,
}

fn unsupported(what: String) -> ModelError {
    ModelError::Unsupported(what)
}

/// The marker terms and joint coordinates of the scene's sensors; a joint coordinate this
/// formulation cannot read is refused, naming the sensor.
pub(super) fn sensor_terms(
    lookup: &TermLookup,
    prepared: &PreparedScene,
) -> Result<SensorTerms, ModelError> {
    let mut terms = SensorTerms {
        markers: HashMap::new(),
        joints: HashMap::new(),
    };
    for (sensor, target) in lookup.scene.sensors.iter().zip(prepared.sensor_targets()) {
        match *target {
            SensorTarget::Position { marker, .. } | SensorTarget::Velocity { marker, .. } => {
                let term = lookup.point(marker);
                terms.markers.insert(marker, term);
            }
            SensorTarget::JointCoordinate(joint) => {
                let coordinate = joint_coordinate(lookup, &sensor.name, joint)?;
                terms.joints.insert(joint, coordinate);
            }
            SensorTarget::InterfaceForce { marker, .. } => {
                // The marker, and the force elements' and joints' markers the balances read.
                let joints = prepared
                    .joint_markers()
                    .iter()
                    .flat_map(|p| [p.first, p.second]);
                let ids = std::iter::once(marker).chain(prepared.force_marker_ids());
                for id in ids.chain(joints) {
                    let term = lookup.point(id);
                    terms.markers.insert(id, term);
                }
            }
            SensorTarget::Modal { .. }
            | SensorTarget::Energy
            | SensorTarget::Angle { .. }
            | SensorTarget::ElementForce { .. }
            | SensorTarget::Stress { .. } => {}
        }
    }
    Ok(terms)
}

/// The angle of a revolute joint (φ0 still 0) or the slide of a prismatic joint.
fn joint_coordinate(
    lookup: &TermLookup,
    sensor: &str,
    joint: JointId,
) -> Result<SpatialJointCoordinate, ModelError> {
    let scene = lookup.scene;
    let j = &scene.joints[joint.0];
    let ends = lookup.joints[joint.0];
    let dir1 = |v: &Vector3<f64>| lookup.direction(ends.first, v);
    let dir2 = |v: &Vector3<f64>| lookup.direction(ends.second, v);
    Ok(match &j.kind {
        JointKind::Revolute { axis: Some(axis) } => {
            let a = axis.vec().normalize();
            let (n1, _) = perpendiculars(&a);
            SpatialJointCoordinate(JointCoordinate::Angle {
                p1: dir1(&n1),
                p2: dir2(&n1),
                a: dir1(&a),
                phi0: 0.0,
            })
        }
        JointKind::Prismatic { axis } => {
            let a = axis.vec().normalize();
            let (p1, p2) = (lookup.point(ends.first), lookup.point(ends.second));
            let s0 = (lookup.position0(&p2) - lookup.position0(&p1)).dot(&a);
            SpatialJointCoordinate(JointCoordinate::Slide {
                x: p2,
                origin: p1,
                z: dir1(&a),
                s0,
            })
        }
        k => {
            return Err(unsupported(format!(
                "{}: sensor `{sensor}`: a joint coordinate is defined for revolute (angle) and prismatic (slide) joints only; joint `{}` is {k:?}",
                scene.origin, j.name
            )));
        }
    })
}

impl Spatial {
    /// The scene's sensors over the resolved terms, the joint angles measured from their
    /// value at q0.
    pub(super) fn build_sensors(
        &self,
        prepared: &PreparedScene,
        terms: SensorTerms,
    ) -> Result<SpatialSensors, ModelError> {
        let joint = |_sensor: &str, id: JointId| {
            let mut coordinate = terms.joints[&id].clone();
            if let JointCoordinate::Angle { p1, p2, a, phi0 } = &mut coordinate.0 {
                *phi0 = self.angle(p1, p2, a, &self.coordinates.q0, &self.zero_rates);
            }
            Ok(coordinate)
        };
        let mode = |BodyId(b): BodyId, index: usize| {
            let body = &self.bodies[b];
            (index < body.n_modes).then_some(body.offset + 12 + index)
        };
        Sensors::new(
            prepared,
            SensorHandles {
                marker: |id| terms.markers[&id].clone(),
                joint,
                mode,
            },
        )
    }
}

impl SensorQuery for Spatial {
    type JointCoordinate = SpatialJointCoordinate;

    fn body_frame(&self, body: usize, q: &DVector<f64>) -> (Vector3<f64>, Matrix3<f64>) {
        self.frame(body, q)
    }

    fn joint_coordinate(
        &self,
        joint: &SpatialJointCoordinate,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> JointReading {
        match &joint.0 {
            JointCoordinate::Angle { p1, p2, a, phi0 } => {
                JointReading::Angle(self.angle(p1, p2, a, q, qd) - phi0)
            }
            JointCoordinate::Slide { x, origin, z, s0 } => {
                let d = x.eval(&self.bodies, q, qd).value - origin.eval(&self.bodies, q, qd).value;
                JointReading::Value(d.dot(&z.eval(&self.bodies, q, qd).value) - s0)
            }
        }
    }

    fn total_energy(&mut self, q: &DVector<f64>, qd: &DVector<f64>) -> f64 {
        self.energy(q, qd)
    }

    fn element_reading(
        &self,
        element: usize,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> ElementReading {
        self.force_elements.reading(element, self, q, qd)
    }

    /// r0 and A = [u v w] are coordinates: their rates and accelerations are those
    /// entries of q̇ and q̈.
    fn frame_motion(
        &self,
        body: usize,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        qdd: &DVector<f64>,
    ) -> FrameMotion {
        let offset = self.bodies[body].offset;
        let (r0, a) = frame_of(q.as_slice(), offset);
        let (v0, ad) = frame_of(qd.as_slice(), offset);
        let (a0, add) = frame_of(qdd.as_slice(), offset);
        FrameMotion::from_rotation_rates([r0, v0, a0], [&a, &ad, &add])
    }
}
