//! The vehicle force elements (`Link` of nonlinear laws, along its markers or along a
//! body1-fixed axis; docs/methods.md §2.6) in both formulations, on the rigid 3D double
//! pendulum (`models/double_pendulum_3d.ron`):
//! - the link along link1's turning axis: its generalized forces are −∂V/∂q of its energy
//!   (virtual work through the auxiliary axis marker) in natural and in relative coordinates;
//! - a piecewise link and an axis link, with the element-force and angle sensors: every sensor
//!   agrees between the formulations, the difference falling as O(h²);
//! - a link whose spring is a `Table` equal to a linear spring runs the trajectory of the
//!   `SpringDamper` bit for bit.

mod common;
use common::*;
use flexmbd_core::Formulation;
use flexmbd_model::{
    Axis, Direction, ElementQuantity, Force, Law, Marker, Scene, Sensor, SensorKind, V3,
};
use flexmbd_test_support::scenes::VEHICLE_CORNER;

fn sensor(name: &str, kind: SensorKind) -> Sensor {
    Sensor {
        name: name.into(),
        kind,
        displacement: false,
    }
}

fn polynomial(coefficients: &[f64], about: f64) -> Law {
    Law::Polynomial {
        coefficients: coefficients.to_vec(),
        about,
    }
}

/// A link from `body1.marker1` to `body2.marker2`.
fn link(
    name: &str,
    ends: [(&str, &str); 2],
    spring: Law,
    damper: Law,
    axis: Option<Direction>,
) -> Force {
    Force::Link {
        name: name.into(),
        body1: ends[0].0.into(),
        marker1: ends[0].1.into(),
        body2: ends[1].0.into(),
        marker2: ends[1].1.into(),
        spring,
        damper,
        axis,
    }
}

/// The double pendulum with a point `mid` on link1 and an anchor on the ground.
fn pendulum() -> Scene {
    let mut s = model("double_pendulum_3d.ron");
    s.ground.push(Marker {
        name: "anchor".into(),
        position: V3([0.4, 0.6, 0.3]),
    });
    s.bodies[0].markers.push(Marker {
        name: "mid".into(),
        position: V3([0.35, 0.05, 0.0]),
    });
    s
}

/// The leaf-element-like link: along link1's body axis (0.2, 0.3, −1), a cubic spring with a
/// preload, from link1's `mid` to the tip of link2.
fn axis_link(damping: f64) -> Force {
    link(
        "leaf",
        [("link1", "mid"), ("link2", "tip")],
        polynomial(&[-30.0, 400.0, 0.0, 2.0e4], 0.1),
        polynomial(&[0.0, damping], 0.0),
        Some(Direction(V3([0.2, 0.3, -1.0]))),
    )
}

/// A strut-like link along its markers: a stiffening piecewise spring and a piecewise damper.
fn strut() -> Force {
    link(
        "strut",
        [("ground", "anchor"), ("link2", "tip")],
        Law::Piecewise {
            breakpoints: vec![0.9],
            pieces: vec![
                polynomial(&[-8.0, 60.0], 0.9),
                polynomial(&[-8.0, 60.0, 900.0], 0.9),
            ],
            continuous: true,
        },
        Law::Piecewise {
            breakpoints: vec![0.0],
            pieces: vec![polynomial(&[0.0, 0.4], 0.0), polynomial(&[0.0, 0.9], 0.0)],
            continuous: true,
        },
        None,
    )
}

