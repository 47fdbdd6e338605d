//! The leading matrix f_q formed and factorised over the structure the formulation declares
//! when it is compiled ([`flexmbd_core::DeclaredPattern`]; docs/methods.md §5.2, issue 26
//! items 2–3): a sparse Cholesky LLᵀ whose ordering and symbolic analysis are done once.
//!
//! f_q = M + h/2 C + h²/4 K + h²α/4 Φ_qᵀ Φ_q has a structural non-zero at (i, j) when i and j
//! share a coupled group of M, K, C or a row of Φ_q. At set-up the lower triangle of that
//! pattern is ordered by faer's approximate minimum degree (Amestoy, Davis & Duff 1996),
//! permuted once (P f_q Pᵀ, stored as its upper triangle by columns, which faer's simplicial
//! kernel reads without a copy) and analysed with the identity ordering. Each forming then
//! writes the pattern's entries straight into the factorisation's value array (W by a
//! gather from the dense M, C, K; the penalty term row by row of Φ_q, each contribution
//! c Φ_q[r, j] Φ_q[r, i] into a slot computed once), in the same order of operations as the
//! dense forming of `Ali3p::form_leading`, so every entry of f_q is the dense one bit for
//! bit; only the factorisation's rounding differs from the dense kernels. Only the pattern's
//! entries of M, K, C and Φ_q are cleared between passes, and no n × n matrix is scanned.
//!
//! Set up only where it pays (n ≥ [`SPARSE_FROM`] and a factor at most [`DECLARED_MAX_FILL`] of a
//! dense one's entries): smaller systems
//! keep the dense kernels and their bit-identical trajectories.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltParams;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Par, Side, Spec};
use flexmbd_core::{DeclaredPattern, Request, SystemTerms};
use nalgebra::DVector;

use crate::sparse_llt::{SPARSE_FROM, SparseFailure};

/// The largest share of a dense factor's n(n+1)/2 entries at which the declared structure
/// is used. Above `crate::sparse_llt::MAX_FILL` (0.2, set for the sparse factorisation of a
/// densely formed matrix) because here the dense forming, clearing and scanning of n × n
/// matrices go too: the 12-flexible Iltis vehicle's declared factor is 21 % full (8 394 of
/// 39 340 entries at n = 280).
pub const DECLARED_MAX_FILL: f64 = 0.3;

/// The declared structure of f_q with its sparse Cholesky factorisation.
pub struct DeclaredLlt {
    n: usize,
    m: usize,
    /// Original coordinate → its place in the fill-reducing order.
    to_new: Vec<usize>,
    /// Upper triangle of P f_q Pᵀ by columns (CSC), and its values.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
    /// Per value: the column-major index, in the dense n × n M, C, K, of its entry in their
    /// lower triangle.
    source: Vec<usize>,
    /// Φ_q's declared rows: row r's columns are `jac_cols[jac_ptr[r]..jac_ptr[r + 1]]`.
    jac_ptr: Vec<usize>,
    jac_cols: Vec<usize>,
    /// Per row r, the slots of its pairs (k ≤ l of its columns, k outer) in `values`, from
    /// `pair_ptr[r]`.
    pair_ptr: Vec<usize>,
    pair_slot: Vec<usize>,
    /// Column-major indices of M, K, C's pattern (both triangles), cleared between passes.
    clear_coupling: Vec<usize>,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    scratch: MemBuffer,
    /// One right-hand side in the new order.
    work: Vec<f64>,
    /// One row's values of Φ_q (capacity n).
    row_values: Vec<f64>,
}

