//! The leading matrix of ALI3-P's Newton iterations and projections (docs/methods.md §5.2):
//! f_q = W + h²/4 Φ_qᵀ α Φ_q with W = M + h/2 C + h²/4 K, formed (its lower triangle when it
//! is symmetric), factorised by the kernel that pays (the structure the formulation declared,
//! the arrow or sparse form found at the first factorisation, dense Cholesky, LU as the
//! fallback) and solved with.

use super::{Ali3p, Factored};
use crate::arrow_llt::ArrowLlt;
use crate::declared_entries::DeclaredEntries;
use crate::declared_llt::DeclaredLlt;
use crate::error::IntegratorError;
use crate::sparse_llt::SPARSE_FROM;
use crate::structured::{Fallback, StructuredLlt};
use flexmbd_core::Formulation;

/// Up to this many coordinates the penalty term Φ_qᵀ α Φ_q is formed densely
/// ([`Ali3p::form_leading`]): the rigid double four-bar (n = 5 relative, 6 absolute) spent
/// 9 % (relative) and 15 % (absolute) of its run in the pattern-driven loop.
const DENSE_PENALTY_UP_TO: usize = 8;

/// Up to this many entries of Φ_q (m n) a factorisation keeps a copy of the Φ_q it was
/// formed with, so that a later call with nothing changed keeps the factor; above, the copy
/// would cost more than the rare reuse saves (a cut joint's rows change every step).
const KEEP_FROM_AT_MOST: usize = 1024;

/// The inputs of the factor in hand: W's pass (the count of M, Q, K, C passes before it),
/// α, and Φ_q. f_q = W + h²/4 Φ_qᵀ α Φ_q is a function of these alone, so asked again with
/// the same ones, the kernel would return the same factor bit for bit. With constant K and C
/// (kept from the first pass) W is a function of M alone, so a later pass whose M is the
/// same bit for bit leaves W as it was too: the modal coordinates of a spin-up beam whose
/// driven hub angle left the unknowns (`flexmbd_core::driven`) have the constant modal mass.
pub(super) struct FactorInputs {
    /// Φ_q is small enough to keep a copy of.
    keep: bool,
    /// M is kept too (constant K and C, and n² within `KEEP_FROM_AT_MOST`).
    keep_mass: bool,
    valid: bool,
    dynamics_passes: usize,
    alpha: f64,
    phi_q: Vec<f64>,
    mass: Vec<f64>,
}

impl FactorInputs {
    /// Room for an m × n Φ_q when it is small enough to keep (`KEEP_FROM_AT_MOST`), and for
    /// the n × n M when the tangents are constant and it is too.
    pub(super) fn new(m: usize, n: usize, constant_tangents: bool) -> Self {
        let keep = m * n <= KEEP_FROM_AT_MOST;
        let keep_mass = keep && constant_tangents && n * n <= KEEP_FROM_AT_MOST;
        FactorInputs {
            keep,
            keep_mass,
            valid: false,
            dynamics_passes: 0,
            alpha: 0.0,
            phi_q: Vec::with_capacity(if keep { m * n } else { 0 }),
            mass: Vec::with_capacity(if keep_mass { n * n } else { 0 }),
        }
    }

    /// W is the one the factor was formed with: no M, Q, K, C pass since, or (constant K
    /// and C) a pass whose M is the same bit for bit.
    fn same_w(&self, dynamics_passes: usize, mass: &[f64]) -> bool {
        self.dynamics_passes == dynamics_passes || (self.keep_mass && self.mass == mass)
    }
}

impl Ali3p {
    /// Take the structure `f` declares, if any, for the run (issue 26 item 2): its arrow
    /// form when that pays (blocks of a tree's branches and the root's border, factorised by
    /// `crate::arrow_llt`), else the sparse Cholesky over it when that pays
    /// (`crate::declared_llt`), else neither; in large systems only the declared entries
    /// are cleared and formed.
    pub(super) fn take_declared_structure<F: Formulation + ?Sized>(&mut self, f: &F) {
        let (n, m) = (self.q.len(), self.lambda.len());
        let Some(pattern) = f.declared_pattern() else {
            return;
        };
        let Some(entries) = DeclaredEntries::new(&pattern, n, m) else {
            return;
        };
        if let Some(arrow) = ArrowLlt::declared(n, entries.lower()) {
            self.structured = Some(StructuredLlt::Arrow(arrow));
            self.structure_decided = true;
        } else {
            self.declared = DeclaredLlt::new(&entries);
        }
        // Below `SPARSE_FROM` a memset and a dense forming of the n² entries cost less than
        // the loops over the pattern's runs, which are short there: the rigid Iltis vehicle
        // (n = 42, 36 % of n²) ran 10 % slower with them (process CPU, 7 interleaved runs).
        if n >= SPARSE_FROM {
            if self.declared.is_none() {
                self.declared_runs = entries.lower_runs();
            }
            self.entries = Some(entries);
        }
    }

