//! The mode-selection kinds of an imported body (`mode_selection`, docs/methods.md §1.6):
//! `Participation` and `LoadRitz` on the sparse pipeline, with the algorithms of the beams
//! ([`crate::participation`], [`crate::ritz`]) run on the sparse fixed-interface problem
//! ([`crate::sparse_reduction::SparseInteriorProblem`]: K_ii⁻¹ F by the sparse Cholesky of
//! K_ii, M_ii products sparse, Rayleigh–Ritz on the small projected matrices). No N × N
//! dense matrix is formed.
//!
//! ## The loads
//!
//! The loads are inertia loads of unit fields, as for the beams ([`crate::inertia_loads`]),
//! but formed on the FE DOFs and carried to the retained coordinates ũ by virtue of u = T ũ:
//! the consistent load of a field u is f̃ = Tᵀ M u (virtual work). Every field that depends
//! on position is divided by R, the largest distance of an FE node from the body origin.
//!
//! **Clamped frame** (the frame's interface point holds the frame DOFs): the beams' loads,
//! restricted to the interior rows i:
//!
//! - translations u = e_a; Euler fields u = e_a × r̄ / R, with node rotation e_a / R where
//!   the node has rotational DOFs; centrifugal fields u = S r̄ / R for the six symmetric
//!   S = e_a e_bᵀ + e_b e_aᵀ (a ≤ b), which span ω × (ω × r̄) over all ω, no node rotation;
//! - the inertia loads of the interfaces' static modes, M̃ X̃_s (the M_ib coupling).
//!
//! On a single-node RBE2 interface T is the identity on that node's six DOFs (the spider has
//! no arm), so a beam exported node by node gets exactly the beam's loads.
//!
//! **Free-free** (no DOF held): the inertia load of a rigid acceleration is M φ_r for a
//! rigid-body mode φ_r, and the elastic free-free modes are M-orthogonal to every φ_r:
//! Γ = φ_kᵀ M φ_r = 0 [R: Craig & Kurdila 2006, *Fundamentals of Structural Dynamics*,
//! 2nd ed.: orthogonality of the rigid-body and elastic modes of an unrestrained
//! structure]. Translations and angular accelerations
//! therefore excite no elastic mode and are left out. What deforms a free body is
//!
//! - the centrifugal loads f̃ = Tᵀ M S r̄ / R (six S as above): ω × (ω × r̄) = (ω ωᵀ −
//!   |ω|² 𝟙) r̄ is not a rigid acceleration field (its gradient is symmetric, not skew);
//! - unit forces and moments at the interface points: f̃ = e_c on each of the six
//!   coordinates of every interface point.
//!
//! A load's self-equilibrated part, f − M Φ_r Φ_rᵀ f (the inertia-relief load of an
//! unrestrained structure, Craig & Kurdila 2006), has the same participation factors, φ_kᵀ (f − M Φ_r Φ_rᵀ f) = φ_kᵀ f, so the
//! loads are used as they are. These loads have different units (kg m for the centrifugal
//! fields, N and N m at the interfaces) and a free body has no K_ii⁻¹ for the shares'
//! total static response, so each load weighs the same: the share of candidate k is
//!
//!   c_k = (1/L') Σ_l (Γ_kl² / ω_k²) / Σ_j (Γ_jl² / ω_j²),
//!
//! over the L' loads that excite some candidate (the ranking of [`crate::participation`]
//! with the static response of each load measured on the candidates). A load counts when
//! the candidates' effective mass Σ_j Γ_jl² exceeds [`UNFELT_LOAD`] times
//! Σ_i f_i² / M̃_ii (the diagonal estimate of f_lᵀ M̃⁻¹ f_l, all modes' together):
//! otherwise its shares would be its round-off, normalised.
//!
//! ## Free-free Ritz vectors
//!
//! The static response of a free body is that of inertia relief [R: Craig & Kurdila 2006]:
//! under the self-equilibrated part g = f − M̃ Φ_r Φ_rᵀ f of a load (Φ_r the M̃-orthonormal
//! rigid-body modes, found with the elastic ones by the Lanczos solver), the elastic
//! deflection x solves K̃ x = g with Φ_rᵀ M̃ x = 0. K̃ is singular; with the factor of
//! K̃ − σ M̃ (σ < 0, the eigen-solver's default shift, [`crate::sparse_eigen::default_shift`])
//! K̃ x = g reads (K̃ − σM̃) x = g − σ M̃ x, solved by the fixed point
//!
//!   x ← P_r (K̃ − σM̃)⁻¹ (g − σ M̃ x),   P_r = 𝟙 − Φ_r Φ_rᵀ M̃,
//!
//! whose error on elastic mode k shrinks by |σ| / (ω_k² + |σ|) per sweep (stopped at a
//! relative change of [`FLEXIBILITY_TOL`]; refused after [`FLEXIBILITY_SWEEPS`]). The block
//! Ritz sequence of [`crate::ritz`] then runs on this operator with the free-free loads
//! above, its vectors kept M̃-orthogonal to Φ_r, and the Rayleigh–Ritz step gives elastic
//! vectors with positive Ritz frequencies.

