//! Dense LU with partial pivoting and Cholesky, in place and allocation-free after set-up:
//! the leading matrix of a step is small (tens of coordinates) and dense. faer's
//! in-place kernels take their scratch from a buffer sized once (`*_scratch`); at most
//! [`SMALL`] coordinates plain unblocked loops are used instead, whose cost is the
//! arithmetic itself (faer's dispatch, views and recursion cost about 1 200 instructions
//! per factorisation and 1 500 per solve at n = 5, several times the arithmetic).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::{Par, Spec};
use nalgebra::{DMatrix, DVector};

/// Up to this many coordinates the factorisations run the unblocked loops of this module
/// instead of faer's kernels (measured crossover: see `benches/dense.rs`).
pub const SMALL: usize = 12;

/// Above [`SMALL`] and up to this many coordinates faer factorises (below it the unblocked
/// loops do) and the solves run `llt_solve_mirrored` on the factor with Lᵀ mirrored into
/// its upper triangle and 1 / L_jj kept (no division in the sweeps' dependency chain): two
/// column sweeps of n²/2 multiply–adds each, where faer's blocked triangular solves recurse
/// into matrix–vector products whose set-up costs more than the arithmetic at these sizes.
pub const MIRRORED_SOLVE: usize = 64;

/// A reusable LU factorisation of an n × n matrix.
pub struct DenseLu {
    n: usize,
    lu: DMatrix<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    scratch: MemBuffer,
    /// Unblocked kernels (n ≤ [`SMALL`]); `perm` then holds LAPACK-style row interchanges.
    small: bool,
}

/// The matrix could not be factorised: its pivots fell below the relative threshold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Singular {
    /// Smallest |pivot| / largest |pivot|.
    pub pivot_ratio: f64,
}

impl DenseLu {
    /// Storage for n × n matrices.
    pub fn new(n: usize) -> Self {
        let req = StackReq::any_of(&[
            factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Spec::default()),
            solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
        ]);
        DenseLu {
            n,
            lu: DMatrix::zeros(n, n),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            scratch: MemBuffer::new(req),
            small: n <= SMALL,
        }
    }

    /// Factorise a copy of `a`. Fails when a pivot is below 1e-14 of the largest.
    pub fn factor(&mut self, a: &DMatrix<f64>) -> Result<(), Singular> {
        self.lu.as_mut_slice().copy_from_slice(a.as_slice());
        let n = self.n;
        if self.small {
            lu_unblocked(self.lu.as_mut_slice(), n, &mut self.perm);
        } else {
            self.factor_faer();
        }
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for i in 0..n {
            let p = self.lu[(i, i)].abs();
            lo = lo.min(p);
            hi = hi.max(p);
        }
        if n > 0 && (!(lo.is_finite() && hi.is_finite()) || lo <= 1e-14 * hi || hi == 0.0) {
            return Err(Singular {
                pivot_ratio: if hi > 0.0 { lo / hi } else { 0.0 },
            });
        }
        Ok(())
    }

    fn factor_faer(&mut self) {
        let n = self.n;
        let mat = faer::MatMut::from_column_major_slice_mut(self.lu.as_mut_slice(), n, n);
        let stack = MemStack::new(&mut self.scratch);
        factor::lu_in_place(
            mat,
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            stack,
            Spec::default(),
        );
    }

    /// Solve A x = b in place (b ← x) with the last factorisation.
    pub fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        let n = self.n;
        if self.small {
            lu_solve_unblocked(self.lu.as_slice(), n, &self.perm, b.as_mut_slice());
            return;
        }
        let lu = faer::MatRef::from_column_major_slice(self.lu.as_slice(), n, n);
        let rhs = faer::MatMut::from_column_major_slice_mut(b.as_mut_slice(), n, 1);
        let perm = faer::perm::PermRef::new_checked(&self.perm, &self.perm_inv, n);
        let stack = MemStack::new(&mut self.scratch);
        solve::solve_in_place(lu, lu, perm, rhs, Par::Seq, stack);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_pivoting_system() {
        let a = DMatrix::from_row_slice(3, 3, &[0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0]);
        let x = DVector::from_vec(vec![1.0, -2.0, 0.5]);
        let mut b = &a * &x;
        let mut lu = DenseLu::new(3);
        lu.factor(&a).unwrap();
        lu.solve_in_place(&mut b);
        assert!((b - x).norm() < 1e-14);
    }

    #[test]
    fn refuses_a_singular_matrix() {
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 4.0]);
        assert!(DenseLu::new(2).factor(&a).is_err());
    }
}

