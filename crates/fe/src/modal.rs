//! Dense symmetric generalized eigenproblem K x = ω² M x (docs/methods.md §1.3 step 3).
//!
//! Method (faer): Cholesky M = L Lᵀ, the standard symmetric problem
//! A = L⁻¹ K L⁻ᵀ = U Λ Uᵀ, and x = L⁻ᵀ u. The vectors are then mass-normalised
//! (xᵀ M x = uᵀ u = 1) by construction, the eigenvalues ω² come ascending, and
//! each vector's sign is fixed so that its largest-magnitude component
//! (the first one on a tie) is positive: runs are bit-identical.
//!
//! Works on a free-free model (rigid modes give ω² ≈ 0, possibly slightly
//! negative by round-off) or on a constrained one ([`constrained_eigen`]).
//!
//! The mass factor fails on fine beam meshes: M's rotary entries (ρI h) make it so ill
//! conditioned that A's largest eigenvalues (~E/ρh²) swamp its smallest, and the lowest ω²
//! come out wrong (a 1 m, 10 mm steel cantilever of 50 elements: 10.67 Hz for 8.355 Hz).
//! So the lowest [`CHECKED_PAIRS`] pairs are checked by their normwise backward error
//! ‖K x − ω² M x‖ / ((‖K‖ + |ω²| ‖M‖) ‖x‖) (∞-norms; Higham & Higham 1998), and when one
//! exceeds [`BACKWARD_ERROR_TOL`] the problem is solved again in shift-invert form: the
//! Cholesky factor C = K − σM = L Lᵀ (σ = 0 if K is positive definite, else a small
//! negative shift), the standard problem L⁻¹ M L⁻ᵀ u = μ u, ω² = σ + 1/μ, x = L⁻ᵀ u / √μ,
//! whose lowest ω² are its largest μ and keep their relative accuracy. Well-conditioned
//! problems keep the first solution, bit for bit.

use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, Par, Side};
use nalgebra::DMatrix;

use crate::assembly::submatrix;
use crate::error::FeError;

/// Eigenpairs of K x = ω² M x.
#[derive(Clone, Debug, PartialEq)]
pub struct Eigenpairs {
    /// ω² (rad²/s²), ascending.
    pub omega_sq: Vec<f64>,
    /// Mass-normalised eigenvectors, one per column, in the order of `omega_sq`.
    pub vectors: DMatrix<f64>,
}

impl Eigenpairs {
    /// Natural frequencies in Hz, √max(ω², 0) / 2π.
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.omega_sq
            .iter()
            .map(|&l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect()
    }

    /// Keep only the first `n` pairs.
    pub fn truncate(mut self, n: usize) -> Self {
        self.omega_sq.truncate(n);
        self.vectors = self.vectors.columns(0, n).into_owned();
        self
    }
}

