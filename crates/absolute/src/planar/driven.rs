//! Unit vectors turned by a law: the natural coordinates that a driven angle prescribes
//! (`flexmbd_core::driven`).
//!
//! A body whose basis holds its own unit vector u (point-and-vector) and whose angle to
//! the ground is driven, sin(φ − φ₀ − θ(t)) = 0 with |u|² = 1, has u known at every t:
//! with β the angle of u,
//!
//! ```text
//! β = β₀ ± θ(t),  u = (cos β, sin β),  u̇ = β̇ E u,  ü = β̈ E u − β̇² u
//! ```
//!
//! (E the rotation by π/2; a direction at a node of the body counts as u when the
//! node's rotation is zero in every mode, as at a clamped root). β₀ = ∠ā_g + φ₀ − ∠ā_b when the angle runs from the ground
//! direction ā_g to the body's C(ā_b) u, and ∠ā_g − φ₀ − ∠ā_b, with −θ, when it runs the
//! other way. Those two rows then only prescribe u's two coordinates, which the
//! integrator can leave out of its unknowns: the spin-up beam driven at its hub becomes
//! its modal coordinates alone.

use flexmbd_core::DrivenCoordinates;
use flexmbd_model::MotionLaw;
use nalgebra::Vector2;

use super::Planar;
use super::body::Slot;
use super::constraints::Constraint;

/// A body's unit vector u turned by a law relative to the ground.
pub(super) struct DrivenFrame {
    /// The coordinates of u's x and y components.
    u: [usize; 2],
    /// The rows |u|² − 1 = 0 and sin(φ − φ₀ − θ(t)) = 0.
    rows: [usize; 2],
    /// β₀ and the sign of θ in β = β₀ ± θ(t).
    beta0: f64,
    sign: f64,
    law: MotionLaw,
}

impl Planar {
    /// The unit vectors that a driven angle to the ground prescribes (module documentation).
    pub(super) fn find_driven_frames(&self) -> Vec<DrivenFrame> {
        let mut row = 0;
        let mut unit_rows = Vec::new();
        let mut angles = Vec::new();
        for c in &self.constraints {
            match c {
                Constraint::UnitVector(u) => unit_rows.push((row, u.u)),
                Constraint::Angle(a) => angles.push((row, a)),
                _ => {}
            }
            row += c.rows();
        }
        let angle_of = |v: &Vector2<f64>| v.y.atan2(v.x);
        let mut frames: Vec<DrivenFrame> = Vec::new();
        for (angle_row, a) in angles {
            let (on_body, ground, sign) = match (a.d1.body, a.d2.body) {
                (None, Some(_)) => (&a.d2, &a.d1, 1.0),
                (Some(_), None) => (&a.d1, &a.d2, -1.0),
                _ => continue,
            };
            let Some(b) = on_body.body.map(|k| &self.bodies[k]) else {
                continue;
            };
            // The direction is u itself unless a node's modal rotation turns it (a node of a
            // clamped root has none: its rotation row is zero in every mode).
            let node_turns = on_body
                .node
                .is_some_and(|node| b.rot_row(node).iter().any(|&r| r != 0.0));
            if node_turns {
                continue;
            }
            let (Slot::Q(ux), Slot::Q(uy)) = (b.slots[2], b.slots[3]) else {
                continue;
            };
            // u is the basis's own unit vector: (r0, u) = T x_b leaves it as it is.
            let takes = |r: usize| (0..4).all(|k| b.frame_map[(r, k)] == f64::from(k == r));
            let unit = unit_rows
                .iter()
                .find(|(_, u)| *u == [Slot::Q(ux), Slot::Q(uy)]);
            let (Some(&(unit_row, _)), true) = (unit, takes(2) && takes(3)) else {
                continue;
            };
            if frames.iter().any(|f| f.u == [ux, uy]) {
                continue;
            }
            frames.push(DrivenFrame {
                u: [ux, uy],
                rows: [unit_row, angle_row],
                beta0: angle_of(&ground.abar) + sign * a.phi0 - angle_of(&on_body.abar),
                sign,
                law: a.law.clone(),
            });
        }
        frames
    }

    /// The coordinates and rows of the driven unit vectors, frame by frame (u_x, u_y).
    pub(super) fn driven_declaration(&self) -> Option<DrivenCoordinates> {
        let mut d = DrivenCoordinates::default();
        for f in &self.driven_frames {
            d.coordinates.extend(f.u);
            d.rows.extend(f.rows);
        }
        (!d.coordinates.is_empty()).then_some(d)
    }

    /// (u, u̇, ü) of every driven unit vector's components at t, in the order of
    /// [`driven_declaration`](Self::driven_declaration).
    pub(super) fn driven_frame_motion(&self, t: f64, out: &mut [[f64; 3]]) {
        for (f, out) in self.driven_frames.iter().zip(out.chunks_exact_mut(2)) {
            let (th, thd, thdd) = f.law.eval(t);
            let (beta, rate, accel) = (f.beta0 + f.sign * th, f.sign * thd, f.sign * thdd);
            let (s, c) = beta.sin_cos();
            // u = (c, s), u̇ = β̇ (−s, c), ü = β̈ (−s, c) − β̇² (c, s).
            out[0] = [c, -rate * s, -accel * s - rate * rate * c];
            out[1] = [s, rate * c, accel * c - rate * rate * s];
        }
    }
}
