//! The absolute formulation of flexmbd: natural (fully Cartesian) coordinates,
//! basic points and unit vectors shared between bodies (García de Jalón & Bayo
//! 1994), with floating-frame flexible bodies in natural coordinates (thesis ch. 2,
//! methods.md §3). It compiles a [`flexmbd_model::Scene`] and implements
//! [`flexmbd_core::Formulation`].

mod flex;
pub mod planar;

use flexmbd_core::Dim;
use flexmbd_model::{ModelError, Scene};

pub use planar::Planar;

/// Compile a scene for the absolute formulation.
pub fn compile(scene: &Scene) -> Result<Planar, ModelError> {
    if scene.dim != Dim::Planar {
        return Err(ModelError::Unsupported(
            "the absolute formulation runs planar scenes only so far; 3D scenes are not supported yet".into(),
        ));
    }
    let prepared = scene.prepare_bodies()?;
    Planar::compile(scene, prepared)
}