    /// Write W = M + h/2 C + h²/4 K (the leading matrix without the penalty) into `lead`:
    /// its lower triangle only when `lower_only`, the whole matrix otherwise. Formed in place
    /// each time, or once into `w` and copied when M, K and C are constant.
    pub(super) fn form_w(&mut self, lower_only: bool) {
        let h = self.settings.step;
        let (a, b) = (0.5 * h, 0.25 * h * h);
        let n = self.lead.nrows();
        let tt = &self.terms;
        let (mass, damping, stiffness) = (
            tt.mass.as_slice(),
            tt.damping.as_slice(),
            tt.stiffness.as_slice(),
        );
        // Column j's entries from row `first(j)` down: the lower triangle, or all of it.
        let first = |j: usize| if lower_only { j } else { 0 };
        let lead = self.lead.as_mut_slice();
        if self.constant_w {
            if !self.w_ready {
                self.w_ready = true;
                let w = self.w.as_mut_slice().iter_mut();
                for (((w, m), c), k) in w.zip(mass).zip(damping).zip(stiffness) {
                    *w = m + a * c + b * k;
                }
            }
            for j in 0..n {
                let column = j * n + first(j)..(j + 1) * n;
                lead[column.clone()].copy_from_slice(&self.w.as_slice()[column]);
            }
            return;
        }
        if lower_only && !self.declared_runs.is_empty() {
            for run in &self.declared_runs {
                let terms = mass[run.clone()]
                    .iter()
                    .zip(&damping[run.clone()])
                    .zip(&stiffness[run.clone()]);
                for (l, ((m, c), k)) in lead[run.clone()].iter_mut().zip(terms) {
                    *l = m + a * c + b * k;
                }
            }
            return;
        }
        for j in 0..n {
            let column = j * n + first(j)..(j + 1) * n;
            let terms = mass[column.clone()]
                .iter()
                .zip(&damping[column.clone()])
                .zip(&stiffness[column.clone()]);
            for (l, ((m, c), k)) in lead[column].iter_mut().zip(terms) {
                *l = m + a * c + b * k;
            }
        }
    }

    /// Form f_q = W + h²/4 Φ_qᵀ α Φ_q: its lower triangle only when `lower_only` (the
    /// Cholesky kernels read no more; the strict upper triangle is then stale), the whole
    /// matrix for the LU.
    pub(super) fn form_leading(&mut self, lower_only: bool) {
        self.form_w(lower_only);
        let h = self.settings.step;
        let lead = self.lead.as_mut_slice();
        let (m, n) = self.terms.phi_q.shape();
        // Φ_qᵀ α Φ_q row by row over Φ_q's non-zero pattern (`JacobianPattern`): natural-
        // coordinate Jacobians have a handful per row, where a dense product would cost m n².
        // Column-major slices.
        let c = 0.25 * h * h * self.alpha;
        let pq = self.terms.phi_q.as_slice();
        if n <= DENSE_PENALTY_UP_TO {
            // Small systems: every entry's sum over the rows in a register, in the same row
            // order and with the same products (c Φ_rj) Φ_ri as the loop below, the entries
            // outside the pattern adding exact zeros. The pattern's bookkeeping and the
            // updates of the same entries through memory, row after row, cost more here than
            // the few products they skip.
            for j in 0..n {
                let col = &mut lead[j * n..(j + 1) * n];
                let phi_j = &pq[j * m..(j + 1) * m];
                for i in if lower_only { j } else { 0 }..n {
                    let phi_i = &pq[i * m..(i + 1) * m];
                    let mut sum = col[i];
                    for (vj, vi) in phi_j.iter().zip(phi_i) {
                        sum += c * vj * vi;
                    }
                    col[i] = sum;
                }
            }
            return;
        }
        self.pattern.cover(pq);
        for r in 0..m {
            self.nz.clear();
            self.nz
                .extend(self.pattern.row(r).iter().map(|&j| (j, pq[r + j * m])));
            for (k, &(j, vj)) in self.nz.iter().enumerate() {
                let cj = c * vj;
                let col = &mut lead[j * n..(j + 1) * n];
                // `nz` is in increasing j: entries from k on are on or below the diagonal.
                let rows = if lower_only {
                    &self.nz[k..]
                } else {
                    &self.nz[..]
                };
                for &(i, vi) in rows {
                    col[i] += cj * vi;
                }
            }
        }
    }

