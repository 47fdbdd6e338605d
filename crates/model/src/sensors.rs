//! Sensors, written once for every formulation over its [`SensorQuery`].
//!
//! Each sensor of the scene is resolved once, when a formulation compiles the prepared scene,
//! into the formulation's handles (a marker, a joint coordinate, a modal coordinate's index),
//! and read at output instants:
//!
//! - `Position`: r_P, or Aᵀ(r_P − r0) in the body frame {r0, A} of `frame`;
//! - `Velocity`: ṙ_P, or Aᵀṙ_P in the axes of `frame`;
//! - `JointCoordinate`: the formulation's reading relative to the start; an angle known up to
//!   whole turns is made continuous by counting turns between readings (a jump over π is a
//!   turn);
//! - `Modal`: the modal coordinate y_k;
//! - `Energy`: the formulation's total mechanical energy;
//! - `Angle`: one intrinsic Cardan angle (x, y′, z″) of R = A(t) A(0)ᵀ, A(t) from
//!   [`SensorQuery::body_frame`] and A(0) the orientation the scene gives the body: with
//!   R = R_x(α) R_y(β) R_z(γ), α = atan2(−R₁₂, R₂₂), β = asin R₀₂, γ = atan2(−R₀₁, R₀₀);
//! - `ElementForce`: a force element's tension (a tyre's normal force) or length (a tyre's
//!   deflection), from [`SensorQuery::element_reading`], the code of the element's forces;
//! - `InterfaceForce`: the force or moment the rest of the system exerts on a body at a
//!   marker, from the body's balance at (q, q̇, q̈) ([`crate::interface_force`]).
//!
//! A `displacement` sensor reports its value minus the marker's undeformed value
//! ([`PreparedScene::sensor_offsets`]).

use std::f64::consts::{PI, TAU};

use flexmbd_core::{Dim, InvalidValue, JointReading, SensorQuery};
use flexmbd_fe::solid::stress::{Stress, largest_principal, von_mises};
use nalgebra::{DMatrix, DVector, Matrix3};

use crate::error::ModelError;
use crate::interface_force::InterfaceForce;
use crate::prepared::{BodyId, JointId, MarkerId, PreparedScene, SensorTarget};
use crate::scene::{Axis, ElementQuantity, InterfaceQuantity, StressQuantity};

/// One sensor, resolved into a formulation's handles (`M`: marker, `J`: joint coordinate).
#[derive(Clone, Debug)]
enum Reading<M, J> {
    Position {
        marker: M,
        axis: usize,
        frame: Option<usize>,
    },
    Velocity {
        marker: M,
        axis: usize,
        frame: Option<usize>,
    },
    JointCoordinate {
        joint: J,
        /// The last value reported, and the whole turns counted so far.
        last: f64,
        turns: f64,
    },
    /// The coordinate index of the mode (`None`: a body without that mode reads 0).
    Modal(Option<usize>),
    Energy,
    Angle {
        body: usize,
        axis: Axis,
        reference: Matrix3<f64>,
    },
    ElementForce {
        element: usize,
        quantity: ElementQuantity,
    },
    /// The balance of the marker's body (boxed: it holds the body's inertia and storage).
    InterfaceForce(Box<InterfaceForce<M>>),
    /// The coordinate index of each mode of the body, and the set's stress shapes.
    Stress {
        coords: Vec<Option<usize>>,
        shapes: Vec<DMatrix<f64>>,
        quantity: StressQuantity,
    },
}

/// The sensors of a scene, compiled for one formulation.
#[derive(Clone, Debug)]
pub struct Sensors<M, J> {
    names: Vec<String>,
    readings: Vec<Reading<M, J>>,
    offsets: Vec<f64>,
    /// q̈ = 0, for reads without accelerations.
    at_rest: DVector<f64>,
}

impl<M, J> Default for Sensors<M, J> {
    fn default() -> Self {
        Sensors {
            names: Vec::new(),
            readings: Vec::new(),
            offsets: Vec::new(),
            at_rest: DVector::zeros(0),
        }
    }
}

/// How a formulation names what the sensors read, given while it compiles a scene.
pub struct SensorHandles<MarkerOf, JointOf, ModeOf> {
    /// The formulation's handle of a marker.
    pub marker: MarkerOf,
    /// The handle of a joint's coordinate for the sensor named by the first argument, or the
    /// refusal (a joint whose coordinate this formulation cannot read).
    pub joint: JointOf,
    /// The coordinate index of mode `index` of a body (`None` if it has no such mode).
    pub mode: ModeOf,
}

