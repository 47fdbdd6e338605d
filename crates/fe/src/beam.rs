//! Euler–Bernoulli beam element matrices in element axes (docs/methods.md §1.2, [R: standard FE]).
//!
//! Local DOFs:
//! - 2D: (u₁, v₁, θ₁, u₂, v₂, θ₂), θ = v′.
//! - 3D: (u, v, w, θx, θy, θz) per node, with θz = v′ and θy = −w′; the
//!   (w, θy) blocks are the (v, θz) blocks with every w–θy coupling sign-flipped.
//!
//! Blocks (length L):
//! - axial: EA/L [1 −1; −1 1], mass ρAL/6 [2 1; 1 2];
//! - bending: EI/L³ [12 6L −12 6L; …], consistent mass ρAL/420 [156 22L 54 −13L; …];
//! - torsion: GJ/L [1 −1; −1 1] (J Saint-Venant), mass ρI_pL/6 [2 1; 1 2] (I_p = I_y + I_z);
//! - unit-axial-force geometric matrix K_σ = ∫ N′ᵀN′ dx = 1/(30L) [36 3L −36 3L; …].
//!
//! Default mass (so that the mass cloud of §2.7 reproduces XᵀMX exactly):
//! 2D consistent mass without rotary inertia; 3D Rayleigh mass = consistent
//! + ρI_z K_σ + ρI_y K_σ^(w) + the torsion block.

use nalgebra::{Matrix4, SMatrix};

/// 6 × 6 element matrix (2D).
pub type Mat6 = SMatrix<f64, 6, 6>;
/// 12 × 12 element matrix (3D).
pub type Mat12 = SMatrix<f64, 12, 12>;

/// Which element mass matrix to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MassModel {
    /// Consistent translational mass only (plus, in 3D, the torsion block).
    /// The 2D default.
    Consistent,
    /// Consistent + cross-section rotary inertia ρI K_σ in both bending planes
    /// (+ torsion block). The 3D default (Rayleigh beam).
    Rayleigh,
}

/// Material and section constants of an element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamProps {
    /// Young's modulus E (Pa).
    pub e: f64,
    /// Shear modulus G (Pa).
    pub g: f64,
    /// Density ρ (kg/m³).
    pub rho: f64,
    /// Area A (m²).
    pub area: f64,
    /// I_y = ∫ z² dA (m⁴).
    pub iy: f64,
    /// I_z = ∫ y² dA (m⁴).
    pub iz: f64,
    /// Saint-Venant J (m⁴).
    pub j: f64,
}

impl BeamProps {
    /// Polar moment I_p = I_y + I_z.
    pub fn ip(&self) -> f64 {
        self.iy + self.iz
    }
}

/// Bending stiffness on (v₁, θz₁, v₂, θz₂) for unit EI.
pub fn bending_stiffness_unit(l: f64) -> Matrix4<f64> {
    let l2 = l * l;
    Matrix4::new(
        12.0,
        6.0 * l,
        -12.0,
        6.0 * l,
        6.0 * l,
        4.0 * l2,
        -6.0 * l,
        2.0 * l2,
        -12.0,
        -6.0 * l,
        12.0,
        -6.0 * l,
        6.0 * l,
        2.0 * l2,
        -6.0 * l,
        4.0 * l2,
    ) / (l2 * l)
}

/// Consistent bending mass on (v₁, θz₁, v₂, θz₂) for unit ρA.
pub fn bending_mass_unit(l: f64) -> Matrix4<f64> {
    let l2 = l * l;
    Matrix4::new(
        156.0,
        22.0 * l,
        54.0,
        -13.0 * l,
        22.0 * l,
        4.0 * l2,
        13.0 * l,
        -3.0 * l2,
        54.0,
        13.0 * l,
        156.0,
        -22.0 * l,
        -13.0 * l,
        -3.0 * l2,
        -22.0 * l,
        4.0 * l2,
    ) * (l / 420.0)
}

/// The unit-axial-force geometric matrix K_σ = ∫₀ᴸ N′ᵀN′ dx on (v₁, θz₁, v₂, θz₂).
pub fn k_sigma(l: f64) -> Matrix4<f64> {
    let l2 = l * l;
    Matrix4::new(
        36.0,
        3.0 * l,
        -36.0,
        3.0 * l,
        3.0 * l,
        4.0 * l2,
        -3.0 * l,
        -l2,
        -36.0,
        -3.0 * l,
        36.0,
        -3.0 * l,
        3.0 * l,
        -l2,
        -3.0 * l,
        4.0 * l2,
    ) / (30.0 * l)
}

