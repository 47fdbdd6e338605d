//! Constraints between two markers that are not joints (docs/methods.md §3.4): the
//! scene's `constraints:` list, and its validation.
//!
//! A joint shares a point or an axis and so can be a tree edge of the relative formulation;
//! these constraints never are (they are always cut constraints there) and carry no
//! coordinates of their own:
//!
//! - `Distance`: the markers keep the distance L, ½(|r_P2 − r_P1|² − L²) = 0 — a massless
//!   bar with spherical ends (the Iltis tie rod, docs/scenes.md §2);
//! - `PointInPlane`: marker P2 stays in the plane through marker P1 normal to the
//!   body1-fixed n, n·(r_P2 − r_P1) = 0 (3D only).
//!
//! ```ron
//! constraints: [
//!     Distance(name: "tie_rod_fl", body1: "chassis", marker1: "T0_fl",
//!              body2: "carrier_fl", marker2: "T1_fl", length: None),
//!     PointInPlane(name: "leaf_link_plane_fl", body1: "chassis", marker1: "L0_fl",
//!                  normal: (1.0, 0.0, 0.0), body2: "carrier_fl", marker2: "U_fl"),
//! ]
//! ```
//!
//! Validation (`Scene::check_constraints`, run by [`Scene::validate`]): existing bodies and
//! markers, two different bodies, names unique among the joints and the constraints, a
//! finite positive `length` and a finite non-zero `normal`, `PointInPlane` only in a 3D
//! scene, and the markers satisfying the constraint at t = 0 to within
//! [`CONSTRAINT_TOLERANCE`] (like the joints' coincident markers).

use std::collections::HashSet;

use flexmbd_core::{Dim, InvalidValue};
use flexmbd_fe::bounds::{self, Range};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::ModelError;
use crate::scene::{Scene, V3};

/// The largest residual (m) of a constraint at t = 0 that counts as satisfied: a distance
/// off its length, a point off its plane.
pub const CONSTRAINT_TOLERANCE: f64 = 1e-6;

/// The range of a `Distance` constraint's length (m).
const LENGTH: Range = Range {
    min: 0.0,
    max: 2e6,
    open_min: true,
    unit: "m",
};

/// A constraint between marker `marker1` of `body1` and marker `marker2` of `body2`
/// (`ground` for the fixed body).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Constraint {
    /// The markers keep their distance: |r_P2 − r_P1| = L (a massless bar with spherical
    /// ends).
    Distance {
        /// Name, unique among the joints and constraints.
        name: String,
        /// First body.
        body1: String,
        /// Marker on the first body.
        marker1: String,
        /// Second body.
        body2: String,
        /// Marker on the second body.
        marker2: String,
        /// L (m); `None`: the markers' distance at t = 0.
        #[serde(default)]
        length: Option<f64>,
    },
    /// Marker P2 stays in the plane through marker P1 normal to n, n fixed in body 1:
    /// n·(r_P2 − r_P1) = 0 (3D only).
    PointInPlane {
        /// Name, unique among the joints and constraints.
        name: String,
        /// First body: it carries the plane.
        body1: String,
        /// Marker on the first body: a point of the plane.
        marker1: String,
        /// Normal of the plane, body1 components (normalised on use); written `(x, y, z)` or
        /// `[x, y, z]`.
        #[serde(deserialize_with = "list_or_tuple")]
        normal: V3,
        /// Second body.
        body2: String,
        /// Marker on the second body: the point that stays in the plane.
        marker2: String,
    },
}

/// A [`V3`] written as a list `[x, y, z]` (as every vector of the scene) or as a tuple
/// `(x, y, z)` (the vehicle scenes' syntax for axes and normals).
fn list_or_tuple<'de, D: serde::Deserializer<'de>>(d: D) -> Result<V3, D::Error> {
    struct Numbers;
    impl<'de> serde::de::Visitor<'de> for Numbers {
        type Value = Vec<f64>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a vector of 2 or 3 numbers, `(x, y, z)` or `[x, y, z]`")
        }
        fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<f64>, A::Error> {
            let mut v = Vec::with_capacity(3);
            while let Some(x) = seq.next_element::<f64>()? {
                if v.len() == 3 {
                    return Err(serde::de::Error::custom(
                        "expected a vector of 2 or 3 numbers, found more",
                    ));
                }
                v.push(x);
            }
            Ok(v)
        }
    }
    let v = d.deserialize_any(Numbers)?;
    V3::try_from(v).map_err(serde::de::Error::custom)
}

impl Constraint {
    /// The constraint's name.
    pub fn name(&self) -> &str {
        match self {
            Constraint::Distance { name, .. } | Constraint::PointInPlane { name, .. } => name,
        }
    }

    /// The variant name, for messages.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Constraint::Distance { .. } => "Distance",
            Constraint::PointInPlane { .. } => "PointInPlane",
        }
    }

    /// The two ends, (body, marker) each, first then second.
    pub fn ends(&self) -> [(&str, &str); 2] {
        match self {
            Constraint::Distance {
                body1,
                marker1,
                body2,
                marker2,
                ..
            }
            | Constraint::PointInPlane {
                body1,
                marker1,
                body2,
                marker2,
                ..
            } => [(body1, marker1), (body2, marker2)],
        }
    }

    /// The two ends, to rename them (a scene rewrite).
    pub fn ends_mut(&mut self) -> [(&mut String, &mut String); 2] {
        match self {
            Constraint::Distance {
                body1,
                marker1,
                body2,
                marker2,
                ..
            }
            | Constraint::PointInPlane {
                body1,
                marker1,
                body2,
                marker2,
                ..
            } => [(body1, marker1), (body2, marker2)],
        }
    }
}

