//! Constraint equations of the planar scene, their Jacobian Φ_q, Φ_t and acceleration bias
//! c = Φ̈|q̈=0 (docs/methods.md §3.1–§3.3).
//!
//! - Distance: |r_j − r_i|² − L² = 0 (two-point bases), bias 2 |ṙ_j − ṙ_i|².
//! - Marker distance (a scene `Distance` constraint): ½(|r_P2 − r_P1|² − L²) = 0, bias
//!   |ṙ_P2 − ṙ_P1|² + (r_P2 − r_P1)·(bias_P2 − bias_P1) (docs/methods.md §3.4).
//! - Unit vector: |u|² − 1 = 0 (point-and-vector bases), bias 2 |u̇|².
//! - Point on a body: r0 + A (r̄_P + X_P y) − r_point = 0 (linear for rigid bodies, bilinear
//!   for flexible ones).
//! - Prismatic slide: (r_P2 − r_P1) × d₁ = 0, or its driver (r_P2 − r_P1) · d₁ − s₀ − s(t) = 0.
//! - Angle: Φ = σ cos θ − κ sin θ = sin(φ − θ) with σ = d₁ × d₂, κ = d₁ · d₂ and
//!   θ = φ₀ + θ(t), never singular at its root; Φ_t = −θ̇ (σ sin θ + κ cos θ).

use flexmbd_core::{Request, State, SystemTerms};
use flexmbd_model::MotionLaw;
use flexmbd_model::constraint_equations::{Motion, distance};
use nalgebra::{DVector, Vector2, Vector3};

use super::Planar;
use super::algebra::{cross, e_mat};
use super::body::{PointSlots, Slot};
use super::kinematics::{Direction, PlanarMarker};

/// A constraint of the planar scene: one equation, or two for a point on a body.
pub(super) enum Constraint {
    Distance(Distance),
    MarkerDistance(MarkerDistance),
    UnitVector(UnitVector),
    PointOnBody(PointOnBody),
    Slide(Slide),
    Angle(Angle),
}

/// |r_b − r_a|² − L² = 0 between the two points of a rigid body's basis.
pub(super) struct Distance {
    pub(super) a: PointSlots,
    pub(super) b: PointSlots,
    /// L² (m²).
    pub(super) length_squared: f64,
}

/// ½(|r_P2 − r_P1|² − L²) = 0 between two markers: a scene `Distance` constraint (the
/// equation of `flexmbd_model::constraint_equations`).
pub(super) struct MarkerDistance {
    pub(super) p1: PlanarMarker,
    pub(super) p2: PlanarMarker,
    /// L (m).
    pub(super) length: f64,
}

/// |u|² − 1 = 0 for a body's own unit vector.
pub(super) struct UnitVector {
    pub(super) u: [Slot; 2],
}

/// r_P(q) − r_point = 0 for a joint point P of a body not in its basis (2 rows).
pub(super) struct PointOnBody {
    pub(super) marker: PlanarMarker,
    pub(super) point: PointSlots,
}

/// Prismatic: (r_P2 − r_P1) × d₁ = 0 (`along` = None), or its driver
/// (r_P2 − r_P1) · d₁ − s₀ − s(t) = 0 (`along` = (s₀, s)).
pub(super) struct Slide {
    pub(super) p1: PlanarMarker,
    pub(super) p2: PlanarMarker,
    pub(super) d1: Direction,
    pub(super) along: Option<(f64, MotionLaw)>,
}

/// sin(φ − φ₀ − θ(t)) = 0 for the angle φ from d₁ to d₂.
pub(super) struct Angle {
    pub(super) d1: Direction,
    pub(super) d2: Direction,
    /// φ₀: the angle at t = 0 (rad).
    pub(super) phi0: f64,
    pub(super) law: MotionLaw,
}

impl Constraint {
    /// Number of equations.
    pub(super) fn rows(&self) -> usize {
        match self {
            Constraint::PointOnBody(_) => 2,
            _ => 1,
        }
    }
}

/// What the constraints are evaluated at, and which terms are requested.
struct Evaluation<'a> {
    t: f64,
    q: &'a DVector<f64>,
    qd: &'a DVector<f64>,
    req: Request,
}

