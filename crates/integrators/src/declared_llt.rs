//! The leading matrix f_q formed and factorised over the structure the formulation declares
//! when it is compiled ([`flexmbd_core::DeclaredPattern`]; docs/methods.md §5.2, issue 26
//! items 2–3): a sparse Cholesky LLᵀ whose ordering and symbolic analysis are done once.
//!
//! f_q = M + h/2 C + h²/4 K + h²α/4 Φ_qᵀ Φ_q has a structural non-zero at (i, j) when i and j
//! share a coupled group of M, K, C or a row of Φ_q. At set-up the lower triangle of that
//! pattern is ordered by faer's approximate minimum degree (Amestoy, Davis & Duff 1996),
//! permuted once (P f_q Pᵀ) and eliminated symbolically to the pattern of its factor L, with
//! each row's entries of L listed. Each forming then writes f_q's entries straight into an
//! array on L's pattern (W by a
//! gather from the dense M, C, K; the penalty term row by row of Φ_q, each contribution
//! c Φ_q[r, j] Φ_q[r, i] into a slot computed once), in the same order of operations as the
//! dense forming of `Ali3p::form_leading`, so every entry of f_q is the dense one bit for
//! bit; only the factorisation's rounding differs from the dense kernels. The numeric
//! factorisation is this module's left-looking kernel over the fixed pattern (no
//! elimination-tree search per factorisation, as faer's simplicial kernel makes: on the
//! 12-flexible vehicle the step's profile samples fell from 2 924 with faer's kernel to 2 373). Only the pattern's
//! entries of M, K, C and Φ_q are cleared between passes, and no n × n matrix is scanned.
//!
//! Set up only where it pays (n ≥ [`SPARSE_FROM`] and a factor at most [`DECLARED_MAX_FILL`] of a
//! dense one's entries): smaller systems
//! keep the dense kernels and their bit-identical trajectories.

use faer::Side;
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymmetricOrdering, factorize_symbolic_cholesky,
};
use flexmbd_core::SystemTerms;
use nalgebra::DVector;

use crate::declared_entries::DeclaredEntries;
use crate::sparse_llt::{SPARSE_FROM, SparseFailure};

/// The largest share of a dense factor's n(n+1)/2 entries at which the declared structure
/// is used. Above `crate::sparse_llt::MAX_FILL` (0.2, set for the sparse factorisation of a
/// densely formed matrix) because here the dense forming, clearing and scanning of n × n
/// matrices go too: the 12-flexible Iltis vehicle's declared factor is 21 % full (8 394 of
/// 39 340 entries at n = 280). The rigid bump (n = 108) declares a factor over 30 % full,
/// looser than the 20 % its numbers show (a rigid body's direction term writes only the
/// columns of its non-zero local components), and at 0.5 it took the declared route and
/// ran slower: 0.39–0.44 s against 0.32 s (CLI `cpu_seconds`, 3 interleaved runs).
pub const DECLARED_MAX_FILL: f64 = 0.3;

/// The declared structure of f_q with its sparse Cholesky factorisation.
pub struct DeclaredLlt {
    n: usize,
    m: usize,
    /// Original coordinate → its place in the fill-reducing order.
    to_new: Vec<usize>,
    /// The pattern of the factor L of P f_q Pᵀ by columns (CSC, the diagonal first), and
    /// f_q's values on it (zero at the fill-in).
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
    /// Per entry of f_q: its position in the factor's pattern (`gather_slot`) and the
    /// column-major index, in the dense n × n M, C, K, of its entry in their lower triangle.
    gather_slot: Vec<usize>,
    source: Vec<usize>,
    /// Per row i of the factor, its entries (k, position of L[i, k]) left of the diagonal:
    /// `row_entries[row_ptr[i]..row_ptr[i + 1]]`.
    row_ptr: Vec<usize>,
    row_entries: Vec<(usize, usize)>,
    /// Position in the current column of each row (left-looking factorisation).
    position: Vec<usize>,
    /// Per row r, the slots of its pairs (k ≤ l of its columns, k outer) in `values`, from
    /// `pair_ptr[r]`.
    pair_ptr: Vec<usize>,
    pair_slot: Vec<usize>,
    l_values: Vec<f64>,
    /// One right-hand side in the new order.
    work: Vec<f64>,
    /// One row's values of Φ_q (capacity n).
    row_values: Vec<f64>,
}

