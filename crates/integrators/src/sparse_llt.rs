//! Sparse Cholesky LLᵀ of the leading matrix f_q of large systems (faer's supernodal or
//! simplicial kernels behind an AMD fill-reducing ordering), for the integrator's Newton
//! iterations and projections (docs/methods.md §5.2).
//!
//! The leading matrix is formed densely as before; only its factorisation changes. Its
//! structural non-zeros are those of M + h/2 C + h²/4 (K + Φ_qᵀ α Φ_q): in natural
//! coordinates a body's coordinates couple with its own and its joint partners', in
//! relative coordinates the coordinates of one branch of the tree (a vehicle's corners)
//! couple with the root's but not with each other's branches. The Cholesky factor of such
//! a matrix, ordered by minimum degree, holds a fraction of the n²/2 entries of a dense one,
//! and the work falls with it.
//!
//! The pattern is taken from the matrix itself: its non-zeros when the factorisation is set
//! up, grown (a new symbolic analysis, which allocates) whenever an entry outside it turns
//! non-zero later — a contact closing, a Jacobian entry that was zero by symmetry at the
//! start. Every factorisation checks the entries outside the pattern, so a factor is never
//! that of a truncated matrix. When the factor would be dense anyway
//! ([`SparseLlt::worthwhile`]) the caller keeps the dense kernels.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltParams;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Par, Side, Spec};
use nalgebra::{DMatrix, DVector};

/// The smallest system for which the sparse factorisation is considered: below it faer's
/// dense kernels win whatever the pattern (`benches/dense.rs`, group
/// `structured_against_dense`: 5.1 against 3.7 µs at n = 42 with a factor 46 % full).
pub const SPARSE_FROM: usize = 96;

/// The largest share of a dense factor's n(n+1)/2 entries at which the sparse
/// factorisation is used. `benches/dense.rs` (factorise + solve): at n = 118 and 33 % full
/// it took 33 µs against the dense 24 µs, at n = 230 and 17 % full 70 against 96 µs; on the
/// Iltis vehicle the factors are 16 % full in natural coordinates (n = 204, 280: the
/// sparse kernels faster) and 24 % in relative ones with 12 flexible bodies (n = 118: the
/// dense ones faster).
pub const MAX_FILL: f64 = 0.2;

/// A reusable sparse Cholesky factorisation of an n × n symmetric positive definite matrix
/// given densely (its lower triangle is read).
pub struct SparseLlt {
    n: usize,
    /// Column pointers and row indices of the lower-triangle pattern (CSC).
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// The pattern's values, gathered from the dense matrix.
    values: Vec<f64>,
    /// Column-major index in the dense matrix of each pattern entry, in CSC order.
    source: Vec<usize>,
    /// Column-major indices of the lower-triangle entries outside the pattern.
    outside: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    scratch: MemBuffer,
}

/// The sparse factorisation failed: the matrix is not (numerically) positive definite, or
/// the symbolic analysis could not be done.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SparseFailure;

impl SparseLlt {
    /// Set up for the pattern of `a`'s lower triangle (its non-zeros and the diagonal).
    pub fn new(a: &DMatrix<f64>) -> Result<Self, SparseFailure> {
        let n = a.nrows();
        let pattern: Vec<bool> = (0..n * n)
            .map(|k| k % n >= k / n && (a.as_slice()[k] != 0.0 || k % n == k / n))
            .collect();
        Self::with_pattern(n, &pattern)
    }

    /// Whether the factor is sparse enough to be worth it: at most [`MAX_FILL`] of a dense
    /// factor's entries.
    pub fn worthwhile(&self) -> bool {
        let dense = self.n * (self.n + 1) / 2;
        (self.symbolic.len_val() as f64) <= MAX_FILL * dense as f64
    }

    /// Entries of the Cholesky factor.
    pub fn factor_entries(&self) -> usize {
        self.symbolic.len_val()
    }

