//! Builders for what a vehicle adds to a scene (issue 13's scene language): nonlinear
//! [`Link`](Force::Link)s, [`Tyre`](Force::Tyre)s on [`Road`]s, marker [`Constraint`]s, and
//! the laws, profiles and sensors they use. Each produces the same value the RON loader
//! produces for the same text; [`SceneBuilder::build`](super::SceneBuilder::build) validates.
//!
//! ```
//! use flexmbd_model::builder::{LinkBuilder, TyreBuilder};
//! use flexmbd_model::{Contact, Force, Law, Profile, Road};
//!
//! // The benchmark's leaf element (docs/scenes.md §2.4): linear about 0.106 m with a bump stop,
//! // acting along the chassis's −z axis.
//! let leaf: Force = LinkBuilder::new("leaf_fl", ("chassis", "E_fl"), ("carrier_fl", "U_fl"))
//!     .spring(Law::piecewise(
//!         vec![0.106],
//!         vec![
//!             Law::polynomial_about(vec![-5242.276, 1.0e7], 0.106),
//!             Law::polynomial_about(vec![-5457.712, 35906.0], 0.1),
//!         ],
//!     ))
//!     .along_axis([0.0, 0.0, -1.0])
//!     .into();
//! assert_eq!(leaf.kind_name(), "Link");
//! let tyre: Force = TyreBuilder::new("tyre_fl", ("carrier_fl", "W_fl"), "left", 0.364325, 4.6e5)
//!     .contact(Contact::ProfileNormal)
//!     .into();
//! let road = Road::new("left", Profile::cosine_bump(0.971, 5.0, 0.2));
//! assert_eq!(road.profile.eval(0.971 + 2.5).0, 0.2);
//! # let _ = tyre;
//! ```

use crate::direction::Direction;
use crate::laws::Law;
use crate::roads::{Contact, Profile, Road};
use crate::scene::{Axis, ElementQuantity, Force, SensorKind, V3};
use crate::scene_constraints::Constraint;

/// Builds a [`Force::Link`]: laws of length and rate between two markers (both `Zero` until
/// set), along the markers or along an axis fixed in the first body.
#[derive(Clone, Debug)]
pub struct LinkBuilder {
    force: Force,
}

impl LinkBuilder {
    /// A link `name` from `first` to `second`, each `(body, marker)`.
    pub fn new(name: &str, first: (&str, &str), second: (&str, &str)) -> Self {
        LinkBuilder {
            force: Force::Link {
                name: name.to_string(),
                body1: first.0.to_string(),
                marker1: first.1.to_string(),
                body2: second.0.to_string(),
                marker2: second.1.to_string(),
                spring: Law::Zero,
                damper: Law::Zero,
                axis: None,
            },
        }
    }

    /// The spring law F(l), tension positive (N).
    pub fn spring(mut self, law: Law) -> Self {
        if let Force::Link { spring, .. } = &mut self.force {
            *spring = law;
        }
        self
    }

    /// The damper law F(l̇), tension positive (N).
    pub fn damper(mut self, law: Law) -> Self {
        if let Force::Link { damper, .. } = &mut self.force {
            *damper = law;
        }
        self
    }

    /// Act along this axis of the first body (its components in that body's frame) rather
    /// than along the line between the markers.
    pub fn along_axis(mut self, direction: [f64; 3]) -> Self {
        if let Force::Link { axis, .. } = &mut self.force {
            *axis = Some(Direction(V3(direction)));
        }
        self
    }
}

impl From<LinkBuilder> for Force {
    fn from(builder: LinkBuilder) -> Force {
        builder.force
    }
}

/// Builds a [`Force::Tyre`]: `Vertical` contact and no lateral damping until set.
#[derive(Clone, Debug)]
pub struct TyreBuilder {
    force: Force,
}