use nalgebra::{DMatrix, DVector, Vector3};
use sprs::CsMat;

use super::interfaces::RetainedMap;
use super::{ImportedBodySpec, invalid};
use crate::assembly::{DofSets, dof_slot};
use crate::craig_bampton::{InteriorBasis, InteriorOperator};
use crate::error::FeError;
use crate::import::FeModel;
use crate::inertia_loads::centrifugal_tensors;
use crate::modal::{Eigenpairs, fix_signs, generalized_eigen};
use crate::selection::ModeSelection;
use crate::sparse::{Columns, ShiftedCholesky, symmetric_matvec};
use crate::sparse_reduction::{SparseInteriorProblem, lowest_interior_modes, sparse_times_dense};
use crate::{participation, pod, ritz};
use flexmbd_core::Dim;

/// Relative effective mass (Σ_j Γ_jl² over f_lᵀ M⁻¹ f_l) below which a load counts as
/// exciting none of a free body's candidates (module docs).
pub const UNFELT_LOAD: f64 = 1e-12;

/// The candidate modes of `Participation`: `mode_candidates`, or max(2 n, 4) for
/// n = `normal_modes` (the pilot's default of the beams' proper orthogonal modes) but at
/// most the `available` modes. An explicit count above `available` is refused by name.
pub fn candidate_count(
    spec: &ImportedBodySpec,
    available: usize,
    body: &str,
) -> Result<usize, FeError> {
    match spec.mode_candidates {
        Some(c) if c > available => Err(invalid(
            format!("{body}.mode_candidates"),
            c,
            format!("the model has only {available} normal modes to take candidates from"),
        )),
        Some(c) => Ok(c),
        None => Ok((2 * spec.normal_modes).max(4).min(available)),
    }
}

/// The dynamic basis of a clamped imported body (module docs) on the sparse problem `p` of
/// the retained coordinates split by `sets`; `mt` = M̃, `tol` the eigen-solver's residual.
pub fn clamped_basis(
    spec: &ImportedBodySpec,
    model: &FeModel,
    map: &RetainedMap,
    mt: &CsMat<f64>,
    sets: &DofSets,
    p: &SparseInteriorProblem,
    tol: f64,
    singular: &dyn Fn(String) -> FeError,
) -> Result<InteriorBasis, FeError> {
    let n = spec.normal_modes;
    let ni = p.n_interior();
    if n == 0 {
        return Ok(InteriorBasis {
            vectors: DMatrix::zeros(ni, 0),
            omega_sq: Vec::new(),
        });
    }
    if n > ni {
        return Err(invalid(
            format!("{}.normal_modes", p.name),
            n,
            format!("the clamped model has only {ni} interior coordinates"),
        ));
    }
    let loads = clamped_loads(model, map, mt, sets, p.x_static);
    match spec.mode_selection {
        ModeSelection::LoadRitz => ritz::load_ritz(p, &loads, n, &DMatrix::zeros(ni, 0)),
        ModeSelection::Participation => {
            let c = candidate_count(spec, ni, p.name)?;
            let candidates = lowest_interior_modes(p.kii, p.mii, c, tol, None, &sets.i, singular)?;
            let shares = participation::static_response_shares(
                p,
                &candidates.vectors,
                &candidates.omega_sq,
                &loads,
            );
            Ok(keep_ranked(&candidates, &shares, n))
        }
        ModeSelection::ProperOrthogonal => {
            // The pilot kept the lowest K modes by this same call (LowestFrequency with
            // K normal modes): its record holds their coordinates.
            let eta = spec.pilot_coordinates(p.name)?;
            let candidates =
                lowest_interior_modes(p.kii, p.mii, eta.nrows(), tol, None, &sets.i, singular)?;
            pod::proper_orthogonal_modes(
                p,
                &InteriorBasis {
                    vectors: candidates.vectors,
                    omega_sq: candidates.omega_sq,
                },
                eta,
                n,
            )
        }
        ModeSelection::LowestFrequency => {
            let lowest = lowest_interior_modes(p.kii, p.mii, n, tol, None, &sets.i, singular)?;
            Ok(InteriorBasis {
                vectors: lowest.vectors,
                omega_sq: lowest.omega_sq,
            })
        }
    }
}

