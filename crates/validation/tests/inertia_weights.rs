//! The weights of the inertia terms over a pilot run and the terms chosen by them (issue 31
//! item 2, `flexmbd::term_weights`, `flexmbd_body::weights`), relative formulation:
//!
//! * on the spin-up beams (docs/scenes.md §5, spun up in 2 s instead of 15 s so that a
//!   short run reaches full speed), every weight is finite and non-negative, and the
//!   gyroscopic force, which acts on the modal rows alone, weighs nothing in the rigid part;
//! * the second-order terms' modal weight grows with the speed: their modal force is the
//!   centrifugal softening `Ω² M_yy y` of the bending modes against an elastic balance
//!   `K y`, whose ratio in the kinetic norm is at most (Ω/ω₁)² (Rayleigh: `‖Ky‖² =
//!   yᵀKM⁻¹Ky ≥ ω₁⁴ yᵀMy`), ω₁ = 3.80 rad/s the first bending frequency; the axial modes'
//!   centrifugal load in the full force keeps it below that;
//! * the spatial beam spinning in its plane without gravity weighs its terms as the planar
//!   one does (the 3D and the lean 2D kernels, the 6 × 6 and 3 × 3 metrics; the modal norm
//!   does not depend on how the degenerate y/z bending pairs are mixed);
//! * the weights' choice at a threshold does not bound the trajectory: on the 2D spin-up
//!   beam over 20 s it moves the tip by more than the threshold (measured, kept as the
//!   finding); a lower threshold's choice moves it less; the choice is also judged against
//!   the large-deformation ANCF cable;
//! * the choice confirmed at a tolerance (`Pilot::confirm`: the weights' ladder, each rung
//!   run in place of the full model over the pilot) meets it on the pilot's horizon, judged
//!   again here by an independent run of the chosen scene (`simulation::run`) against the
//!   full model's: on the 2D spin-up beam the confirmation rejects the weights' first
//!   choice; on the 3D beam and the double four-bar with five flexible steel bars (bar by
//!   bar) likewise met; on the Iltis vehicle with its 12 beam bodies flexible (1 s, over the
//!   ramp's first 0.35 s) met at 1e-2 and 1e-3 by a choice that drops terms on every body,
//!   whose run does differ from the full model's.

use flexmbd::body::weights::TermGroup;
use flexmbd::model::{FormulationKind, InitialState, Scene, Stiffening, V3};
use flexmbd::simulation::run;
use flexmbd::term_weights::{BodyWeights, TermChoice, apply_choice, pilot, weigh_terms};
use flexmbd_ancf::{CableSpec, run_spin_up};
use flexmbd_core::Dim;

/// A spin-up beam spun up to `omega` rad/s in 2 s, run for 3 s (relative, the scene's FNL1).
fn spin_up(file: &str, omega: f64) -> Scene {
    let mut scene = flexmbd_test_support::scenes::model(file);
    let sets = [
        format!("drivers.spin.law.SpinUp.omega_s={omega}"),
        "drivers.spin.law.SpinUp.t_s=2".to_string(),
    ];
    let sets: Vec<_> = sets
        .iter()
        .map(|s| flexmbd::model::parse_set(s).unwrap())
        .collect();
    scene.apply_sets(&sets).unwrap();
    scene.solver.formulation = FormulationKind::Relative;
    scene.solver.duration = 3.0;
    scene
}

/// The largest relative difference between the 3D beam's weights in its plane and the 2D one's.
const WORST_3D: f64 = 1e-3;
/// The threshold bounds forces, not the trajectory: on the spin-up beam the weights' choice
/// at 1e-2 drops the gyroscopic force (modal weight 4.0e-3, deformation weight 9.6e-4) and
/// moves the tip by 1.41e-2 of its range over 20 s (a workless force, integrated over a
/// resonant spin-up: it shifts the phase of the bending vibration). Not met at 1 ×; this
/// guards the measured factor. The confirmed choice meets 1 × (`confirmed`).
const SPIN_UP_AMPLIFICATION: f64 = 1.5;