#[test]
fn axis_link_forces_are_minus_its_energy_gradient_in_both_formulations() {
    let mut s = pendulum();
    s.forces = vec![axis_link(0.0)];
    let energy = sensor_column(&s, "energy");
    let absolute = {
        let (mut a, mut b) = with_and_without_forces(&s, flexmbd_absolute::compile);
        let mut q = a.coordinates().q0.clone();
        for i in 0..q.len() {
            q[i] += 0.05 * ((i as f64) * 1.3 + 0.4).sin();
        }
        spring_gradient_error(&mut a, &mut b, energy, &q, |_| 1e-6)
    };
    let relative = {
        let (mut a, mut b) = with_and_without_forces(&s, flexmbd_relative::compile);
        let mut q = a.coordinates().q0.clone();
        for i in 0..q.len() {
            q[i] += 0.3 * ((i as f64) * 1.3 + 0.4).sin();
        }
        spring_gradient_error(&mut a, &mut b, energy, &q, |_| 1e-6)
    };
    for (form, (err, q_link)) in [("absolute", absolute), ("relative", relative)] {
        eprintln!("{form}: |Q_link + ∂V/∂q| {err:.1e} (|Q_link| {q_link:.2})");
        assert!(q_link > 1.0 && err < 1e-7 * q_link, "{form}: {err:e}");
    }
}

#[test]
fn nonlinear_links_and_their_sensors_agree_with_the_relative_formulation() {
    let mut s = pendulum();
    s.forces = vec![strut(), axis_link(0.5)];
    s.sensors.extend([
        sensor(
            "strut",
            SensorKind::ElementForce {
                force: "strut".into(),
                quantity: ElementQuantity::Force,
            },
        ),
        sensor(
            "leaf_length",
            SensorKind::ElementForce {
                force: "leaf".into(),
                quantity: ElementQuantity::Length,
            },
        ),
        sensor(
            "leaf",
            SensorKind::ElementForce {
                force: "leaf".into(),
                quantity: ElementQuantity::Force,
            },
        ),
        sensor(
            "link2_pitch",
            SensorKind::Angle {
                body: "link2".into(),
                axis: Axis::Y,
            },
        ),
    ]);
    let d: Vec<f64> = [1e-3_f64, 5e-4, 2.5e-4]
        .iter()
        .map(|&h| {
            let every = (0.01 / h).round() as usize;
            let (a, _) = run_absolute(&s, h, 1.0, every);
            let (r, _) = run_relative(&s, h, 1.0, every);
            (0..a[0].len())
                .map(|c| {
                    let (d, range) = column_difference(&a, &r, c);
                    assert!(range > 1e-6, "column {c} does not move");
                    d / range
                })
                .fold(0.0, f64::max)
        })
        .collect();
    eprintln!("links with sensors, relative vs absolute / range: {d:?}");
    assert!(d[0] / d[1] > 3.0 && d[1] / d[2] > 3.0, "{d:?}");
    assert!(d[2] < 1e-4, "{d:?}");
}

#[test]
fn a_table_link_equal_to_a_linear_spring_runs_the_spring_damper_trajectory() {
    let (k, c) = (40.0, 0.8);
    let mut spring = pendulum();
    spring.forces = vec![Force::SpringDamper {
        name: "s".into(),
        body1: "ground".into(),
        marker1: "anchor".into(),
        body2: "link2".into(),
        marker2: "tip".into(),
        stiffness: k,
        damping: c,
        free_length: Some(1.0),
    }];
    let mut table = spring.clone();
    table.forces = vec![link(
        "s",
        [("ground", "anchor"), ("link2", "tip")],
        // One segment, extrapolated both ways: 0 + (k/1)(l − 1), the spring's k (l − l₀)
        // operation for operation.
        Law::Table {
            x: vec![1.0, 2.0],
            y: vec![0.0, k],
        },
        polynomial(&[0.0, c], 0.0),
        None,
    )];
    let h = 1e-3;
    let (a, _) = run_absolute(&spring, h, 1.0, 10);
    let (b, _) = run_absolute(&table, h, 1.0, 10);
    let (ar, _) = run_relative(&spring, h, 1.0, 10);
    let (br, _) = run_relative(&table, h, 1.0, 10);
    // The link's energy counts from its start length, the spring's from its free length:
    // the energies differ by the constant ½ k (l(0) − l₀)².
    let energy = sensor_column(&spring, "energy");
    for (x, y) in [(&a, &b), (&ar, &br)] {
        let offset = x[0][energy] - y[0][energy];
        assert!(offset > 0.1, "{offset}");
        for (rx, ry) in x.iter().zip(y.iter()) {
            for c in 0..rx.len() {
                if c == energy {
                    assert!((rx[c] - ry[c] - offset).abs() < 1e-12);
                } else {
                    assert_eq!(rx[c].to_bits(), ry[c].to_bits(), "column {c}");
                }
            }
        }
    }
    assert!(column_difference(&a, &ar, 0).1 > 0.1, "the tip moves");
}

