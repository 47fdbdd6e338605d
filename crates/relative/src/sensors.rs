//! The relative formulation's side of the sensors written once (`flexmbd_model::sensors`):
//! its joint coordinates (a planar revolute's angle between its markers, node rotations
//! included; a cut prismatic's slide from its t = 0 value; a tree joint's coordinate) and the
//! [`SensorQuery`] the shared sensors read, answered from one kinematics pass at (z, ż).

use flexmbd_core::{Dim, ElementReading, FrameMotion, JointReading, SensorQuery};
use flexmbd_model::sensors::{SensorHandles, Sensors};
use flexmbd_model::{BodyId, JointId, JointKind, MarkerId, ModelError, PreparedScene, Scene};
use nalgebra::{DVector, Matrix3, Vector2, Vector3};

use crate::kinematics::{angle_at, angle_of, dir_at, point_at};
use crate::system::{Relative, unsupported};
use crate::topology::{BodyInfo, Side};

/// A joint coordinate as the relative formulation reads it.
#[derive(Clone, Debug)]
pub struct RelativeJointCoordinate(JointCoordinate);

#[derive(Clone, Debug)]
enum JointCoordinate {
    /// 2D joint angle between the two markers' directions (node rotations included), less
    /// its value ψ0 at t = 0.
    Angle2 { i: Side, j: Side, psi0: f64 },
    /// A joint coordinate of the tree (its sign: the tree may run the joint backwards).
    Tree { z: usize, sign: f64 },
    /// Displacement of j's marker relative to i's along an axis fixed at i, less its value
    /// d0 at t = 0.
    Slide {
        i: Side,
        nbar: Vector3<f64>,
        j: Side,
        d0: f64,
    },
}

/// The relative formulation's sensors.
pub(crate) type RelativeSensors = Sensors<Side, RelativeJointCoordinate>;

impl Relative {
    /// The scene's sensors, resolved at z0 (the tree's kinematics are run there first).
    pub(crate) fn build_sensors(
        &mut self,
        prepared: &PreparedScene,
        infos: &[BodyInfo],
    ) -> Result<RelativeSensors, ModelError> {
        let scene = prepared.scene();
        let (q0, qd0) = (self.coordinates.q0.clone(), self.coordinates.qd0.clone());
        self.kinematics(&q0, &qd0);
        let this = &*self;
        let side_at = |id: MarkerId| Side::at(prepared, infos, id);
        Sensors::new(
            prepared,
            SensorHandles {
                marker: side_at,
                joint: |sensor: &str, joint: JointId| {
                    let ends = prepared.joint_markers()[joint.0];
                    let sides = (side_at(ends.first), side_at(ends.second));
                    this.joint_coordinate_sensor(scene, infos, sensor, joint, sides)
                },
                mode: |BodyId(b): BodyId, index: usize| {
                    let body = &this.bodies[b];
                    (index < body.n_modes).then_some(body.first_mode + index)
                },
            },
        )
    }

    /// The coordinate of a joint: a planar revolute's angle between its markers, a cut
    /// prismatic's slide (from its value at z0: the tree's kinematics are those of z0), or a
    /// tree joint's first coordinate.
    fn joint_coordinate_sensor(
        &self,
        scene: &Scene,
        infos: &[BodyInfo],
        sensor: &str,
        joint: JointId,
        (si, sj): (Side, Side),
    ) -> Result<RelativeJointCoordinate, ModelError> {
        let ji = joint.0;
        let j = &scene.joints[ji];
        let a0 = |s: &Side| s.body.map_or(Matrix3::identity(), |b| infos[b].a0);
        Ok(RelativeJointCoordinate(
            match (self.tree.dim, &j.kind, &self.tree.topology.tree[ji]) {
                (Dim::Planar, JointKind::Revolute { .. }, _) => JointCoordinate::Angle2 {
                    i: si,
                    j: sj,
                    psi0: angle_of(&a0(&sj)) - angle_of(&a0(&si)),
                },
                (_, JointKind::Prismatic { axis }, None) => {
                    let nbar = a0(&si).transpose() * axis.vec().normalize();
                    let d0 = self.slide(&si, &nbar, &sj);
                    JointCoordinate::Slide {
                        i: si,
                        nbar,
                        j: sj,
                        d0,
                    }
                }
                (_, _, Some(tj)) if !tj.coords.is_empty() => JointCoordinate::Tree {
                    z: tj.coords[0],
                    sign: if tj.reversed { -1.0 } else { 1.0 },
                },
                _ => {
                    return Err(unsupported(format!(
                        "sensor `{}`: the coordinate of joint `{}` ({:?}) is not available in the relative formulation",
                        sensor, j.name, j.kind
                    )));
                }
            },
        ))
    }

