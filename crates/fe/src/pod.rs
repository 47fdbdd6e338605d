//! Proper orthogonal modes from a pilot run (docs/methods.md §1.6; [R: Kerschen, Golinval,
//! Vakakis & Bergman 2005, *The method of proper orthogonal decomposition for dynamical
//! characterization and order reduction of mechanical systems: an overview*, Nonlinear
//! Dyn. 41:147–169]) as the dynamic part of a Craig–Bampton basis
//! (`mode_selection: ProperOrthogonal`).
//!
//! A pilot run of the scene keeps, for this body, its lowest K fixed-interface normal modes
//! Φ_K (M_ii-orthonormal, [`candidate_count`]) and records their coordinates η(t_j) at every
//! step (every k-th of a very long pilot): the snapshot matrix H = [η(t_0) … η(t_T)]
//! (K × (T+1)). The facade runs the pilot (`flexmbd::pilot`: this crate runs no
//! simulation) and hands the record to the FE stage in [`BeamBodySpec::pilot`]; the body's
//! dynamic basis is then built here:
//!
//! 1. the snapshot correlation C = H Hᵀ / (T+1) (K × K; the method of snapshots: C's
//!    eigenvectors are H's left singular vectors, its eigenvalues their σ²);
//! 2. the leading n eigenvectors U_n (eigenvalues descending, the lower index first on a
//!    tie) — the n-dimensional subspace that holds the most of the recorded deformation;
//!    since Φ_K is M_ii-orthonormal, ‖Φ_K η‖_M = ‖η‖, so this is the POD in the mass metric.
//!    The snapshots are the displacements, not centred: the mean deflection (the sag under
//!    gravity or centrifugal load) is part of what the basis must hold;
//! 3. Rayleigh–Ritz in the span of Φ_K U_n ([`crate::ritz::rayleigh_ritz`]): vectors
//!    M_ii-orthonormal and K_ii-orthogonal with their Ritz frequencies, so that K_ff stays
//!    block-diagonal and damping, the shape integrals, the B-matrix route and stiffening
//!    work on them unchanged.
//!
//! With n = K the span is that of Φ_K, and the basis is the K lowest modes themselves.

use nalgebra::DMatrix;

use crate::craig_bampton::{InteriorBasis, InteriorOperator};
use crate::error::FeError;
use crate::ritz::rayleigh_ritz;
use crate::selection::ModeSelection;
use crate::spec::BeamBodySpec;

/// The default pilot duration as a fraction of the scene's duration: all of it, since a
/// shorter pilot misses what the scene does later (the measurements: docs/design.md,
/// "Proper orthogonal modes").
pub const DEFAULT_PILOT_FRACTION: f64 = 1.0;

/// What a pilot run recorded for one body.
#[derive(Clone, Debug, PartialEq)]
pub struct PilotRecord {
    /// The dynamic modal coordinates of the pilot body, one row per dynamic mode of its
    /// basis ([`pilot_spec`]: the lowest K modes that are not purely axial and the body's
    /// axial modes, in ascending frequency), one column per sample.
    pub coordinates: DMatrix<f64>,
    /// The time of each sample (s).
    pub times: Vec<f64>,
}

/// K, the number of fixed-interface normal modes the pilot keeps: `mode_candidates`, or
/// max(2 n, 4) for n = `normal_modes`, at most the interior DOFs left after the axial modes.
pub fn candidate_count(spec: &BeamBodySpec) -> usize {
    spec.mode_candidates.unwrap_or_else(|| {
        (2 * spec.normal_modes)
            .max(4)
            .min(crate::selection::interior_after_axial(spec))
    })
}

/// The spec the pilot runs in place of `spec`: the lowest [`candidate_count`] normal modes.
pub fn pilot_spec(spec: &BeamBodySpec) -> BeamBodySpec {
    BeamBodySpec {
        normal_modes: candidate_count(spec),
        mode_selection: ModeSelection::LowestFrequency,
        mode_candidates: None,
        pilot_duration: None,
        pilot: None,
        ..spec.clone()
    }
}

/// How long `spec`'s pilot runs (s) in a scene of `scene_duration` (s).
pub fn pilot_duration(spec: &BeamBodySpec, scene_duration: f64) -> f64 {
    spec.pilot_duration
        .unwrap_or(DEFAULT_PILOT_FRACTION * scene_duration)
}

/// The coefficients U_n (K × n) of the `n` leading proper orthogonal modes of the
/// snapshots `eta` (K × samples) of the candidates, orthonormal columns.
pub fn leading_directions(eta: &DMatrix<f64>, n: usize) -> DMatrix<f64> {
    let k = eta.nrows();
    let samples = eta.ncols().max(1) as f64;
    let c = eta * eta.transpose() / samples;
    let c = (&c + c.transpose()) * 0.5;
    let e = c.symmetric_eigen();
    let mut order: Vec<usize> = (0..k).collect();
    order.sort_by(|&a, &b| {
        e.eigenvalues[b]
            .total_cmp(&e.eigenvalues[a])
            .then(a.cmp(&b))
    });
    e.eigenvectors.select_columns(&order[..n.min(k)])
}

/// The `n` proper orthogonal modes of `candidates` (the pilot's K lowest modes, its
/// `eta` rows in the same order) on `p`, Rayleigh–Ritz'd in their span.
pub fn proper_orthogonal_modes<P: InteriorOperator + ?Sized>(
    p: &P,
    candidates: &InteriorBasis,
    eta: &DMatrix<f64>,
    n: usize,
) -> Result<InteriorBasis, FeError> {
    if eta.nrows() != candidates.vectors.ncols() {
        return Err(FeError::Dimension {
            what: format!("{}: the pilot run's modal coordinates", p.name()),
            detail: format!(
                "{} recorded coordinates for {} candidate modes",
                eta.nrows(),
                candidates.vectors.ncols()
            ),
        });
    }
    let u = leading_directions(eta, n);
    rayleigh_ritz(p, &(&candidates.vectors * u), "proper orthogonal modes")
}