/// A reusable Cholesky factorisation LLᵀ of a symmetric positive definite n × n matrix,
/// in place and allocation-free after set-up (faer's in-place kernel). About twice as
/// fast as the LU at the sizes of a step (`benches/dense.rs`).
pub struct DenseLlt {
    n: usize,
    l: DMatrix<f64>,
    scratch: MemBuffer,
    /// Unblocked kernels (n ≤ [`SMALL`]).
    small: bool,
    /// The factor mirrored, solved by column sweeps (n ≤ [`MIRRORED_SOLVE`]), and 1 / L_jj
    /// for them.
    mirrored: bool,
    inverse_diagonal: Vec<f64>,
}

/// The matrix is not (numerically) positive definite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NotPositiveDefinite;

impl DenseLlt {
    /// Storage for n × n matrices.
    pub fn new(n: usize) -> Self {
        use faer::linalg::cholesky::llt;
        let req = StackReq::any_of(&[
            llt::factor::cholesky_in_place_scratch::<f64>(n, Par::Seq, Spec::default()),
            llt::solve::solve_in_place_scratch::<f64>(n, 1, Par::Seq),
        ]);
        DenseLlt {
            n,
            l: DMatrix::zeros(n, n),
            scratch: MemBuffer::new(req),
            small: n <= SMALL,
            mirrored: n <= MIRRORED_SOLVE,
            inverse_diagonal: vec![0.0; n],
        }
    }

    /// Factorise a copy of `a` (its lower triangle is read).
    pub fn factor(&mut self, a: &DMatrix<f64>) -> Result<(), NotPositiveDefinite> {
        use faer::linalg::cholesky::llt;
        self.l.as_mut_slice().copy_from_slice(a.as_slice());
        let n = self.n;
        if self.small {
            llt_unblocked(self.l.as_mut_slice(), n)?;
        } else {
            let mat = faer::MatMut::from_column_major_slice_mut(self.l.as_mut_slice(), n, n);
            let stack = MemStack::new(&mut self.scratch);
            llt::factor::cholesky_in_place(
                mat,
                Default::default(),
                Par::Seq,
                stack,
                Spec::default(),
            )
            .map_err(|_| NotPositiveDefinite)?;
        }
        if self.mirrored {
            mirror_factor(self.l.as_mut_slice(), n, &mut self.inverse_diagonal);
        }
        Ok(())
    }

    /// Solve A x = b in place with the last factorisation.
    pub fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        use faer::linalg::cholesky::llt;
        let n = self.n;
        if self.mirrored {
            llt_solve_mirrored(
                self.l.as_slice(),
                &self.inverse_diagonal,
                n,
                b.as_mut_slice(),
            );
            return;
        }
        let l = faer::MatRef::from_column_major_slice(self.l.as_slice(), n, n);
        let rhs = faer::MatMut::from_column_major_slice_mut(b.as_mut_slice(), n, 1);
        let stack = MemStack::new(&mut self.scratch);
        llt::solve::solve_in_place(l, rhs, Par::Seq, stack);
    }

    /// The factor L of the last factorisation: column-major n × n, L in the lower triangle
    /// (the strict upper triangle holds whatever the input had there, or Lᵀ).
    pub fn factor_data(&self) -> &[f64] {
        self.l.as_slice()
    }

    /// Whether [`factor_data`](Self::factor_data) holds Lᵀ in its strict upper triangle
    /// (n ≤ [`MIRRORED_SOLVE`]).
    pub fn upper_holds_transpose(&self) -> bool {
        self.mirrored
    }

    /// L⁻¹ B in place for a column-major n × k matrix B (faer's blocked triangular solve).
    pub fn solve_lower_many_in_place(&self, b: &mut DMatrix<f64>) {
        let n = self.n;
        let k = b.ncols();
        let l = faer::MatRef::from_column_major_slice(self.l.as_slice(), n, n);
        let rhs = faer::MatMut::from_column_major_slice_mut(b.as_mut_slice(), n, k);
        faer::linalg::triangular_solve::solve_lower_triangular_in_place(l, rhs, Par::Seq);
    }
}

#[cfg(test)]
mod llt_tests {
    use super::*;

    #[test]
    fn solves_an_spd_system_and_refuses_an_indefinite_one() {
        let a = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0]);
        let x = DVector::from_vec(vec![1.0, -2.0, 0.5]);
        let mut b = &a * &x;
        let mut llt = DenseLlt::new(3);
        llt.factor(&a).unwrap();
        llt.solve_in_place(&mut b);
        assert!((b - x).norm() < 1e-14);
        let indefinite = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        assert!(
            llt.factor(&DMatrix::from_row_slice(
                3,
                3,
                &[1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0]
            ))
            .is_err()
        );
        assert!(DenseLlt::new(2).factor(&indefinite).is_err());
    }
}

