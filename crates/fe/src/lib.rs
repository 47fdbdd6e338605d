//! Finite-element preprocessing for flexmbd (methods.md §1–§2.3, §6.1).

pub mod assembly;
pub mod beam;
pub mod error;
pub mod modal;
pub mod reduced;
pub mod rigid;
pub mod spec;

pub use error::FeError;
pub use reduced::{
    Dof, MassCloud, ModeInventory, NodeDof, NodeModes, ReducedBody, ShapeIntegrals,
    StiffeningIntegrals,
};
pub use spec::{BeamBodySpec, Damping, Geometry, Material, ReferenceFrame, Section};
