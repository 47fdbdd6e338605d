//! Craig–Bampton on sparse K and M (docs/methods.md §1.3–§1.4), for models too large for the
//! dense reduction of [`crate::craig_bampton`]: the same sets and the same modes,
//!
//! - static modes X_s = [𝟙_bb; −K_ii⁻¹ K_ib] by one sparse Cholesky of K_ii and n_b solves;
//! - the n_d lowest fixed-interface modes of (K_ii, M_ii) by shift-invert Lanczos
//!   ([`crate::sparse_eigen`], its default shift);
//! - M_ff = XᵀMX, K_ff = XᵀKX from sparse products with the N × n mode matrix,
//!
//! and the same refusals: K_ii singular (a pivot fails, or a fixed-interface mode at ω² ≈ 0,
//! a mechanism), K_ff not positive definite. No dense matrix larger than N × n is formed.

use nalgebra::DMatrix;
use sprs::{CsMat, TriMat};

use crate::assembly::DofSets;
use crate::craig_bampton::{Reduction, check_reduced_stiffness};
use crate::error::FeError;
use crate::sparse::ShiftedCholesky;
use crate::sparse_eigen::{SparseEigenOptions, lowest_modes};

/// The eigen-solver's bound on the backward error of each fixed-interface mode of a beam
/// reduced here (`sparse_eigen`'s module docs; its default).
pub const BEAM_EIGEN_TOL: f64 = 1e-12;

/// A (sparse) times X (dense).
pub fn sparse_times_dense(a: &CsMat<f64>, x: &DMatrix<f64>) -> DMatrix<f64> {
    let mut y = DMatrix::zeros(a.rows(), x.ncols());
    for (value, (i, j)) in a.iter() {
        for c in 0..x.ncols() {
            y[(i, c)] += value * x[(j, c)];
        }
    }
    y
}

/// (A + Aᵀ)/2 of a square dense matrix.
pub fn symmetrise(a: &DMatrix<f64>) -> DMatrix<f64> {
    (a + a.transpose()) * 0.5
}

/// The rows and columns `keep` (ascending) of A, CSC.
pub fn submatrix(a: &CsMat<f64>, keep: &[usize]) -> CsMat<f64> {
    let mut new_index = vec![usize::MAX; a.rows()];
    for (k, &i) in keep.iter().enumerate() {
        new_index[i] = k;
    }
    let mut t = TriMat::new((keep.len(), keep.len()));
    for (value, (i, j)) in a.iter() {
        let (ni, nj) = (new_index[i], new_index[j]);
        if ni != usize::MAX && nj != usize::MAX {
            t.add_triplet(ni, nj, *value);
        }
    }
    t.to_csc()
}

/// The block of rows `rows` and columns `cols` of A, dense.
fn dense_block(a: &CsMat<f64>, rows: &[usize], cols: &[usize]) -> DMatrix<f64> {
    let index = |list: &[usize], n: usize| {
        let mut at = vec![usize::MAX; n];
        for (k, &i) in list.iter().enumerate() {
            at[i] = k;
        }
        at
    };
    let (row_at, col_at) = (index(rows, a.rows()), index(cols, a.cols()));
    let mut out = DMatrix::zeros(rows.len(), cols.len());
    for (value, (i, j)) in a.iter() {
        if row_at[i] != usize::MAX && col_at[j] != usize::MAX {
            out[(row_at[i], col_at[j])] += value;
        }
    }
    out
}

/// mean_i K_ii / M_ii: the scale of ω² on the mesh (an element's own frequency squared).
fn mean_diagonal_ratio(k: &CsMat<f64>, m: &CsMat<f64>) -> f64 {
    let diagonal = |a: &CsMat<f64>| {
        let mut d = vec![0.0; a.rows()];
        for (v, (i, j)) in a.iter() {
            if i == j {
                d[i] += v;
            }
        }
        d
    };
    let (dk, dm) = (diagonal(k), diagonal(m));
    let ratios: Vec<f64> = dk
        .iter()
        .zip(&dm)
        .filter(|(_, m)| **m > 0.0)
        .map(|(k, m)| k / m)
        .collect();
    ratios.iter().sum::<f64>() / ratios.len().max(1) as f64
}

