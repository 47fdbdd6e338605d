//! ALI3-P: the index-3 augmented Lagrangian formulation with mass-orthogonal
//! projections of velocities and accelerations, on the trapezoidal rule
//! (thesis ch. 2; methods.md §5; Bayo & Ledesma 1996, Cuadrado et al. 2001).
//!
//! Equations of motion with a scalar penalty α and multipliers λ*:
//!
//! M q̈ + Φ_qᵀ α Φ + Φ_qᵀ λ* = Q,  λ*_{i+1} = λ*_i + α Φ_{i+1}.
//!
//! Trapezoidal rule with q_{n+1} the unknown: q̇ = (2/h) q + q̂̇, q̈ = (4/h²) q + q̂̈.
//! Residual and tangent (scaled by h²/4):
//!
//! f = h²/4 (M q̈ + Φ_qᵀ(αΦ + λ*) − Q),  f_q ≈ M + h/2 C + h²/4 (Φ_qᵀ α Φ_q + K).
//!
//! After Newton converges, velocities and accelerations are projected onto the
//! constraint manifold with f_q = W + h²/4 Φ_qᵀ α Φ_q (W = M + h/2 C + h²/4 K):
//!
//! f_q q̇ = W q̇* − h²/4 Φ_qᵀ α Φ_t,  f_q q̈ = W q̈* − h²/4 Φ_qᵀ α c,
//!
//! solved for the increments q̇ − q̇*, q̈ − q̈* (same equations; the round-off of the
//! ill-conditioned f_q then falls on the increments, see `project_increment`).
//!
//! Φ_q is that of the converged q (written by the Φ pass after the last update), W that of
//! the last Newton iteration (see `project`). Per step: one formulation pass for M, Q (K,
//! C) and Φ_q at the predictor, one Φ, Φ_q pass after each update (each further iteration
//! adds an M, Q pass), one pass for c; one factorisation per iteration and one for the
//! projections, unless the last correction was far below the tolerance (Newton's factor
//! then serves them: `newton_factor_serves`); without constraints (m = 0) neither the Φ
//! passes nor the projections, which would change nothing. The predictor is per coordinate the
//! trapezoidal rule with q̈_{n+1} = q̈_n or with q̈_{n+1} = 2q̈_n − q̈_{n−1}, whichever has
//! recently been nearer the solution; a formulation may ask for a third
//! (`Formulation::predictor_repeats_miss`): the first plus the last step's miss, q_n − its
//! prediction. The miss is h²/4 (q̈*_n − q̈_{n−1}) with q̈* the trapezoidal rule's
//! acceleration before the projection, so where the projections move q̈ by a steady offset
//! this predicts it, and elsewhere it is the extrapolation again.
//!
//! Deviations from the literal text, both from methods.md's checked corrections:
//! the penalty scales with h² (α = 4·10⁴ m_ref / h², §5.3), and a step that reaches the
//! iteration limit with ‖Φ‖∞ ≤ `accept_phi` and a last correction ‖Δq‖∞ ≤ `accept_phi` ·
//! max(‖q‖∞, 1) is accepted and counted (singular configurations, §5.2); any step whose q,
//! q̇, q̈ or λ* is not finite fails. Ours: at a singular configuration the multiplier update converges
//! only linearly in the rank-deficient direction of Φ_q (rate ≈ 1/(1 + α σ² h²/4m) for its
//! small singular value σ; an exact tangent by differences, tried, did not change the rate),
//! so after two slow corrections (θ ≥ 0.5 from the third iteration) α is raised ×10 for the
//! rest of the step, at most twice; the converged q, λ do not depend on α. Double four-bar,
//! h = 1 ms: the steps accepted at the limit go from 1 / 4 (rigid / 2 flexible bars,
//! absolute) to 0, every step then meets the tolerance.

use std::time::Instant;

use flexmbd_core::{Formulation, Request, State, SystemTerms};
use nalgebra::{DMatrix, DVector};

