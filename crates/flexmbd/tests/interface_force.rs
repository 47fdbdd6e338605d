//! The `InterfaceForce` sensor (`flexmbd_model::interface_force`) against physics: a rigid
//! pendulum's pin force against Newton–Euler in closed form, both formulations, planar and
//! spatial; the flexible pendulum's pin force in the absolute formulation against the
//! relative one; at a static equilibrium the sensor against `flexmbd equilibrium`'s joint
//! reactions (the static balance written separately, `equilibrium/reactions.rs`); and bad
//! input refused by name.

use flexmbd::model::{Axis, InterfaceQuantity, Sensor, SensorKind};
use flexmbd::model::{FormulationKind, Scene};
use flexmbd::{Simulation, equilibrium};

const FORMULATIONS: [FormulationKind; 2] = [FormulationKind::Absolute, FormulationKind::Relative];

fn scene(text: &str, formulation: FormulationKind) -> Scene {
    let mut s = Scene::from_ron_str(text, "test scene").unwrap();
    s.solver.formulation = formulation;
    s.validate().unwrap();
    s
}

/// The sensor rows of a run, every step, by name.
fn run(s: &Scene) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut sim = Simulation::new(s).unwrap();
    let names = sim.sensor_names().to_vec();
    let mut out = vec![sim.sensors()];
    while sim.time() < s.solver.duration - 0.5 * s.solver.step {
        sim.step().unwrap();
        out.push(sim.sensors());
    }
    (names, out)
}

fn column(names: &[String], rows: &[Vec<f64>], name: &str) -> Vec<f64> {
    let k = names.iter().position(|n| n == name).unwrap();
    rows.iter().map(|r| r[k]).collect()
}

const MASS: f64 = 2.0;
const LENGTH: f64 = 1.0;
const G: f64 = 9.81;

