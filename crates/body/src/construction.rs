//! Construction of a [`FlexibleBody`](crate::FlexibleBody) (docs/methods.md §2.1, §2.3): the checks
//! of a [`ReducedBody`] and its shape integrals packed into contiguous storage, with
//! `G_1 = S³² − S²³`, `G_2 = S¹³ − S³¹`, `G_3 = S²¹ − S¹²` and `M_yy = Σ_a Sᵃᵃ` (2D: S¹¹ + S²²).

use flexmbd_core::{Dim, InvalidValue};
use flexmbd_fe::{ReducedBody, ShapeIntegrals};
use nalgebra::DMatrix;

fn check_shape(field: &str, m: &DMatrix<f64>, r: usize, c: usize) -> Result<(), InvalidValue> {
    if m.shape() != (r, c) {
        return Err(InvalidValue::new(
            field,
            format!("{}x{}", m.nrows(), m.ncols()),
            format!("must be {r}x{c}"),
        ));
    }
    if !m.iter().all(|v| v.is_finite()) {
        return Err(InvalidValue::new(
            field,
            "non-finite entry",
            "must be finite",
        ));
    }
    Ok(())
}

/// Refuse a reduced body whose sizes disagree, whose cloud has non-finite weights, positions
/// or rows, or (2D) leaves the plane z = 0. A weight may be negative: the cloud of an
/// imported body is an exact rewriting of a consistent mass matrix, whose node terms are
/// negative (`flexmbd_fe::imported::inertia`); the mass must be positive.
pub(crate) fn check_reduced(reduced: &ReducedBody) -> Result<(), InvalidValue> {
    let cloud = &reduced.cloud;
    let n = cloud.n_modes;
    if reduced.n_modes() != n {
        return Err(InvalidValue::new(
            "cloud.n_modes",
            n,
            format!("must equal the mode inventory's {}", reduced.n_modes()),
        ));
    }
    if cloud.positions.len() != cloud.weights.len() {
        return Err(InvalidValue::new(
            "cloud.positions",
            cloud.positions.len(),
            format!("must have one entry per weight ({})", cloud.weights.len()),
        ));
    }
    if cloud.mode_rows.len() != 3 * n * cloud.len() {
        return Err(InvalidValue::new(
            "cloud.mode_rows",
            cloud.mode_rows.len(),
            format!("must hold 3 n N_p = {} entries", 3 * n * cloud.len()),
        ));
    }
    for (k, w) in cloud.weights.iter().enumerate() {
        if !w.is_finite() {
            return Err(InvalidValue::new(
                format!("cloud.weights[{k}]"),
                w,
                "must be finite",
            ));
        }
    }
    for (k, p) in cloud.positions.iter().enumerate() {
        if !p.iter().all(|v| v.is_finite()) {
            return Err(InvalidValue::new(
                format!("cloud.positions[{k}]"),
                format!("{p:?}"),
                "must be finite",
            ));
        }
        if reduced.dim == Dim::Planar && p.z != 0.0 {
            return Err(InvalidValue::new(
                format!("cloud.positions[{k}].z"),
                p.z,
                "a planar body lives in z = 0",
            ));
        }
    }
    if let Some(v) = cloud.mode_rows.iter().find(|v| !v.is_finite()) {
        return Err(InvalidValue::new("cloud.mode_rows", v, "must be finite"));
    }
    if reduced.dim == Dim::Planar {
        for k in 0..cloud.len() {
            let zr = &cloud.rows(k)[2 * n..3 * n];
            if let Some(v) = zr.iter().find(|v| **v != 0.0) {
                return Err(InvalidValue::new(
                    format!("cloud.mode_rows[{k}].z"),
                    v,
                    "a planar body has zero z mode rows",
                ));
            }
        }
    }
    check_shape("k_ff", &reduced.k_ff, n, n)?;
    check_shape("c_ff", &reduced.c_ff, n, n)?;
    let si = &reduced.shape_integrals;
    crate_require_positive("shape_integrals.mass", si.mass)?;
    check_shape("shape_integrals.s", &si.s, 3, n)?;
    for a in 0..3 {
        check_shape(&format!("shape_integrals.s_a[{a}]"), &si.s_a[a], 3, n)?;
        for b in 0..3 {
            check_shape(
                &format!("shape_integrals.s_ab[{a}][{b}]"),
                &si.s_ab[a][b],
                n,
                n,
            )?;
        }
    }
    Ok(())
}

/// The shape integrals in contiguous storage, with `G_1, G_2, G_3` and `M_yy`.
pub(crate) struct PackedIntegrals {
    pub(crate) s: Vec<f64>,
    pub(crate) sa: Vec<f64>,
    pub(crate) sab: Vec<f64>,
    pub(crate) g: Vec<f64>,
    pub(crate) m_yy: Vec<f64>,
}

impl PackedIntegrals {
    pub(crate) fn new(si: &ShapeIntegrals, n: usize, dim: Dim) -> Self {
        let mut s = vec![0.0; 3 * n];
        let mut sa = vec![0.0; 9 * n];
        let mut sab = vec![0.0; 9 * n * n];
        for a in 0..3 {
            for j in 0..n {
                s[a * n + j] = si.s[(a, j)];
            }
        }
        for b in 0..3 {
            for a in 0..3 {
                for j in 0..n {
                    sa[(3 * b + a) * n + j] = si.s_a[b][(a, j)];
                }
            }
        }
        for a in 0..3 {
            for b in 0..3 {
                let off = (3 * a + b) * n * n;
                for i in 0..n {
                    for j in 0..n {
                        sab[off + i * n + j] = si.s_ab[a][b][(i, j)];
                    }
                }
            }
        }
        // G_1 = S³² − S²³, G_2 = S¹³ − S³¹, G_3 = S²¹ − S¹² (0-based pairs).
        let pairs = [(2, 1, 1, 2), (0, 2, 2, 0), (1, 0, 0, 1)];
        let mut g = vec![0.0; 3 * n * n];
        for (c, &(a1, b1, a2, b2)) in pairs.iter().enumerate() {
            for i in 0..n {
                for j in 0..n {
                    g[c * n * n + i * n + j] = si.s_ab[a1][b1][(i, j)] - si.s_ab[a2][b2][(i, j)];
                }
            }
        }
        let n_axes = if dim == Dim::Planar { 2 } else { 3 };
        let mut m_yy = vec![0.0; n * n];
        for a in 0..n_axes {
            for i in 0..n {
                for j in 0..n {
                    m_yy[i * n + j] += si.s_ab[a][a][(i, j)];
                }
            }
        }
        // Symmetrize exactly (round-off of the cloud sums).
        for i in 0..n {
            for j in 0..i {
                let v = 0.5 * (m_yy[i * n + j] + m_yy[j * n + i]);
                m_yy[i * n + j] = v;
                m_yy[j * n + i] = v;
            }
        }
        Self {
            s,
            sa,
            sab,
            g,
            m_yy,
        }
    }
}

fn crate_require_positive(field: &str, v: f64) -> Result<f64, InvalidValue> {
    flexmbd_core::require_positive(field, v)
}
