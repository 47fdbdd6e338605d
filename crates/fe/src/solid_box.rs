//! A structured mesh of a rectangular box in 8-node linear-elastic bricks (hex8): the sparse
//! stiffness K and consistent mass M of a solid, for the tests and measurements of the sparse
//! eigen-solver ([`crate::sparse_eigen`]).
//!
//! The box `[0, Lx] × [0, Ly] × [0, Lz]` is cut into `nx × ny × nz` equal bricks of sides
//! `a × b × c`; node `(i, j, k)` sits at `(i a, j b, k c)` and has index
//! `i + (nx + 1) (j + (ny + 1) k)`, its displacements `(u_x, u_y, u_z)` are DOFs `3 node + 0, 1, 2`.
//! Nothing is supported: the model is free-free (six rigid-body modes).
//!
//! ## The element (Bathe, *Finite Element Procedures*, 1996, §5.3; Zienkiewicz, Taylor & Zhu,
//! *The Finite Element Method: Its Basis and Fundamentals*, 7th ed., 2013, §6.5)
//!
//! Trilinear shape functions on the parent cube ξ, η, ζ ∈ [−1, 1]:
//! N_a = ⅛ (1 + ξ ξ_a)(1 + η η_a)(1 + ζ ζ_a), with the corners (ξ_a, η_a, ζ_a) ∈ {±1}³.
//! A brick of the box maps affinely, x = a (ξ + 1)/2 …, so the Jacobian is
//! J = diag(a, b, c)/2, det J = a b c / 8 and ∂N_a/∂x = (2/a) ∂N_a/∂ξ, and so on.
//!
//! - Strain ε = B u with ε = (ε_xx, ε_yy, ε_zz, γ_xy, γ_yz, γ_zx) and, for node a,
//!   B_a = [[∂x,0,0],[0,∂y,0],[0,0,∂z],[∂y,∂x,0],[0,∂z,∂y],[∂z,0,∂x]] N_a.
//! - Isotropic elasticity: σ = D ε with D = λ 1·1ᵀ (on the normal strains) + 2μ I₃ ⊕ μ I₃,
//!   λ = E ν / ((1 + ν)(1 − 2ν)), μ = E / (2 (1 + ν)).
//! - K_e = ∫ Bᵀ D B dV and the consistent mass M_e = ρ ∫ Nᵀ N dV (N the 3 × 24 matrix of the
//!   N_a), both by 2 × 2 × 2 Gauss points ±1/√3 with unit weights: exact for M_e (quadratic
//!   in each direction) and for K_e on an undistorted brick. This full integration locks in
//!   bending (parasitic shear): a bar's bending frequencies come out high and converge from
//!   above as O(h²) under refinement.
//!
//! All bricks of the structured mesh are equal, so K_e and M_e are computed once; the
//! pattern is that of the node graph (each node couples with its up to 27 neighbours in the
//! grid, 3 × 3 blocks), built column by column in order, so no triplets are stored.

use std::collections::HashMap;

use nalgebra::{SMatrix, SVector, Vector3};
use sprs::CsMat;

use crate::error::FeError;
use crate::import::nodes::NodeList;
use crate::import::{Element, FeMesh};
use crate::solid::IsotropicElastic;
// The corners of the parent brick in the element's node order (counter-clockwise at
// ζ = −1, then at ζ = +1) are the general hexahedra's.
use crate::solid::shape::{HEX_CORNERS as CORNERS, HEX20_EDGES, SolidKind, TET10_EDGES};
use flexmbd_core::InvalidValue;

/// A 24 × 24 element matrix (8 nodes × 3 displacements, node-major).
pub type BrickMatrix = SMatrix<f64, 24, 24>;

/// A box of linear-elastic hex8 bricks (SI units).
#[derive(Clone, Debug, PartialEq)]
pub struct SolidBox {
    /// Edge lengths (L_x, L_y, L_z) in m.
    pub lengths: [f64; 3],
    /// Number of bricks along x, y, z (each ≥ 1).
    pub elements: [usize; 3],
    /// Young's modulus E in Pa.
    pub young: f64,
    /// Poisson's ratio ν, in (−1, 0.5).
    pub poisson: f64,
    /// Density ρ in kg/m³.
    pub density: f64,
}

