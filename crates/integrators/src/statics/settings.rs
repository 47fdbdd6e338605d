//! [`StaticSettings`]: the tolerances, iteration limits and budgets of the static solve, with
//! their CHOSEN defaults (the module `statics` documents what each bounds).

/// Settings of [`super::solve_static`] (CHOSEN defaults).
#[derive(Clone, Debug, PartialEq)]
pub struct StaticSettings {
    /// Penalty α; `None`: 10⁴ k_ref (module documentation).
    pub penalty: Option<f64>,
    /// ε_r: ‖g‖∞ ≤ ε_r f_ref.
    pub tol_residual: f64,
    /// ε_q: ‖Δq‖∞ ≤ ε_q max(1, ‖q‖∞).
    pub tol_q: f64,
    /// ε_Φ: ‖Φ‖∞ ≤ ε_Φ.
    pub tol_phi: f64,
    /// Newton iterations per load level.
    pub max_iterations: usize,
    /// Newton iterations of one attempt in all (full load, load stepping and the neutral
    /// polish together): a bound on the work for a load the structure cannot carry, where
    /// load stepping would halve and retry its increments for minutes on a large scene (an
    /// iteration costs n evaluations with the difference tangent). Most converging solves take
    /// under 30; scene B with its beams at 100 E (a stiff, ill-conditioned case) takes 629.
    pub max_total_iterations: usize,
    /// Gauss–Newton iterations of the projections onto Φ = 0 in one attempt, likewise: a
    /// point far off the constraints (a line-search trial after a huge step) can take 50 each,
    /// and each forms and factorises an n × n matrix. A converging solve takes a few per Newton
    /// iteration.
    pub max_projection_iterations: usize,
    /// First load increment 1/`load_steps` when the full load fails.
    pub load_steps: usize,
    /// Smallest load increment before giving up.
    pub min_increment: f64,
    /// Tangent by forward differences of the residual (true) or the formulation's K.
    pub fd_tangent: bool,
}

impl Default for StaticSettings {
    fn default() -> Self {
        StaticSettings {
            penalty: None,
            tol_residual: 1e-10,
            tol_q: 1e-10,
            tol_phi: 1e-10,
            max_iterations: 50,
            max_total_iterations: 2000,
            max_projection_iterations: 2000,
            load_steps: 4,
            min_increment: 1e-3,
            fd_tangent: true,
        }
    }
}
