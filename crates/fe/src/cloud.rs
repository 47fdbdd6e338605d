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
use crate::beam::{
    AXIAL_2D, AXIAL_3D, BeamProps, TORSION_3D, VPLANE_2D, VPLANE_3D, WPLANE_3D, hermite,
};
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

/// Build the mass cloud for the mode matrix `x` (N × n) on `mesh`: at each of
/// the 4 Gauss stations of every element, the centre-line point (2D) or the 4
/// section points (3D), with the station's mode rows rotated into body axes.
pub fn build_cloud(mesh: &Mesh, x: &DMatrix<f64>) -> MassCloud {
    let n = x.ncols();

    let mut cloud = MassCloud {
        n_modes: n,
        positions: Vec::new(),
        weights: Vec::new(),
        mode_rows: Vec::new(),
        description: String::new(),
    };
    for (e, el) in mesh.elements.iter().enumerate() {
        let p = &el.props;
        let offsets = section_offsets(p);
        let l = el.length;
        let lam_t = el.axes.transpose();
        let xl = element_local_modes(mesh, e, x);
        let r0 = mesh.nodes[el.nodes[0]];
        for &(t, wg) in GAUSS4.iter() {
            let xi = 0.5 * (1.0 + t);
            let w = p.rho * p.area * 0.5 * l * wg;
            let pos = r0 + lam_t.column(0) * (xi * l);
            match mesh.dim {
                Dim::Planar => {
                    let tr = planar_station_rows(&xl, xi, l);
                    push_point(&mut cloud, pos, w, &(lam_t * &tr));
                }
                Dim::Spatial => {
                    let (tr, rot) = spatial_station_rows(&xl, xi, l);
                    for d in &offsets {
                        let rows = section_point_rows(&tr, &rot, d);
                        push_point(&mut cloud, pos + lam_t * d, 0.25 * w, &(lam_t * &rows));
                    }
                }
            }
        }
    }
    cloud.description = cloud_description(mesh, cloud.len());
    cloud
}

/// The 3D section points' offsets in element axes, (0, ±a, 0) and (0, 0, ±b)
/// with a² = 2I_z/A and b² = 2I_y/A: each pair carries the section's second
/// moment about one element axis, which gives the rotary inertia.
fn section_offsets(p: &BeamProps) -> [Vector3<f64>; 4] {
    let a = (2.0 * p.iz / p.area).sqrt();
    let b = (2.0 * p.iy / p.area).sqrt();
    [
        Vector3::new(0.0, a, 0.0),
        Vector3::new(0.0, -a, 0.0),
        Vector3::new(0.0, 0.0, b),
        Vector3::new(0.0, 0.0, -b),
    ]
}

/// 2D: the translation rows (3 × n, element axes; z row zero) of the centre
/// line at ξ = `xi` along an element of length `l`: linear axial u, Hermite
/// transverse v, interpolated from the element's local mode rows `xl`.
fn planar_station_rows(xl: &DMatrix<f64>, xi: f64, l: f64) -> DMatrix<f64> {
    let n = xl.ncols();
    let (hn, _) = hermite(xi, l);
    let lin = [1.0 - xi, xi];
    let mut tr = DMatrix::zeros(3, n);
    for j in 0..n {
        tr[(0, j)] = lin[0] * xl[(AXIAL_2D[0], j)] + lin[1] * xl[(AXIAL_2D[1], j)];
        tr[(1, j)] = (0..4).map(|q| hn[q] * xl[(VPLANE_2D[q], j)]).sum();
    }
    tr
}

/// 3D: the translation rows and the section rotation rows (each 3 × n, element
/// axes) at ξ = `xi` along an element of length `l`: linear axial u and twist
/// θx, Hermite v and w, and the bending rotations θz = v′, θy = −w′.
fn spatial_station_rows(xl: &DMatrix<f64>, xi: f64, l: f64) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = xl.ncols();
    let (hn, hd) = hermite(xi, l);
    let lin = [1.0 - xi, xi];
    // The w-plane nodal DOFs are (w, θy) and the nodal slope is w′ = −θy, so the
    // slope entries of the Hermite interpolation enter with a minus sign.
    let s = [1.0, -1.0, 1.0, -1.0];
    let mut tr = DMatrix::zeros(3, n);
    let mut rot = DMatrix::zeros(3, n);
    for j in 0..n {
        tr[(0, j)] = lin[0] * xl[(AXIAL_3D[0], j)] + lin[1] * xl[(AXIAL_3D[1], j)];
        tr[(1, j)] = (0..4).map(|q| hn[q] * xl[(VPLANE_3D[q], j)]).sum();
        tr[(2, j)] = (0..4).map(|q| s[q] * hn[q] * xl[(WPLANE_3D[q], j)]).sum();
        rot[(0, j)] = lin[0] * xl[(TORSION_3D[0], j)] + lin[1] * xl[(TORSION_3D[1], j)];
        // θy = −w′ with w = Σ s_q N_q (w, θy)_q.
        rot[(1, j)] = -(0..4)
            .map(|q| s[q] * hd[q] * xl[(WPLANE_3D[q], j)])
            .sum::<f64>();
        rot[(2, j)] = (0..4).map(|q| hd[q] * xl[(VPLANE_3D[q], j)]).sum();
    }
    (tr, rot)
}

/// The mode rows (element axes) of the section point at offset `d` from the
/// station: its translation `tr` plus θ × d for every mode column.
fn section_point_rows(tr: &DMatrix<f64>, rot: &DMatrix<f64>, d: &Vector3<f64>) -> DMatrix<f64> {
    let mut rows = tr.clone();
    for j in 0..tr.ncols() {
        let th = Vector3::new(rot[(0, j)], rot[(1, j)], rot[(2, j)]);
        let c = th.cross(d);
        for r in 0..3 {
            rows[(r, j)] += c[r];
        }
    }
    rows
}

/// What the cloud of `mesh` is, for reports beside cost comparisons.
fn cloud_description(mesh: &Mesh, n_points: usize) -> String {
    match mesh.dim {
        Dim::Planar => format!(
            "beam centre line: 4 Gauss stations per element ({} elements, {} points), \
             linear axial + Hermite transverse rows, consistent mass without rotary inertia",
            mesh.elements.len(),
            n_points
        ),
        Dim::Spatial => format!(
            "beam sections: 4 Gauss stations per element, 4 section points each \
             ({} elements, {} points; a^2 = 2 Iz/A, b^2 = 2 Iy/A), Rayleigh mass",
            mesh.elements.len(),
            n_points
        ),
    }
}

/// Append one point of weight `w` at `pos` with its body-axes mode rows (3 × n).
fn push_point(cloud: &mut MassCloud, pos: Vector3<f64>, w: f64, rows: &nalgebra::Matrix3xX<f64>) {
    cloud.positions.push(pos);
    cloud.weights.push(w);
    for r in 0..3 {
        for j in 0..rows.ncols() {
            cloud.mode_rows.push(rows[(r, j)]);
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
