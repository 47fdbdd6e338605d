//! Static equilibrium of a [`Formulation`] at a fixed time (docs/methods.md §5.4 item 4, first
//! option; docs/scenes.md §5 "start from rest with the beam in static equilibrium"), used to
//! start a run at rest in equilibrium before ALI3-P's consistent initial conditions.
//!
//! At fixed t with q̇ = 0 find q and λ with
//!
//! Q(q) − Φ_q(q)ᵀ λ = 0,  Φ(q, t) = 0,
//!
//! the specified coordinates (`Formulation::specified_coordinates`) held at their initial
//! values. Q holds every applied and elastic force (gravity, springs, FNL1/FNL2/FS0
//! elasticity); velocity-dependent terms vanish at q̇ = 0.
//!
//! **Structure: the augmented-Lagrangian Newton step of ALI3-P** (docs/methods.md §5.1–§5.2),
//! with the static residual in place of the dynamic one and M replaced by nothing:
//!
//! g(q; λ) = −Q(q) + Φ_qᵀ(λ + αΦ),  H Δq = −g,
//!
//! H = ∂g/∂q = −∂Q/∂q + Σ_i (λ + αΦ)_i ∇²Φ_i + Φ_qᵀ α Φ_q,
//!
//! with two changes that statics needs (measured on the pendulum of `tests/statics.rs`):
//!
//! - after every correction q is **projected** back onto Φ = 0 by the Gauss–Newton iteration of
//!   the consistent initial positions (docs/methods.md §5.4 item 1, held coordinates fixed). In a
//!   time step the correction is O(h²) and the penalty's curvature term is harmless; in statics
//!   a pendulum 57° off the vertical gets a correction of 2 m along the tangent of its 1.5 m rod,
//!   and without the projection the penalty term α Φ Φ_q of that trial point raised ‖g‖ by 10⁵,
//!   so the line search could not accept any step above 1/1000;
//! - with Φ = 0 the update λ ← λ + αΦ does nothing, so λ is the **least-squares multiplier**
//!   argmin ‖−Q + Φ_qᵀλ‖ at each projected point (regularised for redundancy). It is exact at the
//!   solution and first-order accurate near it, so the iteration keeps Newton's quadratic rate;
//!   it is also what puts the constraint curvature into H (with λ = 0 a pendulum's H is singular).
//!
//! Why not a bordered Newton on [H Φ_qᵀ; Φ_q 0]: the scenes have redundant constraints (the
//! rigid four-bars, docs/methods.md §5.3 "Redundant constraints"), which make the bordered matrix
//! singular; with the penalty the n × n matrix H stays regular whenever H is positive definite
//! on the motions the constraints allow, redundancy or not, as ALI3-P's leading matrix does.
//! The step is then, for large α, the null-space Newton step.
//!
//! **Tangent.** The formulations' K is the approximation ALI3-P needs ("f_q ≈", methods.md
//! §5.1): it omits the constraint curvature Σ(λ + αΦ)∇²Φ (docs/design.md "The integrator")
//! and some configuration dependence of the forces. In a time step M dominates and that only
//! costs iterations; in statics K is the whole tangent, and a pendulum has K = 0, so
//! K + Φ_qᵀαΦ_q is singular there. By default H is therefore formed by forward differences
//! of −Q(q) + Φ_q(q)ᵀ μ with μ = λ + αΦ held (one evaluation per coordinate, step
//! 1e-7 max(1, |q_j|)), plus the exact Φ_qᵀαΦ_q; [`StaticSettings::fd_tangent`] = false uses
//! K + Φ_qᵀαΦ_q instead. H is factorised by LU (the difference tangent is not symmetric).
//!
//! **Globalisation.** A full step is taken when it lowers ‖g‖₂ over projected trial points;
//! if it raises ‖g‖₂, a watchdog (non-monotone acceptance, Chamberlain et al. 1982) takes it
//! anyway and gives the following full steps 5 iterations to fall below the level it started
//! from, else returns there; only then does it backtrack, s = ½, ¼, … down to 1/1024, until
//! ‖g(P(q + sΔq))‖₂ ≤ (1 − 10⁻⁴ s)‖g(q)‖₂. Why the watchdog: in FNL2 (full axial basis) the
//! stiff axial coordinates act like a penalty on u′ + ½w′² = 0, so the first Newton step from the
//! straight beam (the linear droop) stretches it and raises ‖g‖ 10⁴-fold, and the second step
//! lands on the solution. With a monotone line search the accepted steps were ≤ 1/500 of Newton's
//! and the 3D spin-up beam needed 5380 iterations and 128 load steps; with the watchdog, 4.
//! If the full problem still does not converge, it is restarted from the initial guess with
//! load stepping done generically by the Newton homotopy
//!
//! g_μ(q; λ) = g(q; λ) + (1 − μ) Q(q₀),
//!
//! which q₀ solves at μ = 0; when the elastic forces vanish at the undeformed q₀ this is
//! exactly scaling the applied loads by μ. μ rises to 1 in increments starting at
//! 1/`load_steps`, halved after a failed level and doubled again after an easy one.
//!
//! **Penalty.** α = 10⁴ k_ref (CHOSEN, as ALI3-P's effective penalty h²α/4 = 10⁴ m_ref of
//! docs/methods.md §5.3 with the stiffness scale in place of the mass scale), k_ref the largest
//! diagonal entry of H without the penalty at the first iterate (or of M, per s², when that
//! is zero). With the projection α only has to make H regular across the constraints.
//!
//! **Neutral directions.** When the plain attempt fails it is repeated with the tangent
//! H + ρ M(q₀), and a converged point is freed of its drift along the motions no force resists,
//! or refused where the coordinates are singular: the `neutral` module says why and how.
//!
//! **Stop.** ‖g‖∞ ≤ ε_r f_ref on the free coordinates (f_ref the largest |Q_j| met), ‖Φ‖∞ ≤ ε_Φ
//! and the last correction ‖Δq‖∞ ≤ ε_q max(1, ‖q‖∞). Also stopped, as converged, when a
//! full Newton correction is below 10⁻³ ε_q max(1, ‖q‖∞), ‖Φ‖∞ ≤ ε_Φ and ‖g‖∞ no longer
//! falls (not below half its previous value; the multipliers may still be settling while q
//! is): neither q nor g can get better. That happens when a scene starts exactly at its equilibrium in minimal
//! coordinates: the net generalised force, and with it f_ref, is round-off (a bar held level
//! by a spring: |Q| = 5e-13 N·m), so ‖g‖∞ ≤ ε_r f_ref cannot hold. On failure an error carries the
//! iteration count, the residual, the constraint error and the load factor reached — never
//! a panic, never NaN. The solver runs once per scene and allocates its workspace up front.
//!
//! **Code.** `solve_static` tries the full load, then `load_stepping`; each load level is
//! `level`, whose iteration is the tangent (`tangent`; α from the first one, `set_penalty`),
//! the Newton correction (`newton_correction`) and the watchdog line search (`line_search`),
//! each trial point being projected onto Φ = 0 (`project`) with its least-squares multipliers
//! (`estimate_multipliers`) and residual (`residual`) — `trial`.

