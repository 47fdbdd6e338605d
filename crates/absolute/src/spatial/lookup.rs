//! Compile-time resolution of the prepared scene's markers into terms: a marker becomes a point term with its
//! FE node's translation rows, a joint axis a direction term turning with its node
//! (docs/methods.md §3.3: `V = X_P` for a point, `V = [X^r_j × ā]_j` for a direction).

use flexmbd_body::NodeRows;
use flexmbd_model::{MarkerId, MarkerPair, Scene};
use nalgebra::{Matrix3, Vector3};

use super::SpatialBody;
use super::kinematics::Term;

/// The data to build marker terms: the bodies' frames at t = 0 and their node rows (read at
/// the node of a flexible body's marker; a rigid body's markers have none).
pub(super) struct TermLookup<'a> {
    pub(super) scene: &'a Scene,
    /// The markers of each joint (the prepared scene's).
    pub(super) joints: &'a [MarkerPair],
    /// The markers of each constraint (the prepared scene's).
    pub(super) constraints: &'a [MarkerPair],
    pub(super) bodies: &'a [SpatialBody],
    /// Origin and rotation of every body at t = 0.
    pub(super) initial_frames: Vec<(Vector3<f64>, Matrix3<f64>)>,
    /// Every body's node rows.
    pub(super) nodes: Vec<&'a NodeRows>,
}

impl TermLookup<'_> {
    /// The global position of a term at t = 0 (undeformed).
    pub(super) fn position0(&self, t: &Term) -> Vector3<f64> {
        match t.body {
            None => t.undeformed,
            Some(body_index) => {
                let (o, a) = self.initial_frames[body_index];
                o + a * t.undeformed
            }
        }
    }

    /// The point term of a marker (of a body or of the ground), with its node's translation
    /// rows and, on a foreshortened body, its FS0 node.
    pub(super) fn point(&self, marker: MarkerId) -> Term {
        let k = marker.index;
        match marker.body.map(|b| b.0) {
            None => Term {
                body: None,
                point: true,
                undeformed: self.scene.ground[k].position.vec(),
                modal_rows: Vec::new(),
                foreshortening_node: None,
            },
            Some(body_index) => {
                let b = &self.bodies[body_index];
                let rows = match b.markers[k].node {
                    Some(node) => self.nodes[body_index].translation(node).to_vec(),
                    None => Vec::new(),
                };
                let foreshortening_node = if b.body.has_foreshortening() && !rows.is_empty() {
                    b.markers[k].node
                } else {
                    None
                };
                Term {
                    body: Some(body_index),
                    point: true,
                    undeformed: b.markers[k].position,
                    modal_rows: rows,
                    foreshortening_node,
                }
            }
        }
    }

    /// A direction fixed in the marker's body (at its node on a flexible body), given in
    /// ground components at t = 0.
    pub(super) fn direction(&self, marker: MarkerId, global: &Vector3<f64>) -> Term {
        let g = global.normalize();
        match marker.body.map(|b| b.0) {
            None => Term {
                body: None,
                point: false,
                undeformed: g,
                modal_rows: Vec::new(),
                foreshortening_node: None,
            },
            Some(body_index) => {
                let k = marker.index;
                let local = self.initial_frames[body_index].1.tr_mul(&g);
                let rows = match self.bodies[body_index].markers[k].node {
                    Some(node) => {
                        let nodes = self.nodes[body_index];
                        let n = nodes.n_modes();
                        let mut rows = vec![0.0; 3 * n];
                        for j in 0..n {
                            let theta = Vector3::new(
                                nodes.rotation_row(node, 0)[j],
                                nodes.rotation_row(node, 1)[j],
                                nodes.rotation_row(node, 2)[j],
                            );
                            let c = theta.cross(&local);
                            for a in 0..3 {
                                rows[a * n + j] = c[a];
                            }
                        }
                        rows
                    }
                    None => Vec::new(),
                };
                Term {
                    body: Some(body_index),
                    point: false,
                    undeformed: local,
                    modal_rows: rows,
                    foreshortening_node: None,
                }
            }
        }
    }
}
