//! Hostile input (issue 12): every defect class found by hand and by mutation, as a minimal
//! scene, refused once at load with the same error in both formulations (or, where the
//! input is valid, compiled without a panic). Each test is named after what it reproduces.

use flexmbd::simulation::compile;
use flexmbd_fe::{Dof, NodeDof, ReferenceFrame};
use flexmbd_model::{
    BodyModel, Driver, FormulationKind, ModelError, MotionLaw, Orientation, Scene, Stiffening, V3,
};
use flexmbd_test_support::scenes::{model, models_dir};

/// The refusal of `scene` by each formulation: the same message from both (the check is
/// the model's, done once), returned.
fn refusal_in_both(scene: &Scene) -> String {
    let mut messages = [FormulationKind::Absolute, FormulationKind::Relative].map(|f| {
        let mut s = scene.clone();
        s.solver.formulation = f;
        match compile(&s) {
            Ok(_) => panic!("{f:?} accepted the scene"),
            Err(e) => e.to_string(),
        }
    });
    assert_eq!(
        messages[0], messages[1],
        "the formulations refuse differently"
    );
    std::mem::take(&mut messages[0])
}

/// [`refusal_in_both`], checked to contain each of `parts`.
fn refused_with(scene: &Scene, parts: &[&str]) -> String {
    let e = refusal_in_both(scene);
    for part in parts {
        assert!(e.contains(part), "lacks {part:?}: {e}");
    }
    e
}

/// The refusal ([`refusal_in_both`]) of `models/NAME` with the first `from` in its text
/// replaced by `to`, parsed (not validated) with its source.
fn refusal_of_edit(name: &str, from: &str, to: &str) -> String {
    let path = models_dir().join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains(from), "{name} lacks {from:?}");
    let edited = text.replacen(from, to, 1);
    refusal_in_both(&Scene::from_ron_str(&edited, &format!("models/{name}")).unwrap())
}

fn beam_of<'a>(scene: &'a mut Scene, body: &str) -> &'a mut flexmbd_fe::BeamBodySpec {
    let b = scene.bodies.iter_mut().find(|b| b.name == body).unwrap();
    match &mut b.model {
        BodyModel::Beam(spec) => spec,
        BodyModel::Rigid { .. } | BodyModel::Imported(_) => panic!("{body} is not a beam"),
    }
}

#[test]
fn nan_marker_position_is_refused_in_both_formulations() {
    let e = refusal_of_edit(
        "double_four_bar.ron",
        r#"(name: "A", position: [0.0, 0.0])"#,
        r#"(name: "A", position: [NaN, 0.0])"#,
    );
    assert_eq!(
        e,
        "models/double_four_bar.ron:33: bodies[crank1].markers[A].position[0] = NaN: \
         must be finite: allowed [-1e6, 1e6] m"
    );
}

#[test]
fn validation_error_names_the_line() {
    // Each refusal names the line of its field in the file; a field the file omits has none:
    // (model, text, edited, the refusal's start).
    for (name, from, to, start) in [
        (
            "double_four_bar.ron",
            "gravity: [0.0, -9.81]",
            "gravity: [0.0, -1e308]",
            "models/double_four_bar.ron:16: gravity[1] = -1e308",
        ),
        (
            "spin_up_beam_2d.ron",
            "t_s: 15.0",
            "t_s: -1.0",
            "models/spin_up_beam_2d.ron:61: drivers[spin].law.SpinUp.t_s",
        ),
        (
            "double_four_bar.ron",
            r#"marker2: "A"),"#,
            r#"marker2: "Z"),"#,
            "models/double_four_bar.ron:85: joints[A0].marker2",
        ),
        // A name given twice: the line of the repeat.
        (
            "double_four_bar.ron",
            r#"(name: "B0""#,
            r#"(name: "A0""#,
            "models/double_four_bar.ron:86: joints[A0].name = A0: duplicate joint name",
        ),
    ] {
        let e = refusal_of_edit(name, from, to);
        assert!(e.starts_with(start), "{e}");
    }
}

