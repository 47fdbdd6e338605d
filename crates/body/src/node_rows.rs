//! The mode rows of a body at its nodes, in the one layout every formulation reads.
//!
//! A node P of a flexible body moves with the modal coordinates y as (docs/methods.md §1.1,
//! §4.3)
//!
//! ```text
//! r̄_P = r̄_u,P + X^t_P y,        θ̄_P = X^r_P y,
//! ```
//!
//! with X^t_P and X^r_P its 3 × n translation and small-rotation rows in body components.
//! Joints, force elements, constraints and sensors attach to nodes: the absolute
//! formulation projects them on its natural coordinates, the relative one turns them into
//! elementary joints of the augmented tree (§4.3). Both read them here, so whatever made
//! the body (a built-in beam, an imported FE model) stays invisible to them.
//!
//! Layout: node-major; per node 6n numbers, the three translation rows then the three
//! rotation rows, each row n numbers long. In 2D the z translation row and the x, y
//! rotation rows are zero.

use nalgebra::{DMatrix, Vector3};

use crate::{InvalidValue, ReducedBody};

/// Undeformed positions and mode rows at a body's nodes (see the module documentation).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeRows {
    n_modes: usize,
    positions: Vec<Vector3<f64>>,
    /// Per node: X^t (3 rows of n) then X^r (3 rows of n).
    rows: Vec<f64>,
}

impl NodeRows {
    /// Node rows from their parts: `rows` holds 6n numbers per position in the layout of
    /// the module documentation.
    pub fn new(
        n_modes: usize,
        positions: Vec<Vector3<f64>>,
        rows: Vec<f64>,
    ) -> Result<Self, InvalidValue> {
        if rows.len() != 6 * n_modes * positions.len() {
            return Err(InvalidValue::new(
                "node rows",
                rows.len(),
                format!(
                    "{} nodes of {n_modes} modes need 6 x {n_modes} x {} numbers",
                    positions.len(),
                    positions.len()
                ),
            ));
        }
        Ok(NodeRows {
            n_modes,
            positions,
            rows,
        })
    }