impl<M, J> Sensors<M, J> {
    /// Resolve the prepared scene's sensors into a formulation's handles.
    pub fn new<MarkerOf, JointOf, ModeOf>(
        prepared: &PreparedScene,
        mut handles: SensorHandles<MarkerOf, JointOf, ModeOf>,
    ) -> Result<Self, ModelError>
    where
        MarkerOf: FnMut(MarkerId) -> M,
        JointOf: FnMut(&str, JointId) -> Result<J, ModelError>,
        ModeOf: FnMut(BodyId, usize) -> Option<usize>,
    {
        let scene = prepared.scene();
        let mut readings = Vec::with_capacity(scene.sensors.len());
        for (sensor, target) in scene.sensors.iter().zip(prepared.sensor_targets()) {
            let axis = |component: Axis| {
                if scene.dim == Dim::Planar && component == Axis::Z {
                    return Err(scene.invalid(InvalidValue::new(
                        format!("sensors[{}].component", sensor.name),
                        "Z",
                        "a planar scene has x and y components only",
                    )));
                }
                Ok(component.index())
            };
            readings.push(match *target {
                SensorTarget::Position {
                    marker,
                    component,
                    frame,
                } => Reading::Position {
                    marker: (handles.marker)(marker),
                    axis: axis(component)?,
                    frame: frame.map(|b| b.0),
                },
                SensorTarget::Velocity {
                    marker,
                    component,
                    frame,
                } => Reading::Velocity {
                    marker: (handles.marker)(marker),
                    axis: axis(component)?,
                    frame: frame.map(|b| b.0),
                },
                SensorTarget::JointCoordinate(joint) => Reading::JointCoordinate {
                    joint: (handles.joint)(&sensor.name, joint)?,
                    last: 0.0,
                    turns: 0.0,
                },
                SensorTarget::Modal { body, index } => Reading::Modal((handles.mode)(body, index)),
                SensorTarget::Energy => Reading::Energy,
                SensorTarget::Angle {
                    body,
                    axis,
                    reference,
                } => Reading::Angle {
                    body: body.0,
                    axis,
                    reference,
                },
                SensorTarget::ElementForce { element, quantity } => {
                    Reading::ElementForce { element, quantity }
                }
                SensorTarget::InterfaceForce {
                    marker,
                    component,
                    quantity,
                    frame,
                } => Reading::InterfaceForce(Box::new(InterfaceForce::new(
                    prepared,
                    marker,
                    (
                        quantity,
                        interface_axis(scene, &sensor.name, component, quantity)?,
                        frame.map(|b| b.0),
                    ),
                    &mut handles.marker,
                    &mut handles.mode,
                )?)),
                SensorTarget::Stress {
                    body,
                    table,
                    quantity,
                } => {
                    let shapes = prepared.stress_set(table).shapes.clone();
                    let n = shapes.first().map_or(0, |s| s.ncols());
                    Reading::Stress {
                        coords: (0..n).map(|k| (handles.mode)(body, k)).collect(),
                        shapes,
                        quantity,
                    }
                }
            });
        }
        Ok(Sensors {
            names: scene.sensors.iter().map(|s| s.name.clone()).collect(),
            readings,
            offsets: prepared.sensor_offsets().to_vec(),
            at_rest: DVector::zeros(0),
        })
    }

    /// The sensors' names, in output order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Read every sensor at (q, q̇, q̈) into `out` (one value per name); `qdd` `None` reads
    /// as q̈ = 0 (a state at rest; only interface forces read q̈). A formulation with
    /// recursive kinematics runs its kinematic pass at (q, q̇) first.
    pub fn read<K>(
        &mut self,
        query: &mut K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        qdd: Option<&DVector<f64>>,
        out: &mut [f64],
    ) where
        K: SensorQuery<Marker = M, JointCoordinate = J>,
    {
        let qdd = match qdd {
            Some(qdd) => qdd,
            None => {
                // Sized once: the first read at rest of a scene allocates it.
                if self.at_rest.len() != q.len() {
                    self.at_rest = DVector::zeros(q.len());
                }
                &self.at_rest
            }
        };
        for (k, reading) in self.readings.iter_mut().enumerate() {
            let value = match reading {
                Reading::Position {
                    marker,
                    axis,
                    frame,
                } => {
                    let (p, _) = query.marker_state(marker, q, qd);
                    match frame {
                        None => p[*axis],
                        Some(body) => {
                            let (r0, a) = query.body_frame(*body, q);
                            (a.transpose() * (p - r0))[*axis]
                        }
                    }
                }
                Reading::Velocity {
                    marker,
                    axis,
                    frame,
                } => {
                    let (_, v) = query.marker_state(marker, q, qd);
                    match frame {
                        None => v[*axis],
                        Some(body) => (query.body_frame(*body, q).1.transpose() * v)[*axis],
                    }
                }
                Reading::JointCoordinate { joint, last, turns } => {
                    match query.joint_coordinate(joint, q, qd) {
                        JointReading::Value(v) => v,
                        JointReading::Angle(angle) => continuous_angle(angle, last, turns),
                    }
                }
                Reading::Modal(index) => index.map_or(0.0, |i| q[i]),
                Reading::Energy => query.total_energy(q, qd),
                Reading::Angle {
                    body,
                    axis,
                    reference,
                } => {
                    let (_, a) = query.body_frame(*body, q);
                    cardan_angles(&(a * reference.transpose()))[axis.index()]
                }
                Reading::ElementForce { element, quantity } => {
                    let reading = query.element_reading(*element, q, qd);
                    match quantity {
                        ElementQuantity::Force => reading.force,
                        ElementQuantity::Length => reading.length,
                    }
                }
                Reading::InterfaceForce(sensor) => sensor.read(query, q, qd, qdd),
                Reading::Stress {
                    coords,
                    shapes,
                    quantity,
                } => {
                    // σ = S y node by node, into a fixed 6-vector: no allocation per read
                    // (sensors are read every step when the output interval is the step).
                    shapes
                        .iter()
                        .map(|s| {
                            let mut sigma = Stress::zeros();
                            for (k, c) in coords.iter().enumerate() {
                                if let Some(i) = c {
                                    sigma += s.fixed_view::<6, 1>(0, k) * q[*i];
                                }
                            }
                            match (*quantity, quantity.component()) {
                                (_, Some(c)) => sigma[c],
                                (StressQuantity::MaxPrincipal, None) => largest_principal(&sigma),
                                _ => von_mises(&sigma),
                            }
                        })
                        .fold(f64::NEG_INFINITY, f64::max)
                }
            };
            out[k] = value - self.offsets[k];
        }
    }
}

