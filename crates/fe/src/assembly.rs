//! Mesh, element axes, transformation to body components and sparse assembly
//! (docs/methods.md §1.2 "Assembly" and "Element axes").
//!
//! - Element axes: x_e from the first node to the second; y_e = k̄ × x_e / |k̄ × x_e|,
//!   z_e = x_e × y_e, with k̄ the orientation vector (default ē₃, ē₂ for an
//!   element parallel to ē₃). Λ_e has the element axes as **rows** (body components).
//! - T_e = blockdiag(Λ_e, …): local = T_e · body; K = Σ T_eᵀ K_loc T_e, M likewise.
//! - Global DOF numbering: node-major, `node * d + slot` with slots
//!   2D (Ux, Uy, Rz), 3D (Ux, Uy, Uz, Rx, Ry, Rz).
//!
//! K and M are assembled from triplets into CSR (sprs) for the free-floating
//! model (N DOFs), then converted to dense for the small dense work of §1.3.

use flexmbd_core::Dim;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use sprs::{CsMat, TriMat};

use crate::beam::{self, BeamProps, MassModel};
use crate::reduced::{Dof, NodeDof};
use crate::spec::{BeamBodySpec, Section};

/// Slot of a DOF inside a node (None for a DOF a 2D node does not have).
pub fn dof_slot(dim: Dim, dof: Dof) -> Option<usize> {
    match dim {
        Dim::Planar => match dof {
            Dof::Ux => Some(0),
            Dof::Uy => Some(1),
            Dof::Rz => Some(2),
            _ => None,
        },
        Dim::Spatial => Some(match dof {
            Dof::Ux => 0,
            Dof::Uy => 1,
            Dof::Uz => 2,
            Dof::Rx => 3,
            Dof::Ry => 4,
            Dof::Rz => 5,
        }),
    }
}

/// Global index of a nodal DOF (None if the DOF does not exist in `dim`).
pub fn global_index(dim: Dim, nd: NodeDof) -> Option<usize> {
    dof_slot(dim, nd.dof).map(|s| nd.node * dim.n_rigid() + s)
}

/// Undeformed position of mesh node `node` of a spec (body components); the
/// spec's points must be valid.
pub fn node_position(spec: &BeamBodySpec, node: usize) -> Vector3<f64> {
    if spec.geometry.is_frame() {
        return crate::frame::frame_mesh(spec).0[node];
    }
    let ne = spec.geometry.elements_per_segment.max(1);
    let seg = (node / ne).min(spec.geometry.points.len() - 2);
    let j = node - seg * ne;
    let a = spec.point(seg);
    let b = spec.point(seg + 1);
    a + (b - a) * (j as f64 / ne as f64)
}

/// One beam element.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    /// First and second node.
    pub nodes: [usize; 2],
    /// Length L_e (m).
    pub length: f64,
    /// Λ_e: rows are x_e, y_e, z_e in body components.
    pub axes: Matrix3<f64>,
    /// Material and section constants.
    pub props: BeamProps,
}

/// The beam mesh in body components.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// Planar or spatial.
    pub dim: Dim,
    /// Node positions (m), body components (z = 0 in 2D).
    pub nodes: Vec<Vector3<f64>>,
    /// Elements in polyline order, or member by member for a frame.
    pub elements: Vec<Element>,
}

/// Element axes Λ_e (rows x_e, y_e, z_e) for the direction `x` (unit) and the
/// orientation vector `k` (None → ē₃, or ē₂ when x ∥ ē₃).
pub fn element_axes(x: &Vector3<f64>, k: Option<&Vector3<f64>>) -> Matrix3<f64> {
    let kk = match k {
        Some(k) => *k,
        None => {
            let e3 = Vector3::z();
            if e3.cross(x).norm() < 1e-9 {
                Vector3::y()
            } else {
                e3
            }
        }
    };
    let y = kk.cross(x).normalize();
    let z = x.cross(&y);
    Matrix3::from_rows(&[x.transpose(), y.transpose(), z.transpose()])
}

