//! Springs and links (`SpringDamper`, `Link`) drawn as thin cylinders between their two
//! markers: each end's position at a frame is r0 + A (r̄ + X^t y) on its body (r̄ the
//! marker, X^t the rows of the FE node it sits on in a flexible body), or the ground
//! marker's; the glTF node of a spring is then placed at end 1, turned so that its y axis
//! points to end 2, and scaled along y to their distance.

use flexmbd::core::BodyPose;
use flexmbd::model::{Force, PreparedScene};
use nalgebra::Vector3;

/// One end of a spring (or a tyre's wheel centre): the body it is on (`None`: the ground),
/// the marker's position in that body's frame (ground components on the ground), and the
/// FE node it sits on.
#[derive(Clone, Debug)]
pub(crate) struct End {
    body: Option<usize>,
    local: Vector3<f64>,
    node: Option<usize>,
}

impl End {
    /// Marker `marker` of body `body` (`"ground"`: a ground marker) of `prepared`, if found.
    pub(crate) fn find(prepared: &PreparedScene, body: &str, marker: &str) -> Option<End> {
        let scene = prepared.scene();
        if body == "ground" {
            let m = scene.ground.iter().find(|m| m.name == marker)?;
            return Some(End {
                body: None,
                local: m.position.vec(),
                node: None,
            });
        }
        let b = scene.bodies.iter().position(|b| b.name == body)?;
        let local = scene.bodies[b]
            .markers
            .iter()
            .find(|m| m.name == marker)?
            .position
            .vec();
        let prepared_body = prepared.bodies().iter().position(|p| p.index == b)?;
        let node = prepared.bodies()[prepared_body].nodes.node_at(&local, 1e-9);
        Some(End {
            body: Some(prepared_body),
            local,
            node,
        })
    }

    /// Its position (m, ground components) at a frame of `poses`.
    pub(crate) fn at(&self, prepared: &PreparedScene, poses: &[BodyPose]) -> Vector3<f64> {
        match self.body {
            None => self.local,
            Some(b) => {
                let pose = &poses[b];
                let mut r = self.local;
                if let Some(n) = self.node {
                    let nodes = &prepared.bodies()[b].nodes;
                    for (j, y) in pose.modes.iter().enumerate() {
                        r += Vector3::from_fn(|a, _| nodes.translation_entry(n, a, j)) * *y;
                    }
                }
                pose.origin + pose.rotation * r
            }
        }
    }
}

/// A spring or link of the prepared scene, located by its ends.
#[derive(Clone, Debug)]
pub struct Spring {
    /// Its name.
    pub name: String,
    ends: [End; 2],
}

impl Spring {
    /// Every spring-damper and link of `prepared` whose ends are found.
    pub fn of(prepared: &PreparedScene) -> Vec<Spring> {
        let end = |(body, marker): (&str, &str)| End::find(prepared, body, marker);
        prepared
            .scene()
            .forces
            .iter()
            .filter_map(|f| match f {
                Force::SpringDamper { name, .. } | Force::Link { name, .. } => {
                    let [a, b] = f.ends();
                    Some(Spring {
                        name: name.clone(),
                        ends: [end(a)?, end(b)?],
                    })
                }
                _ => None,
            })
            .collect()
    }

    /// The positions of its two ends (m, ground components) at a frame of `poses`.
    pub fn at(&self, prepared: &PreparedScene, poses: &[BodyPose]) -> [Vector3<f64>; 2] {
        [0, 1].map(|k| self.ends[k].at(prepared, poses))
    }
}
