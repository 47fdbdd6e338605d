//! Element matrices of the isoparametric solids of [`super::shape`]: isotropic linear
//! elasticity, stiffness, consistent and lumped mass (Zienkiewicz, Taylor & Zhu 2013,
//! §6.5, §16.2.4; Bathe 1996, §5.3).
//!
//! With the element's node positions x_a, the map x(ξ) = Σ_a N_a(ξ) x_a has the Jacobian
//! J_ij = ∂x_i/∂ξ_j = Σ_a x_ai ∂N_a/∂ξ_j, and ∂N_a/∂x = J⁻ᵀ ∂N_a/∂ξ. An integration point
//! where det J ≤ 0 means an inverted or degenerate element: refused, naming the element.
//!
//! - Strain ε = B u, ε = (ε_xx, ε_yy, ε_zz, γ_xy, γ_yz, γ_zx); for node a
//!   B_a = [[∂x,0,0],[0,∂y,0],[0,0,∂z],[∂y,∂x,0],[0,∂z,∂y],[∂z,0,∂x]] N_a.
//! - σ = D ε, D = λ 1·1ᵀ (normal strains) + 2μ I₃ ⊕ μ I₃, λ = E ν / ((1 + ν)(1 − 2ν)),
//!   μ = E / (2 (1 + ν)).
//! - K_e = ∫ Bᵀ D B dV, consistent M_e = ρ ∫ Nᵀ N dV (N the 3 × 3n matrix of the N_a).
//!
//! Integration ([`super::quadrature`]): C3D4 K by the centroid (B constant: exact), M by
//! the 4-point rule (degree 2: exact); C3D10 K by the 4-point rule (exact on a straight-sided
//! element; Abaqus's and CalculiX's rule), M by the collapsed 64-point rule (degree 5: exact
//! for the quartic N_a N_b); C3D8 K and M by 2 × 2 × 2 Gauss points (full integration, as
//! CalculiX's C3D8; exact for M and for K on a parallelepiped); C3D20 K and M by 3 × 3 × 3
//! (full integration, CalculiX's C3D20; exact for M on a parallelepiped).
//!
//! **Lumped mass**, diagonal, each element's mass m_e = ρ V_e kept in each direction:
//! C3D4 and C3D8 by the row sum, m_a = ρ ∫ N_a dV (the N_a ≥ 0, so every m_a > 0: ρ V/4 on
//! a tetrahedron, ρ V/8 on a parallelepiped); C3D10 and C3D20 by HRZ diagonal scaling
//! (Hinton, Rock & Zienkiewicz, Earthquake Eng. Struct. Dyn. 4, 1976), m_a = M_aa m_e /
//! Σ_b M_bb, because their row sums are zero (C3D10) or negative (C3D20) at the corners.

use nalgebra::{DMatrix, Matrix3, SMatrix, Vector3};
use serde::{Deserialize, Serialize};

use super::quadrature::{self, Point};
use super::shape::SolidKind;
use crate::error::FeError;
use flexmbd_core::InvalidValue;

/// An isotropic linear-elastic material (SI units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IsotropicElastic {
    /// Young's modulus E (Pa), > 0.
    pub young: f64,
    /// Poisson's ratio ν, in (−1, 0.5).
    pub poisson: f64,
    /// Density ρ (kg/m³), > 0.
    pub density: f64,
}

impl IsotropicElastic {
    /// Steel: E = 210 GPa, ν = 0.3, ρ = 7850 kg/m³.
    pub const STEEL: IsotropicElastic = IsotropicElastic {
        young: 210e9,
        poisson: 0.3,
        density: 7850.0,
    };