/// Call `$f(args…, n)` with n a literal for n ≤ 8, so that the inlined loops are unrolled
/// and their bounds checks folded; the general loops otherwise.
macro_rules! sized {
    ($f:ident, $n:expr, $($arg:expr),*) => {
        match $n {
            1 => $f($($arg,)* 1),
            2 => $f($($arg,)* 2),
            3 => $f($($arg,)* 3),
            4 => $f($($arg,)* 4),
            5 => $f($($arg,)* 5),
            6 => $f($($arg,)* 6),
            7 => $f($($arg,)* 7),
            8 => $f($($arg,)* 8),
            n => $f($($arg,)* n),
        }
    };
}

fn lu_unblocked(a: &mut [f64], n: usize, piv: &mut [usize]) {
    sized!(lu_unblocked_n, n, a, piv)
}
fn lu_solve_unblocked(a: &[f64], n: usize, piv: &[usize], b: &mut [f64]) {
    sized!(lu_solve_unblocked_n, n, a, piv, b)
}
fn llt_unblocked(a: &mut [f64], n: usize) -> Result<(), NotPositiveDefinite> {
    sized!(llt_unblocked_n, n, a)
}

/// Right-looking LU with partial pivoting (LAPACK's getf2) of a column-major n × n slice:
/// the unit lower factor below the diagonal, U on and above it; `piv[k]` is the row
/// interchanged with row k at stage k. A zero pivot is left in place (the caller's pivot
/// check reports it).
#[inline(always)]
fn lu_unblocked_n(a: &mut [f64], piv: &mut [usize], n: usize) {
    let (a, piv) = (&mut a[..n * n], &mut piv[..n]);
    for k in 0..n {
        let col = &a[k * n..(k + 1) * n];
        let (mut p, mut big) = (k, col[k].abs());
        for (i, v) in col.iter().enumerate().skip(k + 1) {
            if v.abs() > big {
                big = v.abs();
                p = i;
            }
        }
        piv[k] = p;
        if p != k {
            for j in 0..n {
                a.swap(k + j * n, p + j * n);
            }
        }
        let d = a[k + k * n];
        if d == 0.0 {
            continue;
        }
        let r = 1.0 / d;
        for v in &mut a[k * n + k + 1..(k + 1) * n] {
            *v *= r;
        }
        // The multipliers in a full-length column with zeros at rows ≤ k, so that every
        // column update is a loop of constant length n (unrolled, no bounds checks); the
        // rows ≤ k then receive x − 0·u = x.
        let mut lk = [0.0; SMALL];
        let lk = &mut lk[..n];
        lk[k + 1..].copy_from_slice(&a[k * n + k + 1..(k + 1) * n]);
        for j in k + 1..n {
            let colj = &mut a[j * n..(j + 1) * n];
            let ukj = colj[k];
            for i in 0..n {
                colj[i] -= lk[i] * ukj;
            }
        }
    }
}

/// Solve with the factors of [`lu_unblocked`], b ← A⁻¹ b.
#[inline(always)]
fn lu_solve_unblocked_n(a: &[f64], piv: &[usize], b: &mut [f64], n: usize) {
    let (a, piv, b) = (&a[..n * n], &piv[..n], &mut b[..n]);
    for (k, &p) in piv.iter().enumerate() {
        b.swap(k, p);
    }
    for j in 0..n {
        let bj = b[j];
        for (x, l) in b[j + 1..].iter_mut().zip(&a[j * n + j + 1..(j + 1) * n]) {
            *x -= l * bj;
        }
    }
    for j in (0..n).rev() {
        b[j] /= a[j + j * n];
        let bj = b[j];
        for (x, u) in b[..j].iter_mut().zip(&a[j * n..j * n + j]) {
            *x -= u * bj;
        }
    }
}

/// Right-looking Cholesky LLᵀ of a column-major n × n slice (lower triangle read and
/// overwritten by L; the strict upper triangle is left as it was).
#[inline(always)]
fn llt_unblocked_n(a: &mut [f64], n: usize) -> Result<(), NotPositiveDefinite> {
    let a = &mut a[..n * n];
    for k in 0..n {
        let d = a[k + k * n];
        if !(d > 0.0 && d.is_finite()) {
            return Err(NotPositiveDefinite);
        }
        let l = d.sqrt();
        a[k + k * n] = l;
        let r = 1.0 / l;
        for i in k + 1..n {
            a[k * n + i] *= r;
        }
        for j in k + 1..n {
            let ljk = a[k * n + j];
            for i in j..n {
                a[j * n + i] -= a[k * n + i] * ljk;
            }
        }
    }
    Ok(())
}