/// The component index of an interface force: a planar scene's forces have x and y
/// components, its moments a z component only.
fn interface_axis(
    scene: &crate::scene::Scene,
    sensor: &str,
    component: Axis,
    quantity: InterfaceQuantity,
) -> Result<usize, ModelError> {
    let planar = scene.dim == Dim::Planar;
    match (planar, quantity, component) {
        (true, InterfaceQuantity::Force, Axis::Z) => Err(scene.invalid(InvalidValue::new(
            format!("sensors[{sensor}].component"),
            "Z",
            "a planar scene's forces have x and y components only",
        ))),
        (true, InterfaceQuantity::Moment, Axis::X | Axis::Y) => {
            Err(scene.invalid(InvalidValue::new(
                format!("sensors[{sensor}].component"),
                format!("{component:?}"),
                "a planar scene's moments have a z component only",
            )))
        }
        _ => Ok(component.index()),
    }
}

/// The intrinsic Cardan angles (α, β, γ) about x, y′, z″ of the rotation R =
/// R_x(α) R_y(β) R_z(γ) (β in [−π/2, π/2]).
pub fn cardan_angles(r: &Matrix3<f64>) -> [f64; 3] {
    [
        (-r[(1, 2)]).atan2(r[(2, 2)]),
        r[(0, 2)].clamp(-1.0, 1.0).asin(),
        (-r[(0, 1)]).atan2(r[(0, 0)]),
    ]
}

/// The angle `angle` (known up to whole turns) made continuous with the last value reported:
/// whole turns are added while the jump from `last` exceeds π.
fn continuous_angle(angle: f64, last: &mut f64, turns: &mut f64) -> f64 {
    let mut v = angle + *turns * TAU;
    while v - *last > PI {
        *turns -= 1.0;
        v -= TAU;
    }
    while v - *last < -PI {
        *turns += 1.0;
        v += TAU;
    }
    *last = v;
    v
}

#[cfg(test)]
mod tests {
    use super::{cardan_angles, continuous_angle};
    use nalgebra::{Rotation3, Vector3};

    #[test]
    fn cardan_angles_undo_the_three_rotations() {
        let (a, b, c) = (0.3, -0.7, 2.1);
        let r = Rotation3::from_axis_angle(&Vector3::x_axis(), a)
            * Rotation3::from_axis_angle(&Vector3::y_axis(), b)
            * Rotation3::from_axis_angle(&Vector3::z_axis(), c);
        let [x, y, z] = cardan_angles(r.matrix());
        assert!((x - a).abs() < 1e-14 && (y - b).abs() < 1e-14 && (z - c).abs() < 1e-14);
        // Pitch about +y turns the x axis (forward) down: nose down is positive.
        let pitch = Rotation3::from_axis_angle(&Vector3::y_axis(), 0.1);
        assert!((pitch * Vector3::x()).z < 0.0);
        assert!((cardan_angles(pitch.matrix())[1] - 0.1).abs() < 1e-15);
    }
    use std::f64::consts::{PI, TAU};

    #[test]
    fn an_angle_read_modulo_a_turn_is_made_continuous() {
        let (mut last, mut turns) = (0.0, 0.0);
        // A joint turning at 1 rad per reading, read in (−π, π].
        let mut reported = Vec::new();
        for k in 0..20 {
            let true_angle = k as f64;
            let wrapped = (true_angle + PI).rem_euclid(TAU) - PI;
            reported.push(continuous_angle(wrapped, &mut last, &mut turns));
        }
        for (k, v) in reported.iter().enumerate() {
            assert!((v - k as f64).abs() < 1e-12, "reading {k}: {v}");
        }
        assert_eq!(turns, 3.0);
        // And back: turning the other way removes the turns again.
        for k in (0..20).rev() {
            let wrapped = (k as f64 + PI).rem_euclid(TAU) - PI;
            let v = continuous_angle(wrapped, &mut last, &mut turns);
            assert!((v - k as f64).abs() < 1e-12, "back, reading {k}: {v}");
        }
        assert_eq!(turns, 0.0);
    }
}
