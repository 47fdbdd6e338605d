//! The lowest eigenpairs of a large sparse symmetric pencil K x = ω² M x, by shift-invert
//! block Lanczos with thick restarts and full M-orthogonalisation.
//!
//! K is symmetric positive semi-definite (a free-free model has six rigid-body modes,
//! ω² = 0), M symmetric positive definite; both `sprs::CsMat<f64>` in full symmetric storage.
//!
//! ## The method
//!
//! - **Spectral transformation** (Ericsson & Ruhe, Math. Comp. 35, 1980; Grimes, Lewis &
//!   Simon, SIAM J. Matrix Anal. Appl. 15, 1994): with a shift σ < 0, A = K − σM is positive
//!   definite even with rigid-body modes, and the operator OP = A⁻¹ M is self-adjoint in the
//!   M inner product with eigenvalues θ = 1 / (ω² − σ) > 0. The lowest ω² are the largest θ,
//!   well separated, so a Krylov method on OP finds them in few steps. A is factorised once,
//!   A = L Lᵀ, by faer's sparse Cholesky ([`crate::sparse::ShiftedCholesky`]).
//! - **Block Lanczos** (Golub & Underwood 1977; Grimes, Lewis & Simon 1994) with block size
//!   p: the basis V (M-orthonormal, Vᵀ M V = I) grows by p vectors a step, W = OP V_j, each
//!   orthogonalised against the whole basis twice (classical Gram–Schmidt, "twice is enough",
//!   Giraud et al. 2005) in the M inner product; M V is kept beside V so that an inner
//!   product costs no product with M. The Gram–Schmidt coefficients form the projected matrix
//!   H = Vᵀ M OP V (symmetric, block tridiagonal after a fresh start). A block of p ≥ 6
//!   finds the six equal θ of the rigid-body modes at once, which a single-vector Lanczos
//!   finds only through round-off.
//! - **Thick restart** (Wu & Simon, SIAM J. Matrix Anal. Appl. 22, 2000; the Krylov–Schur
//!   form of Stewart 2001): when the basis holds m vectors, H = S Θ Sᵀ; the k Ritz vectors
//!   V S_k of the largest θ are kept with H_k = diag(θ₁ … θ_k), the residual block follows
//!   with its coupling B S_k (B the last block of H below the basis), and the basis grows
//!   again. Saad, *Numerical Methods for Large Eigenvalue Problems*, 2nd ed., 2011, ch. 6–8.
//! - **Convergence**: the Ritz estimate ‖B s_i‖ = ‖OP y_i − θ_i y_i‖_M measures the residual
//!   of OP, not of the pencil: K y − ω² M y = −(K − σM) r / θ with r = OP y − θ y, and r lies
//!   in the residual block, dominated by the unconverged end of the basis where
//!   K − σM ≈ M / θ_min. So ‖B s_i‖ ≤ tol θ_min (θ_min the smallest Ritz value of the cycle)
//!   flags a cycle whose wanted pairs may have converged; then x_i = V s_i,
//!   ω²_i = x_iᵀ K x_i / x_iᵀ M x_i and the normwise backward error of the pair is checked
//!   (Higham & Higham, "Structured backward error and condition of generalized eigenvalue
//!   problems", SIAM J. Matrix Anal. Appl. 20, 1998, eq. 2.3):
//!
//!   η(x, ω²) = ‖K x − ω² M x‖ / ((‖K‖ + |ω²| ‖M‖) ‖x‖) ≤ tol,
//!
//!   the smallest relative perturbation of K and M (in norm) for which (x, ω²) is an exact
//!   pair. The norms are the max absolute column sums ‖·‖₁, which bound the 2-norm of a
//!   symmetric matrix from above, computed once. Round-off alone makes η about ε √nnz per
//!   row, whatever the spread of K: for a beam of short elements (K_ii up to 10¹³ against
//!   ‖K x‖ of 10³ for its lowest mode) the relative residual ‖K x − ω² M x‖ / ‖K x‖ cannot
//!   fall below ~10⁻¹⁰, as the cancellation in K x loses ε ‖|K| |x|‖, while η reaches 10⁻¹⁶.
//!   It is defined for a rigid-body mode as well (ω² = 0: η = ‖K x‖ / (‖K‖ ‖x‖)). When a
//!   pair's η is too large, the Ritz threshold is lowered tenfold and the iteration goes on.
//!
//! ## The shift
//!
//! By default σ = −10⁻⁵ · mean_i(K_ii / M_ii) ([`default_shift`]). The mean diagonal ratio is
//! of the order of the model's highest ω² (an element's own frequencies), so |σ| sits far
//! below it: K − σM stays positive definite against the round-off of K's rigid-body null
//! space, and the attainable residual of a rigid-body mode, about ε ω²_max / (2|σ|), stays
//! near 10⁻¹¹ in the relative measure ‖r‖ / ‖(K − σM) x‖ (η is smaller still). On most models |σ| also lies below the first elastic
//! ω², so the elastic θ keep their relative gaps. For a very slender model (first elastic ω²
//! far below 10⁻⁵ of the element frequencies) a shift closer to zero converges faster:
//! [`SparseEigenOptions::shift`].
//!
//! Results are deterministic: a fixed pseudo-random start, sequential kernels (`Par::Seq`),
//! and each vector's sign fixed so that its largest-magnitude component is positive.

