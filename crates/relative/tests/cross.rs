//! Same scene, two formulations: the relative and absolute (natural-coordinate) runs of
//! the rigid and flexible double four-bar and of the flexible pendulum agree, and their
//! difference shrinks as O(h²) (both converge to the same solution).
//!
//! The four-bar passes singular configurations (all bars aligned, at t ≈ 0.71, 1.23, 2.66,
//! 3.17, 4.60 s) where the mobility jumps, Newton converges only linearly (the augmented
//! Lagrangian's multiplier update in the rank-deficient direction) and the motion is
//! sensitive: a 1e-9 relative change of the initial velocity moves B0(5 s) by 1.7e-7 m.
//! So the clean O(h²) ratio is asserted over the first 1.5 s (rigid) or 1 s (flexible), and
//! over 5 s the runs use tight Newton settings (ε = 1e-12, 100 iterations) and small steps,
//! where the difference falls to a floor of about 1e-6 of the range set at the passages
//! (rigid: at the floor; one flexible bar: below it), no longer at a clean 4× per halving.
//!
//! Measured over 5 s (max |Δ| / range of B0's x, y; ε = 1e-12), for the record:
//! - rigid, h = 2.5e-4 / 1.25e-4 / 6.25e-5: 3.13e-6 / 1.01e-6 / 1.01e-6 (at the floor: a
//!   change of round-off, e.g. of the factorisation kernels, moves the last two by ±10 %);
//! - 1 flexible bar, h = 1.25e-4 / 6.25e-5 / 3.125e-5: 2.56e-6 / 7.76e-7 / 4.10e-7;
//! - 3 and 5 flexible bars do not reach 1e-6: best 1.96e-6 (3 bars, h = 1.5625e-5) and
//!   9.6e-6 (5 bars, h = 3.125e-5), and the difference grows again at smaller steps
//!   (5 bars: 1.9e-5 at 1.5625e-5, 3.9e-5 at 7.8e-6) because the default penalty
//!   α = 4·10⁴ m_ref/h² amplifies round-off in Φ as h⁻² (with α fixed at 1e12, 5 bars reach
//!   4.7e-7 at 3.125e-5, but the rigid and 1-bar runs then stall at a singular passage).
//!   docs/design.md has the figures.

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
    convergence_at(scene, duration, cols, [1e-3, 5e-4, 2.5e-4])
}

/// The double four-bar with the tight Newton settings of the 5 s comparisons.
fn tight(mut s: Scene) -> Scene {
    s.solver.newton_tolerance = 1e-12;
    s.solver.max_iterations = 100;
    s
}

fn convergence_at(scene: &Scene, duration: f64, cols: &[usize], hs: [f64; 3]) -> Vec<f64> {
    let d: Vec<f64> = hs
        .iter()
        .map(|&h| difference(scene, h, duration, cols))
        .collect();
    let flex = scene.bodies.iter().filter(|b| b.flexible).count();
    eprintln!(
        "{} ({flex} flexible), {duration} s: relative vs absolute, max difference / range at h = {hs:?}: {:.2e} {:.2e} {:.2e} (ratios {:.2}, {:.2})",
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
    // Over 5 s the difference falls from h = 0.25 ms to the singular-passage floor of about
    // 1.0e-6 of the range and stays there (measured 3.13e-6, 1.01e-6, 1.01e-6; at h = 31 µs
    // it rises to 2.5e-6, the penalty's round-off): the bound guards that floor, it does not
    // claim the 1e-6 of issue 5 (docs/design.md).
    let d = convergence_at(
        &tight(four_bar(0)),
        5.0,
        &[0, 1],
        [2.5e-4, 1.25e-4, 6.25e-5],
    );
    assert!(d[0] / d[1] > 2.5, "{d:?}");
    assert!(d[1] < 1.2e-6 && d[2] < 1.2e-6, "{d:?}");
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
    }
    // Over 5 s, at steps that resolve the axial static modes (ωh ≤ 0.5 at 3.125e-5).
    let d = convergence_at(
        &tight(four_bar(1)),
        5.0,
        &[0, 1],
        [1.25e-4, 6.25e-5, 3.125e-5],
    );
    assert!(d[2] < 1e-6, "{d:?}");
    assert!(d[0] > d[1] && d[1] > d[2], "{d:?}");
}

#[test]
fn flexible_pendulum_agrees_with_natural_coordinates() {
    // Tip position (the elastic deflection columns carry the unresolved ~750 Hz modes,
    // whose phase error under the undamped trapezoidal rule does not converge at these h).
    let d = convergence(&model("flexible_pendulum.ron"), 2.0, &[0, 1]);
    assert!(d[2] < 1e-6, "{d:?}");
    assert!(d[0] / d[1] > 3.5 && d[1] / d[2] > 3.5, "{d:?}");
}