impl TyreBuilder {
    /// The tyre `name` of the wheel centre `(body, marker)` on `road`, with unloaded radius
    /// (m) and radial stiffness (N/m).
    pub fn new(
        name: &str,
        wheel_centre: (&str, &str),
        road: &str,
        radius: f64,
        stiffness: f64,
    ) -> Self {
        TyreBuilder {
            force: Force::Tyre {
                name: name.to_string(),
                body: wheel_centre.0.to_string(),
                marker: wheel_centre.1.to_string(),
                road: road.to_string(),
                radius,
                stiffness,
                contact: Contact::Vertical,
                lateral_damping: 0.0,
            },
        }
    }

    /// The contact model.
    pub fn contact(mut self, model: Contact) -> Self {
        if let Force::Tyre { contact, .. } = &mut self.force {
            *contact = model;
        }
        self
    }

    /// The lateral damper's coefficient c (N·s/m).
    pub fn lateral_damping(mut self, c: f64) -> Self {
        if let Force::Tyre {
            lateral_damping, ..
        } = &mut self.force
        {
            *lateral_damping = c;
        }
        self
    }
}

impl From<TyreBuilder> for Force {
    fn from(builder: TyreBuilder) -> Force {
        builder.force
    }
}

impl Law {
    /// F = Σ c_k x^k.
    pub fn polynomial(coefficients: Vec<f64>) -> Law {
        Law::polynomial_about(coefficients, 0.0)
    }

    /// F = Σ c_k (x − about)^k.
    pub fn polynomial_about(coefficients: Vec<f64>, about: f64) -> Law {
        Law::Polynomial {
            coefficients,
            about,
        }
    }

    /// Piece i on (b_{i−1}, b_i], checked continuous at the breakpoints.
    pub fn piecewise(breakpoints: Vec<f64>, pieces: Vec<Law>) -> Law {
        Law::Piecewise {
            breakpoints,
            pieces,
            continuous: true,
        }
    }

    /// Piecewise linear through (x_i, y_i).
    pub fn table(x: Vec<f64>, y: Vec<f64>) -> Law {
        Law::Table { x, y }
    }
}

impl Road {
    /// A road `name` with `profile`.
    pub fn new(name: &str, profile: Profile) -> Road {
        Road {
            name: name.to_string(),
            profile,
        }
    }
}

impl Profile {
    /// One cosine bump from ground x `start`, `length` long, `height` high (m).
    pub fn cosine_bump(start: f64, length: f64, height: f64) -> Profile {
        Profile::CosineBump {
            start,
            length,
            height,
        }
    }

    /// Piecewise linear through (x_i, z_i); a repeated x is a step.
    pub fn table(x: Vec<f64>, z: Vec<f64>) -> Profile {
        Profile::Table { x, z }
    }
}

impl Constraint {
    /// The distance between two markers held at `length` (m), or at its initial value when
    /// `None`.
    pub fn distance(
        name: &str,
        first: (&str, &str),
        second: (&str, &str),
        length: Option<f64>,
    ) -> Constraint {
        Constraint::Distance {
            name: name.to_string(),
            body1: first.0.to_string(),
            marker1: first.1.to_string(),
            body2: second.0.to_string(),
            marker2: second.1.to_string(),
            length,
        }
    }

    /// The second marker held in the plane through the first with `normal` (components in
    /// the first body's frame).
    pub fn point_in_plane(
        name: &str,
        first: (&str, &str),
        normal: [f64; 3],
        second: (&str, &str),
    ) -> Constraint {
        Constraint::PointInPlane {
            name: name.to_string(),
            body1: first.0.to_string(),
            marker1: first.1.to_string(),
            normal: V3(normal),
            body2: second.0.to_string(),
            marker2: second.1.to_string(),
        }
    }
}

impl SensorKind {
    /// One Cardan angle of the body's rotation since t = 0 (rad).
    pub fn angle(body: &str, axis: Axis) -> Self {
        SensorKind::Angle {
            body: body.to_string(),
            axis,
        }
    }

    /// A force element's tension, or a tyre's normal force (N).
    pub fn element_force(force: &str) -> Self {
        SensorKind::ElementForce {
            force: force.to_string(),
            quantity: ElementQuantity::Force,
        }
    }
}
