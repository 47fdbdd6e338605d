//! The constraints of the cut joints, of the drivers and of the scene's constraints between
//! markers (docs/methods.md §4.6, §3.4), built once at compile time in the order their rows
//! take in Φ.
//!
//! A cut joint between the markers i and j gives, in their Cartesian positions:
//!
//! ```text
//! planar revolute:   r_i − r_j = 0 (+ sin(ψ − ψ₀ − θ(t)) = 0 when driven)
//! planar rigid:      r_i − r_j = 0,  sin(ψ − ψ₀) = 0
//! planar prismatic:  n·(r_j − r_i) = 0 (n ⟂ the axis, fixed at i),  sin(ψ − ψ₀) = 0
//! spherical:         r_i − r_j = 0
//! revolute (axis a): r_i − r_j = 0,  a·n₁ = 0,  a·n₂ = 0
//! universal:         r_i − r_j = 0,  a₁·a₂ = 0
//! cylindrical:       a·n₁ = a·n₂ = 0,  n₁·(r_j − r_i) = n₂·(r_j − r_i) = 0
//! prismatic:         the cylindrical rows and n₁·n₂ = 0 (the twist about a)
//! rigid:             r_i − r_j = 0,  e_x·e_y = e_y·e_z = e_z·e_x = 0
//! ```
//!
//! with ψ = θ_j − θ_i the 2D angle between the markers (ψ₀ its t = 0 value), n₁, n₂ the
//! [`perpendiculars`] of the axis, and every axis given in the ground at t = 0 and carried
//! by its side's body (i for a, n, j for the second vector of a product). A cut Free joint
//! adds nothing. A driven joint of the tree adds z_c − s θ(t) = 0 (s = −1 when the tree
//! runs the joint from body2 to body1).

use flexmbd_core::Dim;
use flexmbd_model::{
    Constraint as SceneConstraint, Driver, JointKind, ModelError, MotionLaw, PreparedScene,
};
use nalgebra::{Matrix3, Vector3};

use crate::constraints::Constraint;
use crate::kinematics::angle_of;
use crate::system::unsupported;
use crate::topology::{BodyInfo, Side, Topology};

/// Two unit vectors perpendicular to a and to each other.
pub(crate) fn perpendiculars(a: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let t = if a.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let n1 = a.cross(&t).normalize();
    let n2 = a.cross(&n1);
    (n1, n2)
}

/// The two sides of a cut joint and their bodies' rotations at t = 0.
struct CutJoint {
    i: Side,
    j: Side,
    a0_i: Matrix3<f64>,
    a0_j: Matrix3<f64>,
    /// The scene and joint, for messages.
    what: String,
}

impl CutJoint {
    fn new(prepared: &PreparedScene, infos: &[BodyInfo], ji: usize) -> CutJoint {
        let scene = prepared.scene();
        let joint = &scene.joints[ji];
        let ends = prepared.joint_markers()[ji];
        let i = Side::at(prepared, infos, ends.first);
        let j = Side::at(prepared, infos, ends.second);
        let a0_of = |s: &Side| s.body.map_or(Matrix3::identity(), |b| infos[b].a0);
        CutJoint {
            i,
            j,
            a0_i: a0_of(&i),
            a0_j: a0_of(&j),
            what: format!("{}: cut joint `{}`", scene.origin, joint.name),
        }
    }

    /// A ground-component axis at t = 0 in side i's body components.
    fn axis_at_i(&self, v: Vector3<f64>) -> Vector3<f64> {
        self.a0_i.transpose() * v
    }

    /// A ground-component axis at t = 0 in side j's body components.
    fn axis_at_j(&self, v: Vector3<f64>) -> Vector3<f64> {
        self.a0_j.transpose() * v
    }

    fn point(&self) -> Constraint {
        Constraint::Point {
            i: self.i,
            j: self.j,
        }
    }

    /// sin(ψ − ψ₀ − θ(t)) = 0 with ψ₀ the angle between the markers at t = 0.
    fn angle(&self, law: MotionLaw) -> Constraint {
        Constraint::Angle2 {
            i: self.i,
            j: self.j,
            psi0: angle_of(&self.a0_j) - angle_of(&self.a0_i),
            law,
            sign: 1.0,
        }
    }