    /// Refuse non-positive or non-finite moduli and density and ν outside (−1, 0.5);
    /// `prefix` leads the field names (e.g. `bodies[rod].material`).
    pub fn validate(&self, prefix: &str) -> Result<(), InvalidValue> {
        let field = |f: &str| {
            if prefix.is_empty() {
                f.to_string()
            } else {
                format!("{prefix}.{f}")
            }
        };
        for (name, v) in [("young", self.young), ("density", self.density)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(InvalidValue::new(field(name), v, "must be finite and > 0"));
            }
        }
        if !(self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(InvalidValue::new(
                field("poisson"),
                self.poisson,
                "must lie in (-1, 0.5) (the bulk and shear moduli positive)",
            ));
        }
        Ok(())
    }

    /// Lamé's λ and μ.
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.young, self.poisson);
        (
            e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            e / (2.0 * (1.0 + nu)),
        )
    }

    /// The elasticity matrix D (6 × 6, engineering shear strains; module docs).
    pub fn elasticity(&self) -> SMatrix<f64, 6, 6> {
        let (lambda, mu) = self.lame();
        let mut d = SMatrix::<f64, 6, 6>::zeros();
        for i in 0..3 {
            for j in 0..3 {
                d[(i, j)] = lambda;
            }
            d[(i, i)] += 2.0 * mu;
            d[(i + 3, i + 3)] = mu;
        }
        d
    }
}

/// The mass matrix of the elements.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum MassMatrix {
    /// Consistent: ρ ∫ Nᵀ N dV.
    #[default]
    Consistent,
    /// Lumped (diagonal): row sum for C3D4 and C3D8, HRZ for C3D10 and C3D20 (module docs).
    Lumped,
}

/// The stiffness rule of a kind (module docs).
pub fn stiffness_rule(kind: SolidKind) -> Vec<Point> {
    match kind {
        SolidKind::Tet4 => quadrature::tet_centroid(),
        SolidKind::Tet10 => quadrature::tet_four_point(),
        SolidKind::Hex8 => quadrature::hex_gauss(2),
        SolidKind::Hex20 => quadrature::hex_gauss(3),
    }
}

/// The consistent-mass rule of a kind (module docs).
pub fn mass_rule(kind: SolidKind) -> Vec<Point> {
    match kind {
        SolidKind::Tet4 => quadrature::tet_four_point(),
        SolidKind::Tet10 => quadrature::tet_collapsed(4),
        SolidKind::Hex8 => quadrature::hex_gauss(2),
        SolidKind::Hex20 => quadrature::hex_gauss(3),
    }
}

/// Shape functions, physical gradients and det J of one element at one parent point.
pub struct PointData {
    /// N_a.
    pub n: Vec<f64>,
    /// ∂N_a/∂(x, y, z).
    pub dn: Vec<Vector3<f64>>,
    /// det J.
    pub det_j: f64,
}

/// [`PointData`] at `p` of the element of `kind` with node positions `x`; a non-positive
/// det J is refused naming `element` (e.g. `element 12 of bar.msh`) and the point.
pub fn point_data(
    kind: SolidKind,
    x: &[Vector3<f64>],
    p: [f64; 3],
    element: &str,
) -> Result<PointData, FeError> {
    let nn = kind.n_nodes();
    let (mut n, mut dxi) = (vec![0.0; nn], vec![[0.0; 3]; nn]);
    kind.shape(p, &mut n, &mut dxi);
    let mut j = Matrix3::<f64>::zeros();
    for (xa, da) in x.iter().zip(&dxi) {
        for r in 0..3 {
            for c in 0..3 {
                j[(r, c)] += xa[r] * da[c];
            }
        }
    }
    let det_j: f64 = j.determinant();
    if !det_j.is_finite() {
        return Err(FeError::Invalid(InvalidValue::new(
            element.to_string(),
            format!("det J = {det_j:e} at parent point {p:?}"),
            "the Jacobian determinant is not finite: node coordinates too large",
        )));
    }
    let scale = x
        .iter()
        .map(|xa| (xa - x[0]).norm())
        .fold(0.0_f64, f64::max);
    // A determinant below round-off of the element's size cubed is degenerate too.
    let positive = det_j > 1e-12 * scale.powi(3);
    if !positive {
        return Err(FeError::Invalid(InvalidValue::new(
            element.to_string(),
            format!("det J = {det_j:e} at parent point {p:?}"),
            format!(
                "the {kind} element is inverted or degenerate (non-positive Jacobian \
                 determinant): check its node order and positions"
            ),
        )));
    }
    let j_inv_t = j
        .try_inverse()
        .map(|m| m.transpose())
        .unwrap_or_else(Matrix3::zeros);
    let dn = dxi.iter().map(|d| j_inv_t * Vector3::from(*d)).collect();
    Ok(PointData { n, dn, det_j })
}

