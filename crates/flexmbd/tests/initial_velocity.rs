//! The scene-wide initial velocity (`Scene::initial_velocity`, `flexmbd_model`'s
//! `initial_velocity` module): every body translating at v from the start, after a static
//! equilibrium or beside the bodies' own velocities, in both formulations.

use flexmbd::model::{FormulationKind, InitialState, Scene};
use flexmbd::simulation::run;

/// Two bodies on a free base and a hinge about x, a spring from the arm to the base, all in
/// the plane x = 0 through the base's centre of mass with principal axes along x, no gravity; the arm is set swinging (a given start) or the pair is at rest (a static start,
/// every direction of the free base neutral): nothing acts along x, so every point moves along
/// x at exactly v.
const SCENE: &str = r#"(
    name: "free pair", dim: Spatial, gravity: [0.0, 0.0, 0.0],
    initial_velocity: [5.0, 0.0, 0.0],
    bodies: [
        (name: "base", model: Rigid(mass: 3.0, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([0.1, 0.2, 0.25])),
         markers: [(name: "o", position: [0.0, 0.0, 0.0]), (name: "hinge", position: [0.0, 0.2, 0.0]),
                   (name: "top", position: [0.0, 0.0, 0.6])]),
        (name: "arm", origin: [0.0, 0.2, 0.0],
         model: Rigid(mass: 1.0, center_of_mass: [0.0, 0.3, 0.0], inertia: Diagonal([0.01, 0.002, 0.01])),
         markers: [(name: "hinge", position: [0.0, 0.0, 0.0]), (name: "tip", position: [0.0, 0.6, 0.0])],
         velocity: (angular: [2.0, 0.0, 0.0])),
    ],
    joints: [
        (name: "float", kind: Free, body1: "ground", marker1: "o0", body2: "base", marker2: "o"),
        (name: "hinge", kind: Revolute(axis: Some([1.0, 0.0, 0.0])), body1: "base", marker1: "hinge", body2: "arm", marker2: "hinge"),
    ],
    ground: [(name: "o0", position: [0.0, 0.0, 0.0])],
    forces: [SpringDamper(name: "spring", body1: "base", marker1: "top", body2: "arm", marker2: "tip", stiffness: 400.0, damping: 2.0)],
    sensors: [
        (name: "base_x", kind: Position(body: "base", marker: "o", component: X)),
        (name: "tip_x", kind: Position(body: "arm", marker: "tip", component: X)),
        (name: "tip_y", kind: Position(body: "arm", marker: "tip", component: Y)),
        (name: "tip_vx", kind: Velocity(body: "arm", marker: "tip", component: X)),
    ],
    solver: (step: 1e-3, duration: 0.5, output_interval: Some(0.1)),
)"#;

#[test]
fn every_body_moves_forward_at_the_scene_velocity_in_both_formulations_and_starts() {
    for form in [FormulationKind::Absolute, FormulationKind::Relative] {
        for start in [InitialState::Given, InitialState::StaticEquilibrium] {
            let mut scene = Scene::from_ron_str(SCENE, "free_pair.ron").unwrap();
            scene.solver.formulation = form;
            scene.solver.initial_state = start;
            let (summary, history) = run(&scene, |_| {}).unwrap();
            assert_eq!(
                summary.status, "ok",
                "{form:?} {start:?}: {:?}",
                summary.message
            );
            let column = |name: &str| history.header.iter().position(|n| n == name).unwrap() - 1;
            let (bx, tx, tv) = (column("base_x"), column("tip_x"), column("tip_vx"));
            for row in &history.rows {
                let t = row[0];
                let expect = 5.0 * t;
                assert!(
                    (row[bx + 1] - expect).abs() < 1e-9,
                    "{form:?} {start:?}: base x {} at t = {t}",
                    row[bx + 1]
                );
                assert!(
                    (row[tx + 1] - expect).abs() < 1e-9,
                    "{form:?} {start:?}: tip x {} at t = {t}",
                    row[tx + 1]
                );
                assert!(
                    (row[tv + 1] - 5.0).abs() < 1e-9,
                    "{form:?} {start:?}: tip vx {}",
                    row[tv + 1]
                );
            }
        }
    }
}

#[test]
fn the_initial_velocity_is_a_settable_validated_scene_value() {
    let mut scene = Scene::from_ron_str(SCENE, "free_pair.ron").unwrap();
    scene
        .apply_sets(&[flexmbd::model::parse_set("initial_velocity.0=10").unwrap()])
        .unwrap();
    assert_eq!(scene.initial_velocity.0, [10.0, 0.0, 0.0]);
    let bad = SCENE.replace("[5.0, 0.0, 0.0]", "[5.0, 1e300, 0.0]");
    let e = Scene::from_ron_str(&bad, "free_pair.ron")
        .unwrap()
        .validate()
        .unwrap_err()
        .to_string();
    assert!(e.contains("initial_velocity") && e.contains("1e300"), "{e}");
}
