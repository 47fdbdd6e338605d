//! Time integrators of flexmbd, generic over [`flexmbd_core::Formulation`]:
//! ALI3-P on the trapezoidal rule (docs/methods.md §5), its consistent initial conditions, and
//! the static equilibrium that can start a run (docs/methods.md §5.4 item 4, [`statics`]),
//! and the linearised free vibration about it ([`linearise`](mod@linearise), docs/methods.md §5.5).

#![warn(missing_docs)]

pub mod ali3p;
pub mod arrow_llt;
mod contraction;
pub mod declared_entries;
pub mod declared_llt;
mod error;
mod initial;
mod jacobian_pattern;
pub mod linearise;
pub mod lu;
mod settings;
pub mod sparse_llt;
mod start_from;
pub mod statics;
mod structured;

pub use ali3p::{Ali3p, Ali3pSettings, Checkpoint, IntegratorError, Stats};
pub use linearise::{Linearisation, Mode, ModeKind, VibrationError, linearise};
pub use start_from::StartFrom;
pub use statics::{StaticCounters, StaticError, StaticSettings, StaticSolution, solve_static};