    /// a · b = 0, a and b given in the ground at t = 0.
    fn perp(&self, a: Vector3<f64>, b: Vector3<f64>) -> Constraint {
        Constraint::Perp {
            i: self.i,
            abar: self.axis_at_i(a),
            j: self.j,
            bbar: self.axis_at_j(b),
        }
    }

    /// n · (r_j − r_i) = 0, n given in the ground at t = 0.
    fn slide(&self, n: Vector3<f64>) -> Constraint {
        Constraint::Slide {
            i: self.i,
            nbar: self.axis_at_i(n),
            j: self.j,
        }
    }
}

/// The constraints of every cut joint, in the order of `topology.cuts`.
pub(crate) fn cut_joint_constraints(
    prepared: &PreparedScene,
    infos: &[BodyInfo],
    topology: &Topology,
) -> Result<Vec<Constraint>, ModelError> {
    let scene = prepared.scene();
    let mut constraints = Vec::new();
    for &ji in &topology.cuts {
        let joint = &scene.joints[ji];
        let cut = CutJoint::new(prepared, infos, ji);
        let driver = scene.drivers.iter().find(|d| d.joint == joint.name);
        match (scene.dim, &joint.kind) {
            // A cut Free joint (its body reached through other joints) adds nothing.
            (_, JointKind::Free) => {}
            (
                Dim::Planar,
                JointKind::Revolute { .. } | JointKind::Rigid | JointKind::Prismatic { .. },
            ) => planar_cut_joint(&cut, &joint.kind, driver, &mut constraints)?,
            (Dim::Spatial, kind) => spatial_cut_joint(&cut, kind, driver, &mut constraints)?,
            (d, k) => {
                return Err(unsupported(format!(
                    "{}: {k:?} is not a {d} joint",
                    cut.what
                )));
            }
        }
    }
    Ok(constraints)
}

/// A planar revolute (driven or not), rigid or prismatic cut joint.
fn planar_cut_joint(
    cut: &CutJoint,
    kind: &JointKind,
    driver: Option<&Driver>,
    constraints: &mut Vec<Constraint>,
) -> Result<(), ModelError> {
    match kind {
        JointKind::Revolute { .. } => {
            constraints.push(cut.point());
            if let Some(d) = driver {
                constraints.push(cut.angle(d.law.clone()));
            }
        }
        JointKind::Rigid => {
            constraints.push(cut.point());
            constraints.push(cut.angle(MotionLaw::Locked));
        }
        JointKind::Prismatic { axis } => {
            if driver.is_some() {
                return Err(unsupported(format!(
                    "{}: a driven prismatic joint must be in the tree (drive a joint of the spanning tree instead)",
                    cut.what
                )));
            }
            let mut a = axis.vec();
            a.z = 0.0;
            let n = Vector3::new(-a.y, a.x, 0.0).normalize();
            constraints.push(cut.slide(n));
            constraints.push(cut.angle(MotionLaw::Locked));
        }
        _ => unreachable!("not a planar cut joint with constraints"),
    }
    Ok(())
}

/// A spatial cut joint (not driven).
fn spatial_cut_joint(
    cut: &CutJoint,
    kind: &JointKind,
    driver: Option<&Driver>,
    constraints: &mut Vec<Constraint>,
) -> Result<(), ModelError> {
    if driver.is_some() {
        return Err(unsupported(format!(
            "{}: driven cut joints are not supported in 3D yet (drive a joint of the spanning tree)",
            cut.what
        )));
    }
    match kind {
        JointKind::Free => {}
        JointKind::Spherical => constraints.push(cut.point()),
        JointKind::Revolute { axis } => {
            let a = axis.map(|v| v.vec().normalize()).ok_or_else(|| {
                unsupported(format!("{}: a 3D revolute joint needs an axis", cut.what))
            })?;
            let (n1, n2) = perpendiculars(&a);
            constraints.push(cut.point());
            constraints.push(cut.perp(a, n1));
            constraints.push(cut.perp(a, n2));
        }
        JointKind::Universal { axis1, axis2 } => {
            constraints.push(cut.point());
            constraints.push(cut.perp(axis1.vec().normalize(), axis2.vec().normalize()));
        }
        JointKind::Cylindrical { axis } | JointKind::Prismatic { axis } => {
            let a = axis.vec().normalize();
            let (n1, n2) = perpendiculars(&a);
            constraints.push(cut.perp(a, n1));
            constraints.push(cut.perp(a, n2));
            for n in [n1, n2] {
                constraints.push(cut.slide(n));
            }
            if matches!(kind, JointKind::Prismatic { .. }) {
                constraints.push(cut.perp(n1, n2));
            }
        }
        JointKind::Rigid => {
            constraints.push(cut.point());
            let e = [Vector3::x(), Vector3::y(), Vector3::z()];
            for k in 0..3 {
                constraints.push(cut.perp(e[k], e[(k + 1) % 3]));
            }
        }
    }
    Ok(())
}