use flexmbd_core::{Formulation, Request, State, SystemTerms};
use nalgebra::{DMatrix, DVector};

use crate::lu::DenseLu;

mod error;
mod load_stepping;
mod neutral;
mod settings;

pub use error::StaticError;

use load_stepping::Stall;
pub use settings::StaticSettings;

/// A static equilibrium.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticSolution {
    /// Positions q.
    pub q: DVector<f64>,
    /// Multipliers λ (the constraint reaction on the system is −Φ_qᵀλ).
    pub lambda: DVector<f64>,
    /// How the solve went.
    pub counters: StaticCounters,
    /// The penalty α used.
    pub penalty: f64,
}

/// How a static solve went: iterations, load levels, evaluations and the final residuals.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct StaticCounters {
    /// Newton iterations, all load levels (failed attempts included).
    pub iterations: usize,
    /// Load levels solved (1 when the full load converged directly).
    pub load_steps: usize,
    /// Formulation evaluations.
    pub evaluations: usize,
    /// Final ‖g‖∞ on the free coordinates (force units of the coordinates).
    pub residual: f64,
    /// Final ‖Φ‖∞.
    pub phi: f64,
}

/// ρ of the regularised attempt, relative to k_ref / m_ref (module documentation, "Neutral
/// directions").
const REGULARISATION: f64 = 1e-6;

