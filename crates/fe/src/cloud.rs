//! The mass cloud of a beam body (docs/methods.md §2.7 items 3 and 4, §2.1).
//!
//! - 2D: 4 Gauss stations per element on the centre line, weights
//!   ρA (L_e/2) w_g, rows X_g = Λ_eᵀ N_e(ξ_g) T_e X_e with linear axial and
//!   Hermite transverse shape functions. With the 2D consistent mass (no rotary
//!   inertia), Σ_g w_g X_gᵀX_g = XᵀMX exactly (4-point Gauss is exact to degree 7).
//! - 3D: each station is replaced by 4 section points at (0, ±a, 0), (0, 0, ±b)
//!   in element axes, a² = 2I_z/A, b² = 2I_y/A, weight w_g/4, rows
//!   X^t_g − d̃ X^r_g (= X^t_g + θ_g × d) with the interpolated section rotation
//!   (θx linear, θz = v′, θy = −w′). This reproduces the Rayleigh mass of §1.2
//!   (consistent + ρI_z K_σ + ρI_y K_σ^(w) + ρI_pL/6 [2 1; 1 2]) exactly.
//!
//! The cloud is purely translational with scalar weights, which is the
//! condition under which B-matrix projection and the shape integrals agree to
//! round-off (§2.7, "The condition").

use flexmbd_core::Dim;
use nalgebra::{DMatrix, Vector3};

use crate::assembly::Mesh;
use crate::beam::{AXIAL_2D, AXIAL_3D, TORSION_3D, VPLANE_2D, VPLANE_3D, WPLANE_3D, hermite};
use crate::reduced::MassCloud;

/// 4-point Gauss–Legendre rule on [−1, 1]: (abscissa, weight).
pub const GAUSS4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_8),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_8),
];

/// The element's mode rows in element axes: T_e X_e (6 × n or 12 × n).
pub fn element_local_modes(mesh: &Mesh, e: usize, x: &DMatrix<f64>) -> DMatrix<f64> {
    let dofs = mesh.element_dofs(e);
    let xe = DMatrix::from_fn(dofs.len(), x.ncols(), |i, j| x[(dofs[i], j)]);
    mesh.transformation(e) * xe
}

/// Build the mass cloud for the mode matrix `x` (N × n) on `mesh`.
pub fn build_cloud(mesh: &Mesh, x: &DMatrix<f64>) -> MassCloud {
    let n = x.ncols();
    let p = &mesh.props;
    let mut positions = Vec::new();
    let mut weights = Vec::new();
    let mut mode_rows = Vec::new();
    let a = (2.0 * p.iz / p.area).sqrt();
    let b = (2.0 * p.iy / p.area).sqrt();
    let offsets = [
        Vector3::new(0.0, a, 0.0),
        Vector3::new(0.0, -a, 0.0),
        Vector3::new(0.0, 0.0, b),
        Vector3::new(0.0, 0.0, -b),
    ];
    for (e, el) in mesh.elements.iter().enumerate() {
        let l = el.length;
        let lam_t = el.axes.transpose();
        let xl = element_local_modes(mesh, e, x);
        let r0 = mesh.nodes[el.nodes[0]];
        for &(t, wg) in GAUSS4.iter() {
            let xi = 0.5 * (1.0 + t);
            let w = p.rho * p.area * 0.5 * l * wg;
            let (hn, hd) = hermite(xi, l);
            let lin = [1.0 - xi, xi];
            let pos = r0 + lam_t.column(0) * (xi * l);
            // Local translation rows (3 × n) and rotation rows (3 × n).
            let mut tr = DMatrix::zeros(3, n);
            let mut rot = DMatrix::zeros(3, n);
            match mesh.dim {
                Dim::Planar => {
                    for j in 0..n {
                        tr[(0, j)] = lin[0] * xl[(AXIAL_2D[0], j)] + lin[1] * xl[(AXIAL_2D[1], j)];
                        tr[(1, j)] = (0..4).map(|q| hn[q] * xl[(VPLANE_2D[q], j)]).sum();
                    }
                }
                Dim::Spatial => {
                    let s = [1.0, -1.0, 1.0, -1.0];
                    for j in 0..n {
                        tr[(0, j)] = lin[0] * xl[(AXIAL_3D[0], j)] + lin[1] * xl[(AXIAL_3D[1], j)];
                        tr[(1, j)] = (0..4).map(|q| hn[q] * xl[(VPLANE_3D[q], j)]).sum();
                        tr[(2, j)] = (0..4).map(|q| s[q] * hn[q] * xl[(WPLANE_3D[q], j)]).sum();
                        rot[(0, j)] =
                            lin[0] * xl[(TORSION_3D[0], j)] + lin[1] * xl[(TORSION_3D[1], j)];
                        // θy = −w′ with w = Σ s_q N_q (w, θy)_q.
                        rot[(1, j)] = -(0..4)
                            .map(|q| s[q] * hd[q] * xl[(WPLANE_3D[q], j)])
                            .sum::<f64>();
                        rot[(2, j)] = (0..4).map(|q| hd[q] * xl[(VPLANE_3D[q], j)]).sum();
                    }
                }
            }
            match mesh.dim {
                Dim::Planar => {
                    push_point(
                        &mut positions,
                        &mut weights,
                        &mut mode_rows,
                        pos,
                        w,
                        &(lam_t * &tr),
                    );
                }
                Dim::Spatial => {
                    for d in &offsets {
                        // θ × d for every mode column, in element axes.
                        let mut rows = tr.clone();
                        for j in 0..n {
                            let th = Vector3::new(rot[(0, j)], rot[(1, j)], rot[(2, j)]);
                            let c = th.cross(d);
                            for r in 0..3 {
                                rows[(r, j)] += c[r];
                            }
                        }
                        push_point(
                            &mut positions,
                            &mut weights,
                            &mut mode_rows,
                            pos + lam_t * d,
                            0.25 * w,
                            &(lam_t * &rows),
                        );
                    }
                }
            }
        }
    }
    let description = match mesh.dim {
        Dim::Planar => format!(
            "beam centre line: 4 Gauss stations per element ({} elements, {} points), \
             linear axial + Hermite transverse rows, consistent mass without rotary inertia",
            mesh.elements.len(),
            weights.len()
        ),
        Dim::Spatial => format!(
            "beam sections: 4 Gauss stations per element, 4 section points each \
             ({} elements, {} points; a^2 = 2 Iz/A, b^2 = 2 Iy/A), Rayleigh mass",
            mesh.elements.len(),
            weights.len()
        ),
    };
    MassCloud {
        n_modes: n,
        positions,
        weights,
        mode_rows,
        description,
    }
}

fn push_point(
    positions: &mut Vec<Vector3<f64>>,
    weights: &mut Vec<f64>,
    mode_rows: &mut Vec<f64>,
    pos: Vector3<f64>,
    w: f64,
    rows: &nalgebra::Matrix3xX<f64>,
) {
    positions.push(pos);
    weights.push(w);
    for r in 0..3 {
        for j in 0..rows.ncols() {
            mode_rows.push(rows[(r, j)]);
        }
    }
}

/// Σ_k w_k X_kᵀ X_k (n × n): the cloud's reduced mass, to compare with XᵀMX.
pub fn cloud_mass(cloud: &MassCloud) -> DMatrix<f64> {
    let n = cloud.n_modes;
    let mut m = DMatrix::zeros(n, n);
    for k in 0..cloud.len() {
        let w = cloud.weights[k];
        let x = DMatrix::from_row_slice(3, n, cloud.rows(k));
        m += (x.transpose() * x) * w;
    }
    m
}