impl Planar {
    /// Φ, Φ_q, Φ_t and the bias, as requested.
    pub(super) fn constraints(&self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        let State { t, q, qd, .. } = state;
        let at = Evaluation { t, q, qd, req };
        let mut row = 0;
        for constraint in &self.constraints {
            match constraint {
                Constraint::Distance(c) => c.evaluate(&at, out, row),
                Constraint::MarkerDistance(c) => c.evaluate(self, &at, out, row),
                Constraint::UnitVector(c) => c.evaluate(&at, out, row),
                Constraint::PointOnBody(c) => c.evaluate(self, &at, out, row),
                Constraint::Slide(c) => c.evaluate(self, &at, out, row),
                Constraint::Angle(c) => c.evaluate(self, &at, out, row),
            }
            row += constraint.rows();
        }
    }
}

impl Distance {
    fn evaluate(&self, at: &Evaluation, out: &mut SystemTerms, row: usize) {
        let (a, b, q, qd, req) = (&self.a, &self.b, at.q, at.qd, at.req);
        let pa = Vector2::new(a.x.get(q), a.y.get(q));
        let pb = Vector2::new(b.x.get(q), b.y.get(q));
        let d = pb - pa;
        if req.constraints {
            out.phi[row] = d.norm_squared() - self.length_squared;
        }
        if req.jacobian {
            for (slot, v) in [
                (a.x, -2.0 * d.x),
                (a.y, -2.0 * d.y),
                (b.x, 2.0 * d.x),
                (b.y, 2.0 * d.y),
            ] {
                if let Slot::Q(i) = slot {
                    out.phi_q[(row, i)] += v;
                }
            }
        }
        if req.accel_term {
            let dd = Vector2::new(b.x.rate(qd) - a.x.rate(qd), b.y.rate(qd) - a.y.rate(qd));
            out.accel_term[row] = 2.0 * dd.norm_squared();
        }
    }
}

impl MarkerDistance {
    fn evaluate(&self, planar: &Planar, at: &Evaluation, out: &mut SystemTerms, row: usize) {
        let (q, req) = (at.q, at.req);
        let motion = |m: &PlanarMarker| {
            let (r, v, bias) = planar.marker_motion(m, q, at.qd);
            let lift = |x: Vector2<f64>| Vector3::new(x.x, x.y, 0.0);
            Motion {
                value: lift(r),
                rate: lift(v),
                bias: lift(bias),
            }
        };
        let d = motion(&self.p2).minus(&motion(&self.p1));
        let equation = distance(&d, self.length);
        if req.constraints {
            out.phi[row] = equation.phi;
        }
        if req.jacobian {
            // ∂Φ/∂d = d.
            let w = Vector2::new(d.value.x, d.value.y);
            let phi_q = &mut out.phi_q;
            planar.marker_columns(&self.p2, q, |i, col| phi_q[(row, i)] += w.dot(&col));
            planar.marker_columns(&self.p1, q, |i, col| phi_q[(row, i)] -= w.dot(&col));
        }
        if req.accel_term {
            out.accel_term[row] = equation.accel_term;
        }
    }
}

impl UnitVector {
    fn evaluate(&self, at: &Evaluation, out: &mut SystemTerms, row: usize) {
        let (u, q, qd, req) = (&self.u, at.q, at.qd, at.req);
        let v = Vector2::new(u[0].get(q), u[1].get(q));
        if req.constraints {
            out.phi[row] = v.norm_squared() - 1.0;
        }
        if req.jacobian {
            for (slot, x) in [(u[0], v.x), (u[1], v.y)] {
                if let Slot::Q(i) = slot {
                    out.phi_q[(row, i)] += 2.0 * x;
                }
            }
        }
        if req.accel_term {
            let vd = Vector2::new(u[0].rate(qd), u[1].rate(qd));
            out.accel_term[row] = 2.0 * vd.norm_squared();
        }
    }
}

impl PointOnBody {
    fn evaluate(&self, planar: &Planar, at: &Evaluation, out: &mut SystemTerms, row: usize) {
        let (marker, point, q, req) = (&self.marker, &self.point, at.q, at.req);
        let (r, _, bias) = planar.marker_motion(marker, q, at.qd);
        if req.constraints {
            let target = Vector2::new(point.x.get(q), point.y.get(q));
            out.phi[row] = r.x - target.x;
            out.phi[row + 1] = r.y - target.y;
        }
        if req.jacobian {
            let phi_q = &mut out.phi_q;
            planar.marker_columns(marker, q, |i, col| {
                phi_q[(row, i)] += col.x;
                phi_q[(row + 1, i)] += col.y;
            });
            for (a, slot) in [point.x, point.y].into_iter().enumerate() {
                if let Slot::Q(i) = slot {
                    out.phi_q[(row + a, i)] -= 1.0;
                }
            }
        }
        if req.accel_term {
            out.accel_term[row] = bias.x;
            out.accel_term[row + 1] = bias.y;
        }
    }
}

