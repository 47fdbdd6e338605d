//! The scene's sensors: what each named output column measures (positions, velocities,
//! joint coordinates, modal coordinates, energy, angles, stresses, force elements' and
//! interfaces' forces). Part of the scene format ([`crate::scene`]), kept apart so that
//! the scene's bodies, joints and solver settings and its outputs each read as one idea.

use serde::{Deserialize, Serialize};

use crate::scene::Axis;

/// A named output, one CSV column.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sensor {
    /// Column name.
    pub name: String,
    /// What it measures.
    pub kind: SensorKind,
    /// For a `Position` sensor: report the displacement, the position minus the marker's
    /// undeformed position in the same frame (from the bodies' placements at t = 0), e.g.
    /// the tip displacement of a beam in its own turning frame. Applied by
    /// `flexmbd::simulation` to every formulation alike.
    #[serde(default)]
    pub displacement: bool,
}

/// What a sensor measures.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum SensorKind {
    /// A marker's position (m): ground components, or components in `frame`'s body frame
    /// relative to its origin.
    Position {
        /// Body of the marker.
        body: String,
        /// The marker.
        marker: String,
        /// Component.
        component: Axis,
        /// Body whose frame the components are taken in (`None`: ground).
        #[serde(default)]
        frame: Option<String>,
    },
    /// A marker's velocity (m/s), components as for `Position`.
    Velocity {
        /// Body of the marker.
        body: String,
        /// The marker.
        marker: String,
        /// Component.
        component: Axis,
        /// Body whose axes the components are taken in (`None`: ground).
        #[serde(default)]
        frame: Option<String>,
    },
    /// A joint coordinate (rad or m), relative to its value at t = 0.
    JointCoordinate {
        /// The joint.
        joint: String,
    },
    /// A modal coordinate of a flexible body.
    Modal {
        /// The body.
        body: String,
        /// Mode index (0-based, static modes first).
        index: usize,
    },
    /// Total mechanical energy (J): kinetic + gravity + elastic + force elements.
    Energy,
    /// One intrinsic Cardan angle (x, y′, z″) of the body's rotation since t = 0,
    /// R = A(t) A(0)ᵀ, A(0) the orientation the scene gives the body (rad; X and Z in
    /// (−π, π], Y in [−π/2, π/2]; about +y positive nose down).
    Angle {
        /// The body.
        body: String,
        /// Which angle: X (first, about x), Y (second, about y′), Z (third, about z″).
        axis: Axis,
    },
    /// The largest von Mises stress (or largest principal stress, or stress component) over
    /// a node set of a flexible body
    /// whose K and M the built-in solid elements assembled (`source: Solid`; Pa): the
    /// modal stress shapes (`flexmbd_fe::solid::stress`, nodal averages) times the body's
    /// modal coordinates, the elastic stress of the linear theory.
    Stress {
        /// The body.
        body: String,
        /// A node set of its mesh (a Gmsh physical group), case-insensitive.
        nodes: String,
        /// What to report (`VonMises` when omitted).
        #[serde(default)]
        quantity: StressQuantity,
    },
    /// A force element's tension (SpringDamper, Link; N) or normal force (Tyre, ≥ 0; N), or
    /// with `quantity: Length` its length l (m; a tyre: its deflection δ).
    ElementForce {
        /// The force element.
        force: String,
        /// What to report (`Force` when omitted).
        #[serde(default)]
        quantity: ElementQuantity,
    },
    /// The force (N) or moment (N·m, about the marker's current point) that the rest of the
    /// system exerts on a moving body at one of its markers, through every joint, scene
    /// constraint and force element attached there: a bearing's force on a rotor, a pin's
    /// force on a link (`flexmbd_model::interface_force`). Ground components, or components
    /// in `frame`'s body axes.
    InterfaceForce {
        /// The body the force acts on.
        body: String,
        /// Its marker (an interface marker of an imported or solid body, or any marker).
        marker: String,
        /// Component.
        component: Axis,
        /// `Force` (N) or `Moment` (N·m); `Force` when omitted.
        #[serde(default)]
        quantity: InterfaceQuantity,
        /// Body whose axes the components are taken in (`None`: ground).
        #[serde(default)]
        frame: Option<String>,
    },
}

/// What an `InterfaceForce` sensor reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum InterfaceQuantity {
    /// The force on the body (N).
    #[default]
    Force,
    /// The moment on the body about the marker's current point (N·m).
    Moment,
}

/// What a `Stress` sensor reports at each node of its set (the largest over the set).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum StressQuantity {
    /// The von Mises stress (Pa).
    #[default]
    VonMises,
    /// The largest principal stress (Pa).
    MaxPrincipal,
    /// The largest σ_xx over the set (Pa, body axes; so for the other components).
    Sxx,
    /// σ_yy.
    Syy,
    /// σ_zz.
    Szz,
    /// τ_xy.
    Sxy,
    /// τ_yz.
    Syz,
    /// τ_zx.
    Szx,
}

impl StressQuantity {
    /// For a component, its index in (σ_xx, σ_yy, σ_zz, τ_xy, τ_yz, τ_zx).
    pub fn component(self) -> Option<usize> {
        match self {
            StressQuantity::VonMises | StressQuantity::MaxPrincipal => None,
            StressQuantity::Sxx => Some(0),
            StressQuantity::Syy => Some(1),
            StressQuantity::Szz => Some(2),
            StressQuantity::Sxy => Some(3),
            StressQuantity::Syz => Some(4),
            StressQuantity::Szx => Some(5),
        }
    }
}

/// What an `ElementForce` sensor reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ElementQuantity {
    /// The tension (N) or a tyre's normal force.
    #[default]
    Force,
    /// The length l (m) the element's laws are evaluated at; a tyre's deflection δ (m).
    Length,
}

impl SensorKind {
    /// The marker a Position, Velocity or InterfaceForce sensor reads, (body, marker), and the
    /// body whose frame its components are taken in (`None`: ground); `None` for the other
    /// kinds.
    pub fn marker(&self) -> Option<(&str, &str, Option<&str>)> {
        match self {
            SensorKind::Position {
                body,
                marker,
                frame,
                ..
            }
            | SensorKind::Velocity {
                body,
                marker,
                frame,
                ..
            }
            | SensorKind::InterfaceForce {
                body,
                marker,
                frame,
                ..
            } => Some((body, marker, frame.as_deref())),
            _ => None,
        }
    }

    /// The same, to rename them (a scene rewrite).
    pub fn marker_mut(&mut self) -> Option<(&mut String, &mut String, &mut Option<String>)> {
        match self {
            SensorKind::Position {
                body,
                marker,
                frame,
                ..
            }
            | SensorKind::Velocity {
                body,
                marker,
                frame,
                ..
            }
            | SensorKind::InterfaceForce {
                body,
                marker,
                frame,
                ..
            } => Some((body, marker, frame)),
            _ => None,
        }
    }
}