impl DeclaredLlt {
    /// Set up for `pattern` of a system of n coordinates and m constraints; `None` when the
    /// sparse factorisation would not pay (module docs) or the pattern does not fit n, m.
    pub fn new(pattern: &DeclaredPattern, n: usize, m: usize) -> Option<Self> {
        if n < SPARSE_FROM || pattern.jacobian_rows.len() != m {
            return None;
        }
        let in_range = |c: &Vec<usize>| c.iter().all(|&j| j < n);
        if !(pattern.coupled.iter().all(in_range) && pattern.jacobian_rows.iter().all(in_range)) {
            return None;
        }
        let mut lower = pattern.coupling_flags(n);
        for row in &pattern.jacobian_rows {
            for &j in row {
                for &i in row {
                    lower[i + j * n] = true;
                }
            }
        }
        let clear_coupling: Vec<usize> = {
            let flags = pattern.coupling_flags(n);
            (0..n * n).filter(|&k| flags[k]).collect()
        };
        for j in 0..n {
            lower[j + j * n] = true;
            for i in 0..j {
                lower[i + j * n] = false;
            }
        }
        let to_new = fill_reducing_order(n, &lower).ok()?;
        // The upper triangle of P f_q Pᵀ: entry (i, j), i ≥ j, goes to (min, max) of their
        // new places.
        let mut upper = vec![usize::MAX; n * n];
        for j in 0..n {
            for i in j..n {
                if lower[i + j * n] {
                    let (a, b) = (to_new[i], to_new[j]);
                    upper[a.min(b) + a.max(b) * n] = i + j * n;
                }
            }
        }
        let (mut col_ptr, mut row_idx, mut source) = (vec![0], Vec::new(), Vec::new());
        let mut slot_of = vec![usize::MAX; n * n];
        for nj in 0..n {
            for ni in 0..=nj {
                let k = upper[ni + nj * n];
                if k != usize::MAX {
                    slot_of[k] = row_idx.len();
                    row_idx.push(ni);
                    source.push(k);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let symbolic = factorize_symbolic_cholesky(
            SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx),
            Side::Upper,
            SymmetricOrdering::Identity,
            CholeskySymbolicParams::default(),
        )
        .ok()?;
        if symbolic.len_val() as f64 > DECLARED_MAX_FILL * (n * (n + 1) / 2) as f64 {
            return None;
        }
        let (mut jac_ptr, mut jac_cols) = (vec![0], Vec::new());
        let (mut pair_ptr, mut pair_slot) = (vec![0], Vec::new());
        for row in &pattern.jacobian_rows {
            jac_cols.extend_from_slice(row);
            jac_ptr.push(jac_cols.len());
            for (k, &j) in row.iter().enumerate() {
                for &i in &row[k..] {
                    // Lower-triangle entry (i, j): i ≥ j as the row is increasing.
                    pair_slot.push(slot_of[i + j * n]);
                }
            }
            pair_ptr.push(pair_slot.len());
        }
        let scratch = MemBuffer::new(StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Spec::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]));
        Some(DeclaredLlt {
            n,
            m,
            to_new,
            values: vec![0.0; row_idx.len()],
            l_values: vec![0.0; symbolic.len_val()],
            col_ptr,
            row_idx,
            source,
            jac_ptr,
            jac_cols,
            pair_ptr,
            pair_slot,
            clear_coupling,
            symbolic,
            scratch,
            work: vec![0.0; n],
            row_values: Vec::with_capacity(n),
        })
    }

    /// Entries of the Cholesky factor.
    pub fn factor_entries(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Set to zero the terms `req` asks for, as [`SystemTerms::clear`] does, but of M, K,
    /// C and Φ_q only the declared entries (the formulation writes no others).
    pub fn clear(&self, terms: &mut SystemTerms, req: Request) {
        if req.dynamics {
            let mass = terms.mass.as_mut_slice();
            for &k in &self.clear_coupling {
                mass[k] = 0.0;
            }
            terms.forces.as_mut_slice().fill(0.0);
            if req.tangents {
                let (stiffness, damping) =
                    (terms.stiffness.as_mut_slice(), terms.damping.as_mut_slice());
                for &k in &self.clear_coupling {
                    stiffness[k] = 0.0;
                    damping[k] = 0.0;
                }
            }
        }
        if req.constraints {
            terms.phi.as_mut_slice().fill(0.0);
        }
        if req.jacobian {
            let (m, phi_q) = (self.m, terms.phi_q.as_mut_slice());
            for r in 0..m {
                for &j in &self.jac_cols[self.jac_ptr[r]..self.jac_ptr[r + 1]] {
                    phi_q[r + j * m] = 0.0;
                }
            }
            terms.phi_t.as_mut_slice().fill(0.0);
        }
        if req.accel_term {
            terms.accel_term.as_mut_slice().fill(0.0);
        }
    }

    /// Form f_q = M + a C + b K + c Φ_qᵀ Φ_q (a = h/2, b = h²/4, c = h²α/4) over the
    /// pattern, entry for entry as the dense forming does.
    pub fn form(&mut self, terms: &SystemTerms, a: f64, b: f64, c: f64) {
        let (mass, damping, stiffness) = (
            terms.mass.as_slice(),
            terms.damping.as_slice(),
            terms.stiffness.as_slice(),
        );
        for (v, &k) in self.values.iter_mut().zip(&self.source) {
            *v = mass[k] + a * damping[k] + b * stiffness[k];
        }
        let (m, pq) = (self.m, terms.phi_q.as_slice());
        for r in 0..m {
            let columns = &self.jac_cols[self.jac_ptr[r]..self.jac_ptr[r + 1]];
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

    /// Factorise the formed f_q.
    pub fn factor(&mut self) -> Result<(), SparseFailure> {
        let n = self.n;
        let matrix = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx),
            &self.values,
        );
        self.symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                matrix,
                Side::Upper,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut self.scratch),
                Spec::<LltParams, f64>::default(),
            )
            .map(|_| ())
            .map_err(|_| SparseFailure)
    }

    /// Solve f_q x = b in place with the last factorisation.
    pub fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        let n = self.n;
        for (i, &p) in self.to_new.iter().enumerate() {
            self.work[p] = b[i];
        }
        let rhs = faer::MatMut::from_column_major_slice_mut(&mut self.work, n, 1);
        LltRef::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.scratch),
        );
        for (i, &p) in self.to_new.iter().enumerate() {
            b[i] = self.work[p];
        }
    }

    /// The dense lower triangle of the last formed f_q into `lead` (column-major n × n),
    /// for the dense fallback when the sparse factorisation fails.
    pub fn lower_into(&self, lead: &mut [f64]) {
        let n = self.n;
        for j in 0..n {
            lead[j * n + j..(j + 1) * n].fill(0.0);
        }
        for (&v, &k) in self.values.iter().zip(&self.source) {
            lead[k] = v;
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
