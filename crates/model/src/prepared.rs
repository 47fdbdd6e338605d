//! The prepared scene: the stage between a [`Scene`] and a formulation.
//!
//! [`PreparedScene::new`] does, once and for every formulation alike, everything that
//! depends on the scene but not on the coordinates it will be run in:
//!
//! 1. validation (names, references, values; errors name the file and the field);
//! 2. the scene-wide initial velocity handed to the bodies ([`Scene::with_initial_velocity`]),
//!    and the scene rewrites of the stiffening method ([`crate::rewrite`]: FNL2's axial basis,
//!    FS0 without axial modes, substructuring);
//! 3. the auxiliary marker P1 + a added to body1 of each link along a body-fixed axis a
//!    (`crate::force_elements::Link`: the axis as the difference of two body points);
//! 4. every body reduced (FE preprocessing, Craig–Bampton) and built for run time, with its
//!    elastic model installed and, for FS0, its shortening data ([`PreparedBody`]);
//! 5. every name resolved into a typed id: [`BodyId`], [`MarkerId`], [`JointId`];
//! 6. the inputs compiled ([`crate::inputs::InputTable`]): the axis points of each load on a
//!    rigid body added to it, and each driver with an input given the law that reads it
//!    ([`MotionLaw::Input`]).
//!
//! A formulation takes a `&PreparedScene`, never a `Scene`: it cannot be handed a scene
//! whose stiffening rewrite was skipped, since the only way to make a `PreparedScene` is
//! [`PreparedScene::new`].

use std::borrow::Cow;

use crate::bodies::PreparedBody;
use crate::error::ModelError;
use crate::inputs::{DriverInput, InputTable};
use crate::rewrite::rewrite_for_stiffening;
use crate::scene::{Axis, ElementQuantity, GROUND, MotionLaw, Scene, SensorKind};

/// A body of the prepared scene: its index in [`PreparedScene::bodies`] (and in the
/// prepared scene's `bodies`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId(pub usize);

/// A joint of the prepared scene: its index in the prepared scene's `joints`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct JointId(pub usize);

/// A marker: a ground marker (`body: None`, index in `Scene::ground`) or a marker of a body
/// (index in that body's `markers`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MarkerId {
    /// The body, `None` for the ground.
    pub body: Option<BodyId>,
    /// Index in the body's (or the ground's) marker list.
    pub index: usize,
}

/// The two markers a joint, a two-point force element or a constraint connects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MarkerPair {
    /// Marker on the first body (`body1`, `marker1`).
    pub first: MarkerId,
    /// Marker on the second body (`body2`, `marker2`).
    pub second: MarkerId,
}

/// What a sensor measures, with its names resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SensorTarget {
    /// A marker's position component (m), in the ground or in `frame`'s body frame.
    Position {
        /// The marker.
        marker: MarkerId,
        /// The component.
        component: Axis,
        /// Body whose frame the component is taken in (`None`: ground).
        frame: Option<BodyId>,
    },
    /// A marker's velocity component (m/s), in ground axes or in `frame`'s body axes.
    Velocity {
        /// The marker.
        marker: MarkerId,
        /// The component.
        component: Axis,
        /// Body whose axes the component is taken in (`None`: ground).
        frame: Option<BodyId>,
    },
    /// A joint coordinate relative to its value at t = 0 (rad or m).
    JointCoordinate(JointId),
    /// A modal coordinate of a body.
    Modal {
        /// The body.
        body: BodyId,
        /// Mode index (static modes first).
        index: usize,
    },
    /// Total mechanical energy (J).
    Energy,
    /// One intrinsic Cardan angle of a body's rotation R = A(t) A(0)ᵀ since t = 0 (rad).
    Angle {
        /// The body.
        body: BodyId,
        /// Which angle: X (first), Y (second), Z (third).
        axis: Axis,
        /// A(0): the orientation the scene gives the body.
        reference: nalgebra::Matrix3<f64>,
    },
    /// The largest stress over a node set of a solid body: the set's stress shapes are
    /// [`PreparedScene::stress_set`]`(table)`.
    Stress {
        /// The body.
        body: BodyId,
        /// Index of the set's stress shapes in the prepared scene.
        table: usize,
        /// What to report.
        quantity: crate::scene::StressQuantity,
    },
    /// The force or moment the rest of the system exerts on a body at one of its markers
    /// ([`crate::interface_force`]).
    InterfaceForce {
        /// The marker (on a moving body).
        marker: MarkerId,
        /// The component.
        component: Axis,
        /// Force or moment.
        quantity: crate::scene::InterfaceQuantity,
        /// Body whose axes the component is taken in (`None`: ground).
        frame: Option<BodyId>,
    },
    /// A force element's tension or normal force, or its length.
    ElementForce {
        /// Its index in the prepared scene's `forces`.
        element: usize,
        /// What to report.
        quantity: ElementQuantity,
    },
}

