//! What every [`Force`] element answers whatever its kind: its name, its kind's name, its two
//! ends (body, marker), and a spring's free length from its markers; and a [`JointKind`]'s name.

use nalgebra::Vector3;

use crate::scene::{Force, JointKind};

impl Force {
    /// The element's name.
    pub fn name(&self) -> &str {
        match self {
            Force::SpringDamper { name, .. }
            | Force::Link { name, .. }
            | Force::Tyre { name, .. }
            | Force::Load { name, .. } => name,
        }
    }

    /// The variant's name, for messages and reports.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Force::SpringDamper { .. } => "SpringDamper",
            Force::Link { .. } => "Link",
            Force::Tyre { .. } => "Tyre",
            Force::Load { .. } => "Load",
        }
    }

    /// The element's two ends, (body, marker) each, first then second. A tyre has one end,
    /// its wheel centre, given twice.
    pub fn ends(&self) -> [(&str, &str); 2] {
        match self {
            Force::SpringDamper {
                body1,
                marker1,
                body2,
                marker2,
                ..
            }
            | Force::Link {
                body1,
                marker1,
                body2,
                marker2,
                ..
            } => [(body1, marker1), (body2, marker2)],
            Force::Tyre { body, marker, .. } | Force::Load { body, marker, .. } => {
                [(body, marker), (body, marker)]
            }
        }
    }

    /// The element's ends (each once), to rename them (a scene rewrite).
    pub fn ends_mut(&mut self) -> Vec<(&mut String, &mut String)> {
        match self {
            Force::SpringDamper {
                body1,
                marker1,
                body2,
                marker2,
                ..
            }
            | Force::Link {
                body1,
                marker1,
                body2,
                marker2,
                ..
            } => vec![(body1, marker1), (body2, marker2)],
            Force::Tyre { body, marker, .. } | Force::Load { body, marker, .. } => {
                vec![(body, marker)]
            }
        }
    }

    /// The free length of a spring–damper whose markers sit at `r1`, `r2` at t = 0: its
    /// `free_length`, or their distance (a `Link` along its markers: their distance).
    /// Markers that coincide are refused (a spring of zero length has no direction), naming
    /// the force.
    pub fn spring_free_length(
        &self,
        origin: &str,
        r1: &Vector3<f64>,
        r2: &Vector3<f64>,
    ) -> Result<f64, crate::ModelError> {
        let name = self.name();
        let free_length = match self {
            Force::SpringDamper { free_length, .. } => *free_length,
            _ => None,
        };
        let [(body1, marker1), (body2, marker2)] = self.ends();
        let l = (r2 - r1).norm();
        if l <= 1e-9 * (1.0 + r1.norm().max(r2.norm())) {
            return Err(crate::ModelError::Invalid {
                file: origin.to_string(),
                line: None,
                error: flexmbd_core::InvalidValue::new(
                    format!("forces[{name}]"),
                    format!("{body1}.{marker1} – {body2}.{marker2}"),
                    format!(
                        "the two markers coincide at t = 0 (distance {l:.3e} m): a spring of zero length has no direction"
                    ),
                ),
            });
        }
        Ok(free_length.unwrap_or(l))
    }
}

impl JointKind {
    /// The variant's name, for messages and reports.
    pub fn kind_name(&self) -> &'static str {
        match self {
            JointKind::Revolute { .. } => "Revolute",
            JointKind::Spherical => "Spherical",
            JointKind::Universal { .. } => "Universal",
            JointKind::Prismatic { .. } => "Prismatic",
            JointKind::Cylindrical { .. } => "Cylindrical",
            JointKind::Rigid => "Rigid",
            JointKind::Free => "Free",
        }
    }
}