impl SolidBox {
    /// A steel box (E = 210 GPa, ν = 0.3, ρ = 7850 kg/m³).
    pub fn steel(lengths: [f64; 3], elements: [usize; 3]) -> SolidBox {
        SolidBox {
            lengths,
            elements,
            young: 210e9,
            poisson: 0.3,
            density: 7850.0,
        }
    }

    /// Refuse non-physical values and meshes whose size would overflow.
    pub fn validate(&self) -> Result<(), FeError> {
        let positive = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(InvalidValue::new(name, v, "must be finite and > 0"))
            }
        };
        for (axis, &l) in ["x", "y", "z"].iter().zip(&self.lengths) {
            positive(&format!("lengths.{axis}"), l)?;
        }
        positive("young", self.young)?;
        positive("density", self.density)?;
        if !(self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(InvalidValue::new("poisson", self.poisson, "must lie in (-1, 0.5)").into());
        }
        for (axis, &n) in ["x", "y", "z"].iter().zip(&self.elements) {
            if n == 0 {
                return Err(
                    InvalidValue::new(format!("elements.{axis}"), n, "must be >= 1").into(),
                );
            }
        }
        let nodes = self
            .elements
            .iter()
            .try_fold(1usize, |acc, &n| acc.checked_mul(n + 1));
        // 81 entries a column at most: keep 3 · nodes · 81 representable.
        if nodes.and_then(|n| n.checked_mul(243)).is_none() {
            return Err(InvalidValue::new(
                "elements",
                format!("{:?}", self.elements),
                "too many nodes to index",
            )
            .into());
        }
        Ok(())
    }

    /// Nodes along x, y, z.
    fn nodes_per_axis(&self) -> [usize; 3] {
        self.elements.map(|n| n + 1)
    }

    /// Number of nodes, (n_x + 1)(n_y + 1)(n_z + 1).
    pub fn n_nodes(&self) -> usize {
        self.nodes_per_axis().iter().product()
    }

    /// Number of DOFs, 3 per node.
    pub fn n_dofs(&self) -> usize {
        3 * self.n_nodes()
    }

    /// Index of grid node (i, j, k).
    pub fn node_index(&self, i: usize, j: usize, k: usize) -> usize {
        let [nx, ny, _] = self.nodes_per_axis();
        i + nx * (j + ny * k)
    }

    /// Position (m) of node `node`.
    pub fn node_position(&self, node: usize) -> [f64; 3] {
        let [nx, ny, _] = self.nodes_per_axis();
        let (i, j, k) = (node % nx, (node / nx) % ny, node / (nx * ny));
        let h = self.brick_sides();
        [i as f64 * h[0], j as f64 * h[1], k as f64 * h[2]]
    }

    /// Sides (a, b, c) of one brick.
    pub fn brick_sides(&self) -> [f64; 3] {
        [0, 1, 2].map(|d| self.lengths[d] / self.elements[d] as f64)
    }

    /// The material, for the built-in solid elements ([`crate::solid`]).
    pub fn material(&self) -> IsotropicElastic {
        IsotropicElastic {
            young: self.young,
            poisson: self.poisson,
            density: self.density,
        }
    }

    /// The isotropic elasticity matrix D (6 × 6, engineering shear strains).
    fn elasticity(&self) -> SMatrix<f64, 6, 6> {
        self.material().elasticity()
    }

    /// The box as a mesh of any built-in solid `kind` ([`crate::solid::shape`]), for
    /// [`crate::solid::solid_model`]: node ids `1…` — the grid nodes in [`Self::node_index`]
    /// order first, then the mid-edge nodes of C3D10 and C3D20 in order of first use;
    /// element ids `1…`. Each brick is one C3D8 or C3D20, or the six C3D4 or C3D10 of
    /// Kuhn's subdivision along its diagonal from corner 0 to corner 6 (Kuhn, 1960; the
    /// tetrahedra of neighbouring bricks share their face diagonals, so the mesh is
    /// conforming). The mesh is in SI units and has no sets.
    pub fn mesh(&self, kind: SolidKind) -> Result<FeMesh, FeError> {
        self.validate()?;
        const KUHN: [[usize; 4]; 6] = [
            [0, 1, 2, 6],
            [0, 2, 3, 6],
            [0, 3, 7, 6],
            [0, 7, 4, 6],
            [0, 4, 5, 6],
            [0, 5, 1, 6],
        ];
        let mut nodes = NodeList::default();
        for n in 0..self.n_nodes() {
            let p = self.node_position(n);
            nodes.ids.push((n + 1).to_string());
            nodes.index.insert((n + 1).to_string(), n);
            nodes.positions.push(Vector3::from(p));
        }
        let mut mids: HashMap<(usize, usize), usize> = HashMap::new();
        let mut mid = |nodes: &mut NodeList, a: usize, b: usize| {
            *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let id = (nodes.ids.len() + 1).to_string();
                nodes.index.insert(id.clone(), nodes.ids.len());
                nodes.ids.push(id);
                let p = (nodes.positions[a] + nodes.positions[b]) * 0.5;
                nodes.positions.push(p);
                nodes.ids.len() - 1
            })
        };
        let mut elements = Vec::new();
        let [ex, ey, ez] = self.elements;
        for bz in 0..ez {
            for by in 0..ey {
                for bx in 0..ex {
                    let corners = CORNERS.map(|c| {
                        let o = c.map(|s| usize::from(s > 0.0));
                        self.node_index(bx + o[0], by + o[1], bz + o[2])
                    });
                    let conn: Vec<Vec<usize>> = match kind {
                        SolidKind::Hex8 | SolidKind::Hex20 => vec![corners.to_vec()],
                        SolidKind::Tet4 | SolidKind::Tet10 => KUHN
                            .iter()
                            .map(|t| t.iter().map(|&v| corners[v]).collect())
                            .collect(),
                    };
                    for mut c in conn {
                        let edges: &[[usize; 2]] = match kind {
                            SolidKind::Tet10 => &TET10_EDGES,
                            SolidKind::Hex20 => &HEX20_EDGES,
                            _ => &[],
                        };
                        for &[a, b] in edges {
                            let m = mid(&mut nodes, c[a], c[b]);
                            c.push(m);
                        }
                        elements.push(Element {
                            id: (elements.len() + 1).to_string(),
                            kind: kind.abaqus_name().to_string(),
                            nodes: c,
                        });
                    }
                }
            }
        }
        Ok(FeMesh {
            nodes,
            elements,
            ..FeMesh::default()
        })
    }

    /// K_e and M_e of one brick (module docs), 2 × 2 × 2 Gauss points.
    pub fn element_matrices(&self) -> (BrickMatrix, BrickMatrix) {
        let h = self.brick_sides();
        let det_j = h[0] * h[1] * h[2] / 8.0;
        let d = self.elasticity();
        let g = 1.0 / 3.0_f64.sqrt();
        let (mut k, mut m) = (BrickMatrix::zeros(), BrickMatrix::zeros());
        for gp in CORNERS {
            let point = gp.map(|s| s * g);
            let (n, dn) = shape_functions(&point, &h);
            let mut b = SMatrix::<f64, 6, 24>::zeros();
            for a in 0..8 {
                let [dx, dy, dz] = dn[a];
                let c = 3 * a;
                b[(0, c)] = dx;
                b[(1, c + 1)] = dy;
                b[(2, c + 2)] = dz;
                b[(3, c)] = dy;
                b[(3, c + 1)] = dx;
                b[(4, c + 1)] = dz;
                b[(4, c + 2)] = dy;
                b[(5, c)] = dz;
                b[(5, c + 2)] = dx;
            }
            k += b.transpose() * d * b * det_j;
            for a in 0..8 {
                for c in 0..8 {
                    let mac = self.density * n[a] * n[c] * det_j;
                    for dir in 0..3 {
                        m[(3 * a + dir, 3 * c + dir)] += mac;
                    }
                }
            }
        }
        // Exact symmetry (the products above are symmetric only to round-off).
        ((k + k.transpose()) * 0.5, (m + m.transpose()) * 0.5)
    }

    /// Assemble the free-free K and consistent M (CSC, full symmetric storage, the same
    /// pattern).
    pub fn assemble(&self) -> Result<(CsMat<f64>, CsMat<f64>), FeError> {
        self.validate()?;
        let (col_ptr, row_idx) = self.pattern();
        let (ke, me) = self.element_matrices();
        let mut k_values = vec![0.0; row_idx.len()];
        let mut m_values = vec![0.0; row_idx.len()];
        let [ex, ey, ez] = self.elements;
        for bz in 0..ez {
            for by in 0..ey {
                for bx in 0..ex {
                    let nodes = CORNERS.map(|c| {
                        let o = c.map(|s| usize::from(s > 0.0));
                        self.node_index(bx + o[0], by + o[1], bz + o[2])
                    });
                    for (b, &q) in nodes.iter().enumerate() {
                        for (a, &p) in nodes.iter().enumerate() {
                            let column = &row_idx[col_ptr[3 * q]..col_ptr[3 * q + 1]];
                            // Rows of a column come in node triples, sorted.
                            let slot = column
                                .binary_search(&(3 * p))
                                .expect("neighbour nodes are in the pattern");
                            for db in 0..3 {
                                let start = col_ptr[3 * q + db] + slot;
                                for da in 0..3 {
                                    k_values[start + da] += ke[(3 * a + da, 3 * b + db)];
                                    m_values[start + da] += me[(3 * a + da, 3 * b + db)];
                                }
                            }
                        }
                    }
                }
            }
        }
        let n = self.n_dofs();
        let k = CsMat::new_csc((n, n), col_ptr.clone(), row_idx.clone(), k_values);
        let m = CsMat::new_csc((n, n), col_ptr, row_idx, m_values);
        Ok((k, m))
    }

    /// Column pointers and sorted row indices of the node graph, 3 × 3 blocks.
    fn pattern(&self) -> (Vec<usize>, Vec<usize>) {
        let [nx, ny, nz] = self.nodes_per_axis();
        let range = |i: usize, n: usize| i.saturating_sub(1)..(i + 2).min(n);
        let mut col_ptr = Vec::with_capacity(3 * self.n_nodes() + 1);
        col_ptr.push(0);
        let mut row_idx = Vec::new();
        let mut neighbours = Vec::with_capacity(27);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    neighbours.clear();
                    for kk in range(k, nz) {
                        for jj in range(j, ny) {
                            for ii in range(i, nx) {
                                neighbours.push(self.node_index(ii, jj, kk));
                            }
                        }
                    }
                    for _dir in 0..3 {
                        for &p in &neighbours {
                            row_idx.extend([3 * p, 3 * p + 1, 3 * p + 2]);
                        }
                        col_ptr.push(row_idx.len());
                    }
                }
            }
        }
        (col_ptr, row_idx)
    }
}