fn to_faer(a: &DMatrix<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

/// Solve K x = ω² M x for symmetric K and symmetric positive definite M.
/// `what` names the problem in errors.
pub fn generalized_eigen(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    what: &str,
) -> Result<Eigenpairs, FeError> {
    let n = k.nrows();
    if k.ncols() != n || m.nrows() != n || m.ncols() != n {
        return Err(FeError::Dimension {
            what: what.to_string(),
            detail: format!(
                "K is {}x{}, M is {}x{}",
                k.nrows(),
                k.ncols(),
                m.nrows(),
                m.ncols()
            ),
        });
    }
    if n == 0 {
        return Ok(Eigenpairs {
            omega_sq: Vec::new(),
            vectors: DMatrix::zeros(0, 0),
        });
    }
    let pairs = by_mass_factor(k, m, what)?;
    if lowest_pairs_hold(k, m, &pairs) {
        return Ok(pairs);
    }
    Ok(by_shifted_stiffness_factor(k, m).unwrap_or(pairs))
}

/// The pairs whose backward error is checked: the lowest, where the mass factor's error
/// falls (an absolute error of ε times the largest ω²).
pub const CHECKED_PAIRS: usize = 32;

/// Largest backward error accepted from the mass-factor solution (well-conditioned
/// problems give ~1e-15).
pub const BACKWARD_ERROR_TOL: f64 = 1e-10;

/// Largest absolute row sum.
fn norm_inf(a: &DMatrix<f64>) -> f64 {
    a.row_iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Whether each of the lowest [`CHECKED_PAIRS`] pairs has a backward error of at most
/// [`BACKWARD_ERROR_TOL`].
fn lowest_pairs_hold(k: &DMatrix<f64>, m: &DMatrix<f64>, pairs: &Eigenpairs) -> bool {
    let n = pairs.omega_sq.len().min(CHECKED_PAIRS);
    let x = pairs.vectors.columns(0, n);
    let (kx, mx) = (k * x, m * x);
    let (nk, nm) = (norm_inf(k), norm_inf(m));
    (0..n).all(|j| {
        let w = pairs.omega_sq[j];
        let r = (kx.column(j) - w * mx.column(j)).amax();
        let scale = (nk + w.abs() * nm) * x.column(j).amax();
        r <= BACKWARD_ERROR_TOL * scale
    })
}

/// K x = ω² M x in shift-invert form (see the module documentation); `None` when neither
/// K nor K − σM has a Cholesky factor.
fn by_shifted_stiffness_factor(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Option<Eigenpairs> {
    let n = k.nrows();
    let factor = |sigma: f64| {
        to_faer(&(k - sigma * m))
            .llt(Side::Lower)
            .ok()
            .map(|llt| (sigma, llt))
    };
    // A shift far below the element frequencies, as the sparse solver's default
    // (crate::sparse_eigen::default_shift), when K is singular (rigid modes, mechanisms).
    let ratio = (0..n)
        .filter(|&i| m[(i, i)] > 0.0)
        .map(|i| k[(i, i)] / m[(i, i)])
        .sum::<f64>()
        / n as f64;
    let (sigma, llt) = factor(0.0).or_else(|| factor(-1e-5 * ratio.abs()))?;
    let l = llt.L();
    let mut y = to_faer(m);
    solve_lower_triangular_in_place(l, y.as_mut(), Par::Seq);
    let mut a = y.transpose().to_owned();
    solve_lower_triangular_in_place(l, a.as_mut(), Par::Seq);
    let a = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let eig = a.self_adjoint_eigen(Side::Lower).ok()?;
    let mu = eig.S().column_vector();
    let mut x = eig.U().to_owned();
    solve_upper_triangular_in_place(l.transpose(), x.as_mut(), Par::Seq);
    // μ ascending, so ω² = σ + 1/μ descending: take the columns from the last.
    let order: Vec<usize> = (0..n).rev().collect();
    if order.iter().any(|&c| mu[c].is_nan() || mu[c] <= 0.0) {
        return None;
    }
    let omega_sq: Vec<f64> = order.iter().map(|&c| sigma + 1.0 / mu[c]).collect();
    let mut vectors = DMatrix::from_fn(n, n, |i, j| {
        let c = order[j];
        x[(i, c)] / mu[c].sqrt()
    });
    fix_signs(&mut vectors);
    Some(Eigenpairs { omega_sq, vectors })
}

/// K x = ω² M x by the Cholesky factor of M (see the module documentation).
fn by_mass_factor(k: &DMatrix<f64>, m: &DMatrix<f64>, what: &str) -> Result<Eigenpairs, FeError> {
    let n = k.nrows();
    let mf = to_faer(m);
    let llt = mf
        .llt(Side::Lower)
        .map_err(|e| FeError::NotPositiveDefinite {
            what: format!("mass matrix of {what}"),
            pivot: match e {
                faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => index,
            },
        })?;
    let l = llt.L();
    // Y = L⁻¹ K, A = L⁻¹ Yᵀ = L⁻¹ K L⁻ᵀ.
    let mut y = to_faer(k);
    solve_lower_triangular_in_place(l, y.as_mut(), Par::Seq);
    let mut a = y.transpose().to_owned();
    solve_lower_triangular_in_place(l, a.as_mut(), Par::Seq);
    let a = Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let eig = a
        .self_adjoint_eigen(Side::Lower)
        .map_err(|_| FeError::EigenNoConvergence {
            what: what.to_string(),
        })?;
    let s = eig.S().column_vector();
    let mut x = eig.U().to_owned();
    // x = L⁻ᵀ u.
    solve_upper_triangular_in_place(l.transpose(), x.as_mut(), Par::Seq);
    let mut vectors = DMatrix::from_fn(n, n, |i, j| x[(i, j)]);
    let omega_sq: Vec<f64> = (0..n).map(|i| s[i]).collect();
    fix_signs(&mut vectors);
    Ok(Eigenpairs { omega_sq, vectors })
}

/// Make the largest-magnitude component of each column positive (first on a tie).
pub fn fix_signs(v: &mut DMatrix<f64>) {
    for mut c in v.column_iter_mut() {
        let mut best = 0.0_f64;
        let mut sign = 1.0;
        for &x in c.iter() {
            if x.abs() > best {
                best = x.abs();
                sign = x.signum();
            }
        }
        if sign < 0.0 {
            c.neg_mut();
        }
    }
}

/// Eigenpairs with the DOFs in `fixed` held at zero (e.g. supports); the
/// vectors are expanded back to all N DOFs with zeros on `fixed`.
pub fn constrained_eigen(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    fixed: &[usize],
    what: &str,
) -> Result<Eigenpairs, FeError> {
    let n = k.nrows();
    let mut is_fixed = vec![false; n];
    for &f in fixed {
        if f >= n {
            return Err(FeError::Dimension {
                what: what.to_string(),
                detail: format!("fixed DOF {f} >= N = {n}"),
            });
        }
        is_fixed[f] = true;
    }
    let free: Vec<usize> = (0..n).filter(|&i| !is_fixed[i]).collect();
    let kr = submatrix(k, &free, &free);
    let mr = submatrix(m, &free, &free);
    let e = generalized_eigen(&kr, &mr, what)?;
    let mut vectors = DMatrix::zeros(n, free.len());
    for (a, &i) in free.iter().enumerate() {
        vectors.row_mut(i).copy_from(&e.vectors.row(a));
    }
    Ok(Eigenpairs {
        omega_sq: e.omega_sq,
        vectors,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_dof_spring_mass() {
        // m1 = 1, m2 = 2; springs k = 3 (ground–1) and 2 (1–2).
        let k = DMatrix::from_row_slice(2, 2, &[5.0, -2.0, -2.0, 2.0]);
        let m = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 2.0]);
        let e = generalized_eigen(&k, &m, "2-dof").unwrap();
        // det(K − λM) = (5 − λ)(2 − 2λ) − 4 = 2λ² − 12λ + 6 → λ = 3 ∓ √6.
        let l1 = 3.0 - 6f64.sqrt();
        let l2 = 3.0 + 6f64.sqrt();
        assert!((e.omega_sq[0] - l1).abs() < 1e-13);
        assert!((e.omega_sq[1] - l2).abs() < 1e-13);
        let g = e.vectors.transpose() * &m * &e.vectors;
        assert!((g - DMatrix::identity(2, 2)).norm() < 1e-14);
        let again = generalized_eigen(&k, &m, "2-dof").unwrap();
        assert_eq!(e, again);
    }

    #[test]
    fn non_spd_mass_is_refused() {
        let k = DMatrix::identity(2, 2);
        let m = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, -1.0]);
        assert!(matches!(
            generalized_eigen(&k, &m, "x"),
            Err(FeError::NotPositiveDefinite { .. })
        ));
    }
}
