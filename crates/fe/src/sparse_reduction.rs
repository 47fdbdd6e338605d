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

use nalgebra::{DMatrix, DVector};
use sprs::{CsMat, TriMat};

use crate::assembly::DofSets;
use crate::craig_bampton::{InteriorBasis, InteriorOperator, Reduction, check_reduced_stiffness};
use crate::error::FeError;
use crate::sparse::{Columns, ShiftedCholesky, symmetric_matvec};
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
    let i = &sets.i;
    if n_d > i.len() {
        return Err(FeError::TooManyModes {
            requested: n_d,
            available: i.len(),
        });
    }
    let parts = Parts::new(k, m, sets, name, frame, !sets.b.is_empty())?;
    let pairs = lowest_interior_modes(
        &parts.kii,
        &parts.mii,
        n_d,
        tol,
        shift,
        i,
        &parts.singular(),
    )?;
    parts.finish(k, m, &pairs.vectors, pairs.omega_sq)
}

/// The `n_d` lowest modes of (K_ii, M_ii) to the backward error `tol` (shift-invert
/// Lanczos with `shift`, None: its default), a pivot failure or an ω² ≈ 0 refused through
/// `singular` as a mechanism; `interior` maps interior indices to DOFs in the messages.
pub(crate) fn lowest_interior_modes(
    kii: &CsMat<f64>,
    mii: &CsMat<f64>,
    n_d: usize,
    tol: f64,
    shift: Option<f64>,
    interior: &[usize],
    singular: &dyn Fn(String) -> FeError,
) -> Result<crate::modal::Eigenpairs, FeError> {
    let options = SparseEigenOptions {
        tol,
        shift,
        ..SparseEigenOptions::default()
    };
    let pairs = lowest_modes(kii, mii, n_d, &options).map_err(|e| match e {
        FeError::ShiftedNotPositiveDefinite { pivot, .. } => singular(format!(
            "Cholesky pivot of interior DOF {} is not positive",
            interior.get(pivot).copied().unwrap_or(pivot)
        )),
        other => other,
    })?;
    if let Some(&lowest) = pairs.omega_sq.first()
        && lowest <= 1e-12 * mean_diagonal_ratio(kii, mii)
    {
        return Err(singular(format!(
            "the lowest fixed-interface mode has ω² = {lowest:e}, at most 1e-12 of the mean \
             K_ii/M_ii: a mechanism, or a mesh too fine for double precision (the condition \
             number of a beam's K_ii grows as (length / element length)⁴: fewer elements)"
        )));
    }
    Ok(pairs)
}

/// Reduce the free-floating sparse (K, M) on `sets` with the static modes and the dynamic
/// basis `dynamic` builds on the sparse fixed-interface problem (not called when there are
/// no interior DOFs): the sparse counterpart of
/// [`crate::craig_bampton::reduce_with_basis`].
pub fn reduce_sparse_with_basis(
    k: &CsMat<f64>,
    m: &CsMat<f64>,
    sets: &DofSets,
    name: &str,
    frame: &str,
    dynamic: impl FnOnce(&SparseInteriorProblem) -> Result<InteriorBasis, FeError>,
) -> Result<Reduction, FeError> {
    let parts = Parts::new(k, m, sets, name, frame, true)?;
    let basis = match &parts.chol {
        Some(chol) => dynamic(&SparseInteriorProblem {
            kii: &parts.kii,
            mii: &parts.mii,
            kii_chol: chol,
            x_static: &parts.x_static,
            name,
        })?,
        None => InteriorBasis {
            vectors: DMatrix::zeros(0, 0),
            omega_sq: Vec::new(),
        },
    };
    parts.finish(k, m, &basis.vectors, basis.omega_sq)
}

/// The sparse fixed-interface problem a dynamic basis is built on: the interior blocks, the
/// factorised K_ii and the static modes (the sparse [`crate::craig_bampton::InteriorProblem`]).
pub struct SparseInteriorProblem<'a> {
    /// K_ii (n_i × n_i, sparse).
    pub kii: &'a CsMat<f64>,
    /// M_ii (n_i × n_i, sparse).
    pub mii: &'a CsMat<f64>,
    /// The Cholesky factorisation of K_ii (shift 0).
    pub kii_chol: &'a ShiftedCholesky,
    /// The static modes X_s (N × n_b).
    pub x_static: &'a DMatrix<f64>,
    /// The spec origin, for errors.
    pub name: &'a str,
}