use std::time::{Duration, Instant};

use faer::dyn_stack::MemBuffer;
use faer::linalg::matmul::matmul;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par, Side};
use nalgebra::DMatrix;
use sprs::CsMat;

use crate::error::FeError;
use crate::modal::{Eigenpairs, fix_signs, generalized_eigen};
use crate::sparse::{Columns, ShiftedCholesky, check_symmetric, norm, symmetric_matvec};

/// The default shift's fraction of the mean diagonal ratio K_ii / M_ii (module docs).
pub const SHIFT_FRACTION: f64 = 1e-5;

/// Models with N < DENSE_FACTOR · (m + p) DOFs (m the basis size, p the block size) are
/// solved densely ([`generalized_eigen`]): the Krylov basis would fill much of the space.
const DENSE_FACTOR: usize = 2;

/// A new direction whose M-norm fell below this fraction of its norm before
/// orthogonalisation is taken as dependent on the basis.
const BREAKDOWN: f64 = 1e-12;

/// Settings of [`lowest_modes`].
#[derive(Clone, Debug, PartialEq)]
pub struct SparseEigenOptions {
    /// Bound on the backward error η of every pair (module docs). Default 10⁻¹².
    pub tol: f64,
    /// Block size p of the Lanczos steps. Default 6, the number of rigid-body modes of a
    /// free body: equal eigenvalues up to p are found at once.
    pub block_size: usize,
    /// Basis size m (the projected problem's order) before a restart. Default
    /// max(2 n_modes, n_modes + 3p); at least n_modes + 2p is used.
    pub basis_size: Option<usize>,
    /// The shift σ. Default [`default_shift`]; it must make K − σM positive definite,
    /// i.e. lie below every eigenvalue.
    pub shift: Option<f64>,
    /// Bound on the number of restarts. Default 100.
    pub max_restarts: usize,
}

impl Default for SparseEigenOptions {
    fn default() -> Self {
        SparseEigenOptions {
            tol: 1e-12,
            block_size: 6,
            basis_size: None,
            shift: None,
            max_restarts: 100,
        }
    }
}

/// Wall-clock time of the phases of a solve.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhaseTimes {
    /// Checks of the input and the default shift.
    pub checks: Duration,
    /// Symbolic Cholesky analysis (AMD ordering, supernodes).
    pub symbolic: Duration,
    /// Numeric Cholesky factorisation of K − σM.
    pub numeric: Duration,
    /// Solves with the factor (the operator OP).
    pub solves: Duration,
    /// Gram–Schmidt against the basis and products with M.
    pub orthogonalisation: Duration,
    /// Projected eigenproblems, restarts, Ritz vectors and the residual checks.
    pub rayleigh_ritz: Duration,
    /// The whole call.
    pub total: Duration,
}

/// What a solve did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// The shift σ used.
    pub shift: f64,
    /// Block size p.
    pub block_size: usize,
    /// Basis size m.
    pub basis_size: usize,
    /// Numeric factorisations of K − σM (1, or 0 when solved densely).
    pub factorisations: usize,
    /// Entries of the Cholesky factor L.
    pub factor_entries: usize,
    /// Vectors to which OP was applied (one solve with L and Lᵀ each).
    pub solves: usize,
    /// Thick restarts.
    pub restarts: usize,
    /// The backward error η of each returned pair (module docs), in their order.
    pub residuals: Vec<f64>,
    /// Whether the model was small enough to be solved densely.
    pub dense: bool,
    /// Time by phase.
    pub times: PhaseTimes,
}

