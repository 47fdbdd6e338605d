//! The modes of an imported body on its retained coordinates ũ (docs/methods.md §1.3–§1.4):
//! K̃ = Tᵀ K T, M̃ = Tᵀ M T, then either
//!
//! - a **clamped** frame (interface point F): the r set is F's six coordinates, the b set
//!   the six of every `boundary` interface, i the rest; static modes
//!   X̃_s = [𝟙_bb; −K̃_ii⁻¹ K̃_ib] by one sparse Cholesky of K̃_ii and n_b solves, and the n_d
//!   lowest fixed-interface modes of (K̃_ii, M̃_ii) by shift-invert Lanczos
//!   ([`crate::sparse_eigen`]);
//! - or **free-free**: the 6 + n_d lowest modes of (K̃, M̃), of which the six lowest must be
//!   rigid-body modes (|ω²| below 1e-6 of the first elastic ω²) and are dropped.
//!
//! No dense matrix larger than Ñ × n is formed.

use nalgebra::DMatrix;
use sprs::{CsMat, TriMat};

use super::interfaces::{ResolvedInterface, RetainedMap};
use super::{ImportedBodySpec, ImportedFrame, invalid};
use crate::error::FeError;
use crate::import::FeModel;
use crate::sparse::ShiftedCholesky;
use crate::sparse_eigen::{SparseEigenOptions, lowest_modes};

/// Relative size (to the first elastic ω²) below which a free-free mode counts as rigid.
pub const RIGID_MODE_TOL: f64 = 1e-6;

/// The eigen-solver's residual bound here. A rigid-body mode's attainable residual is
/// about ε ω²_max / |σ| (`sparse_eigen`'s module docs), which on a free body with stiff
/// interface spiders sits at 1e-10, the solver's default; 1e-9 leaves room and still
/// gives every ω² to about the square of it (Rayleigh quotients of a symmetric pencil).
pub const EIGEN_TOL: f64 = 1e-9;

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
    let (x, omega_sq, frame_point) = match &spec.frame {
        ImportedFrame::FreeFree => {
            let (x, w2) = free_free(&kt, &mt, spec.normal_modes, body)?;
            (x, w2, None)
        }
        ImportedFrame::Interface(name) => {
            let frame = point(name).unwrap_or_default();
            let (x, w2) = clamped(&kt, &mt, map, frame, &boundary_points, spec, body)?;
            (x, w2, Some(frame))
        }
    };
    let k_ff = symmetrise(&(x.transpose() * sparse_times_dense(&kt, &x)));
    Ok(RetainedModes {
        x,
        k_ff,
        omega_sq,
        frame_point,
        boundary_points,
    })
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

/// A (sparse) times X (dense).
pub fn sparse_times_dense(a: &CsMat<f64>, x: &DMatrix<f64>) -> DMatrix<f64> {
    let mut y = DMatrix::zeros(a.rows(), x.ncols());
    for (value, (i, j)) in a.iter() {
        for c in 0..x.ncols() {
            y[(i, c)] += value * x[(j, c)];
        }
    }
    y
}

fn symmetrise(a: &DMatrix<f64>) -> DMatrix<f64> {
    (a + a.transpose()) * 0.5
}

/// The rows and columns `keep` of A (ascending indices), CSC.
fn submatrix(a: &CsMat<f64>, keep: &[usize]) -> CsMat<f64> {
    let mut new_index = vec![usize::MAX; a.rows()];
    for (k, &i) in keep.iter().enumerate() {
        new_index[i] = k;
    }
    let mut t = TriMat::new((keep.len(), keep.len()));
    for (value, (i, j)) in a.iter() {
        let (ni, nj) = (new_index[i], new_index[j]);
        if ni != usize::MAX && nj != usize::MAX {
            t.add_triplet(ni, nj, *value);
        }
    }
    t.to_csc()
}

/// The columns `cols` of the rows `rows` of A, dense (rows.len() × cols.len()).
fn dense_block(a: &CsMat<f64>, rows: &[usize], cols: &[usize]) -> DMatrix<f64> {
    let mut row_index = vec![usize::MAX; a.rows()];
    for (k, &i) in rows.iter().enumerate() {
        row_index[i] = k;
    }
    let mut col_index = vec![usize::MAX; a.cols()];
    for (k, &j) in cols.iter().enumerate() {
        col_index[j] = k;
    }
    let mut out = DMatrix::zeros(rows.len(), cols.len());
    for (value, (i, j)) in a.iter() {
        if row_index[i] != usize::MAX && col_index[j] != usize::MAX {
            out[(row_index[i], col_index[j])] += value;
        }
    }
    out
}

