//! Same scene, two formulations: the relative and absolute (natural-coordinate) runs of
//! the rigid and flexible double four-bar and of the flexible pendulum agree, and their
//! difference shrinks as O(h²) (both converge to the same solution).
//!
//! The four-bar passes singular configurations (all bars aligned, first near t ≈ 1.6 s)
//! where Newton is accepted at its iteration limit and the sensitivity to any
//! perturbation is large; the clean O(h²) ratio is therefore asserted over the first
//! 1.5 s (rigid) or 1 s (flexible), and the 5 s histories are held to a bound.

mod common;
use common::*;
use flexmbd_model::Scene;

/// Max over time of |relative − absolute| for the first `cols` sensors, relative to each
/// sensor's range; sampled every 0.01 s.
fn difference(scene: &Scene, h: f64, duration: f64, cols: &[usize]) -> f64 {
    let every = (0.01 / h).round() as usize;
    let (a, _) = run_absolute(scene, h, duration, every);
    let (r, _) = run_relative(scene, h, duration, every);
    let mut worst = 0.0f64;
    for &c in cols {
        let (lo, hi) = a
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, u), x| (l.min(x[c]), u.max(x[c])));
        let d = a
            .iter()
            .zip(&r)
            .map(|(x, y)| (x[c] - y[c]).abs())
            .fold(0.0, f64::max);
        worst = worst.max(d / (hi - lo));
    }
    worst
}

fn convergence(scene: &Scene, duration: f64, cols: &[usize]) -> Vec<f64> {
    let d: Vec<f64> = [1e-3, 5e-4, 2.5e-4]
        .iter()
        .map(|&h| difference(scene, h, duration, cols))
        .collect();
    let flex = scene.bodies.iter().filter(|b| b.flexible).count();
    eprintln!(
        "{} ({flex} flexible), {duration} s: relative vs absolute, max difference / range at h = 1e-3, 5e-4, 2.5e-4: {:.2e} {:.2e} {:.2e} (ratios {:.2}, {:.2})",
        scene.name,
        d[0],
        d[1],
        d[2],
        d[0] / d[1],
        d[1] / d[2]
    );
    d
}

#[test]
fn rigid_four_bar_agrees_with_natural_coordinates() {
    let d = convergence(&four_bar(0), 1.5, &[0, 1]);
    assert!(d[2] < 1e-6, "{d:?}");
    assert!(d[0] / d[1] > 3.5 && d[1] / d[2] > 3.5, "{d:?}");
    let d = convergence(&four_bar(0), 5.0, &[0, 1]);
    assert!(d[2] < 1e-5, "{d:?}");
}

#[test]
fn flexible_four_bar_agrees_with_natural_coordinates() {
    for k in [1, 3, 5] {
        // Undamped axial static modes (~2.5 kHz) are unresolved at these steps and both
        // formulations show the same step-dependent energy exchange with them after the
        // first second (energy drift of either does not shrink monotonically either).
        let d = convergence(&four_bar(k), 1.0, &[0, 1]);
        assert!(d[2] < 2e-6, "{k}: {d:?}");
        assert!(d[0] / d[1] > 3.0 && d[1] / d[2] > 3.0, "{k}: {d:?}");
        // Over 5 s the singular passages amplify the difference; with 3 flexible bars
        // the two formulations' histories separate by up to ~1 % of the range (reported).
        let d = convergence(&four_bar(k), 5.0, &[0, 1]);
        assert!(d[2] < 2e-2, "{k}: {d:?}");
    }
}

#[test]
fn flexible_pendulum_agrees_with_natural_coordinates() {
    // Tip position (the elastic deflection columns carry the unresolved ~750 Hz modes,
    // whose phase error under the undamped trapezoidal rule does not converge at these h).
    let d = convergence(&model("flexible_pendulum.ron"), 2.0, &[0, 1]);
    assert!(d[2] < 1e-6, "{d:?}");
    assert!(d[0] / d[1] > 3.5 && d[1] / d[2] > 3.5, "{d:?}");
}
