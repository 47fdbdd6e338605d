//! The vehicle force elements and sensors end to end (docs/methods.md §2.6), in both
//! formulations, against closed forms: a mass hanging on a `Link` with a cubic spring (along
//! its markers and along a ground-fixed axis), a wheel on a vertical slider resting on a
//! `Vertical` tyre (deflection mg/K, frequency √(K/m)/2π), the tyre lifting off (exactly no
//! force in the air), `ProfileNormal` on a flat road equal to `Vertical`, and the `Angle`
//! sensor on a body turned by a driven revolute.

use flexmbd::model::{FormulationKind, Scene};
use flexmbd::{Simulation, equilibrium, vibration};
use std::f64::consts::PI;

const FORMULATIONS: [FormulationKind; 2] = [FormulationKind::Absolute, FormulationKind::Relative];

fn scene(text: &str, formulation: FormulationKind) -> Scene {
    let mut s = Scene::from_ron_str(text, "test scene").unwrap();
    s.solver.formulation = formulation;
    s.validate().unwrap();
    s
}

fn relative_error(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A planar block on a vertical slider hanging from a link whose spring is
/// F = k x + k₃ x³ (x = l − 1, tension positive); `axis`: `None` or `Some((0.0, -1.0))`.
fn hanging_on_a_link(axis: &str) -> String {
    format!(
        r#"(
    name: "link mass", dim: Planar, gravity: [0.0, -9.81],
    ground: [(name: "A", position: [0.0, 0.0]), (name: "G", position: [0.0, -1.0])],
    bodies: [(name: "block", origin: [0.0, -1.0],
        model: Rigid(mass: 3.0, center_of_mass: [0.0, 0.0], inertia: Planar(0.01)),
        markers: [(name: "P", position: [0.0, 0.0])])],
    joints: [(name: "slide", kind: Prismatic(axis: [0.0, 1.0, 0.0]), body1: "ground", marker1: "G", body2: "block", marker2: "P")],
    forces: [Link(name: "spring", body1: "ground", marker1: "A", body2: "block", marker2: "P",
        spring: Polynomial(about: 1.0, coefficients: [0.0, 4000.0, 0.0, 1.0e8]), damper: Zero, axis: {axis})],
    sensors: [(name: "y", kind: Position(body: "block", marker: "P", component: Y)),
              (name: "spring", kind: ElementForce(force: "spring"))],
    solver: (step: 1e-3, duration: 1.0),
)"#
    )
}

#[test]
fn mass_on_a_cubic_link_hangs_at_the_closed_form_stretch() {
    let (k, k3, weight) = (4000.0, 1.0e8, 3.0 * 9.81);
    // k x + k₃ x³ = m g by Newton.
    let mut x: f64 = weight / k;
    for _ in 0..50 {
        x -= (k * x + k3 * x.powi(3) - weight) / (k + 3.0 * k3 * x * x);
    }
    assert!(
        x < 0.9 * weight / k,
        "the cubic term matters: {x} vs {}",
        weight / k
    );
    for axis in ["None", "Some((0.0, -1.0))"] {
        for form in FORMULATIONS {
            let e = equilibrium(&scene(&hanging_on_a_link(axis), form)).unwrap();
            eprintln!("{axis}, {form:?}:\n{}", e.to_text());
            let stretch = -1.0 - e.sensor("y").unwrap();
            assert!(
                relative_error(stretch, x) < 1e-9,
                "{axis} {form:?}: {stretch} vs {x}"
            );
            let f = &e.forces[0];
            assert_eq!((f.name.as_str(), f.kind), ("spring", "Link"));
            assert!(relative_error(f.force, weight) < 1e-9, "{f:?}");
            assert!(relative_error(f.length, 1.0 + x) < 1e-12, "{f:?}");
            assert_eq!(f.free_length, None);
            assert_eq!(e.sensor("spring"), Some(f.force));
        }
    }
}

/// A 50 kg wheel on a vertical slider, its centre W at `z0`, on a tyre of the benchmark's
/// radius and stiffness on a flat road.
fn wheel(z0: f64, contact: &str) -> String {
    format!(
        r#"(
    name: "wheel", dim: Spatial, gravity: [0.0, 0.0, -9.81],
    ground: [(name: "G", position: [0.0, 0.0, {z0}])],
    roads: [Road(name: "flat", profile: Flat)],
    bodies: [(name: "wheel", origin: [0.0, 0.0, {z0}],
        model: Rigid(mass: 50.0, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([1.0, 2.0, 1.0])),
        markers: [(name: "W", position: [0.0, 0.0, 0.0])])],
    joints: [(name: "slide", kind: Prismatic(axis: [0.0, 0.0, 1.0]), body1: "ground", marker1: "G", body2: "wheel", marker2: "W")],
    forces: [Tyre(name: "tyre", body: "wheel", marker: "W", road: "flat", radius: 0.364325,
        stiffness: 460000.0, contact: {contact}, lateral_damping: 10.0)],
    sensors: [(name: "z", kind: Position(body: "wheel", marker: "W", component: Z)),
              (name: "tyre", kind: ElementForce(force: "tyre")),
              (name: "deflection", kind: ElementForce(force: "tyre", quantity: Length))],
    solver: (step: 5e-4, duration: 1.0),
)"#
    )
}