/// The `n_modes` lowest eigenpairs of K x = ω² M x (module docs): ω² ascending,
/// mass-normalised vectors with their signs fixed.
pub fn lowest_modes(
    k: &CsMat<f64>,
    m: &CsMat<f64>,
    n_modes: usize,
    options: &SparseEigenOptions,
) -> Result<Eigenpairs, FeError> {
    lowest_modes_with_stats(k, m, n_modes, options).map(|(pairs, _)| pairs)
}

/// [`lowest_modes`] with what the solve did.
pub fn lowest_modes_with_stats(
    k: &CsMat<f64>,
    m: &CsMat<f64>,
    n_modes: usize,
    options: &SparseEigenOptions,
) -> Result<(Eigenpairs, Stats), FeError> {
    let start = Instant::now();
    let n = k.rows();
    check_symmetric(k, n, "stiffness matrix K")?;
    check_symmetric(m, n, "mass matrix M")?;
    check_options(options, n_modes, n)?;
    let shift = match options.shift {
        Some(s) => s,
        None => default_shift(k, m)?,
    };
    let p = options.block_size;
    let basis = options
        .basis_size
        .unwrap_or((2 * n_modes).max(n_modes + 3 * p))
        .max(n_modes + 2 * p);
    let mut stats = Stats {
        shift,
        block_size: p,
        basis_size: basis,
        ..Stats::default()
    };
    stats.times.checks = start.elapsed();
    let norms = PencilNorms::of(k, m);
    let pairs = if n_modes == 0 {
        Eigenpairs {
            omega_sq: Vec::new(),
            vectors: DMatrix::zeros(n, 0),
        }
    } else if n < DENSE_FACTOR * (basis + p) {
        stats.dense = true;
        dense_lowest(k, m, n_modes, norms, &mut stats)?
    } else {
        let chol = ShiftedCholesky::new(k, m, shift)?;
        stats.factorisations = 1;
        stats.factor_entries = chol.factor_entries();
        stats.times.symbolic = chol.times.symbolic;
        stats.times.numeric = chol.times.numeric;
        let mut lanczos = Lanczos::new(&chol, Columns::of(m), p, basis);
        lanczos.run(k, norms, n_modes, options, &mut stats)?
    };
    stats.times.total = start.elapsed();
    Ok((pairs, stats))
}

/// σ = −[`SHIFT_FRACTION`] · mean_i(K_ii / M_ii) (module docs). Refuses a mass matrix
/// with a diagonal entry that is not positive (it cannot be positive definite).
pub fn default_shift(k: &CsMat<f64>, m: &CsMat<f64>) -> Result<f64, FeError> {
    let (kc, mc) = (Columns::of(k), Columns::of(m));
    let n = k.rows();
    let mut sum = 0.0;
    for i in 0..n {
        let mii = mc.get(i, i);
        if mii.is_nan() || mii <= 0.0 {
            return Err(FeError::NotPositiveDefinite {
                what: format!("mass matrix M (diagonal entry {i} is {mii:e})"),
                pivot: i,
            });
        }
        sum += kc.get(i, i).max(0.0) / mii;
    }
    let mean = if n == 0 { 0.0 } else { sum / n as f64 };
    // A zero K (all modes rigid) still needs a negative shift.
    Ok(if mean > 0.0 {
        -SHIFT_FRACTION * mean
    } else {
        -1.0
    })
}

fn check_options(options: &SparseEigenOptions, n_modes: usize, n: usize) -> Result<(), FeError> {
    use flexmbd_core::InvalidValue;
    if n_modes > n {
        return Err(FeError::TooManyModes {
            requested: n_modes,
            available: n,
        });
    }
    if !(options.tol.is_finite() && options.tol > 0.0 && options.tol < 1.0) {
        return Err(InvalidValue::new("tol", options.tol, "must lie in (0, 1)").into());
    }
    if options.block_size == 0 {
        return Err(InvalidValue::new("block_size", 0, "must be >= 1").into());
    }
    if let Some(s) = options.shift
        && !s.is_finite()
    {
        return Err(InvalidValue::new("shift", s, "must be finite").into());
    }
    Ok(())
}