/// The planar slider-crank (rigid rod) with a piecewise link from the crank pin to the wall
/// and a link along the crank's body y axis to the rod's middle, with their element-force
/// sensors and the rod's angle: the two formulations agree at O(h²).
#[test]
fn planar_links_agree_with_the_relative_formulation() {
    let mut s = model("slider_crank.ron");
    s.bodies[1].flexible = false;
    s.sensors.retain(|sensor| sensor.name != "rod_mode2");
    s.forces.extend([
        link(
            "crank_wall",
            [("crank", "B"), ("ground", "wall")],
            Law::Piecewise {
                breakpoints: vec![1.6],
                pieces: vec![
                    polynomial(&[0.0, 30.0], 1.6),
                    polynomial(&[0.0, 30.0, 200.0], 1.6),
                ],
                continuous: true,
            },
            polynomial(&[0.0, 0.5], 0.0),
            None,
        ),
        link(
            "crank_rod",
            [("crank", "B"), ("rod", "mid")],
            polynomial(&[2.0, 80.0], 0.0),
            polynomial(&[0.0, 0.3], 0.0),
            Some(Direction(V3([0.0, 1.0, 0.0]))),
        ),
    ]);
    s.sensors.extend([
        sensor(
            "crank_wall",
            SensorKind::ElementForce {
                force: "crank_wall".into(),
                quantity: ElementQuantity::Force,
            },
        ),
        sensor(
            "crank_rod",
            SensorKind::ElementForce {
                force: "crank_rod".into(),
                quantity: ElementQuantity::Force,
            },
        ),
        sensor(
            "rod_angle",
            SensorKind::Angle {
                body: "rod".into(),
                axis: Axis::Z,
            },
        ),
    ]);
    let cols: Vec<usize> = [
        "slider_x",
        "crank_angle",
        "crank_wall",
        "crank_rod",
        "rod_angle",
    ]
    .iter()
    .map(|name| sensor_column(&s, name))
    .collect();
    let d: Vec<f64> = [1e-3_f64, 5e-4, 2.5e-4]
        .iter()
        .map(|&h| {
            let every = (0.01 / h).round() as usize;
            let (a, _) = run_absolute(&s, h, 1.0, every);
            let (r, _) = run_relative(&s, h, 1.0, every);
            worst_difference(&a, &r, &cols)
        })
        .collect();
    eprintln!("planar links, relative vs absolute / range: {d:?}");
    assert!(d[0] / d[1] > 3.0 && d[1] / d[2] > 3.0, "{d:?}");
    assert!(d[2] < 1e-5, "{d:?}");
}