/// Reduce the free-floating sparse (K, M) on `sets`, keeping `n_d` fixed-interface modes
/// found to the backward error `tol` with the eigen-solver's `shift` (None: its default).
/// `name` and `frame` name the model in refusals, as for
/// [`crate::craig_bampton::reduce_matrices`].
#[allow(clippy::too_many_arguments)]
pub fn reduce_sparse(
    k: &CsMat<f64>,
    m: &CsMat<f64>,
    sets: &DofSets,
    n_d: usize,
    tol: f64,
    shift: Option<f64>,
    name: &str,
    frame: &str,
) -> Result<Reduction, FeError> {
    let (i, b) = (&sets.i, &sets.b);
    if n_d > i.len() {
        return Err(FeError::TooManyModes {
            requested: n_d,
            available: i.len(),
        });
    }
    let singular = |detail: String| FeError::SingularInterior {
        spec: name.to_string(),
        frame: frame.to_string(),
        detail,
    };
    let kii = submatrix(k, i);
    let mii = submatrix(m, i);
    let n = k.rows();
    let n_s = b.len();
    let mut x = DMatrix::zeros(n, n_s + n_d);
    for (c, &row) in b.iter().enumerate() {
        x[(row, c)] = 1.0;
    }
    if n_s > 0 && !i.is_empty() {
        let chol = ShiftedCholesky::new(&kii, &mii, 0.0).map_err(|e| match e {
            FeError::ShiftedNotPositiveDefinite { pivot, .. } => singular(format!(
                "Cholesky pivot of interior DOF {} is not positive",
                i.get(pivot).copied().unwrap_or(pivot)
            )),
            other => other,
        })?;
        let mut rhs = -dense_block(k, i, b);
        let mut scratch = chol.solve_scratch(n_s);
        let view = faer::MatMut::from_column_major_slice_mut(rhs.as_mut_slice(), i.len(), n_s);
        chol.solve_in_place(view, &mut scratch);
        for (a, &row) in i.iter().enumerate() {
            for c in 0..n_s {
                x[(row, c)] = rhs[(a, c)];
            }
        }
    }
    let options = SparseEigenOptions {
        tol,
        shift,
        ..SparseEigenOptions::default()
    };
    let pairs = lowest_modes(&kii, &mii, n_d, &options).map_err(|e| match e {
        FeError::ShiftedNotPositiveDefinite { pivot, .. } => singular(format!(
            "Cholesky pivot of interior DOF {} is not positive",
            i.get(pivot).copied().unwrap_or(pivot)
        )),
        other => other,
    })?;
    if let Some(&lowest) = pairs.omega_sq.first()
        && lowest <= 1e-12 * mean_diagonal_ratio(&kii, &mii)
    {
        return Err(singular(format!(
            "the lowest fixed-interface mode has ω² = {lowest:e}, at most 1e-12 of the mean \
             K_ii/M_ii: a mechanism, or a mesh too fine for double precision (the condition \
             number of a beam's K_ii grows as (length / element length)⁴: fewer elements)"
        )));
    }
    for (a, &row) in i.iter().enumerate() {
        for c in 0..n_d {
            x[(row, n_s + c)] = pairs.vectors[(a, c)];
        }
    }
    let m_ff = symmetrise(&(x.transpose() * sparse_times_dense(m, &x)));
    let k_ff = symmetrise(&(x.transpose() * sparse_times_dense(k, &x)));
    check_reduced_stiffness(&k_ff, &m_ff, name, frame)?;
    Ok(Reduction {
        sets: sets.clone(),
        x,
        m_ff,
        k_ff,
        omega_sq: pairs.omega_sq,
    })
}