/// Shape function values N_a and physical gradients ∂N_a/∂(x, y, z) at parent point
/// (ξ, η, ζ) of a brick of sides `h`.
fn shape_functions(point: &[f64; 3], h: &[f64; 3]) -> (SVector<f64, 8>, [[f64; 3]; 8]) {
    let mut n = SVector::<f64, 8>::zeros();
    let mut dn = [[0.0; 3]; 8];
    for (a, corner) in CORNERS.iter().enumerate() {
        let f = [0, 1, 2].map(|d| 1.0 + point[d] * corner[d]);
        n[a] = f[0] * f[1] * f[2] / 8.0;
        dn[a] = [
            corner[0] * f[1] * f[2] / 8.0 * 2.0 / h[0],
            corner[1] * f[0] * f[2] / 8.0 * 2.0 / h[1],
            corner[2] * f[0] * f[1] / 8.0 * 2.0 / h[2],
        ];
    }
    (n, dn)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The consistent mass adds up to the box's mass in each direction, and K annihilates
    /// rigid translations and rotations.
    #[test]
    fn mass_sums_to_the_box_mass_and_rigid_motion_is_stress_free() {
        let b = SolidBox::steel([0.3, 0.2, 0.1], [3, 2, 2]);
        let (k, m) = b.assemble().unwrap();
        let n = b.n_dofs();
        let mass = b.density * 0.3 * 0.2 * 0.1;
        let ones_x: Vec<f64> = (0..n).map(|i| f64::from(i % 3 == 0)).collect();
        let total: f64 = m.iter().map(|(v, (r, c))| v * ones_x[r] * ones_x[c]).sum();
        assert!((total - mass).abs() < 1e-12 * mass, "{total} vs {mass}");
        // Rotation about z: u = (−y, x, 0).
        let rot: Vec<f64> = (0..n)
            .map(|i| {
                let p = b.node_position(i / 3);
                [-p[1], p[0], 0.0][i % 3]
            })
            .collect();
        let mut kx = vec![0.0; n];
        for (v, (r, c)) in k.iter() {
            kx[r] += v * rot[c];
        }
        let kmax = k.data().iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        assert!(kx.iter().all(|v| v.abs() < 1e-12 * kmax));
    }
}