    /// The symbolic analysis and the workspace for the lower-triangle `pattern`
    /// (column-major n × n flags).
    fn with_pattern(n: usize, pattern: &[bool]) -> Result<Self, SparseFailure> {
        let (mut col_ptr, mut row_idx, mut source, mut outside) =
            (vec![0], Vec::new(), Vec::new(), Vec::new());
        for j in 0..n {
            for i in j..n {
                let k = i + j * n;
                if pattern[k] {
                    row_idx.push(i);
                    source.push(k);
                } else {
                    outside.push(k);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let symbolic = factorize_symbolic_cholesky(
            SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|_| SparseFailure)?;
        let scratch = MemBuffer::new(StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Spec::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]));
        Ok(SparseLlt {
            n,
            values: vec![0.0; row_idx.len()],
            l_values: vec![0.0; symbolic.len_val()],
            col_ptr,
            row_idx,
            source,
            outside,
            symbolic,
            scratch,
        })
    }

    /// Grow the pattern by the non-zeros of `a` outside it (allocates: a new analysis).
    fn grow(&mut self, a: &DMatrix<f64>) -> Result<(), SparseFailure> {
        let n = self.n;
        let mut pattern = vec![false; n * n];
        for &k in &self.source {
            pattern[k] = true;
        }
        for &k in &self.outside {
            pattern[k] = a.as_slice()[k] != 0.0;
        }
        *self = Self::with_pattern(n, &pattern)?;
        Ok(())
    }

    /// Factorise `a` (its lower triangle). The pattern grows first if `a` has non-zeros
    /// outside it.
    pub fn factor(&mut self, a: &DMatrix<f64>) -> Result<(), SparseFailure> {
        let dense = a.as_slice();
        if self.outside.iter().any(|&k| dense[k] != 0.0) {
            self.grow(a)?;
        }
        for (v, &k) in self.values.iter_mut().zip(&self.source) {
            *v = dense[k];
        }
        let n = self.n;
        let matrix = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx),
            &self.values,
        );
        self.symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                matrix,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut self.scratch),
                Spec::<LltParams, f64>::default(),
            )
            .map(|_| ())
            .map_err(|_| SparseFailure)
    }

    /// Solve A x = b in place with the last factorisation.
    pub fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        let n = self.n;
        let rhs = faer::MatMut::from_column_major_slice_mut(b.as_mut_slice(), n, 1);
        LltRef::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.scratch),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An arrow matrix like a vehicle's in relative coordinates: a dense root block coupled
    /// to `branches` dense blocks that do not couple with each other; SPD.
    fn arrow(root: usize, branches: usize, size: usize) -> DMatrix<f64> {
        let n = root + branches * size;
        let mut a = DMatrix::zeros(n, n);
        let coupled =
            |i: usize, j: usize| i < root || j < root || (i - root) / size == (j - root) / size;
        for j in 0..n {
            for i in 0..n {
                if coupled(i, j) {
                    a[(i, j)] = ((i * 7 + j * 7 + i * j) as f64 * 0.37).sin() / n as f64;
                }
            }
            a[(j, j)] += 2.0;
        }
        a
    }

    #[test]
    fn solves_an_arrow_system_as_the_dense_cholesky_does() {
        let a = arrow(6, 8, 28);
        let x = DVector::from_fn(a.nrows(), |i, _| (i as f64 * 0.3).cos());
        let mut b = &a * &x;
        let mut llt = SparseLlt::new(&a).unwrap();
        assert!(llt.worthwhile(), "{} entries", llt.factor_entries());
        llt.factor(&a).unwrap();
        llt.solve_in_place(&mut b);
        assert!((b - x).amax() < 1e-12);
    }

    /// An entry outside the set-up pattern (a contact closing) grows the pattern: the
    /// factor is that of the whole matrix, not of its truncation.
    #[test]
    fn an_entry_outside_the_pattern_grows_it() {
        let a = arrow(6, 4, 28);
        let mut llt = SparseLlt::new(&a).unwrap();
        let before = llt.factor_entries();
        let mut coupled = a.clone();
        let (i, j) = (6 + 28 + 3, 6 + 2 * 28 + 5);
        coupled[(i, j)] = 0.1;
        coupled[(j, i)] = 0.1;
        let x = DVector::from_fn(a.nrows(), |i, _| (i as f64 * 0.3).sin());
        let mut b = &coupled * &x;
        llt.factor(&coupled).unwrap();
        llt.solve_in_place(&mut b);
        assert!((b - x).amax() < 1e-12);
        assert!(llt.factor_entries() > before);
    }

    #[test]
    fn a_dense_matrix_is_not_worthwhile_and_an_indefinite_one_fails() {
        let a = arrow(40, 1, 60);
        assert!(!SparseLlt::new(&a).unwrap().worthwhile());
        let mut indefinite = arrow(6, 4, 28);
        indefinite[(50, 50)] = -5.0;
        assert!(
            SparseLlt::new(&indefinite)
                .unwrap()
                .factor(&indefinite)
                .is_err()
        );
    }
}
