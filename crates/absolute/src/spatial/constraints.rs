//! The constraint equations Φ, their Jacobian Φ_q, Φ_t and the acceleration term
//! (docs/methods.md §3.1–§3.2): the six orthonormality conditions of every body frame and
//! the joint and driver equations, then the scene's marker constraints
//! (`marker_constraints`), all written over [`Term`]s.

use flexmbd_core::{Request, State, SystemTerms};
use flexmbd_model::MotionLaw;
use nalgebra::{DVector, Vector3};

use super::kinematics::{Term, frame_of};
use super::marker_constraints::DistanceConstraint;
use super::{Spatial, SpatialBody};

/// One block of constraint rows.
pub(super) enum Constraint {
    /// The six orthonormality conditions of the body whose coordinates start at `offset`.
    Orthonormality { offset: usize },
    /// `point2 − point1 = 0` (3 rows).
    Coincide { point2: Term, point1: Term },
    /// A dot product (1 row).
    Dot(DotConstraint),
    /// A driven relative angle (1 row).
    Angle(AngleConstraint),
    /// A scene `Distance` constraint (1 row).
    Distance(DistanceConstraint),
}

/// `(x − origin)·z − c0 − s(t) = 0` (no `origin`: `x·z − c0 − s(t)`; no law: s = 0).
pub(super) struct DotConstraint {
    pub(super) x: Term,
    pub(super) origin: Option<Term>,
    pub(super) z: Term,
    pub(super) c0: f64,
    pub(super) law: Option<MotionLaw>,
}

/// `σ cos θ − κ sin θ = 0`, σ = (p1 × p2)·a, κ = p1·p2, θ = φ0 + θ(t).
pub(super) struct AngleConstraint {
    pub(super) p1: Term,
    pub(super) p2: Term,
    pub(super) a: Term,
    /// The angle at t = 0 (set after the bodies are built).
    pub(super) phi0: f64,
    pub(super) law: MotionLaw,
}

impl Constraint {
    pub(super) fn rows(&self) -> usize {
        match self {
            Constraint::Orthonormality { .. } => 6,
            Constraint::Coincide { .. } => 3,
            _ => 1,
        }
    }
}

/// The state a constraint block is evaluated at, and what is asked of it.
pub(super) struct At<'a> {
    pub(super) bodies: &'a [SpatialBody],
    pub(super) t: f64,
    pub(super) q: &'a DVector<f64>,
    pub(super) qd: &'a DVector<f64>,
    pub(super) req: Request,
}

impl Spatial {
    /// Fill Φ, Φ_q, Φ_t and the acceleration term as `req` asks.
    pub(super) fn constraint_terms(&self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        let State { t, q, qd, .. } = state;
        let at = At {
            bodies: &self.bodies,
            t,
            q,
            qd,
            req,
        };
        let mut row = 0;
        for constraint in &self.constraints {
            match constraint {
                Constraint::Orthonormality { offset } => orthonormality(&at, *offset, row, out),
                Constraint::Coincide { point2, point1 } => {
                    coincide(&at, point2, point1, row, out);
                }
                Constraint::Dot(dot) => dot.evaluate(&at, row, out),
                Constraint::Angle(angle) => angle.evaluate(&at, row, out),
                Constraint::Distance(distance) => distance.evaluate(&at, row, out),
            }
            row += constraint.rows();
        }
    }
}

/// `u·u = v·v = w·w = 1`, `u·v = v·w = w·u = 0`.
fn orthonormality(at: &At, off: usize, row: usize, out: &mut SystemTerms) {
    let req = at.req;
    let (_, a) = frame_of(at.q.as_slice(), off);
    let (_, ad) = frame_of(at.qd.as_slice(), off);
    // (u,u), (v,v), (w,w), (u,v), (v,w), (w,u).
    const PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)];
    for (k, &(i, j)) in PAIRS.iter().enumerate() {
        let (ei, ej) = (a.column(i), a.column(j));
        if req.constraints {
            out.phi[row + k] = ei.dot(&ej) - if i == j { 1.0 } else { 0.0 };
        }
        if req.jacobian {
            for c in 0..3 {
                out.phi_q[(row + k, off + 3 + 3 * i + c)] += ej[c];
                out.phi_q[(row + k, off + 3 + 3 * j + c)] += ei[c];
            }
        }
        if req.accel_term {
            out.accel_term[row + k] = 2.0 * ad.column(i).dot(&ad.column(j));
        }
    }
}