fn weights(scene: &Scene) -> BodyWeights {
    let mut w = weigh_terms(scene, None).unwrap();
    assert_eq!(w.len(), 1);
    w.remove(0)
}

fn group(w: &BodyWeights, g: TermGroup) -> flexmbd::body::weights::Weight {
    w.table.groups.iter().find(|(x, _)| *x == g).unwrap().1
}

fn print(label: &str, w: &BodyWeights) {
    for (g, x) in &w.table.groups {
        eprintln!(
            "{label} {:<13} rigid {:.3e} / {:.3e}  modal {:.3e} / {:.3e}  deformation {:.3e} / {:.3e}",
            g.name(),
            x.rigid_max,
            x.rigid_rms,
            x.modal_max,
            x.modal_rms,
            x.deformation_max,
            x.deformation_rms
        );
    }
    for (t, x) in &w.table.candidates {
        eprintln!(
            "{label} {t:<7} drops rigid {:.3e} modal {:.3e} deformation {:.3e}",
            x.rigid_max, x.modal_max, x.deformation_max
        );
    }
}

fn all_weights(w: &BodyWeights) -> Vec<f64> {
    let each = |x: &flexmbd::body::weights::Weight| {
        [
            x.rigid_max,
            x.rigid_rms,
            x.modal_max,
            x.modal_rms,
            x.deformation_max,
            x.deformation_rms,
        ]
    };
    w.table
        .groups
        .iter()
        .map(|(_, x)| each(x))
        .chain(w.table.candidates.iter().map(|(_, x)| each(x)))
        .flatten()
        .collect()
}

/// Every weight finite and non-negative; the gyroscopic force's rigid part zero.
fn check_weights(w: &BodyWeights) {
    for v in all_weights(w) {
        assert!(v.is_finite() && v >= 0.0, "{}: {v}", w.body);
    }
    let gyro = group(w, TermGroup::Gyroscopic);
    assert!(gyro.rigid_max < 1e-12, "{}: {gyro:?}", w.body);
}

#[test]
fn the_second_order_weight_grows_with_the_speed() {
    // Linear elasticity, below the first bending frequency ω₁ = 3.80 rad/s.
    let omega_1: f64 = 3.80;
    let mut modal = Vec::new();
    for omega in [1.0, 2.0] {
        let mut scene = spin_up("spin_up_beam_2d.ron", omega);
        scene.solver.stiffening = Stiffening::Linear;
        let w = weights(&scene);
        print(&format!("Ω {omega}"), &w);
        assert_eq!(w.table.samples, 301);
        check_weights(&w);
        let m = group(&w, TermGroup::SecondOrder).modal_max;
        let bound = (omega / omega_1).powi(2);
        eprintln!("Ω {omega}: second-order modal weight {m:.3e}, (Ω/ω₁)² = {bound:.3e}");
        // Measured 5.18e-2 against 6.9e-2 at 1 rad/s, 1.28e-1 against 2.8e-1 at 2 rad/s.
        assert!(m < bound, "{m:e} ≥ {bound:e}");
        modal.push(m);
    }
    // Measured 2.5: the bending ratio's Ω² (×4) diluted by the axial load's growth.
    assert!(modal[1] > 2.0 * modal[0], "{modal:?}");
    assert!(modal[0] > 0.5 * (1.0 / omega_1).powi(2), "{modal:?}");
}

#[test]
fn the_spatial_beam_in_its_plane_weighs_as_the_planar_one() {
    let planar = weights(&spin_up("spin_up_beam_2d.ron", 2.0));
    let mut scene = spin_up("spin_up_beam_3d.ron", 2.0);
    scene.gravity = V3([0.0, 0.0, 0.0]);
    scene.solver.initial_state = InitialState::Given;
    let spatial = weights(&scene);
    print("2D", &planar);
    print("3D", &spatial);
    check_weights(&planar);
    check_weights(&spatial);
    let (a, b) = (all_weights(&planar), all_weights(&spatial));
    // The weights that are zero by construction (gyroscopic, rigid) are round-off in both.
    let worst = a
        .iter()
        .zip(&b)
        .filter(|(x, _)| **x > 1e-12)
        .map(|(x, y)| (x - y).abs() / x)
        .fold(0.0, f64::max);
    eprintln!("3D in plane against 2D: largest relative difference of a weight {worst:.2e}");
    assert!(worst < WORST_3D, "{worst:e}");
}

