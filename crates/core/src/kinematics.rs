//! The kinematic query a formulation answers for the elements written once over it: force
//! elements (`flexmbd_model::force_elements`) and, later, sensors and inputs.
//!
//! An element names the formulation's markers by the formulation's own handle
//! ([`MarkerKinematics::Marker`], resolved once when the scene is compiled) and asks, at a
//! state (q, q̇):
//!
//! - the marker's position r_P and velocity ṙ_P (ground components; z = 0 in a planar
//!   scene);
//! - the non-zero columns ∂r_P/∂q_i of the marker's position Jacobian, so that a force F on
//!   the marker adds Q_i += ∂r_P/∂q_i · F (the virtual work F · δr_P, docs/methods.md §2.6).
//!
//! A formulation whose kinematics are recursive (the relative one) answers from its last
//! kinematic pass, which must be at (q, q̇): it calls the elements after that pass.

use nalgebra::{DVector, Matrix3, Vector3};

/// Marker positions, velocities and Jacobian columns of a formulation.
pub trait MarkerKinematics {
    /// The formulation's handle of a marker.
    type Marker;

    /// Position r_P (m) and velocity ṙ_P (m/s) of `marker` at (q, q̇), ground components.
    fn marker_state(
        &self,
        marker: &Self::Marker,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector3<f64>, Vector3<f64>);

    /// Visit the non-zero columns (i, ∂r_P/∂q_i) of `marker` at q. A coordinate visited twice
    /// has the sum of its columns.
    fn marker_jacobian(
        &mut self,
        marker: &Self::Marker,
        q: &DVector<f64>,
        visit: &mut dyn FnMut(usize, Vector3<f64>),
    );
}

/// What the sensors written once (`flexmbd_model::sensors`) need beyond the markers.
pub trait SensorQuery: MarkerKinematics {
    /// The formulation's handle of a joint coordinate (resolved when the scene is compiled).
    type JointCoordinate;

    /// Origin r0 (m) and rotation A (columns: body axes, ground components) of a body's frame
    /// at q, the body named by its index in the prepared scene. Planar: z = 0, A about z.
    fn body_frame(&self, body: usize, q: &DVector<f64>) -> (Vector3<f64>, Matrix3<f64>);

    /// A joint coordinate at (q, q̇), relative to its value at the start.
    fn joint_coordinate(
        &self,
        joint: &Self::JointCoordinate,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> JointReading;

    /// Total mechanical energy at (q, q̇) (J): kinetic, gravity, elastic, force elements.
    fn total_energy(&mut self, q: &DVector<f64>, qd: &DVector<f64>) -> f64;

    /// The state of force element `element` (its index in the scene's `forces`) at (q, q̇),
    /// computed by the same code as its forces.
    fn element_reading(
        &self,
        element: usize,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> ElementReading;
}

/// A force element's state as a sensor reads it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ElementReading {
    /// Tension (N; a tyre: its normal force, ≥ 0).
    pub force: f64,
    /// The length its laws are evaluated at (m; a tyre: its deflection δ, negative in the
    /// air).
    pub length: f64,
}

/// A joint coordinate as a formulation reads it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointReading {
    /// An angle known up to whole turns (rad); the sensor counts the turns.
    Angle(f64),
    /// A distance or an angle already continuous in time (m or rad).
    Value(f64),
}
