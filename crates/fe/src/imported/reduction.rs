//! The modes of an imported body on its retained coordinates ũ (docs/methods.md §1.3–§1.4):
//! K̃ = Tᵀ K T, M̃ = Tᵀ M T, then either
//!
//! - a **clamped** frame (interface point F): the r set is F's six coordinates, the b set
//!   the six of every `boundary` interface, i the rest, and Craig–Bampton on sparse
//!   matrices ([`crate::sparse_reduction`]);
//! - or **free-free**: the 6 + n_d lowest modes of (K̃, M̃), of which the six lowest must be
//!   rigid-body modes (|ω²| below 1e-6 of the first elastic ω²) and are dropped.
//!
//! A clamped frame with `reference: Buckens` then has its modes projected M̃-orthogonally
//! off the rigid-body modes of the retained coordinates ([`retained_rigid_modes`]) by
//! [`crate::reference::buckens_basis`], the beams' projection: X̃ ← X̃ − R̃ (R̃ᵀM̃R̃)⁻¹ R̃ᵀM̃X̃.
//! The frame point's six rows are then no longer zero.
//!
//! No dense matrix larger than Ñ × n is formed.

use nalgebra::DMatrix;
use sprs::CsMat;

use super::interfaces::{ResolvedInterface, RetainedMap};
use super::{ImportedBodySpec, ImportedFrame, POINT_DOFS, invalid, selection};
use crate::assembly::DofSets;
use crate::craig_bampton::Reduction;
use crate::error::FeError;
use crate::import::FeModel;
use crate::modal::Eigenpairs;
use crate::reference::{self, ReferenceCondition};
use crate::selection::ModeSelection;
use crate::sparse_eigen::{SparseEigenOptions, lowest_modes};
use crate::sparse_reduction::{
    reduce_sparse, reduce_sparse_with_basis, sparse_times_dense, symmetrise,
};

/// Relative size (to the first elastic ω²) below which a free-free mode counts as rigid.
pub const RIGID_MODE_TOL: f64 = 1e-6;

/// The eigen-solver's bound on the backward error η of each pair (`sparse_eigen`'s module
/// docs), its default: round-off leaves η near 10⁻¹⁶ even for a rigid-body mode of a free
/// body with stiff interface spiders, whose relative residual stalls near 10⁻¹⁰.
pub const EIGEN_TOL: f64 = 1e-12;

fn eigen_options() -> SparseEigenOptions {
    SparseEigenOptions {
        tol: EIGEN_TOL,
        ..SparseEigenOptions::default()
    }
}

/// The modes on the retained coordinates.
#[derive(Clone, Debug)]
pub struct RetainedModes {
    /// X̃ (Ñ × n): static modes first, then normal modes.
    pub x: DMatrix<f64>,
    /// K_ff = X̃ᵀ K̃ X̃ (symmetrised).
    pub k_ff: DMatrix<f64>,
    /// ω² of the normal modes, ascending.
    pub omega_sq: Vec<f64>,
    /// The interface points whose coordinates are the frame's (clamped) — none when free.
    pub frame_point: Option<usize>,
    /// The boundary interface points, in mode order (six static modes each).
    pub boundary_points: Vec<usize>,
}