/// The choice confirmed at `tolerance` on a pilot of `scene` judging `sensors`, checked by an
/// independent run of the chosen scene against the full model's history `full`: it meets
/// the tolerance on the pilot's horizon, and the pilot measured the same error; with that
/// run's error.
fn confirmed(
    scene: &Scene,
    tolerance: f64,
    sensors: &[&str],
    full: &flexmbd::History,
) -> (TermChoice, f64) {
    let judged: Vec<String> = sensors.iter().map(|s| s.to_string()).collect();
    let p = pilot(scene, None, &judged).unwrap();
    let choice = p.confirm(tolerance, None).unwrap();
    for t in choice.rejected.iter().chain([&choice.chosen]) {
        eprintln!(
            "  rung {:<40} weight {:.2e} pilot error {:.3e} CPU {:.3} s work {} n²",
            t.label(),
            t.weight,
            t.error,
            t.cpu_seconds,
            t.kernel_work
        );
    }
    let weights_choice = choice.weights_choice().label();
    let e = error(&run_ok(&choice.apply(scene)), full, sensors);
    eprintln!(
        "confirmed at {tolerance:e}: {} (weights' choice {weights_choice}), pilot error {:.3e}, \
         run again {e:.3e}; kernel work {} of {}",
        choice.chosen.label(),
        choice.chosen.error,
        choice.chosen.kernel_work,
        choice.full_kernel_work
    );
    assert!(choice.chosen.error <= tolerance, "{choice:?}");
    assert!(e <= tolerance, "{}: {e:e}", choice.chosen.label());
    assert!(
        (e - choice.chosen.error).abs() <= 1e-9 * tolerance,
        "{e:e} vs {:e}",
        choice.chosen.error
    );
    for t in &choice.rejected {
        assert!(t.error > tolerance, "{t:?}");
    }
    (choice, e)
}

/// max over `sensors` of max |a − b| / range(b).
fn error(a: &flexmbd::History, b: &flexmbd::History, sensors: &[&str]) -> f64 {
    sensors
        .iter()
        .map(|s| {
            let (x, y) = (a.column(s).unwrap(), b.column(s).unwrap());
            let range = y.iter().cloned().fold(f64::MIN, f64::max)
                - y.iter().cloned().fold(f64::MAX, f64::min);
            x.iter()
                .zip(&y)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max)
                / range
        })
        .fold(0.0, f64::max)
}

fn run_ok(scene: &Scene) -> flexmbd::History {
    let (summary, h) = run(scene, |_| {}).unwrap();
    assert_eq!(summary.status, "ok", "{:?}", summary.message);
    h
}

