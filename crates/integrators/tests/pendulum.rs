//! ALI3-P on a planar pendulum in natural coordinates (a point mass on a massless
//! rod): period against the exact elliptic-integral solution, second-order
//! convergence, energy conservation, constraint satisfaction, consistent initial
//! conditions, redundancy, and a clean failure on an absurd step.

mod common;
use common::*;
use flexmbd_core::Coordinates;
use flexmbd_integrators::{Ali3p, Ali3pSettings, IntegratorError};
use nalgebra::DVector;

fn energy(p: &Pendulum, s: &Ali3p) -> f64 {
    0.5 * p.mass * s.qd.norm_squared() + p.mass * G * s.q[1]
}

/// Complete elliptic integral of the first kind K(k) by the arithmetic–geometric mean.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0, (1.0 - k * k).sqrt());
    for _ in 0..30 {
        let an = 0.5 * (a + b);
        b = (a * b).sqrt();
        a = an;
    }
    std::f64::consts::PI / (2.0 * a)
}

fn run(p: &mut Pendulum, h: f64, duration: f64) -> Ali3p {
    let mut s = ali3p_at(p, h);
    let steps = (duration / h).round() as usize;
    for _ in 0..steps {
        s.step(p).unwrap();
    }
    s
}

#[test]
fn large_amplitude_period_matches_the_elliptic_integral() {
    let theta0 = std::f64::consts::FRAC_PI_2;
    let mut p = pendulum(theta0);
    let exact = 4.0 * (p.length / G).sqrt() * elliptic_k((theta0 / 2.0).sin());
    let h = 1e-3;
    let mut s = ali3p_at(&mut p, h);
    // x = 0 is crossed at T/4 (+ → −) and 3T/4 (− → +).
    let mut crossings = Vec::new();
    let mut x_prev = s.q[0];
    while crossings.len() < 2 {
        s.step(&mut p).unwrap();
        let x = s.q[0];
        if x_prev.signum() != x.signum() && x != 0.0 {
            let frac = x_prev / (x_prev - x);
            crossings.push(s.t - h + frac * h);
        }
        x_prev = x;
    }
    let period = 2.0 * (crossings[1] - crossings[0]);
    let rel = (period - exact).abs() / exact;
    assert!(
        rel < 2e-5,
        "period {period} against exact {exact}: relative error {rel:e}"
    );
}

#[test]
fn second_order_convergence_and_energy() {
    let duration = 2.0;
    let reference = run(&mut pendulum(1.0), 1e-4 / 4.0, duration);
    let mut errors = Vec::new();
    let mut drifts = Vec::new();
    for h in [4e-3, 2e-3, 1e-3] {
        let mut p = pendulum(1.0);
        let e0 = {
            let s = ali3p_at(&mut p, h);
            energy(&p, &s)
        };
        let mut s = ali3p_at(&mut p, h);
        let mut drift: f64 = 0.0;
        for _ in 0..(duration / h).round() as usize {
            s.step(&mut p).unwrap();
            drift = drift.max((energy(&p, &s) - e0).abs());
            let phi = s.q.norm_squared() - p.length * p.length;
            assert!(phi.abs() < 1e-9, "constraint violated: {phi:e}");
        }
        errors.push((s.q.clone() - reference.q.clone()).amax());
        drifts.push(drift);
    }
    for w in errors.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            (3.5..4.5).contains(&ratio),
            "position error ratio {ratio} (errors {errors:?})"
        );
    }
    for w in drifts.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            (3.0..5.0).contains(&ratio),
            "energy drift ratio {ratio} (drifts {drifts:?})"
        );
    }
    assert!(
        drifts[2] < 1e-4 * 2.0 * G * 1.5,
        "energy drift {:e}",
        drifts[2]
    );
}

