//! Scene loading: the double four-bar parses and validates; bad input is refused
//! with the file, line and field; `--set` reaches any scalar by its path (list items by
//! name, the fields of enum items such as constraints and forces too).

use flexmbd_model::{BodyModel, ModelError, Scene, parse_set};

fn models_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models")
}

fn four_bar_text() -> String {
    std::fs::read_to_string(models_dir().join("double_four_bar.ron")).unwrap()
}

/// The validation error of the double four-bar with `from` in its text replaced by `to`
/// (the text still parses).
fn refused_after(from: &str, to: &str) -> ModelError {
    let text = four_bar_text();
    assert!(text.contains(from), "the four-bar lacks {from:?}");
    Scene::from_ron_str(&text.replace(from, to), "f.ron")
        .unwrap()
        .validate()
        .unwrap_err()
}

/// The message of `e` names each of `parts`.
fn assert_names_all(e: &ModelError, parts: &[&str]) {
    let msg = e.to_string();
    for part in parts {
        assert!(msg.contains(part), "lacks {part:?}: {msg}");
    }
}

#[test]
fn double_four_bar_loads() {
    let s = Scene::load(models_dir().join("double_four_bar.ron")).unwrap();
    assert_eq!(s.bodies.len(), 5);
    assert_eq!(s.joints.len(), 7);
    assert_eq!(
        s.sensors
            .iter()
            .map(|x| x.name.as_str())
            .collect::<Vec<_>>(),
        ["B0_x", "B0_y", "energy"]
    );
    assert!(s.bodies.iter().all(|b| !b.flexible));
}

#[test]
fn misspelt_field_names_file_line_and_field() {
    let text = four_bar_text().replace("output_interval:", "output_intervall:");
    let line = text
        .lines()
        .position(|l| l.contains("output_intervall"))
        .unwrap()
        + 1;
    let e = Scene::from_ron_str(&text, "four_bar.ron").unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with(&format!("four_bar.ron:{line}:")), "{msg}");
    assert!(msg.contains("output_intervall"), "{msg}");
}

#[test]
fn joint_naming_a_missing_body_is_refused() {
    let e = refused_after(
        "body2: \"coupler2\", marker2: \"B\"",
        "body2: \"coupler9\", marker2: \"B\"",
    );
    assert!(matches!(e, ModelError::Missing { kind: "body", .. }), "{e}");
    assert_names_all(&e, &["joints[B2].body2", "coupler9"]);
}

#[test]
fn sensor_on_a_missing_marker_is_refused() {
    let e = refused_after(
        "(body: \"crank1\", marker: \"B\", component: Y)",
        "(body: \"crank1\", marker: \"C\", component: Y)",
    );
    assert_names_all(&e, &["sensors[B0_y].marker", "`C`"]);
}

#[test]
fn non_positive_step_and_duration_are_refused() {
    for (field, bad) in [
        ("step: 1e-3", "step: 0.0"),
        ("duration: 5.0", "duration: -1.0"),
    ] {
        let name = field.split(':').next().unwrap();
        assert_names_all(&refused_after(field, bad), &[&format!("solver.{name}")]);
    }
}

/// A spin-up time so short that Ωs/Ts overflows (1e-308 s, a fuzzer's finding: the hub's
/// angle was NaN at t = 0) is refused by name, with its value.
#[test]
fn a_spin_up_time_below_a_nanosecond_is_refused() {
    let text = std::fs::read_to_string(models_dir().join("spin_up_beam_2d.ron")).unwrap();
    assert!(text.contains("t_s: 15.0"));
    let e = Scene::from_ron_str(&text.replace("t_s: 15.0", "t_s: 1e-308"), "f.ron")
        .unwrap()
        .validate()
        .unwrap_err();
    assert_names_all(&e, &["SpinUp.t_s", "1e-308"]);
}

#[test]
fn set_reaches_scalars_by_path() {
    let mut s = Scene::load(models_dir().join("double_four_bar.ron")).unwrap();
    let sets: Vec<_> = [
        "bodies.crank1.flexible=true",
        "solver.step=5e-4",
        "bodies.coupler1.model.Beam.material.young_modulus=7e10",
    ]
    .iter()
    .map(|a| parse_set(a).unwrap())
    .collect();
    s.apply_sets(&sets).unwrap();
    assert!(s.bodies[0].flexible);
    assert_eq!(s.solver.step, 5e-4);
    let BodyModel::Beam(spec) = &s.bodies[1].model else {
        panic!()
    };
    assert_eq!(spec.material.young_modulus, 7e10);
    // The round trip keeps everything else bit for bit.
    let mut again = Scene::load(models_dir().join("double_four_bar.ron")).unwrap();
    again.bodies[0].flexible = true;
    again.solver.step = 5e-4;
    if let BodyModel::Beam(spec) = &mut again.bodies[1].model {
        spec.material.young_modulus = 7e10;
    }
    assert_eq!(s, again);
}

