//! Sensors of the planar scene, built from the scene's sensor list and read at (q, q̇):
//! marker positions and velocities (ground or body-frame components), joint coordinates
//! (the relative angle, unwrapped across ±π, or a prismatic slide), modal coordinates and
//! the total energy.
//!
//! Kept apart, building and reading together, to be replaced by the shared sensor code.

use flexmbd_model::{Axis, JointKind, ModelError, PreparedScene, SensorKind};
use nalgebra::DVector;

use super::Planar;
use super::build::names::{body_index, marker_index};
use super::kinematics::{Direction, PlanarMarker};

/// What a sensor reads.
pub(super) enum PlanarSensor {
    /// A component of a marker's position, in ground axes or in the frame of body `frame`.
    Position {
        body: Option<usize>,
        marker: usize,
        axis: usize,
        frame: Option<usize>,
    },
    /// A component of a marker's velocity, in ground axes or turned into the frame of body
    /// `frame`.
    Velocity {
        body: Option<usize>,
        marker: usize,
        axis: usize,
        frame: Option<usize>,
    },
    /// The angle from d₁ to d₂ less its value φ₀ at t = 0, continuous across ±π.
    JointAngle {
        d1: Direction,
        d2: Direction,
        phi0: f64,
        unwrapper: AngleUnwrapper,
    },
    /// Prismatic joint coordinate: (r_P2 − r_P1) · d₁ − s₀.
    Slide {
        p1: PlanarMarker,
        p2: PlanarMarker,
        d1: Direction,
        s0: f64,
    },
    /// A modal coordinate (`None`: beyond the body's modes, reads 0).
    Modal { coordinate: Option<usize> },
    /// Kinetic + gravity + elastic + spring energy.
    Energy,
}

/// Makes an angle in (−π, π] continuous from one reading to the next by counting turns.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct AngleUnwrapper {
    /// The previous reading (rad).
    previous: f64,
    /// Whole turns added to the angle.
    turns: f64,
}

impl AngleUnwrapper {
    /// The angle plus the whole turns that bring it within π of the previous reading.
    pub(super) fn unwrap(&mut self, angle: f64) -> f64 {
        let tau = std::f64::consts::TAU;
        let mut v = angle + self.turns * tau;
        while v - self.previous > std::f64::consts::PI {
            self.turns -= 1.0;
            v -= tau;
        }
        while v - self.previous < -std::f64::consts::PI {
            self.turns += 1.0;
            v += tau;
        }
        self.previous = v;
        v
    }
}

/// The index of a planar component (x → 0, y → 1); a z component is refused.
fn planar_axis(a: Axis, name: &str) -> Result<usize, ModelError> {
    match a {
        Axis::X => Ok(0),
        Axis::Y => Ok(1),
        Axis::Z => Err(ModelError::Unsupported(format!(
            "sensor `{name}`: a planar scene has no z component"
        ))),
    }
}

impl Planar {
    /// The scene's sensors, in order (joint coordinates measured from their value at q0).
    pub(super) fn build_sensors(
        &self,
        prepared: &PreparedScene,
        q0: &DVector<f64>,
    ) -> Result<Vec<PlanarSensor>, ModelError> {
        let scene = prepared.scene();
        let zero = DVector::zeros(self.n_coordinates);
        let mut sensors = Vec::new();
        for s in &scene.sensors {
            let sensor = match &s.kind {
                SensorKind::Position {
                    body,
                    marker,
                    component,
                    frame,
                } => {
                    let (b, k) = marker_index(scene, body, marker);
                    PlanarSensor::Position {
                        body: b,
                        marker: k,
                        axis: planar_axis(*component, &s.name)?,
                        frame: frame.as_deref().and_then(|f| body_index(scene, f)),
                    }
                }
                SensorKind::Velocity {
                    body,
                    marker,
                    component,
                    frame,
                } => {
                    let (b, k) = marker_index(scene, body, marker);
                    PlanarSensor::Velocity {
                        body: b,
                        marker: k,
                        axis: planar_axis(*component, &s.name)?,
                        frame: frame.as_deref().and_then(|f| body_index(scene, f)),
                    }
                }
                SensorKind::JointCoordinate { joint } => {
                    let j = scene
                        .joints
                        .iter()
                        .find(|j| &j.name == joint)
                        .expect("validated");
                    if let JointKind::Prismatic { axis } = &j.kind {
                        let (p1, p2, d1) = self.prismatic_parts(scene, j, axis, q0)?;
                        let s0 = self.slide(&p1, &p2, &d1, q0, &zero);
                        PlanarSensor::Slide { p1, p2, d1, s0 }
                    } else {
                        let d1 = self.direction_at(scene, &j.body1, &j.marker1);
                        let d2 = self.direction_at(scene, &j.body2, &j.marker2);
                        let phi0 = self.angle(&d1, &d2, q0);
                        PlanarSensor::JointAngle {
                            d1,
                            d2,
                            phi0,
                            unwrapper: AngleUnwrapper::default(),
                        }
                    }
                }
                SensorKind::Modal { body, index } => {
                    let b = &self.bodies[body_index(scene, body).expect("validated")];
                    PlanarSensor::Modal {
                        coordinate: (*index < b.n_modes).then_some(b.first_mode + index),
                    }
                }
                SensorKind::Energy => PlanarSensor::Energy,
            };
            sensors.push(sensor);
        }
        Ok(sensors)
    }

