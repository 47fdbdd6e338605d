//! Inputs to a running simulation (`flexmbd_model::inputs`, `Simulation::set_input`): a
//! load, a driver, a road and a force element's scale set by the host between steps give
//! what the same values written into the scene give; a torque does the work τ Δθ; a step
//! with inputs allocates nothing; bad inputs and states are refused by name and value; a
//! step that fails under an absurd input leaves the simulation usable.

use flexmbd::model::{
    Driver, Force, FormulationKind, Input, InputKind, JointKind, MotionLaw, Profile, Scene, Sensor,
    SensorKind, V3,
};
use flexmbd::{Error, Simulation};
use flexmbd_test_support::scenes::model;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

const FORMULATIONS: [FormulationKind; 2] = [FormulationKind::Absolute, FormulationKind::Relative];

fn load(name: &str, body: &str, marker: &str, torque: [f64; 3]) -> Force {
    Force::Load {
        name: name.into(),
        body: body.into(),
        marker: marker.into(),
        force: V3([0.0; 3]),
        torque: V3(torque),
    }
}

fn input(name: &str, kind: InputKind) -> Input {
    Input {
        name: name.into(),
        kind,
    }
}

fn sensor(name: &str, kind: SensorKind) -> Sensor {
    Sensor {
        name: name.into(),
        kind,
        displacement: false,
    }
}

/// The rigid double four-bar with a `motor` load of torque τ_z on crank1 at its pin A0,
/// with a `motor` input on it when `input_driven` (the scene's τ_z is then the input's
/// value until the host sets it). Sensors: B0_x, B0_y, energy, crank1's angle.
fn four_bar_with_motor(form: FormulationKind, tau: f64, input_driven: bool) -> Scene {
    let mut scene = model("double_four_bar.ron");
    scene.solver.formulation = form;
    scene
        .forces
        .push(load("motor", "crank1", "A", [0.0, 0.0, tau]));
    if input_driven {
        scene.inputs.push(input(
            "motor",
            InputKind::Load {
                force: "motor".into(),
            },
        ));
    }
    scene.sensors.push(sensor(
        "crank_angle",
        SensorKind::Angle {
            body: "crank1".into(),
            axis: flexmbd::model::Axis::Z,
        },
    ));
    scene
}

fn assert_same_state(a: &Simulation, b: &Simulation, what: &str) {
    assert_eq!(a.time().to_bits(), b.time().to_bits(), "{what}: time");
    for (i, (x, y)) in a.positions().iter().zip(b.positions()).enumerate() {
        assert_eq!(x.to_bits(), y.to_bits(), "{what}: q[{i}] {x} vs {y}");
    }
    for (i, (x, y)) in a.velocities().iter().zip(b.velocities()).enumerate() {
        assert_eq!(x.to_bits(), y.to_bits(), "{what}: qd[{i}] {x} vs {y}");
    }
}

/// The torque set through the input API before every step and the same constant torque
/// written into the scene as a `Load` give the same trajectory bit for bit: one element,
/// one evaluation, the value read from the input table instead of the scene. The input's
/// scene also starts at τ (its `Load`'s value): the consistent initial accelerations are
/// found at t = 0, before the host can set anything, and with another torque they differ.
#[test]
fn torque_set_every_step_equals_the_same_torque_in_the_scene() {
    for form in FORMULATIONS {
        let tau = 3.0;
        let mut written = Simulation::new(&four_bar_with_motor(form, tau, false)).unwrap();
        let mut set = Simulation::new(&four_bar_with_motor(form, tau, true)).unwrap();
        // The input is what the element reads: zero it and the motion changes.
        let mut zeroed = Simulation::new(&four_bar_with_motor(form, tau, true)).unwrap();
        zeroed.set_input_by_name("motor", &[0.0; 6]).unwrap();
        zeroed.advance_to(0.3).unwrap();
        let motor = set.input("motor").unwrap();
        for _ in 0..300 {
            set.set_input(motor, &[0.0, 0.0, 0.0, 0.0, 0.0, tau])
                .unwrap();
            set.step().unwrap();
            written.step().unwrap();
        }
        assert_same_state(&written, &set, &format!("{form:?}"));
        let moved = (zeroed.positions() - set.positions()).amax();
        assert!(
            moved > 1e-3,
            "{form:?}: the torque moved the crank by {moved}"
        );
    }
}