/// A scene ready for a formulation (see the module documentation).
#[derive(Clone, Debug)]
pub struct PreparedScene {
    scene: Scene,
    bodies: Vec<PreparedBody>,
    joints: Vec<MarkerPair>,
    forces: Vec<MarkerPair>,
    constraints: Vec<MarkerPair>,
    force_axes: Vec<Option<MarkerId>>,
    load_axes: Vec<Vec<MarkerId>>,
    drivers: Vec<JointId>,
    sensors: Vec<SensorTarget>,
    stress_sets: Vec<crate::stress::StressSet>,
    sensor_offsets: Vec<f64>,
    inputs: InputTable,
}

impl PreparedScene {
    /// Validate `scene`, rewrite it for its stiffening method, reduce and build its bodies,
    /// and resolve its names.
    pub fn new(scene: &Scene) -> Result<PreparedScene, ModelError> {
        scene.validate()?;
        let moving = scene.with_initial_velocity();
        let scene = match rewrite_for_stiffening(&moving)? {
            Cow::Borrowed(s) => s.clone(),
            Cow::Owned(s) => s,
        };
        let (scene, axis_markers) = crate::force_elements::add_axis_markers(scene);
        let (mut scene, load_axis_markers) = crate::force_elements::add_load_axis_markers(scene);
        let inputs = InputTable::new(&scene);
        for (k, driver) in scene.drivers.iter_mut().enumerate() {
            if let Some(slots) = inputs.driver_slots(k) {
                let law = std::mem::replace(&mut driver.law, MotionLaw::Locked);
                driver.law = MotionLaw::Input(DriverInput {
                    law: std::sync::Arc::new(law),
                    slots,
                });
            }
        }
        let bodies = scene.prepare_bodies()?;
        let joints = scene
            .joints
            .iter()
            .map(|j| scene.marker_pair(&j.body1, &j.marker1, &j.body2, &j.marker2))
            .collect::<Result<_, _>>()?;
        let forces = scene
            .forces
            .iter()
            .map(|f| {
                let [(body1, marker1), (body2, marker2)] = f.ends();
                scene.marker_pair(body1, marker1, body2, marker2)
            })
            .collect::<Result<_, _>>()?;
        let constraints = scene
            .constraints
            .iter()
            .map(|c| {
                let [(body1, marker1), (body2, marker2)] = c.ends();
                scene.marker_pair(body1, marker1, body2, marker2)
            })
            .collect::<Result<_, _>>()?;
        let force_axes = axis_markers
            .iter()
            .map(|m| m.as_ref().map(|(b, m)| scene.marker_id(b, m)).transpose())
            .collect::<Result<_, _>>()?;
        let load_axes = load_axis_markers
            .iter()
            .map(|points| points.iter().map(|(b, m)| scene.marker_id(b, m)).collect())
            .collect::<Result<_, _>>()?;
        let drivers = scene
            .drivers
            .iter()
            .map(|d| scene.joint_id(&d.joint))
            .collect::<Result<_, _>>()?;
        let mut sensors: Vec<SensorTarget> = scene
            .sensors
            .iter()
            .map(|s| scene.sensor_target(&s.kind))
            .collect::<Result<_, _>>()?;
        let stress_sets = crate::stress::stress_sets(&scene, &bodies, &mut sensors)?;
        let sensor_offsets = scene.sensor_offsets();
        Ok(PreparedScene {
            scene,
            bodies,
            joints,
            forces,
            constraints,
            force_axes,
            load_axes,
            drivers,
            sensors,
            stress_sets,
            sensor_offsets,
            inputs,
        })
    }