/// The dense route for small models: the same pairs, backward errors measured the same way.
fn dense_lowest(
    k: &CsMat<f64>,
    m: &CsMat<f64>,
    n_modes: usize,
    norms: PencilNorms,
    stats: &mut Stats,
) -> Result<Eigenpairs, FeError> {
    let kd = crate::assembly::to_dense(k);
    let md = crate::assembly::to_dense(m);
    let pairs = generalized_eigen(&kd, &md, "sparse pencil (solved densely)")?.truncate(n_modes);
    let (kc, mc) = (Columns::of(k), Columns::of(m));
    stats.residuals = (0..n_modes)
        .map(|j| {
            let x: Vec<f64> = pairs.vectors.column(j).iter().copied().collect();
            backward_error(&kc, &mc, norms, &x, pairs.omega_sq[j])
        })
        .collect();
    Ok(pairs)
}

/// ‖K‖₁ and ‖M‖₁ (max absolute column sums), the norms of the backward error (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PencilNorms {
    /// ‖K‖₁.
    pub k: f64,
    /// ‖M‖₁.
    pub m: f64,
}

impl PencilNorms {
    /// The norms of K and M.
    pub fn of(k: &CsMat<f64>, m: &CsMat<f64>) -> Self {
        PencilNorms {
            k: one_norm(k),
            m: one_norm(m),
        }
    }
}

/// max_j Σ_i |a_ij|.
fn one_norm(a: &CsMat<f64>) -> f64 {
    let mut columns = vec![0.0_f64; a.cols()];
    for (v, (_, j)) in a.iter() {
        columns[j] += v.abs();
    }
    columns.into_iter().fold(0.0, f64::max)
}

/// η(x, λ) = ‖K x − λ M x‖ / ((‖K‖₁ + |λ| ‖M‖₁) ‖x‖) (module docs).
pub fn backward_error(
    k: &Columns<'_>,
    m: &Columns<'_>,
    norms: PencilNorms,
    x: &[f64],
    lambda: f64,
) -> f64 {
    let n = x.len();
    let (mut kx, mut mx) = (vec![0.0; n], vec![0.0; n]);
    symmetric_matvec(k, x, &mut kx);
    symmetric_matvec(m, x, &mut mx);
    backward_error_of(&kx, &mx, norms, norm(x), lambda)
}

fn backward_error_of(kx: &[f64], mx: &[f64], norms: PencilNorms, x_norm: f64, lambda: f64) -> f64 {
    let r: Vec<f64> = kx.iter().zip(mx).map(|(a, b)| a - lambda * b).collect();
    let denominator = (norms.k + lambda.abs() * norms.m) * x_norm;
    if denominator > 0.0 {
        norm(&r) / denominator
    } else {
        norm(&r)
    }
}

/// The state of the thick-restart block Lanczos iteration.
struct Lanczos<'a> {
    chol: &'a ShiftedCholesky,
    m: Columns<'a>,
    n: usize,
    /// Block size p.
    p: usize,
    /// Basis size m at which a restart happens.
    basis: usize,
    /// The basis V (column-major n × (basis + p)), M-orthonormal.
    v: Vec<f64>,
    /// M V, aligned with `v`.
    mv: Vec<f64>,
    /// The projected matrix H = Vᵀ M OP V, (basis + p)², column-major; its lower triangle
    /// holds the Lanczos relation.
    h: Mat<f64>,
    /// Columns to which OP has been applied; columns [s, s + p) are the next block.
    s: usize,
    /// Workspace: the block W = OP V_j, then the restart's products.
    work: Vec<f64>,
    scratch: MemBuffer,
    rng: u64,
    solves: usize,
    times: PhaseTimes,
}

/// The Ritz pairs of one cycle, θ descending.
struct Ritz {
    theta: Vec<f64>,
    /// Eigenvectors of H, s × s, column-major, in the order of `theta`.
    vectors: Mat<f64>,
    /// Ritz estimates ‖B s_i‖.
    estimates: Vec<f64>,
}

impl<'a> Lanczos<'a> {
    fn new(chol: &'a ShiftedCholesky, m: Columns<'a>, p: usize, basis: usize) -> Self {
        let n = chol.n();
        let width = basis + p;
        Lanczos {
            chol,
            m,
            n,
            p,
            basis,
            v: vec![0.0; n * width],
            mv: vec![0.0; n * width],
            h: Mat::zeros(width, width),
            s: 0,
            work: vec![0.0; n * basis.max(p)],
            scratch: chol.solve_scratch(p),
            rng: 0x9E37_79B9_7F4A_7C15,
            solves: 0,
            times: PhaseTimes::default(),
        }
    }