/// The torque does the work τ Δθ on the crank it turns: the mechanical energy (kinetic and
/// gravity; no other force) changes by it, in both formulations, and they agree.
#[test]
fn torque_on_the_crank_does_the_work_tau_times_its_rotation() {
    let tau = 4.0;
    let mut finals = Vec::new();
    for form in FORMULATIONS {
        let mut sim = Simulation::new(&four_bar_with_motor(form, 0.0, true)).unwrap();
        let e0 = sim.sensor("energy").unwrap();
        sim.set_input_by_name("motor", &[0.0, 0.0, 0.0, 0.0, 0.0, tau])
            .unwrap();
        sim.advance_to(0.5).unwrap();
        let work = tau * sim.sensor("crank_angle").unwrap();
        let gained = sim.sensor("energy").unwrap() - e0;
        assert!(work.abs() > 0.5, "{form:?}: the torque worked: {work} J");
        assert!(
            (gained - work).abs() < 2e-3 * work.abs(),
            "{form:?}: energy gained {gained} J, work τ Δθ = {work} J"
        );
        finals.push(sim.sensor("B0_x").unwrap());
    }
    assert!(
        (finals[0] - finals[1]).abs() < 1e-6,
        "absolute and relative B0_x: {finals:?}"
    );
}

/// A spatial torque on a rigid link hinged about ground z: only its z component works
/// (τ_z Δθ), the others load the hinge; both formulations.
#[test]
fn spatial_torque_works_through_its_component_along_the_hinge() {
    for form in FORMULATIONS {
        let mut scene = model("double_pendulum_3d.ron");
        scene.solver.formulation = form;
        scene.bodies.truncate(1);
        scene.joints.truncate(1);
        scene.joints[0].kind = JointKind::Revolute {
            axis: Some(V3([0.0, 0.0, 1.0])),
        };
        scene.sensors = vec![
            sensor(
                "angle",
                SensorKind::JointCoordinate {
                    joint: "ball".into(),
                },
            ),
            sensor("energy", SensorKind::Energy),
        ];
        // The scene's torque is the input's start value (the initial accelerations are
        // found with it); the host then sets off-axis components too.
        scene
            .forces
            .push(load("motor", "link1", "J", [0.0, 0.0, 0.3]));
        scene.inputs.push(input(
            "motor",
            InputKind::Load {
                force: "motor".into(),
            },
        ));
        let mut sim = Simulation::new(&scene).unwrap();
        let e0 = sim.sensor("energy").unwrap();
        let tau = [0.7, -0.4, 0.3];
        sim.set_input_by_name("motor", &[0.0, 0.0, 0.0, tau[0], tau[1], tau[2]])
            .unwrap();
        let t = 0.4;
        sim.advance_to(t).unwrap();
        // Rotation about the fixed z axis under a constant τ_z: θ = ω₀ t + ½ τ_z/I_O t²,
        // I_O = I_zz + m (x_c² + y_c²) about the pin (the trapezoidal rule is exact here).
        let i_o = 0.063 + 1.5 * (0.35f64.powi(2) + 0.04f64.powi(2));
        let expected = 1.5 * t + 0.5 * tau[2] / i_o * t * t;
        let angle = sim.sensor("angle").unwrap();
        assert!(
            (angle - expected).abs() < 1e-5,
            "{form:?}: θ = {angle} rad, expected {expected}"
        );
        let work = tau[2] * (angle - 1.5 * t);
        let gained = sim.sensor("energy").unwrap() - e0;
        let kinetic_gain = 0.5 * i_o * ((1.5 + tau[2] / i_o * t).powi(2) - 1.5f64.powi(2));
        assert!(
            (gained - kinetic_gain).abs() < 1e-3 * kinetic_gain,
            "{form:?}: energy gained {gained} J, ½ I_O (ω² − ω₀²) = {kinetic_gain} J (work {work})"
        );
    }
}