/// Passes of taking back the neutral drift (each a linearisation and a Newton polish).
const NEUTRAL_PASSES: usize = 4;

/// Full Newton steps the watchdog allows before ‖g‖ must fall below its starting level.
const WATCHDOG: usize = 5;

/// A full Newton correction below this fraction of ε_q max(1, ‖q‖∞) ends the iteration as
/// converged (module documentation, "Stop").
const NEGLIGIBLE_CORRECTION: f64 = 1e-3;

const HINT: &str = "check that the loads have an equilibrium the constraints and stiffness can carry (a mechanism or a buckled, snapping structure has none nearby); more load steps or a looser tolerance may help";

/// Workspace and state of one solve.
struct Solver<'s> {
    s: &'s StaticSettings,
    t: f64,
    n: usize,
    held: Vec<bool>,
    terms: SystemTerms,
    zero_qd: DVector<f64>,
    alpha: f64,
    /// Regularisation ρ of the second attempt (0 in the first): H + ρ M₀.
    regularisation: f64,
    /// M(q₀), the metric of the regularisation.
    mass0: DMatrix<f64>,
    /// Q(q₀), for the homotopy.
    q0_forces: DVector<f64>,
    f_ref: f64,
    evaluations: usize,
    /// Gauss–Newton iterations of the projections so far.
    projection_iterations: usize,
    iterations: usize,
    // Workspace.
    g: DVector<f64>,
    g_try: DVector<f64>,
    base: DVector<f64>,
    mu: DVector<f64>,
    phi_q_base: DMatrix<f64>,
    h: DMatrix<f64>,
    dq: DVector<f64>,
    q_try: DVector<f64>,
    lambda_try: DVector<f64>,
    q_ref: DVector<f64>,
    lambda_ref: DVector<f64>,
    lu: DenseLu,
    /// Φ_q Φ_qᵀ and its factorisation (multiplier estimate).
    mm: DMatrix<f64>,
    lu_m: DenseLu,
    /// Last ‖g‖∞ and ‖Φ‖∞ (for errors).
    last_residual: f64,
    last_phi: f64,
}

const REQ_FULL: Request = Request {
    dynamics: true,
    tangents: false,
    constraints: true,
    jacobian: true,
    accel_term: false,
};

enum Level {
    Converged,
    Failed,
    /// Within reach of the tolerance but no longer improving: a floor (rounding along a
    /// neutral motion, the penalty times rounding) that more iterations or load steps do not
    /// lower; the regularised attempt is the cure (`neutral`).
    Stalled,
}

/// State of the watchdog of one load level (module documentation, "Globalisation").
#[derive(Default)]
struct Watchdog {
    /// (‖g‖₂ where it started, full steps left).
    active: Option<(f64, usize)>,
    /// Skip it once after it failed.
    off: bool,
}

