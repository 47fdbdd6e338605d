//! Finite-element preprocessing for flexmbd (methods.md §1–§2.3, §6.1).

pub mod reduced;

pub use reduced::{
    Dof, MassCloud, ModeInventory, NodeDof, NodeModes, ReducedBody, ShapeIntegrals,
    StiffeningIntegrals,
};