#[test]
fn wheel_on_a_vertical_tyre_deflects_by_mg_over_k_and_hops_at_sqrt_k_over_m() {
    let (m, k, r) = (50.0, 460000.0, 0.364325);
    for form in FORMULATIONS {
        let s = scene(&wheel(0.36, "Vertical"), form);
        let e = equilibrium(&s).unwrap();
        eprintln!("{form:?}:\n{}", e.to_text());
        let z = e.sensor("z").unwrap();
        assert!(
            relative_error(r - z, m * 9.81 / k) < 1e-9,
            "{form:?}: z = {z}"
        );
        let f = &e.forces[0];
        assert_eq!(f.kind, "Tyre");
        assert!(relative_error(f.force, m * 9.81) < 1e-9, "{f:?}");
        assert!(relative_error(f.length, m * 9.81 / k) < 1e-9, "{f:?}");
        let v = vibration(&s).unwrap();
        eprintln!("{}", v.to_text());
        let hz = v.frequencies("oscillatory");
        assert_eq!(hz.len(), 1, "{form:?}");
        let exact = (k / m).sqrt() / (2.0 * PI);
        assert!(
            relative_error(hz[0], exact) < 1e-6,
            "{form:?}: {} vs {exact}",
            hz[0]
        );
    }
}

/// The sensor rows of a run, every step.
fn rows(s: &Scene) -> Vec<Vec<f64>> {
    let mut sim = Simulation::new(s).unwrap();
    let mut out = vec![sim.sensors()];
    while sim.time() < s.solver.duration - 0.5 * s.solver.step {
        sim.step().unwrap();
        out.push(sim.sensors());
    }
    out
}

#[test]
fn a_tyre_in_the_air_carries_exactly_nothing_and_never_pulls() {
    let r = 0.364325;
    for form in FORMULATIONS {
        // Dropped from 8 cm above touching: it falls, lands, bounces back into the air.
        let rows = rows(&scene(&wheel(r + 0.08, "Vertical"), form));
        let (mut airborne, mut loaded, mut landed_again) = (0, 0.0f64, false);
        for (k, row) in rows.iter().enumerate() {
            let (z, force, deflection) = (row[0], row[1], row[2]);
            assert_eq!(deflection, r - z, "{form:?}: row {k}");
            if z > r {
                assert_eq!(
                    force.to_bits(),
                    0.0f64.to_bits(),
                    "{form:?}: row {k}, z = {z}"
                );
                airborne += 1;
                landed_again |= loaded > 0.0;
            } else {
                assert!(force >= 0.0, "{form:?}: row {k}");
                loaded = loaded.max(force);
            }
        }
        assert!(
            airborne > 100 && loaded > 1e3 && landed_again,
            "{form:?}: {airborne}, {loaded}"
        );
    }
}

#[test]
fn profile_normal_contact_on_a_flat_road_is_the_vertical_contact() {
    let r = 0.364325;
    for form in FORMULATIONS {
        let vertical = rows(&scene(&wheel(r + 0.02, "Vertical"), form));
        let normal = rows(&scene(&wheel(r + 0.02, "ProfileNormal"), form));
        assert_eq!(vertical, normal, "{form:?}");
        assert!(vertical.iter().any(|row| row[1] > 1e3));
    }
}

/// A plate on a revolute joint about ground axis `axis`, turned `start` rad about it at t = 0,
/// driven harmonically; an `Angle` sensor of component `component` and the joint's coordinate.
fn driven_plate(axis: &str, component: &str) -> String {
    format!(
        r#"(
    name: "plate", dim: Spatial, gravity: [0.0, 0.0, -9.81],
    ground: [(name: "O", position: [0.0, 0.0, 0.0])],
    bodies: [(name: "plate", orientation: AxisAngle(axis: {axis}, angle: 0.3),
        model: Rigid(mass: 2.0, center_of_mass: [0.1, 0.05, 0.02], inertia: Diagonal([0.1, 0.2, 0.25])),
        markers: [(name: "O", position: [0.0, 0.0, 0.0])])],
    joints: [(name: "hinge", kind: Revolute(axis: Some({axis})), body1: "ground", marker1: "O", body2: "plate", marker2: "O")],
    drivers: [(name: "turn", joint: "hinge", law: Harmonic(amplitude: 1.2, frequency: 1.5))],
    sensors: [(name: "angle", kind: Angle(body: "plate", axis: {component})),
              (name: "hinge", kind: JointCoordinate(joint: "hinge"))],
    solver: (step: 1e-3, duration: 0.5),
)"#
    )
}

#[test]
fn angle_sensor_on_a_driven_revolute_reads_the_driven_angle() {
    for (axis, component) in [
        ("[1.0, 0.0, 0.0]", "X"),
        ("[0.0, 1.0, 0.0]", "Y"),
        ("[0.0, 0.0, 1.0]", "Z"),
    ] {
        for form in FORMULATIONS {
            let rows = rows(&scene(&driven_plate(axis, component), form));
            let peak = rows.iter().map(|r| r[1].abs()).fold(0.0, f64::max);
            assert!(peak > 1.0, "{component} {form:?}: {peak}");
            for row in &rows {
                assert!(
                    (row[0] - row[1]).abs() < 1e-8,
                    "{component} {form:?}: angle {} vs hinge {}",
                    row[0],
                    row[1]
                );
            }
        }
    }
}
