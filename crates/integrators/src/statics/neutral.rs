//! The neutral motions of a static equilibrium, and taking back what a solve drifted along
//! them.
//!
//! **The regularised attempt.** A free vehicle on vertical tyres can be moved forward, sideways or
//! turned about the vertical without any force changing; a pendulum on a ball joint can be
//! turned about the vertical. H is singular along such motions (or, with the difference
//! tangent, has only rounding there), so Newton either stops at the first factorisation or
//! wanders along them by rounding-sized residuals divided by rounding-sized pivots (the 3D
//! double pendulum turned 36 rad about the vertical and never met the step test). When the
//! plain attempt fails, the solve is repeated with H + ρ M(q₀), ρ = 10⁻⁶ k_ref/m_ref: the
//! Levenberg–Marquardt step in the kinetic metric, which leaves a neutral motion untouched
//! (the residual has no component along it) and slows Newton elsewhere only by the factor
//! ρm/(k + ρm), 10⁻⁶ for the stiffest direction. Its steps along a neutral motion are
//! rounding residuals over ρm, about 10⁻⁷ m, so that attempt is converged on ‖g‖ and ‖Φ‖
//! alone (the step test cannot hold there, and ‖g‖ ≤ ε_r f_ref is the equilibrium
//! condition itself). It is a second attempt rather than the default so that the scenes that converge without it keep their bits. A body that is
//! really free under a load (a falling body) still fails, with the first attempt's diagnosis.
//!
//! **The drift taken back.** Every placement along a neutral motion is the same equilibrium,
//! and Newton moves along these motions by whatever rounding and difference-tangent errors push it (the
//! Iltis vehicle: 0.09 mm forward in one formulation, 0.10 mm in the other, so that the two
//! met the bump 1.6·10⁻⁵ m apart). So that a solve's answer depends on the scene and not on the
//! path, the displacement from the guess q₀ is made M-orthogonal to the neutral motions:
//!
//! 1. linearise about (q*, λ*) (`crate::linearise`): M, K and the basis R of the motions the
//!    constraints (and the held coordinates) allow;
//! 2. the neutral motions are the generalized eigenvectors of (RᵀKR, RᵀMR) whose eigenvalues
//!    are zero to [`NEUTRAL_TOLERANCE`] of the largest, M-orthonormal: N = R Y, NᵀMN = I;
//! 3. q ← q* − N Nᵀ M (q* − q₀).
//!
//! A translation is neutral exactly, so this is exact for it in natural coordinates (M
//! constant: the system's mass centre stays put); a turn only to first order, and in relative
//! coordinates M varies with q: so the result is polished by Newton and the pass repeated
//! (up to `NEUTRAL_PASSES`) until the correction is below the step tolerance. It runs after
//! every solve but changes nothing where there is no neutral motion.
//!
//! **Coordinate singularities.** A converged point where M + α_M Φ_qᵀΦ_q is singular is
//! refused ([`StaticError::CoordinateSingularity`]): there the relative formulation's Cardan
//! angles are at ±90°, where the generalized force of a turn vanishes without equilibrium
//! (measured: the 3D double pendulum and a spherical pendulum reached 5π/2 with residual
//! 10⁻¹⁵).

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use super::{Level, NEUTRAL_PASSES, REGULARISATION, REQ_FULL, Solver, StaticError};
use crate::linearise::{linearise, null_space};
use flexmbd_core::Formulation;

/// Generalized eigenvalues ω² at most this fraction of the largest are neutral: a difference
/// tangent's error is ≈ ε^{2/3} ≈ 4·10⁻¹¹ of the largest, while the softest physical mode of
/// the Iltis vehicle is 10⁻² of its wheel hop and that of the FNL2 spin-up beam (first bending
/// against the highest axial FE mode) 10⁻⁸.
pub const NEUTRAL_TOLERANCE: f64 = 1e-9;