/// K̃ and M̃, then the modes (module docs).
pub fn reduce(
    spec: &ImportedBodySpec,
    model: &FeModel,
    interfaces: &[ResolvedInterface],
    map: &RetainedMap,
    body: &str,
) -> Result<RetainedModes, FeError> {
    let kt = project(&model.k, &map.t);
    let mt = project(&model.m, &map.t);
    let point = |name: &str| interfaces.iter().position(|i| i.name == name);
    let boundary_points: Vec<usize> = spec.boundary.iter().filter_map(|b| point(b)).collect();
    let (x, k_ff, omega_sq, frame_point) = match &spec.frame {
        ImportedFrame::FreeFree => {
            let (x, w2) = match spec.mode_selection {
                ModeSelection::LowestFrequency => free_free(&kt, &mt, spec.normal_modes, body)?,
                ModeSelection::Participation => {
                    let available = kt.rows().saturating_sub(7);
                    if spec.normal_modes > available {
                        return Err(FeError::TooManyModes {
                            requested: spec.normal_modes,
                            available,
                        });
                    }
                    let c = selection::candidate_count(spec, available, body)?;
                    let (x, w2) = free_free(&kt, &mt, c, body)?;
                    let candidates = Eigenpairs {
                        omega_sq: w2,
                        vectors: x,
                    };
                    selection::free_free_participation(
                        spec,
                        model,
                        map,
                        &mt,
                        interfaces.len(),
                        &candidates,
                    )
                }
                ModeSelection::LoadRitz => {
                    let (_, rigid) = free_free_pairs(&kt, &mt, 0, body)?;
                    selection::free_free_ritz(spec, model, map, &kt, &mt, &rigid, body)?
                }
                ModeSelection::ProperOrthogonal => {
                    let eta = spec.pilot_coordinates(body)?;
                    let (x, w2) = free_free(&kt, &mt, eta.nrows(), body)?;
                    let candidates = Eigenpairs {
                        omega_sq: w2,
                        vectors: x,
                    };
                    selection::free_free_proper_orthogonal(
                        &candidates,
                        eta,
                        spec.normal_modes,
                        body,
                    )?
                }
            };
            let k_ff = symmetrise(&(x.transpose() * sparse_times_dense(&kt, &x)));
            (x, k_ff, w2, None)
        }
        ImportedFrame::Interface(name) => {
            let frame = point(name).unwrap_or_default();
            let mut red = clamped(&kt, &mt, model, map, frame, &boundary_points, spec, body)?;
            if spec.reference == ReferenceCondition::Buckens {
                // The same deformations modulo rigid motion: K_ff stays (K̃ R̃ = 0).
                let r = retained_rigid_modes(model, interfaces, map);
                red.x = reference::buckens_basis(&red.x, &mt, &r, body)?.0;
            }
            (red.x, red.k_ff, red.omega_sq, Some(frame))
        }
    };
    Ok(RetainedModes {
        x,
        k_ff,
        omega_sq,
        frame_point,
        boundary_points,
    })
}

/// The six rigid-body modes R̃ on the retained coordinates ũ ([`reference::rigid_row`] of
/// every independent FE DOF at its node, and of every interface point's six coordinates at
/// the point). Both couplings carry a rigid motion exactly (an RBE2 spider by construction;
/// an RBE3 point at its nodes' centroid takes their mean translation and, since
/// Σ d_s × (θ × d_s) = J θ, their rotation), so T R̃ is the FE model's rigid-body modes
/// and X̃ M̃-orthogonal to R̃ makes X = T X̃ M-orthogonal to them.
pub fn retained_rigid_modes(
    model: &FeModel,
    interfaces: &[ResolvedInterface],
    map: &RetainedMap,
) -> DMatrix<f64> {
    let mut dofs = vec![(nalgebra::Vector3::zeros(), crate::reduced::Dof::Ux); map.n_retained()];
    for (row, d) in model.dofs.iter().enumerate() {
        if let Some(c) = map.independent[row] {
            dofs[c] = (model.mesh.nodes.positions[d.node], d.dof);
        }
    }
    for (p, itf) in interfaces.iter().enumerate() {
        for (c, dof) in POINT_DOFS.into_iter().enumerate() {
            dofs[map.point_start(p) + c] = (itf.point, dof);
        }
    }
    reference::rigid_modes_of_dofs(dofs)
}

