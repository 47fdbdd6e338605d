//! Whole runs: energy conservation of the flexible pendulum, the two inertia routes,
//! determinism (the 5 s four-bar's timing is the xtask's and `benches/step.rs`'s).

mod common;
use common::*;
use flexmbd_body::InertiaMethod;

#[test]
fn flexible_pendulum_conserves_energy() {
    let s = model("flexible_pendulum.ron");
    let (rows, phi) = run_relative(&s, 1e-3, 10.0, 10);
    let (drift, per_scale) = flexible_pendulum_energy_drift(&rows);
    eprintln!(
        "pendulum: energy drift {drift:.3e} J over 10 s ({per_scale:.2e} relative), ‖Φ‖ {phi:.1e}"
    );
    assert!(per_scale < 1e-4);
}

#[test]
fn rigid_four_bar_energy_drift_is_second_order() {
    let s = four_bar(0);
    let drift = |h: f64| {
        let (rows, _) = run_relative(&s, h, 5.0, 1);
        let e0 = rows[0][2];
        rows.iter().map(|r| (r[2] - e0).abs()).fold(0.0, f64::max)
    };
    let (a, b) = (drift(1e-3), drift(5e-4));
    eprintln!(
        "four-bar energy drift over 5 s: {a:.2e} J (h = 1e-3), {b:.2e} J (h = 5e-4), ratio {:.2}",
        a / b
    );
    assert!(a / b > 3.0 && a / b < 5.5, "{a:e} {b:e}");
}

#[test]
fn inertia_routes_agree() {
    for scene in [four_bar(5), model("flexible_pendulum.ron")] {
        let mut sh = scene.clone();
        sh.solver.inertia = InertiaMethod::ShapeIntegrals;
        let mut bm = scene.clone();
        bm.solver.inertia = InertiaMethod::BMatrix;
        let (a, _) = run_relative(&sh, 1e-3, 1.0, 1);
        let (b, _) = run_relative(&bm, 1e-3, 1.0, 1);
        let d = largest_difference(&a, &b, &[0, 1]);
        eprintln!(
            "{}: B-matrix vs shape integrals, max difference over 1 s {d:.2e} m",
            scene.name
        );
        // Identical in exact arithmetic. Measured 2.9e-12 m (four-bar), 6.9e-12 m (pendulum).
        assert!(d < 1e-10, "{d:e}");
    }
}

#[test]
fn reruns_are_bit_identical() {
    let s = four_bar(2);
    let (a, _) = run_relative(&s, 1e-3, 1.0, 1);
    let (b, _) = run_relative(&s, 1e-3, 1.0, 1);
    assert!(
        a.iter()
            .zip(&b)
            .all(|(x, y)| x.iter().zip(y).all(|(u, v)| u.to_bits() == v.to_bits()))
    );
}