/// q* with its drift from `q0` along the neutral motions removed (module documentation);
/// `None` when there is no neutral motion or the linearisation fails.
pub fn without_neutral_drift<F: Formulation + ?Sized>(
    f: &mut F,
    t: f64,
    q0: &DVector<f64>,
    q: &DVector<f64>,
    lambda: &DVector<f64>,
    held: &[bool],
) -> Option<DVector<f64>> {
    let lin = linearise(f, t, q, lambda).ok()?;
    let n = q.len();
    let n_held = held.iter().filter(|&&h| h).count();
    let rows = lin_constraint_rows(f, t, q, n);
    let mut blocked = DMatrix::zeros(rows.nrows() + n_held, n);
    blocked.rows_mut(0, rows.nrows()).copy_from(&rows);
    for (k, j) in (0..n).filter(|&j| held[j]).enumerate() {
        blocked[(rows.nrows() + k, j)] = 1.0;
    }
    let r = null_space(&blocked).ok()?;
    let modes = neutral_modes(&r, &lin.mass, &lin.stiffness)?;
    if modes.ncols() == 0 {
        return None;
    }
    let drift = q - q0;
    let weights = modes.transpose() * (&lin.mass * drift);
    Some(q - modes * weights)
}

/// Φ_q at q.
fn lin_constraint_rows<F: Formulation + ?Sized>(
    f: &mut F,
    t: f64,
    q: &DVector<f64>,
    n: usize,
) -> DMatrix<f64> {
    let m = f.n_constraints();
    let mut terms = flexmbd_core::SystemTerms::new(n, m);
    let zero = DVector::zeros(n);
    let req = flexmbd_core::Request {
        tangents: false,
        ..flexmbd_core::Request::ALL
    };
    f.evaluate(flexmbd_core::State::new(t, q, &zero), req, &mut terms);
    terms.phi_q
}

/// N = R Y (n × k): the M-orthonormal generalized eigenvectors of (RᵀKR, RᵀMR) with
/// eigenvalues within [`NEUTRAL_TOLERANCE`] of zero. `None` when RᵀMR is not positive definite.
fn neutral_modes(
    r: &DMatrix<f64>,
    mass: &DMatrix<f64>,
    stiffness: &DMatrix<f64>,
) -> Option<DMatrix<f64>> {
    let m_r = r.transpose() * mass * r;
    let k_r = r.transpose() * stiffness * r;
    let l = m_r.cholesky()?.l();
    let l_inv = l.clone().try_inverse()?;
    // A = L⁻¹ K_r L⁻ᵀ, symmetrised (the difference tangent is not exactly symmetric).
    let a = &l_inv * k_r * l_inv.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let eigen = SymmetricEigen::new(a);
    let largest = eigen.eigenvalues.amax();
    if largest == 0.0 {
        return None;
    }
    let zero: Vec<usize> = (0..eigen.eigenvalues.len())
        .filter(|&i| eigen.eigenvalues[i].abs() <= NEUTRAL_TOLERANCE * largest)
        .collect();
    let mut y = DMatrix::zeros(r.ncols(), zero.len());
    for (k, &i) in zero.iter().enumerate() {
        y.set_column(k, &eigen.eigenvectors.column(i));
    }
    // x = L⁻ᵀ y: M_r-orthonormal.
    Some(r * (l_inv.transpose() * y))
}

/// The largest ‖H⁻¹g‖∞ a converged point may leave, per f_ref/m_ref
/// ([`Solver::check_coordinates`]); at a true equilibrium it is of the order of the
/// residual tolerance, 10⁻¹⁰.
const FALSE_EQUILIBRIUM: f64 = 1e-6;

/// ... unless H does not amplify g: ‖H⁻¹g‖∞ at most this times ‖g‖∞/m_ref is a
/// well-conditioned H (a scene that starts at its equilibrium has f_ref = ‖g‖∞, both
/// round-off, and passes by this).
const AMPLIFICATION: f64 = 1e3;