impl DeclaredLlt {
    /// Set up for the declared `entries` of a system; `None` when the sparse factorisation
    /// would not pay (module docs).
    pub fn new(entries: &DeclaredEntries) -> Option<Self> {
        let n = entries.n();
        if n < SPARSE_FROM {
            return None;
        }
        let (m, lower) = (entries.m(), entries.lower());
        let to_new = fill_reducing_order(n, lower).ok()?;
        // The lower triangle of P f_q Pᵀ: entry (i, j), i ≥ j, goes to (max, min) of their
        // new places; then the factor's pattern by symbolic elimination (each column's
        // rows below the diagonal couple pairwise in the later columns).
        let mut origin = vec![usize::MAX; n * n];
        let mut factor_flags = vec![false; n * n];
        for j in 0..n {
            for i in j..n {
                if lower[i + j * n] {
                    let (a, b) = (to_new[i], to_new[j]);
                    origin[a.max(b) + a.min(b) * n] = i + j * n;
                    factor_flags[a.max(b) + a.min(b) * n] = true;
                }
            }
        }
        let mut below = Vec::with_capacity(n);
        for j in 0..n {
            below.clear();
            below.extend((j + 1..n).filter(|&i| factor_flags[i + j * n]));
            for (k, &a) in below.iter().enumerate() {
                for &b in &below[k..] {
                    factor_flags[b + a * n] = true;
                }
            }
        }
        let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
        let (mut source, mut gather_slot) = (Vec::new(), Vec::new());
        let mut slot_of = vec![usize::MAX; n * n];
        for nj in 0..n {
            for ni in nj..n {
                if factor_flags[ni + nj * n] {
                    let k = origin[ni + nj * n];
                    if k != usize::MAX {
                        slot_of[k] = row_idx.len();
                        gather_slot.push(row_idx.len());
                        source.push(k);
                    }
                    row_idx.push(ni);
                }
            }
            col_ptr.push(row_idx.len());
        }
        if row_idx.len() as f64 > DECLARED_MAX_FILL * (n * (n + 1) / 2) as f64 {
            return None;
        }
        // Per row i of the factor, its entries L[i, k], k < i: (k, position), k increasing.
        let mut row_lists: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
        for k in 0..n {
            for p in col_ptr[k] + 1..col_ptr[k + 1] {
                row_lists[row_idx[p]].push((k, p));
            }
        }
        let mut row_ptr = vec![0];
        let mut row_entries = Vec::new();
        for list in row_lists {
            row_entries.extend(list);
            row_ptr.push(row_entries.len());
        }
        let (mut pair_ptr, mut pair_slot) = (vec![0], Vec::new());
        for r in 0..m {
            let row = entries.jacobian_row(r);
            for (k, &j) in row.iter().enumerate() {
                for &i in &row[k..] {
                    // Lower-triangle entry (i, j): i ≥ j as the row is increasing.
                    pair_slot.push(slot_of[i + j * n]);
                }
            }
            pair_ptr.push(pair_slot.len());
        }
        Some(DeclaredLlt {
            n,
            m,
            to_new,
            values: vec![0.0; row_idx.len()],
            l_values: vec![0.0; row_idx.len()],
            col_ptr,
            row_idx,
            gather_slot,
            source,
            row_ptr,
            row_entries,
            position: vec![0; n],
            pair_ptr,
            pair_slot,
            work: vec![0.0; n],
            row_values: Vec::with_capacity(n),
        })
    }

    /// Entries of the Cholesky factor.
    pub fn factor_entries(&self) -> usize {
        self.row_idx.len()
    }

