//! The entries a formulation declared when it was compiled ([`DeclaredPattern`]; issue 26
//! item 2), in the forms the integrator reads them: the lower-triangle pattern of the
//! leading matrix f_q = M + h/2 C + h²/4 K + h²α/4 Φ_qᵀ Φ_q (an entry (i, j) is structural
//! when i and j share a coupled group of M, K, C or a row of Φ_q), and the entries of M, K,
//! C and Φ_q cleared between passes — the formulation writes no others, so nothing else
//! is cleared, scanned or formed.

use std::ops::Range;

use flexmbd_core::{DeclaredPattern, Request, SystemTerms};
use nalgebra::{DMatrix, DVector};

use crate::arrow_llt::runs;

/// A declared pattern checked against the system's sizes, with its lists of entries.
pub struct DeclaredEntries {
    n: usize,
    m: usize,
    /// f_q's lower-triangle pattern: `lower[i + j n]` for (i, j), i ≥ j (diagonal included).
    lower: Vec<bool>,
    /// M, K, C's pattern (both triangles) as runs of consecutive column-major indices, each
    /// within one column.
    coupling: Vec<Range<usize>>,
    /// Φ_q's declared rows: row r's columns are `jac_cols[jac_ptr[r]..jac_ptr[r + 1]]`.
    jac_ptr: Vec<usize>,
    jac_cols: Vec<usize>,
}

impl DeclaredEntries {
    /// The entries of `pattern` for n coordinates and m constraints; `None` when the
    /// pattern does not fit those sizes (a column out of range, a row count other than m).
    pub fn new(pattern: &DeclaredPattern, n: usize, m: usize) -> Option<Self> {
        let in_range = |c: &Vec<usize>| c.iter().all(|&j| j < n);
        let fits = pattern.jacobian_rows.len() == m
            && pattern.coupled.iter().all(in_range)
            && pattern.jacobian_rows.iter().all(in_range);
        if !fits {
            return None;
        }
        let flags = pattern.coupling_flags(n);
        // Runs within one column each (`sub_product` reads a run as one column's rows).
        let coupling = (0..n)
            .flat_map(|j| runs((j * n..(j + 1) * n).filter(|&k| flags[k])))
            .collect();
        let mut lower = flags;
        for row in &pattern.jacobian_rows {
            for &j in row {
                for &i in row {
                    lower[i + j * n] = true;
                }
            }
        }
        for j in 0..n {
            lower[j + j * n] = true;
            for i in 0..j {
                lower[i + j * n] = false;
            }
        }
        let (mut jac_ptr, mut jac_cols) = (vec![0], Vec::new());
        for row in &pattern.jacobian_rows {
            jac_cols.extend_from_slice(row);
            jac_ptr.push(jac_cols.len());
        }
        Some(DeclaredEntries {
            n,
            m,
            lower,
            coupling,
            jac_ptr,
            jac_cols,
        })
    }

    /// The number of coordinates n.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The number of constraint rows m.
    pub fn m(&self) -> usize {
        self.m
    }

    /// f_q's lower-triangle pattern, n × n column-major.
    pub fn lower(&self) -> &[bool] {
        &self.lower
    }

    /// f_q's lower-triangle pattern as runs of consecutive column-major indices.
    pub fn lower_runs(&self) -> Vec<Range<usize>> {
        runs((0..self.n * self.n).filter(|&k| self.lower[k]))
    }

    /// Row r of Φ_q's declared columns, increasing.
    pub fn jacobian_row(&self, r: usize) -> &[usize] {
        &self.jac_cols[self.jac_ptr[r]..self.jac_ptr[r + 1]]
    }

    /// Set to zero the terms `req` asks for, as [`SystemTerms::clear`] does, but of M, K,
    /// C and Φ_q only the declared entries.
    pub fn clear(&self, terms: &mut SystemTerms, req: Request) {
        if req.dynamics {
            let mass = terms.mass.as_mut_slice();
            for run in &self.coupling {
                mass[run.clone()].fill(0.0);
            }
            terms.forces.as_mut_slice().fill(0.0);
            if req.tangents {
                let (stiffness, damping) =
                    (terms.stiffness.as_mut_slice(), terms.damping.as_mut_slice());
                for run in &self.coupling {
                    stiffness[run.clone()].fill(0.0);
                    damping[run.clone()].fill(0.0);
                }
            }
        }
        if req.constraints {
            terms.phi.as_mut_slice().fill(0.0);
        }
        if req.jacobian {
            let (m, phi_q) = (self.m, terms.phi_q.as_mut_slice());
            for r in 0..m {
                for &j in self.jacobian_row(r) {
                    phi_q[r + j * m] = 0.0;
                }
            }
            terms.phi_t.as_mut_slice().fill(0.0);
        }
        if req.accel_term {
            terms.accel_term.as_mut_slice().fill(0.0);
        }
    }