/// The vehicle corner of issue 13's syntax (strut, leaf element along the chassis axis, two
/// tyres in contact on level road), at rest: its force elements' Q is −∂V/∂q of the energy
/// sensor's potential (the laws' integrals, ½ K δ²) in both formulations.
#[test]
fn vehicle_corner_forces_are_minus_their_energy_gradient_in_both_formulations() {
    let mut s = Scene::from_ron_str(VEHICLE_CORNER, "corner").unwrap();
    s.sensors = vec![sensor("energy", SensorKind::Energy)];
    let perturbed = |mut q: nalgebra::DVector<f64>| {
        for i in 0..q.len() {
            q[i] += 2e-3 * ((i as f64) * 1.3 + 0.4).sin();
        }
        q
    };
    let absolute = {
        let (mut a, mut b) = with_and_without_forces(&s, flexmbd_absolute::compile);
        let q = perturbed(a.coordinates().q0.clone());
        spring_gradient_error(&mut a, &mut b, 0, &q, |_| 1e-7)
    };
    let relative = {
        let (mut a, mut b) = with_and_without_forces(&s, flexmbd_relative::compile);
        let q = perturbed(a.coordinates().q0.clone());
        spring_gradient_error(&mut a, &mut b, 0, &q, |_| 1e-7)
    };
    for (form, (err, q_forces)) in [("absolute", absolute), ("relative", relative)] {
        eprintln!("{form}: |Q + ∂V/∂q| {err:.1e} (|Q| {q_forces:.0})");
        assert!(q_forces > 1e3 && err < 1e-6 * q_forces, "{form}: {err:e}");
    }
}

/// A free wheel (a 60 kg body on a `Free` joint, its centre W at its centre of mass) rolling
/// at 5 m/s over the benchmark's cosine bump on a profile-normal tyre with a lateral damper:
/// height, speeds and tyre force agree between the formulations.
#[test]
fn free_wheel_over_the_cosine_bump_agrees_with_the_relative_formulation() {
    let s = Scene::from_ron_str(
        r#"(
    name: "wheel on the bump", dim: Spatial, gravity: [0.0, 0.0, -9.81],
    ground: [(name: "O", position: [0.5, 0.0, 0.363])],
    roads: [Road(name: "bump", profile: CosineBump(start: 0.97, length: 5.0, height: 0.2))],
    bodies: [(name: "wheel", origin: [0.5, 0.0, 0.363],
        model: Rigid(mass: 60.0, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([1.5, 2.5, 1.5])),
        markers: [(name: "W", position: [0.0, 0.0, 0.0])],
        velocity: (linear: [5.0, 0.1, 0.0]))],
    joints: [(name: "free", kind: Free, body1: "ground", marker1: "O", body2: "wheel", marker2: "W")],
    forces: [Tyre(name: "tyre", body: "wheel", marker: "W", road: "bump", radius: 0.364325,
        stiffness: 460000.0, contact: ProfileNormal, lateral_damping: 500.0)],
    sensors: [(name: "z", kind: Position(body: "wheel", marker: "W", component: Z)),
              (name: "vx", kind: Velocity(body: "wheel", marker: "W", component: X)),
              (name: "vy", kind: Velocity(body: "wheel", marker: "W", component: Y)),
              (name: "tyre", kind: ElementForce(force: "tyre"))],
    solver: (step: 1e-3, duration: 1.0),
)"#,
        "wheel",
    )
    .unwrap();
    let d: Vec<f64> = [1e-3_f64, 5e-4, 2.5e-4]
        .iter()
        .map(|&h| {
            let every = (0.01 / h).round() as usize;
            let (a, _) = run_absolute(&s, h, 1.0, every);
            let (r, _) = run_relative(&s, h, 1.0, every);
            // The bump loads the tyre well above the weight, and it stays on the road
            // (a lift-off's kink would spoil the O(h²) comparison).
            let low = a.iter().map(|row| row[3]).fold(f64::MAX, f64::min);
            let high = a.iter().map(|row| row[3]).fold(0.0, f64::max);
            assert!(
                low > 0.0 && high > 1.3 * 60.0 * 9.81,
                "h = {h}: {low} – {high} N"
            );
            worst_difference(&a, &r, &[0, 1, 2, 3])
        })
        .collect();
    eprintln!("free wheel over the bump, relative vs absolute / range: {d:?}");
    // The force acts at the centre of mass: the body only translates, and its translation
    // is the same coordinates, discretised the same way, in both formulations — they agree
    // to the Newton tolerance at every step (measured ≤ 1e-9 of the range).
    assert!(d.iter().all(|&x| x < 1e-8), "{d:?}");
}