impl Solver<'_> {
    fn eval<F: Formulation + ?Sized>(&mut self, f: &mut F, q: &DVector<f64>, req: Request) {
        self.terms.clear(req);
        f.evaluate(State::new(self.t, q, &self.zero_qd), req, &mut self.terms);
        self.evaluations += 1;
    }

    /// g = −Q + (1 − load) Q₀ + Φ_qᵀ(λ + αΦ) from the current terms, held entries zeroed,
    /// into `out`; μ = λ + αΦ into `self.mu`.
    fn residual(&mut self, lambda: &DVector<f64>, load: f64, into_try: bool) {
        let tt = &self.terms;
        self.mu.copy_from(lambda);
        // The regularised attempt leaves out αΦ: on the projected points Φ is rounding, and
        // α times rounding (≈ 10⁻⁶ N at α = 5·10⁹) would floor ‖g‖ above its tolerance.
        if self.mass0.is_empty() {
            self.mu.axpy(self.alpha, &tt.phi, 1.0);
        }
        let out = if into_try {
            &mut self.g_try
        } else {
            &mut self.g
        };
        out.copy_from(&tt.forces);
        out.axpy(1.0 - load, &self.q0_forces, -1.0);
        out.gemv_tr(1.0, &tt.phi_q, &self.mu, 1.0);
        for (v, &h) in out.iter_mut().zip(&self.held) {
            if h {
                *v = 0.0;
            }
        }
        self.f_ref = self.f_ref.max(tt.forces.amax());
    }

    /// λ = argmin ‖−Q + (1 − load) Q₀ + Φ_qᵀλ‖ over the free coordinates, regularised for
    /// redundant constraints: (Φ_q Φ_qᵀ + εI) λ = Φ_q (Q − (1 − load) Q₀).
    fn estimate_multipliers(&mut self, lambda: &mut DVector<f64>, load: f64) {
        let m = lambda.len();
        if m == 0 {
            return;
        }
        let tt = &self.terms;
        self.phi_q_base.copy_from(&tt.phi_q);
        for (j, &h) in self.held.iter().enumerate() {
            if h {
                self.phi_q_base.column_mut(j).fill(0.0);
            }
        }
        self.g_try.copy_from(&tt.forces);
        self.g_try.axpy(-(1.0 - load), &self.q0_forces, 1.0);
        // Φ_q Φ_qᵀ by rows (no temporaries).
        let a = &self.phi_q_base;
        for i in 0..m {
            for j in 0..=i {
                let v = a.row(i).dot(&a.row(j));
                self.mm[(i, j)] = v;
                self.mm[(j, i)] = v;
            }
        }
        // The regularised attempt meets ‖g‖ ≤ ε_r f_ref on the multipliers alone (module
        // documentation, "Neutral directions"): a smaller ε, whose bias is below that.
        let relative_eps = if self.mass0.is_empty() { 1e-10 } else { 1e-14 };
        let eps = relative_eps
            * (0..m)
                .map(|i| self.mm[(i, i)])
                .fold(0.0, f64::max)
                .max(1e-300);
        for i in 0..m {
            self.mm[(i, i)] += eps;
        }
        lambda.gemv(1.0, &self.phi_q_base, &self.g_try, 0.0);
        if self.lu_m.factor(&self.mm).is_ok() {
            self.lu_m.solve_in_place(lambda);
        }
        if !lambda.iter().all(|v| v.is_finite()) {
            lambda.fill(0.0);
        }
    }

    /// Project q onto Φ(q, t) = 0 with the held coordinates fixed: Gauss–Newton on the
    /// regularised normal equations (εI + JᵀJ) Δq = −JᵀΦ (tolerates redundancy, as the
    /// consistent initial positions of docs/methods.md §5.4 item 1). Uses `h`, `lu`, `base` as
    /// scratch. False when it does not reach ‖Φ‖∞ ≤ ε_Φ.
    fn project<F: Formulation + ?Sized>(&mut self, f: &mut F, q: &mut DVector<f64>) -> bool {
        if self.terms.phi.is_empty() {
            return true;
        }
        let tight = 1e-3 * self.s.tol_phi;
        let req = Request {
            constraints: true,
            jacobian: true,
            ..Request::default()
        };
        let mut phi = f64::INFINITY;
        for _ in 0..50 {
            if self.projection_iterations >= self.s.max_projection_iterations {
                return false;
            }
            self.projection_iterations += 1;
            self.eval(f, q, req);
            phi = self.terms.phi.amax();
            if !phi.is_finite() {
                return false;
            }
            if phi <= tight {
                return true;
            }
            self.phi_q_base.copy_from(&self.terms.phi_q);
            for (j, &h) in self.held.iter().enumerate() {
                if h {
                    self.phi_q_base.column_mut(j).fill(0.0);
                }
            }
            let j = &self.phi_q_base;
            self.h.gemm_tr(1.0, j, j, 0.0);
            let eps = 1e-12 * (0..self.n).map(|i| self.h[(i, i)]).fold(0.0, f64::max);
            for i in 0..self.n {
                self.h[(i, i)] += eps.max(f64::MIN_POSITIVE);
            }
            self.base.gemv_tr(-1.0, j, &self.terms.phi, 0.0);
            if self.lu.factor(&self.h).is_err() {
                return false;
            }
            self.lu.solve_in_place(&mut self.base);
            *q += &self.base;
        }
        phi <= self.s.tol_phi
    }

    /// Newton at load factor `load` from q: projected onto Φ = 0 after every correction,
    /// multipliers by least squares, watchdog and backtracking on ‖g‖₂ (module documentation).
    fn level<F: Formulation + ?Sized>(
        &mut self,
        f: &mut F,
        q: &mut DVector<f64>,
        lambda: &mut DVector<f64>,
        load: f64,
    ) -> Result<Level, StaticError> {
        if !self.project(f, q) {
            return Ok(Level::Failed);
        }
        let (mut last_dq, mut last_full_dq) = (f64::INFINITY, f64::INFINITY);
        let mut last_res = f64::INFINITY;
        let mut watchdog = Watchdog::default();
        let req = Request {
            tangents: !self.s.fd_tangent,
            ..REQ_FULL
        };
        self.restart_at(f, q, lambda, load, req);
        let mut stall = Stall::default();
        for _ in 0..self.s.max_iterations {
            if self.iterations >= self.s.max_total_iterations {
                return Ok(Level::Failed);
            }
            let phi = self.terms.phi.amax();
            let res = self.g.amax();
            self.last_residual = res;
            self.last_phi = phi;
            if !(res.is_finite() && phi.is_finite()) {
                return Ok(Level::Failed);
            }
            if stall.stuck(res, self.f_ref) {
                return Ok(Level::Stalled);
            }
            let q_scale = q.amax().max(1.0);
            if res <= self.s.tol_residual * self.f_ref
                && phi <= self.s.tol_phi
                && (last_dq <= self.s.tol_q * q_scale || self.regularisation > 0.0)
            {
                return Ok(Level::Converged);
            }
            if phi <= self.s.tol_phi
                && last_full_dq <= NEGLIGIBLE_CORRECTION * self.s.tol_q * q_scale
                && res >= 0.5 * last_res
            {
                return Ok(Level::Converged);
            }
            last_res = res;
            self.iterations += 1;
            self.tangent(f, q, load);
            if self.alpha == 0.0 {
                self.set_penalty();
            }
            if let Some(failed) = self.newton_correction()? {
                return Ok(failed);
            }
            let Some(step) = self.line_search(f, q, lambda, load, req, &mut watchdog) else {
                if watchdog.active.is_some() {
                    // The watchdog ran out: back to where it started, with a damped step.
                    watchdog.active = None;
                    watchdog.off = true;
                    q.copy_from(&self.q_ref);
                    lambda.copy_from(&self.lambda_ref);
                    self.restart_at(f, q, lambda, load, req);
                    (last_dq, last_full_dq) = (f64::INFINITY, f64::INFINITY);
                    continue;
                }
                return Ok(Level::Failed);
            };
            watchdog.off = false;
            if let Some((g_ref, _)) = watchdog.active
                && self.g_try.norm() <= (1.0 - 1e-4) * g_ref
            {
                watchdog.active = None;
            }
            q.copy_from(&self.q_try);
            lambda.copy_from(&self.lambda_try);
            std::mem::swap(&mut self.g, &mut self.g_try);
            last_dq = step * self.dq.amax();
            last_full_dq = if step == 1.0 { last_dq } else { f64::INFINITY };
        }
        Ok(Level::Failed)
    }

    /// Terms, least-squares multipliers and residual g at q (already on Φ = 0).
    fn restart_at<F: Formulation + ?Sized>(
        &mut self,
        f: &mut F,
        q: &DVector<f64>,
        lambda: &mut DVector<f64>,
        load: f64,
        req: Request,
    ) {
        self.eval(f, q, req);
        self.estimate_multipliers(lambda, load);
        self.residual(lambda, load, false);
    }

    /// Tangent H of −Q + Φ_qᵀμ at q, μ = λ + αΦ held, into `h` (Φ_qᵀαΦ_q is added by
    /// [`Self::newton_correction`], exactly): forward differences, one evaluation per free
    /// coordinate, or the formulation's K (module documentation, "Tangent").
    fn tangent<F: Formulation + ?Sized>(&mut self, f: &mut F, q: &mut DVector<f64>, load: f64) {
        if !self.s.fd_tangent {
            self.h.copy_from(&self.terms.stiffness);
            return;
        }
        self.base.copy_from(&self.g);
        // Keep Φ_q of the base point for the penalty term: the columns overwrite terms.
        self.phi_q_base.copy_from(&self.terms.phi_q);
        for j in 0..self.n {
            if self.held[j] {
                continue;
            }
            let d = 1e-7 * q[j].abs().max(1.0);
            let qj = q[j];
            q[j] = qj + d;
            self.eval(
                f,
                q,
                Request {
                    constraints: false,
                    ..REQ_FULL
                },
            );
            q[j] = qj;
            let tt = &self.terms;
            // Column: (−Q(q + d e_j) + Φ_q(q + d e_j)ᵀ μ − (−Q + Φ_qᵀμ)) / d; the
            // homotopy term is constant and cancels.
            let mut col = self.h.column_mut(j);
            col.copy_from(&tt.forces);
            col.gemv_tr(1.0, &tt.phi_q, &self.mu, -1.0);
            col.axpy(1.0 - load, &self.q0_forces, 1.0);
            for (i, v) in col.iter_mut().enumerate() {
                *v = if self.held[i] {
                    0.0
                } else {
                    (*v - self.base[i]) / d
                };
            }
        }
        self.terms.phi_q.copy_from(&self.phi_q_base);
    }

    /// First tangent: α = 10⁴ k_ref unless given (module documentation, "Penalty").
    fn set_penalty(&mut self) {
        let n = self.n;
        let k_ref = (0..n)
            .filter(|&i| !self.held[i])
            .map(|i| self.h[(i, i)].abs())
            .fold(0.0, f64::max);
        let m_ref = (0..n)
            .map(|i| self.terms.mass[(i, i)].abs())
            .fold(0.0, f64::max);
        let k_ref = if k_ref > 0.0 { k_ref } else { m_ref.max(1.0) };
        self.alpha = self.s.penalty.unwrap_or(1e4 * k_ref);
        if self.mass0.nrows() == n {
            self.regularisation = REGULARISATION * k_ref / m_ref.max(f64::MIN_POSITIVE);
        }
    }

    /// The Newton correction: H += Φ_qᵀαΦ_q, held rows and columns replaced by the identity,
    /// H Δq = −g into `dq`. `Some(Level::Failed)` when H is singular or Δq not finite after
    /// the first iteration; singular at the first one is an error (a free motion).
    fn newton_correction(&mut self) -> Result<Option<Level>, StaticError> {
        let a = self.alpha;
        let phi_q = &self.terms.phi_q;
        self.h.gemm_tr(a, phi_q, phi_q, 1.0);
        if self.regularisation > 0.0 {
            let rho = self.regularisation;
            for (h, m) in self.h.iter_mut().zip(self.mass0.iter()) {
                *h += rho * m;
            }
        }
        for j in 0..self.n {
            if self.held[j] {
                self.h.row_mut(j).fill(0.0);
                self.h.column_mut(j).fill(0.0);
                self.h[(j, j)] = 1.0;
            }
        }
        if let Err(e) = self.lu.factor(&self.h) {
            // Singular at the initial guess: the scene has a free motion. Later, the
            // iteration wandered off (past a limit point, say): let load stepping try.
            if self.iterations == 1 {
                return Err(StaticError::Singular {
                    iterations: self.iterations,
                    pivot_ratio: e.pivot_ratio,
                });
            }
            return Ok(Some(Level::Failed));
        }
        self.dq.copy_from(&self.g);
        self.dq.neg_mut();
        self.lu.solve_in_place(&mut self.dq);
        if !self.dq.iter().all(|v| v.is_finite()) {
            return Ok(Some(Level::Failed));
        }
        Ok(None)
    }

    /// Step length s along `dq` from (q, λ): the full step first; if it raises ‖g‖₂, the
    /// watchdog may still take it, else backtracking s = ½, ¼, … ≥ 1/1024 on ‖g‖₂ over
    /// projected trial points (module documentation, "Globalisation"). The accepted point is
    /// left in `q_try`, `lambda_try`, `g_try`; `None` when no step is accepted.
    fn line_search<F: Formulation + ?Sized>(
        &mut self,
        f: &mut F,
        q: &DVector<f64>,
        lambda: &DVector<f64>,
        load: f64,
        req: Request,
        watchdog: &mut Watchdog,
    ) -> Option<f64> {
        let g0 = self.g.norm();
        let mut step = 1.0;
        while step >= 1.0 / 1024.0 {
            if let Some(g1) = self.trial(f, q, step, load, req) {
                if g1.is_finite() && g1 <= (1.0 - 1e-4 * step) * g0 {
                    return Some(step);
                }
                // At round-off the residual cannot fall further: accept a full step that
                // does not raise it much, so the test on Δq can finish.
                if step == 1.0 && g0 <= 1e3 * self.s.tol_residual * self.f_ref && g1 <= 2.0 * g0 {
                    return Some(step);
                }
                // Watchdog: take a full step that raises ‖g‖ and give the following full
                // steps WATCHDOG iterations to fall below the level it started from.
                if step == 1.0 && g1.is_finite() {
                    if watchdog.active.is_none() && !watchdog.off {
                        self.q_ref.copy_from(q);
                        self.lambda_ref.copy_from(lambda);
                        watchdog.active = Some((g0, WATCHDOG));
                        return Some(step);
                    }
                    if let Some((g_ref, left)) = watchdog.active
                        && left > 1
                    {
                        watchdog.active = Some((g_ref, left - 1));
                        return Some(step);
                    }
                }
            }
            if let Some((_, 1)) = watchdog.active {
                // The watchdog ran out: the caller goes back to where it started.
                return None;
            }
            step *= 0.5;
        }
        None
    }

    /// Trial point P(q + s Δq) into `q_try`, with its least-squares multipliers in
    /// `lambda_try` and residual in `g_try`; ‖g_try‖₂, or `None` when the projection fails.
    fn trial<F: Formulation + ?Sized>(
        &mut self,
        f: &mut F,
        q: &DVector<f64>,
        step: f64,
        load: f64,
        req: Request,
    ) -> Option<f64> {
        let mut q_try = std::mem::take(&mut self.q_try);
        q_try.copy_from(q);
        q_try.axpy(step, &self.dq, 1.0);
        let projected = self.project(f, &mut q_try);
        if projected {
            self.eval(f, &q_try, req);
        }
        self.q_try = q_try;
        if !projected {
            return None;
        }
        let mut l_try = std::mem::take(&mut self.lambda_try);
        self.estimate_multipliers(&mut l_try, load);
        self.residual(&l_try, load, true);
        self.lambda_try = l_try;
        Some(self.g_try.norm())
    }
}

