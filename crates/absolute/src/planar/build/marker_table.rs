//! The scene's marker table: every marker (ground markers first, then
//! each body's in order) under one global index, with its initial position.

use flexmbd_model::{GROUND, MarkerId, Scene};
use nalgebra::{Matrix2, Vector2};

/// A body's frame at t = 0.
#[derive(Clone, Copy, Debug)]
pub(super) struct InitialFrame {
    /// Origin (m, ground components).
    pub(super) origin: Vector2<f64>,
    /// Angle of the body x axis from the ground x axis (rad).
    pub(super) angle: f64,
}

impl InitialFrame {
    /// The rotation [[cos, −sin], [sin, cos]] of the frame.
    pub(super) fn rotation(&self) -> Matrix2<f64> {
        let (s, c) = self.angle.sin_cos();
        Matrix2::new(c, -s, s, c)
    }
}

/// Every marker of the scene under a global index.
pub(super) struct MarkerTable {
    /// (body, or `None` for the ground; index within it) of each global marker.
    pub(super) owner: Vec<(Option<usize>, usize)>,
    /// Ground markers: ground position; body markers: position in the body frame (m).
    pub(super) position: Vec<Vector2<f64>>,
    /// Global index of each body's first marker.
    pub(super) first_of_body: Vec<usize>,
    /// Each body's frame at t = 0.
    pub(super) frames: Vec<InitialFrame>,
}

impl MarkerTable {
    pub(super) fn new(scene: &Scene) -> MarkerTable {
        let mut owner = Vec::new();
        let mut position = Vec::new();
        for (k, m) in scene.ground.iter().enumerate() {
            owner.push((None, k));
            position.push(Vector2::new(m.position.0[0], m.position.0[1]));
        }
        let mut first_of_body = Vec::new();
        for (b, body) in scene.bodies.iter().enumerate() {
            first_of_body.push(owner.len());
            for (k, m) in body.markers.iter().enumerate() {
                owner.push((Some(b), k));
                position.push(Vector2::new(m.position.0[0], m.position.0[1]));
            }
        }
        let frames = scene
            .bodies
            .iter()
            .map(|b| {
                let a = b.orientation.matrix();
                InitialFrame {
                    origin: Vector2::new(b.origin.0[0], b.origin.0[1]),
                    angle: a[(1, 0)].atan2(a[(0, 0)]),
                }
            })
            .collect();
        MarkerTable {
            owner,
            position,
            first_of_body,
            frames,
        }
    }

    /// Number of markers.
    pub(super) fn len(&self) -> usize {
        self.owner.len()
    }

    /// The global index of a marker of the prepared scene.
    pub(super) fn global(&self, marker: MarkerId) -> usize {
        match marker.body {
            None => marker.index,
            Some(b) => self.first_of_body[b.0] + marker.index,
        }
    }

    /// The initial position of a marker, ground components (m).
    pub(super) fn global_position(&self, global: usize) -> Vector2<f64> {
        match self.owner[global] {
            (None, _) => self.position[global],
            (Some(b), _) => {
                let frame = self.frames[b];
                frame.origin + frame.rotation() * self.position[global]
            }
        }
    }

    /// The name `body.marker` of a marker, for messages.
    pub(super) fn name<'a>(&self, scene: &'a Scene, global: usize) -> (&'a str, &'a str) {
        match self.owner[global] {
            (None, k) => (GROUND, scene.ground[k].name.as_str()),
            (Some(b), k) => (
                scene.bodies[b].name.as_str(),
                scene.bodies[b].markers[k].name.as_str(),
            ),
        }
    }
}
