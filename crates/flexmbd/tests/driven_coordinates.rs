//! Driven joints taken out of the unknowns (`flexmbd_core::driven`, `solver.drivers`): the
//! driven coordinate follows its law exactly, the unknowns and rows it cost are gone, and
//! the motion is the one the driver rows give, as near a converged reference as they come.
//!
//! The reference of each case is the constrained run at a tenth of the step and a tight
//! Newton tolerance; the trapezoidal rule's error at the scene's step is what both runs
//! carry, so the eliminated run must be at least as near the reference as the constrained
//! one (the driver rows' projections move the modal accelerations, the law does not).

use flexmbd::model::{Driver, DriverHandling, FormulationKind, MotionLaw, Scene, Stiffening};
use flexmbd::output::History;
use flexmbd::simulation::run;
use flexmbd_test_support::scenes::model;

/// The run of `scene` with its drivers handled as `drivers`: its coordinate and row counts
/// and its history.
fn history(scene: &Scene, drivers: DriverHandling) -> ((usize, usize), History) {
    let mut scene = scene.clone();
    scene.solver.drivers = drivers;
    let (summary, history) = run(&scene, |_| {}).unwrap();
    assert_eq!(
        summary.status, "ok",
        "{}: {:?}",
        scene.name, summary.message
    );
    ((summary.n_coordinates, summary.n_constraints), history)
}

/// The reference: driver rows, a tenth of the step, Newton tolerance 1e-12, the same
/// output instants.
fn reference(scene: &Scene) -> History {
    let mut fine = scene.clone();
    let h = fine.solver.step;
    fine.solver.output_interval = Some(fine.solver.output_interval.unwrap_or(h));
    fine.solver.step = h / 10.0;
    fine.solver.newton_tolerance = 1e-12;
    history(&fine, DriverHandling::Constraint).1
}

