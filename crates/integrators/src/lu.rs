//! Dense LU with partial pivoting, in place and allocation-free after set-up: the
//! leading matrix of a step is small (tens of coordinates) and dense. faer's
//! in-place kernels take their scratch from a buffer sized once (`*_scratch`).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::{Par, Spec};
use nalgebra::{DMatrix, DVector};

/// A reusable LU factorisation of an n × n matrix.
pub struct DenseLu {
    n: usize,
    lu: DMatrix<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    scratch: MemBuffer,
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
        }
    }

    /// Factorise a copy of `a`. Fails when a pivot is below 1e-14 of the largest.
    pub fn factor(&mut self, a: &DMatrix<f64>) -> Result<(), Singular> {
        self.lu.copy_from(a);
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

    /// Solve A x = b in place (b ← x) with the last factorisation.
    pub fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        let n = self.n;
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
        }
    }

    /// Factorise a copy of `a` (its lower triangle is read).
    pub fn factor(&mut self, a: &DMatrix<f64>) -> Result<(), NotPositiveDefinite> {
        use faer::linalg::cholesky::llt;
        self.l.copy_from(a);
        let n = self.n;

        let mat = faer::MatMut::from_column_major_slice_mut(self.l.as_mut_slice(), n, n);
        let stack = MemStack::new(&mut self.scratch);
        llt::factor::cholesky_in_place(mat, Default::default(), Par::Seq, stack, Spec::default())
            .map(|_| ())
            .map_err(|_| NotPositiveDefinite)
    }

    /// Solve A x = b in place with the last factorisation.
    pub fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        use faer::linalg::cholesky::llt;
        let n = self.n;

        let l = faer::MatRef::from_column_major_slice(self.l.as_slice(), n, n);
        let rhs = faer::MatMut::from_column_major_slice_mut(b.as_mut_slice(), n, 1);
        let stack = MemStack::new(&mut self.scratch);
        llt::solve::solve_in_place(l, rhs, Par::Seq, stack);
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