/// A uniform rigid bar (mass 2 kg, length 1 m) pinned at one end, released from horizontal;
/// sensors: the pin angle and the pin's force (ground and bar axes) and moment.
fn rigid_pendulum(spatial: bool) -> String {
    let i_g = MASS * LENGTH * LENGTH / 12.0;
    let (dim, gravity, o, origin, com, inertia, axis) = if spatial {
        (
            "Spatial",
            "[0.0, -9.81, 0.0]",
            "[0.0, 0.0, 0.0]",
            "[0.0, 0.0, 0.0]",
            "[0.5, 0.0, 0.0]",
            format!("Diagonal([1e-4, {i_g}, {i_g}])"),
            "Some([0.0, 0.0, 1.0])",
        )
    } else {
        (
            "Planar",
            "[0.0, -9.81]",
            "[0.0, 0.0]",
            "[0.0, 0.0]",
            "[0.5, 0.0]",
            format!("Planar({i_g})"),
            "None",
        )
    };
    let sensor = |name: &str, c: &str, q: &str, frame: &str| {
        format!(
            r#"(name: "{name}", kind: InterfaceForce(body: "bar", marker: "pin", component: {c}, quantity: {q}, frame: {frame})),"#
        )
    };
    let mut sensors = String::new();
    for (name, c, q, frame) in [
        ("fx", "X", "Force", "None"),
        ("fy", "Y", "Force", "None"),
        ("f_axial", "X", "Force", r#"Some("bar")"#),
        ("f_normal", "Y", "Force", r#"Some("bar")"#),
        ("mz", "Z", "Moment", "None"),
    ] {
        sensors += &sensor(name, c, q, frame);
    }
    if spatial {
        sensors += &sensor("fz", "Z", "Force", "None");
        sensors += &sensor("mx", "X", "Moment", "None");
        sensors += &sensor("my", "Y", "Moment", "None");
    }
    format!(
        r#"(
    name: "rigid pendulum", dim: {dim}, gravity: {gravity},
    ground: [(name: "O", position: {o})],
    bodies: [(name: "bar", origin: {origin},
        model: Rigid(mass: {MASS}, center_of_mass: {com}, inertia: {inertia}),
        markers: [(name: "pin", position: {o})])],
    joints: [(name: "pin", kind: Revolute(axis: {axis}), body1: "ground", marker1: "O", body2: "bar", marker2: "pin")],
    sensors: [(name: "angle", kind: JointCoordinate(joint: "pin")), {sensors}],
    solver: (step: 1e-3, duration: 1.5),
)"#
    )
}

/// The pin force on the bar at angle θ (from horizontal, counter-clockwise) after its release
/// from rest at θ = 0: I_O = m L²/3, energy ω² = −3 g sin θ / L, moment α = −3 g cos θ / (2 L),
/// F = m (α ẑ × r_G − ω² r_G − g) with r_G = (L/2)(cos θ, sin θ).
fn pin_force(theta: f64) -> [f64; 2] {
    let (s, c) = theta.sin_cos();
    let w2 = -3.0 * G * s / LENGTH;
    let alpha = -1.5 * G * c / LENGTH;
    let h = 0.5 * LENGTH;
    let (ax, ay) = (-alpha * h * s - w2 * h * c, alpha * h * c - w2 * h * s);
    [MASS * ax, MASS * (ay + G)]
}

#[test]
fn a_rigid_pendulums_pin_force_is_newton_eulers_in_both_formulations() {
    for spatial in [false, true] {
        for form in FORMULATIONS {
            let (names, rows) = run(&scene(&rigid_pendulum(spatial), form));
            let col = |n: &str| column(&names, &rows, n);
            let (angle, fx, fy) = (col("angle"), col("fx"), col("fy"));
            let (axial, normal, mz) = (col("f_axial"), col("f_normal"), col("mz"));
            let mut worst = 0.0f64;
            let mut worst_axes = 0.0f64;
            for k in 0..angle.len() {
                let [ex, ey] = pin_force(angle[k]);
                worst = worst.max((fx[k] - ex).abs()).max((fy[k] - ey).abs());
                // The same force in the bar's axes.
                let (s, c) = angle[k].sin_cos();
                let (ea, en) = (c * fx[k] + s * fy[k], -s * fx[k] + c * fy[k]);
                worst_axes = worst_axes
                    .max((axial[k] - ea).abs())
                    .max((normal[k] - en).abs());
                // A pin carries no moment about its axis: zero to the Newton tolerance (1e-9)
                // of q̈, relative to the bar's weight moment m g L.
                assert!(
                    mz[k].abs() < 1e-8 * MASS * G * LENGTH,
                    "{form:?}: a pin carries no moment: {}",
                    mz[k]
                );
            }
            let swing = angle.iter().cloned().fold(0.0, f64::min);
            eprintln!(
                "spatial {spatial} {form:?}: swing to {swing:.3} rad, pin force off Newton-Euler by {worst:.3e} N (weight {:.2} N), axes {worst_axes:.1e}",
                MASS * G
            );
            assert!(swing < -1.5, "the bar swings through the bottom: {swing}");
            // The integrator's energy error (trapezoidal rule, h = 1 ms) bounds the
            // difference: ω² of the closed form is that of exact energy conservation.
            assert!(worst < 1e-3 * MASS * G, "{form:?}: {worst:.3e} N");
            assert!(worst_axes < 1e-12 * MASS * G * 100.0, "{worst_axes:e}");
            if spatial {
                for n in ["fz", "mx", "my"] {
                    let m = col(n).iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    assert!(
                        m < 1e-8 * MASS * G * LENGTH,
                        "{form:?}: {n} up to {m:e} in a planar swing"
                    );
                }
            }
        }
    }
}

fn model(name: &str) -> Scene {
    let path = format!("{}/../../models/{name}", env!("CARGO_MANIFEST_DIR"));
    Scene::load(&path).unwrap()
}

/// Interface-force sensors `<prefix>_f<x|y|z>`, `<prefix>_m<x|y|z>` at `body`.`marker`, ground
/// components (a planar scene: fx, fy and mz).
fn add_interface_sensors(s: &mut Scene, prefix: &str, body: &str, marker: &str) {
    let planar = s.dim == flexmbd::core::Dim::Planar;
    for (quantity, tag) in [
        (InterfaceQuantity::Force, "f"),
        (InterfaceQuantity::Moment, "m"),
    ] {
        for (component, axis) in [(Axis::X, "x"), (Axis::Y, "y"), (Axis::Z, "z")] {
            let in_plane = (quantity == InterfaceQuantity::Force) != (component == Axis::Z);
            if planar && !in_plane {
                continue;
            }
            s.sensors.push(Sensor {
                name: format!("{prefix}_{tag}{axis}"),
                kind: SensorKind::InterfaceForce {
                    body: body.into(),
                    marker: marker.into(),
                    component,
                    quantity,
                    frame: None,
                },
                displacement: false,
            });
        }
    }
}

/// The largest difference between the two formulations' histories of each named sensor,
/// and the largest value: (difference, scale) per name.
fn formulations_apart(s: &Scene, names: &[&str]) -> Vec<(f64, f64)> {
    let runs: Vec<_> = FORMULATIONS
        .iter()
        .map(|&f| {
            let mut s = s.clone();
            s.solver.formulation = f;
            run(&s)
        })
        .collect();
    names
        .iter()
        .map(|n| {
            let a = column(&runs[0].0, &runs[0].1, n);
            let b = column(&runs[1].0, &runs[1].1, n);
            let diff = a
                .iter()
                .zip(&b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            (diff, scale)
        })
        .collect()
}

/// The formulations discretise differently (natural against relative coordinates), so their
/// histories meet as the step shrinks: the pin force of a flexible beam (its inertia from the
/// floating-frame equations at each formulation's q̈) converges to one history, as the motion
/// does (`crates/validation/tests/formulations_agree_springs.rs`). Measured: planar 2.8e-3,
/// 1.0e-3, 2.8e-4 N of 6.5 N (ratios 2.8 and 3.6, towards O(h²)); 3D 9.1e-5, 2.3e-5, 1.8e-5 N
/// of 5.3 N (O(h²), then a floor at 3.4e-6 of the force). Asserted: the gap shrinks by more
/// than 4 over the three steps and ends below 1e-4 of the largest force. The pendulums
/// keep their two lowest modes here (9.2 and 58 Hz planar, the 3D beam's lowest pair), which
/// these steps resolve: a force reads q̈, where a mode weighs ω² times more than in the
/// position, and the scenes' higher modes (up to 316 Hz planar, undamped) converge only from
/// h ≈ 0.1 ms (measured with all four planar modes: 9.5e-3, 3.3e-3, 9.0e-4 N at h = 0.25,
/// 0.125, 0.0625 ms, ratios 2.9 and 3.7).
#[test]
fn the_flexible_pendulums_pin_force_agrees_between_the_formulations() {
    let mut failed = Vec::new();
    for (file, marker, modes) in [
        ("flexible_pendulum.ron", "pin", "normal_modes: 4,"),
        ("flexible_pendulum_3d.ron", "root", "normal_modes: 6,"),
    ] {
        let path = format!("{}/../../models/{file}", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(modes));
        let mut s = Scene::from_ron_str(&text.replace(modes, "normal_modes: 2,"), &path).unwrap();
        let body = s.bodies[0].name.clone();
        s.solver.duration = 0.2;
        add_interface_sensors(&mut s, "pin", &body, marker);
        let names: Vec<String> = s.sensors.iter().map(|x| x.name.clone()).collect();
        let forces: Vec<&str> = names
            .iter()
            .map(String::as_str)
            .filter(|n| n.starts_with("pin_f"))
            .collect();
        let step = 1e-3;
        let apart: Vec<(f64, f64)> = [1.0, 0.5, 0.25]
            .iter()
            .map(|f| {
                s.solver.step = step * f;
                s.solver.output_interval = Some(step);
                formulations_apart(&s, &forces)
                    .into_iter()
                    .fold((0.0, 0.0), |(d, m), (a, b)| {
                        (f64::max(d, a), f64::max(m, b))
                    })
            })
            .collect();
        let d: Vec<f64> = apart.iter().map(|a| a.0).collect();
        eprintln!(
            "{file}, 2 modes: pin force, absolute against relative at h, h/2, h/4 (h = {step} s): {:.3e} {:.3e} {:.3e} N (largest {:.3e} N)",
            d[0], d[1], d[2], apart[2].1
        );
        let converges = d[0] > d[1] && d[1] > d[2] && d[0] / d[2] > 4.0;
        let converges = converges && d[2] < 1e-4 * apart[2].1;
        failed.extend((!converges).then(|| format!("{file}: {d:?}")));
    }
    assert!(failed.is_empty(), "{failed:?}");
}

/// At rest the sensor is the static balance: equal to `flexmbd equilibrium`'s reaction of the
/// only joint at the marker, on a flexible bar held by a spring (planar) and on a rigid bar
/// pulled out of its plane of rotation by a spring (spatial: the pin carries moments).
#[test]
fn at_a_static_equilibrium_the_sensor_equals_the_joint_reaction() {
    let mut flexible = model("flexible_pendulum.ron");
    flexible.forces = vec![
        Scene::from_ron_str(
            r#"(name: "x", dim: Planar, bodies: [], solver: (step: 1e-3, duration: 1.0),
                ground: [(name: "A", position: [1.0, 1.0])],
                forces: [SpringDamper(name: "hold", body1: "ground", marker1: "A", body2: "bar", marker2: "tip",
                                      stiffness: 200.0, damping: 0.0, free_length: Some(0.5))])"#,
            "spring",
        )
        .unwrap()
        .forces
        .remove(0),
    ];
    flexible.ground.push(flexmbd::model::Marker {
        name: "A".into(),
        position: flexmbd::model::V3([1.0, 1.0, 0.0]),
    });
    add_interface_sensors(&mut flexible, "pin", "bar", "pin");
    let spatial_text = rigid_pendulum(true)
        .replace(
            r#"ground: [(name: "O", position: [0.0, 0.0, 0.0])],"#,
            r#"ground: [(name: "O", position: [0.0, 0.0, 0.0]), (name: "A", position: [1.0, 0.5, 0.4])],
    forces: [SpringDamper(name: "hold", body1: "ground", marker1: "A", body2: "bar", marker2: "tip",
                          stiffness: 500.0, damping: 0.0, free_length: Some(0.1))],"#,
        )
        .replace(
            r#"markers: [(name: "pin", position: [0.0, 0.0, 0.0])]"#,
            r#"markers: [(name: "pin", position: [0.0, 0.0, 0.0]), (name: "tip", position: [1.0, 0.0, 0.0])]"#,
        );
    let mut spatial = scene(&spatial_text, FormulationKind::Absolute);
    spatial.sensors.retain(|s| s.name == "angle");
    add_interface_sensors(&mut spatial, "pin", "bar", "pin");
    // The solid bar (Gmsh bricks, Craig–Bampton modes) held near the horizontal by a vertical
    // spring at its tip interface, its ball joint made a revolute about y (a ball leaves the
    // spin about the bar's axis free, and the static solve singular).
    let mut solid = model("solid_bar_pendulum.ron");
    solid.joints[0].kind = flexmbd::model::JointKind::Revolute {
        axis: Some(flexmbd::model::V3([0.0, 1.0, 0.0])),
    };
    solid.ground.push(flexmbd::model::Marker {
        name: "A".into(),
        position: flexmbd::model::V3([0.2, 0.01, 0.51]),
    });
    let mut spring = flexible.forces[0].clone();
    if let flexmbd::model::Force::SpringDamper {
        body2,
        marker2,
        stiffness,
        ..
    } = &mut spring
    {
        *body2 = "bar".into();
        *marker2 = "tip".into();
        *stiffness = 1000.0;
    }
    solid.forces = vec![spring];
    solid.sensors.push(Sensor {
        name: "angle".into(),
        kind: SensorKind::Angle {
            body: "bar".into(),
            axis: Axis::Y,
        },
        displacement: false,
    });
    add_interface_sensors(&mut solid, "pin", "bar", "root");
    for base in [flexible, spatial, solid] {
        for form in FORMULATIONS {
            let mut s = base.clone();
            s.solver.formulation = form;
            let e = equilibrium(&s).unwrap();
            let reactions = e.reactions.as_ref().expect("reactions computed");
            let pin = &reactions.joints[0];
            let angle = e.sensor("angle").unwrap();
            let mut worst = 0.0f64;
            for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                for (tag, expected) in [("f", pin.force[k]), ("m", pin.moment[k])] {
                    let Some(v) = e.sensor(&format!("pin_{tag}{axis}")) else {
                        continue;
                    };
                    worst = worst.max((v - expected).abs());
                    eprintln!(
                        "{} {form:?}: pin_{tag}{axis} {v:.9e}, reaction {expected:.9e}",
                        s.name
                    );
                }
            }
            eprintln!(
                "{} {form:?}: at {angle:.4} rad, sensor and reaction {worst:.2e} apart",
                s.name
            );
            let weight = 9.81 * 2.0;
            assert!(angle.abs() > 1e-3, "the load turns the bar: {angle}");
            assert!(worst < 1e-9 * weight, "{} {form:?}: {worst:e}", s.name);
            assert!(pin.force.iter().any(|f| f.abs() > 0.1), "{pin:?}");
        }
    }
}

