//! Scenes built in code (`flexmbd::model::builder`): the double four-bar of
//! `models/double_four_bar.ron` (docs/scenes.md §1) written with the builders is the same scene
//! as the file, runs to the same B0 history bit for bit, and goes through RON text and back
//! unchanged; a builder's mistake is refused by the same validation, naming the field.

use std::f64::consts::FRAC_PI_2;

use flexmbd::core::Dim;
use flexmbd::fe::{BeamBodySpec, Dof, Material, NodeDof, Section};
use flexmbd::model::builder::{BodyBuilder, SceneBuilder};
use flexmbd::model::{
    Axis, GROUND, Joint, JointKind, Orientation, Scene, Sensor, SensorKind, Solver,
};

fn models() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models")
}

/// One 1 m steel bar of the four-bar: 10 elements, frame clamped at the first pin, the second
/// pin's two translations as static modes, 2 normal modes (scenes.md §1).
fn bar_spec() -> BeamBodySpec {
    let mut spec = BeamBodySpec::straight(Dim::Planar, steel(), bar_section(), 1.0, 10);
    spec.boundary = vec![
        NodeDof {
            node: 10,
            dof: Dof::Ux,
        },
        NodeDof {
            node: 10,
            dof: Dof::Uy,
        },
    ];
    spec.normal_modes = 2;
    spec
}

/// Steel as scenes.md §1 gives it.
fn steel() -> Material {
    Material {
        young_modulus: 2.1e11,
        density: 7850.0,
        poisson_ratio: Some(0.3),
        shear_modulus: None,
    }
}

/// 1 kg over 1 m of steel: A = m/(ρL), a solid circle (scenes.md §1).
fn bar_section() -> Section {
    Section::General {
        area: 1.2739e-4,
        iy: 1.2914e-9,
        iz: 1.2914e-9,
        torsion_j: 2.5828e-9,
    }
}

/// A bar at `origin` turned by `angle`, rigid, with its pins A and B and a velocity guess.
fn bar(
    name: &str,
    origin: [f64; 3],
    angle: f64,
    linear: [f64; 3],
    angular: [f64; 3],
) -> BodyBuilder {
    BodyBuilder::beam(name, bar_spec())
        .origin(origin)
        .orientation(Orientation::Angle(angle))
        .flexible(false)
        .marker("A", [0.0, 0.0, 0.0])
        .marker("B", [1.0, 0.0, 0.0])
        .velocity(linear, angular)
}

/// The double four-bar (IFToMM A02, N = 2; scenes.md §1) in code.
fn double_four_bar() -> Scene {
    let revolute = || JointKind::Revolute { axis: None };
    let crank = [0.0, 0.0, -1.0];
    let still = [0.0; 3];
    SceneBuilder::new("double four-bar", Dim::Planar)
        .description(
            "IFToMM A02 with N = 2: three cranks and two couplers, 7 revolute joints, mobility 1",
        )
        .gravity([0.0, -9.81, 0.0])
        .ground_marker("A0", [0.0, 0.0, 0.0])
        .ground_marker("A1", [1.0, 0.0, 0.0])
        .ground_marker("A2", [2.0, 0.0, 0.0])
        .body(bar("crank1", [0.0, 0.0, 0.0], FRAC_PI_2, still, crank))
        .body(bar(
            "coupler1",
            [0.0, 1.0, 0.0],
            0.0,
            [1.0, 0.0, 0.0],
            still,
        ))
        .body(bar("crank2", [1.0, 0.0, 0.0], FRAC_PI_2, still, crank))
        .body(bar(
            "coupler2",
            [1.0, 1.0, 0.0],
            0.0,
            [1.0, 0.0, 0.0],
            still,
        ))
        .body(bar("crank3", [2.0, 0.0, 0.0], FRAC_PI_2, still, crank))
        .joint(Joint::new(
            "A0",
            revolute(),
            (GROUND, "A0"),
            ("crank1", "A"),
        ))
        .joint(Joint::new(
            "B0",
            revolute(),
            ("crank1", "B"),
            ("coupler1", "A"),
        ))
        .joint(Joint::new(
            "A1",
            revolute(),
            (GROUND, "A1"),
            ("crank2", "A"),
        ))
        .joint(Joint::new(
            "B1a",
            revolute(),
            ("crank2", "B"),
            ("coupler1", "B"),
        ))
        .joint(Joint::new(
            "B1b",
            revolute(),
            ("crank2", "B"),
            ("coupler2", "A"),
        ))
        .joint(Joint::new(
            "A2",
            revolute(),
            (GROUND, "A2"),
            ("crank3", "A"),
        ))
        .joint(Joint::new(
            "B2",
            revolute(),
            ("crank3", "B"),
            ("coupler2", "B"),
        ))
        .sensor(Sensor::new(
            "B0_x",
            SensorKind::position("crank1", "B", Axis::X),
        ))
        .sensor(Sensor::new(
            "B0_y",
            SensorKind::position("crank1", "B", Axis::Y),
        ))
        .sensor(Sensor::new("energy", SensorKind::Energy))
        .solver(Solver::new(1e-3, 5.0).output_interval(0.01))
        .build()
        .unwrap()
}