/// mean_i K_ii / M_ii: the scale of ω² on the mesh (an element's own frequency squared).
fn mean_diagonal_ratio(k: &CsMat<f64>, m: &CsMat<f64>) -> f64 {
    let diagonal = |a: &CsMat<f64>| {
        let mut d = vec![0.0; a.rows()];
        for (v, (i, j)) in a.iter() {
            if i == j {
                d[i] += v;
            }
        }
        d
    };
    let (dk, dm) = (diagonal(k), diagonal(m));
    let ratios: Vec<f64> = dk
        .iter()
        .zip(&dm)
        .filter(|(_, m)| **m > 0.0)
        .map(|(k, m)| k / m)
        .collect();
    ratios.iter().sum::<f64>() / ratios.len().max(1) as f64
}

fn free_free(
    kt: &CsMat<f64>,
    mt: &CsMat<f64>,
    n_elastic: usize,
    body: &str,
) -> Result<(DMatrix<f64>, Vec<f64>), FeError> {
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
    Ok((x, w2[6..6 + n_elastic].to_vec()))
}

fn clamped(
    kt: &CsMat<f64>,
    mt: &CsMat<f64>,
    map: &RetainedMap,
    frame: usize,
    boundary_points: &[usize],
    spec: &ImportedBodySpec,
    body: &str,
) -> Result<(DMatrix<f64>, Vec<f64>), FeError> {
    let n = kt.rows();
    let mut set = vec![0u8; n]; // 0 interior, 1 boundary, 2 frame
    let fs = map.point_start(frame);
    set[fs..fs + 6].fill(2);
    let mut b = Vec::with_capacity(6 * boundary_points.len());
    for &p in boundary_points {
        let s = map.point_start(p);
        set[s..s + 6].fill(1);
        b.extend(s..s + 6);
    }
    let i: Vec<usize> = (0..n).filter(|&r| set[r] == 0).collect();
    if spec.normal_modes > i.len() {
        return Err(FeError::TooManyModes {
            requested: spec.normal_modes,
            available: i.len(),
        });
    }
    let kii = submatrix(kt, &i);
    let mii = submatrix(mt, &i);
    let singular = |e: FeError| match e {
        FeError::ShiftedNotPositiveDefinite { pivot, .. } => FeError::SingularInterior {
            spec: body.to_string(),
            frame: format!("interface {:?}", spec.frame),
            detail: format!("pivot {pivot} of the interior stiffness"),
        },
        other => other,
    };
    let n_s = b.len();
    let n_d = spec.normal_modes;
    let mut x = DMatrix::zeros(n, n_s + n_d);
    if n_s > 0 {
        let chol = ShiftedCholesky::new(&kii, &mii, 0.0).map_err(singular)?;
        let mut rhs = -dense_block(kt, &i, &b);
        let mut scratch = chol.solve_scratch(n_s);
        let view = faer::MatMut::from_column_major_slice_mut(rhs.as_mut_slice(), i.len(), n_s);
        chol.solve_in_place(view, &mut scratch);
        for (k, &row) in i.iter().enumerate() {
            for c in 0..n_s {
                x[(row, c)] = rhs[(k, c)];
            }
        }
        for (c, &row) in b.iter().enumerate() {
            x[(row, c)] = 1.0;
        }
    }
    let pairs = lowest_modes(&kii, &mii, n_d, &eigen_options()).map_err(singular)?;
    if let Some(&lowest) = pairs.omega_sq.first()
        && lowest <= 1e-12 * mean_diagonal_ratio(&kii, &mii)
    {
        return Err(FeError::SingularInterior {
            spec: body.to_string(),
            frame: format!("interface {:?}", spec.frame),
            detail: format!("the lowest fixed-interface mode has ω² = {lowest:e}: a mechanism"),
        });
    }
    for (k, &row) in i.iter().enumerate() {
        for c in 0..n_d {
            x[(row, n_s + c)] = pairs.vectors[(k, c)];
        }
    }
    Ok((x, pairs.omega_sq))
}
