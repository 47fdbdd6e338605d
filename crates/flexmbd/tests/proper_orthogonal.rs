//! Proper orthogonal modes from a pilot run (`mode_selection: ProperOrthogonal`,
//! docs/methods.md §1.6): what the pilot sees makes the basis, both inertia routes run the
//! basis alike, and a failed pilot or a body run rigid is handled by name.

use flexmbd::Simulation;
use flexmbd::fe::ReferenceFrame;
use flexmbd::model::{BodyModel, Constraint, Marker, Scene, V3};
use flexmbd::simulation::run;

/// `file` of `models/`, changed by `edit`, then by `sets` (and validated again).
fn scene(file: &str, edit: impl FnOnce(&mut Scene), sets: &[(&str, &str)]) -> Scene {
    let path = format!("{}/../../models/{file}", env!("CARGO_MANIFEST_DIR"));
    let mut scene = Scene::load(path).unwrap();
    edit(&mut scene);
    let sets: Vec<(String, String)> = sets
        .iter()
        .map(|(p, v)| (p.to_string(), v.to_string()))
        .collect();
    scene.apply_sets(&sets).unwrap();
    scene
}

/// The flexible pendulum's bar simply supported — pinned at its end A, its end B held on
/// the ground's x axis (to µm: a link of 1 km from below), its frame the chord A–B — and
/// released under gravity, its `modes` normal modes chosen by `selection`.
fn supported_bar(selection: &str, modes: &str) -> Scene {
    let roller = |scene: &mut Scene| {
        if let BodyModel::Beam(spec) = &mut scene.bodies[0].model {
            spec.frame = ReferenceFrame::Chord { a: 0, b: 10 };
        }
        // A roller: a link 1 km long from far below B (B moves by µm).
        scene.ground.push(Marker {
            name: "below_B".into(),
            position: V3([1.0, -1000.0, 0.0]),
        });
        scene.constraints.push(Constraint::Distance {
            name: "roller".into(),
            body1: "ground".into(),
            marker1: "below_B".into(),
            body2: "bar".into(),
            marker2: "tip".into(),
            length: None,
        });
    };
    scene(
        "flexible_pendulum.ron",
        roller,
        &[
            ("bodies.bar.model.Beam.mode_selection", selection),
            ("bodies.bar.model.Beam.normal_modes", modes),
            ("solver.duration", "0.5"),
        ],
    )
}

#[test]
fn a_symmetric_load_gives_only_symmetric_proper_orthogonal_modes() {
    // Gravity on the simply supported bar is symmetric about mid-span: the pilot (the 4
    // lowest modes) moves modes 1 and 3 and leaves the antisymmetric modes 2 and 4 at rest,
    // so the two proper orthogonal modes are modes 1 and 3, where the lowest two are 1 and 2.
    let lowest = Simulation::new(&supported_bar("LowestFrequency", "4")).unwrap();
    let pod = Simulation::new(&supported_bar("ProperOrthogonal", "2")).unwrap();
    let hz = |sim: &Simulation| -> Vec<f64> {
        let inventory = sim.mode_inventory("bar").unwrap();
        inventory
            .normal_modes
            .iter()
            .map(|m| m.frequency_hz)
            .collect()
    };
    let (f_lowest, f_pod) = (hz(&lowest), hz(&pod));
    println!("lowest: {f_lowest:?} Hz; proper orthogonal: {f_pod:?} Hz");
    assert_eq!(f_pod.len(), 2);
    for (chosen, mode) in f_pod.iter().zip([f_lowest[0], f_lowest[2]]) {
        assert!(
            (chosen - mode).abs() < 1e-9 * mode,
            "{chosen} Hz against {mode} Hz"
        );
    }
}

#[test]
fn initial_modes_on_proper_orthogonal_modes_are_refused_by_name() {
    let start_deformed = |scene: &mut Scene| scene.bodies[0].initial_modes = vec![1e-3];
    let scene = scene(
        "flexible_pendulum.ron",
        start_deformed,
        &[
            ("bodies.bar.model.Beam.mode_selection", "ProperOrthogonal"),
            ("bodies.bar.model.Beam.normal_modes", "1"),
        ],
    );
    let e = Simulation::new(&scene).err().expect("refused").to_string();
    println!("{e}");
    assert!(e.contains("bodies[bar].initial_modes") && e.contains("[0.001]"));
}