#[test]
fn unknown_set_path_is_refused() {
    let mut s = Scene::load(models_dir().join("double_four_bar.ron")).unwrap();
    for (arg, expect) in [
        ("bodies.crank9.flexible=true", "no item named `crank9`"),
        ("solver.stepp=1", "`stepp` is not a field"),
        ("solver.step=abc", "not a number"),
        ("solver.step=-1", "solver.step"),
    ] {
        let e = s.apply_sets(&[parse_set(arg).unwrap()]).unwrap_err();
        assert!(e.to_string().contains(expect), "{arg}: {e}");
    }
}

#[test]
fn initial_state_defaults_to_given_and_is_settable() {
    use flexmbd_model::InitialState;
    let mut s = Scene::load(models_dir().join("double_four_bar.ron")).unwrap();
    assert_eq!(s.solver.initial_state, InitialState::Given);
    s.apply_sets(&[parse_set("solver.initial_state=StaticEquilibrium").unwrap()])
        .unwrap();
    assert_eq!(s.solver.initial_state, InitialState::StaticEquilibrium);
    let spin = Scene::load(models_dir().join("spin_up_beam_3d.ron")).unwrap();
    assert_eq!(spin.solver.initial_state, InitialState::StaticEquilibrium);
    let e = s
        .apply_sets(&[parse_set("solver.initial_state=Sideways").unwrap()])
        .unwrap_err();
    assert!(e.to_string().contains("Sideways"), "{e}");
}

/// A scene with a `Distance` constraint (its length given) and a spring–damper, both enum
/// items of their lists.
const TIED: &str = r#"(
    name: "tied", dim: Spatial, gravity: [0.0, 0.0, -9.81],
    ground: [(name: "O", position: [0.0, 0.0, 0.0]), (name: "P", position: [0.0, 0.0, 0.5])],
    bodies: [(name: "bob", origin: [0.6, 0.0, 0.0],
        model: Rigid(mass: 1.0, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([0.01, 0.01, 0.01])),
        markers: [(name: "c", position: [0.0, 0.0, 0.0])])],
    forces: [SpringDamper(name: "spring", body1: "ground", marker1: "P", body2: "bob", marker2: "c",
        stiffness: 10.0, damping: 0.0)],
    constraints: [
        Distance(name: "rod", body1: "ground", marker1: "O", body2: "bob", marker2: "c", length: Some(0.6)),
        PointInPlane(name: "plane", body1: "ground", marker1: "O", normal: (0.0, 1.0, 0.0), body2: "bob", marker2: "c"),
    ],
    solver: (step: 1e-3, duration: 1.0),
)"#;

#[test]
fn set_reaches_the_fields_of_constraints_and_forces_by_name() {
    let scene = Scene::from_ron_str(TIED, "tied.ron").unwrap();
    scene.validate().unwrap();
    let mut s = scene.clone();
    // By the item's name, with or without the variant's name; by index.
    let sets: Vec<_> = [
        "forces.spring.stiffness=20",
        "constraints.plane.PointInPlane.marker1=O",
        "constraints.1.name=in_plane",
    ]
    .iter()
    .map(|a| parse_set(a).unwrap())
    .collect();
    s.apply_sets(&sets).unwrap();
    let flexmbd_model::Force::SpringDamper { stiffness, .. } = &s.forces[0] else {
        panic!("the first force is the spring–damper");
    };
    assert_eq!(*stiffness, 20.0);
    assert_eq!(s.constraints[1].name(), "in_plane");
    // A length the markers are not at is refused after the set, naming the field.
    let e = s
        .apply_sets(&[parse_set("constraints.rod.length=0.7").unwrap()])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("tied.ron:10: constraints[rod].length = 0.7: ")
            && e.contains("0.600000000 m apart"),
        "{e}"
    );
    let e = s
        .apply_sets(&[parse_set("constraints.rod.lenght=0.7").unwrap()])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`lenght` is not a field of `constraints.rod`"),
        "{e}"
    );
}