    /// Form f_q = M + a C + b K + c Φ_qᵀ Φ_q (a = h/2, b = h²/4, c = h²α/4) over the
    /// pattern, entry for entry as the dense forming does.
    pub fn form(&mut self, entries: &DeclaredEntries, terms: &SystemTerms, a: f64, b: f64, c: f64) {
        let (mass, damping, stiffness) = (
            terms.mass.as_slice(),
            terms.damping.as_slice(),
            terms.stiffness.as_slice(),
        );
        self.values.fill(0.0);
        for (&slot, &k) in self.gather_slot.iter().zip(&self.source) {
            self.values[slot] = mass[k] + a * damping[k] + b * stiffness[k];
        }
        let (m, pq) = (self.m, terms.phi_q.as_slice());
        for r in 0..m {
            let columns = entries.jacobian_row(r);
            self.row_values.clear();
            self.row_values
                .extend(columns.iter().map(|&j| pq[r + j * m]));
            let mut slots = self.pair_slot[self.pair_ptr[r]..self.pair_ptr[r + 1]].iter();
            for (k, &vj) in self.row_values.iter().enumerate() {
                let cj = c * vj;
                for (&vi, &slot) in self.row_values[k..].iter().zip(slots.by_ref()) {
                    self.values[slot] += cj * vi;
                }
            }
        }
    }

    /// Factorise the formed f_q: left-looking Cholesky over the factor's pattern, column j
    /// less L[j, k] times column k for every k with L[j, k] ≠ 0, then scaled by its pivot's
    /// square root (Davis 2006, §4.8). Fails on a pivot that is not positive.
    pub fn factor(&mut self) -> Result<(), SparseFailure> {
        let l = &mut self.l_values;
        l.copy_from_slice(&self.values);
        let (col_ptr, row_idx) = (&self.col_ptr, &self.row_idx);
        for j in 0..self.n {
            let (first, end) = (col_ptr[j], col_ptr[j + 1]);
            for p in first..end {
                self.position[row_idx[p]] = p;
            }
            for &(k, p_jk) in &self.row_entries[self.row_ptr[j]..self.row_ptr[j + 1]] {
                let l_jk = l[p_jk];
                for p in p_jk..col_ptr[k + 1] {
                    let target = self.position[row_idx[p]];
                    l[target] -= l[p] * l_jk;
                }
            }
            let pivot = l[first];
            if !(pivot > 0.0 && pivot.is_finite()) {
                return Err(SparseFailure);
            }
            let d = pivot.sqrt();
            l[first] = d;
            for v in &mut l[first + 1..end] {
                *v /= d;
            }
        }
        Ok(())
    }

    /// Solve f_q x = b in place with the last factorisation (L y = P b, Lᵀ z = y, x = Pᵀ z).
    pub fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        let (l, x) = (&self.l_values, &mut self.work);
        for (i, &p) in self.to_new.iter().enumerate() {
            x[p] = b[i];
        }
        let (col_ptr, row_idx) = (&self.col_ptr, &self.row_idx);
        for j in 0..self.n {
            let xj = x[j] / l[col_ptr[j]];
            x[j] = xj;
            for p in col_ptr[j] + 1..col_ptr[j + 1] {
                x[row_idx[p]] -= l[p] * xj;
            }
        }
        for j in (0..self.n).rev() {
            let mut xj = x[j];
            for p in col_ptr[j] + 1..col_ptr[j + 1] {
                xj -= l[p] * x[row_idx[p]];
            }
            x[j] = xj / l[col_ptr[j]];
        }
        for (i, &p) in self.to_new.iter().enumerate() {
            b[i] = x[p];
        }
    }

    /// The dense lower triangle of the last formed f_q into `lead` (column-major n × n),
    /// for the dense fallback when the sparse factorisation fails.
    pub fn lower_into(&self, lead: &mut [f64]) {
        let n = self.n;
        for j in 0..n {
            lead[j * n + j..(j + 1) * n].fill(0.0);
        }
        for (&slot, &k) in self.gather_slot.iter().zip(&self.source) {
            lead[k] = self.values[slot];
        }
    }
}

