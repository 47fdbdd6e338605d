//! The 3D spin-up scene (docs/scenes.md §5 scene F, gravity along −z) started at rest in static
//! equilibrium (`solver.initial_state: StaticEquilibrium`, docs/methods.md §5.4 item 4), against
//! the ANCF cable started from its own static equilibrium (`Cable::solve_static`). The full
//! 20 s comparison of every method is the report's (`cargo xtask reproduce-thesis --only
//! spin-up`); these tests take the static droop and the first 8 s.

use flexmbd::integrators::{StaticSettings, solve_static};
use flexmbd::model::{FormulationKind, MotionLaw, Scene, Stiffening};
use flexmbd::simulation::{compile, run};
use flexmbd_ancf::{Cable, CableSpec, run_spin_up};
use flexmbd_core::{Dim, State};
use nalgebra::DVector;

fn scene(st: Stiffening, f: FormulationKind) -> Scene {
    let mut scene = flexmbd_test_support::scenes::model("spin_up_beam_3d.ron");
    scene.solver.stiffening = st;
    scene.solver.formulation = f;
    if st == Stiffening::Foreshortening {
        scene.solver.inertia = flexmbd::body::InertiaMethod::BMatrix;
    }
    scene
}

/// The static tip displacement (u_x, u_y, u_z) of a method.
fn static_tip(st: Stiffening, f: FormulationKind) -> [f64; 3] {
    let scene = scene(st, f);
    let mut form = compile(&scene).unwrap();
    let sol = solve_static(form.as_mut(), 0.0, &StaticSettings::default()).unwrap();
    let names = form.sensor_names().to_vec();
    let mut out = vec![0.0; names.len()];
    let qd = DVector::zeros(sol.q.len());
    form.sensors(State::new(0.0, &sol.q, &qd), &mut out);
    let get = |n: &str| out[names.iter().position(|s| s == n).unwrap()];
    eprintln!(
        "{st:?} {f:?}: static tip ({:.3} mm, {:.1e}, {:.6} m), {} iterations, {} load steps, {} evaluations",
        get("tip_ux") * 1e3,
        get("tip_uy"),
        get("tip_uz"),
        sol.counters.iterations,
        sol.counters.load_steps,
        sol.counters.evaluations
    );
    [get("tip_ux"), get("tip_uy"), get("tip_uz")]
}

fn cable_static(elements: usize) -> [f64; 3] {
    let mut c = Cable::new(&CableSpec::spin_up_beam(Dim::Spatial, elements)).unwrap();
    c.solve_static(0.0, 10).unwrap();
    c.tip_displacement(0.0, &c.initial_positions().clone())
}