impl Slide {
    fn evaluate(&self, planar: &Planar, at: &Evaluation, out: &mut SystemTerms, row: usize) {
        let (q, qd, req) = (at.q, at.qd, at.req);
        let (r1, v1, b1) = planar.marker_motion(&self.p1, q, qd);
        let (r2, v2, b2) = planar.marker_motion(&self.p2, q, qd);
        let (d, dd, db) = planar.direction(&self.d1, q, qd);
        let (x, xd, xb) = (r2 - r1, v2 - v1, b2 - b1);
        let e = e_mat();
        // Φ = x × d (∂/∂x = −E d, ∂/∂d = E x), or x · d − s₀ − s(t).
        let (phi, w_x, w_d, phi_t, bias) = match &self.along {
            None => (
                cross(&x, &d),
                -(e * d),
                e * x,
                0.0,
                cross(&xb, &d) + 2.0 * cross(&xd, &dd) + cross(&x, &db),
            ),
            Some((s0, law)) => {
                let (sv, svd, svdd) = law.eval(at.t);
                (
                    x.dot(&d) - s0 - sv,
                    d,
                    x,
                    -svd,
                    xb.dot(&d) + 2.0 * xd.dot(&dd) + x.dot(&db) - svdd,
                )
            }
        };
        if req.constraints {
            out.phi[row] = phi;
        }
        if req.jacobian {
            let phi_q = &mut out.phi_q;
            planar.marker_columns(&self.p2, q, |i, col| phi_q[(row, i)] += w_x.dot(&col));
            planar.marker_columns(&self.p1, q, |i, col| phi_q[(row, i)] -= w_x.dot(&col));
            planar.add_direction_jacobian(&self.d1, &w_d, q, &mut out.phi_q, row);
            out.phi_t[row] = phi_t;
        }
        if req.accel_term {
            out.accel_term[row] = bias;
        }
    }
}

impl Angle {
    fn evaluate(&self, planar: &Planar, at: &Evaluation, out: &mut SystemTerms, row: usize) {
        let (q, qd, req) = (at.q, at.qd, at.req);
        let (th_l, thd, thdd) = self.law.eval(at.t);
        let th = self.phi0 + th_l;
        let (s, c) = th.sin_cos();
        let (a, ad, a_bias) = planar.direction(&self.d1, q, qd);
        let (bv, bd, b_bias) = planar.direction(&self.d2, q, qd);
        let sigma = cross(&a, &bv);
        let kappa = a.dot(&bv);
        if req.constraints {
            out.phi[row] = sigma * c - kappa * s;
        }
        if req.jacobian {
            // ∂σ/∂a = −E b, ∂σ/∂b = E a; ∂κ/∂a = b, ∂κ/∂b = a.
            let e = e_mat();
            let wa = -(e * bv) * c - bv * s;
            let wb = (e * a) * c - a * s;
            planar.add_direction_jacobian(&self.d1, &wa, q, &mut out.phi_q, row);
            planar.add_direction_jacobian(&self.d2, &wb, q, &mut out.phi_q, row);
            out.phi_t[row] = -thd * (sigma * s + kappa * c);
        }
        if req.accel_term {
            let sigma_d = cross(&ad, &bv) + cross(&a, &bd);
            let kappa_d = ad.dot(&bv) + a.dot(&bd);
            let sigma_b = 2.0 * cross(&ad, &bd) + cross(&a_bias, &bv) + cross(&a, &b_bias);
            let kappa_b = 2.0 * ad.dot(&bd) + a_bias.dot(&bv) + a.dot(&b_bias);
            out.accel_term[row] = sigma_b * c
                - kappa_b * s
                - 2.0 * thd * (sigma_d * s + kappa_d * c)
                - thdd * (sigma * s + kappa * c)
                - thd * thd * (sigma * c - kappa * s);
        }
    }
}