/// The spin-up beam's driver, its law's θ, θ̇, θ̈ at each step's end time set through a
/// `Driver` input over a `Locked` law, gives the scene's `SpinUp` history bit for bit
/// (the spin-up starts at rest, where `Locked` and `SpinUp` agree).
#[test]
fn driver_set_step_by_step_from_its_law_reproduces_the_scene_driver() {
    for file in ["spin_up_beam_2d.ron", "spin_up_beam_3d.ron"] {
        for form in FORMULATIONS {
            let mut scene = model(file);
            scene.solver.formulation = form;
            let law = scene.drivers[0].law.clone();
            assert!(matches!(law, MotionLaw::SpinUp { .. }), "{file}");
            let mut by_host = scene.clone();
            by_host.drivers[0].law = MotionLaw::Locked;
            let driver = by_host.drivers[0].name.clone();
            by_host
                .inputs
                .push(input("spin", InputKind::Driver { driver }));
            let mut written = Simulation::new(&scene).unwrap();
            let mut set = Simulation::new(&by_host).unwrap();
            let spin = set.input("spin").unwrap();
            for _ in 0..200 {
                let (theta, rate, accel) = law.eval(set.next_time());
                set.set_input(spin, &[theta, rate, accel]).unwrap();
                set.step().unwrap();
                written.step().unwrap();
            }
            assert_same_state(&written, &set, &format!("{file} {form:?}"));
            assert!(written.positions().amax() > 0.0);
        }
    }
}

/// A driver input that is never set leaves the scene's law in charge.
#[test]
fn driver_input_not_set_follows_the_scene_law() {
    let mut scene = model("spin_up_beam_2d.ron");
    let mut with_input = scene.clone();
    let driver = scene.drivers[0].name.clone();
    with_input
        .inputs
        .push(input("spin", InputKind::Driver { driver }));
    scene.solver.formulation = FormulationKind::Relative;
    with_input.solver.formulation = FormulationKind::Relative;
    let mut a = Simulation::new(&scene).unwrap();
    let mut b = Simulation::new(&with_input).unwrap();
    a.advance_to(0.1).unwrap();
    b.advance_to(0.1).unwrap();
    assert_same_state(&a, &b, "unset driver input");
}

/// The Iltis on the bump road: a `Road` input moving the road by Δx = 0.4 m and up by
/// Δz = 0 gives the scene whose bump starts 0.4 m later (to rounding: h(x − Δx) against
/// the bump's own start), and the tyres meet the bump later than on the unmoved road.
#[test]
fn road_offset_moves_the_bump_under_the_wheels() {
    let base = model("iltis_bump.ron");
    let start = match &base.roads[0].profile {
        Profile::CosineBump { start, .. } => *start,
        other => panic!("the Iltis road is a cosine bump: {other:?}"),
    };
    let mut moved = base.clone();
    moved.roads[0].profile = match &base.roads[0].profile {
        Profile::CosineBump { length, height, .. } => Profile::CosineBump {
            start: start + 0.4,
            length: *length,
            height: *height,
        },
        _ => unreachable!(),
    };
    let mut with_input = base.clone();
    with_input.inputs.push(input(
        "road",
        InputKind::Road {
            road: "road".into(),
        },
    ));
    let mut unmoved = Simulation::new(&base).unwrap();
    let mut written = Simulation::new(&moved).unwrap();
    let mut set = Simulation::new(&with_input).unwrap();
    set.set_input_by_name("road", &[0.4, 0.0]).unwrap();
    let front = set.sensor_index("tyre_fl").unwrap();
    let (mut a, mut b, mut c) = (vec![0.0; 12], vec![0.0; 12], vec![0.0; 12]);
    let mut worst: f64 = 0.0;
    let mut earliest_difference = None;
    for k in 0..250 {
        for (sim, out) in [
            (&mut unmoved, &mut a),
            (&mut written, &mut b),
            (&mut set, &mut c),
        ] {
            sim.step().unwrap();
            out.resize(sim.sensor_names().len(), 0.0);
            sim.read_sensors(out);
        }
        worst = worst.max((b[front] - c[front]).abs());
        if earliest_difference.is_none() && (a[front] - c[front]).abs() > 1.0 {
            earliest_difference = Some(k);
        }
    }
    assert!(
        worst < 1e-6 * b[front].abs().max(1.0),
        "tyre_fl differs by {worst} N"
    );
    assert!(
        earliest_difference.is_some(),
        "the bump under the front wheel changed its force within 0.25 s"
    );
}

