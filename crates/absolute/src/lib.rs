//! The absolute formulation of flexmbd: natural (fully Cartesian) coordinates,
//! basic points and unit vectors shared between bodies (García de Jalón & Bayo
//! 1994), with floating-frame flexible bodies in natural coordinates (thesis ch. 2,
//! docs/methods.md §3). It compiles a [`flexmbd_model::PreparedScene`] and implements
//! [`flexmbd_core::Formulation`]: planar scenes by [`Planar`], spatial scenes by
//! [`Spatial`], both behind the [`Absolute`] enum that [`compile`] returns.

mod flex;
pub mod planar;
pub mod spatial;

use flexmbd_core::{Coordinates, Dim, Formulation, Request, State, SystemTerms};
use flexmbd_model::{ModelError, PreparedScene};

pub use planar::Planar;
pub use spatial::Spatial;

/// A compiled scene: planar or spatial natural coordinates.
pub enum Absolute {
    /// A 2D scene.
    Planar(Box<Planar>),
    /// A 3D scene.
    Spatial(Box<Spatial>),
}

/// Compile a prepared scene for the absolute formulation.
///
/// The scene must be prepared first ([`PreparedScene::new`]: validated, rewritten for its
/// stiffening method, its bodies reduced and built, its names resolved):
///
/// ```
/// use flexmbd_core::Formulation;
/// use flexmbd_model::{PreparedScene, Scene};
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/double_four_bar.ron");
/// let scene = Scene::load(path)?;
/// let formulation = flexmbd_absolute::compile(&PreparedScene::new(&scene)?)?;
/// assert!(formulation.n_coordinates() > 0);
/// # Ok::<(), flexmbd_model::ModelError>(())
/// ```
///
/// A bare scene is not accepted, so no formulation can run a scene whose stiffening rewrite
/// (FNL2's axial basis, substructuring) was skipped:
///
/// ```compile_fail
/// use flexmbd_model::Scene;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/double_four_bar.ron");
/// let scene = Scene::load(path)?;
/// let formulation = flexmbd_absolute::compile(&scene)?;
/// # Ok::<(), flexmbd_model::ModelError>(())
/// ```
pub fn compile(prepared: &PreparedScene) -> Result<Absolute, ModelError> {
    match prepared.scene().dim {
        Dim::Planar => Ok(Absolute::Planar(Box::new(Planar::compile(prepared)?))),
        Dim::Spatial => Ok(Absolute::Spatial(Box::new(Spatial::compile(prepared)?))),
    }
}

macro_rules! both {
    ($self:expr, $f:ident => $e:expr) => {
        match $self {
            Absolute::Planar($f) => $e,
            Absolute::Spatial($f) => $e,
        }
    };
}

impl Formulation for Absolute {
    fn coordinates(&self) -> &Coordinates {
        both!(self, f => f.coordinates())
    }
    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        both!(self, f => f.evaluate(state, req, out))
    }
    fn symmetric_tangent(&self) -> bool {
        both!(self, f => f.symmetric_tangent())
    }
    fn constant_tangents(&self) -> bool {
        both!(self, f => f.constant_tangents())
    }
    fn constant_mass(&self) -> bool {
        both!(self, f => f.constant_mass())
    }
    fn declared_pattern(&self) -> Option<flexmbd_core::DeclaredPattern> {
        both!(self, f => f.declared_pattern())
    }
    fn predictor_repeats_miss(&self) -> bool {
        both!(self, f => f.predictor_repeats_miss())
    }
    fn driven_coordinates(&self) -> Option<flexmbd_core::DrivenCoordinates> {
        both!(self, f => f.driven_coordinates())
    }
    fn driven_motion(&self, t: f64, out: &mut [[f64; 3]]) {
        both!(self, f => f.driven_motion(t, out))
    }
}

impl flexmbd_core::Observe for Absolute {
    fn sensor_names(&self) -> &[String] {
        both!(self, f => f.sensor_names())
    }
    fn sensors(&mut self, state: State<'_>, out: &mut [f64]) {
        both!(self, f => f.sensors(state, out))
    }
    fn body_poses(&mut self, state: State<'_>, out: &mut [flexmbd_core::BodyPose]) {
        both!(self, f => f.body_poses(state, out))
    }
}
