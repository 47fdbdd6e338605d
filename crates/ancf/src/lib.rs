//! ANCF cable elements in 2D and 3D: the large-deformation reference model of the
//! spin-up beam (thesis ch. 4; docs/methods.md §7; docs/scenes.md §5).
//!
//! - `element` (private): Hermite interpolation, constant mass, distributed
//!   load, elastic line energy with ε = |r′| − 1 and |κ|² = |r′ × r″|²/|r′|⁴, analytic
//!   force and tangent, 5/3 Gauss points (§7.1–§7.2) [Berzeri & Shabana 2000;
//!   Gerstmayr & Shabana 2006; Gerstmayr & Irschik 2008].
//! - [`Cable`]: the [`flexmbd_core::Formulation`] with the driven-hub root
//!   constraints, exact Φ_t and bias (§7.3), sensors `tip_ux`, `tip_uy` (`tip_uz`),
//!   `energy`, and a static-equilibrium solver with load stepping (§5.4 item 4).
//! - [`run_spin_up`]: the spin-up run with ALI3-P (§5) returning a [`History`]; [`run_cable`]
//!   the same from a cable's own start, without the static equilibrium.
//!
//! Choices recorded: curvature measure with |r′|² (Exudyn-compatible, §7.2 correction);
//! Gauss orders 9/5 (5 and 3 points); analytic tangent (checked against finite
//! differences); root at the origin, hub axis z; 3D cable without torsion and with
//! isotropic bending (§7.2 "Limits"); dense M and K as the integrators expect.
//!
//! Checked by the tests against the Exudyn static check and the 2D spin-up reference, and
//! for mesh convergence by the `convergence` example (figures in `docs/design.md`).

#![warn(missing_docs)]

mod cable;
mod element;
mod run;
mod spec;

pub use cable::{Cable, StaticError, StaticReport};
pub use run::{AncfError, History, run_cable, run_spin_up, run_spin_up_or_stop, run_spin_up_with};
pub use spec::CableSpec;