impl Mesh {
    /// Build the mesh of a **validated** spec: each polyline segment is split
    /// into `elements_per_segment` equal elements; a frame's members as
    /// [`crate::frame::frame_mesh`] splits them.
    pub fn from_spec(spec: &BeamBodySpec) -> Mesh {
        let props = |section: &Section| {
            let sp = section.props();
            BeamProps {
                e: spec.material.young_modulus,
                g: spec.shear_modulus(),
                rho: spec.material.density,
                area: sp.area,
                iy: sp.iy,
                iz: sp.iz,
                j: sp.j,
            }
        };
        let element = |nodes: &[Vector3<f64>], ends: [usize; 2], k: Option<Vector3<f64>>, props| {
            let d = nodes[ends[1]] - nodes[ends[0]];
            let length = d.norm();
            let x = d / length;
            Element {
                nodes: ends,
                length,
                axes: element_axes(&x, k.as_ref()),
                props,
            }
        };
        let (nodes, elements) = if spec.geometry.is_frame() {
            let (nodes, frame_elements) = crate::frame::frame_mesh(spec);
            let elements = frame_elements
                .iter()
                .map(|el| {
                    let k = crate::frame::member_orientation(spec, el.member).map(Vector3::from);
                    let p = props(crate::frame::member_section(spec, el.member));
                    element(&nodes, el.nodes, k, p)
                })
                .collect();
            (nodes, elements)
        } else {
            let k = spec.geometry.orientation.map(Vector3::from);
            let p = props(&spec.section);
            let nodes: Vec<Vector3<f64>> = (0..spec.n_nodes())
                .map(|i| node_position(spec, i))
                .collect();
            let elements = (0..nodes.len() - 1)
                .map(|e| element(&nodes, [e, e + 1], k, p))
                .collect();
            (nodes, elements)
        };
        Mesh {
            dim: spec.dim,
            nodes,
            elements,
        }
    }

    /// DOFs per node (3 or 6).
    pub fn dofs_per_node(&self) -> usize {
        self.dim.n_rigid()
    }

    /// Number of DOFs N of the free-floating model.
    pub fn n_dofs(&self) -> usize {
        self.nodes.len() * self.dofs_per_node()
    }

    /// The default mass model: 2D consistent (no rotary inertia), 3D Rayleigh (methods.md §1.2).
    pub fn default_mass_model(&self) -> MassModel {
        match self.dim {
            Dim::Planar => MassModel::Consistent,
            Dim::Spatial => MassModel::Rayleigh,
        }
    }

    /// T_e as a dense (6 × 6 or 12 × 12) matrix: local DOFs = T_e · body DOFs.
    pub fn transformation(&self, e: usize) -> DMatrix<f64> {
        let lam = &self.elements[e].axes;
        match self.dim {
            Dim::Planar => {
                let mut t = DMatrix::zeros(6, 6);
                for n in 0..2 {
                    let o = 3 * n;
                    for i in 0..2 {
                        for j in 0..2 {
                            t[(o + i, o + j)] = lam[(i, j)];
                        }
                    }
                    t[(o + 2, o + 2)] = 1.0;
                }
                t
            }
            Dim::Spatial => {
                let mut t = DMatrix::zeros(12, 12);
                for b in 0..4 {
                    let o = 3 * b;
                    for i in 0..3 {
                        for j in 0..3 {
                            t[(o + i, o + j)] = lam[(i, j)];
                        }
                    }
                }
                t
            }
        }
    }

    /// Global DOF indices of element `e` (6 or 12), in element order.
    pub fn element_dofs(&self, e: usize) -> Vec<usize> {
        let d = self.dofs_per_node();
        self.elements[e]
            .nodes
            .iter()
            .flat_map(|&n| (0..d).map(move |s| n * d + s))
            .collect()
    }

    /// Local element stiffness and mass (element axes).
    pub fn element_matrices(&self, e: usize, model: MassModel) -> (DMatrix<f64>, DMatrix<f64>) {
        let l = self.elements[e].length;
        let p = &self.elements[e].props;
        match self.dim {
            Dim::Planar => {
                let k = beam::stiffness_2d(p, l);
                let m = beam::mass_2d(p, l, model);
                (
                    DMatrix::from_column_slice(6, 6, k.as_slice()),
                    DMatrix::from_column_slice(6, 6, m.as_slice()),
                )
            }
            Dim::Spatial => {
                let k = beam::stiffness_3d(p, l);
                let m = beam::mass_3d(p, l, model);
                (
                    DMatrix::from_column_slice(12, 12, k.as_slice()),
                    DMatrix::from_column_slice(12, 12, m.as_slice()),
                )
            }
        }
    }

