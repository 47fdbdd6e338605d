//! The settings of ALI3-P, each with its default and how to choose it, and the counters
//! of what a run did (docs/methods.md §5.2–§5.3).

/// Solver settings (docs/methods.md §5.2–§5.3; defaults there are marked CHOSEN). A scene's
/// solver block sets `step`, `penalty`, `tol_q`/`tol_phi` and `max_iterations`
/// (`flexmbd::integrator_settings`); the others keep their defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct Ali3pSettings {
    /// Time step h (s). Default: `1e-3`.
    ///
    /// Fixed for the run. Choose it to resolve the fastest mode that matters: the
    /// trapezoidal rule is unconditionally stable but damps nothing and shifts the frequency
    /// of a mode with ωh ≳ 1, so keep h below about 1/(10 f) for the highest frequency f (Hz)
    /// whose motion you read; smaller steps also help Newton through singular configurations.
    pub step: f64,
    /// Penalty α. Default: `None`, i.e. 4·10⁴ m_ref / h² with m_ref the largest diagonal
    /// entry of M at t₀.
    ///
    /// The default makes the penalty term h²α/4 Φ_qᵀΦ_q of the leading matrix 10⁴ times its
    /// largest mass, which holds the constraints to round-off in a few iterations without
    /// ruining the matrix's conditioning. Set a value only to reproduce a published run;
    /// much larger values cost accuracy in the projections, much smaller ones iterations.
    pub penalty: Option<f64>,
    /// Relative position tolerance ε_q of Newton: ‖Δq‖∞ ≤ ε_q max(1, ‖q‖∞) (with the
    /// contraction estimate of the error). Default: `1e-9`.
    ///
    /// It bounds the error each step leaves in the positions, so it is the floor of a
    /// trajectory's accuracy once h is small; tighter values cost iterations, and values
    /// near round-off (1e-15 relative) cannot be met.
    pub tol_q: f64,
    /// Constraint tolerance ε_Φ on ‖Φ‖∞ (m or rad, as the constraints). Default: `1e-9`.
    ///
    /// Usually equal to `tol_q`; both must hold for a step to converge.
    pub tol_phi: f64,
    /// At the iteration limit, accept the iterate when ‖Φ‖∞ is below this and the last
    /// correction ‖Δq‖∞ below this times max(‖q‖∞, 1) (counted in
    /// [`Stats::accepted_unconverged`]); otherwise the step fails. Default: `1e-6`.
    ///
    /// A safety valve for singular configurations where the multipliers converge slowly;
    /// set it to `tol_phi` to make every such step an error instead.
    pub accept_phi: f64,
    /// Newton iteration limit per step. Default: `20`.
    ///
    /// A step that needs more is too large for the motion: a higher limit rarely helps,
    /// a smaller `step` does.
    pub max_iterations: usize,
    /// Modified Newton: keep the factorised f_q while ‖Δq_i‖/‖Δq_{i−1}‖ < 0.5; an iteration on
    /// a kept f_q that fails this turns the rest of the step to full Newton (methods.md
    /// §5.2). Default: `false`.
    ///
    /// Saves factorisations when f_q changes slowly (large n, mild nonlinearity) at the cost
    /// of extra iterations; off, every iteration refactorises.
    pub reuse_tangent: bool,
    /// Judge the first Newton iterate by the contraction the steps before measured
    /// (`crate::contraction`): stop after one correction when the second, as estimated,
    /// would be within the tolerance. Default: `false`.
    ///
    /// Saves 14–25 % of the iterations on the Iltis runs, but the steps' errors then reach
    /// the tolerance where a second iteration left 10⁻⁵ of it, and at a kink of the road the
    /// steps before do not predict the step's contraction: the rigid vehicle's link forces
    /// move by 6e-5 of their range from a run at a 10⁴ times tighter tolerance, against
    /// 1e-7 without it. Off, the first iterate is judged by ‖Δq₁‖ itself.
    pub first_iterate_from_contraction: bool,
    /// Factorise the leading matrix with its structure where that pays
    /// (`crate::structured`): the arrow form of a tree in relative coordinates (a vehicle's
    /// chassis and corners, [`ARROW_FROM`](crate::arrow_llt::ARROW_FROM) coordinates and
    /// more), the sparse Cholesky of large systems with a sparse factor
    /// ([`SPARSE_FROM`](crate::sparse_llt::SPARSE_FROM) coordinates and more: natural
    /// coordinates of many bodies). Default: `true`.
    ///
    /// The structured and dense factorisations give the same trajectories to round-off;
    /// `false` keeps the dense kernels (to check that, and the speed, in tests and benchmarks).
    pub structured_factorisation: bool,
    /// Time the phases (evaluation, factorisation, projection) on every k-th step only and
    /// scale, so that reading the clock does not cost more than the step. Default: `32`.
    ///
    /// A timed step reads the clock a dozen times (about 20 ns each on a virtual machine):
    /// at k = 8 that was 3 % of the 4-mode relative spin-up's 1.1 µs step.
    ///
    /// `1` times every step (exact phase times, slower small systems); larger values only
    /// make the phase times in [`Stats`] coarser. Never changes the trajectory.
    pub profile_every: usize,
}

impl Default for Ali3pSettings {
    fn default() -> Self {
        Ali3pSettings {
            step: 1e-3,
            penalty: None,
            tol_q: 1e-9,
            tol_phi: 1e-9,
            accept_phi: 1e-6,
            max_iterations: 20,
            reuse_tangent: false,
            first_iterate_from_contraction: false,
            structured_factorisation: true,
            profile_every: 32,
        }
    }
}

/// What a run did (russell-style counters, asserted by tests).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stats {
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations, all steps.
    pub newton_iterations: usize,
    /// Factorisations of the leading matrix (Cholesky, or LU where it is not SPD).
    pub factorizations: usize,
    /// Of those, factorisations by a structured Cholesky (`crate::structured`).
    pub structured_factorizations: usize,
    /// Formulation evaluation passes.
    pub evaluations: usize,
    /// Steps accepted at the iteration limit with ‖Φ‖∞ ≤ accept_phi.
    pub accepted_unconverged: usize,
    /// Steps that failed (the run stops at the first).
    pub failed_steps: usize,
    /// Seconds in formulation evaluations.
    pub time_evaluation: f64,
    /// Seconds forming and factorising the leading matrix and solving.
    pub time_factorization: f64,
    /// Seconds in the velocity and acceleration projections (forming, factorising, solving;
    /// their formulation passes are counted under `time_evaluation`).
    pub time_projection: f64,
}
