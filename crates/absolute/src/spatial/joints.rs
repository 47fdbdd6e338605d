//! Joints and drivers into constraint equations (docs/methods.md §3.2; the table in the
//! module doc of `spatial`). Body 1 carries the joint axis a; `n1 ⟂ n2 ⟂ a` are fixed unit
//! vectors built from the axis at t = 0 by [`perpendiculars`], the same global vectors
//! fixed in both bodies.

use flexmbd_model::{Joint, JointKind, MarkerPair, ModelError, MotionLaw, Scene, V3};
use nalgebra::{Matrix3, Vector3};

use super::constraints::{AngleConstraint, Constraint, DotConstraint};
use super::kinematics::Term;
use super::lookup::TermLookup;

/// Two unit vectors n1, n2 with (n1, n2, a) right-handed orthonormal.
pub(super) fn perpendiculars(a: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let a = a.normalize();
    let k = a.iamin();
    let mut e = Vector3::zeros();
    e[k] = 1.0;
    let n1 = e.cross(&a).normalize();
    let n2 = a.cross(&n1);
    (n1, n2)
}

/// The constraint equations of every joint of the scene and of their drivers, in the order
/// of the joints.
pub(super) fn joint_constraints(
    lookup: &TermLookup,
    constraints: &mut Vec<Constraint>,
) -> Result<(), ModelError> {
    let scene = lookup.scene;
    for (joint, &ends) in scene.joints.iter().zip(lookup.joints) {
        let driver = driver_of(scene, joint)?;
        let builder = JointBuilder::new(lookup, joint, ends);
        builder.add(driver, constraints)?;
        if driver_refused(&joint.kind, scene, &joint.name) {
            return Err(builder
                .error("only revolute (angle) and prismatic (distance) joints can be driven"));
        }
    }
    Ok(())
}

/// The motion law of the driver naming `joint`, if any (at most one).
fn driver_of(scene: &Scene, joint: &Joint) -> Result<Option<MotionLaw>, ModelError> {
    let driver: Vec<_> = scene
        .drivers
        .iter()
        .filter(|d| d.joint == joint.name)
        .collect();
    if driver.len() > 1 {
        return Err(joint_error(
            scene,
            joint,
            "more than one driver names this joint",
        ));
    }
    Ok(driver.first().map(|d| d.law.clone()))
}

/// True when a driver names a joint of a kind that cannot be driven.
fn driver_refused(kind: &JointKind, scene: &Scene, joint: &str) -> bool {
    let driven = scene.drivers.iter().any(|d| d.joint == joint);
    driven
        && !matches!(
            kind,
            JointKind::Revolute { .. }
                | JointKind::Prismatic { .. }
                | JointKind::Cylindrical { .. }
        )
}

fn joint_error(scene: &Scene, joint: &Joint, what: &str) -> ModelError {
    ModelError::Unsupported(format!("{}: joint `{}`: {what}", scene.origin, joint.name))
}

/// One joint's markers as terms, and the equations they build.
struct JointBuilder<'a> {
    lookup: &'a TermLookup<'a>,
    joint: &'a Joint,
    /// The joint's markers on body 1 and body 2.
    ends: MarkerPair,
    /// The marker points on body 1 and body 2.
    p1: Term,
    p2: Term,
    /// `r_P2 − r_P1` at t = 0.
    gap: Vector3<f64>,
}

impl<'a> JointBuilder<'a> {
    fn new(lookup: &'a TermLookup<'a>, joint: &'a Joint, ends: MarkerPair) -> Self {
        let p1 = lookup.point(ends.first);
        let p2 = lookup.point(ends.second);
        let gap = lookup.position0(&p2) - lookup.position0(&p1);
        JointBuilder {
            lookup,
            joint,
            ends,
            p1,
            p2,
            gap,
        }
    }

    fn error(&self, what: &str) -> ModelError {
        joint_error(self.lookup.scene, self.joint, what)
    }

    /// A direction fixed in body 1 (at its marker), from its ground components at t = 0.
    fn dir1(&self, v: &Vector3<f64>) -> Term {
        self.lookup.direction(self.ends.first, v)
    }

    /// A direction fixed in body 2 (at its marker), from its ground components at t = 0.
    fn dir2(&self, v: &Vector3<f64>) -> Term {
        self.lookup.direction(self.ends.second, v)
    }

    fn axis_of(&self, v: &V3) -> Result<Vector3<f64>, ModelError> {
        let a = v.vec();
        if !(a.norm() > 1e-12 && a.iter().all(|x| x.is_finite())) {
            return Err(self.error("the axis must be a finite non-zero vector"));
        }
        Ok(a.normalize())
    }

    /// `r_P2 − r_P1 = 0` (3 rows); the markers must coincide at t = 0.
    fn coincide(&self, constraints: &mut Vec<Constraint>) -> Result<(), ModelError> {
        let (j, gap) = (self.joint, self.gap);
        if gap.norm() > 1e-6 {
            return Err(self.error(&format!(
                "markers `{}.{}` and `{}.{}` are {:.3e} m apart at t = 0; they must coincide",
                j.body1,
                j.marker1,
                j.body2,
                j.marker2,
                gap.norm()
            )));
        }
        constraints.push(Constraint::Coincide {
            point2: self.p2.clone(),
            point1: self.p1.clone(),
        });
        Ok(())
    }

    /// `x·z = 0` (1 row).
    fn perpendicular(x: Term, z: Term, constraints: &mut Vec<Constraint>) {
        constraints.push(Constraint::Dot(DotConstraint {
            x,
            origin: None,
            z,
            c0: 0.0,
            law: None,
        }));
    }

