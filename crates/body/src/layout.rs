//! Where the inertia kernels write (docs/methods.md §2.4, §2.5): the layouts of the relative set
//! {ṡ; ω; ẏ} (a planar body keeps the x, y, θz rows and columns of the spatial set, §0) and of
//! the natural set {r0; u; v; w; y}, and the writers of their rigid, coupling and modal blocks
//! into caller storage.

use flexmbd_core::Dim;
use nalgebra::{Dyn, Matrix, Matrix3, StorageMut, U1, Vector2, Vector3};

/// The modal part of a route-(a) result: `Q[o + j] = −qy[j]` and the symmetric n × n block
/// of M at (o, o) from the upper triangle of `yy` (row-major), which the B-matrix loops
/// accumulate one triangle of.
#[inline(always)]
pub(crate) fn write_modal_block<SM, SQ>(
    m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
    q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    o: usize,
    n: usize,
    yy: &[f64],
    qy: &[f64],
) where
    SM: StorageMut<f64, Dyn, Dyn>,
    SQ: StorageMut<f64, Dyn, U1>,
{
    for i in 0..n {
        q_out[o + i] = -qy[i];
        for j in i..n {
            let v = yy[i * n + j];
            m_out[(o + i, o + j)] = v;
            m_out[(o + j, o + i)] = v;
        }
    }
}

/// The rows and columns a body keeps of the spatial relative set {ṡ; ω; ẏ}: for each of the
/// six rigid entries its place in the body's set (a planar body keeps x, y, θz, §0), and the
/// offset of the modal entries.
#[inline(always)]
pub(crate) fn relative_layout(dim: Dim) -> ([Option<usize>; 6], usize) {
    match dim {
        Dim::Spatial => ([Some(0), Some(1), Some(2), Some(3), Some(4), Some(5)], 6),
        Dim::Planar => ([Some(0), Some(1), None, None, None, Some(2)], 3),
    }
}

/// The rigid part of a relative-set result written in the layout of `dim`: M̄ = [[m I, −g̃],
/// [g̃, J]] with the first moment g about the global origin and the inertia J there, and the
/// six rigid entries of Q̄.
#[inline(always)]
pub(crate) fn write_relative_rigid<SM, SQ>(
    m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
    q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    dim: Dim,
    mass: f64,
    moment: &Vector3<f64>,
    inertia: &Matrix3<f64>,
    force: &[f64; 6],
) where
    SM: StorageMut<f64, Dyn, Dyn>,
    SQ: StorageMut<f64, Dyn, U1>,
{
    let (layout, _) = relative_layout(dim);
    let gt = flexmbd_core::skew(moment);
    let mut rigid = [[0.0; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            rigid[i][j] = if i == j { mass } else { 0.0 };
            rigid[i][j + 3] = -gt[(i, j)];
            rigid[i + 3][j] = gt[(i, j)];
            rigid[i + 3][j + 3] = inertia[(i, j)];
        }
    }
    for (i, row) in layout.iter().enumerate() {
        let Some(oi) = *row else { continue };
        for (j, column) in layout.iter().enumerate() {
            if let Some(oj) = *column {
                m_out[(oi, oj)] = rigid[i][j];
            }
        }
        q_out[oi] = force[i];
    }
}

/// The rigid part of a planar relative-set result {ṡx; ṡy; θ̇z}, written directly (the planar
/// kernels sum in-plane quantities only): M̄ = [[m I₂, E g], [(E g)ᵀ, J]] with the first moment
/// g about the global origin (`E g = (−g_y, g_x)`) and the polar inertia J there, and the three
/// rigid entries of Q̄.
#[inline(always)]
pub(crate) fn write_planar_rigid<SM, SQ>(
    m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
    q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    mass: f64,
    moment: &Vector2<f64>,
    inertia: f64,
    force: &[f64; 3],
) where
    SM: StorageMut<f64, Dyn, Dyn>,
    SQ: StorageMut<f64, Dyn, U1>,
{
    m_out[(0, 0)] = mass;
    m_out[(1, 1)] = mass;
    m_out[(0, 1)] = 0.0;
    m_out[(1, 0)] = 0.0;
    m_out[(0, 2)] = -moment.y;
    m_out[(2, 0)] = -moment.y;
    m_out[(1, 2)] = moment.x;
    m_out[(2, 1)] = moment.x;
    m_out[(2, 2)] = inertia;
    q_out[0] = force[0];
    q_out[1] = force[1];
    q_out[2] = force[2];
}