    /// The scene as prepared: after the stiffening rewrite (a substructured beam is several
    /// bodies here, FNL2's beams carry their axial static modes).
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The prepared bodies, in the order of the prepared scene's `bodies`.
    pub fn bodies(&self) -> &[PreparedBody] {
        &self.bodies
    }

    /// One prepared body.
    pub fn body(&self, id: BodyId) -> &PreparedBody {
        &self.bodies[id.0]
    }

    /// The markers of each joint, in the order of the prepared scene's `joints`.
    pub fn joint_markers(&self) -> &[MarkerPair] {
        &self.joints
    }

    /// The markers of each force element, in the order of the prepared scene's `forces`.
    pub fn force_markers(&self) -> &[MarkerPair] {
        &self.forces
    }

    /// The markers of each constraint, in the order of the prepared scene's `constraints`.
    pub fn constraint_markers(&self) -> &[MarkerPair] {
        &self.constraints
    }

    /// Per force element, the auxiliary marker P1 + a of a link along a body1-fixed axis a
    /// (added to body1 by [`PreparedScene::new`]), `None` for the others.
    pub fn force_axis_markers(&self) -> &[Option<MarkerId>] {
        &self.force_axes
    }

    /// Per force element, the axis points P + e_k of a load on a rigid body (added to the
    /// body by [`PreparedScene::new`], `crate::force_elements::Load`), empty for the others.
    pub fn load_axis_markers(&self) -> &[Vec<MarkerId>] {
        &self.load_axes
    }

    /// Every marker the force elements use, the auxiliary axis markers included.
    pub fn force_marker_ids(&self) -> impl Iterator<Item = MarkerId> + '_ {
        self.forces
            .iter()
            .flat_map(|pair| [pair.first, pair.second])
            .chain(self.force_axes.iter().flatten().copied())
            .chain(self.load_axes.iter().flatten().copied())
    }

    /// The scene's inputs, compiled, with the shared table of their values
    /// ([`crate::inputs`]): the force elements and drivers read it, a simulation sets it.
    pub fn inputs(&self) -> &InputTable {
        &self.inputs
    }

    /// The driven joint of each driver, in the order of the prepared scene's `drivers`.
    pub fn driver_joints(&self) -> &[JointId] {
        &self.drivers
    }

    /// The stress shapes of a `Stress` sensor's node set ([`SensorTarget::Stress`]).
    pub fn stress_set(&self, table: usize) -> &crate::stress::StressSet {
        &self.stress_sets[table]
    }

    /// What each sensor measures, in the order of the prepared scene's `sensors`.
    pub fn sensor_targets(&self) -> &[SensorTarget] {
        &self.sensors
    }

    /// Per sensor, the value to subtract from what a formulation reports: the undeformed
    /// position component for `displacement` sensors, 0 otherwise.
    pub fn sensor_offsets(&self) -> &[f64] {
        &self.sensor_offsets
    }

    /// The id of a body by name (`None` for the ground or an unknown name).
    pub fn body_id(&self, name: &str) -> Option<BodyId> {
        self.scene.body_index(name).map(BodyId)
    }

    /// A marker's position in its body's frame (ground markers: ground components), m.
    pub fn marker_position(&self, marker: MarkerId) -> nalgebra::Vector3<f64> {
        match marker.body {
            None => self.scene.ground[marker.index].position.vec(),
            Some(b) => self.scene.bodies[b.0].markers[marker.index].position.vec(),
        }
    }
}

impl Scene {
    fn body_index(&self, name: &str) -> Option<usize> {
        if name == GROUND {
            return None;
        }
        self.bodies.iter().position(|b| b.name == name)
    }

