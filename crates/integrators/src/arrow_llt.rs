//! Cholesky LLᵀ of a leading matrix in **bordered block-diagonal** ("arrow") form: blocks
//! B_k that do not couple with each other, and a border R that couples with all of them.
//! This is the shape of f_q for a tree in relative coordinates (docs/methods.md §4.5): the
//! root body's coordinates (a vehicle's chassis, the border) couple through M with every
//! coordinate below them, while the branches (the four corners, with their modal
//! coordinates) couple only within themselves.
//!
//! With the rows ordered blocks first, border last,
//!
//! ```text
//! [ B_1        C_1ᵀ ]   [ L_1            ] [ L_1ᵀ      W_1ᵀ ]
//! [     ⋱      ⋮    ] = [      ⋱         ] [      ⋱    ⋮    ]
//! [ C_1 ⋯      D    ]   [ W_1  ⋯    L_D  ] [           L_Dᵀ ]
//! ```
//!
//! with L_k Lₖᵀ = B_k, W_k = C_k L_k⁻ᵀ and L_D L_Dᵀ = S = D − Σ_k W_k W_kᵀ (the Schur
//! complement on the border). The work is Σ s_k³/3 + r Σ s_k² + r² n instead of n³/3 for
//! blocks of s_k and a border of r rows: about a tenth for the vehicle (6 + 4 × 28). A solve
//! is y_k = L_k⁻¹ b_k, x_R = S⁻¹ (b_R − Σ W_k y_k), x_k = L_k⁻ᵀ (y_k − W_kᵀ x_R).
//!
//! The structure is found in the matrix's own non-zeros when the factorisation is set up
//! ([`ArrowLlt::detect`]: the border is every coordinate coupled with more than half of the
//! others, the blocks the connected components of what is left). Every factorisation checks
//! that the entries between blocks are still zero; if one is not, it reports
//! [`ArrowFailure`] and the caller goes back to the dense kernels for the rest of the run.

use nalgebra::{DMatrix, DVector};

use crate::lu::{DenseLlt, backward_mirrored};

/// The smallest system for which the arrow form is looked for. Smaller ones keep the dense
/// kernels, which factorise and solve them in about a microsecond (`benches/dense.rs`:
/// 1.2 µs at n = 22, the rigid Iltis on the bump); the arrow form gains from n = 42 on
/// (the rigid vehicle: 2.8 against 3.6 µs).
pub const ARROW_FROM: usize = 32;

/// The arrow form is used when its work (flops) is at most this share of a dense
/// Cholesky's: faer's dense kernel does more flops per second than the arrow form's small
/// pieces (`benches/dense.rs`, group `structured_against_dense`, factorise + solve: at
/// n = 118 a border of 30 and blocks of 22, 29 % of the work, took 27 against 26 µs; the
/// vehicle's 6 + 4 × 28, 10 %, 12 against 23 µs; 6 + 4 × 9 at n = 42, 17 %, 2.8 against
/// 3.6 µs; 6 + 8 × 28 at n = 230 28 against 89 µs).
const MAX_WORK: f64 = 0.25;

/// A reusable Cholesky factorisation of an SPD matrix in bordered block-diagonal form.
pub struct ArrowLlt {
    /// The coordinates of each block, and of the border.
    blocks: Vec<Vec<usize>>,
    border: Vec<usize>,
    /// Per block: B_k gathered, its factorisation and the reciprocals of L_k's diagonal,
    /// W_kᵀ (s_k × r, column-major).
    gathered: Vec<DMatrix<f64>>,
    factors: Vec<DenseLlt>,
    inverse_diagonals: Vec<Vec<f64>>,
    w_t: Vec<DMatrix<f64>>,
    /// The Schur complement S on the border and its factorisation.
    schur: DMatrix<f64>,
    schur_factor: DenseLlt,
    /// The lower-triangle entries between different blocks, as runs of consecutive
    /// column-major indices.
    between_blocks: Vec<std::ops::Range<usize>>,
    /// Where in the matrix (column-major index of its lower triangle) each entry gathered
    /// for a factorisation comes from: S's, per block B_k's lower triangle (with its index
    /// in `gathered`), and W_kᵀ's.
    schur_sources: Vec<usize>,
    block_sources: Vec<Vec<(usize, usize)>>,
    w_sources: Vec<Vec<usize>>,
    /// Solve workspace: the right-hand side per block and on the border.
    y: Vec<Vec<f64>>,
    y_border: DVector<f64>,
}

/// The arrow factorisation failed: an entry between blocks turned non-zero, or a block or
/// the Schur complement is not positive definite. The caller uses the dense kernels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArrowFailure;