impl Solver<'_> {
    /// After a solve: the drift from q₀ along the neutral motions, if there are any, taken back
    /// and the point polished by the regularised Newton (`crate::neutral`); kept as it was when
    /// either fails. A scene without neutral motions is left as solved, bit for bit.
    pub(super) fn take_back_neutral_drift<F: Formulation + ?Sized>(
        &mut self,
        f: &mut F,
        q0: &DVector<f64>,
        q: &mut DVector<f64>,
        lambda: &mut DVector<f64>,
    ) -> Result<(), StaticError> {
        let (residual, phi) = (self.last_residual, self.last_phi);
        // A turn is neutral to first order only: repeated until the correction is rounding.
        for _ in 0..NEUTRAL_PASSES {
            let Some(mut pinned) = without_neutral_drift(f, self.t, q0, q, lambda, &self.held)
            else {
                break;
            };
            let correction = (&pinned - &*q).amax();
            self.regularise_for_polish(f, q);
            let mut multipliers = lambda.clone();
            if !matches!(
                self.level(f, &mut pinned, &mut multipliers, 1.0)?,
                Level::Converged
            ) {
                (self.last_residual, self.last_phi) = (residual, phi);
                break;
            }
            q.copy_from(&pinned);
            lambda.copy_from(&multipliers);
            if correction <= self.s.tol_q * q.amax().max(1.0) {
                break;
            }
        }
        Ok(())
    }

    /// The regularised tangent for the polish of [`Self::take_back_neutral_drift`], H being
    /// singular along the neutral motions (k_ref = α/10⁴ when α is the default, "Penalty").
    fn regularise_for_polish<F: Formulation + ?Sized>(&mut self, f: &mut F, q: &DVector<f64>) {
        if !self.mass0.is_empty() {
            return;
        }
        self.eval(f, q, REQ_FULL);
        self.mass0 = self.terms.mass.clone();
        let m_ref = (0..self.n)
            .map(|i| self.mass0[(i, i)].abs())
            .fold(0.0, f64::max);
        self.regularisation = REGULARISATION * 1e-4 * self.alpha / m_ref.max(f64::MIN_POSITIVE);
    }

    /// At the converged q: H = M + α_M Φ_qᵀΦ_q (α_M = the largest diagonal of M per unit of
    /// Φ_qᵀΦ_q; held coordinates as the identity) must be regular, else the coordinates are
    /// singular there ([`StaticError::CoordinateSingularity`]); and the residual g must not
    /// accelerate the bodies: a = H⁻¹g at most [`FALSE_EQUILIBRIUM`] f_ref/m_ref, or at most
    /// [`AMPLIFICATION`] ‖g‖∞/m_ref (H well-conditioned along g). Near a
    /// coordinate singularity H is regular but ill-conditioned, and a small g in the
    /// coordinates can be a finite force on the bodies ([`StaticError::NearlySingular`]).
    pub(super) fn check_coordinates<F: Formulation + ?Sized>(
        &mut self,
        f: &mut F,
        q: &DVector<f64>,
        lambda: &DVector<f64>,
    ) -> Result<(), StaticError> {
        self.eval(f, q, REQ_FULL);
        let n = self.n;
        let m_ref = (0..n)
            .map(|i| self.terms.mass[(i, i)].abs())
            .fold(0.0, f64::max);
        let phi_q = &self.terms.phi_q;
        let c_ref = (0..n)
            .map(|j| phi_q.column(j).norm_squared())
            .fold(0.0, f64::max);
        self.h.copy_from(&self.terms.mass);
        if c_ref > 0.0 {
            self.h.gemm_tr(m_ref / c_ref, phi_q, phi_q, 1.0);
        }
        for j in 0..n {
            if self.held[j] {
                self.h.row_mut(j).fill(0.0);
                self.h.column_mut(j).fill(0.0);
                self.h[(j, j)] = 1.0;
            }
        }
        if let Err(e) = self.lu.factor(&self.h) {
            return Err(StaticError::CoordinateSingularity {
                pivot_ratio: e.pivot_ratio,
            });
        }
        self.residual(lambda, 1.0, true);
        let residual = self.g_try.amax();
        self.lu.solve_in_place(&mut self.g_try);
        let (acceleration, scale) = (self.g_try.amax(), self.f_ref / m_ref);
        if acceleration > FALSE_EQUILIBRIUM * scale
            && acceleration > AMPLIFICATION * residual / m_ref
        {
            return Err(StaticError::NearlySingular {
                acceleration,
                scale,
            });
        }
        Ok(())
    }
}
