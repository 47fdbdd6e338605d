//! The numbers of a scene in their ranges ([`flexmbd_fe::bounds`], one place for every
//! bound): positions, orientations, axes, velocities, gravity, rigid mass models, initial
//! modes, driver laws and spring parameters. Checked once at load by [`Scene::validate`],
//! so every formulation starts from finite data and refuses the same input the same way.

use flexmbd_core::{Dim, InvalidValue};
use flexmbd_fe::bounds::{self, Range};
use nalgebra::Vector3;

use crate::error::ModelError;
use crate::scene::{Body, BodyModel, Force, Inertia, JointKind, MotionLaw, Orientation, Scene, V3};

impl Scene {
    /// `x` in `range`, refused as `field` otherwise.
    pub(crate) fn in_range(&self, range: Range, field: &str, x: f64) -> Result<(), ModelError> {
        range
            .check(field, x)
            .map(|_| ())
            .map_err(|e| self.invalid(e))
    }

    /// Every component of `v` in `range` (`field[k]`).
    fn vector_in_range(&self, range: Range, field: &str, v: &V3) -> Result<(), ModelError> {
        range.check_all(field, &v.0).map_err(|e| self.invalid(e))
    }

    /// A direction (normalised on use): components in range and a norm that is not zero.
    pub(crate) fn axis(&self, field: &str, v: &V3) -> Result<(), ModelError> {
        self.vector_in_range(bounds::AXIS_COMPONENT, field, v)?;
        if v.vec().norm() < bounds::MIN_AXIS_NORM {
            return Err(self.invalid(InvalidValue::new(
                field,
                format!("{:?}", v.0),
                format!(
                    "must be a non-zero direction (norm at least {:e})",
                    bounds::MIN_AXIS_NORM
                ),
            )));
        }
        Ok(())
    }

    /// Gravity components in [`bounds::GRAVITY`].
    pub(crate) fn check_gravity(&self) -> Result<(), ModelError> {
        self.vector_in_range(bounds::GRAVITY, "gravity", &self.gravity)?;
        self.vector_in_range(bounds::VELOCITY, "initial_velocity", &self.initial_velocity)
    }

    /// A body's placement, velocity and marker positions in range; its orientation a
    /// rotation (finite angle, non-zero axis, non-parallel axes).
    pub(crate) fn check_body_values(&self, b: &Body) -> Result<(), ModelError> {
        let f = |field: &str| format!("bodies[{}].{field}", b.name);
        self.vector_in_range(bounds::POSITION, &f("origin"), &b.origin)?;
        self.check_orientation(&f("orientation"), &b.orientation)?;
        self.vector_in_range(bounds::VELOCITY, &f("velocity.linear"), &b.velocity.linear)?;
        self.vector_in_range(
            bounds::ANGULAR_VELOCITY,
            &f("velocity.angular"),
            &b.velocity.angular,
        )?;
        for m in &b.markers {
            let field = f(&format!("markers[{}].position", m.name));
            self.vector_in_range(bounds::POSITION, &field, &m.position)?;
        }
        for (k, y) in b.initial_modes.iter().enumerate() {
            self.in_range(
                bounds::MODAL_COORDINATE,
                &f(&format!("initial_modes[{k}]")),
                *y,
            )?;
        }
        if let BodyModel::Rigid {
            mass,
            center_of_mass,
            inertia,
        } = &b.model
        {
            self.in_range(bounds::MASS, &f("model.Rigid.mass"), *mass)?;
            let com = f("model.Rigid.center_of_mass");
            self.vector_in_range(bounds::POSITION, &com, center_of_mass)?;
            self.check_inertia(&f("model.Rigid.inertia"), inertia)?;
        }
        Ok(())
    }

    /// Every inertia component in [`bounds::INERTIA`] (their signs are checked with the
    /// rest of the mass model).
    fn check_inertia(&self, field: &str, inertia: &Inertia) -> Result<(), ModelError> {
        let range = bounds::INERTIA;
        match inertia {
            Inertia::Planar(izz) => self.in_range(range, &format!("{field}.Planar"), *izz),
            Inertia::Diagonal(d) => self.vector_in_range(range, &format!("{field}.Diagonal"), d),
            Inertia::Full(rows) => {
                for (i, row) in rows.iter().enumerate() {
                    range
                        .check_all(&format!("{field}.Full[{i}]"), row)
                        .map_err(|e| self.invalid(e))?;
                }
                Ok(())
            }
        }
    }

    /// An orientation that is a rotation: a finite angle, a non-zero axis, two non-parallel
    /// axes.
    fn check_orientation(&self, field: &str, o: &Orientation) -> Result<(), ModelError> {
        match o {
            Orientation::Identity => Ok(()),
            Orientation::Angle(a) => self.in_range(bounds::ANGLE, &format!("{field}.Angle"), *a),
            Orientation::AxisAngle { axis, angle } => {
                self.axis(&format!("{field}.AxisAngle.axis"), axis)?;
                self.in_range(bounds::ANGLE, &format!("{field}.AxisAngle.angle"), *angle)
            }
            Orientation::Axes { x, y } => {
                self.axis(&format!("{field}.Axes.x"), x)?;
                self.axis(&format!("{field}.Axes.y"), y)?;
                let (ex, ey) = (x.vec().normalize(), y.vec().normalize());
                if ex.cross(&ey).norm() < 1e-6 {
                    return Err(self.invalid(InvalidValue::new(
                        format!("{field}.Axes.y"),
                        format!("{:?}", y.0),
                        "is parallel to x: the axes do not fix a rotation",
                    )));
                }
                Ok(())
            }
        }
    }