    /// Read every sensor at (q, q̇) into `out`.
    pub(super) fn read_sensors(&mut self, q: &DVector<f64>, qd: &DVector<f64>, out: &mut [f64]) {
        for k in 0..self.sensors.len() {
            out[k] = match &self.sensors[k] {
                PlanarSensor::Position {
                    body,
                    marker,
                    axis,
                    frame,
                } => {
                    let (p, _, _) = self.marker_motion(&self.sensed_marker(*body, *marker), q, qd);
                    match frame {
                        None => p[*axis],
                        Some(fb) => {
                            let z = DVector::zeros(q.len());
                            let r0 = self.frame(&self.bodies[*fb], q, &z).r0;
                            (self.frame_rotation(*fb, q).transpose() * (p - r0))[*axis]
                        }
                    }
                }
                PlanarSensor::Velocity {
                    body,
                    marker,
                    axis,
                    frame,
                } => {
                    let (_, v, _) = self.marker_motion(&self.sensed_marker(*body, *marker), q, qd);
                    match frame {
                        None => v[*axis],
                        Some(fb) => (self.frame_rotation(*fb, q).transpose() * v)[*axis],
                    }
                }
                PlanarSensor::JointAngle { d1, d2, phi0, .. } => {
                    let a = self.angle(d1, d2, q) - phi0;
                    let PlanarSensor::JointAngle { unwrapper, .. } = &mut self.sensors[k] else {
                        unreachable!()
                    };
                    unwrapper.unwrap(a)
                }
                PlanarSensor::Slide { p1, p2, d1, s0 } => self.slide(p1, p2, d1, q, qd) - s0,
                PlanarSensor::Modal { coordinate } => coordinate.map_or(0.0, |i| q[i]),
                PlanarSensor::Energy => self.energy(q, qd),
            };
        }
    }

    /// Marker `k` of body `body` (or of the ground).
    fn sensed_marker(&self, body: Option<usize>, k: usize) -> PlanarMarker {
        match body {
            None => PlanarMarker::Ground(self.ground_markers[k]),
            Some(body_index) => {
                let b = &self.bodies[body_index];
                PlanarMarker::Body {
                    body: body_index,
                    rbar: b.markers[k].position,
                    node: b.markers[k].node,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn unwrapping_continues_across_pi() {
        let mut unwrapper = AngleUnwrapper::default();
        let readings = [0.0, 3.0, -3.0, -0.5, 2.0, -2.5, 3.1];
        let mut previous = 0.0;
        let mut out = Vec::new();
        for a in readings {
            let v = unwrapper.unwrap(a);
            assert!((v - previous).abs() <= PI, "{previous} → {v}");
            // The reading differs from the angle by whole turns.
            let turns = (v - a) / std::f64::consts::TAU;
            assert!((turns - turns.round()).abs() < 1e-12, "{a} → {v}");
            previous = v;
            out.push(v);
        }
        let tau = std::f64::consts::TAU;
        let expected = [
            0.0,
            3.0,
            -3.0 + tau,
            -0.5 + tau,
            2.0 + tau,
            -2.5 + 2.0 * tau,
            3.1 + tau,
        ];
        for (v, x) in out.iter().zip(expected) {
            assert!((v - x).abs() < 1e-12, "{out:?}");
        }
    }

    #[test]
    fn a_planar_sensor_has_no_z() {
        assert_eq!(planar_axis(Axis::X, "s").unwrap(), 0);
        assert_eq!(planar_axis(Axis::Y, "s").unwrap(), 1);
        let e = planar_axis(Axis::Z, "tip_z").unwrap_err().to_string();
        assert!(e.contains("tip_z") && e.contains("no z"), "{e}");
    }
}
