//! `displacement: true` sensors report the position minus the undeformed position, in
//! every formulation alike.

use flexmbd::model::{Axis, FormulationKind, Scene, Sensor, SensorKind};
use flexmbd::simulation;

fn pendulum() -> Scene {
    Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../models/flexible_pendulum.ron"
    ))
    .unwrap()
}

#[test]
fn displacement_is_position_minus_undeformed_position() {
    for formulation in [FormulationKind::Absolute, FormulationKind::Relative] {
        let mut scene = pendulum();
        scene.solver.formulation = formulation;
        scene.solver.duration = 0.5;
        for (name, axis) in [("tip_ux", Axis::X), ("tip_uy", Axis::Y)] {
            scene.sensors.push(Sensor {
                name: name.into(),
                kind: SensorKind::Position {
                    body: "bar".into(),
                    marker: "tip".into(),
                    component: axis,
                    frame: Some("bar".into()),
                },
                displacement: true,
            });
        }
        scene.validate().unwrap();
        assert_eq!(
            scene.sensor_offsets().iter().filter(|&&o| o != 0.0).count(),
            1,
            "only x of the tip is offset"
        );
        let (summary, history) = simulation::run(&scene, |_| {}).unwrap();
        assert_eq!(summary.status, "ok");
        let ux = history.column("tip_ux").unwrap();
        let uy = history.column("tip_uy").unwrap();
        let v = history.column("tip_v").unwrap(); // the tip's y in the bar frame, a plain position
        assert_eq!(ux[0], 0.0, "{formulation:?}: undeformed at t = 0");
        for (a, b) in uy.iter().zip(&v) {
            assert_eq!(a, b, "{formulation:?}: y has no offset");
        }
        // The bar swings and bends: the tip's axial displacement in the bar frame is the small
        // shortening of the bent bar, not its 1 m length.
        let max_ux = ux.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(
            max_ux < 1e-3,
            "{formulation:?}: tip axial displacement {max_ux}"
        );
    }
}

#[test]
fn displacement_on_a_velocity_sensor_is_refused() {
    let mut scene = pendulum();
    scene.sensors.push(Sensor {
        name: "bad".into(),
        kind: SensorKind::Velocity {
            body: "bar".into(),
            marker: "tip".into(),
            component: Axis::X,
            frame: None,
        },
        displacement: true,
    });
    let e = scene.validate().unwrap_err().to_string();
    assert!(e.contains("sensors[bad].displacement"), "{e}");
}