/// Static equilibrium of `f` at time `t` with q̇ = 0, from `f.initial_guess` (module
/// documentation). The specified coordinates are held at their initial values.
pub fn solve_static<F: Formulation + ?Sized>(
    f: &mut F,
    t: f64,
    settings: &StaticSettings,
) -> Result<StaticSolution, StaticError> {
    let first = attempt(f, t, settings, false);
    match first {
        Err(
            StaticError::Singular { .. }
            | StaticError::NoConvergence { .. }
            | StaticError::CoordinateSingularity { .. }
            | StaticError::NearlySingular { .. },
        ) => {
            // A neutral direction (module documentation, "Neutral directions"): again with
            // the regularised tangent; when that fails too, the first diagnosis stands.
            attempt(f, t, settings, true).or(first)
        }
        _ => first,
    }
}

/// One solve from the initial guess: the full load, then load stepping; with `regularise`
/// the tangent gets ρ M(q₀) (module documentation, "Neutral directions").
fn attempt<F: Formulation + ?Sized>(
    f: &mut F,
    t: f64,
    settings: &StaticSettings,
    regularise: bool,
) -> Result<StaticSolution, StaticError> {
    let (n, m) = (f.n_coordinates(), f.n_constraints());
    let mut q0 = DVector::zeros(n);
    let mut qd = DVector::zeros(n);
    f.initial_guess(&mut q0, &mut qd);
    let mut s = Solver::new(f, t, settings);
    // Q(q₀) for the homotopy, and a finiteness check of the scene at the guess.
    s.eval(f, &q0, REQ_FULL);
    s.q0_forces.copy_from(&s.terms.forces);
    if regularise {
        s.mass0 = s.terms.mass.clone();
    }
    let r0 = s.terms.forces.amax().max(s.terms.phi.amax());
    if !r0.is_finite() {
        return Err(StaticError::NonFinite { residual: r0 });
    }
    let mut q = q0.clone();
    let mut lambda = DVector::zeros(m);
    let mut load_steps = 1;
    // Full load first.
    let full = s.level(f, &mut q, &mut lambda, 1.0)?;
    let mut converged = matches!(full, Level::Converged);
    let mut load = 0.0;
    if matches!(full, Level::Stalled) {
        load = 1.0;
    } else if !converged {
        // Load stepping by the Newton homotopy, from the initial guess.
        q.copy_from(&q0);
        lambda.fill(0.0);
        (converged, load, load_steps) = s.load_stepping(f, &mut q, &mut lambda)?;
    }
    if !converged {
        return Err(StaticError::NoConvergence {
            iterations: s.iterations,
            residual: s.last_residual,
            force_scale: s.f_ref,
            phi: s.last_phi,
            load_factor: load,
            hint: HINT,
        });
    }
    s.take_back_neutral_drift(f, &q0, &mut q, &mut lambda)?;
    s.check_coordinates(f, &q, &lambda)?;
    Ok(StaticSolution {
        q,
        lambda,
        counters: StaticCounters {
            iterations: s.iterations,
            load_steps,
            evaluations: s.evaluations,
            residual: s.last_residual,
            phi: s.last_phi,
        },
        penalty: s.alpha,
    })
}