/// Copy L's strict lower triangle into its strict upper one (column j of Lᵀ above the
/// diagonal is row j of L) and 1 / L_jj into `inverse_diagonal`, for [`llt_solve_mirrored`].
fn mirror_factor(l: &mut [f64], n: usize, inverse_diagonal: &mut [f64]) {
    for j in 0..n {
        for i in 0..j {
            l[j * n + i] = l[i * n + j];
        }
        inverse_diagonal[j] = 1.0 / l[j * n + j];
    }
}

/// Solve LLᵀ x = b in place with a factor mirrored by [`mirror_factor`]: L y = b by columns
/// of L, then Lᵀ x = y by columns of Lᵀ (its upper triangle), each an axpy on a contiguous
/// slice; the only chain from one column to the next is one multiply by 1 / L_jj.
fn llt_solve_mirrored(l: &[f64], inverse_diagonal: &[f64], n: usize, b: &mut [f64]) {
    sized!(llt_solve_mirrored_n, n, l, inverse_diagonal, b)
}

#[inline(always)]
fn llt_solve_mirrored_n(l: &[f64], inverse_diagonal: &[f64], b: &mut [f64], n: usize) {
    let (l, inverse_diagonal, b) = (&l[..n * n], &inverse_diagonal[..n], &mut b[..n]);
    for j in 0..n {
        let bj = b[j] * inverse_diagonal[j];
        b[j] = bj;
        for (x, v) in b[j + 1..].iter_mut().zip(&l[j * n + j + 1..(j + 1) * n]) {
            *x -= v * bj;
        }
    }
    backward_mirrored(l, inverse_diagonal, b);
}

/// Lᵀ x = y in place, y of length s, for an s × s factor holding Lᵀ in its strict upper
/// triangle ([`mirror_factor`]): by columns of Lᵀ, each an axpy on a contiguous slice, so
/// that the only chain from one column to the next is a multiply by 1 / L_jj (a dot product
/// per row would end in a horizontal sum that the next row waits for).
#[inline(always)]
pub(crate) fn backward_mirrored(l: &[f64], inverse_diagonal: &[f64], y: &mut [f64]) {
    let s = y.len();
    for j in (0..s).rev() {
        let xj = y[j] * inverse_diagonal[j];
        y[j] = xj;
        for (x, u) in y[..j].iter_mut().zip(&l[j * s..j * s + j]) {
            *x -= u * xj;
        }
    }
}

#[cfg(test)]
mod small_tests {
    use super::*;

    fn matrix(n: usize, spd: bool) -> DMatrix<f64> {
        // A pseudo-random matrix (sin of a product: not of low rank).
        let b = DMatrix::from_fn(n, n, |i, j| (((i + 1) * (j + 2) * 37 % 101) as f64).sin());
        if spd {
            DMatrix::from_diagonal_element(n, n, 0.5) + &b * b.transpose()
        } else {
            b
        }
    }

    /// The unblocked kernels (n ≤ SMALL) and faer's (above) solve the same systems.
    #[test]
    fn small_and_faer_paths_agree_with_the_residual() {
        for n in [
            1,
            2,
            5,
            7,
            8,
            SMALL,
            SMALL + 1,
            20,
            MIRRORED_SOLVE,
            MIRRORED_SOLVE + 1,
        ] {
            for spd in [false, true] {
                let a = matrix(n, spd);
                let x = DVector::from_fn(n, |i, _| (i as f64 * 0.7).cos());
                let b = &a * &x;
                let mut y = b.clone();
                let mut lu = DenseLu::new(n);
                lu.factor(&a).unwrap();
                lu.solve_in_place(&mut y);
                assert!((&y - &x).amax() < 1e-10, "LU n = {n}");
                if spd {
                    let mut llt = DenseLlt::new(n);
                    llt.factor(&a).unwrap();
                    let mut z = b.clone();
                    llt.solve_in_place(&mut z);
                    assert!((&z - &x).amax() < 1e-10, "LLT n = {n}");
                }
            }
        }
    }

    #[test]
    fn small_path_refuses_singular_and_indefinite_matrices() {
        let mut a = matrix(6, false);
        let r0 = a.row(0).into_owned();
        a.row_mut(3).copy_from(&(2.0 * r0));
        assert!(DenseLu::new(6).factor(&a).is_err());
        let mut s = matrix(6, true);
        s[(4, 4)] = -10.0;
        assert!(DenseLlt::new(6).factor(&s).is_err());
        let nan = DMatrix::from_element(4, 4, f64::NAN);
        assert!(DenseLu::new(4).factor(&nan).is_err());
        assert!(DenseLlt::new(4).factor(&nan).is_err());
    }
}
