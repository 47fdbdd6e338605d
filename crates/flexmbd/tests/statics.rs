//! The static start of a run (`solver.initial_state: StaticEquilibrium`, docs/methods.md §5.4
//! item 4) on floating-frame scenes: the linear cantilever droop against qL⁴/(8EI) in both
//! formulations, a pendulum that must turn to hang, and the scene option end to end.

use flexmbd::core::State;
use flexmbd::integrators::{StaticError, StaticSettings, solve_static};
use flexmbd::model::{FormulationKind, InitialState, Orientation, Scene, Stiffening};
use flexmbd::simulation::{compile, run};
use nalgebra::DVector;

fn models() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models")
}

/// Sensor values of a compiled scene at (t = 0, q, q̇ = 0).
fn sensors_at(scene: &Scene, q: &DVector<f64>) -> Vec<(String, f64)> {
    let mut f = compile(scene).unwrap();
    let mut out = vec![0.0; f.sensor_names().len()];
    let qd = DVector::zeros(q.len());
    f.sensors(State::new(0.0, q, &qd), &mut out);
    f.sensor_names().iter().cloned().zip(out).collect()
}

fn value(v: &[(String, f64)], name: &str) -> f64 {
    v.iter().find(|(n, _)| n == name).unwrap().1
}

/// The 3D spin-up beam (docs/scenes.md §5) with linear elasticity, hub held at θ = 0: the tip
/// droop is the linear cantilever's qL⁴/(8EI) = 1.2·9.81·10⁴/(8·1.4e4) = 1.05114 m up to
/// the truncation of the modal basis (the 20 Hermite elements are exact at the nodes for a
/// uniform load). Measured: 4 bending modes per plane (the scene's 8 normal modes)
/// 1.051027 m (−0.0042 %); 16 normal modes 1.051074 m (+0.0003 %), the same in both
/// formulations.
#[test]
fn linear_cantilever_droop_matches_the_closed_form() {
    let exact = 1.2 * 9.81 * 1e4 / (8.0 * 1.4e4);
    for form in [FormulationKind::Relative, FormulationKind::Absolute] {
        let mut errs = Vec::new();
        for modes in [8, 16] {
            let mut scene = Scene::load(models().join("spin_up_beam_3d.ron")).unwrap();
            scene.solver.stiffening = Stiffening::Linear;
            scene.solver.formulation = form;
            if let flexmbd::model::BodyModel::Beam(spec) = &mut scene.bodies[0].model {
                spec.normal_modes = modes;
            }
            let mut f = compile(&scene).unwrap();
            let sol = solve_static(f.as_mut(), 0.0, &StaticSettings::default()).unwrap();
            let v = sensors_at(&scene, &sol.q);
            let droop = -value(&v, "tip_uz");
            let err = (droop - exact) / exact;
            eprintln!(
                "{form:?}, {modes} bending modes: droop {droop:.6} m (exact {exact:.6}), error {:.4} %, \
                 u_x {:.3e}, u_y {:.3e}; {} iterations, {} evaluations, residual {:.1e}, ‖Φ‖ {:.1e}",
                err * 100.0,
                value(&v, "tip_ux"),
                value(&v, "tip_uy"),
                sol.counters.iterations,
                sol.counters.evaluations,
                sol.counters.residual,
                sol.counters.phi
            );
            // No axial or in-plane response in the linear model (the eigensolver's mixing of
            // the degenerate v/w pairs leaves ~1e-6 m in-plane with 16 modes).
            assert!(value(&v, "tip_uy").abs() < 1e-5);
            assert!(value(&v, "tip_ux").abs() < 1e-9);
            // The hub stays at θ = 0.
            assert!(value(&v, "theta").abs() < 1e-10);
            errs.push(err);
        }
        // Truncation error: measured −4.2e-5 with 4 modes per plane and 3e-6 with 16 modes.
        assert!(errs[0].abs() < 5e-5, "{errs:?}");
        assert!(errs[1].abs() < 5e-6, "{errs:?}");
    }
}

