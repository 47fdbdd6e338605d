//! Why a static solve failed.

/// Why no static equilibrium was found.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StaticError {
    /// Newton (with line search and load stepping) did not converge.
    #[error(
        "static equilibrium not found after {iterations} Newton iterations: ‖g‖∞ = {residual:.3e} (scale {force_scale:.3e}), ‖Φ‖∞ = {phi:.3e}, load factor reached {load_factor:.4}; {hint}"
    )]
    NoConvergence {
        /// Newton iterations made, all levels.
        iterations: usize,
        /// Last ‖g‖∞.
        residual: f64,
        /// Force scale f_ref the residual is judged against.
        force_scale: f64,
        /// Last ‖Φ‖∞.
        phi: f64,
        /// Largest load factor μ solved (0 when not even the first increment converged).
        load_factor: f64,
        /// What to try.
        hint: &'static str,
    },
    /// The tangent at the initial guess could not be factorised.
    #[error(
        "the static tangent is singular at the initial guess (pivot ratio {pivot_ratio:.3e}, Newton iteration {iterations}); a coordinate has neither stiffness nor constraint (a free rigid-body motion, or a mechanism with no load-bearing equilibrium)"
    )]
    Singular {
        /// Newton iterations made.
        iterations: usize,
        /// Smallest / largest pivot.
        pivot_ratio: f64,
    },
    /// The equilibrium found lies where the coordinates stop describing the motion: the
    /// mass matrix on the motions the constraints allow is singular there (a spherical or
    /// free joint's Cardan angles at their ±90° singularity, where the generalized forces of
    /// a turn vanish without the body being in equilibrium).
    #[error(
        "the point found is a coordinate singularity, not an equilibrium: the mass matrix on the allowed motions is singular there (pivot ratio {pivot_ratio:.3e}); a spherical or free joint's middle Cardan angle reached ±90° — start from another orientation or use the absolute formulation"
    )]
    CoordinateSingularity {
        /// Smallest / largest pivot of M + α_M Φ_qᵀΦ_q.
        pivot_ratio: f64,
    },
    /// The point found balances the generalized forces but not the bodies: the coordinates
    /// are nearly singular there (a Cardan middle angle near ±90°), so the residual, small in
    /// the coordinates, is a finite force on the bodies.
    #[error(
        "the point found is not an equilibrium of the bodies: the coordinates are nearly singular there, and the residual left would accelerate them by {acceleration:.3e} (scale f_ref/m_ref {scale:.3e}); a spherical or free joint's middle Cardan angle is near ±90° — start from another orientation or use the absolute formulation"
    )]
    NearlySingular {
        /// ‖H⁻¹g‖∞ at the point found.
        acceleration: f64,
        /// f_ref / m_ref.
        scale: f64,
    },
    /// The formulation returned non-finite numbers at the initial guess.
    #[error(
        "the forces or constraints are not finite at the initial guess (‖g‖∞ = {residual}); check the scene"
    )]
    NonFinite {
        /// The residual found.
        residual: f64,
    },
}
