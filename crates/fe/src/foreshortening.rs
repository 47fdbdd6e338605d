//! Foreshortening integrals F(x) = ∫₀ˣ G dξ (docs/methods.md §6.3, FS0), with
//! G = g_v g_vᵀ + g_w g_wᵀ the outer products of the modes' transverse slopes.
//!
//! - Element ends: `F_end = F_start + X_e^(v)ᵀ K_σ X_e^(v) + X_e^(w)ᵀ K_σ^(w) X_e^(w)`,
//!   accumulated from the root (node 0) outward.
//! - Cloud points (the Gauss stations of [`build_cloud`](crate::cloud::build_cloud), in
//!   the same order; in 3D the 4 section points of a station share its F): `F_start` plus
//!   `∫_{x_start}^{x_p} G` by 3-point Gauss on the sub-interval (v′ is quadratic on a
//!   Hermite element, so G is of degree 4 and the rule is exact).
//!
//! Only straight beams whose nodes follow the mesh order from the root are accepted
//! (docs/methods.md §6.3 "Limits"); the shortening acts along the beam axis ē₁.

use flexmbd_core::{Dim, InvalidValue};
use nalgebra::{DMatrix, Vector3};
use serde::{Deserialize, Serialize};

use crate::assembly::Mesh;
use crate::beam::{VPLANE_2D, VPLANE_3D, WPLANE_3D, hermite, k_sigma, k_sigma_w};
use crate::cloud::{GAUSS4, element_local_modes};

/// 3-point Gauss–Legendre rule on [−1, 1]: (abscissa, weight).
const GAUSS3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// The FS0 data of one straight beam body (docs/methods.md §6.3): the beam axis and F at
/// every mass-cloud point and every FE node (n × n, symmetric).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ForeshorteningData {
    /// Unit beam axis ē₁ in body components (the direction of the shortening).
    pub axis: Vector3<f64>,
    /// F_k = F(x_k), one per mass-cloud point, in cloud order.
    pub cloud: Vec<DMatrix<f64>>,
    /// F at every FE node (F = 0 at the root, node 0).
    pub nodes: Vec<DMatrix<f64>>,
}

/// G = g_v g_vᵀ + g_w g_wᵀ at ξ ∈ [0, 1] of an element with local mode rows `xl`.
fn g_at(dim: Dim, xl: &DMatrix<f64>, xi: f64, l: f64, out: &mut DMatrix<f64>) {
    let n = xl.ncols();
    let (_, hd) = hermite(xi, l);
    let s = [1.0, -1.0, 1.0, -1.0];
    let vp = match dim {
        Dim::Planar => VPLANE_2D,
        Dim::Spatial => VPLANE_3D,
    };
    let gv: Vec<f64> = (0..n)
        .map(|j| (0..4).map(|q| hd[q] * xl[(vp[q], j)]).sum())
        .collect();
    let gw: Vec<f64> = match dim {
        Dim::Planar => vec![0.0; n],
        Dim::Spatial => (0..n)
            .map(|j| (0..4).map(|q| s[q] * hd[q] * xl[(WPLANE_3D[q], j)]).sum())
            .collect(),
    };
    for i in 0..n {
        for j in 0..n {
            out[(i, j)] = gv[i] * gv[j] + gw[i] * gw[j];
        }
    }
}

/// ∫₀^{ξ l} G dx on an element (3-point Gauss, exact).
fn partial_integral(dim: Dim, xl: &DMatrix<f64>, xi: f64, l: f64) -> DMatrix<f64> {
    let n = xl.ncols();
    let mut sum = DMatrix::zeros(n, n);
    let mut g = DMatrix::zeros(n, n);
    for &(t, w) in GAUSS3.iter() {
        g_at(dim, xl, 0.5 * xi * (1.0 + t), l, &mut g);
        sum += &g * (0.5 * xi * l * w);
    }
    sum
}