#[test]
fn the_double_four_bar_built_in_code_is_the_model_file_and_runs_to_the_same_bits() {
    let built = double_four_bar();
    let loaded = Scene::load(models().join("double_four_bar.ron")).unwrap();
    assert!(
        built.same_as(&loaded),
        "built:\n{built:#?}\nloaded:\n{loaded:#?}"
    );
    // One flexible bar too, so that the FE specs take part in the comparison of runs.
    for sets in [vec![], vec!["bodies.crank1.flexible=true"]] {
        let sets: Vec<_> = sets
            .iter()
            .map(|s| flexmbd::model::parse_set(s).unwrap())
            .collect();
        let (mut a, mut b) = (built.clone(), loaded.clone());
        a.apply_sets(&sets).unwrap();
        b.apply_sets(&sets).unwrap();
        a.solver.duration = 1.0;
        b.solver.duration = 1.0;
        let (_, ha) = flexmbd::simulation::run(&a, |_| {}).unwrap();
        let (_, hb) = flexmbd::simulation::run(&b, |_| {}).unwrap();
        assert_eq!(ha.rows.len(), 101);
        for (ra, rb) in ha.rows.iter().zip(&hb.rows) {
            let bits = |r: &Vec<f64>| r.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(ra), bits(rb), "{sets:?}: rows differ at t = {}", ra[0]);
        }
    }
}

#[test]
fn a_scene_goes_through_ron_text_and_back_unchanged() {
    for scene in [
        double_four_bar(),
        Scene::load(models().join("spin_up_beam_3d.ron")).unwrap(),
        Scene::load(models().join("double_pendulum_3d.ron")).unwrap(),
    ] {
        let text = scene.to_ron().unwrap();
        let back = Scene::from_ron_str(&text, "round trip").unwrap();
        back.validate().unwrap();
        assert!(
            back.same_as(&scene),
            "{}: changed through RON:\n{text}",
            scene.name
        );
    }
}

#[test]
fn a_builder_mistake_is_refused_naming_the_field_and_value() {
    let e = SceneBuilder::new("bad pendulum", Dim::Planar)
        .ground_marker("O", [0.0, 0.0, 0.0])
        .body(
            BodyBuilder::rigid(
                "bar",
                -1.0,
                [0.5, 0.0, 0.0],
                flexmbd::model::Inertia::Planar(0.1),
            )
            .marker("pin", [0.0, 0.0, 0.0]),
        )
        .joint(Joint::new(
            "pin",
            JointKind::Revolute { axis: None },
            (GROUND, "O"),
            ("bar", "pin"),
        ))
        .build()
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bad pendulum")
            && e.contains("bodies[bar].model.Rigid.mass")
            && e.contains("-1"),
        "{e}"
    );
    let e = SceneBuilder::new("typo", Dim::Planar)
        .body(BodyBuilder::rigid(
            "bar",
            1.0,
            [0.0; 3],
            flexmbd::model::Inertia::Planar(0.1),
        ))
        .joint(Joint::new(
            "pin",
            JointKind::Revolute { axis: None },
            (GROUND, "O"),
            ("bar", "pin"),
        ))
        .build()
        .unwrap_err()
        .to_string();
    eprintln!("{e}");
    assert!(
        e.contains("typo") && e.contains("marker") && e.contains("`O`"),
        "{e}"
    );
}
