//! Geometric stiffness of a solid body per mode, for FNL1 (issue 29 item 4; thesis ch. 4;
//! docs/methods.md §6.1–§6.2, written there for beams).
//!
//! With the Green–Lagrange strain E = ε + ½ ∇uᵀ∇u (∇u_ip = ∂u_i/∂x_p), the St Venant–Kirchhoff
//! strain energy ½ ∫ E : C : E dV splits as U_L + U₁ + U₂ with the cubic term
//!
//! U₁ = ½ ∫ σ(u) : (∇uᵀ∇u) dV,  σ(u) = C : ε(u) the linear stress
//!
//! (Bathe 1996, §6.3.2, the initial-stress matrix; Zienkiewicz, Taylor & Fox 2014, §10.4).
//! With u = Φ y (Φ the body's mode rows on the FE nodes), U₁ = ½ Σ_k y_k yᵀ K_Gk y with
//!
//! K_Gk = Φᵀ K_σ(σ_k) Φ,  K_σ(σ) = ∫ Gᵀ S G dV,
//!
//! σ_k = D B Φ_k the stress of mode k at the integration points, G the 9 × 3n
//! displacement-gradient matrix (∇u = G u_e, row-wise) and S = I₃ ⊗ σ the 9 × 9
//! block-diagonal stress matrix. Entry by entry,
//!
//! (K_Gk)_mn = Σ_e Σ_g w_g det J_g Σ_{i,p,q} (∇u_m)_ip (σ_k)_pq (∇u_n)_iq,
//!
//! ∇u_m the displacement gradient of mode m at the point. The element matrices K_σ,e are
//! projected on the modes element by element, Σ_e Φ_eᵀ K_σ,e Φ_e, which is Φᵀ K_σ Φ of the
//! assembled K_σ without storing it. Integration by the element's stiffness rule
//! ([`super::element::stiffness_rule`]): exact for C3D4 (constant gradients) and for C3D8 and
//! C3D20 on a parallelepiped up to the degree of the Gauss rule.
//!
//! For a straight beam along x with σ = E u′ e_x e_xᵀ, (∇uᵀ∇u)_xx = u′² + v′² + w′²: U₁ is the
//! beam's ½ ∫ EA u′ (v′² + w′²) dx (docs/methods.md §6.1) plus ½ ∫ E u′ (u_x,x)² dV, the
//! stretching of the axial fibres by the bending rotation, of relative size (r_g / ℓ)²
//! (r_g the section's radius of gyration, ℓ the bending wavelength) and dropped by the beam.
//! FNL1 then uses Q = −(K_L + Σ_k y_k K_Gk) y (`flexmbd-stiffening`).

use nalgebra::{DMatrix, Matrix3, Vector3};

use super::assembly::SolidElement;
use super::element::{IsotropicElastic, point_data, stiffness_rule};
use crate::error::FeError;

/// K_Gk for every mode k of `modes` ((3 · nodes) × n, node-major u_x, u_y, u_z) of the mesh
/// `elements` on `positions` (module docs): n symmetric n × n matrices.
pub fn geometric_stiffness(
    positions: &[Vector3<f64>],
    elements: &[SolidElement],
    material: &IsotropicElastic,
    modes: &DMatrix<f64>,
) -> Result<Vec<DMatrix<f64>>, FeError> {
    let n = modes.ncols();
    let (lambda, mu) = material.lame();
    let mut kg = vec![DMatrix::zeros(n, n); n];
    let mut x = Vec::with_capacity(20);
    let mut grad = vec![Matrix3::zeros(); n];
    let mut sigma = vec![Matrix3::zeros(); n];
    let mut g_sigma = vec![Matrix3::zeros(); n];
    for e in elements {
        x.clear();
        x.extend(e.nodes.iter().map(|&i| positions[i]));
        for (p, w) in stiffness_rule(e.kind) {
            let pd = point_data(e.kind, &x, p, &e.label)?;
            let f = w * pd.det_j;
            // ∇u of every mode at the point, and its linear stress σ = λ tr ε I + 2 μ ε.
            for (m, (g, s)) in grad.iter_mut().zip(sigma.iter_mut()).enumerate() {
                *g = Matrix3::zeros();
                for (a, &node) in e.nodes.iter().enumerate() {
                    let u = Vector3::new(
                        modes[(3 * node, m)],
                        modes[(3 * node + 1, m)],
                        modes[(3 * node + 2, m)],
                    );
                    *g += u * pd.dn[a].transpose();
                }
                let eps = (*g + g.transpose()) * 0.5;
                *s = eps * (2.0 * mu) + Matrix3::identity() * (lambda * eps.trace());
            }
            for (k, s) in sigma.iter().enumerate() {
                if s.amax() == 0.0 {
                    continue;
                }
                for (gs, g) in g_sigma.iter_mut().zip(&grad) {
                    *gs = g * s;
                }
                let kgk = &mut kg[k];
                for (mi, gm) in grad.iter().enumerate() {
                    for (ni, gs) in g_sigma.iter().enumerate() {
                        kgk[(mi, ni)] += f * gm.dot(gs);
                    }
                }
            }
        }
    }
    for m in kg.iter_mut() {
        *m = (&*m + m.transpose()) * 0.5;
    }
    Ok(kg)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solid::{SolidKind, solid_elements};
    use crate::solid_box::SolidBox;

    /// A box under the uniform uniaxial stress σ_xx = E ε of the field u = (ε x, 0, 0) (ν = 0):
    /// a field v = (0, x, 0) has ∂u/∂x = e_y, so (K_G)_vv = ∫ σ_xx dV = E ε V; the field
    /// (0, y, 0) has ∂u/∂x = 0 and a rigid translation no gradient: both 0; and the stress
    /// field's own entry is ∫ σ_xx ε² dV = E ε³ V. Every element kind, to round-off.
    #[test]
    fn uniform_tension_on_every_element_kind() {
        let (e, eps) = (2.0e11, 1e-3);
        let bar = SolidBox {
            lengths: [0.4, 0.1, 0.2],
            elements: [2, 1, 2],
            young: e,
            poisson: 0.0,
            density: 1000.0,
        };
        let volume = 0.4 * 0.1 * 0.2;
        for kind in [
            SolidKind::Tet4,
            SolidKind::Tet10,
            SolidKind::Hex8,
            SolidKind::Hex20,
        ] {
            let mesh = bar.mesh(kind).unwrap();
            let elements = solid_elements(&mesh, "box").unwrap();
            let p = &mesh.nodes.positions;
            let mut modes = DMatrix::zeros(3 * p.len(), 4);
            for (k, x) in p.iter().enumerate() {
                modes[(3 * k, 0)] = eps * x.x;
                modes[(3 * k + 1, 1)] = x.x;
                modes[(3 * k + 1, 2)] = x.y;
                modes[(3 * k + 2, 3)] = 1.0;
            }
            let kg = geometric_stiffness(p, &elements, &bar.material(), &modes).unwrap();
            let tension = &kg[0];
            let scale = e * eps * volume;
            let expected = [eps * eps * scale, scale, 0.0, 0.0];
            for (j, want) in expected.into_iter().enumerate() {
                let got = tension[(j, j)];
                assert!(
                    (got - want).abs() <= 1e-12 * scale,
                    "{kind}: mode {j}: {got} against {want}"
                );
            }
            // A rigid translation has no stress (Σ_a ∂N_a/∂x = 0 to round-off).
            assert!(kg[3].amax() <= 1e-12 * scale, "{kind}: {}", kg[3].amax());
        }
    }
}