    /// n·(r_j − r_i) with n fixed at side i, from the last kinematics pass.
    fn slide(&self, i: &Side, nbar: &Vector3<f64>, j: &Side) -> f64 {
        let (n, _) = dir_at(self, i, nbar);
        let (pi, _) = point_at(self, i);
        let (pj, _) = point_at(self, j);
        n.dot(&(pj - pi))
    }

    /// Read the sensors at (q, q̇, q̈) into `out`, after one kinematics pass at (q, q̇).
    pub(crate) fn read_sensors(
        &mut self,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        qdd: Option<&DVector<f64>>,
        out: &mut [f64],
    ) {
        self.kinematics(q, qd);
        let mut sensors = std::mem::take(&mut self.sensors);
        sensors.read(self, q, qd, qdd, out);
        self.sensors = sensors;
    }
}

impl SensorQuery for Relative {
    type JointCoordinate = RelativeJointCoordinate;

    /// From the last kinematics pass, which the caller has run at q.
    fn body_frame(&self, body: usize, _q: &DVector<f64>) -> (Vector3<f64>, Matrix3<f64>) {
        let f = self.bodies[body].frame;
        (self.frames.position[f], self.frames.rotation[f])
    }

    fn joint_coordinate(
        &self,
        joint: &RelativeJointCoordinate,
        q: &DVector<f64>,
        _qd: &DVector<f64>,
    ) -> JointReading {
        match &joint.0 {
            JointCoordinate::Angle2 { i, j, psi0 } => {
                let (ti, _) = angle_at(self, i);
                let (tj, _) = angle_at(self, j);
                let raw = tj - ti - psi0;
                let d = Vector2::new(raw.cos(), raw.sin());
                JointReading::Angle(d.y.atan2(d.x))
            }
            JointCoordinate::Tree { z, sign } => JointReading::Value(sign * q[*z]),
            JointCoordinate::Slide { i, nbar, j, d0 } => {
                JointReading::Value(self.slide(i, nbar, j) - d0)
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
        self.forces.elements.reading(element, self, q, qd)
    }

    /// From the last kinematics pass (at q, q̇): the body frame's Z = {ṡ; ω} and
    /// Ż = Σ_e v_e ë + D over the elementary joints e on its path (§4.2, ë = L_e q̈), and
    /// the origin's ṙ0 = ṡ + ω × r0, r̈0 = s̈ + ω̇ × r0 + ω × ṙ0.
    fn frame_motion(
        &self,
        body: usize,
        _q: &DVector<f64>,
        _qd: &DVector<f64>,
        qdd: &DVector<f64>,
    ) -> FrameMotion {
        let f = self.bodies[body].frame;
        let (r0, rotation) = (self.frames.position[f], self.frames.rotation[f]);
        let z = self.frames.velocity[f];
        let mut zd = self.frames.bias[f];
        for &e in &self.tree.paths[f] {
            let acceleration: f64 = self.tree.elem_rate[e]
                .iter()
                .map(|&(c, k)| k * qdd[c])
                .sum();
            zd += self.frames.elem_twist[e] * acceleration;
        }
        let omega = z.fixed_rows::<3>(3).into_owned();
        let omega_dot = zd.fixed_rows::<3>(3).into_owned();
        let velocity = z.fixed_rows::<3>(0) + omega.cross(&r0);
        FrameMotion {
            origin: r0,
            rotation,
            velocity,
            angular_velocity: omega,
            acceleration: zd.fixed_rows::<3>(0) + omega_dot.cross(&r0) + omega.cross(&velocity),
            angular_acceleration: omega_dot,
        }
    }
}