/// Bad input is refused by name: an unknown body, marker or frame, the ground, a planar
/// force's z component or moment's x, a scene constraint where every body's balance is needed.
#[test]
fn bad_interface_sensors_are_refused_by_name() {
    let base = rigid_pendulum(false);
    let original = r#"kind: InterfaceForce(body: "bar", marker: "pin", component: X, quantity: Force, frame: None)"#;
    assert!(base.contains(original));
    for (replacement, expected) in [
        (
            r#"kind: InterfaceForce(body: "beam", marker: "pin", component: X)"#,
            "beam",
        ),
        (
            r#"kind: InterfaceForce(body: "bar", marker: "tip", component: X)"#,
            "tip",
        ),
        (
            r#"kind: InterfaceForce(body: "bar", marker: "pin", component: X, frame: Some("crank"))"#,
            "crank",
        ),
        (
            r#"kind: InterfaceForce(body: "ground", marker: "O", component: X)"#,
            "moving body",
        ),
        (
            r#"kind: InterfaceForce(body: "bar", marker: "pin", component: Z)"#,
            "x and y",
        ),
        (
            r#"kind: InterfaceForce(body: "bar", marker: "pin", component: X, quantity: Moment)"#,
            "z component only",
        ),
    ] {
        let text = base.replace(original, replacement);
        let err =
            match Scene::from_ron_str(&text, "test scene").and_then(|s| s.validate().map(|_| s)) {
                Err(e) => e.to_string(),
                Ok(s) => Simulation::new(&s).err().expect(replacement).to_string(),
            };
        assert!(err.contains(expected), "{replacement}: {err}");
    }
    // A scene constraint on the bar at another marker: the reactions of every body are then
    // needed, and the constraints are not among them yet.
    let constrained = base
        .replace(
            r#"markers: [(name: "pin", position: [0.0, 0.0])]"#,
            r#"markers: [(name: "pin", position: [0.0, 0.0]), (name: "tip", position: [1.0, 0.0])]"#,
        )
        .replace(
            r#"ground: [(name: "O", position: [0.0, 0.0])],"#,
            r#"ground: [(name: "O", position: [0.0, 0.0]), (name: "T", position: [1.0, 1.0])],
    constraints: [Distance(name: "tie", body1: "ground", marker1: "T", body2: "bar", marker2: "tip")],"#,
        );
    let s = Scene::from_ron_str(&constrained, "test scene").unwrap();
    let err = Simulation::new(&s).err().expect("refused").to_string();
    assert!(err.contains("tie") && err.contains("`bar`.`pin`"), "{err}");
}

