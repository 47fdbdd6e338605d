//! Sensors, built and evaluated here, as the planar code reports them: a marker's position
//! and velocity in ground components or in a body frame (`Aᵀ (r − r0)`, `Aᵀ ṙ`), the angle
//! of a revolute joint (`atan2(σ, κ)`, unwrapped, relative to t = 0) or the slide of a
//! prismatic joint, a modal coordinate, and the total energy.
//!
//! Kept apart from the rest of the formulation as it stands: shared sensor code is to
//! replace it.

use flexmbd_model::{JointKind, ModelError, SensorKind};
use nalgebra::{DVector, Vector3};

use super::Spatial;
use super::joints::perpendiculars;
use super::kinematics::Term;
use super::lookup::TermLookup;

/// A scene sensor resolved to terms and coordinates.
pub(super) enum CompiledSensor {
    /// A marker's position component, in ground components (`frame: None`) or in the frame
    /// of body `frame`.
    Position {
        term: Term,
        axis: usize,
        frame: Option<usize>,
    },
    /// A marker's velocity component, in ground components or in a body frame.
    Velocity {
        term: Term,
        axis: usize,
        frame: Option<usize>,
    },
    /// A revolute joint's angle from `phi0` (its value at t = 0), unwrapped: `last` is the
    /// last value reported, `turns` the whole turns added.
    Angle {
        p1: Term,
        p2: Term,
        a: Term,
        phi0: f64,
        last: f64,
        turns: f64,
    },
    /// A prismatic joint's slide `(x − origin)·z − s0`.
    Slide {
        x: Term,
        origin: Term,
        z: Term,
        s0: f64,
    },
    /// The coordinate at this index of q.
    Modal { coordinate: usize },
    /// The total mechanical energy.
    Energy,
}

fn unsupported(what: String) -> ModelError {
    ModelError::Unsupported(what)
}

/// The scene's sensors, in order (angle references `phi0` still zero).
pub(super) fn build_sensors(lookup: &TermLookup) -> Result<Vec<CompiledSensor>, ModelError> {
    let scene = lookup.scene;
    let mut sensors = Vec::new();
    for s in &scene.sensors {
        let frame_of_name = |f: &Option<String>| f.as_deref().and_then(|f| lookup.body(f));
        let sensor = match &s.kind {
            SensorKind::Position {
                body,
                marker,
                component,
                frame,
            } => CompiledSensor::Position {
                term: lookup.point(body, marker),
                axis: component.index(),
                frame: frame_of_name(frame),
            },
            SensorKind::Velocity {
                body,
                marker,
                component,
                frame,
            } => CompiledSensor::Velocity {
                term: lookup.point(body, marker),
                axis: component.index(),
                frame: frame_of_name(frame),
            },
            SensorKind::JointCoordinate { joint } => joint_coordinate(lookup, &s.name, joint)?,
            SensorKind::Modal { body, index } => {
                let body_index = lookup.body(body).ok_or_else(|| {
                    unsupported(format!(
                        "{}: sensor `{}`: the ground has no modes",
                        scene.origin, s.name
                    ))
                })?;
                let b = &lookup.bodies[body_index];
                if *index >= b.n_modes {
                    return Err(unsupported(format!(
                        "{}: sensor `{}`: body `{body}` runs with {} modal coordinates",
                        scene.origin, s.name, b.n_modes
                    )));
                }
                CompiledSensor::Modal {
                    coordinate: b.offset + 12 + index,
                }
            }
            SensorKind::Energy => CompiledSensor::Energy,
        };
        sensors.push(sensor);
    }
    Ok(sensors)
}

/// The angle of a revolute joint or the slide of a prismatic joint.
fn joint_coordinate(
    lookup: &TermLookup,
    sensor: &str,
    joint: &str,
) -> Result<CompiledSensor, ModelError> {
    let scene = lookup.scene;
    let j = scene
        .joints
        .iter()
        .find(|j| j.name == joint)
        .expect("validated");
    let dir1 = |v: &Vector3<f64>| lookup.direction(&j.body1, &j.marker1, v);
    let dir2 = |v: &Vector3<f64>| lookup.direction(&j.body2, &j.marker2, v);
    Ok(match &j.kind {
        JointKind::Revolute { axis: Some(axis) } => {
            let a = axis.vec().normalize();
            let (n1, _) = perpendiculars(&a);
            CompiledSensor::Angle {
                p1: dir1(&n1),
                p2: dir2(&n1),
                a: dir1(&a),
                phi0: 0.0,
                last: 0.0,
                turns: 0.0,
            }
        }
        JointKind::Prismatic { axis } => {
            let a = axis.vec().normalize();
            let (p1, p2) = (
                lookup.point(&j.body1, &j.marker1),
                lookup.point(&j.body2, &j.marker2),
            );
            let s0 = (lookup.position0(&p2) - lookup.position0(&p1)).dot(&a);
            CompiledSensor::Slide {
                x: p2,
                origin: p1,
                z: dir1(&a),
                s0,
            }
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
    /// Every sensor's value at (q, q̇), in order; angle sensors update their unwrapping.
    pub(super) fn evaluate_sensors(
        &mut self,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        out: &mut [f64],
    ) {
        for k in 0..self.sensors.len() {
            out[k] = match &self.sensors[k] {
                CompiledSensor::Position { term, axis, frame } => {
                    let p = term.eval(&self.bodies, q, qd).value;
                    match frame {
                        None => p[*axis],
                        Some(fb) => {
                            let (r0, a) = self.frame(*fb, q);
                            a.tr_mul(&(p - r0))[*axis]
                        }
                    }
                }
                CompiledSensor::Velocity { term, axis, frame } => {
                    let v = term.eval(&self.bodies, q, qd).rate;
                    match frame {
                        None => v[*axis],
                        Some(fb) => self.frame(*fb, q).1.tr_mul(&v)[*axis],
                    }
                }
                CompiledSensor::Angle {
                    p1, p2, a, phi0, ..
                } => {
                    let ang = self.angle(p1, p2, a, q, qd) - phi0;
                    let CompiledSensor::Angle { last, turns, .. } = &mut self.sensors[k] else {
                        unreachable!()
                    };
                    let tau = std::f64::consts::TAU;
                    let mut v = ang + *turns * tau;
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
                CompiledSensor::Slide { x, origin, z, s0 } => {
                    let d =
                        x.eval(&self.bodies, q, qd).value - origin.eval(&self.bodies, q, qd).value;
                    d.dot(&z.eval(&self.bodies, q, qd).value) - s0
                }
                CompiledSensor::Modal { coordinate } => q[*coordinate],
                CompiledSensor::Energy => self.energy(q, qd),
            };
        }
    }
}
