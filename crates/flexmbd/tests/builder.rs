//! Scenes built in code (`flexmbd::model::builder`): the double four-bar of
//! `models/double_four_bar.ron` (docs/scenes.md §1) written with the builders is the same scene
//! as the file, runs to the same B0 history bit for bit, and goes through RON text and back
//! unchanged; a builder's mistake is refused by the same validation, naming the field.

// The builder code a user project outside the workspace runs too (`.ci/run`).
#[path = "../../../examples/user-project/src/four_bar.rs"]
mod four_bar;

use flexmbd::core::Dim;
use flexmbd::model::builder::{BodyBuilder, SceneBuilder};
use flexmbd::model::{GROUND, Joint, JointKind, Scene};

fn double_four_bar() -> Scene {
    four_bar::double_four_bar().unwrap()
}

fn models() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models")
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
