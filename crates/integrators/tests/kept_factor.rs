//! The projections keep the last Newton iteration's factor when f_q would be the same bit
//! for bit (no M, Q, K, C pass since, the same α and Φ_q): here a driven angle, whose row of
//! Φ_q is constant, beside an oscillator whose mass depends on its position, so that W
//! changes every step and only the projections can reuse a factor.

use flexmbd_core::{Coordinates, Formulation, Request, State, SystemTerms};
use flexmbd_integrators::{Ali3p, Ali3pSettings};
use nalgebra::DVector;

/// Coordinates (x, θ): a mass 1 + x² on a spring of stiffness `K` (kinetic energy
/// ½ (1 + x²) ẋ², so Q_x = −K x − x ẋ²) and an angle driven at the rate `OMEGA` by
/// Φ = θ − Ω t (Φ_q = [0, 1], Φ_t = −Ω, no acceleration term).
struct DrivenOscillator {
    coordinates: Coordinates,
}

const K: f64 = 40.0;
const OMEGA: f64 = 3.0;

impl DrivenOscillator {
    fn new(x0: f64) -> Self {
        let q0 = DVector::from_column_slice(&[x0, 0.0]);
        let qd0 = DVector::from_column_slice(&[0.0, OMEGA]);
        DrivenOscillator {
            coordinates: Coordinates::new(q0, qd0, 1),
        }
    }
}

impl Formulation for DrivenOscillator {
    fn coordinates(&self) -> &Coordinates {
        &self.coordinates
    }
    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        let (q, qd) = (state.q, state.qd);
        if req.dynamics {
            out.mass[(0, 0)] = 1.0 + q[0] * q[0];
            out.mass[(1, 1)] = 1.0;
            out.forces[0] = -K * q[0] - q[0] * qd[0] * qd[0];
        }
        if req.tangents {
            out.stiffness[(0, 0)] = K + qd[0] * qd[0];
            out.damping[(0, 0)] = 2.0 * q[0] * qd[0];
        }
        if req.constraints {
            out.phi[0] = q[1] - OMEGA * state.t;
            out.phi_t[0] = -OMEGA;
        }
        if req.jacobian {
            out.phi_q[(0, 1)] = 1.0;
        }
    }
}

/// Energy of the oscillator, ½ (1 + x²) ẋ² + ½ K x² (conserved by the exact motion).
fn energy(s: &Ali3p) -> f64 {
    let (x, v) = (s.q[0], s.qd[0]);
    0.5 * (1.0 + x * x) * v * v + 0.5 * K * x * x
}

#[test]
fn the_projections_keep_the_factor_of_a_constant_jacobian_and_the_motion_holds() {
    let mut f = DrivenOscillator::new(0.3);
    let settings = Ali3pSettings {
        step: 1e-3,
        ..Default::default()
    };
    let mut s = Ali3p::new(&mut f, 0.0, settings).unwrap();
    let (e0, f0) = (energy(&s), s.stats.factorizations);
    for _ in 0..2000 {
        s.step(&mut f).unwrap();
    }
    let st = &s.stats;
    // Every Newton iteration refactorises (W moved with x); no projection does.
    assert_eq!(st.factorizations - f0, st.newton_iterations);
    assert!(st.newton_iterations >= st.steps);
    // The driven angle and its rate, projected with the kept factor.
    assert!((s.q[1] - OMEGA * s.t).abs() < 1e-10, "θ = {}", s.q[1]);
    assert!((s.qd[1] - OMEGA).abs() < 1e-10, "θ̇ = {}", s.qd[1]);
    assert!(s.qdd[1].abs() < 1e-8, "θ̈ = {}", s.qdd[1]);
    // The trapezoidal rule conserves this energy to its step error (ωh ≈ 6e-3).
    let drift = (energy(&s) - e0).abs() / e0;
    assert!(drift < 1e-4, "energy drift {drift:e}");
}