/// A `Road` input's Δz raises the road under a wheel standing on it: the tyre is pressed
/// by about K Δz more at once (the first step, before the car responds).
#[test]
fn road_raised_presses_the_tyre_by_its_stiffness() {
    let mut scene = model("iltis_bump.ron");
    scene.inputs.push(input(
        "road",
        InputKind::Road {
            road: "road".into(),
        },
    ));
    let mut sim = Simulation::new(&scene).unwrap();
    let before = sim.sensor("tyre_rl").unwrap();
    sim.set_input_by_name("road", &[0.0, 1e-3]).unwrap();
    let pressed = {
        // The force element read at the state before any step: only the road moved.
        sim.sensor("tyre_rl").unwrap()
    };
    // ProfileNormal on the flat part: K Δz = 460 N.
    assert!(
        (pressed - before - 460.0).abs() < 1e-6 * pressed,
        "tyre_rl {before} N -> {pressed} N"
    );
    sim.step().unwrap();
}

/// A spring's stiffness doubled through a `Scale` input at t = 0.1 s equals a scene whose
/// spring has the double stiffness from that state on (the same checkpoint restored into
/// it), bit for bit: k s is computed once either way.
#[test]
fn stiffness_scaled_equals_the_scene_with_that_stiffness_from_then_on() {
    for form in FORMULATIONS {
        let spring = |k: f64| Force::SpringDamper {
            name: "spring".into(),
            body1: "ground".into(),
            marker1: "A1".into(),
            body2: "crank1".into(),
            marker2: "B".into(),
            stiffness: k,
            damping: 3.0,
            free_length: Some(1.0),
        };
        let mut scene = model("double_four_bar.ron");
        scene.solver.formulation = form;
        let mut stiff = scene.clone();
        scene.forces.push(spring(200.0));
        scene.inputs.push(input(
            "spring",
            InputKind::Scale {
                force: "spring".into(),
            },
        ));
        stiff.forces.push(spring(200.0 * 2.0));
        let mut sim = Simulation::new(&scene).unwrap();
        sim.advance_to(0.1).unwrap();
        let mut reference = Simulation::new(&stiff).unwrap();
        reference.restore(&sim.checkpoint());
        sim.set_input_by_name("spring", &[2.0, 1.0]).unwrap();
        for _ in 0..200 {
            sim.step().unwrap();
            reference.step().unwrap();
        }
        assert_same_state(&reference, &sim, &format!("{form:?}"));
    }
}

/// Stepping with every kind of input set before each step allocates nothing (the spin-up
/// beam's driver, a torque and a spring scale on the four-bar, the Iltis road).
#[test]
fn steps_with_inputs_set_allocate_nothing() {
    let mut spin = model("spin_up_beam_3d.ron");
    let driver = spin.drivers[0].name.clone();
    spin.inputs
        .push(input("spin", InputKind::Driver { driver }));
    let mut bump = model("iltis_bump.ron");
    bump.inputs.push(input(
        "road",
        InputKind::Road {
            road: "road".into(),
        },
    ));
    for form in FORMULATIONS {
        let mut four_bar = four_bar_with_motor(form, 0.0, true);
        four_bar.forces.push(Force::SpringDamper {
            name: "spring".into(),
            body1: "ground".into(),
            marker1: "A1".into(),
            body2: "crank1".into(),
            marker2: "B".into(),
            stiffness: 100.0,
            damping: 1.0,
            free_length: None,
        });
        four_bar.inputs.push(input(
            "spring",
            InputKind::Scale {
                force: "spring".into(),
            },
        ));
        let cases: [(&Scene, &[(&str, usize)]); 3] = [
            (&four_bar, &[("motor", 6), ("spring", 2)]),
            (&spin, &[("spin", 3)]),
            (&bump, &[("road", 2)]),
        ];
        for (scene, inputs) in cases {
            let mut scene = scene.clone();
            scene.solver.formulation = form;
            let mut sim = Simulation::new(&scene).unwrap();
            let ids: Vec<_> = inputs
                .iter()
                .map(|(name, n)| (sim.input(name).unwrap(), *n))
                .collect();
            let mut values = vec![0.0; sim.sensor_names().len()];
            let set = |sim: &mut Simulation, k: usize| {
                for &(id, n) in &ids {
                    // A torque τ_z, a driver's angle, a scale or a road's Δx.
                    let mut v = [0.0; 6];
                    v[n - 1] = 1e-3 * k as f64;
                    if n == 2 {
                        v[0] = 1.0;
                    }
                    sim.set_input(id, &v[..n]).unwrap();
                }
            };
            for k in 0..3 {
                set(&mut sim, k);
                sim.step().unwrap();
            }
            let before = flexmbd_test_support::allocations();
            for k in 3..23 {
                set(&mut sim, k);
                sim.step().unwrap();
                sim.read_sensors(&mut values);
            }
            let made = flexmbd_test_support::allocations() - before;
            assert_eq!(made, 0, "{} {form:?}: {made} allocations", scene.name);
        }
    }
}

