//! The scene's sensors in the relative formulation: their resolution to markers, tree
//! coordinates and modal coordinates at compile time, and their evaluation after one
//! kinematics pass (positions and velocities of markers, optionally in a body's frame; 2D
//! joint angles unwrapped across turns; slider displacements from their t = 0 value; tree
//! and modal coordinates; the total energy of [`Relative::total_energy`]).

use flexmbd_core::Dim;
use flexmbd_model::{JointKind, ModelError, Scene, SensorKind};
use nalgebra::{DVector, Matrix3, Vector2, Vector3};

use crate::kinematics::{angle_at, angle_of, dir_at, point_at};
use crate::system::{Relative, unsupported};
use crate::topology::{BodyInfo, Side, side_of};

pub(crate) enum CompiledSensor {
    Position {
        side: Side,
        axis: usize,
        frame: Option<usize>,
    },
    Velocity {
        side: Side,
        axis: usize,
        frame: Option<usize>,
    },
    /// 2D joint angle between the two markers' directions (node rotations included).
    Angle2 {
        i: Side,
        j: Side,
        psi0: f64,
        last: f64,
        turns: f64,
    },
    /// A joint coordinate of the tree.
    Coord {
        z: usize,
        sign: f64,
    },
    /// Displacement of j's marker relative to i's along an axis fixed at i.
    Slide {
        i: Side,
        nbar: Vector3<f64>,
        j: Side,
        d0: f64,
    },
    Modal(Option<usize>),
    Energy,
}

impl Relative {
    pub(crate) fn build_sensors(
        &mut self,
        scene: &Scene,
        infos: &[BodyInfo],
    ) -> Result<(), ModelError> {
        let body_index = |name: &str| scene.bodies.iter().position(|b| b.name == name);
        let axis = |a: flexmbd_model::Axis, name: &str| -> Result<usize, ModelError> {
            let i = a.index();
            if self.dim == Dim::Planar && i == 2 {
                return Err(unsupported(format!(
                    "sensor `{name}`: a planar scene has no z component"
                )));
            }
            Ok(i)
        };
        let mut sensors = Vec::new();
        for s in &scene.sensors {
            let sensor = match &s.kind {
                SensorKind::Position {
                    body,
                    marker,
                    component,
                    frame,
                } => CompiledSensor::Position {
                    side: side_of(scene, infos, body, marker),
                    axis: axis(*component, &s.name)?,
                    frame: frame.as_deref().and_then(body_index),
                },
                SensorKind::Velocity {
                    body,
                    marker,
                    component,
                    frame,
                } => CompiledSensor::Velocity {
                    side: side_of(scene, infos, body, marker),
                    axis: axis(*component, &s.name)?,
                    frame: frame.as_deref().and_then(body_index),
                },
                SensorKind::JointCoordinate { joint } => {
                    self.joint_coordinate_sensor(scene, infos, &s.name, joint)?
                }
                SensorKind::Modal { body, index } => {
                    let bi = body_index(body).expect("validated");
                    let b = &self.bodies[bi];
                    CompiledSensor::Modal((*index < b.n_modes).then_some(b.first_mode + index))
                }
                SensorKind::Energy => CompiledSensor::Energy,
            };
            sensors.push(sensor);
        }
        // Reference values of slide sensors.
        let (q0, qd0) = (self.q0.clone(), self.qd0.clone());
        self.last_z.copy_from(&q0);
        self.last_zd.copy_from(&qd0);
        self.kinematics(&q0, &qd0);
        for s in &mut sensors {
            if let CompiledSensor::Slide { i, nbar, j, d0 } = s {
                let (n, _) = dir_at(self, i, nbar);
                let (pi, _) = point_at(self, i);
                let (pj, _) = point_at(self, j);
                *d0 = n.dot(&(pj - pi));
            }
        }
        self.sensors = sensors;
        Ok(())
    }