/// Largest |a − b| of sensor `name` over the output instants.
fn max_difference(a: &History, b: &History, name: &str) -> f64 {
    let (a, b) = (a.column(name).unwrap(), b.column(name).unwrap());
    assert_eq!(a.len(), b.len(), "{name}: rows");
    a.iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Below this (m or rad) a difference from the reference is the Newton tolerance's
/// (ε_q = 1e-9 relative to max(‖q‖∞, 1), a few steps' worth), not the step's error.
const TOLERANCE_FLOOR: f64 = 5e-9;

/// Checks one driven scene: the driven coordinates and their rows leave the unknowns
/// (`removed` of each); in every sensor of `sensors` the eliminated run's distance from the
/// reference is of the order of the constrained run's (the two are different second-order
/// discretisations of one problem: measured 0.51 to 1.18 times it) and at most `near`; and
/// in the first sensor it falls as h² (a quarter at half the step).
fn check(scene: &Scene, removed: usize, sensors: &[&str], near: f64) {
    let what = format!("{} ({:?})", scene.name, scene.solver.formulation);
    let ((n_e, m_e), eliminated) = history(scene, DriverHandling::Eliminated);
    let ((n_c, m_c), constrained) = history(scene, DriverHandling::Constraint);
    assert_eq!((n_e + removed, m_e + removed), (n_c, m_c), "{what}: n, m");
    let fine = reference(scene);
    for name in sensors {
        let e = max_difference(&eliminated, &fine, name);
        let c = max_difference(&constrained, &fine, name);
        eprintln!("{what} {name}: eliminated {e:.3e}, driver rows {c:.3e} from the reference");
        assert!(
            e <= 1.25 * c + TOLERANCE_FLOOR,
            "{what} {name}: eliminated {e:.3e} from the reference, driver rows {c:.3e}"
        );
        assert!(e <= near, "{what} {name}: {e:.3e} from the reference");
    }
    let mut half = scene.clone();
    half.solver.output_interval = Some(scene.solver.output_interval.unwrap_or(scene.solver.step));
    half.solver.step /= 2.0;
    let (_, halved) = history(&half, DriverHandling::Eliminated);
    let (e, e2) = (
        max_difference(&eliminated, &fine, sensors[0]),
        max_difference(&halved, &fine, sensors[0]),
    );
    eprintln!("{what} {}: {e:.3e} at h, {e2:.3e} at h/2", sensors[0]);
    assert!(
        e2 < e / 3.0,
        "{what} {}: {e:.3e} at h, {e2:.3e} at h/2",
        sensors[0]
    );
}

/// The 2D spin-up beam (4 bending modes, linear, Ωs = 2 rad/s, the first 6 s of the
/// spin-up) is its modes alone in either formulation: the hub angle (relative) or the unit
/// vector u (absolute) follows the law, with no constraint left.
#[test]
fn the_spin_up_beam_is_its_modes_alone() {
    let mut scene = model("spin_up_beam_2d.ron");
    scene.solver.stiffening = Stiffening::Linear;
    scene.solver.duration = 6.0;
    scene
        .apply_sets(&[
            flexmbd::model::parse_set("drivers.spin.law.SpinUp.omega_s=2").unwrap(),
            flexmbd::model::parse_set("bodies.beam.model.Beam.axial_modes=0").unwrap(),
        ])
        .unwrap();
    for (form, removed) in [
        (FormulationKind::Relative, 1),
        (FormulationKind::Absolute, 2),
    ] {
        scene.solver.formulation = form;
        check(&scene, removed, &["tip_uy"], 5e-6);
        // The hub angle is the law's, to round-off.
        let (_, h) = history(&scene, DriverHandling::Eliminated);
        for (t, theta) in h
            .column("t")
            .unwrap()
            .iter()
            .zip(h.column("theta").unwrap())
        {
            let law = MotionLaw::SpinUp {
                omega_s: 2.0,
                t_s: 15.0,
            };
            assert!((theta - law.eval(*t).0).abs() < 1e-12, "{form:?} θ({t})");
        }
    }
}

/// The 3D spin-up beam (FNL1, from its static equilibrium under gravity): the driven hub
/// joint leaves the unknowns likewise, in relative coordinates its angle, in natural ones the
/// beam's whole frame {r0, u, v, w} with its twelve rows. Both formulations then have the
/// beam's modes alone and the same equations: their histories agree to round-off.
#[test]
fn the_3d_spin_up_beam_drops_its_hub_angle() {
    let mut scene = model("spin_up_beam_3d.ron");
    scene.solver.duration = 3.0;
    let mut histories = Vec::new();
    for (form, removed) in [
        (FormulationKind::Relative, 1),
        (FormulationKind::Absolute, 12),
    ] {
        scene.solver.formulation = form;
        check(&scene, removed, &["tip_uy", "tip_uz"], 1e-5);
        histories.push(history(&scene, DriverHandling::Eliminated).1);
    }
    for name in ["tip_ux", "tip_uy", "tip_uz"] {
        let d = max_difference(&histories[0], &histories[1], name);
        assert!(d < 1e-12, "{name}: relative and absolute {d:e} m apart");
    }
}

/// A driven joint inside closed loops (relative double four-bar, its first crank's tree
/// joint driven harmonically, the second crank flexible so that the motion is not the
/// driver's kinematics alone): the cut joints' rows stay, with Φ_t and c taking the driven
/// rate and acceleration through their driven column, which the energy (velocities) and
/// the flexible crank's motion read. The scene starts its cranks at ω = −1 rad/s and the law
/// at θ̇(0) = 0.94 rad/s: the start rates are projected as the driver rows would project
/// them (`start_velocities_for_the_law`). The two runs then make the same Newton iterations
/// and agree to the Newton tolerance: the energy within 2.2e-6 J (tightening the tolerance
/// of the constrained run to 1e-12 moves it 2.1e-6 J), B0 within 5.2e-13 m.
#[test]
fn a_driven_crank_inside_the_loops() {
    let mut scene = model("double_four_bar.ron");
    scene.solver.formulation = FormulationKind::Relative;
    scene.solver.duration = 1.0;
    scene.solver.output_interval = Some(0.01);
    scene
        .apply_sets(&[flexmbd::model::parse_set("bodies.crank2.flexible=true").unwrap()])
        .unwrap();
    scene.drivers.push(Driver {
        name: "crank".into(),
        joint: "A0".into(),
        law: MotionLaw::Harmonic {
            amplitude: 0.3,
            frequency: 0.5,
            phase: 0.0,
        },
    });
    let summary = |drivers| {
        let mut s = scene.clone();
        s.solver.drivers = drivers;
        run(&s, |_| {}).unwrap()
    };
    let (eliminated, e) = summary(DriverHandling::Eliminated);
    let (constrained, c) = summary(DriverHandling::Constraint);
    assert_eq!(eliminated.status, "ok");
    assert_eq!(
        (eliminated.n_coordinates + 1, eliminated.n_constraints + 1),
        (constrained.n_coordinates, constrained.n_constraints)
    );
    assert_eq!(eliminated.newton_iterations, constrained.newton_iterations);
    let energy = max_difference(&e, &c, "energy");
    let b0 = max_difference(&e, &c, "B0_x").max(max_difference(&e, &c, "B0_y"));
    eprintln!("energy {energy:.3e} J, B0 {b0:.3e} m apart");
    assert!(energy < 1e-5, "energy {energy:e} J apart");
    assert!(b0 < 1e-9, "B0 {b0:e} m apart");
}
