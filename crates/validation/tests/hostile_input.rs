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

/// The scene of `models/NAME` text after `edit`, parsed (not validated) with its source.
fn scene_text(name: &str, edit: impl Fn(String) -> String) -> Scene {
    let path = models_dir().join(name);
    let text = edit(std::fs::read_to_string(&path).unwrap());
    Scene::from_ron_str(&text, &format!("models/{name}")).unwrap()
}

fn beam_of<'a>(scene: &'a mut Scene, body: &str) -> &'a mut flexmbd_fe::BeamBodySpec {
    let b = scene.bodies.iter_mut().find(|b| b.name == body).unwrap();
    match &mut b.model {
        BodyModel::Beam(spec) => spec,
        BodyModel::Rigid { .. } => panic!("{body} is rigid"),
    }
}

#[test]
fn nan_marker_position_is_refused_in_both_formulations() {
    let s = scene_text("double_four_bar.ron", |t| {
        t.replacen(
            r#"(name: "A", position: [0.0, 0.0])"#,
            r#"(name: "A", position: [NaN, 0.0])"#,
            1,
        )
    });
    let e = refusal_in_both(&s);
    assert_eq!(
        e,
        "models/double_four_bar.ron:33: bodies[crank1].markers[A].position[0] = NaN: \
         must be finite: allowed [-1e6, 1e6] m"
    );
}