/// The flexible pendulum (`models/flexible_pendulum.ron`) placed 50° below the horizontal
/// turns to hang straight down, its bar undeformed in bending (the weight acts along it),
/// in both formulations: a constrained static problem with a large rotation.
#[test]
fn flexible_pendulum_turns_to_hang() {
    for form in [FormulationKind::Relative, FormulationKind::Absolute] {
        let mut scene = Scene::load(models().join("flexible_pendulum.ron")).unwrap();
        scene.bodies[0].orientation = Orientation::Angle(-50f64.to_radians());
        scene.solver.formulation = form;
        let mut f = compile(&scene).unwrap();
        let sol = solve_static(f.as_mut(), 0.0, &StaticSettings::default()).unwrap();
        let v = sensors_at(&scene, &sol.q);
        let (x, y, bend) = (value(&v, "tip_x"), value(&v, "tip_y"), value(&v, "tip_v"));
        eprintln!(
            "{form:?}: tip ({x:.3e}, {y:.9}), bending {bend:.1e}; {} iterations, {} load steps",
            sol.counters.iterations, sol.counters.load_steps
        );
        assert!(x.abs() < 1e-9 && (y + 1.0).abs() < 1e-9 && bend.abs() < 1e-9);
    }
}

/// The scene option end to end: the linear 3D beam started in static equilibrium and not
/// spun (Ωs = 0) stays put; started as given it swings down.
#[test]
fn static_start_stays_put_and_given_start_falls() {
    let mut scene = Scene::load(models().join("spin_up_beam_3d.ron")).unwrap();
    assert_eq!(scene.solver.initial_state, InitialState::StaticEquilibrium);
    scene.solver.stiffening = Stiffening::Linear;
    scene.solver.formulation = FormulationKind::Relative;
    scene.solver.duration = 0.5;
    for d in &mut scene.drivers {
        if let flexmbd::model::MotionLaw::SpinUp { omega_s, .. } = &mut d.law {
            *omega_s = 0.0;
        }
    }
    let (summary, h) = run(&scene, |_| {}).unwrap();
    assert_eq!(summary.status, "ok", "{:?}", summary.message);
    assert!(summary.static_iterations > 0);
    let uz = h.column("tip_uz").unwrap();
    let drift = uz.iter().map(|u| (u - uz[0]).abs()).fold(0.0, f64::max);
    eprintln!("static start: u_z(0) = {:.6} m, drift {drift:.1e} m", uz[0]);
    assert!(uz[0] < -1.0 && drift < 1e-9, "{drift}");

    scene.solver.initial_state = InitialState::Given;
    let (_, h) = run(&scene, |_| {}).unwrap();
    let uz = h.column("tip_uz").unwrap();
    assert_eq!(uz[0], 0.0);
    assert!(*uz.last().unwrap() < -0.3);
}