impl<'s> Solver<'s> {
    /// The workspace of a solve of `f` at time `t`, α not yet chosen.
    fn new<F: Formulation + ?Sized>(f: &F, t: f64, settings: &'s StaticSettings) -> Self {
        let (n, m) = (f.n_coordinates(), f.n_constraints());
        let mut held = vec![false; n];
        for &j in f.specified_coordinates() {
            if j < n {
                held[j] = true;
            }
        }
        Solver {
            s: settings,
            t,
            n,
            held,
            terms: SystemTerms::new(n, m),
            zero_qd: DVector::zeros(n),
            alpha: 0.0,
            regularisation: 0.0,
            mass0: DMatrix::zeros(0, 0),
            q0_forces: DVector::zeros(n),
            f_ref: f64::MIN_POSITIVE,
            evaluations: 0,
            iterations: 0,
            projection_iterations: 0,
            g: DVector::zeros(n),
            g_try: DVector::zeros(n),
            base: DVector::zeros(n),
            mu: DVector::zeros(m),
            phi_q_base: DMatrix::zeros(m, n),
            h: DMatrix::zeros(n, n),
            dq: DVector::zeros(n),
            q_try: DVector::zeros(n),
            lambda_try: DVector::zeros(m),
            q_ref: DVector::zeros(n),
            lambda_ref: DVector::zeros(m),
            lu: DenseLu::new(n),
            mm: DMatrix::zeros(m, m),
            lu_m: DenseLu::new(m),
            last_residual: f64::INFINITY,
            last_phi: f64::INFINITY,
        }
    }
}
