//! The planar spin-up beam (docs/scenes.md §5, docs/methods.md §7.3) with ALI3-P: minimum tip
//! deflection against the reference, mesh convergence with its observed rate, step
//! sensitivity, and the energy balance of the driven hub.
//!
//! The full study (8/16/32/64 elements, 20 s) is the ignored test at the end and the
//! `convergence` example.

mod common;

use common::{balance, quick_spin_up};
use flexmbd_ancf::{CableSpec, History, run_spin_up};
use flexmbd_core::Dim;

/// Min tip u_y of the converged reference (Exudyn ANCFCable2D, n = 64; docs/methods.md §7).
const REFERENCE_MIN_UY: f64 = -0.5737900;

fn run(elements: usize, h: f64) -> History {
    run_spin_up(
        &CableSpec::spin_up_beam(Dim::Planar, elements),
        h,
        20.0,
        1e-2,
    )
    .unwrap()
}

fn rate(coarse: f64, fine: f64) -> f64 {
    (coarse / fine).log2()
}

#[test]
fn min_tip_deflection_and_mesh_convergence() {
    let runs: Vec<History> = [4, 8, 16].into_iter().map(|n| run(n, 1e-3)).collect();
    let h16 = &runs[2];
    let min_uy = h16.min(1);
    eprintln!(
        "n = 16: min u_y = {min_uy:.7} m (reference {REFERENCE_MIN_UY}), u_x in [{:.7}, {:.7}], {:.2} it/step, CPU {:.2} s",
        h16.min(0),
        h16.max(0),
        h16.stats.newton_iterations as f64 / h16.stats.steps as f64,
        h16.cpu_seconds
    );
    assert!(
        (min_uy - REFERENCE_MIN_UY).abs() < 1e-6,
        "min u_y = {min_uy}"
    );
    assert_eq!(h16.stats.accepted_unconverged, 0);
    assert!(h16.stats.newton_iterations < 2 * h16.stats.steps);
    // Successive differences over t ∈ [0, 20] s: 4→8 and 8→16 elements.
    let d1 = [
        runs[0].max_difference(&runs[1], 0),
        runs[0].max_difference(&runs[1], 1),
    ];
    let d2 = [
        runs[1].max_difference(&runs[2], 0),
        runs[1].max_difference(&runs[2], 1),
    ];
    let r = [rate(d1[0], d2[0]), rate(d1[1], d2[1])];
    eprintln!(
        "4 vs 8: {d1:?}; 8 vs 16: {d2:?}; observed rates u_x {:.2}, u_y {:.2}",
        r[0], r[1]
    );
    // Cubic Hermite elements: tip errors fall as n⁻⁴ or faster (4.4–5.5 observed up to 64).
    assert!(r[0] > 3.5 && r[1] > 3.5, "rates {r:?}");
    assert!(
        d2[0] < 1e-4 && d2[1] < 1e-4,
        "8 vs 16 differ by {d2:?} (≥ 0.1 mm)"
    );
}

#[test]
fn step_sensitivity() {
    // Eight elements: the step error comes from the low modes, as with 16 (6.7e-6 m there).
    let spec = CableSpec::spin_up_beam(Dim::Planar, 8);
    let a = run_spin_up(&spec, 1e-3, 20.0, 1e-2).unwrap();
    let b = run_spin_up(&spec, 5e-4, 20.0, 1e-2).unwrap();
    let d = [a.max_difference(&b, 0), a.max_difference(&b, 1)];
    eprintln!(
        "n = 8, h = 5e-4 vs 1e-3: |Δu_x| {:.3e}, |Δu_y| {:.3e}",
        d[0], d[1]
    );
    assert!(d[0] < 1e-5 && d[1] < 1e-5, "{d:?}");
}

/// Energy balance dE/dt = λ_d Φ_t (the hub's power through the driven constraint row),
/// integrated by the trapezoidal rule, and the Jacobi integral E − Ω_s L_z after T_s.
/// A quick spin-up (T_s = 3 s) keeps the run short and excites the beam strongly.
#[test]
fn hub_power_balances_energy_and_jacobi_integral_holds() {
    let spec = quick_spin_up(Dim::Planar, 8);
    let report = balance(&spec, 1e-3, 6.0);
    let half = balance(&spec, 5e-4, 6.0);
    eprintln!("h = 1e-3: {report:?}\nh = 5e-4: {half:?}");
    // Work done by the hub: ½ I Ω² ≈ 7200 J plus the vibration energy left after T_s.
    assert!(report.work > 5000.0);
    assert!(report.max_balance_error < 1e-4 * report.work, "{report:?}");
    assert!(report.jacobi_drift < 1e-5 * report.work, "{report:?}");
    // Both defects are errors of the trapezoidal rule: second order in h.
    let r1 = (report.max_balance_error / half.max_balance_error).log2();
    let r2 = (report.jacobi_drift / half.jacobi_drift).log2();
    eprintln!("observed orders: balance {r1:.2}, Jacobi {r2:.2}");
    assert!(r1 > 1.7 && r2 > 1.7, "orders {r1}, {r2}");
}

/// The study of docs/methods.md §7.3 over the full 20 s (about 30 s of CPU):
/// `cargo test --release -p flexmbd-ancf --test spin_up_2d -- --ignored`.
#[test]
#[ignore]
fn full_convergence_study() {
    let runs: Vec<History> = [8, 16, 32, 64].into_iter().map(|n| run(n, 1e-3)).collect();
    let d: Vec<[f64; 2]> = runs
        .windows(2)
        .map(|w| [w[0].max_difference(&w[1], 0), w[0].max_difference(&w[1], 1)])
        .collect();
    for (i, di) in d.iter().enumerate() {
        eprintln!("{} vs {}: {di:?}", 8 << i, 16 << i);
    }
    for k in 0..2 {
        for i in 0..2 {
            let r = rate(d[i][k], d[i + 1][k]);
            assert!(r > 3.5, "component {k}, step {i}: rate {r}");
        }
    }
    assert!(d[1][1] < 1e-6, "16 vs 32 elements: {:e}", d[1][1]);
    assert!((runs[3].min(1) - REFERENCE_MIN_UY).abs() < 1e-6);
    let fine = run(16, 5e-4);
    let dh = fine.max_difference(&runs[1], 1);
    assert!(dh < 1e-5, "h = 5e-4 vs 1e-3: {dh:e}");
}
