//! The choice of a structured factorisation for the leading matrix f_q, made once at the
//! first factorisation from the matrix's own non-zeros (docs/methods.md §5.2, "Factorising
//! f_q"): the arrow form of a tree in relative coordinates ([`crate::arrow_llt`]), else the
//! sparse Cholesky of a large system with a sparse factor ([`crate::sparse_llt`]), else none
//! (the dense kernels of [`crate::lu`]). Only symmetric positive definite matrices are
//! concerned; when a structured factorisation fails (the structure changed, or the matrix is
//! not positive definite) the integrator falls back to the dense kernels for that
//! factorisation, and for the rest of the run if the structure was lost.

use nalgebra::{DMatrix, DVector};

use crate::arrow_llt::ArrowLlt;
use crate::sparse_llt::{SPARSE_FROM, SparseLlt};

/// A structured Cholesky factorisation of the leading matrix.
pub(crate) enum StructuredLlt {
    Arrow(ArrowLlt),
    Sparse(SparseLlt),
}

/// What a failed structured factorisation means for the next ones.
pub(crate) enum Fallback {
    /// This matrix only (not positive definite): try again next time.
    ThisTime,
    /// The structure no longer holds: dense from now on.
    FromNowOn,
}

impl StructuredLlt {
    /// The structured factorisation that pays for `lead`, if any.
    pub(crate) fn choose(lead: &DMatrix<f64>) -> Option<Self> {
        if let Some(arrow) = ArrowLlt::detect(lead) {
            return Some(StructuredLlt::Arrow(arrow));
        }
        if lead.nrows() >= SPARSE_FROM {
            return SparseLlt::new(lead)
                .ok()
                .filter(SparseLlt::worthwhile)
                .map(StructuredLlt::Sparse);
        }
        None
    }

    /// Factorise `lead` (its lower triangle).
    pub(crate) fn factor(&mut self, lead: &DMatrix<f64>) -> Result<(), Fallback> {
        match self {
            // An arrow whose blocks became coupled is refused like an indefinite one; the
            // coupling check is the cheaper question, so ask it again to tell them apart.
            StructuredLlt::Arrow(arrow) => arrow.factor(lead).map_err(|_| {
                if arrow.still_holds(lead) {
                    Fallback::ThisTime
                } else {
                    Fallback::FromNowOn
                }
            }),
            // The sparse pattern grows by itself: a failure is numerical.
            StructuredLlt::Sparse(sparse) => sparse.factor(lead).map_err(|_| Fallback::ThisTime),
        }
    }

    /// Solve with the last factorisation.
    pub(crate) fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        match self {
            StructuredLlt::Arrow(arrow) => arrow.solve_in_place(b),
            StructuredLlt::Sparse(sparse) => sparse.solve_in_place(b),
        }
    }
}
