//! The vehicle scene syntax of issue 13 (nonlinear links, tyres, roads, angle and
//! element-force sensors): a scene written in exactly that syntax compiles in both
//! formulations, and each invalid input is refused at load, the same in both, naming the
//! file, the line, the field and the value. Each test is named after what it reproduces.

use flexmbd::simulation::compile;
use flexmbd_model::{FormulationKind, Scene};

use flexmbd_test_support::scenes::VEHICLE_CORNER as CORNER;

/// The refusal of CORNER with `from` replaced by `to`, the same in both formulations, checked
/// to contain each of `parts` and the line of the edit.
fn refused(from: &str, to: &str, parts: &[&str]) -> String {
    assert!(CORNER.contains(from), "CORNER lacks {from:?}");
    let edited = CORNER.replacen(from, to, 1);
    let line = CORNER[..CORNER.find(from).unwrap()].matches('\n').count() + 1;
    let messages = [FormulationKind::Absolute, FormulationKind::Relative].map(|f| {
        let mut s = Scene::from_ron_str(&edited, "corner.ron").unwrap();
        s.solver.formulation = f;
        match compile(&s) {
            Ok(_) => panic!("{f:?} accepted {to:?}"),
            Err(e) => e.to_string(),
        }
    });
    assert_eq!(
        messages[0], messages[1],
        "the formulations refuse differently"
    );
    let e = messages[0].clone();
    assert!(
        e.contains(&format!("corner.ron:{line}:")),
        "not at line {line}: {e}"
    );
    for part in parts {
        assert!(e.contains(part), "lacks {part:?}: {e}");
    }
    e
}

#[test]
fn the_fixed_vehicle_syntax_compiles_in_both_formulations() {
    for f in [FormulationKind::Absolute, FormulationKind::Relative] {
        let mut s = Scene::from_ron_str(CORNER, "corner.ron").unwrap();
        s.solver.formulation = f;
        let compiled = compile(&s).unwrap_or_else(|e| panic!("{f:?}: {e}"));
        assert_eq!(compiled.sensor_names().len(), 3);
    }
}

#[test]
fn force_on_a_missing_marker_is_refused() {
    refused(
        r#"marker2: "S1_fl""#,
        r#"marker2: "S9_fl""#,
        &["forces[strut_fl].marker2", "S9_fl"],
    );
}

#[test]
fn negative_tyre_stiffness_is_refused() {
    refused(
        "stiffness: 460000.0, contact: Vertical",
        "stiffness: -460000.0, contact: Vertical",
        &["forces[tyre_fl].stiffness", "-460000"],
    );
}

#[test]
fn tyre_radius_of_zero_is_refused() {
    refused(
        "radius: 0.364325, stiffness: 460000.0, contact: Vertical",
        "radius: 0.0, stiffness: 460000.0, contact: Vertical",
        &["forces[tyre_fl].radius", "0"],
    );
}

#[test]
fn negative_lateral_damping_is_refused() {
    refused(
        "lateral_damping: 0.0",
        "lateral_damping: -8328.0",
        &["forces[tyre_fl].lateral_damping", "-8328"],
    );
}

#[test]
fn tyre_on_an_unknown_road_is_refused() {
    refused(
        r#"road: "left""#,
        r#"road: "lfet""#,
        &["forces[tyre_fl].road", "lfet", "left, flat, ramp"],
    );
}

#[test]
fn road_table_out_of_order_is_refused() {
    refused(
        "x: [0.0, 3.0, 4.0, 10.0",
        "x: [0.0, 3.0, 2.0, 10.0",
        &["roads[ramp].profile.Table.x[2]", "2", "non-decreasing"],
    );
}

#[test]
fn road_table_with_three_equal_x_is_refused() {
    refused(
        "10.0, 10.0, 20.0",
        "10.0, 10.0, 10.0",
        &["roads[ramp].profile.Table.x[5]", "at most two equal"],
    );
}

#[test]
fn cosine_bump_of_zero_length_is_refused() {
    refused(
        "length: 5.0",
        "length: 0.0",
        &["roads[left].profile.CosineBump.length", "0"],
    );
}

#[test]
fn breakpoints_not_increasing_are_refused() {
    refused(
        "breakpoints: [-0.20, 0.21]",
        "breakpoints: [0.21, -0.20]",
        &[
            "forces[strut_fl].damper.Piecewise.breakpoints[1]",
            "-0.2",
            "strictly increasing",
        ],
    );
}

#[test]
fn law_that_jumps_where_it_says_it_is_continuous_is_refused_with_both_values() {
    refused(
        "[1919.1638, 1634.727]",
        "[1819.1638, 1634.727]",
        &[
            "forces[strut_fl].damper.Piecewise.breakpoints[1]",
            "0.21",
            "jumps",
            "2162.4",
            "2262.4",
        ],
    );
}

