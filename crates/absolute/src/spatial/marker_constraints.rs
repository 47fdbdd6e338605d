//! The scene's constraints between two markers (`Scene::constraints`, docs/methods.md §3.4)
//! as equations over [`Term`]s, after the joints: a `Distance` is one row
//! ½(d·d − L²) = 0 with d = r_P2 − r_P1 (the equation of
//! `flexmbd_model::constraint_equations`), a `PointInPlane` one dot row
//! n¹·(r_P2 − r_P1) = 0 with n¹ the body1-fixed normal, turning with marker P1's node on a
//! flexible body. Markers on flexible bodies are the point terms of their FE nodes, as for
//! the joints.

use flexmbd_model::constraint_equations::{Motion, distance};
use flexmbd_model::{Constraint as SceneConstraint, ModelError};
use nalgebra::Vector3;

use super::constraints::{At, Constraint, DotConstraint};
use super::kinematics::Term;
use super::lookup::TermLookup;
use flexmbd_core::SystemTerms;

/// ½(|r_P2 − r_P1|² − L²) = 0 (1 row).
pub(super) struct DistanceConstraint {
    pub(super) point1: Term,
    pub(super) point2: Term,
    /// L (m).
    pub(super) length: f64,
}

/// The equations of the scene's constraints, in their order (one row each).
pub(super) fn marker_constraints(
    lookup: &TermLookup,
    constraints: &mut Vec<Constraint>,
) -> Result<(), ModelError> {
    for (c, &ends) in lookup.scene.constraints.iter().zip(lookup.constraints) {
        let point1 = lookup.point(ends.first);
        let point2 = lookup.point(ends.second);
        match c {
            SceneConstraint::Distance { .. } => {
                let length = lookup.scene.constraint_length(c).unwrap_or_default();
                constraints.push(Constraint::Distance(DistanceConstraint {
                    point1,
                    point2,
                    length,
                }));
            }
            SceneConstraint::PointInPlane { normal, .. } => {
                let a1 = ends.first.body.map_or(nalgebra::Matrix3::identity(), |b| {
                    lookup.initial_frames[b.0].1
                });
                let global: Vector3<f64> = a1 * normal.vec();
                constraints.push(Constraint::Dot(DotConstraint {
                    x: point2,
                    origin: Some(point1),
                    z: lookup.direction(ends.first, &global),
                    c0: 0.0,
                    law: None,
                }));
            }
        }
    }
    Ok(())
}

impl DistanceConstraint {
    pub(super) fn evaluate(&self, at: &At, row: usize, out: &mut SystemTerms) {
        let (bodies, q, qd, req) = (at.bodies, at.q, at.qd, at.req);
        let e1 = self.point1.eval(bodies, q, qd);
        let e2 = self.point2.eval(bodies, q, qd);
        let motion = |e: &super::kinematics::TermValue| Motion {
            value: e.value,
            rate: e.rate,
            bias: e.bias,
        };
        let d = motion(&e2).minus(&motion(&e1));
        let equation = distance(&d, self.length);
        if req.constraints {
            out.phi[row] = equation.phi;
        }
        if req.jacobian {
            // ∂Φ/∂d = d.
            self.point2
                .add_jacobian(bodies, &e2, &d.value, q, &mut out.phi_q, row);
            self.point1
                .add_jacobian(bodies, &e1, &(-d.value), q, &mut out.phi_q, row);
        }
        if req.accel_term {
            out.accel_term[row] = equation.accel_term;
        }
    }
}