/// The (w, θy) version of a (v, θz) block: every w–θy coupling sign-flipped
/// (D B D with D = diag(1, −1, 1, −1)), because θy = −w′.
pub fn flip_w(b: &Matrix4<f64>) -> Matrix4<f64> {
    let s = [1.0, -1.0, 1.0, -1.0];
    Matrix4::from_fn(|i, j| s[i] * s[j] * b[(i, j)])
}

/// K_σ^(w) on (w₁, θy₁, w₂, θy₂).
pub fn k_sigma_w(l: f64) -> Matrix4<f64> {
    flip_w(&k_sigma(l))
}

/// 2D element stiffness on (u₁, v₁, θ₁, u₂, v₂, θ₂); in-plane bending uses I_z.
pub fn stiffness_2d(p: &BeamProps, l: f64) -> Mat6 {
    let mut k = Mat6::zeros();
    let ea = p.e * p.area / l;
    put_stiff2(&mut k, AXIAL_2D, ea);
    put4(
        &mut k,
        VPLANE_2D,
        &(bending_stiffness_unit(l) * (p.e * p.iz)),
    );
    k
}

/// 2D element mass on (u₁, v₁, θ₁, u₂, v₂, θ₂).
/// [`MassModel::Consistent`] (default) has no rotary inertia; Rayleigh adds ρI_z K_σ.
pub fn mass_2d(p: &BeamProps, l: f64, model: MassModel) -> Mat6 {
    let mut m = Mat6::zeros();
    put_mass2(&mut m, AXIAL_2D, p.rho * p.area * l / 6.0);
    let mut b = bending_mass_unit(l) * (p.rho * p.area);
    if model == MassModel::Rayleigh {
        b += k_sigma(l) * (p.rho * p.iz);
    }
    put4(&mut m, VPLANE_2D, &b);
    m
}

/// Local 3D index sets: axial, v-plane (v, θz), w-plane (w, θy), torsion.
pub const AXIAL_3D: [usize; 2] = [0, 6];
/// (v₁, θz₁, v₂, θz₂).
pub const VPLANE_3D: [usize; 4] = [1, 5, 7, 11];
/// (w₁, θy₁, w₂, θy₂).
pub const WPLANE_3D: [usize; 4] = [2, 4, 8, 10];
/// (θx₁, θx₂).
pub const TORSION_3D: [usize; 2] = [3, 9];
/// 2D axial (u₁, u₂).
pub const AXIAL_2D: [usize; 2] = [0, 3];
/// 2D bending (v₁, θ₁, v₂, θ₂).
pub const VPLANE_2D: [usize; 4] = [1, 2, 4, 5];

/// 3D element stiffness on (u, v, w, θx, θy, θz)₁,₂.
pub fn stiffness_3d(p: &BeamProps, l: f64) -> Mat12 {
    let mut k = Mat12::zeros();
    put_stiff2(&mut k, AXIAL_3D, p.e * p.area / l);
    let kb = bending_stiffness_unit(l);
    put4(&mut k, VPLANE_3D, &(kb * (p.e * p.iz)));
    put4(&mut k, WPLANE_3D, &(flip_w(&kb) * (p.e * p.iy)));
    put_stiff2(&mut k, TORSION_3D, p.g * p.j / l);
    k
}

/// 3D element mass. Both models include the torsion block ρI_pL/6 [2 1; 1 2];
/// [`MassModel::Rayleigh`] (the 3D default) adds ρI_z K_σ and ρI_y K_σ^(w).
pub fn mass_3d(p: &BeamProps, l: f64, model: MassModel) -> Mat12 {
    let mut m = Mat12::zeros();
    put_mass2(&mut m, AXIAL_3D, p.rho * p.area * l / 6.0);
    let mb = bending_mass_unit(l) * (p.rho * p.area);
    let mut mv = mb;
    let mut mw = flip_w(&mb);
    if model == MassModel::Rayleigh {
        mv += k_sigma(l) * (p.rho * p.iz);
        mw += k_sigma_w(l) * (p.rho * p.iy);
    }
    put4(&mut m, VPLANE_3D, &mv);
    put4(&mut m, WPLANE_3D, &mw);
    put_mass2(&mut m, TORSION_3D, p.rho * p.ip() * l / 6.0);
    m
}