/// The approximate-minimum-degree order of the lower-triangle `pattern` (column-major n × n
/// flags): each original index's place.
fn fill_reducing_order(n: usize, pattern: &[bool]) -> Result<Vec<usize>, SparseFailure> {
    let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
    for j in 0..n {
        row_idx.extend((j..n).filter(|&i| pattern[i + j * n]));
        col_ptr.push(row_idx.len());
    }
    let symbolic = factorize_symbolic_cholesky(
        SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx),
        Side::Lower,
        SymmetricOrdering::Amd,
        CholeskySymbolicParams::default(),
    )
    .map_err(|_| SparseFailure)?;
    let Some(perm) = symbolic.perm() else {
        return Ok((0..n).collect());
    };
    let (_, inverse) = perm.arrays();
    Ok(inverse.to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd_core::DeclaredPattern;
    use nalgebra::DMatrix;

    /// A chain of `bodies` blocks of `size` coordinates, each joined to the next by a
    /// constraint row over both blocks' first three coordinates: M, K, C block diagonal,
    /// Φ_q banded, as in natural coordinates.
    fn chain(bodies: usize, size: usize) -> (DeclaredPattern, SystemTerms) {
        let (n, m) = (bodies * size, bodies - 1);
        let coupled: Vec<Vec<usize>> = (0..bodies)
            .map(|b| (b * size..(b + 1) * size).collect())
            .collect();
        let jacobian_rows: Vec<Vec<usize>> = (0..m)
            .map(|r| {
                let (a, b) = (r * size, (r + 1) * size);
                vec![a, a + 1, a + 2, b, b + 1, b + 2]
            })
            .collect();
        let mut terms = SystemTerms::new(n, m);
        for group in &coupled {
            for &j in group {
                for &i in group {
                    let v = ((i * 7 + j * 7 + i * j) as f64 * 0.37).sin() / size as f64;
                    terms.mass[(i, j)] = v + if i == j { 2.0 } else { 0.0 };
                    terms.stiffness[(i, j)] = 0.3 * v;
                    terms.damping[(i, j)] = 0.1 * v;
                }
            }
        }
        for (r, row) in jacobian_rows.iter().enumerate() {
            for (k, &j) in row.iter().enumerate() {
                terms.phi_q[(r, j)] = (k as f64 + 1.0) * if k < 3 { 1.0 } else { -0.5 };
            }
        }
        (
            DeclaredPattern {
                coupled,
                jacobian_rows,
            },
            terms,
        )
    }

    /// Formed and factorised over the declared pattern, f_q x = b is solved as the dense
    /// f_q = M + a C + b K + c Φ_qᵀ Φ_q gives it.
    #[test]
    fn solves_the_leading_system_as_the_dense_matrix_gives_it() {
        let (pattern, terms) = chain(8, 14);
        let n = terms.mass.nrows();
        let (a, b, c) = (0.5e-3, 0.25e-6, 1e3);
        let dense = &terms.mass
            + a * &terms.damping
            + b * &terms.stiffness
            + c * terms.phi_q.transpose() * &terms.phi_q;
        let entries = DeclaredEntries::new(&pattern, n, terms.phi.len()).unwrap();
        let mut llt = DeclaredLlt::new(&entries).expect("sparse pays");
        assert!(llt.factor_entries() < n * (n + 1) / 5);
        llt.form(&entries, &terms, a, b, c);
        let mut lower = DMatrix::zeros(n, n);
        llt.lower_into(lower.as_mut_slice());
        for j in 0..n {
            for i in j..n {
                assert!((lower[(i, j)] - dense[(i, j)]).abs() <= 1e-12 * dense.amax());
            }
        }
        llt.factor().unwrap();
        let x = DVector::from_fn(n, |i, _| (i as f64 * 0.3).cos());
        let mut rhs = &dense * &x;
        llt.solve_in_place(&mut rhs);
        assert!((rhs - x).amax() < 1e-10, "solution off");
    }

    #[test]
    fn an_indefinite_matrix_fails_and_a_small_one_is_not_set_up() {
        let (pattern, mut terms) = chain(8, 14);
        let n = terms.mass.nrows();
        terms.mass[(50, 50)] = -5.0;
        let entries = DeclaredEntries::new(&pattern, n, terms.phi.len()).unwrap();
        let mut llt = DeclaredLlt::new(&entries).unwrap();
        llt.form(&entries, &terms, 0.0, 0.0, 1.0);
        assert!(llt.factor().is_err());
        let (small, terms) = chain(4, 14);
        assert!(
            DeclaredEntries::new(&small, terms.mass.nrows(), terms.phi.len())
                .and_then(|entries| DeclaredLlt::new(&entries))
                .is_none()
        );
    }
}
