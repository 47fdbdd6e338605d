//! Assembly of a solid mesh's K and M into sparse CSC matrices (full symmetric storage, the
//! same pattern for both), DOFs node-major: node p's (u_x, u_y, u_z) are rows 3p, 3p + 1,
//! 3p + 2.
//!
//! The pattern is that of the node graph — nodes p and q couple when an element holds both —
//! in 3 × 3 blocks, built column by column with the rows sorted; each element's matrices are
//! then added into it in place (a binary search per node pair), so no triplet list of the
//! whole mesh is ever stored.

use nalgebra::{DMatrix, Vector3};
use sprs::CsMat;

use super::element::{self, IsotropicElastic, MassMatrix};
use super::quadrature::Point;
use super::shape::SolidKind;
use crate::error::FeError;

/// One solid element: its label for messages, kind and node indices.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidElement {
    /// How errors name it (e.g. `element 12 of bar.msh`).
    pub label: String,
    /// The element type.
    pub kind: SolidKind,
    /// Node indices (into the positions), in the kind's node order.
    pub nodes: Vec<usize>,
}

/// Column pointers and sorted row indices of the node graph of `elements` over `n_nodes`
/// nodes, in 3 × 3 blocks.
pub fn pattern(n_nodes: usize, elements: &[SolidElement]) -> (Vec<usize>, Vec<usize>) {
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); n_nodes];
    for e in elements {
        for &q in &e.nodes {
            neighbours[q].extend_from_slice(&e.nodes);
        }
    }
    let mut col_ptr = Vec::with_capacity(3 * n_nodes + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::new();
    for list in &mut neighbours {
        list.sort_unstable();
        list.dedup();
        for _dir in 0..3 {
            for &p in list.iter() {
                row_idx.extend([3 * p, 3 * p + 1, 3 * p + 2]);
            }
            col_ptr.push(row_idx.len());
        }
    }
    (col_ptr, row_idx)
}

/// Sparse matrices on one pattern, being assembled.
pub struct Assembler {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl Assembler {
    /// The pattern of `elements` over `n_nodes` nodes.
    pub fn new(n_nodes: usize, elements: &[SolidElement]) -> Self {
        let (col_ptr, row_idx) = pattern(n_nodes, elements);
        Assembler {
            n: 3 * n_nodes,
            col_ptr,
            row_idx,
        }
    }

    /// A zero value array for the pattern.
    pub fn zeros(&self) -> Vec<f64> {
        vec![0.0; self.row_idx.len()]
    }

    /// Add the element matrix `a` (3n × 3n, node-major) of the element on `nodes`.
    pub fn add(&self, values: &mut [f64], nodes: &[usize], a: &DMatrix<f64>) {
        for (b, &q) in nodes.iter().enumerate() {
            let column = &self.row_idx[self.col_ptr[3 * q]..self.col_ptr[3 * q + 1]];
            for (c, &p) in nodes.iter().enumerate() {
                let Ok(slot) = column.binary_search(&(3 * p)) else {
                    continue; // unreachable: the pattern holds every pair of an element
                };
                for db in 0..3 {
                    let start = self.col_ptr[3 * q + db] + slot;
                    for da in 0..3 {
                        values[start + da] += a[(3 * c + da, 3 * b + db)];
                    }
                }
            }
        }
    }

    /// The assembled matrix.
    pub fn matrix(&self, values: Vec<f64>) -> CsMat<f64> {
        CsMat::new_csc(
            (self.n, self.n),
            self.col_ptr.clone(),
            self.row_idx.clone(),
            values,
        )
    }
}

/// Assemble K and M of `elements` on the node `positions` (SI units).
pub fn assemble(
    positions: &[Vector3<f64>],
    elements: &[SolidElement],
    material: &IsotropicElastic,
    mass_matrix: MassMatrix,
) -> Result<(CsMat<f64>, CsMat<f64>), FeError> {
    assemble_with_mass_points(
        positions,
        elements,
        material,
        mass_matrix,
        element::mass_rule,
    )
}

/// [`assemble`] with M integrated by the points `mass_points` gives for each kind:
/// [`element::mass_rule`] (exact) in [`assemble`]; [`element::stiffness_rule`] is
/// CalculiX's rule (its C3D4 and C3D10 masses are integrated with the stiffness points).
pub fn assemble_with_mass_points(
    positions: &[Vector3<f64>],
    elements: &[SolidElement],
    material: &IsotropicElastic,
    mass_matrix: MassMatrix,
    mass_points: fn(SolidKind) -> Vec<Point>,
) -> Result<(CsMat<f64>, CsMat<f64>), FeError> {
    let asm = Assembler::new(positions.len(), elements);
    let (mut k, mut m) = (asm.zeros(), asm.zeros());
    let mut x = Vec::with_capacity(20);
    for e in elements {
        x.clear();
        x.extend(e.nodes.iter().map(|&i| positions[i]));
        let ke = element::stiffness(e.kind, &x, material, &e.label)?;
        let points = mass_points(e.kind);
        let me = element::mass(e.kind, &x, material.density, mass_matrix, &points, &e.label)?;
        asm.add(&mut k, &e.nodes, &ke);
        asm.add(&mut m, &e.nodes, &me);
    }
    Ok((asm.matrix(k), asm.matrix(m)))
}
