//! 3D runs in both formulations (docs/methods.md §8 items 6–8): the rigid 3D double pendulum
//! (ball joint, skew hinge) agrees with the spatial natural-coordinate formulation at O(h²),
//! and the double four-bar written in 3D reproduces the planar run.

mod common;
use common::*;
use flexmbd_core::Formulation;

#[test]
fn double_pendulum_3d_agrees_with_natural_coordinates() {
    let s = model("double_pendulum_3d.ron");
    let f = relative(&s);
    assert_eq!((f.n_coordinates(), f.n_constraints()), (4, 0));
    let d: Vec<f64> = [2e-3f64, 1e-3, 5e-4]
        .iter()
        .map(|&h| {
            let every = (0.01 / h).round() as usize;
            let (a, _) = run_absolute(&s, h, 2.0, every);
            let (r, _) = run_relative(&s, h, 2.0, every);
            a.iter()
                .zip(&r)
                .map(|(x, y)| (0..3).map(|c| (x[c] - y[c]).abs()).fold(0.0, f64::max))
                .fold(0.0, f64::max)
        })
        .collect();
    let drift = |h: f64| {
        let (r, _) = run_relative(&s, h, 2.0, 1);
        r.iter().map(|x| (x[4] - r[0][4]).abs()).fold(0.0, f64::max)
    };
    let (e1, e2) = (drift(2e-3), drift(1e-3));
    eprintln!(
        "3D double pendulum, 2 s: max |tip_rel − tip_abs| at h = 2, 1, 0.5 ms: {:.2e} {:.2e} {:.2e} m (ratios {:.2}, {:.2}); relative energy drift {e1:.2e} / {e2:.2e} J",
        d[0],
        d[1],
        d[2],
        d[0] / d[1],
        d[1] / d[2]
    );
    assert!(d[0] / d[1] > 3.0 && d[1] / d[2] > 3.0, "{d:?}");
    assert!(d[2] < 1e-3, "{d:?}");
    assert!(e1 / e2 > 3.0, "{e1:e} {e2:e}");
}

#[test]
fn spatial_four_bar_reproduces_the_planar_run() {
    let planar = four_bar(0);
    let spatial = planar_scene_in_3d(&planar);
    let f = relative(&spatial);
    eprintln!(
        "four-bar in 3D: {} coordinates, {} constraints",
        f.n_coordinates(),
        f.n_constraints()
    );
    assert_eq!(f.n_coordinates(), 5);
    let (p, _) = run_relative(&planar, 1e-3, 2.0, 10);
    let (r, phi) = run_relative(&spatial, 1e-3, 2.0, 10);
    let (a, _) = run_absolute(&spatial, 1e-3, 2.0, 10);
    let d = |u: &[Vec<f64>], v: &[Vec<f64>]| {
        u.iter()
            .zip(v)
            .map(|(x, y)| (x[0] - y[0]).abs().max((x[1] - y[1]).abs()))
            .fold(0.0, f64::max)
    };
    let (d2, da) = (d(&p, &r), d(&a, &r));
    eprintln!(
        "four-bar 3D relative: vs planar relative {d2:.2e} m, vs 3D absolute {da:.2e} m, ‖Φ‖ {phi:.1e}"
    );
    assert!(d2 < 1e-6, "{d2:e}");
    assert!(da < 1e-3, "{da:e}");
}
