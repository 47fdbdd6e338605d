//! **flexmbd** — real-time flexible multibody dynamics after U. Lugrís,
//! *Real-time methods in flexible multibody dynamics* (PhD thesis, 2008).
//!
//! This facade re-exports the layered crates, in the order data flows through them
//! (see `docs/design.md`):
//!
//! - [`core`]: shared vocabulary (dimension, skew helpers, the error that names a bad input);
//! - [`fe`]: finite-element preprocessing — beams, modal analysis, Craig–Bampton,
//!   the mass cloud and the 13 inertia shape integrals;
//! - [`body`]: the reduced flexible body at run time, its inertia terms by
//!   B-matrix projection or by shape integrals, and its elastic forces;
//! - [`model`]: the scene format (RON) with its validation;
//! - [`absolute`]: the natural-coordinate formulation;
//! - [`integrators`]: ALI3-P on the trapezoidal rule;
//! - [`simulation`]: a scene run end to end, with its summary and history.

pub use flexmbd_body as body;
pub use flexmbd_core as core;
pub use flexmbd_fe as fe;

mod error;
pub mod inventory;
pub mod simulation;

pub use error::Error;
pub use simulation::{Simulation, integrator_settings};

pub use flexmbd_absolute as absolute;
pub use flexmbd_ancf as ancf;
pub use flexmbd_integrators as integrators;
pub use flexmbd_model as model;
