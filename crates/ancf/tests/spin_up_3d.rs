//! The spatial spin-up beam (docs/scenes.md §5): static droop under gravity along −z, then the
//! spin-up from that equilibrium (docs/methods.md §5.4 item 4, §7.3).

mod common;

use common::{balance, quick_spin_up};
use flexmbd_ancf::{Cable, CableSpec, run_spin_up};
use flexmbd_core::Dim;

/// Gravity along −z in 3D bends the cable in the x–z plane exactly as gravity along −y
/// bends the planar cable; the static start is an equilibrium of the dynamic equations
/// (a run without spin stays put).
#[test]
fn static_droop_matches_planar_and_is_an_equilibrium() {
    let spec3 = CableSpec::spin_up_beam(Dim::Spatial, 16);
    let mut c3 = Cable::new(&spec3).unwrap();
    let r3 = c3.solve_static(0.0, 10).unwrap();
    let d3 = c3.tip_displacement(0.0, &c3.initial_positions().clone());
    let spec2 = CableSpec {
        gravity: [0.0, -9.81, 0.0],
        ..CableSpec::spin_up_beam(Dim::Planar, 16)
    };
    let mut c2 = Cable::new(&spec2).unwrap();
    c2.solve_static(0.0, 10).unwrap();
    let d2 = c2.tip_displacement(0.0, &c2.initial_positions().clone());
    let linear = spec3.rho_a * 9.81 * spec3.length.powi(4) / (8.0 * spec3.ei);
    eprintln!(
        "3D static tip {d3:?} ({} load steps, {} iterations, residual {:.1e} N); 2D {d2:?}; linear droop {linear:.4}",
        r3.load_steps, r3.iterations, r3.residual
    );
    assert!((d3[0] - d2[0]).abs() < 1e-10 && (d3[2] - d2[1]).abs() < 1e-10);
    assert!(d3[1].abs() < 1e-14);
    // Large deflection: less droop than the linear qL⁴/(8EI) = 1.051 m, and the tip moves
    // inwards by about 0.6 δ²/L.
    assert!(d3[2] < -0.9 * linear && d3[2] > -linear, "{}", d3[2]);
    assert!(d3[0] < 0.0 && (d3[0] / (0.6 * d3[2] * d3[2] / spec3.length) + 1.0).abs() < 0.1);
    assert!(r3.residual < 1e-12 * spec3.ea);

    let still = CableSpec {
        omega_s: 0.0,
        ..CableSpec::spin_up_beam(Dim::Spatial, 8)
    };
    let h = run_spin_up(&still, 1e-3, 1.0, 0.1).unwrap();
    let drift = (0..3).map(|k| h.max(k) - h.min(k)).fold(0.0, f64::max);
    eprintln!("no spin from the static start: tip drift {drift:.2e} m");
    assert!(drift < 1e-9, "{drift:e}");
}

/// Without gravity the spatial cable reproduces the planar one and stays in the plane.
#[test]
fn spatial_without_gravity_reproduces_planar() {
    let s3 = CableSpec {
        gravity: [0.0; 3],
        ..CableSpec::spin_up_beam(Dim::Spatial, 4)
    };
    let a = run_spin_up(&s3, 1e-3, 20.0, 1e-2).unwrap();
    let b = run_spin_up(&CableSpec::spin_up_beam(Dim::Planar, 4), 1e-3, 20.0, 1e-2).unwrap();
    let (dx, dy) = (a.max_difference(&b, 0), a.max_difference(&b, 1));
    let dz = a.max(2).max(-a.min(2));
    eprintln!("3D vs 2D, 4 elements: |Δu_x| {dx:.1e}, |Δu_y| {dy:.1e}, |u_z| {dz:.1e}");
    assert!(dx < 1e-9 && dy < 1e-9 && dz < 1e-12);
}

/// The 20 s spin-up with gravity (8 elements; the 8/16/32/64 study is the `convergence`
/// example): the tip rises from the static droop towards the plane as the centrifugal
/// stiffening grows, staying above the rotating-string sag (2g/Ω²) ln 2 = 0.378 m.
#[test]
fn spin_up_with_gravity() {
    let spec = CableSpec::spin_up_beam(Dim::Spatial, 8);
    let h = run_spin_up(&spec, 1e-3, 20.0, 1e-2).unwrap();
    let names = ["u_x", "u_y", "u_z"];
    for k in 0..3 {
        eprintln!(
            "{}: [{:.7}, {:.7}], final {:.7}",
            names[k],
            h.min(k),
            h.max(k),
            h.tip.last().unwrap()[k]
        );
    }
    eprintln!(
        "{:.2} it/step, {} accepted unconverged, CPU {:.2} s",
        h.stats.newton_iterations as f64 / h.stats.steps as f64,
        h.stats.accepted_unconverged,
        h.cpu_seconds
    );
    let string_sag = 2.0 * 9.81 / 36.0 * std::f64::consts::LN_2;
    let last = h.tip.last().unwrap();
    assert!(h.tip[0][2] < -1.0);
    assert!(
        last[2] < 0.0 && last[2] > -string_sag,
        "final u_z {}",
        last[2]
    );
    // The lowest point is the static start.
    assert!((h.min(2) - h.tip[0][2]).abs() < 1e-6);
    assert_eq!(h.stats.accepted_unconverged, 0);
}

/// Hub power balances the energy (gravity included) and E − Ω_s L_z holds after T_s, both
/// to second order in h (gravity along the spin axis keeps the Jacobi integral).
#[test]
fn hub_power_balances_energy_with_gravity() {
    let spec = quick_spin_up(Dim::Spatial, 6);
    let a = balance(&spec, 1e-3, 5.0);
    let b = balance(&spec, 5e-4, 5.0);
    let r1 = (a.max_balance_error / b.max_balance_error).log2();
    let r2 = (a.jacobi_drift / b.jacobi_drift).log2();
    eprintln!("h = 1e-3: {a:?}\nh = 5e-4: {b:?}\norders {r1:.2}, {r2:.2}");
    assert!(a.max_balance_error < 1e-4 * a.work);
    assert!(a.jacobi_drift < 1e-5 * a.work);
    assert!(r1 > 1.7 && r2 > 1.7, "orders {r1}, {r2}");
}