use crate::contraction::Contraction;
use crate::declared_entries::DeclaredEntries;
use crate::declared_llt::DeclaredLlt;
pub use crate::error::IntegratorError;
use crate::jacobian_pattern::JacobianPattern;
use crate::lu::{DenseLlt, DenseLu};
pub use crate::settings::{Ali3pSettings, Stats};
use crate::structured::StructuredLlt;

mod leading;
mod predictor;

/// The state of an [`Ali3p`] integrator between steps (see [`Ali3p::checkpoint`]);
/// serialisable (an FMU's saved state), every number kept exactly by a format that
/// round-trips `f64`.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Checkpoint {
    t: f64,
    q: DVector<f64>,
    qd: DVector<f64>,
    qdd: DVector<f64>,
    lambda: DVector<f64>,
    stats: Stats,
    qdd_prev: DVector<f64>,
    have_qdd_prev: bool,
    extrapolate: Vec<bool>,
    pred_err: Vec<(f64, f64)>,
    /// Newton's contraction of the steps before (`crate::contraction`).
    #[serde(default)]
    contraction: Contraction,
    /// The third predictor's state (`Formulation::predictor_repeats_miss`); empty in a
    /// checkpoint written before it existed, which restores as no miss recorded.
    #[serde(default)]
    miss: Vec<f64>,
    #[serde(default)]
    miss_err: Vec<f64>,
    #[serde(default)]
    repeat_miss: Vec<bool>,
}

impl Checkpoint {
    /// The time of the saved state (s).
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The sizes of the integrator it was taken from: coordinates n and constraints m
    /// ([`Ali3p::restore`] accepts it only into one of these sizes).
    pub fn size(&self) -> (usize, usize) {
        (self.q.len(), self.lambda.len())
    }
}

/// The kernel of the last factorisation of the leading matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Factored {
    Llt,
    Structured,
    Declared,
    Lu,
}

/// The ALI3-P integrator with its state and workspace, sized once for one formulation.
pub struct Ali3p {
    settings: Ali3pSettings,
    alpha: f64,
    /// Current time.
    pub t: f64,
    t0: f64,
    /// Positions q.
    pub q: DVector<f64>,
    /// Velocities q̇.
    pub qd: DVector<f64>,
    /// Accelerations q̈.
    pub qdd: DVector<f64>,
    /// Multipliers λ*.
    pub lambda: DVector<f64>,
    /// Counters.
    pub stats: Stats,
    terms: SystemTerms,
    lead: DMatrix<f64>,
    w: DMatrix<f64>,
    lu: DenseLu,
    llt: DenseLlt,
    /// f_q is symmetric (the formulation says so); then Cholesky, with LU as the fallback.
    symmetric: bool,
    /// Which kernel holds the last factorisation.
    factored: Factored,
    /// The structured Cholesky chosen at the first factorisation (`crate::structured`);
    /// `None` keeps the dense kernels.
    structured: Option<StructuredLlt>,
    structure_decided: bool,
    /// The entries the formulation declared (`crate::declared_entries`): only these of M,
    /// K, C and Φ_q are cleared, and, with `declared_runs`, formed.
    entries: Option<DeclaredEntries>,
    /// f_q over the declared structure factorised sparse (`crate::declared_llt`); `None`
    /// keeps the routes above.
    declared: Option<DeclaredLlt>,
    /// f_q's declared lower triangle as runs of column-major indices of `lead`, when the
    /// declared structure is an arrow (`structured` then holds it): W is formed there only.
    declared_runs: Vec<std::ops::Range<usize>>,
    /// K and C are state-independent: evaluated once, kept.
    constant_tangents: bool,
    /// M, K and C are all constant: W is formed once (`w_ready` after that).
    constant_w: bool,
    w_ready: bool,
    /// Timing weight of the current step: `profile_every` on sampled steps, 0 otherwise.
    time_weight: f64,
    rhs: DVector<f64>,
    /// Φ_q's non-zero pattern, and one row's entries in it (capacity n, reused).
    pattern: JacobianPattern,
    nz: Vec<(usize, f64)>,
    qd_hat: DVector<f64>,
    qdd_hat: DVector<f64>,
    tmp_m: DVector<f64>,
    /// q̈ of the previous step (predictor), once a step was taken.
    qdd_prev: DVector<f64>,
    have_qdd_prev: bool,
    /// The predictor without extrapolation, the extrapolation's increment, and per
    /// coordinate whether to add it.
    pred: DVector<f64>,
    pred_d: DVector<f64>,
    extrapolate: Vec<bool>,
    pred_err: Vec<(f64, f64)>,
    /// The formulation asked for the third predictor (`Formulation::predictor_repeats_miss`):
    /// the plain one plus the last step's miss `miss` (q − the plain prediction), per
    /// coordinate where its error, averaged like the other two's (`miss_err`), is under half
    /// of theirs (`repeat_miss`).
    repeats_miss: bool,
    miss: Vec<f64>,
    miss_err: Vec<f64>,
    repeat_miss: Vec<bool>,
    /// Newton's contraction of the steps before, for the first iterate's test.
    contraction: Contraction,
    /// Passes that rewrote M, Q (K, C): the factor in hand is reused only while none ran.
    dynamics_passes: usize,
    /// What the factor in hand was formed from (`leading::FactorInputs`).
    factored_from: leading::FactorInputs,
}

