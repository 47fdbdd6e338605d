//! Why an ALI3-P step or start failed ([`crate::Ali3p`]): each variant names the time and
//! what to try.

/// Why the integrator stopped.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum IntegratorError {
    /// Newton did not converge within the iteration limit.
    #[error(
        "Newton did not converge at t = {t:.6} s after {iterations} iterations: ‖Δq‖∞ = {dq:.3e}, ‖Φ‖∞ = {phi:.3e}; try a smaller step, fewer or softer modes, or more damping"
    )]
    NoConvergence {
        /// Time of the step being solved.
        t: f64,
        /// Iterations made.
        iterations: usize,
        /// Last correction norm.
        dq: f64,
        /// Last constraint violation.
        phi: f64,
    },
    /// The iteration produced non-finite numbers.
    #[error("the solution diverged (non-finite values) at t = {t:.6} s; try a smaller step")]
    Diverged {
        /// Time of the step being solved.
        t: f64,
    },
    /// The leading matrix could not be factorised.
    #[error(
        "the leading matrix is singular at t = {t:.6} s (pivot ratio {pivot_ratio:.3e}); check for bodies without mass or coordinates without stiffness or constraint"
    )]
    Singular {
        /// Time.
        t: f64,
        /// Smallest / largest pivot.
        pivot_ratio: f64,
    },
    /// Initial conditions could not be made consistent.
    #[error(
        "initial positions could not be made consistent: ‖Φ‖∞ = {phi:.3e} after {iterations} iterations (no assembly closes every loop: check the markers of the closing joints and the bodies' lengths)"
    )]
    InconsistentStart {
        /// Remaining violation.
        phi: f64,
        /// Iterations made.
        iterations: usize,
    },
}