    /// Ground marker positions in [`bounds::POSITION`].
    pub(crate) fn check_ground_values(&self) -> Result<(), ModelError> {
        for m in &self.ground {
            let field = format!("ground[{}].position", m.name);
            self.vector_in_range(bounds::POSITION, &field, &m.position)?;
        }
        Ok(())
    }

    /// The axes a joint names: finite, in range, non-zero; a 3D revolute has one; a
    /// universal joint's arms are perpendicular at t = 0; a planar sliding axis lies in the
    /// x–y plane (the tolerances are the absolute formulation's).
    pub(crate) fn check_joint_axes(&self, name: &str, kind: &JointKind) -> Result<(), ModelError> {
        let f = |field: &str| format!("joints[{name}].kind.{field}");
        let spatial = self.dim == Dim::Spatial;
        match kind {
            JointKind::Revolute { axis: Some(a) } => self.axis(&f("Revolute.axis"), a),
            JointKind::Revolute { axis: None } if spatial => Err(self.invalid(InvalidValue::new(
                f("Revolute.axis"),
                "None",
                "a revolute joint of a 3D scene needs its axis (`Revolute(axis: Some([x, y, z]))`)",
            ))),
            JointKind::Universal { axis1, axis2 } => {
                self.axis(&f("Universal.axis1"), axis1)?;
                self.axis(&f("Universal.axis2"), axis2)?;
                let cos = axis1.vec().normalize().dot(&axis2.vec().normalize());
                if cos.abs() > 1e-6 {
                    return Err(self.invalid(InvalidValue::new(
                        f("Universal.axis2"),
                        format!("{:?}", axis2.0),
                        format!("the cross arms must be perpendicular at t = 0 (cos = {cos:.3e})"),
                    )));
                }
                Ok(())
            }
            JointKind::Prismatic { axis } => {
                self.axis(&f("Prismatic.axis"), axis)?;
                let in_plane = (axis.0[0].powi(2) + axis.0[1].powi(2)).sqrt();
                let lies_in_plane = in_plane > 1e-12 && axis.0[2].abs() <= 1e-9 * in_plane;
                if !spatial && !lies_in_plane {
                    return Err(self.invalid(InvalidValue::new(
                        f("Prismatic.axis"),
                        format!("{:?}", axis.0),
                        "a planar sliding axis must be a non-zero vector in the x–y plane",
                    )));
                }
                Ok(())
            }
            JointKind::Cylindrical { axis } => self.axis(&f("Cylindrical.axis"), axis),
            JointKind::Revolute { axis: None }
            | JointKind::Spherical
            | JointKind::Rigid
            | JointKind::Free => Ok(()),
        }
    }

    /// A driver law's parameters in range (a positive spin-up time).
    pub(crate) fn check_law(&self, driver: &str, law: &MotionLaw) -> Result<(), ModelError> {
        let f = |field: &str| format!("drivers[{driver}].law.{field}");
        match *law {
            MotionLaw::Locked | MotionLaw::Input(_) => Ok(()),
            MotionLaw::ConstantRate(r) => {
                self.in_range(bounds::ANGULAR_VELOCITY, &f("ConstantRate"), r)
            }
            MotionLaw::SpinUp { omega_s, t_s } => {
                self.in_range(bounds::ANGULAR_VELOCITY, &f("SpinUp.omega_s"), omega_s)?;
                self.in_range(bounds::TIME_CONSTANT, &f("SpinUp.t_s"), t_s)
            }
            MotionLaw::Harmonic {
                amplitude,
                frequency,
                phase,
            } => {
                self.in_range(bounds::AMPLITUDE, &f("Harmonic.amplitude"), amplitude)?;
                self.in_range(bounds::FREQUENCY, &f("Harmonic.frequency"), frequency)?;
                self.in_range(bounds::ANGLE, &f("Harmonic.phase"), phase)
            }
        }
    }

    /// A spring–damper's stiffness, damping and free length in range; a link's and a
    /// tyre's numbers ([`Scene::check_new_force_values`]).
    pub(crate) fn check_force_values(&self, force: &Force) -> Result<(), ModelError> {
        let Force::SpringDamper {
            name,
            stiffness,
            damping,
            free_length,
            ..
        } = force
        else {
            return self.check_new_force_values(force);
        };
        let f = |field: &str| format!("forces[{name}].{field}");
        self.in_range(bounds::SPRING_STIFFNESS, &f("stiffness"), *stiffness)?;
        self.in_range(bounds::SPRING_DAMPING, &f("damping"), *damping)?;
        if let Some(l) = free_length {
            let range = Range {
                min: 0.0,
                ..bounds::POSITION
            };
            self.in_range(range, &f("free_length"), *l)?;
        }
        Ok(())
    }

    /// A direction at `field` (normalised on use): components in range, a non-zero norm.
    pub(crate) fn check_direction(&self, field: &str, v: &V3) -> Result<(), ModelError> {
        self.axis(field, v)
    }

    /// A marker's position at t = 0 in ground components (`None` for an unknown name).
    pub(crate) fn marker_global(&self, body: &str, marker: &str) -> Option<Vector3<f64>> {
        let p = self.undeformed_position(body, marker, None)?;
        Some(match self.dim {
            Dim::Planar => Vector3::new(p.x, p.y, 0.0),
            Dim::Spatial => p,
        })
    }
}