/// The `n` proper orthogonal modes of a free body (docs/methods.md §1.6, [`crate::pod`])
/// from its free-free elastic `candidates` (M-orthonormal, K-orthogonal: the pilot's lowest
/// K modes) and the pilot's record `eta` of their coordinates: the leading directions U of
/// the snapshots, then Rayleigh–Ritz in the span of Φ U, whose projected matrices are
/// Uᵀ diag(ω²) U and Uᵀ U by the candidates' orthogonality.
pub fn free_free_proper_orthogonal(
    candidates: &Eigenpairs,
    eta: &DMatrix<f64>,
    n: usize,
    body: &str,
) -> Result<(DMatrix<f64>, Vec<f64>), FeError> {
    let u = pod::leading_directions(eta, n);
    let lambda = DMatrix::from_diagonal(&DVector::from_column_slice(&candidates.omega_sq));
    let sym = |a: DMatrix<f64>| (&a + a.transpose()) * 0.5;
    let k = sym(u.transpose() * lambda * &u);
    let m = sym(u.transpose() * &u);
    let e = generalized_eigen(&k, &m, &format!("{body}: proper orthogonal modes"))?;
    let mut vectors = &candidates.vectors * u * e.vectors;
    fix_signs(&mut vectors);
    Ok((vectors, e.omega_sq))
}

/// The free-free elastic modes ranked by participation (module docs): of the
/// `candidates` (mass-normalised, ω² ascending) on the retained coordinates, the
/// `normal_modes` with the largest shares, in ascending frequency.
pub fn free_free_participation(
    spec: &ImportedBodySpec,
    model: &FeModel,
    map: &RetainedMap,
    mt: &CsMat<f64>,
    n_points: usize,
    candidates: &Eigenpairs,
) -> (DMatrix<f64>, Vec<f64>) {
    let loads = free_free_loads(model, map, n_points);
    let gamma = candidates.vectors.transpose() * &loads;
    let m_diagonal = Columns::of(mt);
    let w2 = &candidates.omega_sq;
    let k = w2.len();
    let mut shares = vec![0.0; k];
    let mut counted = 0;
    for l in 0..loads.ncols() {
        let response: Vec<f64> = (0..k)
            .map(|j| {
                if w2[j] > 0.0 {
                    gamma[(j, l)].powi(2) / w2[j]
                } else {
                    0.0
                }
            })
            .collect();
        let total: f64 = response.iter().sum();
        // Σ_j Γ_jl² against f_lᵀ M⁻¹ f_l (≈ Σ_i f_i² / M_ii), the effective mass of every
        // mode together: a load the candidates do not feel is left out, or its
        // normalised round-off would take a share.
        let captured: f64 = (0..k).map(|j| gamma[(j, l)].powi(2)).sum();
        let reach: f64 = (0..loads.nrows())
            .map(|i| (i, m_diagonal.get(i, i)))
            .filter(|&(_, d)| d > 0.0)
            .map(|(i, d)| loads[(i, l)].powi(2) / d)
            .sum();
        if total > 0.0 && captured > UNFELT_LOAD * reach {
            counted += 1;
            for (s, r) in shares.iter_mut().zip(&response) {
                *s += r / total;
            }
        }
    }
    if counted > 0 {
        shares.iter_mut().for_each(|s| *s /= counted as f64);
    }
    let kept = keep_ranked(candidates, &shares, spec.normal_modes);
    (kept.vectors, kept.omega_sq)
}

/// The loads of a free body on the retained coordinates (module docs): the six centrifugal
/// fields, then unit forces and moments at each of the `n_points` interface points.
fn free_free_loads(model: &FeModel, map: &RetainedMap, n_points: usize) -> DMatrix<f64> {
    let mut loads: Vec<DVector<f64>> = centrifugal_fields(model)
        .iter()
        .map(|u| consistent_load(model, map, u))
        .collect();
    for p in 0..n_points {
        for c in 0..6 {
            let mut f = DVector::zeros(map.n_retained());
            f[map.point_start(p) + c] = 1.0;
            loads.push(f);
        }
    }
    DMatrix::from_columns(&loads)
}