#[test]
fn both_inertia_routes_run_the_same_proper_orthogonal_modes() {
    let bars = ["crank1", "coupler1", "crank2", "coupler2", "crank3"];
    let history = |inertia: &str| {
        let mut sets: Vec<(String, String)> = vec![
            ("solver.duration".into(), "1".into()),
            ("solver.inertia".into(), inertia.into()),
        ];
        for b in bars {
            sets.push((format!("bodies.{b}.flexible"), "true".into()));
            sets.push((
                format!("bodies.{b}.model.Beam.mode_selection"),
                "ProperOrthogonal".into(),
            ));
            sets.push((format!("bodies.{b}.model.Beam.normal_modes"), "2".into()));
        }
        let sets: Vec<(&str, &str)> = sets.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
        let (summary, history) = run(&scene("double_four_bar.ron", |_| {}, &sets), |_| {}).unwrap();
        assert_eq!(summary.status, "ok", "{:?}", summary.message);
        (
            history.column("B0_x").unwrap(),
            history.column("B0_y").unwrap(),
        )
    };
    let (a, b) = (history("BMatrix"), history("ShapeIntegrals"));
    let worst =
        a.0.iter()
            .zip(&b.0)
            .chain(a.1.iter().zip(&b.1))
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
    println!("B0: largest difference between the routes {worst:.2e} m");
    assert!(worst < 1e-9);
}

#[test]
fn a_failed_pilot_names_the_body_and_the_failure() {
    let scene = scene(
        "flexible_pendulum.ron",
        |_| {},
        &[
            ("bodies.bar.model.Beam.mode_selection", "ProperOrthogonal"),
            ("bodies.bar.model.Beam.normal_modes", "1"),
            // A quarter-second step: the pilot's leading matrix turns singular.
            ("solver.step", "0.25"),
        ],
    );
    let e = Simulation::new(&scene)
        .err()
        .expect("the pilot is refused")
        .to_string();
    println!("{e}");
    for part in [
        "body `bar`",
        "mode_selection",
        "ProperOrthogonal",
        "pilot run",
        "failed: the leading matrix is singular",
    ] {
        assert!(e.contains(part), "`{part}` missing from: {e}");
    }
}

#[test]
fn a_beam_run_rigid_needs_no_pilot() {
    // The bar's modal sensor goes: a rigid bar has no modal coordinates.
    let no_modal = |scene: &mut Scene| scene.sensors.retain(|s| s.name != "y0");
    let scene = scene(
        "flexible_pendulum.ron",
        no_modal,
        &[
            ("bodies.bar.model.Beam.mode_selection", "ProperOrthogonal"),
            ("bodies.bar.flexible", "false"),
            ("bodies.bar.model.Beam.pilot_duration", "1e7"),
            ("solver.duration", "0.1"),
        ],
    );
    // A pilot of 1e7 s would be refused: there is none.
    let (summary, _) = run(&scene, |_| {}).unwrap();
    assert_eq!(summary.status, "ok", "{:?}", summary.message);
    assert_eq!(
        summary.n_coordinates,
        Simulation::new(&scene).unwrap().n_coordinates()
    );
}

#[test]
fn a_pilot_longer_than_the_scene_runs_to_the_scene_end() {
    // Unbounded, 1e7 s at 1 ms would be 1e10 steps: refused, over the step limit.
    let history = |pilot: Option<&str>| {
        let mut sets = vec![
            ("bodies.bar.model.Beam.mode_selection", "ProperOrthogonal"),
            ("bodies.bar.model.Beam.normal_modes", "1"),
            ("solver.duration", "0.2"),
        ];
        if let Some(d) = pilot {
            sets.push(("bodies.bar.model.Beam.pilot_duration", d));
        }
        let (summary, history) =
            run(&scene("flexible_pendulum.ron", |_| {}, &sets), |_| {}).unwrap();
        assert_eq!(summary.status, "ok", "{:?}", summary.message);
        history.column("tip_y").unwrap()
    };
    assert_eq!(history(Some("1e5")), history(None));
}