/// A rigid body on a ball joint, released 40° off the vertical: its turn about the vertical
/// through the pivot changes no force, a neutral direction of the static tangent
/// (`flexmbd_integrators::statics`, "Neutral directions"). The equilibrium must still be found,
/// with the centre of mass straight below the pivot (absolute formulation); the relative
/// formulation may instead meet its Cardan singularity, which must then be refused.
#[test]
fn ball_jointed_pendulum_hangs_below_its_pivot_despite_the_free_turn_about_the_vertical() {
    let text = r#"(
        name: "spherical pendulum", dim: Spatial, gravity: [0.0, 0.0, -9.81],
        ground: [(name: "O", position: [0.0, 0.0, 0.0])],
        bodies: [(name: "bob", orientation: AxisAngle(axis: [0.3, 1.0, 0.0], angle: 0.7),
            model: Rigid(mass: 2.0, center_of_mass: [0.05, 0.02, -0.5],
                         inertia: Diagonal([0.05, 0.04, 0.01])),
            markers: [(name: "O", position: [0.0, 0.0, 0.0]), (name: "c", position: [0.05, 0.02, -0.5])])],
        joints: [(name: "ball", kind: Spherical, body1: "ground", marker1: "O", body2: "bob", marker2: "O")],
        sensors: [
            (name: "cx", kind: Position(body: "bob", marker: "c", component: X)),
            (name: "cy", kind: Position(body: "bob", marker: "c", component: Y)),
            (name: "cz", kind: Position(body: "bob", marker: "c", component: Z)),
        ],
        solver: (step: 1e-3, duration: 0.01),
    )"#;
    let arm = (0.05f64.powi(2) + 0.02f64.powi(2) + 0.25).sqrt();
    for form in [FormulationKind::Absolute, FormulationKind::Relative] {
        let mut scene = Scene::from_ron_str(text, "spherical_pendulum.ron").unwrap();
        scene.solver.formulation = form;
        let mut f = compile(&scene).unwrap();
        let sol = match solve_static(f.as_mut(), 0.0, &StaticSettings::default()) {
            Ok(sol) => sol,
            // The relative formulation's Cardan angles: Newton reaches their singularity,
            // where the turn's generalized forces vanish; that must be refused, never
            // reported as an equilibrium.
            Err(e @ StaticError::CoordinateSingularity { .. })
                if form == FormulationKind::Relative =>
            {
                eprintln!("{form:?}: {e}");
                continue;
            }
            Err(e) => panic!("{form:?}: {e}"),
        };
        let v = sensors_at(&scene, &sol.q);
        let (x, y, z) = (value(&v, "cx"), value(&v, "cy"), value(&v, "cz"));
        eprintln!("{form:?}: centre of mass ({x:.3e}, {y:.3e}, {z:.12}), arm {arm:.12}");
        assert!(
            x.hypot(y) < 1e-9,
            "{form:?}: not below the pivot: ({x}, {y})"
        );
        assert!(
            (z + arm).abs() < 1e-9,
            "{form:?}: z = {z}, expected {}",
            -arm
        );
    }
}

