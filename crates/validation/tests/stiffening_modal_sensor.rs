//! FNL2 renumbers a beam's modal coordinates (every node's axial DOF becomes a static mode,
//! docs/methods.md §6.2 correction); a `Modal` sensor must keep naming the mode it named.
//! Check: the first bending mode's coordinate on the 2D spin-up beam (docs/scenes.md §5) over the
//! first 3 s, where stiffening barely matters yet, is the same under FNL1 and FNL2 (same
//! cantilever bending shape: the straight beam's bending modes have no axial rows).

use flexmbd::model::{Scene, Sensor, SensorKind, Stiffening};
use flexmbd::simulation::run;
use flexmbd_model::BodyModel;

fn scene() -> Scene {
    let mut s = flexmbd_test_support::scenes::model("spin_up_beam_2d.ron");
    s.sensors.push(Sensor {
        name: "bend1".into(),
        kind: SensorKind::Modal {
            body: "beam".into(),
            index: 0,
        },
        displacement: false,
    });
    s.solver.duration = 3.0;
    s
}

fn without_axial_modes(mut s: Scene) -> Scene {
    for b in &mut s.bodies {
        if let BodyModel::Beam(spec) = &mut b.model {
            spec.axial_modes = 0;
        }
    }
    s
}

fn bend1(mut s: Scene, st: Stiffening) -> Vec<f64> {
    s.solver.stiffening = st;
    let (_, h) = run(&s, |_| {}).unwrap();
    h.column("bend1").unwrap()
}

#[test]
fn fnl2_modal_sensor_names_the_same_mode() {
    let s = without_axial_modes(scene());
    let a = bend1(s.clone(), Stiffening::Fnl1);
    let b = bend1(s, Stiffening::Fnl2);
    let peak = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = a
        .iter()
        .zip(&b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    eprintln!("first bending coordinate: peak {peak:.4e}, FNL1 − FNL2 {diff:.3e}");
    assert!(peak > 1e-3, "{peak}");
    assert!(diff < 0.05 * peak, "{diff} vs {peak}");
}

#[test]
fn fnl2_refuses_a_modal_sensor_it_cannot_re_point() {
    // The model file keeps 2 axial normal modes for FNL1: under FNL2 they vanish and the
    // normal modes' order is only known after the eigen-solution.
    let mut s = scene();
    s.solver.stiffening = Stiffening::Fnl2;
    let e = run(&s, |_| {}).unwrap_err().to_string();
    assert!(e.contains("bend1") && e.contains("axial_modes"), "{e}");
}
