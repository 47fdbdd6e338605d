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

/// The vehicle corner of the test scenes (`flexmbd_test_support::scenes::VEHICLE_CORNER`:
/// a strut with polynomial and piecewise laws, a leaf element along a chassis axis, tyres on a
/// cosine bump and a stepped table) with a distance constraint and a point held in a plane,
/// written with the vehicle builders.
fn vehicle_corner() -> Result<Scene, flexmbd::model::ModelError> {
    use flexmbd::model::builder::{LinkBuilder, TyreBuilder};
    use flexmbd::model::scene_constraints::Constraint;
    use flexmbd::model::{Axis, Contact, Inertia, Law, Profile, Road, Sensor, SensorKind, Solver};
    let free = |name: &str, ground: &str, body: &str, marker: &str| {
        Joint::new(name, JointKind::Free, (GROUND, ground), (body, marker))
    };
    SceneBuilder::new("corner", Dim::Spatial)
        .gravity([0.0, 0.0, -9.81])
        .ground_marker("O", [0.1, 0.5, 0.8])
        .ground_marker("W", [0.0, 0.7, 0.356])
        .body(
            BodyBuilder::rigid(
                "chassis",
                300.0,
                [0.0; 3],
                Inertia::Diagonal(flexmbd::model::V3([50.0, 200.0, 220.0])),
            )
            .origin([0.0, 0.0, 0.6])
            .marker("S0_fl", [0.1, 0.5, 0.2])
            .marker("E_fl", [0.0, 0.6, 0.137]),
        )
        .body(
            BodyBuilder::rigid(
                "carrier_fl",
                57.35,
                [0.0; 3],
                Inertia::Diagonal(flexmbd::model::V3([1.0, 2.0, 1.0])),
            )
            .origin([0.0, 0.7, 0.356])
            .marker("S1_fl", [0.05, -0.1, -0.15])
            .marker("U_fl", [0.0, -0.1, 0.2])
            .marker("W_fl", [0.0, 0.0, 0.0]),
        )
        .joint(free("float", "O", "chassis", "S0_fl"))
        .joint(free("float_carrier", "W", "carrier_fl", "W_fl"))
        .force(
            LinkBuilder::new("strut_fl", ("chassis", "S0_fl"), ("carrier_fl", "S1_fl"))
                .spring(Law::polynomial(vec![
                    -4.0092e6, 2.8397e7, -6.7061e7, 5.2796e7,
                ]))
                .damper(Law::piecewise(
                    vec![-0.20, 0.21],
                    vec![
                        Law::polynomial(vec![-416.42, 1844.3]),
                        Law::polynomial(vec![0.0, 9945.627, 33955.72, -59832.25, -395651.0]),
                        Law::polynomial(vec![1919.1638, 1634.727]),
                    ],
                )),
        )
        .force(
            LinkBuilder::new("leaf_fl", ("chassis", "E_fl"), ("carrier_fl", "U_fl"))
                .spring(Law::piecewise(
                    vec![0.106],
                    vec![
                        Law::polynomial_about(vec![-5242.276, 1.0e7], 0.106),
                        Law::polynomial_about(vec![-5457.712, 35906.0], 0.1),
                    ],
                ))
                .along_axis([0.0, 0.0, -1.0]),
        )
        .force(TyreBuilder::new(
            "tyre_fl",
            ("carrier_fl", "W_fl"),
            "left",
            0.364325,
            460000.0,
        ))
        .force(
            TyreBuilder::new(
                "tyre_bump",
                ("carrier_fl", "W_fl"),
                "ramp",
                0.364325,
                460000.0,
            )
            .contact(Contact::ProfileNormal),
        )
        .road(Road::new("left", Profile::cosine_bump(0.97, 5.0, 0.2)))
        .road(Road::new("flat", Profile::Flat))
        .road(Road::new(
            "ramp",
            Profile::table(
                vec![0.0, 3.0, 4.0, 10.0, 10.0, 20.0, 20.0],
                vec![0.0, 0.0, 0.1, 0.1, 0.0, 0.0, -0.1],
            ),
        ))
        .constraint(Constraint::distance(
            "tie",
            ("chassis", "E_fl"),
            ("carrier_fl", "U_fl"),
            None,
        ))
        .constraint(Constraint::point_in_plane(
            "guide",
            ("chassis", "S0_fl"),
            [2.0, 1.0, 0.0],
            ("carrier_fl", "S1_fl"),
        ))
        .sensor(Sensor::new(
            "chassis_pitch",
            SensorKind::angle("chassis", Axis::Y),
        ))
        .sensor(Sensor::new("tyre_fl", SensorKind::element_force("tyre_fl")))
        .sensor(Sensor::new(
            "strut_fl",
            SensorKind::element_force("strut_fl"),
        ))
        .solver(Solver::new(1e-3, 0.01))
        .build()
}

#[test]
fn the_vehicle_corner_built_with_links_tyres_roads_and_constraints_is_the_ron_scene() {
    let text = flexmbd_test_support::scenes::VEHICLE_CORNER.replace(
        "    sensors: [",
        r#"    constraints: [
        Distance(name: "tie", body1: "chassis", marker1: "E_fl", body2: "carrier_fl", marker2: "U_fl"),
        PointInPlane(name: "guide", body1: "chassis", marker1: "S0_fl", normal: (2.0, 1.0, 0.0), body2: "carrier_fl", marker2: "S1_fl"),
    ],
    sensors: ["#,
    );
    let loaded = Scene::from_ron_str(&text, "corner.ron").unwrap();
    loaded.validate().unwrap();
    let built = vehicle_corner().unwrap();
    assert!(
        built.same_as(&loaded),
        "built:\n{built:#?}\nloaded:\n{loaded:#?}"
    );
    let (_, ha) = flexmbd::simulation::run(&built, |_| {}).unwrap();
    let (_, hb) = flexmbd::simulation::run(&loaded, |_| {}).unwrap();
    assert_eq!(ha.rows, hb.rows);
    // At t = 0 the wheel centre is 0.356 m above the flat start of the road: F = K (R − z).
    let tyre_at_start = ha.column("tyre_fl").unwrap()[0];
    let expected = 460000.0 * (0.364325 - 0.356);
    assert!(
        (tyre_at_start - expected).abs() < 1e-9 * expected,
        "{tyre_at_start} N, expected {expected} N"
    );
}

#[test]
fn a_vehicle_builder_mistake_is_refused_naming_the_field_and_value() {
    use flexmbd::model::builder::TyreBuilder;
    let mut scene = vehicle_corner().unwrap();
    let bad = TyreBuilder::new("tyre_bad", ("carrier_fl", "W_fl"), "left", -0.3, 460000.0);
    scene.forces.push(bad.into());
    let e = scene.validate().unwrap_err().to_string();
    assert!(
        e.contains("tyre_bad") && e.contains("radius") && e.contains("-0.3"),
        "{e}"
    );
}