    /// Form and factorise the leading matrix: over the declared structure when there is
    /// one (`crate::declared_llt`), densely (`form_leading`, `factor_leading`) otherwise or
    /// when the declared factorisation fails (f_q not positive definite).
    ///
    /// The factor in hand is kept when it was formed from the same W (no M, Q, K, C pass
    /// since, or the same M with constant K, C), α and Φ_q (`FactorInputs`): the projections
    /// after a Newton iteration whose Φ_q did not move, every iteration of a system whose
    /// leading matrix is constant.
    pub(super) fn form_and_factor(&mut self) -> Result<(), IntegratorError> {
        let keep = self.factored_from.keep;
        let (phi_q, mass) = (self.terms.phi_q.as_slice(), self.terms.mass.as_slice());
        let from = &mut self.factored_from;
        if keep
            && from.valid
            && from.same_w(self.dynamics_passes, mass)
            && from.alpha == self.alpha
            && from.phi_q.as_slice() == phi_q
        {
            from.dynamics_passes = self.dynamics_passes;
            return Ok(());
        }
        from.valid = false;
        self.form_and_factor_anew()?;
        if keep {
            let from = &mut self.factored_from;
            from.phi_q.clear();
            from.phi_q.extend_from_slice(self.terms.phi_q.as_slice());
            if from.keep_mass {
                from.mass.clear();
                from.mass.extend_from_slice(self.terms.mass.as_slice());
            }
            from.dynamics_passes = self.dynamics_passes;
            from.alpha = self.alpha;
            from.valid = true;
        }
        Ok(())
    }

    /// Form and factorise the leading matrix (see `form_and_factor`).
    fn form_and_factor_anew(&mut self) -> Result<(), IntegratorError> {
        if let (Some(declared), Some(entries)) = (self.declared.as_mut(), self.entries.as_ref()) {
            let h = self.settings.step;
            let (a, b) = (0.5 * h, 0.25 * h * h);
            declared.form(entries, &self.terms, a, b, b * self.alpha);
            if declared.factor().is_ok() {
                self.stats.factorizations += 1;
                self.stats.structured_factorizations += 1;
                self.factored = Factored::Declared;
                return Ok(());
            }
            declared.lower_into(self.lead.as_mut_slice());
            self.structure_decided = true;
            return self.factor_leading();
        }
        self.form_leading(self.symmetric);
        self.factor_leading()
    }

    /// Factorise the leading matrix: Cholesky when symmetric, LU otherwise or as the fallback.
    pub(super) fn factor_leading(&mut self) -> Result<(), IntegratorError> {
        self.stats.factorizations += 1;
        if self.symmetric && !self.structure_decided {
            self.structure_decided = true;
            self.structured = self
                .settings
                .structured_factorisation
                .then(|| StructuredLlt::choose(&self.lead))
                .flatten();
        }
        // `structured` is only ever set for a symmetric f_q (above).
        if let Some(structured) = self.structured.as_mut() {
            match structured.factor(&self.lead) {
                Ok(()) => {
                    self.factored = Factored::Structured;
                    self.stats.structured_factorizations += 1;
                    return Ok(());
                }
                Err(Fallback::FromNowOn) => self.structured = None,
                Err(Fallback::ThisTime) => {}
            }
        }
        if self.symmetric && self.llt.factor(&self.lead).is_ok() {
            self.factored = Factored::Llt;
            return Ok(());
        }
        if self.symmetric {
            // Not positive definite after all: the LU needs the upper triangle too.
            self.form_leading(false);
        }
        self.factored = Factored::Lu;
        self.lu.factor(&self.lead).map_err(|e| {
            self.stats.failed_steps += 1;
            IntegratorError::Singular {
                t: self.t,
                pivot_ratio: e.pivot_ratio,
            }
        })
    }

    pub(super) fn solve_leading(&mut self) {
        if let (Factored::Declared, Some(declared)) = (self.factored, self.declared.as_mut()) {
            return declared.solve_in_place(&mut self.rhs);
        }
        match (self.factored, self.structured.as_mut()) {
            (Factored::Structured, Some(structured)) => structured.solve_in_place(&mut self.rhs),
            (Factored::Llt, _) => self.llt.solve_in_place(&mut self.rhs),
            _ => self.lu.solve_in_place(&mut self.rhs),
        }
    }
}