/// The scene's constraints between markers (docs/methods.md §3.4), never tree edges, in
/// their order: a `Distance` ½(|r_j − r_i|² − L²) = 0 and a `PointInPlane` the slide
/// n·(r_j − r_i) = 0 with n the body1-fixed normal (side i = marker1).
pub(crate) fn marker_constraints(
    prepared: &PreparedScene,
    infos: &[BodyInfo],
    constraints: &mut Vec<Constraint>,
) {
    let scene = prepared.scene();
    for (c, &ends) in scene.constraints.iter().zip(prepared.constraint_markers()) {
        let i = Side::at(prepared, infos, ends.first);
        let j = Side::at(prepared, infos, ends.second);
        match c {
            SceneConstraint::Distance { .. } => constraints.push(Constraint::Distance {
                i,
                j,
                length: scene.constraint_length(c).unwrap_or_default(),
            }),
            SceneConstraint::PointInPlane { normal, .. } => {
                // The normal in body1 components, carried into side i's frame at t = 0.
                let (scene_a1, a0_i) = match ends.first.body {
                    None => (Matrix3::identity(), Matrix3::identity()),
                    Some(b) => (scene.bodies[b.0].orientation.matrix(), infos[b.0].a0),
                };
                let n = scene_a1 * normal.vec().normalize();
                constraints.push(Constraint::Slide {
                    i,
                    nbar: a0_i.transpose() * n,
                    j,
                });
            }
        }
    }
}

/// z_c − s θ(t) = 0 for every driver of a one-coordinate joint of the tree (drivers of cut
/// joints are in [`cut_joint_constraints`]).
pub(crate) fn driver_constraints(
    prepared: &PreparedScene,
    topology: &Topology,
    constraints: &mut Vec<Constraint>,
) -> Result<(), ModelError> {
    let scene = prepared.scene();
    for (d, ji) in scene.drivers.iter().zip(prepared.driver_joints()) {
        let Some(tj) = &topology.tree[ji.0] else {
            continue;
        };
        if tj.coords.len() != 1 {
            return Err(unsupported(format!(
                "{}: driver `{}`: joint `{}` has {} coordinates; only one-coordinate joints (revolute, prismatic) can be driven",
                scene.origin,
                d.name,
                d.joint,
                tj.coords.len()
            )));
        }
        constraints.push(Constraint::Coord {
            z: tj.coords[0],
            law: d.law.clone(),
            sign: if tj.reversed { -1.0 } else { 1.0 },
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perpendiculars_complete_an_orthonormal_right_handed_triple() {
        let axes = [
            Vector3::x(),
            Vector3::y(),
            Vector3::z(),
            -Vector3::x(),
            Vector3::new(0.95, 0.1, -0.3).normalize(),
            Vector3::new(0.2, -0.7, 0.4).normalize(),
        ];
        for a in axes {
            let (n1, n2) = perpendiculars(&a);
            for (u, v, what) in [(a, n1, "a·n1"), (a, n2, "a·n2"), (n1, n2, "n1·n2")] {
                assert!(
                    u.dot(&v).abs() < 1e-15,
                    "{what} = {} for a = {a:?}",
                    u.dot(&v)
                );
            }
            assert!((n1.norm() - 1.0).abs() < 1e-15, "|n1| = {}", n1.norm());
            assert!((n2.norm() - 1.0).abs() < 1e-15, "|n2| = {}", n2.norm());
            let handedness = a.cross(&n1) - n2;
            assert!(handedness.norm() < 1e-15, "a × n1 − n2 = {handedness:?}");
        }
    }

    #[test]
    fn perpendiculars_use_y_as_the_helper_only_near_x() {
        // The helper is x unless a is near x, then y, so n1 = a × helper never vanishes.
        let (n1, _) = perpendiculars(&Vector3::x());
        assert_eq!(n1, Vector3::z());
        let (n1, _) = perpendiculars(&Vector3::z());
        assert_eq!(n1, Vector3::y());
    }
}
