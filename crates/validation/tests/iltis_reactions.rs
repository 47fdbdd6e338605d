//! The joints' and constraints' reactions at the Iltis benchmark vehicle's static
//! equilibrium (scene C0, `models/iltis_vehicle_benchmark.ron`), in both formulations:
//! every body balances, the two formulations give the same reactions, and the loads at a
//! corner are consistent with the force elements' — the carrier's vertical balance with its
//! tyre load and leaf element, the A-arm's moment about its pivot with its strut.

use flexmbd::equilibrium::{Equilibrium, JointReaction};
use flexmbd::model::{Axis, FormulationKind, Scene, Sensor, SensorKind};
use nalgebra::{Matrix3, Rotation3, Vector3};

const FORMS: [FormulationKind; 2] = [FormulationKind::Absolute, FormulationKind::Relative];
const G: f64 = 9.81;

/// Scene C0 in `form`, with position sensors on the markers the checks below need.
fn vehicle(form: FormulationKind) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../models/iltis_vehicle_benchmark.ron");
    let mut scene = Scene::load(path).unwrap();
    scene.solver.formulation = form;
    for (body, marker) in [
        ("chassis", "S0_fl"),
        ("aarm_fl", "S1"),
        ("aarm_fl", "B"),
        ("aarm_fl", "A0"),
    ] {
        for (axis, tag) in [(Axis::X, "x"), (Axis::Y, "y"), (Axis::Z, "z")] {
            scene.sensors.push(Sensor {
                name: format!("{body}.{marker}.{tag}"),
                kind: SensorKind::Position {
                    body: body.into(),
                    marker: marker.into(),
                    component: axis,
                    frame: None,
                },
                displacement: false,
            });
        }
    }
    scene.sensors.push(Sensor {
        name: "chassis_yaw".into(),
        kind: SensorKind::Angle {
            body: "chassis".into(),
            axis: Axis::Z,
        },
        displacement: false,
    });
    scene
}

fn point(e: &Equilibrium, body: &str, marker: &str) -> Vector3<f64> {
    let c = |tag: &str| e.sensor(&format!("{body}.{marker}.{tag}")).unwrap();
    Vector3::new(c("x"), c("y"), c("z"))
}

fn reaction<'a>(e: &'a Equilibrium, name: &str) -> &'a JointReaction {
    let r = e.reactions.as_ref().unwrap();
    r.joints.iter().find(|j| j.name == name).unwrap()
}

fn force_element(e: &Equilibrium, name: &str) -> f64 {
    e.forces.iter().find(|f| f.name == name).unwrap().force
}

/// The chassis rotation since t = 0 from its Cardan-angle sensors (R = R_x R_y R_z).
fn chassis_turn(e: &Equilibrium) -> Matrix3<f64> {
    let angle = |name: &str| e.sensor(name).unwrap();
    let r = |axis: Vector3<f64>, a: f64| {
        *Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), a).matrix()
    };
    r(Vector3::x(), angle("chassis_roll"))
        * r(Vector3::y(), angle("chassis_pitch"))
        * r(Vector3::z(), angle("chassis_yaw"))
}

#[test]
fn iltis_equilibrium_reactions_balance_every_body_and_agree_between_formulations() {
    let [absolute, relative] = FORMS.map(|form| flexmbd::equilibrium(&vehicle(form)).unwrap());
    eprintln!("{}", relative.reactions.as_ref().unwrap().to_text());
    for e in [&absolute, &relative] {
        let r = e.reactions.as_ref().unwrap();
        // 9 bodies; 4 revolutes (5 each), 4 spherical (3), 12 constraints (1).
        assert_eq!((r.equations, r.unknowns), (54, 44), "{}", e.formulation);
        assert!(!r.redundant, "{}: rank {}", e.formulation, r.rank);
        assert!(
            r.residual_force < 1e-6 && r.residual_moment < 1e-6,
            "{}: unbalanced {} N, {} N m",
            e.formulation,
            r.residual_force,
            r.residual_moment
        );
    }
    let (ra, rr) = (absolute.reactions.unwrap(), relative.reactions.unwrap());
    let largest = ra
        .joints
        .iter()
        .flat_map(|j| j.force.iter().chain(&j.moment))
        .fold(0.0f64, |m, v| m.max(v.abs()));
    for (a, r) in ra.joints.iter().zip(&rr.joints) {
        assert_eq!(a.name, r.name);
        for (x, y) in a
            .force
            .iter()
            .chain(&a.moment)
            .zip(r.force.iter().chain(&r.moment))
        {
            assert!(
                (x - y).abs() < 1e-7 * largest,
                "{}: absolute {a:?}, relative {r:?}",
                a.name
            );
        }
    }
}

#[test]
fn iltis_corner_loads_agree_with_the_reactions_at_the_carrier_and_the_a_arm() {
    for form in FORMS {
        let e = flexmbd::equilibrium(&vehicle(form)).unwrap();
        // The front-left carrier (57.35 kg), vertically: its tyre load up, its weight, the
        // leaf element's force at U along the chassis-fixed −z (tension T pulls U towards
        // E: −T a on U with a = R (0, 0, −1)), and the ball joint's, leaf link's and tie
        // rod's reactions on it.
        let a = chassis_turn(&e) * Vector3::new(0.0, 0.0, -1.0);
        let leaf = -force_element(&e, "leaf_fl") * a;
        let reactions: f64 = [
            "ball_joint_fl",
            "leaf_link_fl",
            "leaf_link_plane_fl",
            "tie_rod_fl",
        ]
        .iter()
        .map(|n| reaction(&e, n).force[2])
        .sum();
        let tyre = force_element(&e, "tyre_fl");
        let vertical = tyre - 57.35 * G + leaf.z + reactions;
        eprintln!(
            "{form:?}: tyre {tyre} N, leaf {} N, reactions {reactions} N",
            leaf.z
        );
        assert!(
            vertical.abs() < 1e-6 * tyre,
            "{form:?}: carrier unbalanced by {vertical} N"
        );
        // The front-left A-arm (6 kg), about its pivot axis (chassis x through A0): its
        // weight at its centre of mass (on B–A0, 0.16073 m from B), the strut's force at S1
        // (−T n, n from S0 to S1), and the ball joint's reaction on the carrier, reversed,
        // at B. The pivot carries no moment about its axis.
        let (b, a0, s1, s0) = (
            point(&e, "aarm_fl", "B"),
            point(&e, "aarm_fl", "A0"),
            point(&e, "aarm_fl", "S1"),
            point(&e, "chassis", "S0_fl"),
        );
        let centre = b + (a0 - b) * (0.16073 / 0.3214000622);
        let strut = -force_element(&e, "strut_fl") * (s1 - s0).normalize();
        let ball = -Vector3::from(reaction(&e, "ball_joint_fl").force);
        let axis = chassis_turn(&e) * Vector3::x();
        let about_pivot = ((centre - a0).cross(&Vector3::new(0.0, 0.0, -6.0 * G))
            + (s1 - a0).cross(&strut)
            + (b - a0).cross(&ball))
        .dot(&axis);
        let scale = (b - a0).norm() * ball.norm();
        eprintln!("{form:?}: A-arm moment about its pivot {about_pivot} N m (scale {scale})");
        assert!(
            about_pivot.abs() < 1e-6 * scale,
            "{form:?}: {about_pivot} N m"
        );
        let pivot = reaction(&e, "aarm_pivot_fl");
        assert!(Vector3::from(pivot.moment).dot(&axis).abs() < 1e-9 * scale);
    }
}