    fn marker_id(&self, body: &str, marker: &str) -> Result<MarkerId, ModelError> {
        let (id, list) = if body == GROUND {
            (None, &self.ground)
        } else {
            let k = self
                .body_index(body)
                .ok_or_else(|| self.missing(format!("marker `{marker}`"), "body", body))?;
            (Some(BodyId(k)), &self.bodies[k].markers)
        };
        let index = list
            .iter()
            .position(|m| m.name == marker)
            .ok_or_else(|| self.missing(format!("body `{body}`"), "marker", marker))?;
        Ok(MarkerId { body: id, index })
    }

    fn marker_pair(
        &self,
        body1: &str,
        marker1: &str,
        body2: &str,
        marker2: &str,
    ) -> Result<MarkerPair, ModelError> {
        Ok(MarkerPair {
            first: self.marker_id(body1, marker1)?,
            second: self.marker_id(body2, marker2)?,
        })
    }

    fn joint_id(&self, name: &str) -> Result<JointId, ModelError> {
        self.joints
            .iter()
            .position(|j| j.name == name)
            .map(JointId)
            .ok_or_else(|| self.missing("a driver".into(), "joint", name))
    }

    fn frame_id(&self, frame: &Option<String>) -> Result<Option<BodyId>, ModelError> {
        match frame.as_deref() {
            None | Some(GROUND) => Ok(None),
            Some(name) => self
                .body_index(name)
                .map(|k| Some(BodyId(k)))
                .ok_or_else(|| self.missing("a sensor frame".into(), "body", name)),
        }
    }

    fn sensor_target(&self, kind: &SensorKind) -> Result<SensorTarget, ModelError> {
        Ok(match kind {
            SensorKind::Position {
                body,
                marker,
                component,
                frame,
            } => SensorTarget::Position {
                marker: self.marker_id(body, marker)?,
                component: *component,
                frame: self.frame_id(frame)?,
            },
            SensorKind::Velocity {
                body,
                marker,
                component,
                frame,
            } => SensorTarget::Velocity {
                marker: self.marker_id(body, marker)?,
                component: *component,
                frame: self.frame_id(frame)?,
            },
            SensorKind::JointCoordinate { joint } => {
                SensorTarget::JointCoordinate(self.joint_id(joint)?)
            }
            SensorKind::Modal { body, index } => SensorTarget::Modal {
                body: self
                    .body_index(body)
                    .map(BodyId)
                    .ok_or_else(|| self.missing("a modal sensor".into(), "body", body))?,
                index: *index,
            },
            SensorKind::Energy => SensorTarget::Energy,
            SensorKind::Angle { body, axis } => {
                let k = self
                    .body_index(body)
                    .ok_or_else(|| self.missing("an angle sensor".into(), "body", body))?;
                SensorTarget::Angle {
                    body: BodyId(k),
                    axis: *axis,
                    reference: self.bodies[k].orientation.matrix(),
                }
            }
            SensorKind::Stress { body, quantity, .. } => SensorTarget::Stress {
                body: self
                    .body_index(body)
                    .map(BodyId)
                    .ok_or_else(|| self.missing("a stress sensor".into(), "body", body))?,
                // Filled in by crate::stress::stress_sets once the bodies are prepared.
                table: usize::MAX,
                quantity: *quantity,
            },
            SensorKind::InterfaceForce {
                body,
                marker,
                component,
                quantity,
                frame,
            } => SensorTarget::InterfaceForce {
                marker: self.marker_id(body, marker)?,
                component: *component,
                quantity: *quantity,
                frame: self.frame_id(frame)?,
            },
            SensorKind::ElementForce { force, quantity } => SensorTarget::ElementForce {
                element: self
                    .forces
                    .iter()
                    .position(|f| f.name() == force)
                    .ok_or_else(|| {
                        self.missing("an element-force sensor".into(), "force element", force)
                    })?,
                quantity: *quantity,
            },
        })
    }
}