#[test]
fn out_of_range_values_are_refused_in_both_formulations() {
    let base = model("double_four_bar.ron");
    type Edit = fn(&mut Scene);
    let cases: [(&str, Edit); 11] = [
        ("bodies[crank1].origin[0] = inf", |s| {
            s.bodies[0].origin.0[0] = f64::INFINITY
        }),
        ("bodies[crank1].velocity.linear[0] = 1e308", |s| {
            s.bodies[0].velocity.linear.0[0] = 1e308
        }),
        ("bodies[crank1].orientation.Angle = NaN", |s| {
            s.bodies[0].orientation = Orientation::Angle(f64::NAN)
        }),
        (
            "bodies[crank1].orientation.AxisAngle.axis = [0.0, 0.0, 0.0]",
            |s| {
                s.bodies[0].orientation = Orientation::AxisAngle {
                    axis: V3([0.0; 3]),
                    angle: 0.0,
                }
            },
        ),
        ("ground[A0].position[1] = -inf", |s| {
            s.ground[0].position.0[1] = f64::NEG_INFINITY
        }),
        ("drivers[d].law.ConstantRate = NaN", |s| {
            s.drivers.push(Driver {
                name: "d".into(),
                joint: "A0".into(),
                law: MotionLaw::ConstantRate(f64::NAN),
            })
        }),
        ("body `crank1`: material.young_modulus = 1e20", |s| {
            beam_of(s, "crank1").material.young_modulus = 1e20
        }),
        ("body `crank1`: geometry.points[1][0] = 1e300", |s| {
            beam_of(s, "crank1").geometry.points[1][0] = 1e300
        }),
        ("bodies[crank1].initial_modes[0] = NaN", |s| {
            s.bodies[0].initial_modes = vec![f64::NAN]
        }),
        ("solver.penalty = 1e300: out of range", |s| {
            s.solver.penalty = Some(1e300)
        }),
        (
            "solver.max_iterations = 18446744073709551615: must be in 1..=10000",
            |s| s.solver.max_iterations = usize::MAX,
        ),
    ];
    for (want, edit) in cases {
        let mut s = base.clone();
        s.bodies[0].flexible = true;
        edit(&mut s);
        let e = refusal_in_both(&s);
        assert!(e.contains(want), "{want}: {e}");
    }
}

#[test]
fn relative_with_no_bodies_does_not_panic() {
    let mut s = model("double_four_bar.ron");
    s.bodies.clear();
    s.joints.clear();
    s.sensors.retain(|x| x.name == "energy");
    refused_with(&s, &["bodies = []: the scene has no moving body"]);
}

#[test]
fn relative_with_no_coordinates_does_not_panic() {
    // One bar welded to the ground: no coordinate at all, an empty velocity fit.
    let mut s = model("flexible_pendulum.ron");
    s.bodies[0].flexible = false;
    s.sensors.retain(|x| {
        matches!(
            x.kind,
            flexmbd_model::SensorKind::Position { .. } | flexmbd_model::SensorKind::Energy
        )
    });
    s.joints[0].kind = flexmbd_model::JointKind::Rigid;
    s.solver.formulation = FormulationKind::Relative;
    let compiled = compile(&s).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(compiled.n_coordinates(), 0);
}

#[test]
fn second_driver_on_a_joint_is_refused() {
    let mut s = model("spin_up_beam_2d.ron");
    let mut second = s.drivers[0].clone();
    second.name = "again".into();
    second.law = MotionLaw::ConstantRate(1.0);
    s.drivers.push(second);
    refused_with(
        &s,
        &["drivers[again].joint = hub: joint `hub` is already driven by `spin`"],
    );
}

#[test]
fn non_coincident_joint_markers_refused_in_both_formulations() {
    let mut s = model("double_four_bar.ron");
    let coupler2 = s.bodies.iter_mut().find(|b| b.name == "coupler2").unwrap();
    coupler2.origin.0[1] += 0.01; // joined at B1b (its marker A) and B2
    refused_with(
        &s,
        &[
            "joints[B1b].marker2 = coupler2.A at (1.000000, 1.010000)",
            "joined markers must coincide at t = 0",
        ],
    );
}

#[test]
fn hyperstatic_frame_is_refused() {
    let mut s = model("flexible_pendulum.ron");
    let at = |node, dof| NodeDof { node, dof };
    beam_of(&mut s, "bar").frame = ReferenceFrame::Dofs(vec![
        at(0, Dof::Ux),
        at(0, Dof::Uy),
        at(0, Dof::Rz),
        at(10, Dof::Uy),
    ]);
    refused_with(&s, &["body `bar`: frame.Dofs = 4 DOFs: hyperstatic"]);
}

#[test]
fn substructuring_100000_is_refused_with_memory() {
    let mut s = model("spin_up_beam_3d.ron");
    s.solver.stiffening = Stiffening::Substructuring(100_000);
    refused_with(
        &s,
        &[
            "solver.stiffening = Substructuring(100000): too many substructures",
            "about 1400000 coordinates",
            "15.7 TB each",
        ],
    );
}

