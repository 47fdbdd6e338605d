//! The roads the tyres roll on, drawn as strips of ground: a road's profile z = h(x),
//! the same for every y (`flexmbd::model::roads`; docs/methods.md §2.6), is a surface of
//! the ground frame, drawn over the ground x its tyres' wheel centres cover during the run
//! (widened by their spread and four tyre radii on each side, so the road ahead shows) and
//! across the y of its tyres (widened by a tyre radius). The profile is drawn exactly: the
//! strip's edges pass through a table's points (a step as a vertical face) and 32 points
//! of a cosine bump, flat in between where the profile is flat. Only spatial scenes have
//! roads drawn (their z is up).

use flexmbd::core::{BodyPose, Dim};
use flexmbd::model::roads::Profile;
use flexmbd::model::{Force, PreparedScene};
use nalgebra::Vector3;

use crate::shapes::BodyShape;
use crate::springs::End;

/// A road with the tyres on it, and how far their wheel centres have gone.
#[derive(Clone, Debug)]
pub struct RoadStrip {
    /// The road's name.
    pub name: String,
    profile: Profile,
    /// Wheel centres and tyre radii.
    wheels: Vec<(End, f64)>,
    /// The wheel centres' ground x and y, least and greatest over the frames seen.
    x: [f64; 2],
    y: [f64; 2],
    /// The largest spread in x of the wheel centres at one frame.
    spread: f64,
}

impl RoadStrip {
    /// Every road of spatial `prepared` with a tyre whose wheel centre is found.
    pub(crate) fn of(prepared: &PreparedScene) -> Vec<RoadStrip> {
        let scene = prepared.scene();
        if scene.dim != Dim::Spatial {
            return Vec::new();
        }
        scene
            .roads
            .iter()
            .filter_map(|road| {
                let wheels: Vec<_> = scene
                    .forces
                    .iter()
                    .filter_map(|f| match f {
                        Force::Tyre {
                            body,
                            marker,
                            road: on,
                            radius,
                            ..
                        } if *on == road.name => {
                            Some((End::find(prepared, body, marker)?, *radius))
                        }
                        _ => None,
                    })
                    .collect();
                (!wheels.is_empty()).then(|| RoadStrip {
                    name: road.name.clone(),
                    profile: road.profile.clone(),
                    wheels,
                    x: [f64::INFINITY, f64::NEG_INFINITY],
                    y: [f64::INFINITY, f64::NEG_INFINITY],
                    spread: 0.0,
                })
            })
            .collect()
    }

    /// Widen the extents by the wheel centres at a frame of `poses`.
    pub(crate) fn observe(&mut self, prepared: &PreparedScene, poses: &[BodyPose]) {
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        for (wheel, _) in &self.wheels {
            let w = wheel.at(prepared, poses);
            (low, high) = (low.min(w.x), high.max(w.x));
            self.y = [self.y[0].min(w.y), self.y[1].max(w.y)];
        }
        self.x = [self.x[0].min(low), self.x[1].max(high)];
        self.spread = self.spread.max(high - low);
    }

    /// The profile's points (x, z) from `x0` to `x1`: the ends, a table's points between
    /// them (both heights of a step), 33 points across a cosine bump.
    fn profile(&self, x0: f64, x1: f64) -> Vec<(f64, f64)> {
        let h = |x: f64| self.profile.eval(x).0;
        let inner: Vec<(f64, f64)> = match &self.profile {
            Profile::Flat => Vec::new(),
            &Profile::CosineBump { start, length, .. } => (0..=32)
                .map(|k| start + length * k as f64 / 32.0)
                .map(|x| (x, h(x)))
                .collect(),
            Profile::Table { x, z } => x.iter().copied().zip(z.iter().copied()).collect(),
        };
        let mut points = vec![(x0, h(x0))];
        points.extend(inner.into_iter().filter(|&(x, _)| x > x0 && x < x1));
        points.push((x1, h(x1)));
        points
    }

    /// The strip's mesh in ground components (empty before any frame was seen): a flat
    /// quadrilateral per segment of the profile, its normal (−Δz, 0, Δx) normalised.
    pub fn shape(&self) -> BodyShape {
        let mut shape = BodyShape {
            name: self.name.clone(),
            ..BodyShape::default()
        };
        if !(self.x[0].is_finite() && self.x[1].is_finite()) {
            return shape;
        }
        let radius = self.wheels.iter().map(|w| w.1).fold(0.0, f64::max);
        let margin = self.spread + 4.0 * radius;
        let (y0, y1) = (self.y[0] - radius, self.y[1] + radius);
        let points = self.profile(self.x[0] - margin, self.x[1] + margin);
        for pair in points.windows(2) {
            let [(xa, za), (xb, zb)] = [pair[0], pair[1]];
            let Some(normal) = Vector3::new(za - zb, 0.0, xb - xa).try_normalize(0.0) else {
                continue; // a repeated point
            };
            let first = shape.positions.len() as u32;
            for p in [[xa, y0, za], [xb, y0, zb], [xb, y1, zb], [xa, y1, za]] {
                shape.positions.push(Vector3::from(p));
                shape.normals.push(normal);
            }
            shape.triangles.push([first, first + 1, first + 2]);
            shape.triangles.push([first, first + 2, first + 3]);
        }
        shape
    }
}