/// Mode j's rigid–modal couplings of a planar relative-set M̄, symmetric: the translation
/// rows x, y and the rotation row θz of column 3 + j.
#[inline(always)]
pub(crate) fn write_planar_coupling<SM>(
    m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
    j: usize,
    x: f64,
    y: f64,
    theta: f64,
) where
    SM: StorageMut<f64, Dyn, Dyn>,
{
    m_out[(0, 3 + j)] = x;
    m_out[(3 + j, 0)] = x;
    m_out[(1, 3 + j)] = y;
    m_out[(3 + j, 1)] = y;
    m_out[(2, 3 + j)] = theta;
    m_out[(3 + j, 2)] = theta;
}

/// The rigid–modal couplings of a relative-set M̄ in the layout of `dim`, symmetric: rows
/// ṡ from `translation` and rows ω from `rotation` (both 3 × n, row-major).
#[inline(always)]
pub(crate) fn write_relative_couplings<SM>(
    m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
    dim: Dim,
    n: usize,
    translation: &[f64],
    rotation: &[f64],
) where
    SM: StorageMut<f64, Dyn, Dyn>,
{
    let (layout, o) = relative_layout(dim);
    for (i, row) in layout.iter().enumerate() {
        let Some(oi) = *row else { continue };
        let source = if i < 3 {
            &translation[i * n..(i + 1) * n]
        } else {
            &rotation[(i - 3) * n..(i - 2) * n]
        };
        for (j, &v) in source.iter().enumerate() {
            m_out[(oi, o + j)] = v;
            m_out[(o + j, oi)] = v;
        }
    }
}

/// The modal part of a route-(b) result: `Q[o + j] = force[j]` and the n × n block of M at
/// (o, o) from the full row-major `mass`.
#[inline(always)]
pub(crate) fn write_modal_rows<SM, SQ>(
    m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
    q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    o: usize,
    mass: &[f64],
    force: &[f64],
) where
    SM: StorageMut<f64, Dyn, Dyn>,
    SQ: StorageMut<f64, Dyn, U1>,
{
    let n = force.len();
    for i in 0..n {
        q_out[o + i] = force[i];
        for j in 0..n {
            m_out[(o + i, o + j)] = mass[i * n + j];
        }
    }
}

/// The rigid 12 × 12 block of a spatial natural-coordinate mass matrix over (r0, u, v, w)
/// (docs/methods.md §3.2): every 3 × 3 block is a scalar times I₃, the scalars being
/// [[m, m̄ᵀ], [m̄, P]] with the first moment m̄ and second moment P of the (deformed) body.
#[inline(always)]
pub(crate) fn write_natural_rigid_block_3d<SM>(
    m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
    m: f64,
    mb: &Vector3<f64>,
    p: &Matrix3<f64>,
) where
    SM: StorageMut<f64, Dyn, Dyn>,
{
    for bi in 0..4 {
        for bj in 0..4 {
            let v = match (bi, bj) {
                (0, 0) => m,
                (0, b) => mb[b - 1],
                (a, 0) => mb[a - 1],
                (a, b) => p[(a - 1, b - 1)],
            };
            for i in 0..3 {
                for j in 0..3 {
                    m_out[(3 * bi + i, 3 * bj + j)] = if i == j { v } else { 0.0 };
                }
            }
        }
    }
}
