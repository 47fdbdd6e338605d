//! Time integrators of flexmbd, generic over [`flexmbd_core::Formulation`]:
//! ALI3-P on the trapezoidal rule (methods.md §5) and its consistent initial conditions.

pub mod ali3p;
mod initial;
pub mod lu;

pub use ali3p::{Ali3p, Ali3pSettings, IntegratorError, Stats};
