//! Shared vocabulary of flexmbd: the spatial dimension of a model, small-rotation
//! helpers (skew matrices), and the error that names a bad input value.
//!
//! Everything here is plain data with no dependency on the later stages
//! (`fe` → `body` → formulations → integrators), so every crate can use it.

#![warn(missing_docs)]

pub mod driven;
pub mod formulation;
pub mod kinematics;
pub mod pattern;

pub use driven::{DrivenCoordinates, DrivenEliminated};
pub use formulation::{
    BodyMotion, BodyPose, CompiledScene, Coordinates, Formulation, Observe, Request, State,
    SystemTerms,
};
pub use kinematics::{ElementReading, FrameMotion, JointReading, MarkerKinematics, SensorQuery};
pub use pattern::DeclaredPattern;

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// Planar (x–y plane, rotation about z) or spatial model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Dim {
    /// 2D: the x–y plane; a body has 3 rigid-body DOFs (x, y, θz).
    Planar,
    /// 3D: a body has 6 rigid-body DOFs.
    Spatial,
}

impl Dim {
    /// Number of translational components (2 or 3).
    pub const fn n_trans(self) -> usize {
        match self {
            Dim::Planar => 2,
            Dim::Spatial => 3,
        }
    }
    /// Number of rotational components (1 or 3).
    pub const fn n_rot(self) -> usize {
        match self {
            Dim::Planar => 1,
            Dim::Spatial => 3,
        }
    }
    /// Rigid-body DOFs of one body (3 or 6).
    pub const fn n_rigid(self) -> usize {
        self.n_trans() + self.n_rot()
    }
}

impl std::fmt::Display for Dim {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Dim::Planar => "2D",
            Dim::Spatial => "3D",
        })
    }
}

/// The skew-symmetric matrix ã with ã b = a × b (docs/methods.md §0).
#[inline]
pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// A value in a model that is not physical or not consistent, named by its
/// field path (e.g. `section.area`) so that the user can find it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field} = {value}: {reason}")]
pub struct InvalidValue {
    /// Dotted path of the offending field in the model description.
    pub field: String,
    /// The offending value, as the user wrote it (formatted).
    pub value: String,
    /// Why it is refused.
    pub reason: String,
}

impl InvalidValue {
    /// Build an error for `field` holding `value`.
    pub fn new(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        reason: impl Into<String>,
    ) -> Self {
        Self {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

/// Refuse a value that is not finite and strictly positive.
pub fn require_positive(field: &str, value: f64) -> Result<f64, InvalidValue> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(InvalidValue::new(field, value, "must be finite and > 0"))
    }
}

/// Refuse a value that is not finite and non-negative.
pub fn require_non_negative(field: &str, value: f64) -> Result<f64, InvalidValue> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(InvalidValue::new(field, value, "must be finite and >= 0"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skew_is_cross_product() {
        let a = Vector3::new(1.0, -2.0, 0.5);
        let b = Vector3::new(0.3, 4.0, -1.0);
        assert!((skew(&a) * b - a.cross(&b)).norm() < 1e-15);
        assert_eq!(skew(&a).transpose(), -skew(&a));
    }

    #[test]
    fn positivity_checks_name_the_field() {
        let e = require_positive("section.area", -1.0).unwrap_err();
        assert_eq!(e.field, "section.area");
        assert!(e.to_string().contains("-1"));
        assert!(require_positive("x", f64::NAN).is_err());
        assert!(require_non_negative("x", 0.0).is_ok());
    }
}