    /// The rows of every node of a reduced body (none for a rigid body).
    pub fn from_reduced(reduced: &ReducedBody) -> Self {
        let n = reduced.n_modes();
        let mut rows = Vec::with_capacity(reduced.nodes.len() * 6 * n);
        for node in &reduced.nodes {
            for matrix in [&node.translation, &node.rotation] {
                for a in 0..3 {
                    rows.extend((0..n).map(|j| matrix[(a, j)]));
                }
            }
        }
        NodeRows {
            n_modes: n,
            positions: reduced.nodes.iter().map(|node| node.position).collect(),
            rows,
        }
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True when the body has no nodes (a rigid body).
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Number of modal coordinates n (the length of every row).
    pub fn n_modes(&self) -> usize {
        self.n_modes
    }

    /// Undeformed position r̄_u of a node (m, body components).
    pub fn position(&self, node: usize) -> Vector3<f64> {
        self.positions[node]
    }

    /// The first node within `tolerance` of `point`, if any.
    pub fn node_at(&self, point: &Vector3<f64>, tolerance: f64) -> Option<usize> {
        self.positions
            .iter()
            .position(|p| (p - point).norm() <= tolerance)
    }

    /// The translation rows X^t of a node: 3n numbers, row-major.
    pub fn translation(&self, node: usize) -> &[f64] {
        let start = 6 * self.n_modes * node;
        &self.rows[start..start + 3 * self.n_modes]
    }

    /// The rotation rows X^r of a node: 3n numbers, row-major.
    pub fn rotation(&self, node: usize) -> &[f64] {
        let start = 6 * self.n_modes * node + 3 * self.n_modes;
        &self.rows[start..start + 3 * self.n_modes]
    }

    /// Row `a` (0, 1, 2 = body x, y, z) of X^t at a node.
    pub fn translation_row(&self, node: usize, a: usize) -> &[f64] {
        &self.translation(node)[a * self.n_modes..(a + 1) * self.n_modes]
    }

    /// Row `a` (0, 1, 2 = about body x, y, z) of X^r at a node.
    pub fn rotation_row(&self, node: usize, a: usize) -> &[f64] {
        &self.rotation(node)[a * self.n_modes..(a + 1) * self.n_modes]
    }

    /// Entry (a, m) of X^t at a node (one bounds check: the per-step paths read these).
    #[inline]
    pub fn translation_entry(&self, node: usize, a: usize, m: usize) -> f64 {
        self.rows[(6 * node + a) * self.n_modes + m]
    }

    /// Entry (a, m) of X^r at a node.
    #[inline]
    pub fn rotation_entry(&self, node: usize, a: usize, m: usize) -> f64 {
        self.rows[(6 * node + 3 + a) * self.n_modes + m]
    }

    /// X^t of a node as a 3 × n matrix.
    pub fn translation_matrix(&self, node: usize) -> DMatrix<f64> {
        DMatrix::from_row_slice(3, self.n_modes, self.translation(node))
    }

    /// X^r of a node as a 3 × n matrix.
    pub fn rotation_matrix(&self, node: usize) -> DMatrix<f64> {
        DMatrix::from_row_slice(3, self.n_modes, self.rotation(node))
    }

    /// The largest |entry| of every row of every node (0 for a rigid body).
    pub fn largest_entry(&self) -> f64 {
        self.rows.iter().fold(0.0f64, |a, v| a.max(v.abs()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Dim;
    use flexmbd_fe::NodeModes;
    use nalgebra::Matrix3;

    fn one_node_body(translation: DMatrix<f64>, rotation: DMatrix<f64>) -> ReducedBody {
        let mut body =
            ReducedBody::rigid(Dim::Spatial, 1.0, Vector3::zeros(), Matrix3::identity()).unwrap();
        body.inventory.normal_frequencies_hz = vec![1.0; translation.ncols()];
        body.nodes = vec![NodeModes {
            position: Vector3::new(0.5, -1.0, 2.0),
            translation,
            rotation,
        }];
        body
    }

    #[test]
    fn rows_keep_translation_then_rotation_row_major() {
        // Two modes at one node: X^t[a, m] = 10 a + m, X^r[a, m] = −(10 a + m) − 1.
        let t = DMatrix::from_fn(3, 2, |a, m| (10 * a + m) as f64);
        let r = DMatrix::from_fn(3, 2, |a, m| -((10 * a + m) as f64) - 1.0);
        let rows = NodeRows::from_reduced(&one_node_body(t.clone(), r.clone()));
        assert_eq!(rows.len(), 1);
        assert_eq!(rows.n_modes(), 2);
        assert_eq!(rows.position(0), Vector3::new(0.5, -1.0, 2.0));
        for a in 0..3 {
            for m in 0..2 {
                assert_eq!(rows.translation_row(0, a)[m], t[(a, m)]);
                assert_eq!(rows.rotation_row(0, a)[m], r[(a, m)]);
                assert_eq!(rows.translation_entry(0, a, m), t[(a, m)]);
                assert_eq!(rows.rotation_entry(0, a, m), r[(a, m)]);
            }
        }
        assert_eq!(rows.translation_matrix(0), t);
        assert_eq!(rows.rotation_matrix(0), r);
        assert_eq!(rows.largest_entry(), 22.0);
    }

    #[test]
    fn new_refuses_rows_of_the_wrong_length() {
        let positions = vec![Vector3::zeros(); 2];
        assert!(NodeRows::new(3, positions.clone(), vec![0.0; 36]).is_ok());
        let error = NodeRows::new(3, positions, vec![0.0; 35]).unwrap_err();
        assert!(error.to_string().contains("node rows"), "{error}");
    }

    #[test]
    fn node_at_finds_a_node_within_the_tolerance_only() {
        let z = DMatrix::zeros(3, 1);
        let rows = NodeRows::from_reduced(&one_node_body(z.clone(), z));
        assert_eq!(
            rows.node_at(&Vector3::new(0.5, -1.0, 2.0 + 1e-10), 1e-9),
            Some(0)
        );
        assert_eq!(rows.node_at(&Vector3::new(0.5, -1.0, 2.1), 1e-9), None);
    }
}