fn refused(result: Result<impl std::fmt::Debug, Error>) -> String {
    match result {
        Err(e @ Error::Input(_)) => e.to_string(),
        other => panic!("expected an input refusal, got {other:?}"),
    }
}

/// Unknown names, wrong counts and values out of range are refused by name and value, and
/// leave the inputs as they were.
#[test]
fn bad_input_names_and_values_are_refused() {
    let mut sim =
        Simulation::new(&four_bar_with_motor(FormulationKind::Relative, 0.0, true)).unwrap();
    let message = refused(sim.input("motr"));
    assert!(
        message.contains("motr") && message.contains("inputs: motor"),
        "{message}"
    );
    let message = refused(sim.set_input_by_name("motor", &[1.0, 2.0]));
    assert!(message.contains("takes 6 values"), "{message}");
    let motor = sim.input("motor").unwrap();
    let message = refused(sim.set_input(motor, &[0.0, 0.0, 0.0, 0.0, 0.0, f64::NAN]));
    assert!(
        message.contains("inputs[motor][5]") && message.contains("NaN"),
        "{message}"
    );
    let message = refused(sim.set_input(motor, &[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]));
    assert!(
        message.contains("inputs[motor][2]") && message.contains("planar"),
        "{message}"
    );
    assert_eq!(sim.input_values(motor).unwrap(), vec![0.0; 6]);
    let message = refused(sim.sensor("B9_x"));
    assert!(
        message.contains("B9_x") && message.contains("B0_x"),
        "{message}"
    );
}

/// A scene whose input names a missing element, driver or road, or an element of the wrong
/// kind, is refused when loaded, naming the file, line, field and value.
#[test]
fn scene_inputs_naming_missing_targets_are_refused_with_their_line() {
    let text = std::fs::read_to_string(
        flexmbd_test_support::scenes::models_dir().join("double_four_bar.ron"),
    )
    .unwrap();
    let cases = [
        (
            "(name: \"steer\", kind: Driver(driver: \"wheel\"))",
            "driver",
            "wheel",
        ),
        (
            "(name: \"bump\", kind: Road(road: \"lane\"))",
            "road",
            "lane",
        ),
        (
            "(name: \"push\", kind: Load(force: \"motor\"))",
            "force element",
            "motor",
        ),
        (
            "(name: \"stiff\", kind: Scale(force: \"spring\"))",
            "force element",
            "spring",
        ),
    ];
    for (entry, kind, name) in cases {
        let with = text.replacen(
            "    solver:",
            &format!("    inputs: [\n        {entry},\n    ],\n    solver:"),
            1,
        );
        let line = with
            .lines()
            .position(|l| l.contains(entry))
            .map(|i| i + 1)
            .unwrap();
        let error = Scene::from_ron_str(&with, "four_bar_inputs.ron")
            .unwrap()
            .validate()
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("four_bar_inputs.ron")
                && error.contains(&format!(":{line}"))
                && error.contains(kind)
                && error.contains(name),
            "{entry}: {error}"
        );
    }
    // A Load input on a spring, and two inputs on one element.
    let mut scene = four_bar_with_motor(FormulationKind::Absolute, 0.0, true);
    scene.inputs[0].kind = InputKind::Scale {
        force: "motor".into(),
    };
    let error = scene.validate().unwrap_err().to_string();
    assert!(error.contains("Scale") && error.contains("Load"), "{error}");
    let mut scene = four_bar_with_motor(FormulationKind::Absolute, 0.0, true);
    scene.inputs.push(input(
        "again",
        InputKind::Load {
            force: "motor".into(),
        },
    ));
    let error = scene.validate().unwrap_err().to_string();
    assert!(
        error.contains("inputs[again]") && error.contains("another input"),
        "{error}"
    );
}