/// Load-dependent Ritz vectors of a free body (module docs, "Free-free Ritz vectors") on
/// the retained (K̃, M̃) with its M̃-orthonormal rigid-body modes `rigid` (Ñ × 6):
/// (vectors, Ritz ω²).
pub fn free_free_ritz(
    spec: &ImportedBodySpec,
    model: &FeModel,
    map: &RetainedMap,
    kt: &CsMat<f64>,
    mt: &CsMat<f64>,
    rigid: &DMatrix<f64>,
    body: &str,
) -> Result<(DMatrix<f64>, Vec<f64>), FeError> {
    let n_points = (map.n_retained() - map.n_independent) / 6;
    let loads = free_free_loads(model, map, n_points);
    let shift = crate::sparse_eigen::default_shift(kt, mt)?;
    let flexibility = ElasticFlexibility {
        kt,
        mt,
        rigid,
        m_rigid: sparse_times_dense(mt, rigid),
        chol: ShiftedCholesky::new(kt, mt, shift)?,
        name: body,
        unconverged: std::cell::Cell::new(false),
    };
    let basis = ritz::load_ritz(&flexibility, &loads, spec.normal_modes, rigid)?;
    if flexibility.unconverged.get() {
        return Err(invalid(
            format!("{body}.mode_selection"),
            "LoadRitz",
            format!(
                "the free body's static responses did not converge in {FLEXIBILITY_SWEEPS} \
                 sweeps (its first elastic ω² is far below the shift {shift:e} of the \
                 flexibility solve): take Participation or LowestFrequency"
            ),
        ));
    }
    Ok((basis.vectors, basis.omega_sq))
}

/// Largest number of refinement sweeps of a free body's static response (module docs).
pub const FLEXIBILITY_SWEEPS: usize = 200;

/// Relative change (max norm) at which a refinement sweep counts as converged.
pub const FLEXIBILITY_TOL: f64 = 1e-14;

/// The elastic flexibility of a free body as a fixed-interface operator for the Ritz
/// sequence: `solve_block` gives x = G_e f, the deflection M̃-orthogonal to the rigid-body
/// modes Φ_r under the self-equilibrated part g = f − M̃ Φ_r Φ_rᵀ f of the load, i.e. the
/// solution of K̃ x = g with Φ_rᵀ M̃ x = 0 (module docs).
struct ElasticFlexibility<'a> {
    kt: &'a CsMat<f64>,
    mt: &'a CsMat<f64>,
    rigid: &'a DMatrix<f64>,
    m_rigid: DMatrix<f64>,
    chol: ShiftedCholesky,
    name: &'a str,
    /// Set when a solve ended its sweeps unconverged.
    unconverged: std::cell::Cell<bool>,
}

impl ElasticFlexibility<'_> {
    fn shifted_solve(&self, rhs: &mut DMatrix<f64>) {
        let (rows, cols) = rhs.shape();
        let mut scratch = self.chol.solve_scratch(cols);
        let view = faer::MatMut::from_column_major_slice_mut(rhs.as_mut_slice(), rows, cols);
        self.chol.solve_in_place(view, &mut scratch);
    }

    /// x − Φ_r Φ_rᵀ M̃ x.
    fn remove_rigid(&self, x: &DMatrix<f64>) -> DMatrix<f64> {
        x - self.rigid * (self.m_rigid.transpose() * x)
    }
}

impl InteriorOperator for ElasticFlexibility<'_> {
    fn name(&self) -> &str {
        self.name
    }
    fn n_interior(&self) -> usize {
        self.kt.rows()
    }
    fn solve_block(&self, b: &DMatrix<f64>) -> DMatrix<f64> {
        let g = b - &self.m_rigid * (self.rigid.transpose() * b);
        let sigma = self.chol.shift;
        let mut x = g.clone();
        self.shifted_solve(&mut x);
        x = self.remove_rigid(&x);
        for _ in 0..FLEXIBILITY_SWEEPS {
            let mut next = &g - sparse_times_dense(self.mt, &x) * sigma;
            self.shifted_solve(&mut next);
            next = self.remove_rigid(&next);
            let change = (&next - &x).amax();
            x = next;
            if change <= FLEXIBILITY_TOL * x.amax() {
                return x;
            }
        }
        self.unconverged.set(true);
        x
    }
    fn mass_times(&self, v: &DVector<f64>) -> DVector<f64> {
        let mut y = DVector::zeros(v.len());
        symmetric_matvec(&Columns::of(self.mt), v.as_slice(), y.as_mut_slice());
        y
    }
    fn stiffness_form(&self, v: &DMatrix<f64>) -> DMatrix<f64> {
        v.transpose() * sparse_times_dense(self.kt, v)
    }
    fn mass_form(&self, v: &DMatrix<f64>) -> DMatrix<f64> {
        v.transpose() * sparse_times_dense(self.mt, v)
    }
}