/// The projections take Newton's last factor as it is when q moved by at most this share of
/// the Newton tolerance ε_q max(‖q‖∞, 1) since it was formed (`Ali3p::newton_factor_serves`).
/// Measured against refactorising at the converged q: at 10⁻³ the 34 reference runs move by
/// at most 6.5e-10 of a sensor's range (energies 1.4e-11 J, a thousandth of what the Newton
/// tolerance itself moves them); at 10⁻² the rigid 3D double pendulum (absolute) moved by
/// 6.4e-9 of its hinge angle's range, ten times the difference between tolerances 10⁻⁹ and
/// 10⁻¹³.
const PROJECTION_REUSE: f64 = 1e-3;

impl Ali3p {
    /// Build the integrator for `f` and make its initial conditions consistent (methods.md §5.4).
    pub fn new<F: Formulation + ?Sized>(
        f: &mut F,
        t0: f64,
        settings: Ali3pSettings,
    ) -> Result<Self, IntegratorError> {
        let (n, m) = (f.n_coordinates(), f.n_constraints());
        let constant_w = f.constant_tangents() && f.constant_mass();
        let mut s = Ali3p {
            alpha: 0.0,
            t: t0,
            t0,
            q: DVector::zeros(n),
            qd: DVector::zeros(n),
            qdd: DVector::zeros(n),
            lambda: DVector::zeros(m),
            stats: Stats::default(),
            terms: SystemTerms::new(n, m),
            lead: DMatrix::zeros(n, n),
            // Kept only when M, K and C are constant (`form_w`).
            w: if constant_w {
                DMatrix::zeros(n, n)
            } else {
                DMatrix::zeros(0, 0)
            },
            lu: DenseLu::new(n),
            llt: DenseLlt::new(n),
            symmetric: f.symmetric_tangent(),
            factored: Factored::Lu,
            structured: None,
            structure_decided: false,
            entries: None,
            declared: None,
            declared_runs: Vec::new(),
            constant_tangents: f.constant_tangents(),
            constant_w,
            w_ready: false,
            time_weight: 1.0,
            rhs: DVector::zeros(n),
            pattern: JacobianPattern::new(m, n),
            nz: Vec::with_capacity(n),
            qd_hat: DVector::zeros(n),
            qdd_hat: DVector::zeros(n),
            tmp_m: DVector::zeros(m),
            qdd_prev: DVector::zeros(n),
            have_qdd_prev: false,
            pred: DVector::zeros(n),
            pred_d: DVector::zeros(n),
            extrapolate: vec![false; n],
            pred_err: vec![(0.0, 0.0); n],
            repeats_miss: f.predictor_repeats_miss(),
            miss: vec![0.0; n],
            miss_err: vec![0.0; n],
            repeat_miss: vec![false; n],
            contraction: Contraction::default(),
            dynamics_passes: 0,
            factored_from: leading::FactorInputs::new(m, n, f.constant_tangents()),
            settings,
        };
        if s.symmetric && s.settings.structured_factorisation {
            s.take_declared_structure(f);
        }
        f.initial_guess(&mut s.q, &mut s.qd);
        s.eval(f, Request::ALL);
        let h = s.settings.step;
        let m_ref = (0..n)
            .map(|i| s.terms.mass[(i, i)].abs())
            .fold(0.0, f64::max)
            .max(1e-12);
        s.alpha = s.settings.penalty.unwrap_or(4e4 * m_ref / (h * h));
        crate::initial::make_consistent(&mut s, f)?;
        Ok(s)
    }

