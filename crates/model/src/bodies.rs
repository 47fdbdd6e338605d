//! From a scene body to the plain data of FE preprocessing: a [`ReducedBody`] for
//! every body (rigid bodies and beams run rigid have zero modes), and the FE node
//! each marker of a flexible body sits on.

use flexmbd_core::InvalidValue;
use flexmbd_fe::{ReducedBody, reduce};

use crate::error::ModelError;
use crate::scene::{Body, BodyModel, Scene};

/// The preprocessed form of one scene body.
#[derive(Clone, Debug)]
pub struct PreparedBody {
    /// Index in `Scene::bodies`.
    pub index: usize,
    /// Reduced data (zero modes when rigid).
    pub reduced: ReducedBody,
    /// True when the body has modal coordinates.
    pub flexible: bool,
    /// For each marker of the body, the FE node it sits on (flexible bodies only).
    pub marker_nodes: Vec<Option<usize>>,
}

impl Scene {
    /// Preprocess every body (FE reduction, rigid mass models).
    pub fn prepare_bodies(&self) -> Result<Vec<PreparedBody>, ModelError> {
        self.bodies
            .iter()
            .enumerate()
            .map(|(i, b)| self.prepare_body(i, b))
            .collect()
    }

    fn prepare_body(&self, index: usize, b: &Body) -> Result<PreparedBody, ModelError> {
        let fe_err = |source| ModelError::Fe {
            file: self.origin.clone(),
            body: b.name.clone(),
            source: Box::new(source),
        };
        match &b.model {
            BodyModel::Rigid {
                mass,
                center_of_mass,
                inertia,
            } => {
                let reduced =
                    ReducedBody::rigid(self.dim, *mass, center_of_mass.vec(), inertia.tensor())
                        .map_err(|e: InvalidValue| ModelError::Invalid {
                            file: self.origin.clone(),
                            error: InvalidValue {
                                field: format!("bodies[{}].model.Rigid.{}", b.name, e.field),
                                ..e
                            },
                        })?;
                Ok(PreparedBody {
                    index,
                    reduced,
                    flexible: false,
                    marker_nodes: vec![None; b.markers.len()],
                })
            }
            BodyModel::Beam(spec) => {
                let mut spec = spec.clone();
                if !b.flexible {
                    // The rigid body with the beam's mass properties: no modes at all.
                    spec.boundary.clear();
                    spec.normal_modes = 0;
                }
                let reduced = reduce(&spec).map_err(fe_err)?;
                let mut marker_nodes = Vec::with_capacity(b.markers.len());
                let length: f64 = spec
                    .geometry
                    .points
                    .windows(2)
                    .map(|w| {
                        let d: f64 = w[0].iter().zip(&w[1]).map(|(a, c)| (c - a) * (c - a)).sum();
                        d.sqrt()
                    })
                    .sum();
                for m in &b.markers {
                    let p = m.position.vec();
                    let node = reduced
                        .nodes
                        .iter()
                        .position(|n| (n.position - p).norm() <= 1e-9 * length.max(1.0));
                    if b.flexible && node.is_none() {
                        return Err(ModelError::Invalid {
                            file: self.origin.clone(),
                            error: InvalidValue::new(
                                format!("bodies[{}].markers[{}].position", b.name, m.name),
                                format!("{:?}", m.position.0),
                                "a marker of a flexible body must sit on an FE node",
                            ),
                        });
                    }
                    marker_nodes.push(node);
                }
                Ok(PreparedBody {
                    index,
                    flexible: b.flexible && reduced.n_modes() > 0,
                    reduced,
                    marker_nodes,
                })
            }
        }
    }
}
