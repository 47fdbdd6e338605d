//! Ranking fixed-interface normal modes by what the body's loads excite
//! (docs/methods.md §1.6; [R: Craig & Kurdila 2006, modal participation factors and
//! effective modal mass]; [R: Chopra, Dynamics of Structures, modal contribution factors]).
//!
//! For mass-normalised fixed-interface modes φ_k (ω_k²) and the interior load
//! distributions f_l of [`crate::inertia_loads`], the participation factor of mode k in
//! load l is Γ_kl = φ_kᵀ f_l (Γ_kl² is its effective modal mass for that load). A mode with
//! a large effective mass but a high frequency barely deforms under the load, so the rank
//! weighs Γ by the mode's flexibility: the mode's share of the static response,
//!
//!   c_k = Σ_l Γ_kl² / ω_k²  /  Σ_l f_lᵀ K_ii⁻¹ f_l,
//!
//! the part of the loads' static strain energy the mode carries (Chopra's modal
//! contribution to the static response). Over all modes the shares sum to 1. The loads
//! are the unit-motion fields of [`crate::inertia_loads`], so the sum over l adds like
//! with like. A mode the loads cannot excite (Γ_kl = 0 for every l: e.g. an axial mode
//! of a straight beam under transverse loads only) has share 0 and ranks last.

use nalgebra::DMatrix;

use crate::craig_bampton::InteriorOperator;

/// Each candidate's share c_k of the static response of `loads` (n_i × L) on `p`; the
/// candidates are the mass-normalised columns of `vectors` with their `omega_sq`.
pub fn static_response_shares<P: InteriorOperator + ?Sized>(
    p: &P,
    vectors: &DMatrix<f64>,
    omega_sq: &[f64],
    loads: &DMatrix<f64>,
) -> Vec<f64> {
    let deflections = p.solve_block(loads);
    let total: f64 = loads
        .column_iter()
        .zip(deflections.column_iter())
        .map(|(f, u)| f.dot(&u))
        .sum();
    let gamma = vectors.transpose() * loads;
    (0..vectors.ncols())
        .map(|k| {
            let g2: f64 = gamma.row(k).iter().map(|g| g * g).sum();
            if total > 0.0 && omega_sq[k] > 0.0 {
                g2 / omega_sq[k] / total
            } else {
                0.0
            }
        })
        .collect()
}

/// Candidate indices by share, largest first; equal shares keep the lower index (the
/// lower frequency) first, so the order is deterministic.
pub fn rank(shares: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..shares.len()).collect();
    order.sort_by(|&a, &b| shares[b].total_cmp(&shares[a]).then(a.cmp(&b)));
    order
}