/// The `n` candidates with the largest shares, in ascending frequency.
fn keep_ranked(candidates: &Eigenpairs, shares: &[f64], n: usize) -> InteriorBasis {
    let mut keep: Vec<usize> = participation::rank(shares).into_iter().take(n).collect();
    keep.sort_unstable();
    InteriorBasis {
        vectors: candidates.vectors.select_columns(&keep),
        omega_sq: keep.iter().map(|&k| candidates.omega_sq[k]).collect(),
    }
}

/// The interior loads of a clamped body (module docs): translations, Euler fields,
/// centrifugal fields, then the static modes' inertia loads, n_i × L.
fn clamped_loads(
    model: &FeModel,
    map: &RetainedMap,
    mt: &CsMat<f64>,
    sets: &DofSets,
    x_static: &DMatrix<f64>,
) -> DMatrix<f64> {
    let scale = 1.0 / r_max(model);
    let zero = Vector3::zeros();
    let mut fields = Vec::new();
    for a in 0..3 {
        fields.push(rigid_field(model, &Vector3::ith(a, 1.0), &zero));
    }
    for a in 0..3 {
        fields.push(rigid_field(model, &zero, &Vector3::ith(a, scale)));
    }
    fields.extend(centrifugal_fields(model));
    let mut columns: Vec<DVector<f64>> = fields
        .iter()
        .map(|u| consistent_load(model, map, u))
        .collect();
    let static_loads = sparse_times_dense(mt, x_static);
    columns.extend(static_loads.column_iter().map(|c| c.into_owned()));
    DMatrix::from_fn(sets.i.len(), columns.len(), |a, l| columns[l][sets.i[a]])
}

/// The largest distance of an FE node from the body origin (1 when all sit at it).
fn r_max(model: &FeModel) -> f64 {
    let r = model
        .mesh
        .nodes
        .positions
        .iter()
        .map(|x| x.norm())
        .fold(0.0, f64::max);
    if r > 0.0 { r } else { 1.0 }
}

/// u = t + θ × r̄ on the translational DOFs, θ on the rotational ones.
fn rigid_field(model: &FeModel, t: &Vector3<f64>, theta: &Vector3<f64>) -> DVector<f64> {
    let positions = &model.mesh.nodes.positions;
    DVector::from_iterator(
        model.n_dofs(),
        model.dofs.iter().map(|d| {
            let du = t + theta.cross(&positions[d.node]);
            match dof_slot(Dim::Spatial, d.dof) {
                Some(s) if s < 3 => du[s],
                Some(s) => theta[s - 3],
                None => 0.0,
            }
        }),
    )
}

/// The six centrifugal fields S r̄ / R on the FE DOFs (no node rotation).
fn centrifugal_fields(model: &FeModel) -> Vec<DVector<f64>> {
    let scale = 1.0 / r_max(model);
    let positions = &model.mesh.nodes.positions;
    centrifugal_tensors(Dim::Spatial)
        .into_iter()
        .map(|s| {
            let s = s * scale;
            DVector::from_iterator(
                model.n_dofs(),
                model
                    .dofs
                    .iter()
                    .map(|d| match dof_slot(Dim::Spatial, d.dof) {
                        Some(a) if a < 3 => (s * positions[d.node])[a],
                        _ => 0.0,
                    }),
            )
        })
        .collect()
}

/// f̃ = Tᵀ M u on the retained coordinates.
fn consistent_load(model: &FeModel, map: &RetainedMap, u: &DVector<f64>) -> DVector<f64> {
    let mut mu = vec![0.0; u.len()];
    symmetric_matvec(&Columns::of(&model.m), u.as_slice(), &mut mu);
    let mut f = DVector::zeros(map.n_retained());
    for (value, (r, c)) in map.t.iter() {
        f[c] += value * mu[r];
    }
    f
}