/// Add c [1 −1; −1 1] on the index pair (bar / shaft stiffness).
fn put_stiff2<const N: usize>(m: &mut SMatrix<f64, N, N>, idx: [usize; 2], c: f64) {
    m[(idx[0], idx[0])] += c;
    m[(idx[1], idx[1])] += c;
    m[(idx[0], idx[1])] -= c;
    m[(idx[1], idx[0])] -= c;
}

/// Add c [2 1; 1 2] on the index pair (consistent linear-element mass).
fn put_mass2<const N: usize>(m: &mut SMatrix<f64, N, N>, idx: [usize; 2], c: f64) {
    m[(idx[0], idx[0])] += 2.0 * c;
    m[(idx[1], idx[1])] += 2.0 * c;
    m[(idx[0], idx[1])] += c;
    m[(idx[1], idx[0])] += c;
}

fn put4<const N: usize>(m: &mut SMatrix<f64, N, N>, idx: [usize; 4], b: &Matrix4<f64>) {
    for (a, &i) in idx.iter().enumerate() {
        for (c, &j) in idx.iter().enumerate() {
            m[(i, j)] += b[(a, c)];
        }
    }
}

/// Hermite cubic shape functions on (v₁, θ₁, v₂, θ₂) at ξ = x/L ∈ [0, 1]:
/// returns (N, dN/dx), so v = N·(v₁, θ₁, v₂, θ₂) and v′ = (dN/dx)·(…).
pub fn hermite(xi: f64, l: f64) -> ([f64; 4], [f64; 4]) {
    let x2 = xi * xi;
    let x3 = x2 * xi;
    (
        [
            1.0 - 3.0 * x2 + 2.0 * x3,
            l * (xi - 2.0 * x2 + x3),
            3.0 * x2 - 2.0 * x3,
            l * (x3 - x2),
        ],
        [
            (6.0 * x2 - 6.0 * xi) / l,
            1.0 - 4.0 * xi + 3.0 * x2,
            (6.0 * xi - 6.0 * x2) / l,
            3.0 * x2 - 2.0 * xi,
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn props() -> BeamProps {
        BeamProps {
            e: 2.0e11,
            g: 8.0e10,
            rho: 7800.0,
            area: 2e-4,
            iy: 6.0e-9,
            iz: 1.5e-9,
            j: 4.0e-9,
        }
    }

    #[test]
    fn k_sigma_is_integral_of_hermite_derivatives() {
        let l = 0.37;
        // 4-point Gauss is exact for the degree-4 integrand.
        let gp = [
            (-0.861_136_311_594_052_6, 0.347_854_845_137_453_8),
            (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
            (0.861_136_311_594_052_6, 0.347_854_845_137_453_8),
        ];
        let mut ks = Matrix4::zeros();
        let mut mb = Matrix4::zeros();
        for (t, w) in gp {
            let (n, dn) = hermite(0.5 * (1.0 + t), l);
            for i in 0..4 {
                for j in 0..4 {
                    ks[(i, j)] += 0.5 * l * w * dn[i] * dn[j];
                    mb[(i, j)] += 0.5 * l * w * n[i] * n[j];
                }
            }
        }
        assert!((ks - k_sigma(l)).norm() < 1e-13 * k_sigma(l).norm());
        assert!((mb - bending_mass_unit(l)).norm() < 1e-13 * bending_mass_unit(l).norm());
    }

    #[test]
    fn element_matrices_symmetric_and_rigid_free() {
        let p = props();
        let l = 0.3;
        let k = stiffness_3d(&p, l);
        let m = mass_3d(&p, l, MassModel::Rayleigh);
        assert_eq!(k, k.transpose());
        assert_eq!(m, m.transpose());
        // Rigid rotation about local z by small angle: v = x θ, θz = θ.
        let mut d = SMatrix::<f64, 12, 1>::zeros();
        d[5] = 1.0;
        d[7] = l;
        d[11] = 1.0;
        assert!((k * d).norm() < 1e-6 * k.norm());
        // Rigid rotation about local y: w = −x θ, θy = θ.
        let mut d = SMatrix::<f64, 12, 1>::zeros();
        d[4] = 1.0;
        d[8] = -l;
        d[10] = 1.0;
        assert!((k * d).norm() < 1e-6 * k.norm());
        // Mass: total translational mass ρAL along each axis.
        let ones_u = {
            let mut d = SMatrix::<f64, 12, 1>::zeros();
            d[1] = 1.0;
            d[7] = 1.0;
            d
        };
        let mt = (ones_u.transpose() * m * ones_u)[0];
        assert!((mt - p.rho * p.area * l).abs() < 1e-14);
    }
}