    /// The equations of the joint and of its driver.
    fn add(
        &self,
        driver: Option<MotionLaw>,
        constraints: &mut Vec<Constraint>,
    ) -> Result<(), ModelError> {
        match &self.joint.kind {
            // A floating base: no equation.
            JointKind::Free => {}
            JointKind::Spherical => self.coincide(constraints)?,
            JointKind::Revolute { axis } => {
                let Some(axis) = axis else {
                    return Err(self.error(
                        "a revolute joint of a 3D scene needs its axis (`Revolute(axis: Some((x, y, z)))`)",
                    ));
                };
                self.revolute(axis, driver, constraints)?;
            }
            JointKind::Universal { axis1, axis2 } => self.universal(axis1, axis2, constraints)?,
            JointKind::Cylindrical { axis } | JointKind::Prismatic { axis } => {
                self.sliding(axis, driver, constraints)?;
            }
            JointKind::Rigid => {
                self.coincide(constraints)?;
                let e = Matrix3::<f64>::identity();
                for (x, y) in [(0, 1), (1, 2), (2, 0)] {
                    let (ex, ey) = (e.column(x).into_owned(), e.column(y).into_owned());
                    Self::perpendicular(self.dir1(&ex), self.dir2(&ey), constraints);
                }
            }
        }
        Ok(())
    }

    /// Point + `a¹·n²₁ = 0`, `a¹·n²₂ = 0`, and the angle driver
    /// `σ cos θ(t) − κ sin θ(t) = 0` with `p = n₁` fixed in each body.
    fn revolute(
        &self,
        axis: &V3,
        driver: Option<MotionLaw>,
        constraints: &mut Vec<Constraint>,
    ) -> Result<(), ModelError> {
        let a = self.axis_of(axis)?;
        let (n1, n2) = perpendiculars(&a);
        self.coincide(constraints)?;
        Self::perpendicular(self.dir1(&a), self.dir2(&n1), constraints);
        Self::perpendicular(self.dir1(&a), self.dir2(&n2), constraints);
        if let Some(law) = driver {
            constraints.push(Constraint::Angle(AngleConstraint {
                p1: self.dir1(&n1),
                p2: self.dir2(&n1),
                a: self.dir1(&a),
                phi0: 0.0,
                law,
            }));
        }
        Ok(())
    }

    /// Point + `a¹₁·a²₂ = 0` (the cross arms, perpendicular at t = 0).
    fn universal(
        &self,
        axis1: &V3,
        axis2: &V3,
        constraints: &mut Vec<Constraint>,
    ) -> Result<(), ModelError> {
        let (a1, a2) = (self.axis_of(axis1)?, self.axis_of(axis2)?);
        if a1.dot(&a2).abs() > 1e-6 {
            return Err(self.error(&format!(
                "the cross arms must be perpendicular at t = 0 (cos = {:.3e})",
                a1.dot(&a2)
            )));
        }
        self.coincide(constraints)?;
        Self::perpendicular(self.dir1(&a1), self.dir2(&a2), constraints);
        Ok(())
    }

    /// Cylindrical: `a¹·n²₁ = a¹·n²₂ = 0`, `(r_P2 − r_P1)·n¹_k = c_k`; prismatic adds
    /// `n¹₁·n²₂ = 0` and takes the distance driver `(r_P2 − r_P1)·a¹ = s₀ + s(t)`.
    fn sliding(
        &self,
        axis: &V3,
        driver: Option<MotionLaw>,
        constraints: &mut Vec<Constraint>,
    ) -> Result<(), ModelError> {
        let a = self.axis_of(axis)?;
        let (n1, n2) = perpendiculars(&a);
        Self::perpendicular(self.dir1(&a), self.dir2(&n1), constraints);
        Self::perpendicular(self.dir1(&a), self.dir2(&n2), constraints);
        for nk in [n1, n2] {
            constraints.push(Constraint::Dot(DotConstraint {
                x: self.p2.clone(),
                origin: Some(self.p1.clone()),
                z: self.dir1(&nk),
                c0: self.gap.dot(&nk),
                law: None,
            }));
        }
        let prismatic = matches!(self.joint.kind, JointKind::Prismatic { .. });
        if prismatic {
            Self::perpendicular(self.dir1(&n1), self.dir2(&n2), constraints);
        }
        match (driver, prismatic) {
            (Some(law), true) => constraints.push(Constraint::Dot(DotConstraint {
                x: self.p2.clone(),
                origin: Some(self.p1.clone()),
                z: self.dir1(&a),
                c0: self.gap.dot(&a),
                law: Some(law),
            })),
            (Some(_), false) => {
                return Err(self.error(
                    "a cylindrical joint cannot be driven (which coordinate?); drive a revolute or a prismatic joint",
                ));
            }
            (None, _) => {}
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perpendiculars_complete_a_right_handed_orthonormal_triad() {
        for a in [
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.3, -2.0, 0.7),
            Vector3::new(-1e-3, 5.0, 1e-3),
        ] {
            let (n1, n2) = perpendiculars(&a);
            let unit = a.normalize();
            for (x, y, want) in [
                (n1, n1, 1.0),
                (n2, n2, 1.0),
                (n1, n2, 0.0),
                (n1, unit, 0.0),
                (n2, unit, 0.0),
            ] {
                assert!((x.dot(&y) - want).abs() < 1e-14, "a = {a:?}: {}", x.dot(&y));
            }
            assert!((n1.cross(&n2) - unit).norm() < 1e-14, "a = {a:?}");
        }
    }

    #[test]
    fn perpendiculars_of_z_are_exact() {
        // The smallest component of ẑ is x: n1 = x̂ × ẑ = −ŷ, n2 = ẑ × n1 = x̂.
        let (n1, n2) = perpendiculars(&Vector3::z());
        assert_eq!(n1, -Vector3::y());
        assert_eq!(n2, Vector3::x());
    }
}
