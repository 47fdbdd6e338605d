//! Validation of the force elements and roads ([`Scene::validate`]): every refusal names
//! the field (`forces[strut_fl].damper.Piecewise.breakpoints[1]`, `roads[left].profile`) and
//! the value, and carries the line of the field in the file where it can be found.

use std::collections::HashSet;

use flexmbd_core::{Dim, InvalidValue};
use flexmbd_fe::bounds;

use crate::error::ModelError;
use crate::scene::{Body, Force, GROUND, Scene};

impl Scene {
    /// Road names unique, each profile valid.
    pub(crate) fn check_roads(&self) -> Result<(), ModelError> {
        let mut names = HashSet::new();
        for road in &self.roads {
            if !names.insert(road.name.as_str()) {
                return Err(self.repeated_name("roads", &road.name, "road"));
            }
            road.profile
                .check(&format!("roads[{}].profile", road.name))
                .map_err(|e| self.invalid(e))?;
        }
        Ok(())
    }

    /// Force names unique; each element's markers exist and its values are in range.
    pub(crate) fn check_forces(&self) -> Result<(), ModelError> {
        let mut names = HashSet::new();
        for force in &self.forces {
            if !names.insert(force.name()) {
                return Err(self.repeated_name("forces", force.name(), "force element"));
            }
            let item = |f: &str| format!("forces[{}].{f}", force.name());
            let [(body1, marker1), (body2, marker2)] = force.ends();
            if let Force::Tyre { .. } | Force::Load { .. } = force {
                self.check_marker(&item("body"), body1, &item("marker"), marker1)?;
            } else {
                self.check_marker(&item("body1"), body1, &item("marker1"), marker1)?;
                self.check_marker(&item("body2"), body2, &item("marker2"), marker2)?;
            }
            self.check_force_values(force)?;
            match force {
                Force::SpringDamper { .. } => {}
                Force::Link {
                    name,
                    spring,
                    damper,
                    axis,
                    body1,
                    ..
                } => self.check_link(name, spring, damper, axis.as_ref(), body1)?,
                Force::Tyre { .. } => self.check_tyre(force)?,
                Force::Load { .. } => self.check_load(force)?,
            }
        }
        Ok(())
    }

    /// A link's laws, and its axis: a direction fixed in a rigid body1 (or the ground).
    fn check_link(
        &self,
        name: &str,
        spring: &crate::laws::Law,
        damper: &crate::laws::Law,
        axis: Option<&crate::direction::Direction>,
        body1: &str,
    ) -> Result<(), ModelError> {
        let f = |field: &str| format!("forces[{name}].{field}");
        spring.check(&f("spring")).map_err(|e| self.invalid(e))?;
        damper.check(&f("damper")).map_err(|e| self.invalid(e))?;
        let Some(a) = axis else {
            return Ok(());
        };
        self.check_direction(&f("axis"), &a.0)?;
        if self.dim == Dim::Planar && a.0.0[2] != 0.0 {
            return Err(self.invalid(InvalidValue::new(
                f("axis"),
                format!("{:?}", a.0.0),
                "a planar link's axis lies in the x–y plane",
            )));
        }
        let flexible = self
            .bodies
            .iter()
            .find(|b| b.name == body1)
            .is_some_and(Body::runs_flexible);
        if flexible && body1 != GROUND {
            return Err(self.invalid(InvalidValue::new(
                f("body1"),
                body1,
                "a link along a body-fixed axis needs a rigid body1 (or the ground): the \
                 axis of a flexible body would turn with its deformation",
            )));
        }
        Ok(())
    }

    /// A tyre: in a 3D scene (z up), on a road that exists.
    fn check_tyre(&self, force: &Force) -> Result<(), ModelError> {
        let Force::Tyre { name, road, .. } = force else {
            return Ok(());
        };
        let f = |field: &str| format!("forces[{name}].{field}");
        if self.dim == Dim::Planar {
            return Err(self.invalid(InvalidValue::new(
                f("body"),
                self.dim_name(),
                "a tyre needs a 3D scene: the road is z = h(x), z up",
            )));
        }
        if !self.roads.iter().any(|r| &r.name == road) {
            let known: Vec<&str> = self.roads.iter().map(|r| r.name.as_str()).collect();
            return Err(ModelError::Missing {
                file: self.origin.clone(),
                line: crate::lines::line_of(&self.source, &f("road")),
                item: f("road"),
                kind: "road",
                name: road.clone(),
                hint: format!(" (roads: {})", known.join(", ")),
            });
        }
        Ok(())
    }

    fn dim_name(&self) -> &'static str {
        match self.dim {
            Dim::Planar => "Planar",
            Dim::Spatial => "Spatial",
        }
    }

    /// A link's and a tyre's numbers in range (the laws are checked by
    /// [`crate::laws::Law::check`]).
    pub(crate) fn check_new_force_values(&self, force: &Force) -> Result<(), ModelError> {
        if let Force::Tyre {
            name,
            radius,
            stiffness,
            lateral_damping,
            ..
        } = force
        {
            let f = |field: &str| format!("forces[{name}].{field}");
            self.in_range(bounds::TYRE_RADIUS, &f("radius"), *radius)?;
            self.in_range(bounds::TYRE_STIFFNESS, &f("stiffness"), *stiffness)?;
            self.in_range(
                bounds::SPRING_DAMPING,
                &f("lateral_damping"),
                *lateral_damping,
            )?;
        }
        Ok(())
    }
}