/// The static droop under gravity (the start of every 3D run). Measured tip (u_x mm, u_z m):
/// cable (16 elements) −62.246 / −1.041924; FNL1 0 / −1.051027 (the linear droop, 4 modes per
/// plane); FNL2 and FS0 −63.125 / −1.051027; SB10 −61.649 / −1.042103; SB20 −62.101 / −1.041973.
///
/// - FNL2 (full axial basis) and FS0 shorten the beam by the foreshortening of the bent shape
///   (0.88 mm off the cable's 62.2 mm) but keep the linear droop: a moderate-rotation model has
///   no large-rotation correction, so they droop 9.1 mm more than the geometrically exact cable
///   (δ/L = 0.10). This 9.1 mm is the floor of their vertical error over the whole run.
/// - FNL1 cannot shorten: its axial error at t = 0 is the whole shortening, ≈ 0.6 δ²/L.
/// - SBn rotate each substructure's frame, so they approach the cable: 0.60 / 0.18 mm for n = 10,
///   0.15 / 0.05 mm for n = 20 (a factor ≈ 4 per halving: second order in the body length).
///
/// Bounds: measured + 10 %, or the physical statement itself.
#[test]
fn static_droop_against_the_cable() {
    let c = cable_static(16);
    eprintln!("cable: {:.3} mm, {:.6} m", c[0] * 1e3, c[2]);
    use FormulationKind::{Absolute, Relative};
    use Stiffening::*;
    let linear = static_tip(Linear, Relative)[2];
    let mut d = Vec::new();
    for (st, f) in [
        (Fnl1, Relative),
        (Fnl1, Absolute),
        (Fnl2, Relative),
        (Fnl2, Absolute),
        (Foreshortening, Relative),
        (Substructuring(10), Relative),
        (Substructuring(20), Relative),
    ] {
        let u = static_tip(st, f);
        let e = [(u[0] - c[0]) * 1e3, u[1] * 1e3, (u[2] - c[2]) * 1e3];
        eprintln!("   Δ against the cable (mm): {e:.3?}");
        assert!(e[1].abs() < 1e-6, "{st:?} {f:?}: no horizontal droop");
        d.push((st, u, e));
    }
    for (st, u, e) in &d {
        match st {
            Fnl1 => {
                assert!(u[0].abs() < 1e-12);
                assert!((u[2] - linear).abs() < 1e-9);
                let shortening = 0.6 * c[2] * c[2] / 10.0 * 1e3;
                assert!((e[0] / shortening - 1.0).abs() < 0.05, "{e:?}");
            }
            Fnl2 | Foreshortening => {
                assert!((u[2] - linear).abs() < 1e-6, "{st:?}: {u:?}");
                assert!(
                    e[0].abs() < 0.97 && (e[2] + 9.10).abs() < 0.1,
                    "{st:?}: {e:?}"
                );
            }
            Substructuring(10) => assert!(e[0].abs() < 0.66 && e[2].abs() < 0.2, "{e:?}"),
            Substructuring(20) => assert!(e[0].abs() < 0.16 && e[2].abs() < 0.055, "{e:?}"),
            _ => unreachable!(),
        }
    }
}

/// The cable from its static equilibrium over `duration` (8 elements: over the 20 s its tip
/// differs from 16 elements by ≤ 0.11 mm, `flexmbd-ancf` convergence example).
fn cable_run(duration: f64) -> flexmbd_ancf::History {
    run_spin_up(
        &CableSpec::spin_up_beam(Dim::Spatial, 8),
        1e-3,
        duration,
        0.01,
    )
    .unwrap()
}

/// Max |Δ| (mm) of the tip components of a method's run against the cable, and the run's
/// largest axial, horizontal and vertical tip excursions.
fn run_errors(
    st: Stiffening,
    f: FormulationKind,
    duration: f64,
    r: &flexmbd_ancf::History,
) -> [f64; 3] {
    let mut scene = scene(st, f);
    scene.solver.duration = duration;
    let (summary, h) = run(&scene, |_| {}).unwrap();
    assert_eq!(summary.status, "ok", "{:?}", summary.message);
    let cols = [
        h.column("tip_ux").unwrap(),
        h.column("tip_uy").unwrap(),
        h.column("tip_uz").unwrap(),
    ];
    assert_eq!(cols[0].len(), r.t.len());
    let mut e = [0.0_f64; 3];
    for k in 0..r.t.len() {
        for c in 0..3 {
            e[c] = e[c].max((cols[c][k] - r.tip[k][c]).abs() * 1e3);
        }
    }
    eprintln!(
        "{st:?} {f:?}: max |Δ| over {duration} s = {e:.3?} mm ({:.2} it/step, CPU {:.2} s)",
        summary.newton_iterations as f64 / summary.steps as f64,
        summary.cpu_seconds
    );
    e
}

