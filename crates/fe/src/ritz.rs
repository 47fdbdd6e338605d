//! Load-dependent Ritz vectors (docs/methods.md §1.6; [R: Wilson, Yuan & Dickens 1982,
//! Earthquake Eng. Struct. Dyn. 10:813–821]) as the dynamic part of a Craig–Bampton basis.
//!
//! On the fixed-interface problem (K_ii, M_ii) and the interior load distributions
//! F = [f_1 … f_L] of [`crate::inertia_loads`], a **block** Krylov sequence:
//!
//! 1. first block: the static responses K_ii⁻¹ F;
//! 2. every candidate is M-orthogonalised against all kept vectors (and the vectors to
//!    stay clear of) by classical Gram–Schmidt, twice; a candidate whose M-norm falls to
//!    [`DEFLATION_TOL`] of its norm before orthogonalisation adds nothing new and is dropped;
//! 3. of the survivors the one with the largest M-norm is kept (M-normalised) — the
//!    largest static response first, so that a truncated block keeps the loads that deform
//!    the body most — and the rest are orthogonalised again, until the block is used up;
//! 4. next block: K_ii⁻¹ M_ii times the vectors kept from the last block; repeat until
//!    n vectors are kept;
//! 5. Rayleigh–Ritz: the n × n problem (Vᵀ K_ii V) q = ω̃² (Vᵀ M_ii V) q gives vectors
//!    V q that are M_ii-orthonormal and K_ii-orthogonal, with Ritz frequencies ω̃² ascending
//!    (signs fixed as for normal modes: runs are bit-identical).
//!
//! Why a block and not Wilson–Yuan–Dickens' one vector at a time over one combined load:
//! a body's loads have different units and their mix changes over a run (gravity, spin-up,
//! interface forces), so no fixed combination stands for them; the first block holds the
//! static response to **each** load, so every static deflection of the load set is
//! reproduced exactly once n reaches the number of independent loads.
//!
//! The sequence runs on any [`InteriorOperator`]: the dense blocks of a built-in beam or the
//! sparse ones of an imported body ([`crate::imported::selection`]).
//!
//! Step 5 makes the basis look like a normal-mode basis to everything downstream:
//! K_ff stays block-diagonal with ω̃² on the dynamic block, so modal damping, the shape
//! integrals, the B-matrix route and stiffening work on it unchanged.

use nalgebra::{DMatrix, DVector};

use crate::craig_bampton::{InteriorBasis, InteriorOperator};
use crate::error::FeError;
use crate::modal::{fix_signs, generalized_eigen};

/// Relative M-norm below which an orthogonalised candidate counts as already in the span.
pub const DEFLATION_TOL: f64 = 1e-10;

/// `n` load-dependent Ritz vectors of `p` started from the interior `loads` (n_i × L),
/// kept M-orthogonal to the M-orthonormal columns of `avoid` (n_i × q; e.g. normal modes
/// kept beside them). Refused, naming `normal_modes`, when the sequence spans fewer than
/// `n` independent vectors.
pub fn load_ritz<P: InteriorOperator + ?Sized>(
    p: &P,
    loads: &DMatrix<f64>,
    n: usize,
    avoid: &DMatrix<f64>,
) -> Result<InteriorBasis, FeError> {
    let ni = p.n_interior();
    let mut span = MSpan::new(p);
    for c in avoid.column_iter() {
        span.push(c.into_owned());
    }
    let fixed = span.len();
    let mut block = p.solve_block(loads);
    while span.len() - fixed < n {
        let kept = keep_from_block(&mut span, &block, fixed + n);
        if kept.is_empty() {
            return Err(FeError::Invalid(flexmbd_core::InvalidValue::new(
                "normal_modes",
                n,
                format!(
                    "the load-dependent Ritz sequence of {} spans only {} independent vectors \
                     (its inertia and interface loads excite no more; methods.md §1.6)",
                    p.name(),
                    span.len() - fixed
                ),
            )));
        }
        let next = DMatrix::from_fn(ni, kept.len(), |i, j| kept[j].1[i]);
        block = p.solve_block(&next);
    }
    let v = DMatrix::from_fn(ni, n, |i, j| span.vectors[fixed + j][i]);
    rayleigh_ritz(p, &v, "load-dependent Ritz vectors")
}