/// The strain-displacement matrix B (6 × 3n) from the physical gradients.
pub fn strain_displacement(dn: &[Vector3<f64>]) -> DMatrix<f64> {
    let mut b = DMatrix::zeros(6, 3 * dn.len());
    for (a, d) in dn.iter().enumerate() {
        let c = 3 * a;
        b[(0, c)] = d.x;
        b[(1, c + 1)] = d.y;
        b[(2, c + 2)] = d.z;
        b[(3, c)] = d.y;
        b[(3, c + 1)] = d.x;
        b[(4, c + 1)] = d.z;
        b[(4, c + 2)] = d.y;
        b[(5, c)] = d.z;
        b[(5, c + 2)] = d.x;
    }
    b
}

/// K_e (3n × 3n, node-major DOFs u_x, u_y, u_z), symmetric to the last bit.
pub fn stiffness(
    kind: SolidKind,
    x: &[Vector3<f64>],
    material: &IsotropicElastic,
    element: &str,
) -> Result<DMatrix<f64>, FeError> {
    let d = material.elasticity();
    let n3 = 3 * kind.n_nodes();
    let mut k = DMatrix::zeros(n3, n3);
    for (p, w) in stiffness_rule(kind) {
        let pd = point_data(kind, x, p, element)?;
        let b = strain_displacement(&pd.dn);
        let db = d * &b;
        k.gemm_tr(w * pd.det_j, &b, &db, 1.0);
    }
    Ok(symmetrised(k))
}

/// M_e (3n × 3n), consistent or lumped, integrated by the points `points` (the exact
/// [`mass_rule`] but to compare with a code that integrates otherwise).
pub fn mass(
    kind: SolidKind,
    x: &[Vector3<f64>],
    density: f64,
    rule: MassMatrix,
    points: &[Point],
    element: &str,
) -> Result<DMatrix<f64>, FeError> {
    let nn = kind.n_nodes();
    // The scalar mass matrix ρ ∫ N_a N_b dV; M_e is it on each direction.
    let mut s = DMatrix::zeros(nn, nn);
    for &(p, w) in points {
        let pd = point_data(kind, x, p, element)?;
        let f = density * w * pd.det_j;
        for a in 0..nn {
            for b in 0..nn {
                s[(a, b)] += f * pd.n[a] * pd.n[b];
            }
        }
    }
    let s = symmetrised(s);
    let diagonal = match (rule, kind) {
        (MassMatrix::Consistent, _) => None,
        (MassMatrix::Lumped, SolidKind::Tet4 | SolidKind::Hex8) => {
            Some(s.row_iter().map(|r| r.sum()).collect::<Vec<_>>())
        }
        (MassMatrix::Lumped, SolidKind::Tet10 | SolidKind::Hex20) => {
            let total = s.sum();
            let trace = s.trace();
            Some((0..nn).map(|a| s[(a, a)] * total / trace).collect())
        }
    };
    let mut m = DMatrix::zeros(3 * nn, 3 * nn);
    for a in 0..nn {
        for b in 0..nn {
            let v = match &diagonal {
                None => s[(a, b)],
                Some(diag) if a == b => diag[a],
                Some(_) => continue,
            };
            for dir in 0..3 {
                m[(3 * a + dir, 3 * b + dir)] = v;
            }
        }
    }
    Ok(m)
}

fn symmetrised(a: DMatrix<f64>) -> DMatrix<f64> {
    (&a + a.transpose()) * 0.5
}