    fn run(
        &mut self,
        k: &CsMat<f64>,
        norms: PencilNorms,
        n_modes: usize,
        options: &SparseEigenOptions,
        stats: &mut Stats,
    ) -> Result<Eigenpairs, FeError> {
        let kc = Columns::of(k);
        self.start_block()?;
        let mut ritz_tol = options.tol;
        let mut restarts = 0;
        let mut converged = 0;
        loop {
            while self.s + self.p <= self.basis {
                self.step()?;
            }
            let t = Instant::now();
            let ritz = self.ritz()?;
            // The residual block is dominated by the unconverged end of the spectrum, where
            // K − σM ≈ (1/θ_min) M: a Ritz estimate e_i then means a residual of
            // about e_i / (2 θ_min) (module docs).
            let theta_min = ritz.theta[self.s - 1].abs();
            let flagged = (0..n_modes)
                .take_while(|&i| ritz.estimates[i] <= ritz_tol * theta_min)
                .count();
            converged = converged.max(flagged);
            if flagged == n_modes {
                let (pairs, residuals) = self.pairs(&kc, norms, &ritz, n_modes);
                if residuals.iter().all(|&r| r <= options.tol) {
                    self.times.rayleigh_ritz += t.elapsed();
                    stats.residuals = residuals;
                    stats.solves = self.solves;
                    stats.restarts = restarts;
                    let (sym, num) = (stats.times.symbolic, stats.times.numeric);
                    stats.times = PhaseTimes {
                        checks: stats.times.checks,
                        symbolic: sym,
                        numeric: num,
                        ..self.times
                    };
                    return Ok(pairs);
                }
                ritz_tol *= 0.1;
            }
            if restarts == options.max_restarts {
                return Err(FeError::SparseEigenNoConvergence {
                    converged,
                    requested: n_modes,
                    tol: options.tol,
                    restarts,
                    solves: self.solves,
                });
            }
            let keep = (n_modes + (self.s - n_modes) / 2).min(self.s - self.p);
            self.restart(&ritz, keep);
            restarts += 1;
            self.times.rayleigh_ritz += t.elapsed();
        }
    }

