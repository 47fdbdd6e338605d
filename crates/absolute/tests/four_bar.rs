//! The rigid double four-bar in natural coordinates (docs/scenes.md §1, scene A):
//! B0 at t = 10 s against the converged reference, constraints at every step,
//! energy conservation and its second-order convergence, coordinate count.

mod common;
use common::*;
use flexmbd_core::Observe as _;
use flexmbd_core::{Formulation, State};
use flexmbd_model::Scene;

/// Converged rigid N = 2 values at t = 10 s [S3 via docs/scenes.md §1 "Reference values"].
const B0_REF: [f64; 2] = [0.32846, 0.94452];

fn scene() -> Scene {
    flexmbd_test_support::scenes::model("double_four_bar.ron")
}

struct Run {
    b0: [f64; 2],
    max_phi: f64,
    energy_drift: f64,
    e0: f64,
    stats: flexmbd_integrators::Stats,
}

fn run(h: f64, duration: f64) -> Run {
    let scene = scene();
    let mut f = absolute(&scene);
    let mut s = ali3p_at(&mut f, h);
    let mut out = vec![0.0; 3];
    f.sensors(State::new(0.0, &s.q, &s.qd), &mut out);
    let e0 = out[2];
    let (mut max_phi, mut drift) = (0.0f64, 0.0f64);
    for _ in 0..(duration / h).round() as usize {
        s.step(&mut f).unwrap();
        max_phi = max_phi.max(s.terms().phi.amax());
        f.sensors(s.state(), &mut out);
        drift = drift.max((out[2] - e0).abs());
    }
    f.sensors(s.state(), &mut out);
    Run {
        b0: [out[0], out[1]],
        max_phi,
        energy_drift: drift,
        e0,
        stats: s.stats.clone(),
    }
}

#[test]
fn rigid_four_bar_has_six_coordinates() {
    let f = absolute(&scene());
    assert_eq!(f.n_coordinates(), 6);
    assert_eq!(f.n_constraints(), 5);
}

#[test]
fn rigid_four_bar_matches_the_reference_at_10_s() {
    let r = run(1e-3, 10.0);
    let err = ((r.b0[0] - B0_REF[0]).powi(2) + (r.b0[1] - B0_REF[1]).powi(2)).sqrt();
    eprintln!(
        "h = 1e-3: B0 = {:?}, error {err:.3e}, max |Φ| {:.2e}, drift {:.3e} J, stats {:?}",
        r.b0, r.max_phi, r.energy_drift, r.stats
    );
    assert!(err < 1e-4, "B0 error {err:e}");
    assert!(r.max_phi < 1e-9, "constraint violation {:e}", r.max_phi);
    // Initial kinetic energy 1.5 J (docs/scenes.md §1).
    assert!(
        r.energy_drift < 1e-3 * 1.5,
        "energy drift {:e} J (E0 = {} J)",
        r.energy_drift,
        r.e0
    );
}

#[test]
fn rigid_four_bar_converges_to_the_reference_with_the_step() {
    let r = run(2.5e-4, 10.0);
    let err = ((r.b0[0] - B0_REF[0]).powi(2) + (r.b0[1] - B0_REF[1]).powi(2)).sqrt();
    assert!(err < 2e-5, "B0 error {err:e} at h = 0.25 ms");
    assert!(r.max_phi < 1e-9);
}

#[test]
fn energy_error_is_second_order() {
    let coarse = run(1e-3, 10.0);
    let fine = run(5e-4, 10.0);
    let ratio = coarse.energy_drift / fine.energy_drift;
    eprintln!(
        "energy drift {:.3e} J → {:.3e} J, ratio {ratio:.2}",
        coarse.energy_drift, fine.energy_drift
    );
    assert!((3.0..5.5).contains(&ratio), "ratio {ratio}");
}

#[test]
fn runs_are_bit_identical() {
    let a = run(1e-3, 1.0);
    let b = run(1e-3, 1.0);
    assert_eq!(a.b0[0].to_bits(), b.b0[0].to_bits());
    assert_eq!(a.b0[1].to_bits(), b.b0[1].to_bits());
}