impl ArrowLlt {
    /// The arrow form of `a`'s pattern (lower triangle) if it has a border and at least two
    /// blocks and saves at least half the work of a dense Cholesky; `None` otherwise.
    pub fn detect(a: &DMatrix<f64>) -> Option<Self> {
        Self::with_coupling(a.nrows(), |i, j| {
            let (hi, lo) = if i > j { (i, j) } else { (j, i) };
            a[(hi, lo)] != 0.0
        })
    }

    /// The arrow form of a pattern declared when the scene was compiled
    /// (`lower[i + j n]`: entry (i, j), i ≥ j, of f_q may be non-zero), found as
    /// [`ArrowLlt::detect`] finds it in a matrix's non-zeros. Entries between blocks are
    /// then zero by declaration, so no factorisation checks them.
    pub fn declared(n: usize, lower: &[bool]) -> Option<Self> {
        let mut arrow = Self::with_coupling(n, |i, j| lower[i.max(j) + i.min(j) * n])?;
        arrow.between_blocks.clear();
        Some(arrow)
    }

    fn with_coupling(n: usize, coupled: impl Fn(usize, usize) -> bool) -> Option<Self> {
        if n < ARROW_FROM {
            return None;
        }
        let degree: Vec<usize> = (0..n)
            .map(|i| (0..n).filter(|&j| j != i && coupled(i, j)).count())
            .collect();
        let in_border: Vec<bool> = degree.iter().map(|&d| 2 * d > n).collect();
        let border: Vec<usize> = (0..n).filter(|&i| in_border[i]).collect();
        let blocks = components(n, &in_border, &coupled);
        // No border, no tree: blocks that are uncoupled at the start are usually so by the
        // symmetry of the initial configuration (a beam's two bending planes), which the
        // motion breaks.
        if blocks.len() < 2 || border.is_empty() {
            return None;
        }
        if arrow_work(&blocks, border.len()) > MAX_WORK * (n as f64).powi(3) / 3.0 {
            return None;
        }
        Some(Self::with_structure(n, blocks, border))
    }

    fn with_structure(n: usize, blocks: Vec<Vec<usize>>, border: Vec<usize>) -> Self {
        let mut block_of = vec![usize::MAX; n];
        for (k, b) in blocks.iter().enumerate() {
            for &i in b {
                block_of[i] = k;
            }
        }
        let between_blocks = (0..n)
            .flat_map(|j| (j + 1..n).map(move |i| (i, j)))
            .filter(|&(i, j)| {
                block_of[i] != usize::MAX && block_of[j] != usize::MAX && block_of[i] != block_of[j]
            })
            .map(|(i, j)| i + j * n);
        let between_blocks = runs(between_blocks);
        let r = border.len();
        // The lower triangle's entry (i, j) or (j, i).
        let lower = |i: usize, j: usize| if i >= j { i + j * n } else { j + i * n };
        let schur_sources = border
            .iter()
            .flat_map(|&bj| border.iter().map(move |&bi| lower(bi, bj)))
            .collect();
        let block_sources = blocks
            .iter()
            .map(|block| {
                let s = block.len();
                let columns = block.iter().enumerate();
                columns
                    .flat_map(|(j, &cj)| {
                        let rows = block.iter().enumerate().skip(j);
                        rows.map(move |(i, &ci)| (i + j * s, lower(ci, cj)))
                    })
                    .collect()
            })
            .collect();
        let w_sources = blocks
            .iter()
            .map(|block| {
                let columns = border.iter();
                columns
                    .flat_map(|&bi| block.iter().map(move |&cj| lower(bi, cj)))
                    .collect()
            })
            .collect();
        ArrowLlt {
            schur_sources,
            block_sources,
            w_sources,
            gathered: blocks
                .iter()
                .map(|b| DMatrix::zeros(b.len(), b.len()))
                .collect(),
            factors: blocks.iter().map(|b| DenseLlt::new(b.len())).collect(),
            inverse_diagonals: blocks.iter().map(|b| vec![0.0; b.len()]).collect(),
            w_t: blocks.iter().map(|b| DMatrix::zeros(b.len(), r)).collect(),
            y: blocks.iter().map(|b| vec![0.0; b.len()]).collect(),
            schur: DMatrix::zeros(r, r),
            schur_factor: DenseLlt::new(r),
            y_border: DVector::zeros(r),
            between_blocks,
            blocks,
            border,
        }
    }

    /// The number of blocks and the border's size.
    pub fn shape(&self) -> (usize, usize) {
        (self.blocks.len(), self.border.len())
    }

    /// The floating-point operations of one factorisation, Σ s_k³/3 + r Σ s_k² + r² Σ s_k +
    /// r³/3 for blocks of s_k and a border of r (leading terms; a dense Cholesky's is n³/3).
    pub fn work(&self) -> f64 {
        arrow_work(&self.blocks, self.border.len())
    }

