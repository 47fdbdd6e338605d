//! Sparse symmetric matrices (sprs) handed to faer: checks, products, the Cholesky
//! factorisation of a shifted pencil K − σM, and Matrix Market output.
//!
//! The matrices are `sprs::CsMat<f64>` in **full symmetric storage** (both triangles). For a
//! symmetric matrix the CSR and CSC arrays are the same, so either storage is read as CSC.
//!
//! [`ShiftedCholesky`] factorises A = K − σM = L Lᵀ (up to a fill-reducing permutation) with
//! faer's sparse Cholesky: a symbolic analysis of the lower triangle's pattern behind an
//! approximate minimum degree ordering (AMD; Amestoy, Davis & Duff, SIAM J. Matrix Anal.
//! Appl. 17, 1996), then a supernodal or simplicial numeric factorisation as faer's flop
//! ratio picks (supernodal for 3D solids). Everything runs on one thread (`Par::Seq`), so
//! results are bitwise reproducible.

use std::io::Write;
use std::path::Path;
use std::time::{Duration, Instant};

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltError, LltParams};
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side, Spec};
use sprs::CsMat;

use crate::error::FeError;

/// Column pointers, row indices and values of a square symmetric matrix read as CSC.
pub struct Columns<'a> {
    /// Column pointers into `row_idx` and `values`, n + 1 of them.
    pub col_ptr: &'a [usize],
    /// Row indices, sorted within each column.
    pub row_idx: &'a [usize],
    /// Values, aligned with `row_idx`.
    pub values: &'a [f64],
}

impl<'a> Columns<'a> {
    /// The arrays of `a` (CSC or CSR: the same for a symmetric matrix).
    pub fn of(a: &'a CsMat<f64>) -> Self {
        Columns {
            col_ptr: a.indptr().into_raw_storage(),
            row_idx: a.indices(),
            values: a.data(),
        }
    }

    /// Entries of column `j`: (row, value).
    pub fn column(&self, j: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.col_ptr[j]..self.col_ptr[j + 1];
        self.row_idx[range.clone()]
            .iter()
            .copied()
            .zip(self.values[range].iter().copied())
    }

    /// Entry (i, j), zero outside the pattern.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let range = self.col_ptr[j]..self.col_ptr[j + 1];
        match self.row_idx[range.clone()].binary_search(&i) {
            Ok(k) => self.values[range.start + k],
            Err(_) => 0.0,
        }
    }
}

/// Check that `a` is square of order `n`, its values finite and it is symmetric: every
/// entry (i, j) matches (j, i) to 10⁻¹² of the larger magnitude. `what` names the matrix.
pub fn check_symmetric(a: &CsMat<f64>, n: usize, what: &str) -> Result<(), FeError> {
    if a.rows() != n || a.cols() != n {
        return Err(FeError::Dimension {
            what: what.to_string(),
            detail: format!("{} is {}x{}, expected {n}x{n}", what, a.rows(), a.cols()),
        });
    }
    let cols = Columns::of(a);
    for j in 0..n {
        for (i, v) in cols.column(j) {
            if !v.is_finite() {
                return Err(FeError::NotSymmetric {
                    what: what.to_string(),
                    row: i,
                    col: j,
                    detail: format!("entry {v} is not finite"),
                });
            }
            if i > j {
                let mirror = cols.get(j, i);
                if (v - mirror).abs() > 1e-12 * v.abs().max(mirror.abs()) {
                    return Err(FeError::NotSymmetric {
                        what: what.to_string(),
                        row: i,
                        col: j,
                        detail: format!("({i}, {j}) = {v:e} but ({j}, {i}) = {mirror:e}"),
                    });
                }
            }
        }
    }
    Ok(())
}

/// y = A x for a symmetric A (each y_j gathered from column j, so the writes are
/// sequential and the sum order fixed).
pub fn symmetric_matvec(a: &Columns<'_>, x: &[f64], y: &mut [f64]) {
    for (j, yj) in y.iter_mut().enumerate() {
        *yj = a.column(j).map(|(i, v)| v * x[i]).sum();
    }
}