/// F at the cloud points and nodes of a straight beam `mesh` with modes `x` (N × n).
///
/// Refused (naming the element) when the elements are not collinear and equally
/// directed, or do not follow each other node to node from node 0.
pub fn foreshortening(mesh: &Mesh, x: &DMatrix<f64>) -> Result<ForeshorteningData, InvalidValue> {
    let n = x.ncols();
    let Some(first) = mesh.elements.first() else {
        return Err(InvalidValue::new(
            "mesh.elements",
            0,
            "foreshortening needs a beam with elements",
        ));
    };
    let axis: Vector3<f64> = first.axes.row(0).transpose();
    for (e, el) in mesh.elements.iter().enumerate() {
        let ax: Vector3<f64> = el.axes.row(0).transpose();
        if (ax - axis).norm() > 1e-9 {
            return Err(InvalidValue::new(
                format!("mesh.elements[{e}]"),
                format!("axis {:?}", ax.as_slice()),
                "foreshortening (FS0) needs a straight beam (methods.md §6.3 limits)",
            ));
        }
        if el.nodes != [e, e + 1] {
            return Err(InvalidValue::new(
                format!("mesh.elements[{e}].nodes"),
                format!("{:?}", el.nodes),
                "foreshortening (FS0) needs the elements in order from the root node 0",
            ));
        }
        let off = mesh.nodes[el.nodes[0]] - mesh.nodes[0];
        if off.cross(&axis).norm() > 1e-9 * (1.0 + off.norm()) {
            return Err(InvalidValue::new(
                format!("mesh.elements[{e}]"),
                "off the beam axis",
                "foreshortening (FS0) needs a straight beam (methods.md §6.3 limits)",
            ));
        }
    }
    let per_station = match mesh.dim {
        Dim::Planar => 1,
        Dim::Spatial => 4,
    };
    let mut nodes = vec![DMatrix::zeros(n, n)];
    let mut cloud = Vec::with_capacity(mesh.elements.len() * 4 * per_station);
    let mut f_start = DMatrix::zeros(n, n);
    for (e, el) in mesh.elements.iter().enumerate() {
        let l = el.length;
        let xl = element_local_modes(mesh, e, x);
        for &(t, _) in GAUSS4.iter() {
            let xi = 0.5 * (1.0 + t);
            let mut f = &f_start + partial_integral(mesh.dim, &xl, xi, l);
            f = (&f + f.transpose()) * 0.5;
            for _ in 0..per_station {
                cloud.push(f.clone());
            }
        }
        let vp = match mesh.dim {
            Dim::Planar => VPLANE_2D,
            Dim::Spatial => VPLANE_3D,
        };
        let xv = DMatrix::from_fn(4, n, |i, j| xl[(vp[i], j)]);
        let mut inc = xv.transpose() * k_sigma(l) * &xv;
        if mesh.dim == Dim::Spatial {
            let xw = DMatrix::from_fn(4, n, |i, j| xl[(WPLANE_3D[i], j)]);
            inc += xw.transpose() * k_sigma_w(l) * &xw;
        }
        f_start += (&inc + inc.transpose()) * 0.5;
        nodes.push(f_start.clone());
    }
    Ok(ForeshorteningData { axis, cloud, nodes })
}

/// ∫₀ˣ G dξ at body-axis distance `x` from the root by an m-point-per-element
/// composite midpoint rule (a dense check quadrature for tests; O(1/m²)).
pub fn dense_quadrature(mesh: &Mesh, modes: &DMatrix<f64>, x: f64, m: usize) -> DMatrix<f64> {
    let n = modes.ncols();
    let mut sum = DMatrix::zeros(n, n);
    let mut g = DMatrix::zeros(n, n);
    let mut start = 0.0;
    for (e, el) in mesh.elements.iter().enumerate() {
        let l = el.length;
        if start >= x {
            break;
        }
        let end = (start + l).min(x);
        let xl = element_local_modes(mesh, e, modes);
        let h = (end - start) / m as f64;
        for i in 0..m {
            let s = start + (i as f64 + 0.5) * h;
            g_at(mesh.dim, &xl, (s - start) / l, l, &mut g);
            sum += &g * h;
        }
        start += l;
    }
    sum
}