/// A step that fails under an absurd torque (10⁷ N·m on a 1 kg crank, Newton limited to 6
/// iterations) returns the time, the residual and a hint, leaves the last good state, and
/// after a sane torque the simulation steps on from there exactly as one that never saw
/// the absurd one.
#[test]
fn failed_step_under_an_absurd_input_leaves_a_usable_simulation() {
    let mut scene = four_bar_with_motor(FormulationKind::Absolute, 0.0, true);
    scene.solver.max_iterations = 6;
    let mut sim = Simulation::new(&scene).unwrap();
    let mut twin = Simulation::new(&scene).unwrap();
    sim.advance_to(0.05).unwrap();
    twin.advance_to(0.05).unwrap();
    let good_time = sim.time();
    sim.set_input_by_name("motor", &[0.0, 0.0, 0.0, 0.0, 0.0, 1e7])
        .unwrap();
    let error = sim.step().unwrap_err();
    let message = error.to_string();
    assert!(
        matches!(
            error,
            Error::Integrator(flexmbd::integrators::IntegratorError::NoConvergence { .. })
        ),
        "{message}"
    );
    assert_eq!(
        error.failed_at().map(f64::to_bits),
        Some(twin.next_time().to_bits()),
        "{message}"
    );
    assert!(
        message.contains("‖Φ‖∞") && message.contains("try a smaller step"),
        "residual and hint: {message}"
    );
    assert_eq!(sim.time(), good_time);
    assert_same_state(&sim, &twin, "after the failed step");
    for s in [&mut sim, &mut twin] {
        s.set_input_by_name("motor", &[0.0, 0.0, 0.0, 0.0, 0.0, 1.0])
            .unwrap();
    }
    for _ in 0..50 {
        sim.step().unwrap();
        twin.step().unwrap();
    }
    assert_same_state(&sim, &twin, "stepping on");
}

/// The state read and written back: a consistent one continues the motion (to ALI3-P's
/// tolerance), one off the constraints is refused and changes nothing.
#[test]
fn state_written_is_checked_against_the_constraints() {
    for form in FORMULATIONS {
        let mut scene = model("double_four_bar.ron");
        scene.solver.formulation = form;
        let mut sim = Simulation::new(&scene).unwrap();
        let mut reference = Simulation::new(&scene).unwrap();
        sim.advance_to(0.1).unwrap();
        reference.advance_to(0.1).unwrap();
        let (q, qd) = (sim.positions().clone(), sim.velocities().clone());
        let mut off = q.clone();
        off[0] += 0.1;
        let message = refused(sim.set_state(off.as_slice(), qd.as_slice()));
        assert!(message.contains("‖Φ(q)‖∞"), "{form:?}: {message}");
        let mut fast = qd.clone();
        fast[0] += 1.0;
        if form == FormulationKind::Absolute {
            let message = refused(sim.set_state(q.as_slice(), fast.as_slice()));
            assert!(message.contains("velocities"), "{form:?}: {message}");
        }
        let message = refused(sim.set_state(&q.as_slice()[1..], qd.as_slice()));
        assert!(message.contains("coordinates"), "{form:?}: {message}");
        assert_same_state(&sim, &reference, "refused states");
        sim.set_state(q.as_slice(), qd.as_slice()).unwrap();
        for _ in 0..100 {
            sim.step().unwrap();
            reference.step().unwrap();
        }
        let (a, b) = (
            sim.sensor("B0_x").unwrap(),
            reference.sensor("B0_x").unwrap(),
        );
        assert!((a - b).abs() < 1e-6, "{form:?}: B0_x {a} vs {b}");
        assert!((sim.time() - reference.time()).abs() < 1e-12);
    }
}

/// The analyses are reachable from a running simulation and are those of its scene.
#[test]
fn equilibrium_vibration_and_inventory_from_a_simulation() {
    let scene = model("flexible_pendulum.ron");
    let sim = Simulation::new(&scene).unwrap();
    let equilibrium = sim.equilibrium().unwrap();
    assert_eq!(
        equilibrium.coordinates,
        flexmbd::equilibrium(&scene).unwrap().coordinates
    );
    let vibration = sim.vibration().unwrap();
    assert_eq!(
        vibration.frequencies("oscillatory"),
        flexmbd::vibration(&scene)
            .unwrap()
            .frequencies("oscillatory")
    );
    let body = scene.bodies[0].name.clone();
    let inventory = sim.mode_inventory(&body).unwrap();
    assert!(!inventory.to_text().is_empty());
    let message = refused(sim.mode_inventory("nobody"));
    assert!(message.contains("nobody"), "{message}");
}