#[test]
fn inconsistent_start_is_projected_holding_the_specified_coordinate() {
    let q0 = DVector::from_column_slice(&[0.6, -0.9]);
    let qd0 = DVector::from_column_slice(&[1.0, 0.7]);
    let mut p = Pendulum {
        mass: 1.0,
        length: 1.0,
        coordinates: Coordinates {
            specified: vec![0],
            ..Coordinates::new(q0, qd0, 1)
        },
    };
    let s = Ali3p::new(&mut p, 0.0, Ali3pSettings::default()).unwrap();
    assert!((s.q[0] - 0.6).abs() < 1e-12, "held x moved: {}", s.q[0]);
    assert!(
        (s.q[1] + 0.8).abs() < 1e-12,
        "y not on the circle: {}",
        s.q[1]
    );
    // Velocity tangent to the circle, with the specified ẋ kept.
    assert!((s.qd[0] - 1.0).abs() < 1e-9);
    assert!((s.q[0] * s.qd[0] + s.q[1] * s.qd[1]).abs() < 1e-10);
    // Acceleration consistent: Φ_q q̈ + c = 0, and the multiplier balances gravity and centripetal load.
    let c = 2.0 * s.qd.norm_squared();
    assert!((2.0 * s.q.dot(&s.qdd) + c).abs() < 1e-8);
}

#[test]
fn redundant_constraints_give_the_same_motion() {
    let single = run(&mut pendulum(0.8), 1e-3, 1.0);
    let mut doubled = pendulum(0.8).with_copies(2);
    let double = run(&mut doubled, 1e-3, 1.0);
    assert!((single.q.clone() - double.q.clone()).amax() < 1e-7);
}

#[test]
fn counters_add_up() {
    let mut p = pendulum(0.5);
    let mut s = Ali3p::new(&mut p, 0.0, Ali3pSettings::default()).unwrap();
    let e0 = s.stats.evaluations;
    for _ in 0..100 {
        s.step(&mut p).unwrap();
    }
    let st = &s.stats;
    assert_eq!(st.steps, 100);
    assert!(st.newton_iterations >= 100);
    // Per iteration: one full pass + one Φ, Φ_q pass; per step: one projection pass (c).
    assert_eq!(st.evaluations - e0, 2 * st.newton_iterations + st.steps);
    // One factorisation per Newton iteration and one for the projections.
    assert_eq!(st.factorizations, st.newton_iterations + st.steps);
    assert_eq!(st.failed_steps, 0);
}

#[test]
fn an_absurd_step_fails_cleanly() {
    let mut p = pendulum(1.4);
    let settings = Ali3pSettings {
        step: 50.0,
        max_iterations: 10,
        penalty: Some(1e3),
        ..Default::default()
    };
    let mut s = Ali3p::new(&mut p, 0.0, settings).unwrap();
    let mut failure = None;
    for _ in 0..20 {
        if let Err(e) = s.step(&mut p) {
            failure = Some(e);
            break;
        }
    }
    match failure {
        Some(
            IntegratorError::NoConvergence { t, .. }
            | IntegratorError::Diverged { t }
            | IntegratorError::Singular { t, .. },
        ) => {
            assert!(t > 0.0);
            assert_eq!(s.stats.failed_steps, 1);
        }
        other => panic!("expected a convergence failure, got {other:?}"),
    }
}

#[test]
fn modified_newton_reuses_the_factorisation_and_reaches_the_same_motion() {
    let full = run(&mut pendulum(1.0), 1e-3, 1.0);
    let mut p = pendulum(1.0);
    let settings = Ali3pSettings {
        step: 1e-3,
        reuse_tangent: true,
        ..Default::default()
    };
    let mut s = Ali3p::new(&mut p, 0.0, settings).unwrap();
    for _ in 0..1000 {
        s.step(&mut p).unwrap();
    }
    assert!(
        s.stats.factorizations < s.stats.newton_iterations + s.stats.steps,
        "{:?}",
        s.stats
    );
    assert!((s.q.clone() - full.q.clone()).amax() < 1e-8);
}
