//! Per-mode geometric stiffness K_Gk (docs/methods.md §6.1, §6.2 "Precomputation").
//!
//! With linear axial and Hermite transverse shape functions, the axial strain
//! of mode k is constant on an element, g_u,k = Δu_k,e / L_e, so
//!
//! K_Gk = Σ_e EA (Δu_k,e / L_e) (X_e^(v)ᵀ K_σ X_e^(v) + X_e^(w)ᵀ K_σ^(w) X_e^(w)),
//!
//! where X_e^(v) are the mode rows of (v₁, θz₁, v₂, θz₂) and X_e^(w) those of
//! (w₁, θy₁, w₂, θy₂), in element axes. Then U₁ = ½ Σ_k y_k yᵀ K_Gk y.
//! On a polyline each element uses its own axial direction (§6 is written for
//! a straight beam along ē₁).
//!
//! [`element_mean_g`] gives the element means Ḡ_e = (X_e^(v)ᵀ K_σ X_e^(v) +
//! X_e^(w)ᵀ K_σ^(w) X_e^(w)) / L_e and the weights EA_e L_e, from which
//! H_ijkl = Σ_e EA_e L_e Ḡ_e,ij Ḡ_e,kl (docs/methods.md §6.2 correction: the element
//! mean of G, not an exact quadrature, matches the constant axial strain of the
//! linear axial element). H is kept in this factored form (n² per element
//! instead of n⁴).

use flexmbd_core::Dim;
use nalgebra::DMatrix;

use crate::assembly::Mesh;
use crate::beam::{AXIAL_2D, AXIAL_3D, VPLANE_2D, VPLANE_3D, WPLANE_3D, k_sigma, k_sigma_w};
use crate::cloud::element_local_modes;

/// K_Gk for every mode k of `x` (N × n): n symmetric n × n matrices.
pub fn geometric_stiffness(mesh: &Mesh, x: &DMatrix<f64>) -> Vec<DMatrix<f64>> {
    let n = x.ncols();
    let mut kg = vec![DMatrix::zeros(n, n); n];
    for (e, el) in mesh.elements.iter().enumerate() {
        let ea = el.props.e * el.props.area;
        let l = el.length;
        let xl = element_local_modes(mesh, e, x);
        let (ax, vp): ([usize; 2], [usize; 4]) = match mesh.dim {
            Dim::Planar => (AXIAL_2D, VPLANE_2D),
            Dim::Spatial => (AXIAL_3D, VPLANE_3D),
        };
        let xv = DMatrix::from_fn(4, n, |i, j| xl[(vp[i], j)]);
        let mut g = xv.transpose() * k_sigma(l) * &xv;
        if mesh.dim == Dim::Spatial {
            let xw = DMatrix::from_fn(4, n, |i, j| xl[(WPLANE_3D[i], j)]);
            g += xw.transpose() * k_sigma_w(l) * &xw;
        }
        for (k, kgk) in kg.iter_mut().enumerate() {
            let du = xl[(ax[1], k)] - xl[(ax[0], k)];
            if du != 0.0 {
                *kgk += &g * (ea * du / l);
            }
        }
    }
    for m in kg.iter_mut() {
        *m = (&*m + m.transpose()) * 0.5;
    }
    kg
}

/// Element means Ḡ_e (n × n, symmetric, one per element) and weights EA_e L_e
/// (docs/methods.md §6.2, "H: Correction"): H_ijkl = Σ_e w_e Ḡ_e,ij Ḡ_e,kl.
pub fn element_mean_g(mesh: &Mesh, x: &DMatrix<f64>) -> (Vec<DMatrix<f64>>, Vec<f64>) {
    let n = x.ncols();
    let mut gs = Vec::with_capacity(mesh.elements.len());
    let mut ws = Vec::with_capacity(mesh.elements.len());
    for (e, el) in mesh.elements.iter().enumerate() {
        let ea = el.props.e * el.props.area;
        let l = el.length;
        let xl = element_local_modes(mesh, e, x);
        let vp = match mesh.dim {
            Dim::Planar => VPLANE_2D,
            Dim::Spatial => VPLANE_3D,
        };
        let xv = DMatrix::from_fn(4, n, |i, j| xl[(vp[i], j)]);
        let mut g = xv.transpose() * k_sigma(l) * &xv;
        if mesh.dim == Dim::Spatial {
            let xw = DMatrix::from_fn(4, n, |i, j| xl[(WPLANE_3D[i], j)]);
            g += xw.transpose() * k_sigma_w(l) * &xw;
        }
        g = (&g + g.transpose()) * (0.5 / l);
        gs.push(g);
        ws.push(ea * l);
    }
    (gs, ws)
}