/// `a − b = 0`.
fn coincide(at: &At, a: &Term, b: &Term, row: usize, out: &mut SystemTerms) {
    let (bodies, q, qd, req) = (at.bodies, at.q, at.qd, at.req);
    let (ea, eb) = (a.eval(bodies, q, qd), b.eval(bodies, q, qd));
    if req.constraints {
        out.phi
            .fixed_rows_mut::<3>(row)
            .copy_from(&(ea.value - eb.value));
    }
    if req.jacobian {
        for k in 0..3 {
            let mut w = Vector3::zeros();
            w[k] = 1.0;
            a.add_jacobian(bodies, &ea, &w, q, &mut out.phi_q, row + k);
            b.add_jacobian(bodies, &eb, &(-w), q, &mut out.phi_q, row + k);
        }
    }
    if req.accel_term {
        out.accel_term
            .fixed_rows_mut::<3>(row)
            .copy_from(&(ea.bias - eb.bias));
    }
}

impl DotConstraint {
    fn evaluate(&self, at: &At, row: usize, out: &mut SystemTerms) {
        let DotConstraint {
            x,
            origin: x2,
            z,
            c0,
            law,
        } = self;
        let (bodies, q, qd, req) = (at.bodies, at.q, at.qd, at.req);
        let ex = x.eval(bodies, q, qd);
        let ex2 = x2.as_ref().map(|x2| x2.eval(bodies, q, qd));
        let ez = z.eval(bodies, q, qd);
        let (mut d, mut dd, mut db) = (ex.value, ex.rate, ex.bias);
        if let Some(e2) = &ex2 {
            d -= e2.value;
            dd -= e2.rate;
            db -= e2.bias;
        }
        let (s, sd, sdd) = law.as_ref().map_or((0.0, 0.0, 0.0), |l| l.eval(at.t));
        if req.constraints {
            out.phi[row] = d.dot(&ez.value) - c0 - s;
        }
        if req.jacobian {
            x.add_jacobian(bodies, &ex, &ez.value, q, &mut out.phi_q, row);
            if let (Some(x2), Some(e2)) = (x2, &ex2) {
                x2.add_jacobian(bodies, e2, &(-ez.value), q, &mut out.phi_q, row);
            }
            z.add_jacobian(bodies, &ez, &d, q, &mut out.phi_q, row);
            out.phi_t[row] = -sd;
        }
        if req.accel_term {
            out.accel_term[row] =
                db.dot(&ez.value) + d.dot(&ez.bias) + 2.0 * dd.dot(&ez.rate) - sdd;
        }
    }
}

impl AngleConstraint {
    fn evaluate(&self, at: &At, row: usize, out: &mut SystemTerms) {
        let AngleConstraint {
            p1,
            p2,
            a,
            phi0,
            law,
        } = self;
        let (bodies, q, qd, req) = (at.bodies, at.q, at.qd, at.req);
        let (th_l, thd, thdd) = law.eval(at.t);
        let (s, c) = (phi0 + th_l).sin_cos();
        let (e1, e2, ea) = (
            p1.eval(bodies, q, qd),
            p2.eval(bodies, q, qd),
            a.eval(bodies, q, qd),
        );
        let (x1, x2, xa) = (e1.value, e2.value, ea.value);
        let sigma = x1.cross(&x2).dot(&xa);
        let kappa = x1.dot(&x2);
        if req.constraints {
            out.phi[row] = sigma * c - kappa * s;
        }
        if req.jacobian {
            let w1 = x2.cross(&xa) * c - x2 * s;
            let w2 = xa.cross(&x1) * c - x1 * s;
            let wa = x1.cross(&x2) * c;
            p1.add_jacobian(bodies, &e1, &w1, q, &mut out.phi_q, row);
            p2.add_jacobian(bodies, &e2, &w2, q, &mut out.phi_q, row);
            a.add_jacobian(bodies, &ea, &wa, q, &mut out.phi_q, row);
            out.phi_t[row] = -thd * (sigma * s + kappa * c);
        }
        if req.accel_term {
            let (d1, d2, da) = (e1.rate, e2.rate, ea.rate);
            let sigma_d = d1.cross(&x2).dot(&xa) + x1.cross(&d2).dot(&xa) + x1.cross(&x2).dot(&da);
            let kappa_d = d1.dot(&x2) + x1.dot(&d2);
            let sigma_b = e1.bias.cross(&x2).dot(&xa)
                + x1.cross(&e2.bias).dot(&xa)
                + x1.cross(&x2).dot(&ea.bias)
                + 2.0 * (d1.cross(&d2).dot(&xa) + d1.cross(&x2).dot(&da) + x1.cross(&d2).dot(&da));
            let kappa_b = e1.bias.dot(&x2) + x1.dot(&e2.bias) + 2.0 * d1.dot(&d2);
            out.accel_term[row] = sigma_b * c
                - kappa_b * s
                - 2.0 * thd * (sigma_d * s + kappa_d * c)
                - thdd * (sigma * s + kappa * c)
                - thd * thd * (sigma * c - kappa * s);
        }
    }
}