    /// A copy of the state a step starts from: time, q, q̇, q̈, λ*, the counters and the
    /// predictor's history (allocates; `restore` does not).
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            t: self.t,
            q: self.q.clone(),
            qd: self.qd.clone(),
            qdd: self.qdd.clone(),
            lambda: self.lambda.clone(),
            stats: self.stats.clone(),
            qdd_prev: self.qdd_prev.clone(),
            have_qdd_prev: self.have_qdd_prev,
            extrapolate: self.extrapolate.clone(),
            pred_err: self.pred_err.clone(),
            contraction: self.contraction,
            miss: self.miss.clone(),
            miss_err: self.miss_err.clone(),
            repeat_miss: self.repeat_miss.clone(),
        }
    }

    /// Overwrite `c` with the state a step starts from, like [`Ali3p::checkpoint`] but into
    /// existing storage: no allocation, so a driver can keep the last good state every step.
    ///
    /// # Panics
    /// If `c` was taken from an integrator of another size.
    pub fn checkpoint_into(&self, c: &mut Checkpoint) {
        assert!(
            c.q.len() == self.q.len() && c.lambda.len() == self.lambda.len(),
            "checkpoint of {} coordinates and {} constraints overwritten from an integrator of {} and {}",
            c.q.len(),
            c.lambda.len(),
            self.q.len(),
            self.lambda.len()
        );
        c.t = self.t;
        c.q.copy_from(&self.q);
        c.qd.copy_from(&self.qd);
        c.qdd.copy_from(&self.qdd);
        c.lambda.copy_from(&self.lambda);
        c.stats.clone_from(&self.stats);
        c.qdd_prev.copy_from(&self.qdd_prev);
        c.have_qdd_prev = self.have_qdd_prev;
        c.extrapolate.copy_from_slice(&self.extrapolate);
        c.pred_err.copy_from_slice(&self.pred_err);
        c.contraction = self.contraction;
        c.miss.clone_from(&self.miss);
        c.miss_err.clone_from(&self.miss_err);
        c.repeat_miss.clone_from(&self.repeat_miss);
    }

    /// Return to a checkpoint of this integrator, so that the next step is the same step
    /// again (benchmarks time one step many times this way). Copies into the existing
    /// storage: no allocation.
    ///
    /// # Panics
    /// If the checkpoint was taken from an integrator of another size.
    pub fn restore(&mut self, c: &Checkpoint) {
        assert!(
            c.q.len() == self.q.len() && c.lambda.len() == self.lambda.len(),
            "checkpoint of {} coordinates and {} constraints restored into an integrator of {} and {}",
            c.q.len(),
            c.lambda.len(),
            self.q.len(),
            self.lambda.len()
        );
        self.t = c.t;
        self.q.copy_from(&c.q);
        self.qd.copy_from(&c.qd);
        self.qdd.copy_from(&c.qdd);
        self.lambda.copy_from(&c.lambda);
        self.stats.clone_from(&c.stats);
        self.qdd_prev.copy_from(&c.qdd_prev);
        self.have_qdd_prev = c.have_qdd_prev;
        self.extrapolate.copy_from_slice(&c.extrapolate);
        self.pred_err.copy_from_slice(&c.pred_err);
        self.contraction = c.contraction;
        if c.miss.len() == self.miss.len() {
            self.miss.copy_from_slice(&c.miss);
            self.miss_err.copy_from_slice(&c.miss_err);
            self.repeat_miss.copy_from_slice(&c.repeat_miss);
        } else {
            self.miss.fill(0.0);
            self.miss_err.fill(0.0);
            self.repeat_miss.fill(false);
        }
    }

    /// The current state (t, q, q̇) with its accelerations q̈, to evaluate the formulation or
    /// read its sensors at.
    pub fn state(&self) -> State<'_> {
        State::new(self.t, &self.q, &self.qd).with_accelerations(&self.qdd)
    }

    /// The penalty α in use.
    pub fn penalty(&self) -> f64 {
        self.alpha
    }
    /// The settings.
    pub fn settings(&self) -> &Ali3pSettings {
        &self.settings
    }
    /// The terms of the last evaluation (M, Q, Φ, ...).
    pub fn terms(&self) -> &SystemTerms {
        &self.terms
    }

    pub(crate) fn eval<F: Formulation + ?Sized>(&mut self, f: &mut F, req: Request) {
        let t0 = (self.time_weight > 0.0).then(Instant::now);
        // Constant tangents were evaluated once (in `new`); never clear or rebuild them.
        let req = if self.constant_tangents && self.stats.evaluations > 0 {
            Request {
                tangents: false,
                ..req
            }
        } else {
            req
        };
        match &self.entries {
            Some(entries) => entries.clear(&mut self.terms, req),
            None => self.terms.clear(req),
        }
        if req.dynamics || req.tangents {
            self.dynamics_passes += 1;
        }
        f.evaluate(State::new(self.t, &self.q, &self.qd), req, &mut self.terms);
        self.stats.evaluations += 1;
        if let Some(t0) = t0 {
            self.stats.time_evaluation += self.time_weight * t0.elapsed().as_secs_f64();
        }
    }

    /// Advance one step of size h (docs/methods.md §5.2): the predictor (`predict`), Newton
    /// iterations — the correction (`correct`), the multiplier update λ* += αΦ
    /// (`update_multipliers`), the convergence test and the singular-passage α raise — then
    /// the predictor choice for the next step (`choose_predictor`) and the projections.
    pub fn step<F: Formulation + ?Sized>(&mut self, f: &mut F) -> Result<(), IntegratorError> {
        self.predict();
        let h = self.settings.step;
        // t = t₀ + k h, not an accumulated sum, so output times are exact multiples.
        self.t = self.t0 + (self.stats.steps + 1) as f64 * h;
        let every = self.settings.profile_every.max(1);
        self.time_weight = if self.stats.steps.is_multiple_of(every) {
            every as f64
        } else {
            0.0
        };
        let (mut dq_norm, mut phi_norm) = (f64::INFINITY, f64::INFINITY);
        let mut prev_dq = f64::INFINITY;
        let mut converged = false;
        let mut iterations = 0;
        // Slow contraction (θ ≥ 0.5 twice after the third iteration) is the multiplier update
        // in a rank-deficient direction of Φ_q (singular configurations): its rate is about
        // 1/(1 + α σ² h²/4m) for the small singular value σ, so α is raised ×10 for the rest
        // of the step (at most twice). The converged q, λ do not depend on α.
        let alpha_step = self.alpha;
        let (mut slow, mut boosts) = (0, 0);
        // Modified Newton gives way to full Newton for the rest of the step once an iteration
        // on a kept tangent fails to halve the correction (the tangent moved: a contact or a
        // law's breakpoint was crossed).
        let mut full_newton = !self.settings.reuse_tangent;
        // The first two corrections, when both were full Newton (`crate::contraction`).
        let (mut first_dq, mut second_dq) = (f64::NAN, None);
        // How far q moved since the factor in hand was formed (`newton_factor_serves`).
        let mut moved = f64::INFINITY;
        while iterations < self.settings.max_iterations {
            iterations += 1;
            let boost = slow >= 2 && boosts < 2;
            if boost {
                self.alpha *= 10.0;
                boosts += 1;
                slow = 0;
            }
            // Modified Newton: refresh the tangent unless the last correction shrank fast.
            let refresh = iterations == 1 || boost || full_newton || dq_norm >= 0.5 * prev_dq;
            self.correct(f, iterations, refresh)?;
            prev_dq = dq_norm;
            dq_norm = self.rhs.amax();
            moved = if refresh { dq_norm } else { moved + dq_norm };
            phi_norm = self.update_multipliers(f);
            if !(dq_norm.is_finite() && phi_norm.is_finite()) {
                self.stats.failed_steps += 1;
                return Err(IntegratorError::Diverged { t: self.t });
            }
            // Error of the iterate: with the observed contraction θ = ‖Δq_i‖/‖Δq_{i−1}‖ < 1 the
            // distance to the solution is about θ/(1−θ)‖Δq_i‖ (Hairer & Wanner II, §IV.8), so a
            // linearly converging iteration can stop one correction earlier than ‖Δq_i‖ ≤ ε_q.
            let theta = if prev_dq.is_finite() {
                dq_norm / prev_dq
            } else {
                1.0
            };
            let error = if iterations == 1 {
                first_dq = dq_norm;
                // The second correction this one would take, as the steps before measured
                // Newton's contraction; ‖Δq₁‖ itself while they have not.
                self.settings
                    .first_iterate_from_contraction
                    .then(|| self.contraction.first_iterate_error(dq_norm))
                    .flatten()
                    .unwrap_or(dq_norm)
            } else if theta < 0.5 {
                theta / (1.0 - theta) * dq_norm
            } else {
                dq_norm
            };
            if iterations == 2 && refresh && !boost {
                second_dq = Some(dq_norm);
            }
            // A kept tangent's slow contraction says nothing about Φ_q's rank.
            if theta >= 0.5 && !refresh {
                full_newton = true;
            } else if iterations >= 3 && theta >= 0.5 {
                slow += 1;
            }
            if error <= self.settings.tol_q * self.q.amax().max(1.0)
                && phi_norm <= self.settings.tol_phi
            {
                converged = true;
                break;
            }
        }
        self.alpha = alpha_step;
        self.stats.newton_iterations += iterations;
        if let Some(d2) = second_dq {
            self.contraction.record(first_dq, d2);
        }
        self.contraction.step_done(second_dq.is_some());
        if !converged {
            // Accepted only when the iterate has settled: ‖Φ‖∞ and the last correction
            // (relative to the positions) both below `accept_phi`. A Newton iteration that
            // wanders off (a step far too large: corrections of 1e146 in a scene without
            // constraints, whose ‖Φ‖ is 0) is a failure, not an acceptance.
            if phi_norm <= self.settings.accept_phi
                && dq_norm <= self.settings.accept_phi * self.q.amax().max(1.0)
            {
                self.stats.accepted_unconverged += 1;
            } else {
                self.stats.failed_steps += 1;
                return Err(IntegratorError::NoConvergence {
                    t: self.t,
                    iterations,
                    dq: dq_norm,
                    phi: phi_norm,
                });
            }
        }
        self.choose_predictor();
        self.set_newmark_rates();
        // Without constraints the projections leave q̇, q̈ as the trapezoidal rule gives them.
        if !self.lambda.is_empty() {
            let refactor = !self.newton_factor_serves(moved, boosts);
            self.project(f, refactor)?;
        }
        if !self.state_is_finite() {
            self.stats.failed_steps += 1;
            return Err(IntegratorError::Diverged { t: self.t });
        }
        self.stats.steps += 1;
        Ok(())
    }

    /// q, q̇, q̈ and λ* all finite (a step that leaves them otherwise fails, whatever its
    /// convergence said).
    fn state_is_finite(&self) -> bool {
        [&self.q, &self.qd, &self.qdd, &self.lambda]
            .iter()
            .all(|v| v.iter().all(|x| x.is_finite()))
    }

    /// One Newton correction of ALI3-P: the M, Q (K, C on `refresh`) pass at q (Φ, Φ_q too
    /// on the first iteration), rhs = −f, f_q formed and factorised on `refresh`, Δq = f_q⁻¹ rhs
    /// into `rhs`, q += Δq. Diverged when Δq is not finite.
    #[inline]
    fn correct<F: Formulation + ?Sized>(
        &mut self,
        f: &mut F,
        iterations: usize,
        refresh: bool,
    ) -> Result<(), IntegratorError> {
        let h = self.settings.step;
        self.set_newmark_rates();
        // Φ and Φ_q at this q come from the pass after the last update (first
        // iteration: from this pass).
        self.eval(
            f,
            Request {
                dynamics: true,
                tangents: refresh,
                constraints: iterations == 1,
                jacobian: iterations == 1,
                accel_term: false,
            },
        );
        let t0 = (self.time_weight > 0.0).then(Instant::now);
        // rhs = −f = −h²/4 (M q̈ + Φ_qᵀ(αΦ + λ) − Q)
        let tt = &self.terms;
        self.tmp_m.copy_from(&self.lambda);
        self.tmp_m.axpy(self.alpha, &tt.phi, 1.0);
        self.rhs.copy_from(&tt.forces);
        match &self.entries {
            Some(entries) => entries.sub_product(&tt.mass, &self.qdd, &mut self.rhs),
            None => self.rhs.gemv(-1.0, &tt.mass, &self.qdd, 1.0),
        }
        self.rhs.gemv_tr(-1.0, &tt.phi_q, &self.tmp_m, 1.0);
        self.rhs *= 0.25 * h * h;
        if refresh {
            self.form_and_factor()?;
        }
        self.solve_leading();
        if let Some(t0) = t0 {
            self.stats.time_factorization += self.time_weight * t0.elapsed().as_secs_f64();
        }
        if !self.rhs.iter().all(|v| v.is_finite()) {
            self.stats.failed_steps += 1;
            return Err(IntegratorError::Diverged { t: self.t });
        }
        self.q += &self.rhs;
        Ok(())
    }

    /// Augmented-Lagrangian multiplier update after a correction: the Φ, Φ_q pass at the new
    /// q (Φ_q for the next iteration or the projections), λ* += αΦ; returns ‖Φ‖∞.
    #[inline]
    fn update_multipliers<F: Formulation + ?Sized>(&mut self, f: &mut F) -> f64 {
        if self.lambda.is_empty() {
            return 0.0;
        }
        // Φ for the multiplier update and the test, Φ_q for the next iteration or the
        // projections (they depend on q and t only).
        self.eval(
            f,
            Request {
                constraints: true,
                jacobian: true,
                ..Request::default()
            },
        );
        let phi_norm = self.terms.phi.amax();
        self.lambda.axpy(self.alpha, &self.terms.phi, 1.0);
        phi_norm
    }

    /// One projection in increment form: with f_q = W + c Φ_qᵀΦ_q (c = h²α/4),
    /// f_q x = W x* − c Φ_qᵀ b is the same equation as f_q (x − x*) = −c Φ_qᵀ (Φ_q x* + b),
    /// so x ← x* + f_q⁻¹(−c Φ_qᵀ r) with r = Φ_q x* + b (b = Φ_t for velocities, the
    /// acceleration term c for accelerations). The solve's round-off is about cond(f_q) · ε
    /// relative to what it returns, and cond(f_q) ≈ 10⁹ on the flexible four-bar (the penalty
    /// against the lightest modal inertia): solving for the whole x would put that noise into
    /// the velocities every step, to accumulate over the steps; solving for the small
    /// increment puts it on the increment (figures in `docs/design.md`, "The integrator").
    fn project_increment(&mut self, accelerations: bool, c: f64) {
        let (x, b) = if accelerations {
            (&self.qdd, &self.terms.accel_term)
        } else {
            (&self.qd, &self.terms.phi_t)
        };
        self.tmp_m.copy_from(b);
        self.tmp_m.gemv(1.0, &self.terms.phi_q, x, 1.0);
        self.rhs.gemv_tr(-c, &self.terms.phi_q, &self.tmp_m, 0.0);
        self.solve_leading();
        if accelerations {
            self.qdd += &self.rhs;
        } else {
            self.qd += &self.rhs;
        }
    }

    fn set_newmark_rates(&mut self) {
        let h = self.settings.step;
        let (a1, a2) = (2.0 / h, 4.0 / (h * h));
        // The expressions of nalgebra's copy + axpy (a x + 1·y), on slices.
        let q = self.q.as_slice();
        for ((v, q), hat) in self
            .qd
            .as_mut_slice()
            .iter_mut()
            .zip(q)
            .zip(self.qd_hat.as_slice())
        {
            *v = a1 * q + hat;
        }
        for ((v, q), hat) in self
            .qdd
            .as_mut_slice()
            .iter_mut()
            .zip(q)
            .zip(self.qdd_hat.as_slice())
        {
            *v = a2 * q + hat;
        }
    }

    /// Whether the projections can take Newton's last factor as it is, f_q formed with Φ_q
    /// at a q that the last corrections moved by `moved` (‖·‖∞ summed): when that is at
    /// most `PROJECTION_REUSE` of the tolerance and α is the one it was formed with (no
    /// raise in this step). The projections' f_q then differs from it only by the change of
    /// Φ_q over `moved`, which moves the projected increments by that relative amount: in a
    /// step whose second iteration contracted quadratically (the flexible vehicle's
    /// ‖Δq₂‖ ≈ 3e-11 against ε_q ‖q‖∞ ≈ 1.5e-8) the factorisation is saved. After one
    /// correction (up to ε_q away, the predictor's Φ_q) it is not: reused there, the factor
    /// was measured to cost 4e-2 m in B0(10 s) of the four-bar (see `project`).
    fn newton_factor_serves(&self, moved: f64, boosts: usize) -> bool {
        boosts == 0 && moved <= PROJECTION_REUSE * self.settings.tol_q * self.q.amax().max(1.0)
    }

    /// Velocity and acceleration projections at the converged positions (methods.md §5.2,
    /// steps 3–4); `refactor` false keeps Newton's last factor (`newton_factor_serves`).
    fn project<F: Formulation + ?Sized>(
        &mut self,
        f: &mut F,
        refactor: bool,
    ) -> Result<(), IntegratorError> {
        let t0 = (self.time_weight > 0.0).then(Instant::now);
        // The projections' own formulation passes are counted under evaluation, not twice.
        let eval_before = self.stats.time_evaluation;
        let h = self.settings.step;
        let c = 0.25 * h * h * self.alpha;
        // Refactorise with Φ_q at the converged q: reusing the last Newton iteration's f_q
        // (Δq ≤ ε_q away) was measured to cost 4e-2 m in B0(10 s) of the four-bar, because
        // the penalty h²α/4 ≈ 10⁴ m amplifies the O(ε_q) change of Φ_q. W = M + h/2 C +
        // h²/4 K is the last Newton iteration's: W only weights the (small) correction
        // q̇ − q̇*, so its O(ε_q) change moves q̇ by O(ε_q ‖q̇ − q̇*‖), and the formulation
        // pass it would take (M, Q, K, C at the converged state) is saved. Where Φ_q did not
        // change (a driven tree joint's row is constant) f_q is the last iteration's bit for
        // bit, and its factor is kept (`form_and_factor`). Where the last correction moved q
        // by a thousandth of the tolerance, Φ_q's change is that small too and Newton's
        // factor is taken as it is (`newton_factor_serves`).
        if refactor {
            self.form_and_factor()?;
        }
        // f_q q̇ = W q̇* − h²/4 Φ_qᵀ α Φ_t, solved for the increment q̇ − q̇* (see
        // `project_increment`).
        self.project_increment(false, c);
        self.eval(
            f,
            Request {
                dynamics: false,
                tangents: false,
                constraints: false,
                jacobian: false,
                accel_term: true,
            },
        );
        // f_q q̈ = W q̈* − h²/4 Φ_qᵀ α c, likewise.
        self.project_increment(true, c);
        if let Some(t0) = t0 {
            let evals = self.stats.time_evaluation - eval_before;
            self.stats.time_projection += self.time_weight * t0.elapsed().as_secs_f64() - evals;
        }
        // Non-finite rates are caught by the step's check of the whole state that follows.
        Ok(())
    }
}
