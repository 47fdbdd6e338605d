//! Same scene, two formulations: the relative and absolute (natural-coordinate) runs of
//! the rigid and flexible double four-bar and of the flexible pendulum agree, and their
//! difference shrinks with the step (both converge to the same solution).
//!
//! The four-bar passes singular configurations (all bars aligned, at t ≈ 0.71, 1.23, 2.66,
//! 3.17, 4.60 s) where the mobility jumps and the motion is sensitive. A clean 4× per
//! halving is asserted over the first 1.5 s (rigid) or 1 s (flexible); over 5 s the runs use
//! tight Newton settings (ε = 1e-12, 100 iterations) and small steps. Measured over 5 s
//! (max |Δ| / range of B0's x, y), for the record:
//! - rigid, h = 2.5e-4 / 1.25e-4 / 6.25e-5: 2.86e-6 / 7.16e-7 / 1.38e-7;
//! - 1 flexible bar, h = 2.5e-4 / 1.25e-4 / 6.25e-5 / 3.125e-5: 1.9e-4 / 2.53e-6 / 7.34e-7 /
//!   4.79e-7 (at 250 µs ωh ≈ 4 for the axial modes);
//! - 5 flexible bars, h = 1e-4 / 5e-5 / 2.5e-5: 1.33e-6 / 6.80e-7 / 6.44e-8 (at h = 6.25e-5,
//!   where ωh ≈ 1 for the undamped ~2.5 kHz axial modes, 1.33e-6 between 8.1e-7 at 1.25e-4
//!   and 4.3e-8 at 3.125e-5). Below h = 2.5e-5 the Newton tolerance takes over (2ε/h in the velocities): 1.02e-6 at
//!   1.25e-5 with ε = 1e-12, 1.9e-7 with ε = 1e-13;
//! - 3 flexible bars (two rigid bars in the right loop, so its passages are nearly rigid and
//!   stiff): 2.1e-4 / 9.3e-5 / 6.3e-6 / 1.2e-5 at h = 1e-4 … 1.25e-5, while each formulation's
//!   own run(h) − run(h/2) is 0.5–2e-3 of the range there: neither has converged, and they
//!   agree 20–200 times better than that (docs/design.md).
//!
//! Until the projections were solved in increment form (ali3p.rs, `project_increment`),
//! solve round-off of ~1e-8 per step in the velocities made the 5 s differences of the flexible
//! runs grow as the step fell (five bars: 9.4e-6 at h = 3.125e-5, 1.9e-5 at 1.56e-5).

mod common;
use common::*;
use flexmbd_model::Scene;

/// Max over time of |relative − absolute| for the first `cols` sensors, relative to each
/// sensor's range; sampled every 0.01 s.
fn difference(scene: &Scene, h: f64, duration: f64, cols: &[usize]) -> f64 {
    let every = (0.01 / h).round() as usize;
    let (a, _) = run_absolute(scene, h, duration, every);
    let (r, _) = run_relative(scene, h, duration, every);
    worst_difference(&a, &r, cols)
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
    // Over 5 s, at the tight settings: O(h²) through five singular passages.
    let d = convergence_at(
        &tight(four_bar(0)),
        5.0,
        &[0, 1],
        [2.5e-4, 1.25e-4, 6.25e-5],
    );
    assert!(d[0] / d[1] > 3.0 && d[1] / d[2] > 3.0, "{d:?}");
    assert!(d[2] < 1e-6, "{d:?}");
}

#[test]
fn flexible_four_bar_agrees_with_natural_coordinates() {
    for k in [1, 3, 5] {
        // Undamped axial static modes (~2.5 kHz) are unresolved at these steps and both
        // formulations show the same step-dependent energy exchange with them after the
        // first second (energy drift of either does not shrink monotonically either).
        let d = convergence(&four_bar(k), 1.0, &[0, 1]);
        assert!(d[2] < 1e-6, "{k}: {d:?}");
        assert!(d[0] / d[1] > 3.0 && d[1] / d[2] > 3.0, "{k}: {d:?}");
    }
    // Over 5 s, at steps near or below the period of the undamped axial static modes
    // (~2.5 kHz, ωh = 0.4–4 here). One bar: not below h = 62.5 µs, where its nearly rigid
    // passages leave a floor of ~5e-7 that round-off moves by ±30 % (4.8e-7 at 31.25 µs with
    // this code, 7.3e-7 with q̇ formed from q − q_n instead: d1 > d2 would hinge on it).
    for (k, hs) in [(1, [2.5e-4, 1.25e-4, 6.25e-5]), (5, [1e-4, 5e-5, 2.5e-5])] {
        let d = convergence_at(&tight(four_bar(k)), 5.0, &[0, 1], hs);
        assert!(d[2] < 1e-6, "{k}: {d:?}");
        assert!(d[0] > d[1] && d[1] > d[2], "{k}: {d:?}");
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

/// The projections must not amplify round-off: two runs whose penalties differ by 1e-13
/// relative (a change of round-off only; the converged q, q̇ do not depend on α) keep their
/// velocities together. Solving the projections for the whole velocity, f_q having a
/// condition number near 1e9 here, put them 4e-9 (absolute) and 2.6e-8 (relative) apart
/// after one step, with the positions 3e-19 apart; solved for the increment, 8e-14 and
/// 1.1e-15 (relative to ‖q̇‖∞).
#[test]
fn projections_do_not_amplify_round_off() {
    let h = 3.125e-5;
    for relative in [false, true] {
        let mut s = tight(four_bar(5));
        if relative {
            s.solver.formulation = flexmbd_model::FormulationKind::Relative;
        }
        let compile = |s: &Scene| -> Box<dyn flexmbd_core::Formulation> {
            if relative {
                Box::new(compiled(s, flexmbd_relative::compile))
            } else {
                Box::new(compiled(s, flexmbd_absolute::compile))
            }
        };
        let (mut f1, mut f2) = (compile(&s), compile(&s));
        let mut a = flexmbd_integrators::Ali3p::new(f1.as_mut(), 0.0, settings(&s, h)).unwrap();
        let mut other = settings(&s, h);
        other.penalty = Some(a.penalty() * (1.0 + 1e-13));
        let mut b = flexmbd_integrators::Ali3p::new(f2.as_mut(), 0.0, other).unwrap();
        a.step(f1.as_mut()).unwrap();
        b.step(f2.as_mut()).unwrap();
        let dq = (&a.q - &b.q).amax();
        let dqd = (&a.qd - &b.qd).amax() / a.qd.amax().max(1.0);
        eprintln!(
            "relative = {relative}: after one step, positions {dq:.1e}, velocities {dqd:.1e} apart"
        );
        assert!(dq < 1e-15, "relative = {relative}: positions {dq:e}");
        assert!(dqd < 1e-12, "relative = {relative}: velocities {dqd:e}");
    }
}