/// Keep vectors of `block` (largest orthogonalised M-norm first) until it is used up or
/// `span` holds `limit` vectors; returns the kept vectors with M times them.
fn keep_from_block<P: InteriorOperator + ?Sized>(
    span: &mut MSpan<P>,
    block: &DMatrix<f64>,
    limit: usize,
) -> Vec<(DVector<f64>, DVector<f64>)> {
    let mut candidates: Vec<(DVector<f64>, f64)> = block
        .column_iter()
        .map(|c| {
            let c = c.into_owned();
            let norm = span.norm(&c);
            (c, norm)
        })
        .collect();
    let mut kept = Vec::new();
    while span.len() < limit {
        let mut best: Option<(usize, DVector<f64>, f64)> = None;
        let mut survivors = Vec::new();
        for (c, raw) in candidates {
            let r = span.orthogonalise(&c);
            let rn = span.norm(&r);
            // A NaN norm counts as no new direction either.
            let new_direction = rn > DEFLATION_TOL * raw;
            if !new_direction {
                continue;
            }
            if best.as_ref().is_none_or(|b| rn > b.2) {
                best = Some((survivors.len(), r.clone(), rn));
            }
            survivors.push((r, raw));
        }
        let Some((index, r, rn)) = best else {
            break;
        };
        survivors.remove(index);
        let v = r / rn;
        kept.push((v.clone(), span.op.mass_times(&v)));
        span.push(v);
        candidates = survivors;
    }
    kept
}

/// Rayleigh–Ritz in the span of the independent columns of `v` (n_i × n): the n × n
/// problem (Vᵀ K_ii V) q = ω̃² (Vᵀ M_ii V) q gives vectors V q, M_ii-orthonormal and
/// K_ii-orthogonal, with their Ritz frequencies ω̃² ascending and signs fixed as for normal
/// modes (step 5 above; also [`crate::pod`]). `what` names the vectors in errors.
pub fn rayleigh_ritz<P: InteriorOperator + ?Sized>(
    p: &P,
    v: &DMatrix<f64>,
    what: &str,
) -> Result<InteriorBasis, FeError> {
    let sym = |a: DMatrix<f64>| (&a + a.transpose()) * 0.5;
    let k = sym(p.stiffness_form(v));
    let m = sym(p.mass_form(v));
    let e = generalized_eigen(&k, &m, &format!("{}: {what}", p.name()))?;
    let mut vectors = v * e.vectors;
    fix_signs(&mut vectors);
    Ok(InteriorBasis {
        vectors,
        omega_sq: e.omega_sq,
    })
}

/// M-orthonormal vectors with M times each, for Gram–Schmidt in the M inner product.
struct MSpan<'a, P: ?Sized> {
    op: &'a P,
    vectors: Vec<DVector<f64>>,
    mass_times: Vec<DVector<f64>>,
}

impl<'a, P: InteriorOperator + ?Sized> MSpan<'a, P> {
    fn new(op: &'a P) -> Self {
        MSpan {
            op,
            vectors: Vec::new(),
            mass_times: Vec::new(),
        }
    }

    fn len(&self) -> usize {
        self.vectors.len()
    }

    fn push(&mut self, v: DVector<f64>) {
        self.mass_times.push(self.op.mass_times(&v));
        self.vectors.push(v);
    }

    fn norm(&self, c: &DVector<f64>) -> f64 {
        c.dot(&self.op.mass_times(c)).max(0.0).sqrt()
    }

    /// c minus its M-projection on the span, classical Gram–Schmidt twice.
    fn orthogonalise(&self, c: &DVector<f64>) -> DVector<f64> {
        let mut r = c.clone();
        for _ in 0..2 {
            let coefficients: Vec<f64> = self.mass_times.iter().map(|mv| mv.dot(&r)).collect();
            for (v, a) in self.vectors.iter().zip(coefficients) {
                r.axpy(-a, v, 1.0);
            }
        }
        r
    }
}