    /// Whether `a` still has the arrow form: every entry between blocks zero.
    pub fn still_holds(&self, a: &DMatrix<f64>) -> bool {
        // Branch-free within a run, so that the compiler can vectorise it.
        let a = a.as_slice();
        self.between_blocks.iter().all(|run| {
            !a[run.clone()]
                .iter()
                .fold(false, |non_zero, &v| non_zero | (v != 0.0))
        })
    }

    /// Factorise `a` (its lower triangle).
    pub fn factor(&mut self, a: &DMatrix<f64>) -> Result<(), ArrowFailure> {
        if !self.still_holds(a) {
            return Err(ArrowFailure);
        }
        let a = a.as_slice();
        let schur = self.schur.as_mut_slice();
        for (v, &source) in schur.iter_mut().zip(&self.schur_sources) {
            *v = a[source];
        }
        for k in 0..self.blocks.len() {
            let g = &mut self.gathered[k];
            // The lower triangle of B_k.
            let gathered = g.as_mut_slice();
            for &(entry, source) in &self.block_sources[k] {
                gathered[entry] = a[source];
            }
            self.factors[k].factor(g).map_err(|_| ArrowFailure)?;
            let s = self.blocks[k].len();
            let l = self.factors[k].factor_data();
            for (i, d) in self.inverse_diagonals[k].iter_mut().enumerate() {
                *d = 1.0 / l[i + i * s];
            }
            // W_kᵀ = L_k⁻¹ C_kᵀ: column i is row i of C_k (the border row against the block).
            let w_t = &mut self.w_t[k];
            for (v, &source) in w_t.as_mut_slice().iter_mut().zip(&self.w_sources[k]) {
                *v = a[source];
            }
            self.factors[k].solve_lower_many_in_place(w_t);
            // S −= W_k W_kᵀ (the border's lower triangle is all the Cholesky reads).
            let w = w_t.as_slice();
            for j in 0..self.border.len() {
                for i in j..self.border.len() {
                    self.schur[(i, j)] -= dot(&w[i * s..(i + 1) * s], &w[j * s..(j + 1) * s]);
                }
            }
        }
        self.schur_factor
            .factor(&self.schur)
            .map_err(|_| ArrowFailure)
    }

    /// Solve A x = b in place with the last factorisation.
    pub fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        for (i, &bi) in self.border.iter().enumerate() {
            self.y_border[i] = b[bi];
        }
        for k in 0..self.blocks.len() {
            let (block, y) = (&self.blocks[k], &mut self.y[k]);
            for (v, &c) in y.iter_mut().zip(block) {
                *v = b[c];
            }
            forward(self.factors[k].factor_data(), &self.inverse_diagonals[k], y);
            let (s, w) = (block.len(), self.w_t[k].as_slice());
            for i in 0..self.border.len() {
                self.y_border[i] -= dot(&w[i * s..(i + 1) * s], y);
            }
        }
        self.schur_factor.solve_in_place(&mut self.y_border);
        for (i, &bi) in self.border.iter().enumerate() {
            b[bi] = self.y_border[i];
        }
        for k in 0..self.blocks.len() {
            let (block, y) = (&self.blocks[k], &mut self.y[k]);
            let (s, w) = (block.len(), self.w_t[k].as_slice());
            for (i, x) in self.y_border.iter().enumerate() {
                for (v, wv) in y.iter_mut().zip(&w[i * s..(i + 1) * s]) {
                    *v -= wv * x;
                }
            }
            let factor = &self.factors[k];
            if factor.upper_holds_transpose() {
                backward_mirrored(factor.factor_data(), &self.inverse_diagonals[k], y);
            } else {
                backward(factor.factor_data(), &self.inverse_diagonals[k], y);
            }
            for (v, &c) in y.iter().zip(block) {
                b[c] = *v;
            }
        }
    }
}

/// Increasing indices as runs of consecutive ones.
pub(crate) fn runs(indices: impl Iterator<Item = usize>) -> Vec<std::ops::Range<usize>> {
    let mut runs: Vec<std::ops::Range<usize>> = Vec::new();
    for k in indices {
        match runs.last_mut() {
            Some(run) if run.end == k => run.end += 1,
            _ => runs.push(k..k + 1),
        }
    }
    runs
}

/// [`ArrowLlt::work`] of `blocks` and a border of `r` coordinates.
fn arrow_work(blocks: &[Vec<usize>], r: usize) -> f64 {
    let r = r as f64;
    blocks
        .iter()
        .map(|b| {
            let s = b.len() as f64;
            s * s * s / 3.0 + r * s * s + r * r * s
        })
        .sum::<f64>()
        + r * r * r / 3.0
}