    /// Assemble the free-floating K and M (body components) from triplets into CSR.
    pub fn assemble(&self, model: MassModel) -> Assembled {
        let n = self.n_dofs();
        let mut kt = TriMat::new((n, n));
        let mut mt = TriMat::new((n, n));
        for e in 0..self.elements.len() {
            let t = self.transformation(e);
            let (kl, ml) = self.element_matrices(e, model);
            let kg = t.transpose() * kl * &t;
            let mg = t.transpose() * ml * &t;
            let dofs = self.element_dofs(e);
            for (a, &i) in dofs.iter().enumerate() {
                for (b, &j) in dofs.iter().enumerate() {
                    if kg[(a, b)] != 0.0 {
                        kt.add_triplet(i, j, kg[(a, b)]);
                    }
                    if mg[(a, b)] != 0.0 {
                        mt.add_triplet(i, j, mg[(a, b)]);
                    }
                }
            }
        }
        Assembled {
            k: kt.to_csr(),
            m: mt.to_csr(),
        }
    }

    /// A rigid-body displacement field (body components) of the FE model:
    /// node translation t + θ × r̄ and node rotation θ (2D: θ about z only).
    pub fn rigid_field(&self, t: &Vector3<f64>, theta: &Vector3<f64>) -> DVector<f64> {
        let d = self.dofs_per_node();
        let mut u = DVector::zeros(self.n_dofs());
        for (k, r) in self.nodes.iter().enumerate() {
            let du = t + theta.cross(r);
            match self.dim {
                Dim::Planar => {
                    u[k * d] = du.x;
                    u[k * d + 1] = du.y;
                    u[k * d + 2] = theta.z;
                }
                Dim::Spatial => {
                    for a in 0..3 {
                        u[k * d + a] = du[a];
                        u[k * d + 3 + a] = theta[a];
                    }
                }
            }
        }
        u
    }
}

/// Assembled sparse stiffness and mass of the free-floating model.
#[derive(Clone, Debug)]
pub struct Assembled {
    /// Stiffness K (N × N, CSR).
    pub k: CsMat<f64>,
    /// Mass M (N × N, CSR).
    pub m: CsMat<f64>,
}

/// Sparse → dense (nalgebra).
pub fn to_dense(a: &CsMat<f64>) -> DMatrix<f64> {
    let (r, c) = a.shape();
    let mut d = DMatrix::zeros(r, c);
    for (v, (i, j)) in a.iter() {
        d[(i, j)] += *v;
    }
    d
}

/// Extract the sub-matrix with the given rows and columns.
pub fn submatrix(a: &DMatrix<f64>, rows: &[usize], cols: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(rows.len(), cols.len(), |i, j| a[(rows[i], cols[j])])
}

/// The r / b / i DOF sets of the Craig–Bampton split (docs/methods.md §1.3), as
/// global indices: r and b in the order given, i ascending (everything else).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DofSets {
    /// Reference (frame) DOFs, removed.
    pub r: Vec<usize>,
    /// Boundary DOFs, one static mode each.
    pub b: Vec<usize>,
    /// Interior DOFs.
    pub i: Vec<usize>,
}

impl DofSets {
    /// Split N DOFs given r and b (indices must be distinct and < N).
    pub fn new(n: usize, r: Vec<usize>, b: Vec<usize>) -> DofSets {
        let mut taken = vec![false; n];
        for &x in r.iter().chain(b.iter()) {
            taken[x] = true;
        }
        let i = (0..n).filter(|&x| !taken[x]).collect();
        DofSets { r, b, i }
    }

    /// Sets from nodal DOFs (must exist in `dim`; a validated spec guarantees it).
    pub fn from_node_dofs(dim: Dim, n: usize, r: &[NodeDof], b: &[NodeDof]) -> DofSets {
        let g = |v: &[NodeDof]| -> Vec<usize> {
            v.iter()
                .map(|nd| global_index(dim, *nd).expect("validated DOF"))
                .collect()
        };
        DofSets::new(n, g(r), g(b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_axes_of_x_aligned_element_are_body_axes() {
        let l = element_axes(&Vector3::x(), None);
        assert_eq!(l, Matrix3::identity());
        let l = element_axes(&Vector3::z(), None);
        // x_e = e3, k = e2: y_e = e2 × e3 = e1, z_e = e3 × e1 = e2.
        assert_eq!(l.row(1), Vector3::x().transpose());
        assert_eq!(l.row(2), Vector3::y().transpose());
        let l = element_axes(&Vector3::y(), None);
        assert!((l * l.transpose() - Matrix3::identity()).norm() < 1e-15);
        assert!((l.determinant() - 1.0).abs() < 1e-15);
    }
}