/// A driver named in a scene with a `Driver` input keeps its name and law in the scene a
/// host reads back (the input's law lives only in the prepared scene).
#[test]
fn scene_with_inputs_round_trips_through_ron() {
    let mut scene = four_bar_with_motor(FormulationKind::Absolute, 0.0, true);
    scene.drivers.push(Driver {
        name: "crank".into(),
        joint: "A0".into(),
        law: MotionLaw::ConstantRate(-1.0),
    });
    scene.inputs.push(input(
        "crank",
        InputKind::Driver {
            driver: "crank".into(),
        },
    ));
    let text = scene.to_ron().unwrap();
    let back = Scene::from_ron_str(&text, "back.ron").unwrap();
    assert_eq!(back.inputs, scene.inputs);
    assert_eq!(back.forces, scene.forces);
    back.validate().unwrap();
}

/// A `Load` on the ground, out of the plane of a planar scene, or with a torque on a
/// flexible body is refused naming the force's field; so is a torque input on a flexible
/// body's load, which keeps its force.
#[test]
fn loads_the_formulations_cannot_apply_are_refused() {
    let refusal = |edit: &dyn Fn(&mut Scene)| {
        let mut scene = four_bar_with_motor(FormulationKind::Relative, 0.0, false);
        edit(&mut scene);
        scene.validate().unwrap_err().to_string()
    };
    let on_ground = refusal(&|s| s.forces[0] = load("motor", "ground", "A0", [0.0; 3]));
    assert!(
        on_ground.contains("forces[motor].body") && on_ground.contains("ground"),
        "{on_ground}"
    );
    let tilted = refusal(&|s| s.forces[0] = load("motor", "crank1", "A", [1.0, 0.0, 0.0]));
    assert!(
        tilted.contains("forces[motor].torque[0]") && tilted.contains("planar"),
        "{tilted}"
    );
    let flexible = refusal(&|s| {
        s.bodies[0].flexible = true;
        s.forces[0] = load("motor", "crank1", "A", [0.0, 0.0, 1.0]);
    });
    assert!(
        flexible.contains("forces[motor].torque") && flexible.contains("rigid"),
        "{flexible}"
    );

    let mut scene = four_bar_with_motor(FormulationKind::Absolute, 0.0, true);
    scene.bodies[0].flexible = true;
    let mut sim = Simulation::new(&scene).unwrap();
    let message = refused(sim.set_input_by_name("motor", &[0.0, 0.0, 0.0, 0.0, 0.0, 1.0]));
    assert!(
        message.contains("inputs[motor][3..6]") && message.contains("flexible"),
        "{message}"
    );
    sim.set_input_by_name("motor", &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0])
        .unwrap();
    sim.step().unwrap();
}

/// Inputs set before the start (`Simulation::with_inputs`) hold from t = 0: the consistent
/// initial conditions see them, and the run is the scene's with the same torque written in,
/// bit for bit; an unknown input or a refused value is an error naming it.
#[test]
fn inputs_set_before_the_start_give_the_scene_with_the_values_written() {
    for form in FORMULATIONS {
        let scene = four_bar_with_motor(form, 0.0, true);
        let torque = [0.0, 0.0, 0.0, 0.0, 0.0, 2.0];
        let mut early = Simulation::with_inputs(&scene, &[("motor", &torque)]).unwrap();
        let mut written = Simulation::new(&four_bar_with_motor(form, 2.0, false)).unwrap();
        let mut late = Simulation::new(&scene).unwrap();
        late.set_input_by_name("motor", &torque).unwrap();
        for _ in 0..50 {
            for s in [&mut early, &mut written, &mut late] {
                s.step().unwrap();
            }
        }
        assert_same_state(&early, &written, "inputs set before the start");
        assert_ne!(
            early.positions(),
            late.positions(),
            "set after the start, the initial accelerations do not see the torque"
        );
        let unknown = Simulation::with_inputs(&scene, &[("motr", &torque)])
            .err()
            .unwrap();
        assert!(unknown.to_string().contains("motr"), "{unknown}");
        let bad = [0.0, 0.0, 0.0, 0.0, 0.0, f64::NAN];
        let refused = Simulation::with_inputs(&scene, &[("motor", &bad)])
            .err()
            .unwrap();
        assert!(
            refused.to_string().contains("inputs[motor][5]"),
            "{refused}"
        );
    }
}