/// The dot product of `a` and `b` (equal lengths) in four interleaved partial sums, added
/// pairwise at the end: the sums of a block's rows and of the border's are a block's
/// length long (28 on the 12-flexible vehicle), and one running sum would wait on each
/// addition's latency in turn. The order is fixed, so the result is the same bits every run.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let (a_rest, b_rest) = (a4.remainder(), b4.remainder());
    let mut sums = [0.0; 4];
    for (x, y) in a4.zip(b4) {
        for ((sum, x), y) in sums.iter_mut().zip(x).zip(y) {
            *sum += x * y;
        }
    }
    for ((sum, x), y) in sums.iter_mut().zip(a_rest).zip(b_rest) {
        *sum += x * y;
    }
    (sums[0] + sums[2]) + (sums[1] + sums[3])
}

/// L y = b in place for L column-major (s × s, lower triangle) with the reciprocals of its
/// diagonal.
fn forward(l: &[f64], inverse_diagonal: &[f64], y: &mut [f64]) {
    let s = y.len();
    for j in 0..s {
        y[j] *= inverse_diagonal[j];
        let yj = y[j];
        for (x, v) in y[j + 1..].iter_mut().zip(&l[j * s + j + 1..(j + 1) * s]) {
            *x -= v * yj;
        }
    }
}

/// Lᵀ x = y in place, L as for [`forward`].
fn backward(l: &[f64], inverse_diagonal: &[f64], y: &mut [f64]) {
    let s = y.len();
    for j in (0..s).rev() {
        y[j] = (y[j] - dot(&l[j * s + j + 1..(j + 1) * s], &y[j + 1..])) * inverse_diagonal[j];
    }
}

/// The connected components of the graph `coupled` on the coordinates not in the border,
/// each in increasing order, ordered by their first coordinate.
fn components(
    n: usize,
    in_border: &[bool],
    coupled: impl Fn(usize, usize) -> bool,
) -> Vec<Vec<usize>> {
    let mut seen = in_border.to_vec();
    let mut blocks = Vec::new();
    for start in 0..n {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let (mut block, mut stack) = (Vec::new(), vec![start]);
        while let Some(v) = stack.pop() {
            block.push(v);
            for u in 0..n {
                if !seen[u] && coupled(u, v) {
                    seen[u] = true;
                    stack.push(u);
                }
            }
        }
        block.sort_unstable();
        blocks.push(block);
    }
    blocks
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An SPD arrow matrix with its rows shuffled: a border of `root` coupled to `branches`
    /// blocks of `size`, the coordinates interleaved (as a formulation numbers them).
    fn shuffled_arrow(root: usize, branches: usize, size: usize) -> DMatrix<f64> {
        let n = root + branches * size;
        let place = |i: usize| (i * 5) % n; // 5 is prime to every n used here (42, 118, 38)
        let mut a = DMatrix::zeros(n, n);
        for j in 0..n {
            for i in 0..n {
                let coupled = i < root || j < root || (i - root) / size == (j - root) / size;
                if coupled {
                    let v = ((i * 7 + j * 7 + i * j) as f64 * 0.37).sin() / n as f64;
                    a[(place(i), place(j))] = v + if i == j { 2.0 } else { 0.0 };
                }
            }
        }
        a
    }

    #[test]
    fn finds_the_arrow_and_solves_as_the_dense_cholesky() {
        for (root, branches, size) in [(6, 4, 9), (6, 4, 28), (3, 5, 7)] {
            let a = shuffled_arrow(root, branches, size);
            let mut arrow = ArrowLlt::detect(&a).expect("an arrow");
            assert_eq!(arrow.shape(), (branches, root));
            let x = DVector::from_fn(a.nrows(), |i, _| (i as f64 * 0.3).cos());
            let mut b = &a * &x;
            arrow.factor(&a).unwrap();
            arrow.solve_in_place(&mut b);
            assert!((b - &x).amax() < 1e-12, "{root} + {branches} × {size}");
        }
    }

    #[test]
    fn indices_are_grouped_into_runs_of_consecutive_ones() {
        assert_eq!(runs([2, 3, 4, 7, 9, 10].into_iter()), [2..5, 7..8, 9..11]);
        assert!(runs(std::iter::empty()).is_empty());
    }

    #[test]
    fn a_coupling_between_blocks_is_refused_and_a_dense_matrix_has_no_arrow() {
        let a = shuffled_arrow(6, 4, 9);
        let mut arrow = ArrowLlt::detect(&a).unwrap();
        let blocks = arrow.blocks.clone();
        let (i, j) = (
            blocks[0][0].max(blocks[1][0]),
            blocks[0][0].min(blocks[1][0]),
        );
        let mut coupled = a.clone();
        coupled[(i, j)] = 0.1;
        coupled[(j, i)] = 0.1;
        assert_eq!(arrow.factor(&coupled), Err(ArrowFailure));
        let dense = DMatrix::from_fn(40, 40, |i, j| if i == j { 50.0 } else { 0.5 });
        assert!(ArrowLlt::detect(&dense).is_none());
    }
}