impl Scene {
    /// Each constraint in turn (see the module documentation): references, names, values,
    /// and the markers satisfying it at t = 0.
    pub(crate) fn check_constraints(&self) -> Result<(), ModelError> {
        let joints: HashSet<&str> = self.joints.iter().map(|j| j.name.as_str()).collect();
        let mut names = HashSet::new();
        for c in &self.constraints {
            let name = c.name();
            if joints.contains(name) {
                return Err(self.invalid(InvalidValue::new(
                    format!("constraints[{name}].name"),
                    name,
                    "a joint has this name: names are unique among joints and constraints",
                )));
            }
            if !names.insert(name) {
                return Err(self.repeated_name("constraints", name, "constraint"));
            }
            self.check_constraint(c)?;
        }
        Ok(())
    }

    /// One constraint: markers, bodies, values, dimension, and the residual at t = 0.
    fn check_constraint(&self, c: &Constraint) -> Result<(), ModelError> {
        let item = |f: &str| format!("constraints[{}].{f}", c.name());
        let [(body1, marker1), (body2, marker2)] = c.ends();
        self.check_marker(&item("body1"), body1, &item("marker1"), marker1)?;
        self.check_marker(&item("body2"), body2, &item("marker2"), marker2)?;
        if body1 == body2 {
            return Err(self.invalid(InvalidValue::new(
                item("body2"),
                body2,
                "a constraint joins markers of two different bodies",
            )));
        }
        match c {
            Constraint::Distance {
                length: Some(l), ..
            } => self.in_range(LENGTH, &item("length"), *l)?,
            Constraint::Distance { length: None, .. } => {}
            Constraint::PointInPlane { normal, .. } => {
                if self.dim == Dim::Planar {
                    return Err(self.invalid(InvalidValue::new(
                        format!("constraints[{}]", c.name()),
                        "PointInPlane",
                        "a point-in-plane constraint needs a 3D scene (`dim: Spatial`)",
                    )));
                }
                self.axis(&item("normal"), normal)?;
            }
        }
        self.check_constraint_at_start(c)
    }

    /// The markers satisfy the constraint at t = 0 within [`CONSTRAINT_TOLERANCE`]; a
    /// distance left to the start must not be zero (a bar of no length has no direction).
    fn check_constraint_at_start(&self, c: &Constraint) -> Result<(), ModelError> {
        let [(body1, marker1), (body2, marker2)] = c.ends();
        let (Some(p1), Some(p2)) = (
            self.marker_global(body1, marker1),
            self.marker_global(body2, marker2),
        ) else {
            return Ok(()); // names are checked above
        };
        let at = |p: Vector3<f64>| match self.dim {
            Dim::Planar => format!("({:.6}, {:.6})", p.x, p.y),
            Dim::Spatial => format!("({:.6}, {:.6}, {:.6})", p.x, p.y, p.z),
        };
        let both = format!(
            "{body1}.{marker1} at {} and {body2}.{marker2} at {}",
            at(p1),
            at(p2)
        );
        let field = |f: &str| format!("constraints[{}].{f}", c.name());
        let found = (p2 - p1).norm();
        match c {
            Constraint::Distance { length: None, .. } if found <= CONSTRAINT_TOLERANCE => Err(self
                .invalid(InvalidValue::new(
                    field("length"),
                    "None",
                    format!(
                        "{both} coincide at t = 0 (distance {found:.3e} m): give the length, \
                         a distance constraint of zero length is a spherical joint"
                    ),
                ))),
            Constraint::Distance {
                length: Some(l), ..
            } if (found - l).abs() > CONSTRAINT_TOLERANCE => Err(self.invalid(InvalidValue::new(
                field("length"),
                bounds::number(*l),
                format!(
                    "{both} are {found:.9} m apart at t = 0 (off by {:.3e} m, tolerance \
                         {CONSTRAINT_TOLERANCE:e} m): the markers must start at the length",
                    found - l
                ),
            ))),
            Constraint::PointInPlane { normal, .. } => {
                let a1 = self.body_rotation(body1);
                let n = a1 * normal.vec().normalize();
                let off = n.dot(&(p2 - p1));
                if off.abs() <= CONSTRAINT_TOLERANCE {
                    return Ok(());
                }
                Err(self.invalid(InvalidValue::new(
                    field("marker2"),
                    format!("{body2}.{marker2} at {}", at(p2)),
                    format!(
                        "is {off:.3e} m off the plane through {body1}.{marker1} at {} normal to \
                         {:?} (body1 components; tolerance {CONSTRAINT_TOLERANCE:e} m): the \
                         marker must start in the plane",
                        at(p1),
                        normal.0
                    ),
                )))
            }
            Constraint::Distance { .. } => Ok(()),
        }
    }

    /// The length L of a `Distance` constraint: its `length`, or the distance of its
    /// markers at t = 0 (undeformed, ground components); `None` for a `PointInPlane` or an
    /// unknown marker. Every formulation takes its L from here.
    pub fn constraint_length(&self, c: &Constraint) -> Option<f64> {
        let Constraint::Distance { length, .. } = c else {
            return None;
        };
        let [(body1, marker1), (body2, marker2)] = c.ends();
        let p1 = self.marker_global(body1, marker1)?;
        let p2 = self.marker_global(body2, marker2)?;
        Some(length.unwrap_or((p2 - p1).norm()))
    }

    /// The rotation of a body at t = 0 (the identity for the ground or an unknown name).
    pub(crate) fn body_rotation(&self, body: &str) -> nalgebra::Matrix3<f64> {
        self.bodies
            .iter()
            .find(|b| b.name == body)
            .map_or(nalgebra::Matrix3::identity(), |b| b.orientation.matrix())
    }
}