#[test]
fn elements_per_segment_of_u64_max_is_refused_with_memory() {
    let mut s = model("flexible_pendulum.ron");
    beam_of(&mut s, "bar").geometry.elements_per_segment = usize::MAX;
    refused_with(&s, &["55340232221128654848 FE DOFs", "bytes each"]);
}

#[test]
fn axial_modes_error_names_axial_modes() {
    let mut s = model("spin_up_beam_2d.ron");
    beam_of(&mut s, "beam").axial_modes = 50;
    let e = refused_with(&s, &["axial_modes = 50"]);
    assert!(!e.contains("normal modes requested"), "{e}");
    // Within the interior DOFs but more than the beam's 20 axial ones: found by the reduction.
    beam_of(&mut s, "beam").axial_modes = 25;
    refused_with(
        &s,
        &["axial_modes = 25: the model has only 20 purely axial"],
    );
}

#[test]
fn every_model_still_loads() {
    for entry in std::fs::read_dir(models_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|x| x != "ron") {
            continue; // models/fe/ and the generator scripts
        }
        let text = std::fs::read_to_string(&path).unwrap();
        if let Ok(scene) = Scene::from_ron_str(&text, &path.display().to_string()) {
            scene
                .validate()
                .unwrap_or_else(|e: ModelError| panic!("{e}"));
        }
    }
}

#[test]
fn joint_kind_mismatches_are_refused_the_same_in_both_formulations() {
    // Each used to run in one formulation (a driver or sensor silently ignored, an axis
    // silently projected) and be refused, differently worded, by the other.
    // (model, text, edited, in the refusal).
    for (name, from, to, refusal) in [
        (
            "spin_up_beam_2d.ron",
            r#"kind: Revolute(), body1: "ground""#,
            r#"kind: Rigid, body1: "ground""#,
            ":61: drivers[spin].joint = hub: only revolute",
        ),
        (
            "double_pendulum_3d.ron",
            r#"kind: JointCoordinate(joint: "hinge")"#,
            r#"kind: JointCoordinate(joint: "ball")"#,
            ":44: sensors[hinge].joint = ball: a joint coordinate",
        ),
        (
            "double_pendulum_3d.ron",
            "Revolute(axis: Some([1.0, 1.0, 0.5]))",
            "Revolute()",
            "joints[hinge].kind.Revolute.axis = None",
        ),
        (
            "double_pendulum_3d.ron",
            "Revolute(axis: Some([1.0, 1.0, 0.5]))",
            "Universal(axis1: [1.0, 0.0, 0.0], axis2: [1.0, 0.1, 0.0])",
            ":38: joints[hinge].kind.Universal.axis2",
        ),
        (
            "slider_crank.ron",
            "Prismatic(axis: [1.0, 0.0])",
            "Prismatic(axis: [1.0, 0.0, 1.0])",
            ":68: joints[rail].kind.Prismatic.axis = [1.0, 0.0, 1.0]",
        ),
    ] {
        let e = refusal_of_edit(name, from, to);
        assert!(e.contains(refusal), "{e}");
    }
}

#[test]
fn huge_solver_step_is_refused_not_a_singular_matrix() {
    // A step of 1e308 s used to run one step to t = 1e308 s and fail with a singular
    // leading matrix; the solver's times are refused at load, naming the field and range.
    let mut s = model("double_four_bar.ron");
    s.solver.step = 1e308;
    let e = refusal_in_both(&s);
    assert!(
        e.ends_with("solver.step = 1e308: out of range: allowed (0, 1e6] s"),
        "{e}"
    );
    let mut s = model("double_four_bar.ron");
    s.solver.duration = f64::INFINITY;
    refused_with(&s, &["solver.duration = inf: must be finite"]);
}

#[test]
fn subnormal_density_is_refused_not_a_slow_eigensolver() {
    // Found by the fuzzer (seed 2026): a density of 1e-308 made the FE matrices subnormal
    // and the eigensolver spent seconds before failing; moduli, densities and masses are
    // bounded below as well as above.
    let e = refusal_of_edit("flexible_pendulum_3d.ron", "7850.0", "1e-308");
    assert!(
        e.contains("density = 1e-308: out of range: allowed [1e-3, 1e6] kg/m³"),
        "{e}"
    );
}

/// The refusal ([`refusal_in_both`]) of `models/NAME` with `constraint` added as its
/// `constraints:` list, on the line of its `sensors:` list.
fn refusal_with_constraint(name: &str, constraint: &str) -> String {
    refusal_of_edit(
        name,
        "    sensors: [",
        &format!("    constraints: [{constraint}],\n    sensors: ["),
    )
}