    fn next_random(&mut self) -> f64 {
        // xorshift64*: a fixed sequence, the same on every run.
        self.rng ^= self.rng >> 12;
        self.rng ^= self.rng << 25;
        self.rng ^= self.rng >> 27;
        let x = self.rng.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    /// Fill columns [0, p) with M-orthonormal pseudo-random vectors.
    fn start_block(&mut self) -> Result<(), FeError> {
        for col in 0..self.p {
            self.append_random(col)?;
        }
        Ok(())
    }

    /// A pseudo-random vector, M-orthogonalised against [0, col) twice, into column `col`.
    fn append_random(&mut self, col: usize) -> Result<(), FeError> {
        let mut w: Vec<f64> = (0..self.n).map(|_| self.next_random()).collect();
        self.orthogonalise_single(&mut w, col);
        self.orthogonalise_single(&mut w, col);
        let (z, beta) = self.m_product(&w)?;
        if beta > 0.0 && beta.is_finite() {
            self.store(w, z, beta, col);
            Ok(())
        } else {
            Err(self.exhausted())
        }
    }

    fn exhausted(&self) -> FeError {
        FeError::Dimension {
            what: "sparse eigen-solver".to_string(),
            detail: format!(
                "the Krylov basis exhausted the space of {} DOFs (basis {} + block {})",
                self.n, self.basis, self.p
            ),
        }
    }

    /// Apply OP to the block [s, s + p) and append the next block [s + p, s + 2p).
    fn step(&mut self) -> Result<(), FeError> {
        let (n, p, s) = (self.n, self.p, self.s);
        let t = Instant::now();
        self.work[..n * p].copy_from_slice(&self.mv[n * s..n * (s + p)]);
        self.chol.solve_in_place(
            MatMut::from_column_major_slice_mut(&mut self.work[..n * p], n, p),
            &mut self.scratch,
        );
        self.solves += p;
        self.times.solves += t.elapsed();
        let t = Instant::now();
        let mut block = std::mem::take(&mut self.work);
        // Block classical Gram–Schmidt against [0, s + p), twice.
        for _ in 0..2 {
            let c = self.project_block(&mut block[..n * p], s + p);
            for i in 0..p {
                for r in 0..s + p {
                    self.h[(r, s + i)] += c[(r, i)];
                }
            }
        }
        for i in 0..p {
            let col = s + p + i;
            let mut w = block[n * i..n * (i + 1)].to_vec();
            // Against the block's new columns [s + p, col), twice.
            for _ in 0..2 {
                for r in s + p..col {
                    let coeff = dot(&self.mv[n * r..n * (r + 1)], &w);
                    axpy(-coeff, &self.v[n * r..n * (r + 1)], &mut w);
                    self.h[(r, s + i)] += coeff;
                }
            }
            let (mut z, mut beta) = self.m_product(&w)?;
            // ‖OP v‖_M before orthogonalisation, by Pythagoras.
            let coefficients = (0..col).map(|r| self.h[(r, s + i)].powi(2)).sum::<f64>();
            let reference = (coefficients + beta * beta).sqrt();
            if beta < 0.5 * reference && beta > BREAKDOWN * reference {
                // Cancellation: one more pass against the whole basis.
                let c = self.orthogonalise_single(&mut w, col);
                for (r, cr) in c.iter().enumerate() {
                    self.h[(r, s + i)] += cr;
                }
                (z, beta) = self.m_product(&w)?;
            }
            if beta > BREAKDOWN * reference {
                self.store(w, z, beta, col);
                self.h[(col, s + i)] = beta;
            } else {
                // OP V_j is (numerically) in the basis: continue with a fresh direction,
                // coupled to nothing.
                self.append_random(col)?;
                self.h[(col, s + i)] = 0.0;
            }
        }
        self.work = block;
        self.s += p;
        self.times.orthogonalisation += t.elapsed();
        Ok(())
    }

    /// C = (M V[:, 0..c])ᵀ W, W −= V[:, 0..c] C for a block W (n × p); returns C.
    fn project_block(&self, block: &mut [f64], c: usize) -> Mat<f64> {
        let n = self.n;
        let p = block.len() / n;
        let v = MatRef::from_column_major_slice(&self.v[..n * c], n, c);
        let mv = MatRef::from_column_major_slice(&self.mv[..n * c], n, c);
        let mut coeff = Mat::zeros(c, p);
        let mut w = MatMut::from_column_major_slice_mut(block, n, p);
        matmul(
            coeff.as_mut(),
            Accum::Replace,
            mv.transpose(),
            w.rb(),
            1.0,
            Par::Seq,
        );
        matmul(w.rb_mut(), Accum::Add, v, coeff.as_ref(), -1.0, Par::Seq);
        coeff
    }

    /// Orthogonalise one vector against columns [0, c) once; returns the coefficients.
    fn orthogonalise_single(&self, w: &mut [f64], c: usize) -> Vec<f64> {
        if c == 0 {
            return Vec::new();
        }
        let coeff = self.project_block(w, c);
        (0..c).map(|r| coeff[(r, 0)]).collect()
    }

    /// M w and ‖w‖_M. Refuses a negative wᵀ M w: M is not positive definite.
    fn m_product(&self, w: &[f64]) -> Result<(Vec<f64>, f64), FeError> {
        let mut z = vec![0.0; self.n];
        symmetric_matvec(&self.m, w, &mut z);
        let wmw = dot(w, &z);
        if wmw < 0.0 {
            return Err(FeError::NotPositiveDefinite {
                what: format!("mass matrix M (a Lanczos vector has xᵀ M x = {wmw:e} < 0)"),
                pivot: 0,
            });
        }
        Ok((z, wmw.sqrt()))
    }

    /// Store w / β in column `col` of V and z / β (z = M w) in M V.
    fn store(&mut self, mut w: Vec<f64>, mut z: Vec<f64>, beta: f64, col: usize) {
        let n = self.n;
        for x in w.iter_mut().chain(z.iter_mut()) {
            *x /= beta;
        }
        self.v[n * col..n * (col + 1)].copy_from_slice(&w);
        self.mv[n * col..n * (col + 1)].copy_from_slice(&z);
    }

    /// Eigenpairs of the projected H[0..s, 0..s] and their Ritz estimates.
    fn ritz(&self) -> Result<Ritz, FeError> {
        let (s, p) = (self.s, self.p);
        let hs = Mat::from_fn(s, s, |i, j| {
            if i >= j {
                self.h[(i, j)]
            } else {
                self.h[(j, i)]
            }
        });
        let eig = hs
            .self_adjoint_eigen(Side::Lower)
            .map_err(|_| FeError::EigenNoConvergence {
                what: "projected Lanczos matrix".to_string(),
            })?;
        let values = eig.S().column_vector();
        let u = eig.U();
        // Descending θ.
        let order: Vec<usize> = (0..s).rev().collect();
        let theta: Vec<f64> = order.iter().map(|&i| values[i]).collect();
        let vectors = Mat::from_fn(s, s, |r, c| u[(r, order[c])]);
        let estimates = (0..s)
            .map(|c| {
                (0..p)
                    .map(|i| {
                        (0..p)
                            .map(|j| self.h[(s + i, s - p + j)] * vectors[(s - p + j, c)])
                            .sum::<f64>()
                            .powi(2)
                    })
                    .sum::<f64>()
                    .sqrt()
            })
            .collect();
        Ok(Ritz {
            theta,
            vectors,
            estimates,
        })
    }

    /// Keep the `keep` leading Ritz vectors, then the residual block (module docs).
    fn restart(&mut self, ritz: &Ritz, keep: usize) {
        let (n, p, s) = (self.n, self.p, self.s);
        let y = ritz.vectors.subcols(0, keep);
        for basis in [&mut self.v, &mut self.mv] {
            let mut product =
                MatMut::from_column_major_slice_mut(&mut self.work[..n * keep], n, keep);
            let current = MatRef::from_column_major_slice(&basis[..n * s], n, s);
            matmul(product.rb_mut(), Accum::Replace, current, y, 1.0, Par::Seq);
            basis[..n * keep].copy_from_slice(&self.work[..n * keep]);
            basis.copy_within(n * s..n * (s + p), n * keep);
        }
        let mut h = Mat::zeros(self.h.nrows(), self.h.ncols());
        for c in 0..keep {
            h[(c, c)] = ritz.theta[c];
            for i in 0..p {
                h[(keep + i, c)] = (0..p)
                    .map(|j| self.h[(s + i, s - p + j)] * ritz.vectors[(s - p + j, c)])
                    .sum();
            }
        }
        self.h = h;
        self.s = keep;
    }

    /// The wanted pairs of this cycle: x_i = V s_i, Rayleigh quotients, backward errors;
    /// sorted by ω², signs fixed.
    fn pairs(
        &self,
        k: &Columns<'_>,
        norms: PencilNorms,
        ritz: &Ritz,
        n_modes: usize,
    ) -> (Eigenpairs, Vec<f64>) {
        let (n, s) = (self.n, self.s);
        let v = MatRef::from_column_major_slice(&self.v[..n * s], n, s);
        let mut x = Mat::zeros(n, n_modes);
        matmul(
            x.as_mut(),
            Accum::Replace,
            v,
            ritz.vectors.subcols(0, n_modes),
            1.0,
            Par::Seq,
        );
        let mut found: Vec<(f64, Vec<f64>, f64)> = (0..n_modes)
            .map(|j| {
                let mut xj: Vec<f64> = (0..n).map(|i| x[(i, j)]).collect();
                let (mut kx, mut mx) = (vec![0.0; n], vec![0.0; n]);
                symmetric_matvec(k, &xj, &mut kx);
                symmetric_matvec(&self.m, &xj, &mut mx);
                let xmx = dot(&xj, &mx);
                let lambda = dot(&xj, &kx) / xmx;
                let residual = backward_error_of(&kx, &mx, norms, norm(&xj), lambda);
                let scale = 1.0 / xmx.sqrt();
                xj.iter_mut().for_each(|v| *v *= scale);
                (lambda, xj, residual)
            })
            .collect();
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut vectors = DMatrix::from_fn(n, n_modes, |i, j| found[j].1[i]);
        fix_signs(&mut vectors);
        let residuals = found.iter().map(|f| f.2).collect();
        let omega_sq = found.into_iter().map(|f| f.0).collect();
        (Eigenpairs { omega_sq, vectors }, residuals)
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}
