//! The planar formulation's side of the sensors written once (`flexmbd_model::sensors`): its
//! joint coordinates (the relative angle of two body-fixed directions, or a prismatic slide,
//! each from its value at q0) and the [`SensorQuery`] the shared sensors read.

use flexmbd_core::{ElementReading, FrameMotion, JointReading, SensorQuery};
use flexmbd_model::sensors::{SensorHandles, Sensors};
use flexmbd_model::{BodyId, JointKind, ModelError, PreparedScene};
use nalgebra::{DVector, Matrix3, Vector2, Vector3};

use super::Planar;
use super::kinematics::{Direction, PlanarMarker};

/// A joint coordinate as the planar formulation reads it.
#[derive(Clone, Debug)]
pub struct PlanarJointCoordinate(JointCoordinate);

#[derive(Clone, Debug)]
enum JointCoordinate {
    /// The angle from d₁ to d₂ less its value φ₀ at q0.
    Angle {
        /// Direction fixed in body 1.
        d1: Direction,
        /// Direction fixed in body 2.
        d2: Direction,
        /// The angle at q0 (rad).
        phi0: f64,
    },
    /// Prismatic joint: (r_P2 − r_P1) · d₁ − s₀.
    Slide {
        /// Marker on body 1.
        p1: PlanarMarker,
        /// Marker on body 2.
        p2: PlanarMarker,
        /// Sliding direction, fixed in body 1.
        d1: Direction,
        /// The slide at q0 (m).
        s0: f64,
    },
}

/// The planar formulation's sensors.
pub(super) type PlanarSensors = Sensors<PlanarMarker, PlanarJointCoordinate>;

impl Planar {
    /// The scene's sensors (joint coordinates measured from their value at q0).
    pub(super) fn build_sensors(
        &self,
        prepared: &PreparedScene,
        q0: &DVector<f64>,
    ) -> Result<PlanarSensors, ModelError> {
        let scene = prepared.scene();
        let joint = |_sensor: &str, id: flexmbd_model::JointId| {
            let j = &scene.joints[id.0];
            let ends = prepared.joint_markers()[id.0];
            Ok(if let JointKind::Prismatic { axis } = &j.kind {
                let (p1, p2, d1) = self.prismatic_parts(prepared, j, ends, axis, q0)?;
                let s0 = self.slide(&p1, &p2, &d1, q0, &self.zero_rates);
                PlanarJointCoordinate(JointCoordinate::Slide { p1, p2, d1, s0 })
            } else {
                let d1 = self.direction_at(ends.first);
                let d2 = self.direction_at(ends.second);
                let phi0 = self.angle(&d1, &d2, q0);
                PlanarJointCoordinate(JointCoordinate::Angle { d1, d2, phi0 })
            })
        };
        let mode = |BodyId(b): BodyId, index: usize| {
            let body = &self.bodies[b];
            (index < body.n_modes).then_some(body.first_mode + index)
        };
        Sensors::new(
            prepared,
            SensorHandles {
                marker: |id| self.marker_of(prepared, id),
                joint,
                mode,
            },
        )
    }
}

impl SensorQuery for Planar {
    type JointCoordinate = PlanarJointCoordinate;

    /// {r0, A} with A the rotation of the normalised unit vector u about z.
    fn body_frame(&self, body: usize, q: &DVector<f64>) -> (Vector3<f64>, Matrix3<f64>) {
        let frame = self.frame(&self.bodies[body], q, &self.zero_rates);
        let u: Vector2<f64> = frame.u / frame.u.norm();
        let rotation = Matrix3::new(u.x, -u.y, 0.0, u.y, u.x, 0.0, 0.0, 0.0, 1.0);
        (Vector3::new(frame.r0.x, frame.r0.y, 0.0), rotation)
    }

    fn joint_coordinate(
        &self,
        joint: &PlanarJointCoordinate,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> JointReading {
        match &joint.0 {
            JointCoordinate::Angle { d1, d2, phi0 } => {
                JointReading::Angle(self.angle(d1, d2, q) - phi0)
            }
            JointCoordinate::Slide { p1, p2, d1, s0 } => {
                JointReading::Value(self.slide(p1, p2, d1, q, qd) - s0)
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

    /// (r0, u) = T x_b is linear in the coordinates: the frame's rates at q̇ are its
    /// velocities and at q̈ its accelerations; with |u| = 1, u̇ = ω E u gives
    /// ω = u × u̇ and ω̇ = u × ü (z components).
    fn frame_motion(
        &self,
        body: usize,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        qdd: &DVector<f64>,
    ) -> FrameMotion {
        let b = &self.bodies[body];
        let frame = self.frame(b, q, qd);
        let accelerations = self.frame(b, q, qdd);
        let (r0, rotation) = self.body_frame(body, q);
        let u2 = frame.u.norm_squared();
        let cross = |a: &Vector2<f64>, b: &Vector2<f64>| a.x * b.y - a.y * b.x;
        let v3 = |v: Vector2<f64>| Vector3::new(v.x, v.y, 0.0);
        FrameMotion {
            origin: r0,
            rotation,
            velocity: v3(frame.r0_rate),
            angular_velocity: Vector3::z() * cross(&frame.u, &frame.u_rate) / u2,
            acceleration: v3(accelerations.r0_rate),
            angular_acceleration: Vector3::z() * cross(&frame.u, &accelerations.u_rate) / u2,
        }
    }
}