#[test]
fn validation_error_names_the_line() {
    // Each refusal names the line of its field in the file; a field the file omits has none.
    let s = scene_text("double_four_bar.ron", |t| {
        t.replace("gravity: [0.0, -9.81]", "gravity: [0.0, -1e308]")
    });
    let e = refusal_in_both(&s);
    assert!(
        e.starts_with("models/double_four_bar.ron:16: gravity[1] = -1e308"),
        "{e}"
    );
    let s = scene_text("spin_up_beam_2d.ron", |t| {
        t.replace("t_s: 15.0", "t_s: -1.0")
    });
    let e = refusal_in_both(&s);
    assert!(
        e.starts_with("models/spin_up_beam_2d.ron:61: drivers[spin].law.SpinUp.t_s"),
        "{e}"
    );
    let s = scene_text("double_four_bar.ron", |t| {
        t.replacen(r#"marker2: "A"),"#, r#"marker2: "Z"),"#, 1)
    });
    let e = refusal_in_both(&s);
    assert!(
        e.starts_with("models/double_four_bar.ron:85: joints[A0].marker2"),
        "{e}"
    );
    // A name given twice: the line of the repeat.
    let s = scene_text("double_four_bar.ron", |t| {
        t.replacen(r#"(name: "B0""#, r#"(name: "A0""#, 1)
    });
    let e = refusal_in_both(&s);
    assert!(
        e.starts_with("models/double_four_bar.ron:86: joints[A0].name = A0: duplicate joint name"),
        "{e}"
    );
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
    let e = refusal_in_both(&s);
    assert!(
        e.contains("bodies = []: the scene has no moving body"),
        "{e}"
    );
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
    let e = refusal_in_both(&s);
    assert!(
        e.contains("drivers[again].joint = hub: joint `hub` is already driven by `spin`"),
        "{e}"
    );
}

#[test]
fn non_coincident_joint_markers_refused_in_both_formulations() {
    let mut s = model("double_four_bar.ron");
    let coupler2 = s.bodies.iter_mut().find(|b| b.name == "coupler2").unwrap();
    coupler2.origin.0[1] += 0.01; // joined at B1b (its marker A) and B2
    let e = refusal_in_both(&s);
    assert!(
        e.contains("joints[B1b].marker2 = coupler2.A at (1.000000, 1.010000)")
            && e.contains("joined markers must coincide at t = 0"),
        "{e}"
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
    let e = refusal_in_both(&s);
    assert!(
        e.contains("body `bar`: frame.Dofs = 4 DOFs: hyperstatic"),
        "{e}"
    );
}

#[test]
fn substructuring_100000_is_refused_with_memory() {
    let mut s = model("spin_up_beam_3d.ron");
    s.solver.stiffening = Stiffening::Substructuring(100_000);
    let e = refusal_in_both(&s);
    assert!(
        e.contains("solver.stiffening = Substructuring(100000): too many substructures")
            && e.contains("about 1400000 coordinates")
            && e.contains("15.7 TB each"),
        "{e}"
    );
}

#[test]
fn elements_per_segment_of_u64_max_is_refused_with_memory() {
    let mut s = model("flexible_pendulum.ron");
    beam_of(&mut s, "bar").geometry.elements_per_segment = usize::MAX;
    let e = refusal_in_both(&s);
    assert!(
        e.contains("55340232221128654848 FE DOFs") && e.contains("bytes each"),
        "{e}"
    );
}

#[test]
fn axial_modes_error_names_axial_modes() {
    let mut s = model("spin_up_beam_2d.ron");
    beam_of(&mut s, "beam").axial_modes = 50;
    let e = refusal_in_both(&s);
    assert!(
        e.contains("axial_modes = 50") && !e.contains("normal modes requested"),
        "{e}"
    );
    // Within the interior DOFs but more than the beam's 20 axial ones: found by the reduction.
    beam_of(&mut s, "beam").axial_modes = 25;
    let e = refusal_in_both(&s);
    assert!(
        e.contains("axial_modes = 25: the model has only 20 purely axial"),
        "{e}"
    );
}

#[test]
fn every_model_still_loads() {
    for entry in std::fs::read_dir(models_dir()).unwrap() {
        let path = entry.unwrap().path();
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
    let e = refusal_in_both(&scene_text("spin_up_beam_2d.ron", |t| {
        t.replace(
            r#"kind: Revolute(), body1: "ground""#,
            r#"kind: Rigid, body1: "ground""#,
        )
    }));
    assert!(
        e.contains(":61: drivers[spin].joint = hub: only revolute"),
        "{e}"
    );
    let e = refusal_in_both(&scene_text("double_pendulum_3d.ron", |t| {
        t.replace(
            r#"kind: JointCoordinate(joint: "hinge")"#,
            r#"kind: JointCoordinate(joint: "ball")"#,
        )
    }));
    assert!(
        e.contains(":44: sensors[hinge].joint = ball: a joint coordinate"),
        "{e}"
    );
    let e = refusal_in_both(&scene_text("double_pendulum_3d.ron", |t| {
        t.replace("Revolute(axis: Some([1.0, 1.0, 0.5]))", "Revolute()")
    }));
    assert!(e.contains("joints[hinge].kind.Revolute.axis = None"), "{e}");
    let e = refusal_in_both(&scene_text("double_pendulum_3d.ron", |t| {
        t.replace(
            "Revolute(axis: Some([1.0, 1.0, 0.5]))",
            "Universal(axis1: [1.0, 0.0, 0.0], axis2: [1.0, 0.1, 0.0])",
        )
    }));
    assert!(e.contains(":38: joints[hinge].kind.Universal.axis2"), "{e}");
    let e = refusal_in_both(&scene_text("slider_crank.ron", |t| {
        t.replace(
            "Prismatic(axis: [1.0, 0.0])",
            "Prismatic(axis: [1.0, 0.0, 1.0])",
        )
    }));
    assert!(
        e.contains(":68: joints[rail].kind.Prismatic.axis = [1.0, 0.0, 1.0]"),
        "{e}"
    );
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
    assert!(refusal_in_both(&s).contains("solver.duration = inf: must be finite"));
}

#[test]
fn subnormal_density_is_refused_not_a_slow_eigensolver() {
    // Found by the fuzzer (seed 2026): a density of 1e-308 made the FE matrices subnormal
    // and the eigensolver spent seconds before failing; moduli, densities and masses are
    // bounded below as well as above.
    let s = scene_text("flexible_pendulum_3d.ron", |t| {
        t.replacen("7850.0", "1e-308", 1)
    });
    let e = refusal_in_both(&s);
    assert!(
        e.contains("density = 1e-308: out of range: allowed [1e-3, 1e6] kg/m³"),
        "{e}"
    );
}
