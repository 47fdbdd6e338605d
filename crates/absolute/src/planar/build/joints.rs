//! Joints and drivers as constraints (docs/methods.md §3.2, planar joints): revolutes share
//! their point (no equation here); a rigid joint (bracket) adds the angle lock θ ≡ 0; a
//! driven revolute the angle driver θ(t); a prismatic joint the slide (r_P2 − r_P1) × d₁ = 0,
//! the angle lock and, when driven, (r_P2 − r_P1) · d₁ − s₀ − s(t) = 0. The scene's
//! `Distance` constraints follow the joints, one row each.

use flexmbd_model::{
    BodyId, Joint, JointKind, MarkerId, MarkerPair, ModelError, MotionLaw, PreparedScene, V3,
};
use nalgebra::{DVector, Vector2};

use super::super::Planar;
use super::super::algebra::e_mat;
use super::super::constraints::{Angle, Constraint, MarkerDistance, Slide};
use super::super::kinematics::{Direction, PlanarMarker};

impl Planar {
    /// The constraints of the joints and drivers, in joint order (angles measured from their
    /// value at q0).
    pub(super) fn joint_constraints(
        &self,
        prepared: &PreparedScene,
        q0: &DVector<f64>,
    ) -> Result<Vec<Constraint>, ModelError> {
        let scene = prepared.scene();
        let zero = DVector::zeros(self.coordinates.len());
        let mut constraints = Vec::new();
        for (j, &ends) in scene.joints.iter().zip(prepared.joint_markers()) {
            let driver = scene.drivers.iter().find(|d| d.joint == j.name);
            if let JointKind::Prismatic { axis } = &j.kind {
                let (p1, p2, d1) = self.prismatic_parts(prepared, j, ends, axis, q0)?;
                constraints.push(Constraint::Slide(Slide {
                    p1,
                    p2,
                    d1,
                    along: None,
                }));
                // The relative rotation is locked.
                let a1 = self.direction_at(ends.first);
                let a2 = self.direction_at(ends.second);
                let phi0 = self.angle(&a1, &a2, q0);
                constraints.push(Constraint::Angle(Angle {
                    d1: a1,
                    d2: a2,
                    phi0,
                    law: MotionLaw::Locked,
                }));
                if let Some(d) = driver {
                    let s0 = self.slide(&p1, &p2, &d1, q0, &zero);
                    constraints.push(Constraint::Slide(Slide {
                        p1,
                        p2,
                        d1,
                        along: Some((s0, d.law.clone())),
                    }));
                }
                continue;
            }
            let law = match (&j.kind, driver) {
                (JointKind::Rigid, _) => Some(MotionLaw::Locked),
                (_, Some(d)) => Some(d.law.clone()),
                _ => None,
            };
            if let Some(law) = law {
                let d1 = self.direction_at(ends.first);
                let d2 = self.direction_at(ends.second);
                let phi0 = self.angle(&d1, &d2, q0);
                constraints.push(Constraint::Angle(Angle { d1, d2, phi0, law }));
            }
        }
        Ok(constraints)
    }

    /// The scene's constraints between markers, in their order: a `Distance` is a
    /// [`MarkerDistance`]; `PointInPlane` is refused (3D only, as validation says).
    pub(super) fn marker_constraints(
        &self,
        prepared: &PreparedScene,
    ) -> Result<Vec<Constraint>, ModelError> {
        let scene = prepared.scene();
        let mut constraints = Vec::new();
        for (c, &ends) in scene.constraints.iter().zip(prepared.constraint_markers()) {
            let p1 = self.marker_of(prepared, ends.first);
            let p2 = self.marker_of(prepared, ends.second);
            let Some(length) = scene.constraint_length(c) else {
                return Err(ModelError::Unsupported(format!(
                    "{}: constraint `{}`: {} is not a planar constraint",
                    scene.origin,
                    c.name(),
                    c.kind_name()
                )));
            };
            constraints.push(Constraint::MarkerDistance(MarkerDistance {
                p1,
                p2,
                length,
            }));
        }
        Ok(constraints)
    }

    /// The x axis of a body's frame, turned at the marker's node on a flexible body (the
    /// ground x axis for the ground).
    pub(in super::super) fn direction_at(&self, marker: MarkerId) -> Direction {
        match marker.body {
            None => Direction {
                body: None,
                node: None,
                abar: Vector2::new(1.0, 0.0),
            },
            Some(BodyId(b)) => Direction {
                body: Some(b),
                node: if self.bodies[b].n_modes > 0 {
                    self.bodies[b].markers[marker.index].node
                } else {
                    None
                },
                abar: Vector2::new(1.0, 0.0),
            },
        }
    }

    /// Markers and sliding direction of a prismatic joint: d₁ is fixed in body 1 (at its
    /// marker's node on a flexible body) and equals the unit axis at q0.
    pub(in super::super) fn prismatic_parts(
        &self,
        prepared: &PreparedScene,
        j: &Joint,
        ends: MarkerPair,
        axis: &V3,
        q0: &DVector<f64>,
    ) -> Result<(PlanarMarker, PlanarMarker, Direction), ModelError> {
        let a = Vector2::new(axis.0[0], axis.0[1]);
        let norm = a.norm();
        if !norm.is_finite() || norm <= 1e-12 || axis.0[2].abs() > 1e-9 * norm {
            return Err(prepared.scene().invalid(flexmbd_core::InvalidValue::new(
                format!("joints[{}].kind.Prismatic.axis", j.name),
                format!("{:?}", axis.0),
                "a planar sliding axis must be a non-zero vector in the x–y plane",
            )));
        }
        let a = a / a.norm();
        let p1 = self.marker_of(prepared, ends.first);
        let p2 = self.marker_of(prepared, ends.second);
        let mut d1 = self.direction_at(ends.first);
        // C(ā) d_x(q0) = a  ⇒  ā = (a · d_x, a · E d_x) / |d_x|².
        let (dx, _, _) = self.direction(&d1, q0, &DVector::zeros(q0.len()));
        let edx = e_mat() * dx;
        d1.abar = Vector2::new(a.dot(&dx), a.dot(&edx)) / dx.norm_squared();
        Ok((p1, p2, d1))
    }
}