    /// y ← y − A x for A = M, K or C over the declared pattern, column by column as
    /// nalgebra's `gemv` forms y + (−A) x (the same sums, without the terms of entries
    /// outside the pattern, which are zero).
    pub fn sub_product(&self, a: &DMatrix<f64>, x: &DVector<f64>, y: &mut DVector<f64>) {
        let (n, a, y) = (self.n, a.as_slice(), y.as_mut_slice());
        for run in &self.coupling {
            let (j, first) = (run.start / n, run.start % n);
            let xj = x[j];
            for (yi, &aij) in y[first..first + run.len()].iter_mut().zip(&a[run.clone()]) {
                *yi += -aij * xj;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arrow_llt::ArrowLlt;

    /// A tree's pattern: a root of 3 coordinates coupled with each of 3 branches of 12,
    /// numbered interleaved; one constraint row per branch on its first two coordinates and
    /// the root's first.
    fn tree() -> (DeclaredPattern, usize) {
        let (root, branches, size) = (3, 3, 12);
        let n = root + branches * size;
        let place = |i: usize| (i * 7) % n; // 7 is prime to 39
        let coupled = (0..branches)
            .map(|b| {
                let mut group: Vec<usize> = (0..root)
                    .chain((0..size).map(|k| root + b * size + k))
                    .map(place)
                    .collect();
                group.sort_unstable();
                group
            })
            .collect();
        let jacobian_rows = (0..branches)
            .map(|b| {
                let mut row = vec![place(0), place(root + b * size), place(root + b * size + 1)];
                row.sort_unstable();
                row
            })
            .collect();
        let pattern = DeclaredPattern {
            coupled,
            jacobian_rows,
        };
        (pattern, n)
    }

    #[test]
    fn the_product_over_the_pattern_is_the_dense_product_bit_for_bit() {
        let (pattern, n) = tree();
        let entries = DeclaredEntries::new(&pattern, n, 3).unwrap();
        let flags = pattern.coupling_flags(n);
        let a = DMatrix::from_fn(n, n, |i, j| {
            let v = ((i * 13 + j * 5) as f64 * 0.71).sin() * 1e3;
            if flags[i + j * n] { v } else { 0.0 }
        });
        let x = DVector::from_fn(n, |i, _| (i as f64 * 0.37).cos() * 1e-3);
        let y0 = DVector::from_fn(n, |i, _| (i as f64 * 1.3).sin());
        let (mut dense, mut declared) = (y0.clone(), y0);
        dense.gemv(-1.0, &a, &x, 1.0);
        entries.sub_product(&a, &x, &mut declared);
        assert_eq!(dense, declared);
    }

    #[test]
    fn only_the_declared_entries_are_cleared() {
        let (pattern, n) = tree();
        let entries = DeclaredEntries::new(&pattern, n, 3).unwrap();
        let mut terms = SystemTerms::new(n, 3);
        terms.mass.fill(1.0);
        terms.phi_q.fill(1.0);
        entries.clear(&mut terms, Request::ALL);
        let flags = pattern.coupling_flags(n);
        for k in 0..n * n {
            assert_eq!(terms.mass.as_slice()[k] == 0.0, flags[k], "entry {k}");
        }
        let cleared = terms.phi_q.iter().filter(|&&v| v == 0.0).count();
        assert_eq!(cleared, 9);
    }

    #[test]
    fn a_declared_tree_is_an_arrow_with_the_root_as_its_border() {
        let (pattern, n) = tree();
        let entries = DeclaredEntries::new(&pattern, n, 3).unwrap();
        let arrow = ArrowLlt::declared(n, entries.lower()).expect("an arrow");
        assert_eq!(arrow.shape(), (3, 3));
        // A pattern that does not fit the sizes is not taken.
        assert!(DeclaredEntries::new(&pattern, n - 1, 3).is_none());
        assert!(DeclaredEntries::new(&pattern, n, 2).is_none());
    }
}