#[test]
fn bad_constraints_are_refused_by_field_and_value() {
    // (model, constraint, parts of the refusal); the constraint sits on line 40 of the 3D
    // double pendulum and line 93 of the double four-bar.
    let tie =
        |ends: &str, length: &str| format!(r#"Distance(name: "tie", {ends}, length: {length})"#);
    let to_tip = r#"body1: "ground", marker1: "O", body2: "link2", marker2: "tip""#;
    let plane = |normal: &str, at: &str| {
        format!(
            r#"PointInPlane(name: "plane", body1: "ground", marker1: "{at}", normal: {normal}, body2: "link2", marker2: "tip")"#
        )
    };
    let pendulum = "double_pendulum_3d.ron";
    let cases: [(&str, String, &[&str]); 10] = [
        (
            pendulum,
            tie(
                r#"body1: "ground", marker1: "O", body2: "link2", marker2: "nowhere""#,
                "None",
            ),
            &[":40: ", "constraints[tie].marker2", "nowhere", "J, tip"],
        ),
        (
            pendulum,
            tie(to_tip, "Some(0.0)"),
            &[":40: constraints[tie].length = 0: out of range: allowed (0, 2e6] m"],
        ),
        (
            pendulum,
            tie(to_tip, "Some(-1.0)"),
            &[":40: constraints[tie].length = -1: out of range"],
        ),
        (
            pendulum,
            tie(to_tip, "Some(NaN)"),
            &[":40: constraints[tie].length = NaN: must be finite"],
        ),
        // link2.tip is 1.1648209 m from the ground point O at t = 0.
        (
            pendulum,
            tie(to_tip, "Some(1.2)"),
            &[
                ":40: constraints[tie].length = 1.2: ",
                "are 1.164820928 m apart at t = 0 (off by -3.518e-2 m",
                "the markers must start at the length",
            ],
        ),
        // The hinge's markers coincide: a distance left to the start would be zero.
        (
            pendulum,
            tie(
                r#"body1: "link1", marker1: "J", body2: "link2", marker2: "J""#,
                "None",
            ),
            &[":40: constraints[tie].length = None: ", "coincide at t = 0"],
        ),
        (
            pendulum,
            plane("(0.0, 0.0, 0.0)", "O"),
            &[":40: constraints[plane].normal = [0.0, 0.0, 0.0]: must be a non-zero direction"],
        ),
        // The tip is 0.05 m above the ground plane z = 0 through O.
        (
            pendulum,
            plane("(0.0, 0.0, 1.0)", "O"),
            &[
                ":40: constraints[plane].marker2 = link2.tip at (1.138791, 0.239713, 0.050000)",
                "is 5.000e-2 m off the plane",
            ],
        ),
        (
            pendulum,
            r#"Distance(name: "hinge", body1: "link1", marker1: "O", body2: "link2", marker2: "tip", length: None)"#.into(),
            &[":40: constraints[hinge].name = hinge: a joint has this name"],
        ),
        (
            "double_four_bar.ron",
            r#"PointInPlane(name: "plane", body1: "ground", marker1: "A0", normal: (0.0, 1.0, 0.0), body2: "crank1", marker2: "B")"#.into(),
            &[":93: constraints[plane] = PointInPlane: a point-in-plane constraint needs a 3D scene"],
        ),
    ];
    for (model_name, constraint, parts) in cases {
        let e = refusal_with_constraint(model_name, &constraint);
        for part in parts {
            assert!(e.contains(part), "{constraint}: lacks {part:?}: {e}");
        }
    }
}

#[test]
fn constraint_on_one_body_or_named_twice_is_refused() {
    let e = refusal_with_constraint(
        "double_pendulum_3d.ron",
        r#"Distance(name: "tie", body1: "link2", marker1: "J", body2: "link2", marker2: "tip", length: None)"#,
    );
    assert!(
        e.contains(":40: constraints[tie].body2 = link2: a constraint joins markers of two different bodies"),
        "{e}"
    );
    let tie = r#"Distance(name: "tie", body1: "ground", marker1: "O", body2: "link2", marker2: "tip", length: None)"#;
    let e = refusal_with_constraint("double_pendulum_3d.ron", &format!("{tie},\n        {tie}"));
    assert!(
        e.contains(":41: constraints[tie].name = tie: duplicate constraint name"),
        "{e}"
    );
}
