//! Shared by the integrator tests: the point-mass pendulum in natural coordinates and an
//! ALI3-P at a given step.
#![allow(dead_code)]

use flexmbd_core::{Coordinates, Formulation, Request, State, SystemTerms};
use flexmbd_integrators::{Ali3p, Ali3pSettings};
use nalgebra::DVector;

pub const G: f64 = 9.81;
/// The standard pendulum's bob mass and rod length.
pub const MASS: f64 = 2.0;
pub const LENGTH: f64 = 1.5;

/// A point mass on a massless rod from the origin: q = (x, y) of the bob,
/// Φ = x² + y² − L² (repeated `coordinates.n_constraints` times to test redundancy),
/// gravity −y, K = 0.
pub struct Pendulum {
    pub mass: f64,
    pub length: f64,
    /// The start, the held coordinates and the number of copies of the rod constraint.
    pub coordinates: Coordinates,
}

impl Pendulum {
    /// The same pendulum with its rod constraint written `copies` times.
    pub fn with_copies(mut self, copies: usize) -> Self {
        self.coordinates.n_constraints = copies;
        self
    }
}

impl Formulation for Pendulum {
    fn coordinates(&self) -> &Coordinates {
        &self.coordinates
    }
    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        let (q, qd) = (state.q, state.qd);
        if req.dynamics {
            out.mass[(0, 0)] = self.mass;
            out.mass[(1, 1)] = self.mass;
            out.forces[1] = -self.mass * G;
        }
        for k in 0..self.coordinates.n_constraints {
            if req.constraints {
                out.phi[k] = q[0] * q[0] + q[1] * q[1] - self.length * self.length;
            }
            if req.jacobian {
                out.phi_q[(k, 0)] = 2.0 * q[0];
                out.phi_q[(k, 1)] = 2.0 * q[1];
            }
            if req.accel_term {
                out.accel_term[k] = 2.0 * (qd[0] * qd[0] + qd[1] * qd[1]);
            }
        }
    }
}

/// The standard pendulum (mass [`MASS`], length [`LENGTH`], one rod constraint), at rest
/// `theta0` off the downward vertical.
pub fn pendulum(theta0: f64) -> Pendulum {
    let q0 = DVector::from_column_slice(&[LENGTH * theta0.sin(), -LENGTH * theta0.cos()]);
    Pendulum {
        mass: MASS,
        length: LENGTH,
        coordinates: Coordinates::new(q0, DVector::zeros(2), 1),
    }
}

/// ALI3-P on `f` from t = 0 at step `h`, the other settings default.
pub fn ali3p_at(f: &mut impl Formulation, h: f64) -> Ali3p {
    Ali3p::new(
        f,
        0.0,
        Ali3pSettings {
            step: h,
            ..Default::default()
        },
    )
    .unwrap()
}