/// The first 8 s of the spin-up (hub speed 3.4 rad/s at 8 s; the largest errors of the 20 s run
/// are all reached by then except SB10's horizontal one, `cargo xtask reproduce-thesis --only
/// spin-up`), relative formulation, against the cable. Measured max |Δx| / |Δy| / |Δz| (mm):
/// FNL1 65.23 / 6.78 / 9.54, FNL2 1.00 / 5.18 / 9.58, FS0 1.01 / 5.27 / 9.59; FNL1 in the
/// absolute formulation equals the relative run to 1e-3 mm. The vertical errors are set at
/// t = 0 by the static droop (see `static_droop_against_the_cable`); FNL1's axial error is the
/// shortening 0.6 δ²/L = 65 mm of the 1.04 m droop, which it cannot represent (the thesis's
/// 28 mm, docs/scenes.md §7.4, is the same effect on a stiffer beam). Bounds: measured + 10 %.
#[test]
fn first_8_s_against_the_cable() {
    use FormulationKind::{Absolute, Relative};
    use Stiffening::*;
    let r = cable_run(8.0);
    let fnl1 = run_errors(Fnl1, Relative, 8.0, &r);
    let fnl2 = run_errors(Fnl2, Relative, 8.0, &r);
    let fs0 = run_errors(Foreshortening, Relative, 8.0, &r);
    let fnl1_ac = run_errors(Fnl1, Absolute, 8.0, &r);
    for (e, m) in [(fnl2, [1.00, 5.18, 9.58]), (fs0, [1.01, 5.27, 9.59])] {
        for c in 0..3 {
            assert!(e[c] < 1.1 * m[c], "{e:?} against {m:?}");
        }
    }
    // FNL1: the largest axial error by far, near the shortening of the static droop.
    let droop = -r.tip[0][2];
    let shortening = 0.6 * droop * droop / 10.0 * 1e3;
    assert!(
        (fnl1[0] / shortening - 1.0).abs() < 0.05,
        "{fnl1:?} vs {shortening}"
    );
    assert!(fnl1[0] > 50.0 * fnl2[0].max(fs0[0]));
    // Without the axial–bending coupling FNL1 also lags more in the plane (thesis: 10.7 against
    // 5.8 mm).
    assert!(fnl1[1] > fnl2[1] && fnl1[1] > fs0[1]);
    for c in 0..3 {
        assert!((fnl1_ac[c] - fnl1[c]).abs() < 0.01, "{fnl1_ac:?} {fnl1:?}");
    }
}

/// SB10 over the first 8 s (measured 0.60 / 7.73 / 4.56 mm; the thesis: 0.50 / 3.19 / 2.33
/// over its 20 s). Bounds: measured + 10 %.
#[test]
fn sb10_first_8_s_against_the_cable() {
    let r = cable_run(8.0);
    let e = run_errors(
        Stiffening::Substructuring(10),
        FormulationKind::Relative,
        8.0,
        &r,
    );
    let m = [0.60, 7.73, 4.56];
    for c in 0..3 {
        assert!(e[c] < 1.1 * m[c], "{e:?} against {m:?}");
    }
}

/// The static start really is static: with Ωs = 0 the tip stays where the static solver put it
/// and does not move for a second (FNL2 and FS0, relative; FNL2, absolute).
#[test]
fn static_start_without_spin_stays_put() {
    use FormulationKind::{Absolute, Relative};
    use Stiffening::*;
    use flexmbd::model::{Axis, Sensor, SensorKind};
    for (st, f) in [
        (Fnl2, Relative),
        (Foreshortening, Relative),
        (Fnl2, Absolute),
    ] {
        let mut scene = scene(st, f);
        scene.solver.duration = 1.0;
        for d in &mut scene.drivers {
            if let MotionLaw::SpinUp { omega_s, .. } = &mut d.law {
                *omega_s = 0.0;
            }
        }
        for (name, c) in [
            ("tip_vx", Axis::X),
            ("tip_vy", Axis::Y),
            ("tip_vz", Axis::Z),
        ] {
            scene.sensors.push(Sensor {
                name: name.into(),
                kind: SensorKind::Velocity {
                    body: "beam".into(),
                    marker: "tip".into(),
                    component: c,
                    frame: None,
                },
                displacement: false,
            });
        }
        let (summary, h) = run(&scene, |_| {}).unwrap();
        assert_eq!(summary.status, "ok");
        let uz = h.column("tip_uz").unwrap();
        let drift = uz.iter().map(|u| (u - uz[0]).abs()).fold(0.0, f64::max);
        let v = ["tip_vx", "tip_vy", "tip_vz"]
            .iter()
            .flat_map(|n| h.column(n).unwrap())
            .fold(0.0, |a: f64, b| a.max(b.abs()));
        eprintln!(
            "{st:?} {f:?}: u_z(0) = {:.6} m, drift {drift:.1e} m, max |v| {v:.1e} m/s",
            uz[0]
        );
        assert!(uz[0] < -1.0);
        assert!(drift < 1e-8 && v < 1e-7, "drift {drift:e}, v {v:e}");
    }
}