#[test]
fn the_spin_up_beams_choice_against_the_full_model_and_the_cable() {
    // The scene as given: 20 s, spun up to 6 rad/s in 15 s.
    let mut scene = flexmbd_test_support::scenes::model("spin_up_beam_2d.ron");
    scene.solver.formulation = FormulationKind::Relative;
    let w = weights(&scene);
    print("20 s", &w);
    check_weights(&w);
    // Past ω₁ the second-order softening is balanced by the stiffening: its deformation
    // weight is of order (Ω/ω₁)² = 2.5 however small its share of the inertia force.
    let second = group(&w, TermGroup::SecondOrder);
    assert!(second.deformation_max > 0.5, "{second:?}");
    let full = run_ok(&scene);
    let sensors = ["tip_ux", "tip_uy"];
    let mut errors = Vec::new();
    for threshold in [1e-2, 1e-3] {
        let (chosen, terms) = apply_choice(&scene, std::slice::from_ref(&w), threshold).unwrap();
        let e = error(&run_ok(&chosen), &full, &sensors);
        eprintln!(
            "threshold {threshold:e}: {} → error {e:.3e} of the range",
            terms[0].1
        );
        errors.push((threshold, terms[0].1, e, chosen));
    }
    let (t1, c1, e1, _) = &errors[0];
    let (_, c2, e2, _) = &errors[1];
    assert_ne!(c1, c2);
    assert_eq!(c1.order, 2, "the second-order terms are kept at {t1}");
    assert!(e2 < e1, "{c2}: {e2:e} not below {c1}: {e1:e}");
    assert!(*e1 <= SPIN_UP_AMPLIFICATION * t1, "{c1}: {e1:e}");
    assert!(
        *e1 > *t1,
        "the weights' choice is over its threshold here: {c1}: {e1:e}"
    );

    // Confirmed: the weights' choice is run and rejected, a richer rung meets 1e-2.
    let (choice, _) = confirmed(&scene, *t1, &sensors, &full);
    assert_eq!(choice.rejected[0].choices[0].1, *c1, "{choice:?}");
    let rejected = choice.rejected[0].error;
    assert!(
        (rejected - e1).abs() <= 1e-9 * e1,
        "the pilot judges the weights' choice as the run does: {rejected:e} vs {e1:e}"
    );
    // A shorter pilot is no predictor of the whole run: over its first 10 s the same
    // choice moves the tip by 9.3e-3 of that horizon's range and is confirmed, yet over
    // the 20 s it moves it by 1.41e-2 (e1): the tolerance holds on the horizon judged only.
    let judged: Vec<String> = sensors.iter().map(|s| s.to_string()).collect();
    let short = pilot(&scene, Some(10.0), &judged)
        .unwrap()
        .confirm(*t1, None)
        .unwrap();
    eprintln!(
        "pilot over 10 s: confirmed {} at {:.3e}; over 20 s it errs {e1:.3e}",
        short.chosen.label(),
        short.chosen.error
    );
    assert_eq!(short.chosen.choices[0].1, *c1);
    assert!(short.chosen.error <= *t1 && *e1 > *t1);

    // Against the ANCF cable (16 elements, the same law, h and output times).
    let cable = run_spin_up(&CableSpec::spin_up_beam(Dim::Planar, 16), 1e-3, 20.0, 0.01).unwrap();
    let against_cable = |h: &flexmbd::History| {
        let (ux, uy) = (h.column("tip_ux").unwrap(), h.column("tip_uy").unwrap());
        assert_eq!(ux.len(), cable.t.len());
        let range = cable.max(1) - cable.min(1);
        (0..cable.t.len())
            .map(|k| {
                (ux[k] - cable.tip[k][0])
                    .abs()
                    .max((uy[k] - cable.tip[k][1]).abs())
            })
            .fold(0.0, f64::max)
            / range
    };
    let (e_full, e_chosen) = (against_cable(&full), against_cable(&run_ok(&errors[0].3)));
    eprintln!("against the ANCF cable: full {e_full:.3e}, {c1} {e_chosen:.3e} of u_y's range");
    assert!(e_chosen <= e_full + t1, "{e_chosen:e} vs {e_full:e}");
}

/// The double four-bar (docs/scenes.md §1) with its five bars flexible, run for 1 s.
fn four_bar() -> Scene {
    let mut scene = flexmbd_test_support::scenes::model("double_four_bar.ron");
    let sets: Vec<_> = ["crank1", "coupler1", "crank2", "coupler2", "crank3"]
        .iter()
        .map(|b| flexmbd::model::parse_set(&format!("bodies.{b}.flexible=true")).unwrap())
        .collect();
    scene.apply_sets(&sets).unwrap();
    scene.solver.formulation = FormulationKind::Relative;
    scene.solver.duration = 1.0;
    scene
}