#[test]
fn piecewise_law_with_a_piece_missing_is_refused() {
    refused(
        "breakpoints: [0.106], pieces",
        "breakpoints: [0.106, 0.2], pieces",
        &[
            "forces[leaf_fl].spring.Piecewise.pieces",
            "2 pieces",
            "3 pieces",
        ],
    );
}

#[test]
fn non_finite_polynomial_coefficient_is_refused() {
    refused(
        "[-4.0092e6, 2.8397e7",
        "[-4.0092e6, inf",
        &["forces[strut_fl].spring.Polynomial.coefficients[1]", "inf"],
    );
}

#[test]
fn zero_link_axis_is_refused() {
    refused(
        "axis: Some((0.0, 0.0, -1.0))",
        "axis: Some((0.0, 0.0, 0.0))",
        &["forces[leaf_fl].axis", "non-zero"],
    );
}

#[test]
fn element_force_sensor_of_a_missing_force_is_refused() {
    refused(
        r#"ElementForce(force: "strut_fl")"#,
        r#"ElementForce(force: "strut_rr")"#,
        &["sensors[strut_fl].force", "strut_rr", "force element"],
    );
}

#[test]
fn angle_sensor_of_a_missing_body_is_refused() {
    refused(
        r#"Angle(body: "chassis""#,
        r#"Angle(body: "chasis""#,
        &["sensors[chassis_pitch].body", "chasis"],
    );
}

#[test]
fn two_force_elements_of_one_name_are_refused() {
    refused(
        r#"Tyre(name: "tyre_bump""#,
        r#"Tyre(name: "tyre_fl""#,
        &["forces", "tyre_fl"],
    );
}

/// `--set forces.NAME.FIELD=VALUE` reaches a force element's fields through its variant.
#[test]
fn set_reaches_tyre_fields_and_refuses_bad_values_by_name() {
    let mut s = Scene::from_ron_str(CORNER, "corner.ron").unwrap();
    let set = |p: &str, v: &str| vec![(p.to_string(), v.to_string())];
    s.apply_sets(&set("forces.tyre_fl.radius", "0.36")).unwrap();
    s.apply_sets(&set("forces.tyre_fl.stiffness", "5e5"))
        .unwrap();
    s.apply_sets(&set("forces.tyre_fl.lateral_damping", "8328.0"))
        .unwrap();
    let tyre = |s: &Scene| match &s.forces[2] {
        flexmbd_model::Force::Tyre {
            radius,
            stiffness,
            lateral_damping,
            ..
        } => (*radius, *stiffness, *lateral_damping),
        _ => panic!("forces[2] is the tyre"),
    };
    assert_eq!(tyre(&s), (0.36, 5e5, 8328.0));
    let e = s
        .apply_sets(&set("forces.tyre_fl.radius", "-1.0"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("forces[tyre_fl].radius") && e.contains("-1"),
        "{e}"
    );
    let e = s
        .apply_sets(&set("forces.tyre_fl.grip", "1.0"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`grip` is not a field") && e.contains("radius"),
        "{e}"
    );
    assert_eq!(
        tyre(&s).0,
        0.36,
        "a refused --set leaves the scene as it was"
    );
}

fn models_dir_scene(name: &str) -> Scene {
    flexmbd_test_support::scenes::model(name)
}

#[test]
fn link_along_the_axis_of_a_flexible_body_is_refused() {
    let mut s = models_dir_scene("flexible_pendulum_3d.ron");
    s.forces.push(flexmbd_model::Force::Link {
        name: "leaf".into(),
        body1: "beam".into(),
        marker1: "tip".into(),
        body2: "ground".into(),
        marker2: "O".into(),
        spring: flexmbd_model::Law::Polynomial {
            coefficients: vec![0.0, 100.0],
            about: 0.0,
        },
        damper: flexmbd_model::Law::Zero,
        axis: Some(flexmbd_model::Direction(flexmbd_model::V3([0.0, 0.0, 1.0]))),
    });
    for f in [FormulationKind::Absolute, FormulationKind::Relative] {
        s.solver.formulation = f;
        let e = compile(&s).err().expect("refused").to_string();
        assert!(
            e.contains("forces[leaf].body1") && e.contains("beam") && e.contains("rigid body1"),
            "{f:?}: {e}"
        );
    }
}

#[test]
fn tyre_in_a_planar_scene_is_refused() {
    let mut s = models_dir_scene("double_four_bar.ron");
    s.roads.push(flexmbd_model::Road {
        name: "flat".into(),
        profile: flexmbd_model::Profile::Flat,
    });
    s.forces.push(flexmbd_model::Force::Tyre {
        name: "tyre".into(),
        body: "crank1".into(),
        marker: "B".into(),
        road: "flat".into(),
        radius: 0.3,
        stiffness: 1e5,
        contact: flexmbd_model::Contact::Vertical,
        lateral_damping: 0.0,
    });
    let e = compile(&s).err().expect("refused").to_string();
    assert!(
        e.contains("forces[tyre]") && e.contains("needs a 3D scene"),
        "{e}"
    );
}