/// The Euclidean norm of a vector.
pub fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// Write the symmetric `a` as a Matrix Market `coordinate real symmetric` file: its lower
/// triangle (row ≥ column, 1-based), column by column, each value in Rust's shortest
/// round-trip decimal form, so that a reader gets the same bits.
pub fn write_matrix_market(path: &Path, a: &CsMat<f64>) -> Result<(), FeError> {
    let io_error = |source| FeError::Io {
        file: path.display().to_string(),
        source,
    };
    let file = std::fs::File::create(path).map_err(io_error)?;
    let mut out = std::io::BufWriter::new(file);
    write_lower_triangle(&mut out, a).map_err(io_error)
}

fn write_lower_triangle(out: &mut impl Write, a: &CsMat<f64>) -> std::io::Result<()> {
    let cols = Columns::of(a);
    let n = a.cols();
    let entries = (0..n)
        .map(|j| cols.column(j).filter(|&(i, _)| i >= j).count())
        .sum::<usize>();
    writeln!(out, "%%MatrixMarket matrix coordinate real symmetric")?;
    writeln!(out, "% written by flexmbd-fe (lower triangle)")?;
    writeln!(out, "{} {} {entries}", a.rows(), n)?;
    for j in 0..n {
        for (i, v) in cols.column(j).filter(|&(i, _)| i >= j) {
            writeln!(out, "{} {} {v:?}", i + 1, j + 1)?;
        }
    }
    out.flush()
}

/// Wall-clock time of the two phases of a sparse Cholesky factorisation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FactorTimes {
    /// AMD ordering, elimination tree, supernodes.
    pub symbolic: Duration,
    /// The numeric factorisation.
    pub numeric: Duration,
}

/// The Cholesky factorisation of A = K − σM (module docs).
pub struct ShiftedCholesky {
    n: usize,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    /// The shift σ.
    pub shift: f64,
    /// Time spent in the symbolic and numeric phases.
    pub times: FactorTimes,
}

impl ShiftedCholesky {
    /// Factorise K − σM for symmetric `k` and `m` of order n (checked by the caller with
    /// [`check_symmetric`]). Fails with [`FeError::ShiftedNotPositiveDefinite`] when a
    /// pivot is not positive.
    pub fn new(k: &CsMat<f64>, m: &CsMat<f64>, shift: f64) -> Result<Self, FeError> {
        let n = k.rows();
        let (col_ptr, row_idx, values) =
            shifted_lower_triangle(&Columns::of(k), &Columns::of(m), shift, n);
        let start = Instant::now();
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| FeError::Dimension {
            what: "symbolic Cholesky analysis of K - sigma M".to_string(),
            detail: format!("{e:?}"),
        })?;
        let symbolic_time = start.elapsed();
        let start = Instant::now();
        let mut l_values = vec![0.0; symbolic.len_val()];
        let mut scratch = MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Spec::default()),
        );
        let matrix = SparseColMatRef::new(pattern, &values);
        symbolic
            .factorize_numeric_llt(
                &mut l_values,
                matrix,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut scratch),
                Spec::<LltParams, f64>::default(),
            )
            .map_err(|e| match e {
                LltError::NonPositivePivot { index } => FeError::ShiftedNotPositiveDefinite {
                    shift,
                    pivot: index,
                },
            })?;
        let numeric = start.elapsed();
        Ok(ShiftedCholesky {
            n,
            symbolic,
            l_values,
            shift,
            times: FactorTimes {
                symbolic: symbolic_time,
                numeric,
            },
        })
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Entries of the factor L.
    pub fn factor_entries(&self) -> usize {
        self.symbolic.len_val()
    }

    /// The workspace [`ShiftedCholesky::solve_in_place`] needs for `columns` right-hand sides.
    pub fn solve_scratch(&self, columns: usize) -> MemBuffer {
        MemBuffer::new(StackReq::any_of(&[self
            .symbolic
            .solve_in_place_scratch::<f64>(columns, Par::Seq)]))
    }

    /// Overwrite the columns of `rhs` (n rows) with (K − σM)⁻¹ rhs.
    pub fn solve_in_place(&self, rhs: MatMut<'_, f64>, scratch: &mut MemBuffer) {
        LltRef::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(scratch),
        );
    }
}

