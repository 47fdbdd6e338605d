//! Bodies turned by a law about a ground axis: the natural coordinates that a driven revolute
//! to the ground prescribes (`flexmbd_core::driven`).
//!
//! A revolute between the ground and body b, driven by θ(t) (`joints.rs`: the point
//! coincidence r_P = p, the two perpendicularities a·n_k = 0 and the angle row, in that
//! order), together with b's six orthonormality rows, leaves b's frame no freedom when its
//! joint terms do not move with its modes (a clamped root: zero modal rows): with R(t) the
//! rotation by s θ(t) about the joint's axis a (ground components),
//!
//! ```text
//! A(t) = R(t) A(0),   r0(t) = p + R(t) (r0(0) − p),
//! ẋ = ω × x,   ẍ = α × x + ω × (ω × x)   for x ∈ {r0 − p, u, v, w},  ω = s θ̇ a,  α = s θ̈ a
//! ```
//!
//! (s = +1 when b is the joint's second body, the angle running from the ground's n₁ to b's;
//! −1 when it is the first). Those twelve rows then only prescribe b's twelve frame
//! coordinates, which the integrator can leave out of its unknowns: the 3D spin-up beam
//! driven at its hub becomes its modal coordinates alone.

use flexmbd_core::DrivenCoordinates;
use flexmbd_model::MotionLaw;
use nalgebra::{DVector, Matrix3, Rotation3, Unit, Vector3};

use super::Spatial;
use super::constraints::{AngleConstraint, Constraint, DotConstraint};
use super::kinematics::{Term, frame_of};

/// A body turned by a law about a ground axis through a ground point.
pub(super) struct DrivenFrame {
    /// Index of its r0 in q (u, v, w follow).
    offset: usize,
    /// The rows its frame's equations hold: orthonormality, coincidence, the two
    /// perpendicularities and the angle.
    rows: Vec<usize>,
    /// The joint's ground point p, its axis a (unit, ground components), r0(0) − p, A(0).
    pivot: Vector3<f64>,
    axis: Unit<Vector3<f64>>,
    arm0: Vector3<f64>,
    frame0: Matrix3<f64>,
    /// s in the rotation by s θ(t).
    sign: f64,
    law: MotionLaw,
}

/// Whether `term` is on the ground or on body `body` with no modal motion (zero modal rows,
/// no foreshortening), so that it moves with b's frame alone.
fn rigid_on(term: &Term, body: usize) -> bool {
    match term.body {
        None => true,
        Some(b) => {
            b == body
                && term.foreshortening_node.is_none()
                && term.modal_rows.iter().all(|&r| r == 0.0)
        }
    }
}

/// A perpendicularity row a·n = 0 whose terms are on the ground or rigid on `body`.
fn perpendicular_on(c: &Constraint, body: usize) -> bool {
    matches!(c, Constraint::Dot(DotConstraint { x, origin: None, z, c0, law: None })
        if *c0 == 0.0 && rigid_on(x, body) && rigid_on(z, body))
}

impl Spatial {
    /// The bodies that a driven revolute to the ground turns (module documentation).
    pub(super) fn find_driven_frames(&self) -> Vec<DrivenFrame> {
        let mut starts = Vec::with_capacity(self.constraints.len());
        let mut row = 0;
        for c in &self.constraints {
            starts.push(row);
            row += c.rows();
        }
        let zero = DVector::zeros(self.coordinates.len());
        let q0 = &self.coordinates.q0;
        let mut frames: Vec<DrivenFrame> = Vec::new();
        for k in 3..self.constraints.len() {
            let Constraint::Angle(AngleConstraint { p1, p2, a, law, .. }) = &self.constraints[k]
            else {
                continue;
            };
            let Constraint::Coincide { point2, point1 } = &self.constraints[k - 3] else {
                continue;
            };
            let (body, ground_point, sign) = match (point1.body, point2.body) {
                (None, Some(b)) if p2.body == Some(b) && p1.body.is_none() => (b, point1, 1.0),
                (Some(b), None) if p1.body == Some(b) && p2.body.is_none() => (b, point2, -1.0),
                _ => continue,
            };
            let rigid = [point1, point2, p1, p2, a]
                .iter()
                .all(|t| rigid_on(t, body))
                && perpendicular_on(&self.constraints[k - 2], body)
                && perpendicular_on(&self.constraints[k - 1], body);
            let offset = self.bodies[body].offset;
            let orthonormality = self.constraints.iter().position(
                |c| matches!(c, Constraint::Orthonormality { offset: o } if *o == offset),
            );
            let (true, Some(o)) = (rigid, orthonormality) else {
                continue;
            };
            if frames.iter().any(|f| f.offset == offset) {
                continue;
            }
            let mut rows: Vec<usize> = (starts[o]..starts[o] + 6).collect();
            rows.extend(starts[k - 3]..starts[k - 3] + 3);
            rows.extend([starts[k - 2], starts[k - 1], starts[k]]);
            let (r0, frame0) = frame_of(q0.as_slice(), offset);
            let pivot = ground_point.undeformed;
            frames.push(DrivenFrame {
                offset,
                rows,
                pivot,
                axis: Unit::new_normalize(a.eval(&self.bodies, q0, &zero).value),
                arm0: r0 - pivot,
                frame0,
                sign,
                law: law.clone(),
            });
        }
        frames
    }

    /// The coordinates and rows of the driven frames, frame by frame ({r0; u; v; w}).
    pub(super) fn driven_declaration(&self) -> Option<DrivenCoordinates> {
        let mut d = DrivenCoordinates::default();
        for f in &self.driven_frames {
            d.coordinates.extend(f.offset..f.offset + 12);
            d.rows.extend(&f.rows);
        }
        (!d.coordinates.is_empty()).then_some(d)
    }

    /// (q, q̇, q̈) of every driven frame's twelve coordinates {r0; u; v; w} at t, in the
    /// order of [`driven_declaration`](Self::driven_declaration).
    pub(super) fn driven_frame_motion(&self, t: f64, out: &mut [[f64; 3]]) {
        for (f, out) in self.driven_frames.iter().zip(out.chunks_exact_mut(12)) {
            let (th, thd, thdd) = f.law.eval(t);
            let rotation = Rotation3::from_axis_angle(&f.axis, f.sign * th);
            let (omega, alpha) = (
                f.axis.into_inner() * (f.sign * thd),
                f.axis.into_inner() * (f.sign * thdd),
            );
            let vectors = [
                f.arm0,
                f.frame0.column(0).into_owned(),
                f.frame0.column(1).into_owned(),
                f.frame0.column(2).into_owned(),
            ];
            for (k, x0) in vectors.iter().enumerate() {
                let x = rotation * x0;
                let rate = omega.cross(&x);
                let accel = alpha.cross(&x) + omega.cross(&rate);
                let value = if k == 0 { f.pivot + x } else { x };
                for c in 0..3 {
                    out[3 * k + c] = [value[c], rate[c], accel[c]];
                }
            }
        }
    }
}