/// The slider-crank (models/slider_crank.ron: crank, flexible rod, slider on a rail with a
/// spring): the rod's pin forces need every body's balance (the rod has joints at B and C).
/// Checked against what is computed otherwise: Newton's third law at B (the crank's side and
/// the rod's, each its own sensor); at C against the slider's own balance (the body route:
/// everything at its pin) less the spring, along the rail, where the rail carries nothing;
/// at rest against `flexmbd equilibrium`'s reactions (an SVD of the static balance). The
/// formulations' histories are printed, not compared: at h = 1 ms the rod's stiff static
/// modes are under-resolved and the step's q̈ differs between them (the rigid slider's own
/// balance, m (a − g), by 1.3 N of 56 N; its position by 4e-6 m), and the pin forces alike.
#[test]
fn a_connecting_rods_pin_forces_come_from_every_bodys_balance() {
    let mut s = model("slider_crank.ron");
    s.solver.duration = 0.5;
    add_interface_sensors(&mut s, "rodB", "rod", "B");
    add_interface_sensors(&mut s, "crankB", "crank", "B");
    add_interface_sensors(&mut s, "rodC", "rod", "C");
    add_interface_sensors(&mut s, "slider", "slider", "pin");
    s.sensors.push(Sensor {
        name: "spring".into(),
        kind: SensorKind::ElementForce {
            force: "spring".into(),
            quantity: Default::default(),
        },
        displacement: false,
    });
    let mut histories = Vec::new();
    for form in FORMULATIONS {
        let mut s = s.clone();
        s.solver.formulation = form;
        let (names, rows) = run(&s);
        let col = |n: &str| column(&names, &rows, n);
        let (mut third, mut slider, mut largest) = (0.0f64, 0.0f64, 0.0f64);
        for k in 0..rows.len() {
            for a in ["fx", "fy", "mz"] {
                let (rod, crank) = (col(&format!("rodB_{a}")), col(&format!("crankB_{a}")));
                third = third.max((rod[k] + crank[k]).abs());
            }
            // On the slider along x: the rod's pull −F_rodC and the spring's tension (the
            // spring lies along −x from the slider to the wall: +tension x̂ on the slider).
            let along = -col("rodC_fx")[k] + col("spring")[k];
            slider = slider.max((along - col("slider_fx")[k]).abs());
            largest = largest
                .max(col("rodB_fx")[k].abs())
                .max(col("rodB_fy")[k].abs());
        }
        eprintln!(
            "{form:?}: rod pin B against the crank's side {third:.2e}, slider along the rail {slider:.2e} (largest pin force {largest:.3} N)"
        );
        assert!(largest > 1.0, "{largest}");
        assert!(third < 1e-9 * largest, "{form:?}: {third:e}");
        assert!(slider < 1e-6 * largest, "{form:?}: {slider:e}");
        histories.push((names, rows));
    }
    let (a, b) = (&histories[0], &histories[1]);
    let apart = |names: &[&str]| {
        names
            .iter()
            .map(|n| {
                column(&a.0, &a.1, n)
                    .iter()
                    .zip(column(&b.0, &b.1, n))
                    .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
            })
            .fold(0.0, f64::max)
    };
    eprintln!(
        "slider-crank: absolute against relative: rod pin forces {:.3e} N, the slider's own balance {:.3e} N, its position {:.3e} m, the rod's mode 2 {:.3e}",
        apart(&["rodB_fx", "rodB_fy", "rodC_fx", "rodC_fy"]),
        apart(&["slider_fx", "slider_fy"]),
        apart(&["slider_x"]),
        apart(&["rod_mode2"])
    );
    // At rest: the reactions of joints B (body2 the rod) and C (body1 the rod: it feels the
    // opposite) of flexmbd equilibrium.
    for form in FORMULATIONS {
        let mut s = s.clone();
        s.solver.formulation = form;
        let e = equilibrium(&s).unwrap();
        let r = e.reactions.as_ref().unwrap();
        let joint = |n: &str| r.joints.iter().find(|j| j.name == n).unwrap();
        let (b, c) = (joint("B"), joint("C"));
        let mut worst = 0.0f64;
        for (k, a) in ["x", "y"].iter().enumerate() {
            worst = worst.max((e.sensor(&format!("rodB_f{a}")).unwrap() - b.force[k]).abs());
            worst = worst.max((e.sensor(&format!("rodC_f{a}")).unwrap() + c.force[k]).abs());
        }
        eprintln!(
            "{form:?}: at rest, rod pin forces against the reactions {worst:.2e} N (B {:?})",
            b.force
        );
        assert!(worst < 1e-8, "{form:?}: {worst:e}");
    }
}