/// The lower triangle (diagonal included) of K − σM in CSC: the union of both patterns,
/// column by column (both have sorted rows).
fn shifted_lower_triangle(
    k: &Columns<'_>,
    m: &Columns<'_>,
    shift: f64,
    n: usize,
) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::new();
    let mut values = Vec::new();
    for j in 0..n {
        let mut a = k.column(j).filter(|&(i, _)| i >= j).peekable();
        let mut b = m.column(j).filter(|&(i, _)| i >= j).peekable();
        loop {
            let (i, v) = match (a.peek().copied(), b.peek().copied()) {
                (None, None) => break,
                (Some((i, kv)), Some((l, mv))) if i == l => {
                    a.next();
                    b.next();
                    (i, kv - shift * mv)
                }
                (Some((i, kv)), Some((l, _))) if i < l => {
                    a.next();
                    (i, kv)
                }
                (Some((i, kv)), None) => {
                    a.next();
                    (i, kv)
                }
                (_, Some((l, mv))) => {
                    b.next();
                    (l, -shift * mv)
                }
            };
            row_idx.push(i);
            values.push(v);
        }
        col_ptr.push(row_idx.len());
    }
    (col_ptr, row_idx, values)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sprs::TriMat;

    fn tridiagonal(n: usize, diag: f64, off: f64) -> CsMat<f64> {
        let mut t = TriMat::new((n, n));
        for i in 0..n {
            t.add_triplet(i, i, diag);
            if i + 1 < n {
                t.add_triplet(i, i + 1, off);
                t.add_triplet(i + 1, i, off);
            }
        }
        t.to_csc()
    }

    #[test]
    fn solves_a_shifted_system() {
        let n = 50;
        let k = tridiagonal(n, 2.0, -1.0);
        let m = tridiagonal(n, 4.0, 1.0);
        let sigma = -0.5;
        let chol = ShiftedCholesky::new(&k, &m, sigma).unwrap();
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        let (mut kx, mut mx) = (vec![0.0; n], vec![0.0; n]);
        symmetric_matvec(&Columns::of(&k), &x, &mut kx);
        symmetric_matvec(&Columns::of(&m), &x, &mut mx);
        let mut b: Vec<f64> = kx.iter().zip(&mx).map(|(a, b)| a - sigma * b).collect();
        let mut scratch = chol.solve_scratch(1);
        chol.solve_in_place(
            faer::MatMut::from_column_major_slice_mut(&mut b, n, 1),
            &mut scratch,
        );
        assert!(b.iter().zip(&x).all(|(a, b)| (a - b).abs() < 1e-12));
    }

    #[test]
    fn writes_the_lower_triangle_in_matrix_market_form() {
        let a = tridiagonal(3, 0.1 + 0.2, -1.0 / 3.0);
        let mut text = Vec::new();
        write_lower_triangle(&mut text, &a).unwrap();
        let text = String::from_utf8(text).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "%%MatrixMarket matrix coordinate real symmetric");
        assert_eq!(lines[2], "3 3 5");
        assert_eq!(lines[3], "1 1 0.30000000000000004");
        assert_eq!(lines[4], "2 1 -0.3333333333333333");
        assert_eq!(lines.len(), 8);
    }

    #[test]
    fn refuses_an_asymmetric_matrix_and_an_indefinite_pencil() {
        let mut t = TriMat::new((3, 3));
        t.add_triplet(0, 0, 1.0);
        t.add_triplet(1, 0, 2.0);
        t.add_triplet(0, 1, 2.5);
        t.add_triplet(2, 2, 1.0);
        let a: CsMat<f64> = t.to_csc();
        assert!(matches!(
            check_symmetric(&a, 3, "K"),
            Err(FeError::NotSymmetric { row: 1, col: 0, .. })
        ));
        let k = tridiagonal(4, -1.0, 0.0);
        let m = tridiagonal(4, 1.0, 0.0);
        assert!(matches!(
            ShiftedCholesky::new(&k, &m, -0.5),
            Err(FeError::ShiftedNotPositiveDefinite { .. })
        ));
    }
}
