//! Modal stress shapes of a solid body (issue 29 item 3): the stress at every node in each
//! mode, so that the stress at a node at any step is a small product, σ(t) = S_node q(t).
//!
//! For mode k with nodal displacements u_k (the mode's FE rows), each element evaluates
//! σ = D B(ξ_a) u_k,e at the parent coordinates ξ_a of each of its nodes (direct nodal
//! evaluation; [`super::element`] for B and D), and a node's stress is the mean over the
//! elements that hold it (unweighted nodal averaging: Zienkiewicz, Taylor & Zhu 2013,
//! §15.2; the stresses of neighbouring elements differ at a node by the discretisation
//! error, which the averaging halves at best — the superconvergent recovery of §15.3 is not
//! attempted). Stress components (σ_xx, σ_yy, σ_zz, τ_xy, τ_yz, τ_zx), Pa, body axes.
//!
//! The von Mises stress, σ_v² = ½[(σ_xx − σ_yy)² + (σ_yy − σ_zz)² + (σ_zz − σ_xx)²] +
//! 3 (τ_xy² + τ_yz² + τ_zx²), and the largest principal stress (the largest eigenvalue of
//! the stress tensor) follow from the six components at the node.

use nalgebra::{DMatrix, Matrix3, SVector, Vector3};

use super::assembly::SolidElement;
use super::element::{IsotropicElastic, point_data, strain_displacement};
use crate::error::FeError;

/// The six stress components (σ_xx, σ_yy, σ_zz, τ_xy, τ_yz, τ_zx).
pub type Stress = SVector<f64, 6>;

/// Modal stress shapes: 6 rows per node (node-major, the components above), one column per
/// mode.
#[derive(Clone, Debug, PartialEq)]
pub struct StressShapes {
    /// (6 · nodes) × modes.
    pub shapes: DMatrix<f64>,
}

impl StressShapes {
    /// The stress shapes of the displacement fields `modes` ((3 · nodes) × modes, node-major
    /// u_x, u_y, u_z) of the mesh `elements` on `positions` (module docs).
    pub fn new(
        positions: &[Vector3<f64>],
        elements: &[SolidElement],
        material: &IsotropicElastic,
        modes: &DMatrix<f64>,
    ) -> Result<StressShapes, FeError> {
        let n_nodes = positions.len();
        let n_modes = modes.ncols();
        let d = material.elasticity();
        let mut shapes = DMatrix::zeros(6 * n_nodes, n_modes);
        let mut count = vec![0usize; n_nodes];
        let mut x = Vec::with_capacity(20);
        for e in elements {
            x.clear();
            x.extend(e.nodes.iter().map(|&i| positions[i]));
            // The element's displacements in every mode, (3 n_e) × modes.
            let mut ue = DMatrix::zeros(3 * e.nodes.len(), n_modes);
            for (a, &node) in e.nodes.iter().enumerate() {
                ue.rows_mut(3 * a, 3).copy_from(&modes.rows(3 * node, 3));
            }
            for (a, p) in e.kind.parent_nodes().into_iter().enumerate() {
                let pd = point_data(e.kind, &x, p, &e.label)?;
                let sigma = d * strain_displacement(&pd.dn) * &ue;
                let node = e.nodes[a];
                let mut rows = shapes.rows_mut(6 * node, 6);
                rows += sigma;
                count[node] += 1;
            }
        }
        for (node, &c) in count.iter().enumerate() {
            if c > 1 {
                let mut rows = shapes.rows_mut(6 * node, 6);
                rows /= c as f64;
            }
        }
        Ok(StressShapes { shapes })
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.shapes.nrows() / 6
    }

    /// The stress at `node` for the modal coordinates `q`: S_node q.
    pub fn stress(&self, node: usize, q: &[f64]) -> Stress {
        let mut s = Stress::zeros();
        for (k, &qk) in q.iter().enumerate() {
            for c in 0..6 {
                s[c] += self.shapes[(6 * node + c, k)] * qk;
            }
        }
        s
    }
}

/// The von Mises stress of `s` (module docs).
pub fn von_mises(s: &Stress) -> f64 {
    let (dxy, dyz, dzx) = (s[0] - s[1], s[1] - s[2], s[2] - s[0]);
    (0.5 * (dxy * dxy + dyz * dyz + dzx * dzx) + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]))
        .sqrt()
}

/// The stress tensor of the six components.
pub fn tensor(s: &Stress) -> Matrix3<f64> {
    Matrix3::new(s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2])
}

/// The largest principal stress of `s`.
pub fn largest_principal(s: &Stress) -> f64 {
    tensor(s).symmetric_eigenvalues().max()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniaxial stress: von Mises and the largest principal stress are |σ| and σ; pure
    /// shear τ: √3 τ and τ.
    #[test]
    fn invariants_of_simple_states() {
        let uniaxial = Stress::from_column_slice(&[-5.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert!((von_mises(&uniaxial) - 5.0).abs() < 1e-14);
        assert!(largest_principal(&uniaxial).abs() < 1e-14);
        let shear = Stress::from_column_slice(&[0.0, 0.0, 0.0, 2.0, 0.0, 0.0]);
        assert!((von_mises(&shear) - 2.0 * 3.0_f64.sqrt()).abs() < 1e-14);
        assert!((largest_principal(&shear) - 2.0).abs() < 1e-14);
    }
}