/// A free base with a hinged arm and a stretched spring between them, no gravity: every rigid
/// motion of the pair is neutral, and the equilibrium (the spring at its free length) is a
/// family. The statics take back the drift along the neutral motions (`flexmbd_integrators`
/// `neutral`): the displacement from the guess is M-orthogonal to them, so the pair's mass
/// centre stays where it was (a translation is neutral exactly) — exactly in the absolute
/// formulation, to second order in the relative one.
#[test]
fn a_free_system_relaxes_about_its_fixed_mass_centre() {
    let text = r#"(
        name: "free pair", dim: Spatial, gravity: [0.0, 0.0, 0.0],
        ground: [(name: "o0", position: [0.0, 0.0, 0.0])],
        bodies: [
            (name: "base", model: Rigid(mass: 3.0, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([0.1, 0.2, 0.25])),
             markers: [(name: "o", position: [0.0, 0.0, 0.0]), (name: "hinge", position: [0.1, 0.2, 0.0]),
                       (name: "top", position: [0.0, 0.0, 0.6])]),
            (name: "arm", origin: [0.1, 0.2, 0.0],
             model: Rigid(mass: 1.0, center_of_mass: [0.0, 0.3, 0.0], inertia: Diagonal([0.01, 0.002, 0.01])),
             markers: [(name: "hinge", position: [0.0, 0.0, 0.0]), (name: "c", position: [0.0, 0.3, 0.0]),
                       (name: "tip", position: [0.0, 0.6, 0.0])]),
        ],
        joints: [
            (name: "float", kind: Free, body1: "ground", marker1: "o0", body2: "base", marker2: "o"),
            (name: "hinge", kind: Revolute(axis: Some([1.0, 0.0, 0.0])), body1: "base", marker1: "hinge", body2: "arm", marker2: "hinge"),
        ],
        forces: [SpringDamper(name: "spring", body1: "base", marker1: "top", body2: "arm", marker2: "tip",
                              stiffness: 400.0, damping: 0.0, free_length: Some(0.95))],
        sensors: [
            (name: "base_x", kind: Position(body: "base", marker: "o", component: X)),
            (name: "base_y", kind: Position(body: "base", marker: "o", component: Y)),
            (name: "base_z", kind: Position(body: "base", marker: "o", component: Z)),
            (name: "arm_x", kind: Position(body: "arm", marker: "c", component: X)),
            (name: "arm_y", kind: Position(body: "arm", marker: "c", component: Y)),
            (name: "arm_z", kind: Position(body: "arm", marker: "c", component: Z)),
            (name: "hinge", kind: JointCoordinate(joint: "hinge")),
        ],
        solver: (step: 1e-3, duration: 0.01),
    )"#;
    // Mass centre at the start: (3·0 + 1·(0.1, 0.5, 0)) / 4.
    let start = [0.1 / 4.0, 0.5 / 4.0, 0.0];
    let mut hinges = Vec::new();
    for form in [FormulationKind::Absolute, FormulationKind::Relative] {
        let mut scene = Scene::from_ron_str(text, "free_pair.ron").unwrap();
        scene.solver.formulation = form;
        let mut f = compile(&scene).unwrap();
        let sol = solve_static(f.as_mut(), 0.0, &StaticSettings::default()).unwrap();
        let v = sensors_at(&scene, &sol.q);
        let hinge = value(&v, "hinge");
        eprintln!("{form:?}: the hinge turned {hinge:.6} rad");
        assert!(hinge.abs() > 0.01, "{form:?}: the spring did not relax");
        hinges.push(hinge);
        // Exact in natural coordinates (M constant, a translation linear in q). In relative
        // ones the kinetic metric varies with q, so the centre is kept only to second order in
        // the relaxation (measured: 3.8·10⁻⁴ m for these 0.15 rad): printed, and the shape of
        // the equilibrium (the hinge angle) checked against the absolute formulation instead.
        let exact = form == FormulationKind::Absolute;
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            let centre = (3.0 * value(&v, &format!("base_{axis}"))
                + value(&v, &format!("arm_{axis}")))
                / 4.0;
            eprintln!(
                "{form:?}: mass centre {axis} {centre:.6e} (start {:.6e})",
                start[k]
            );
            assert!(
                !exact || (centre - start[k]).abs() < 1e-9,
                "{form:?}: the mass centre moved along {axis}"
            );
        }
    }
    assert!(
        (hinges[0] - hinges[1]).abs() < 1e-8,
        "the formulations relaxed to different shapes: {hinges:?}"
    );
}

/// `models/double_pendulum_3d.ron` in the relative formulation: Newton ends near the ball
/// joint's Cardan singularity, where the generalized forces are 4e-10 while the bodies are
/// 0.34 N out of balance (a run from there diverged in its first step). That point must be
/// refused, never returned as an equilibrium; the absolute formulation's is one.
#[test]
fn a_point_near_a_cardan_singularity_is_not_reported_as_an_equilibrium() {
    let mut scene = Scene::load(models().join("double_pendulum_3d.ron")).unwrap();
    scene.solver.formulation = FormulationKind::Relative;
    let mut f = compile(&scene).unwrap();
    match solve_static(f.as_mut(), 0.0, &StaticSettings::default()) {
        Err(
            e @ (StaticError::CoordinateSingularity { .. } | StaticError::NearlySingular { .. }),
        ) => eprintln!("refused: {e}"),
        Ok(sol) => panic!(
            "a false equilibrium: residual {:e} at q = {:?}",
            sol.counters.residual,
            sol.q.as_slice()
        ),
        Err(e) => panic!("another error: {e}"),
    }
    scene.solver.formulation = FormulationKind::Absolute;
    let mut f = compile(&scene).unwrap();
    solve_static(f.as_mut(), 0.0, &StaticSettings::default()).unwrap();
}