impl InteriorOperator for SparseInteriorProblem<'_> {
    fn name(&self) -> &str {
        self.name
    }
    fn n_interior(&self) -> usize {
        self.kii.rows()
    }
    fn solve_block(&self, b: &DMatrix<f64>) -> DMatrix<f64> {
        let mut z = b.clone();
        let (rows, cols) = z.shape();
        let mut scratch = self.kii_chol.solve_scratch(cols);
        let view = faer::MatMut::from_column_major_slice_mut(z.as_mut_slice(), rows, cols);
        self.kii_chol.solve_in_place(view, &mut scratch);
        z
    }
    fn mass_times(&self, v: &DVector<f64>) -> DVector<f64> {
        let mut y = DVector::zeros(v.len());
        symmetric_matvec(&Columns::of(self.mii), v.as_slice(), y.as_mut_slice());
        y
    }
    fn stiffness_form(&self, v: &DMatrix<f64>) -> DMatrix<f64> {
        v.transpose() * sparse_times_dense(self.kii, v)
    }
    fn mass_form(&self, v: &DMatrix<f64>) -> DMatrix<f64> {
        v.transpose() * sparse_times_dense(self.mii, v)
    }
}

/// What both reductions share: the interior blocks, K_ii's factor (when asked for or
/// needed by static modes) and the mode matrix with its static modes filled in.
struct Parts<'a> {
    sets: &'a DofSets,
    name: &'a str,
    frame: &'a str,
    kii: CsMat<f64>,
    mii: CsMat<f64>,
    chol: Option<ShiftedCholesky>,
    x_static: DMatrix<f64>,
}

impl<'a> Parts<'a> {
    fn new(
        k: &CsMat<f64>,
        m: &CsMat<f64>,
        sets: &'a DofSets,
        name: &'a str,
        frame: &'a str,
        factorise: bool,
    ) -> Result<Self, FeError> {
        let (i, b) = (&sets.i, &sets.b);
        let mut parts = Parts {
            sets,
            name,
            frame,
            kii: submatrix(k, i),
            mii: submatrix(m, i),
            chol: None,
            x_static: DMatrix::zeros(k.rows(), b.len()),
        };
        let n_s = b.len();
        for (c, &row) in b.iter().enumerate() {
            parts.x_static[(row, c)] = 1.0;
        }
        if factorise && !i.is_empty() {
            let chol = ShiftedCholesky::new(&parts.kii, &parts.mii, 0.0).map_err(|e| match e {
                FeError::ShiftedNotPositiveDefinite { pivot, .. } => parts.singular()(format!(
                    "Cholesky pivot of interior DOF {} is not positive",
                    i.get(pivot).copied().unwrap_or(pivot)
                )),
                other => other,
            })?;
            if n_s > 0 {
                let mut rhs = -dense_block(k, i, b);
                let mut scratch = chol.solve_scratch(n_s);
                let view =
                    faer::MatMut::from_column_major_slice_mut(rhs.as_mut_slice(), i.len(), n_s);
                chol.solve_in_place(view, &mut scratch);
                for (a, &row) in i.iter().enumerate() {
                    for c in 0..n_s {
                        parts.x_static[(row, c)] = rhs[(a, c)];
                    }
                }
            }
            parts.chol = Some(chol);
        }
        Ok(parts)
    }

    fn singular(&self) -> impl Fn(String) -> FeError + use<'_> {
        |detail| FeError::SingularInterior {
            spec: self.name.to_string(),
            frame: self.frame.to_string(),
            detail,
        }
    }

    /// X = [X_s, the interior `vectors` on the i rows], M_ff, K_ff and the check of K_ff.
    fn finish(
        self,
        k: &CsMat<f64>,
        m: &CsMat<f64>,
        vectors: &DMatrix<f64>,
        omega_sq: Vec<f64>,
    ) -> Result<Reduction, FeError> {
        let (n_s, n_d) = (self.sets.b.len(), omega_sq.len());
        let mut x = DMatrix::zeros(k.rows(), n_s + n_d);
        x.columns_mut(0, n_s).copy_from(&self.x_static);
        for (a, &row) in self.sets.i.iter().enumerate() {
            for c in 0..n_d {
                x[(row, n_s + c)] = vectors[(a, c)];
            }
        }
        let m_ff = symmetrise(&(x.transpose() * sparse_times_dense(m, &x)));
        let k_ff = symmetrise(&(x.transpose() * sparse_times_dense(k, &x)));
        check_reduced_stiffness(&k_ff, &m_ff, self.name, self.frame)?;
        Ok(Reduction {
            sets: self.sets.clone(),
            x,
            m_ff,
            k_ff,
            omega_sq,
        })
    }
}