    /// The coordinate of a joint: a planar revolute's angle between its markers, a cut
    /// prismatic's slide, or a tree joint's first coordinate.
    fn joint_coordinate_sensor(
        &self,
        scene: &Scene,
        infos: &[BodyInfo],
        sensor: &str,
        joint: &str,
    ) -> Result<CompiledSensor, ModelError> {
        let ji = scene
            .joints
            .iter()
            .position(|j| j.name == joint)
            .expect("validated");
        let j = &scene.joints[ji];
        let si = side_of(scene, infos, &j.body1, &j.marker1);
        let sj = side_of(scene, infos, &j.body2, &j.marker2);
        let a0 = |s: &Side| s.body.map_or(Matrix3::identity(), |b| infos[b].a0);
        Ok(match (self.dim, &j.kind, &self.topology.tree[ji]) {
            (Dim::Planar, JointKind::Revolute { .. }, _) => CompiledSensor::Angle2 {
                i: si,
                j: sj,
                psi0: angle_of(&a0(&sj)) - angle_of(&a0(&si)),
                last: 0.0,
                turns: 0.0,
            },
            (_, JointKind::Prismatic { axis }, None) => {
                let nbar = a0(&si).transpose() * axis.vec().normalize();
                CompiledSensor::Slide {
                    i: si,
                    nbar,
                    j: sj,
                    d0: 0.0,
                }
            }
            (_, _, Some(tj)) if !tj.coords.is_empty() => CompiledSensor::Coord {
                z: tj.coords[0],
                sign: if tj.reversed { -1.0 } else { 1.0 },
            },
            _ => {
                return Err(unsupported(format!(
                    "sensor `{}`: the coordinate of joint `{joint}` ({:?}) is not available in the relative formulation",
                    sensor, j.kind
                )));
            }
        })
    }

    /// The sensors' values at (q, q̇) into `out` (one kinematics pass; the energy sensor
    /// re-evaluates the body inertia).
    pub(crate) fn read_sensors(&mut self, q: &DVector<f64>, qd: &DVector<f64>, out: &mut [f64]) {
        self.last_z.copy_from(q);
        self.last_zd.copy_from(qd);
        self.kinematics(q, qd);
        for k in 0..self.sensors.len() {
            let frame_of = |rel: &Relative, fb: Option<usize>| {
                fb.map(|b| {
                    let f = rel.bodies[b].frame;
                    (rel.frame_position[f], rel.frame_rotation[f])
                })
            };
            out[k] = match &self.sensors[k] {
                CompiledSensor::Position { side, axis, frame } => {
                    let (p, _) = point_at(self, side);
                    match frame_of(self, *frame) {
                        None => p[*axis],
                        Some((r0, a)) => (a.transpose() * (p - r0))[*axis],
                    }
                }
                CompiledSensor::Velocity { side, axis, frame } => {
                    let (_, v) = point_at(self, side);
                    match frame_of(self, *frame) {
                        None => v[*axis],
                        Some((_, a)) => (a.transpose() * v)[*axis],
                    }
                }
                CompiledSensor::Angle2 { i, j, psi0, .. } => {
                    let (ti, _) = angle_at(self, i);
                    let (tj, _) = angle_at(self, j);
                    let raw = tj - ti - psi0;
                    let d = Vector2::new(raw.cos(), raw.sin());
                    let a = d.y.atan2(d.x);
                    let CompiledSensor::Angle2 { last, turns, .. } = &mut self.sensors[k] else {
                        unreachable!()
                    };
                    let tau = std::f64::consts::TAU;
                    let mut v = a + *turns * tau;
                    while v - *last > std::f64::consts::PI {
                        *turns -= 1.0;
                        v -= tau;
                    }
                    while v - *last < -std::f64::consts::PI {
                        *turns += 1.0;
                        v += tau;
                    }
                    *last = v;
                    v
                }
                CompiledSensor::Coord { z, sign } => sign * q[*z],
                CompiledSensor::Slide { i, nbar, j, d0 } => {
                    let (n, _) = dir_at(self, i, nbar);
                    let (pi, _) = point_at(self, i);
                    let (pj, _) = point_at(self, j);
                    n.dot(&(pj - pi)) - d0
                }
                CompiledSensor::Modal(idx) => idx.map_or(0.0, |i| q[i]),
                CompiledSensor::Energy => self.energy(q, qd),
            };
        }
    }
}