#[test]
fn the_flexible_four_bar_weighs_each_bar_and_its_choice_meets_the_threshold() {
    let scene = four_bar();
    let w = weigh_terms(&scene, None).unwrap();
    assert_eq!(w.len(), 5);
    for b in &w {
        print(&b.body, b);
        check_weights(b);
    }
    let full = run_ok(&scene);
    let sensors = ["B0_x", "B0_y"];
    let mut last = f64::INFINITY;
    for threshold in [1e-2, 1e-4] {
        let (chosen, terms) = apply_choice(&scene, &w, threshold).unwrap();
        let e = error(&run_ok(&chosen), &full, &sensors);
        eprintln!("threshold {threshold:e}: {terms:?} → error {e:.3e} of the range");
        assert!(e <= threshold, "{threshold:e}: {e:e}");
        assert!(
            e <= last,
            "a lower threshold is no less accurate: {e:e} > {last:e}"
        );
        last = e;
    }
    // Confirmed at 1e-2: the weights' choice is run and met, no rung rejected.
    let (choice, _) = confirmed(&scene, 1e-2, &sensors, &full);
    assert!(choice.rejected.is_empty(), "{choice:?}");
    assert!(choice.chosen.kernel_work < choice.full_kernel_work);
}

#[test]
fn the_spatial_spin_up_beams_confirmed_choice_meets_its_tolerance() {
    // The scene as given: gravity, spun up to 6 rad/s in 15 s, 20 s.
    let mut scene = flexmbd_test_support::scenes::model("spin_up_beam_3d.ron");
    scene.solver.formulation = FormulationKind::Relative;
    let full = run_ok(&scene);
    let sensors = ["tip_ux", "tip_uy", "tip_uz"];
    // At 1e-2 the weights' choice (o2-nv) moves the tip by 1.41e-2, as on the 2D beam: the
    // confirmation rejects it; at 2e-2 it is kept, 1.41e-2 of the range.
    let (at_1, _) = confirmed(&scene, 1e-2, &sensors, &full);
    assert_eq!(at_1.rejected.len(), 1, "{at_1:?}");
    let (at_2, _) = confirmed(&scene, 2e-2, &sensors, &full);
    assert!(at_2.rejected.is_empty(), "{at_2:?}");
    assert_eq!(at_2.chosen.choices, at_1.rejected[0].choices);
    assert!(at_2.chosen.kernel_work < at_2.full_kernel_work);
}

/// The Iltis vehicle (docs/scenes.md §2) with its 12 beam bodies flexible, run for 1 s: it
/// settles from the static equilibrium and drives onto the ramp at 0.65 s, as in the
/// report's section.
fn iltis() -> Scene {
    let mut scene = flexmbd_test_support::scenes::model("iltis_vehicle.ron");
    let sets: Vec<_> = flexmbd_test_support::iltis::vehicle_flexible(12)
        .iter()
        .map(|s| flexmbd::model::parse_set(s).unwrap())
        .collect();
    scene.apply_sets(&sets).unwrap();
    scene.solver.formulation = FormulationKind::Relative;
    scene.solver.duration = 1.0;
    scene
}

#[test]
fn the_flexible_iltis_vehicles_confirmed_choice_meets_its_tolerance_and_drops_terms() {
    let scene = iltis();
    let full = run_ok(&scene);
    let sensors = ["chassis_z", "wheel_fl_z"];
    for tolerance in [1e-2, 1e-3] {
        let (choice, e) = confirmed(&scene, tolerance, &sensors, &full);
        assert_eq!(choice.chosen.choices.len(), 12, "{choice:?}");
        // Not the full set: every body drops terms, and the kernels do less work.
        for (body, terms) in &choice.chosen.choices {
            assert!(!terms.is_full(), "{body} keeps every term at {tolerance:e}");
        }
        assert!(choice.chosen.kernel_work < choice.full_kernel_work);
        // The run differs from the full model's: measured 1.0e-9 of the range at both
        // tolerances, the dropped second-order and gyroscopic terms weighing at most
        // 5.5e-4 on the vehicle's slow motion (so the margin to 1e-3 is wide, and the
        // choice is the weights' first, no rung rejected).
        assert!(
            e > 0.0,
            "{}: the run is the full model's",
            choice.chosen.label()
        );
        assert!(choice.rejected.is_empty(), "{choice:?}");
    }
}