/// Tᵀ A T (sparse), symmetrised exactly: (P + Pᵀ)/2 with P the product, so the pattern
/// and the values are symmetric whatever the round-off of the products.
pub fn project(a: &CsMat<f64>, t: &CsMat<f64>) -> CsMat<f64> {
    let tt: CsMat<f64> = t.transpose_view().to_csc();
    let at: CsMat<f64> = (a * t).to_csc();
    let p: CsMat<f64> = (&tt * &at).to_csc();
    let pt: CsMat<f64> = p.transpose_view().to_csc();
    (&p + &pt).map(|v| 0.5 * v)
}

fn free_free(
    kt: &CsMat<f64>,
    mt: &CsMat<f64>,
    n_elastic: usize,
    body: &str,
) -> Result<(DMatrix<f64>, Vec<f64>), FeError> {
    let (elastic, _) = free_free_pairs(kt, mt, n_elastic, body)?;
    Ok((elastic.vectors, elastic.omega_sq))
}

/// The six rigid-body modes and the `n_elastic` lowest elastic modes of a free body (the
/// checks of the module docs): the elastic pairs and the rigid vectors.
pub(crate) fn free_free_pairs(
    kt: &CsMat<f64>,
    mt: &CsMat<f64>,
    n_elastic: usize,
    body: &str,
) -> Result<(Eigenpairs, DMatrix<f64>), FeError> {
    let n = kt.rows();
    let wanted = 6 + n_elastic + 1;
    if wanted > n {
        return Err(FeError::TooManyModes {
            requested: n_elastic,
            available: n.saturating_sub(7),
        });
    }
    let pairs = lowest_modes(kt, mt, wanted, &eigen_options())?;
    let w2 = &pairs.omega_sq;
    let first_elastic = w2[6];
    let rigid = w2
        .iter()
        .take_while(|v| v.abs() <= RIGID_MODE_TOL * first_elastic)
        .count();
    if first_elastic <= 0.0 || rigid != 6 {
        return Err(invalid(
            format!("{body}.frame"),
            "FreeFree",
            format!(
                "a free body has six rigid-body modes; this model's lowest ω² are {:?} rad²/s² \
                 ({rigid} below {RIGID_MODE_TOL:e} of the seventh): {}",
                &w2[..7.min(w2.len())],
                if rigid > 6 {
                    "disconnected parts or a mechanism in the mesh"
                } else {
                    "the model is supported (springs to ground or constrained DOFs in the export)"
                }
            ),
        ));
    }
    let x = pairs.vectors.columns(6, n_elastic).into_owned();
    let rigid = pairs.vectors.columns(0, 6).into_owned();
    let elastic = Eigenpairs {
        omega_sq: w2[6..6 + n_elastic].to_vec(),
        vectors: x,
    };
    Ok((elastic, rigid))
}

#[allow(clippy::too_many_arguments)]
fn clamped(
    kt: &CsMat<f64>,
    mt: &CsMat<f64>,
    model: &FeModel,
    map: &RetainedMap,
    frame: usize,
    boundary_points: &[usize],
    spec: &ImportedBodySpec,
    body: &str,
) -> Result<Reduction, FeError> {
    let coordinates = |p: usize| map.point_start(p)..map.point_start(p) + 6;
    let r: Vec<usize> = coordinates(frame).collect();
    let b: Vec<usize> = boundary_points
        .iter()
        .flat_map(|&p| coordinates(p))
        .collect();
    let sets = DofSets::new(kt.rows(), r, b);
    let frame_txt = format!("interface {:?}", spec.frame);
    if spec.mode_selection != ModeSelection::LowestFrequency {
        let singular = |detail: String| FeError::SingularInterior {
            spec: body.to_string(),
            frame: frame_txt.clone(),
            detail,
        };
        return reduce_sparse_with_basis(kt, mt, &sets, body, &frame_txt, |p| {
            selection::clamped_basis(spec, model, map, mt, &sets, p, EIGEN_TOL, &singular)
        });
    }
    reduce_sparse(
        kt,
        mt,
        &sets,
        spec.normal_modes,
        EIGEN_TOL,
        None,
        body,
        &frame_txt,
    )
}
