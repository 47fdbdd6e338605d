//! An FMU instance (`flexmbd_fmi::Instance`, what the C API calls): input variables set by
//! value reference give what the same value written into the scene gives, bit for bit; a
//! state saved and restored replays the same steps; bad calls (NaN or infinite inputs,
//! zero, negative, infinite or fractional communication steps, unknown value references,
//! calls out of order, doStep after a failed step) are refused with a message naming the
//! value; two instances in one process are independent.

use flexmbd::Simulation;
use flexmbd::model::{Force, Input, InputKind, Scene, V3};
use flexmbd_fmi::Instance;
use flexmbd_fmi::instance::Mode;
use flexmbd_test_support::scenes::model;

/// The rigid double four-bar with a `motor` load of torque τ_z on crank1 at A, driven by
/// an input `motor` when `input` (as crates/flexmbd/tests/inputs.rs builds it).
fn four_bar_with_motor(tau: f64, input: bool) -> Scene {
    let mut scene = model("double_four_bar.ron");
    scene.forces.push(Force::Load {
        name: "motor".into(),
        body: "crank1".into(),
        marker: "A".into(),
        force: V3([0.0; 3]),
        torque: V3([0.0, 0.0, tau]),
    });
    if input {
        scene.inputs.push(Input {
            name: "motor".into(),
            kind: InputKind::Load {
                force: "motor".into(),
            },
        });
    }
    scene
}

/// An instance of `scene` in step mode.
fn stepping(scene: Scene) -> Instance {
    let mut fmu = Instance::new(scene, &[]).unwrap();
    fmu.enter_initialization(0.0).unwrap();
    fmu.exit_initialization().unwrap();
    fmu
}

/// The outputs (value references after the inputs').
fn outputs(fmu: &mut Instance) -> Vec<f64> {
    let v = fmu.variables();
    let vrs: Vec<u32> = (0..v.outputs.len())
        .map(|k| v.output_reference(k))
        .collect();
    let mut values = vec![0.0; vrs.len()];
    fmu.get(&vrs, &mut values).unwrap();
    values
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

/// τ_z = 2 N·m set through the FMU's `motor.tau_z` in initialisation mode gives, at every
/// communication point of 10 steps, the sensors of the scene with τ_z = 2 written into it,
/// bit for bit (the start holds the input).
#[test]
fn an_input_set_by_value_reference_gives_the_scene_with_that_value() {
    let mut fmu = Instance::new(four_bar_with_motor(0.0, true), &[]).unwrap();
    fmu.enter_initialization(0.0).unwrap();
    let names: Vec<&str> = fmu
        .variables()
        .inputs
        .iter()
        .map(|v| v.name.as_str())
        .collect();
    assert_eq!(
        names,
        [
            "motor.F_x",
            "motor.F_y",
            "motor.F_z",
            "motor.tau_x",
            "motor.tau_y",
            "motor.tau_z"
        ]
    );
    let tau_z = fmu.variables().input_reference(5);
    fmu.set(&[tau_z], &[2.0]).unwrap();
    fmu.exit_initialization().unwrap();
    let mut written = Simulation::new(&four_bar_with_motor(2.0, false)).unwrap();
    let h = written.step_size();
    let mut t = 0.0;
    for _ in 0..30 {
        fmu.do_step(t, 10.0 * h).unwrap();
        for _ in 0..10 {
            written.step().unwrap();
        }
        t = written.time();
        assert_eq!(fmu.simulation().time().to_bits(), t.to_bits());
        assert_eq!(
            bits(&outputs(&mut fmu)),
            bits(&written.sensors()),
            "t = {t}"
        );
    }
    let mut read = [0.0];
    fmu.get(&[tau_z], &mut read).unwrap();
    assert_eq!(read, [2.0]);
}

/// An input set in step mode holds from the next step on, as the library's
/// `Simulation::set_input` between steps: the same outputs bit for bit.
#[test]
fn an_input_set_between_steps_acts_as_the_library_s() {
    let scene = four_bar_with_motor(0.0, true);
    let mut fmu = stepping(scene.clone());
    let mut library = Simulation::new(&scene).unwrap();
    let tau_z = fmu.variables().input_reference(5);
    let h = library.step_size();
    let mut t = 0.0;
    for k in 0..20 {
        let tau = (k as f64 * 0.3).sin();
        fmu.set(&[tau_z], &[tau]).unwrap();
        library
            .set_input_by_name("motor", &[0.0, 0.0, 0.0, 0.0, 0.0, tau])
            .unwrap();
        fmu.do_step(t, 3.0 * h).unwrap();
        for _ in 0..3 {
            library.step().unwrap();
        }
        t = library.time();
        assert_eq!(
            bits(&outputs(&mut fmu)),
            bits(&library.sensors()),
            "t = {t}"
        );
    }
}

/// State saved at t₁, stepped on (the input changed on the way), restored and stepped
/// again with the same inputs: the same outputs bit for bit, and the input's value is the
/// saved one again.
#[test]
fn a_restored_state_replays_the_same_steps() {
    let mut fmu = stepping(four_bar_with_motor(0.0, true));
    let tau_z = fmu.variables().input_reference(5);
    let h = fmu.simulation().step_size();
    fmu.set(&[tau_z], &[1.0]).unwrap();
    fmu.do_step(0.0, 50.0 * h).unwrap();
    let saved = fmu.state();
    let t1 = fmu.simulation().time();
    let run = |fmu: &mut Instance| {
        let mut rows = Vec::new();
        let mut t = t1;
        for k in 0..20 {
            fmu.set(&[tau_z], &[1.0 + k as f64]).unwrap();
            fmu.do_step(t, 5.0 * h).unwrap();
            t = fmu.simulation().time();
            rows.push(bits(&outputs(fmu)));
        }
        rows
    };
    let first = run(&mut fmu);
    fmu.set_state(&saved).unwrap();
    assert_eq!(fmu.simulation().time().to_bits(), t1.to_bits());
    let mut read = [0.0];
    fmu.get(&[tau_z], &mut read).unwrap();
    assert_eq!(read, [1.0], "the input returns to its saved value");
    let again = run(&mut fmu);
    assert_eq!(first, again);
}

/// Each bad call is refused with a message that names the value, and changes nothing.
#[test]
fn bad_calls_are_refused_with_a_message() {
    let mut fmu = Instance::new(four_bar_with_motor(0.0, true), &[]).unwrap();
    let h = fmu.simulation().step_size();
    let refused = |r: Result<(), flexmbd_fmi::CallError>, words: &[&str]| {
        let message = r.expect_err("refused").0;
        for w in words {
            assert!(message.contains(w), "{w:?} not in {message:?}");
        }
    };
    refused(fmu.do_step(0.0, h), &["doStep", "Instantiated"]);
    fmu.enter_initialization(0.0).unwrap();
    fmu.exit_initialization().unwrap();
    let tau_z = fmu.variables().input_reference(5);
    refused(
        fmu.set(&[tau_z], &[f64::NAN]),
        &["motor.tau_z", "NaN", "finite"],
    );
    refused(fmu.set(&[tau_z], &[f64::INFINITY]), &["motor.tau_z", "inf"]);
    refused(fmu.set(&[99], &[1.0]), &["unknown value reference 99"]);
    refused(fmu.set(&[1, 99], &[5.0, 1.0]), &["99"]);
    refused(fmu.set(&[0], &[1.0]), &["not an input"]);
    let mut out = [0.0];
    refused(fmu.get(&[99], &mut out), &["unknown value reference 99"]);
    let mut read = [0.0; 2];
    fmu.get(&[1, tau_z], &mut read).unwrap();
    assert_eq!(read, [0.0, 0.0], "a refused set changes nothing");
    for step in [0.0, -h, f64::NAN, f64::INFINITY] {
        refused(
            fmu.do_step(0.0, step),
            &["communicationStepSize", "positive"],
        );
    }
    refused(fmu.do_step(0.0, 1.5 * h), &["whole number"]);
    refused(fmu.do_step(1.0, h), &["currentCommunicationPoint = 1"]);
    assert_eq!(fmu.simulation().stats().steps, 0);
    fmu.do_step(0.0, 2.0 * h).unwrap();
    assert_eq!(fmu.simulation().stats().steps, 2);
}

/// A step that fails (10⁷ N·m on a 1 kg crank, Newton limited to 6 iterations) is an
/// error naming the time; every later doStep is refused until a state is restored.
#[test]
fn do_step_after_a_failed_step_is_refused_until_a_state_is_restored() {
    let mut scene = four_bar_with_motor(0.0, true);
    scene.solver.max_iterations = 6;
    let mut fmu = stepping(scene);
    let h = fmu.simulation().step_size();
    let tau_z = fmu.variables().input_reference(5);
    fmu.do_step(0.0, 10.0 * h).unwrap();
    let saved = fmu.state();
    let t = fmu.simulation().time();
    fmu.set(&[tau_z], &[1e7]).unwrap();
    let message = fmu.do_step(t, h).unwrap_err().0;
    assert!(message.contains("failed"), "{message}");
    assert_eq!(fmu.mode(), Mode::Failed);
    let message = fmu.do_step(t, h).unwrap_err().0;
    assert!(message.contains("a step failed"), "{message}");
    fmu.set_state(&saved).unwrap();
    fmu.do_step(t, h).unwrap();
}

/// Two instances of one scene stepped in turn give what each gives alone.
#[test]
fn two_instances_are_independent() {
    let scene = four_bar_with_motor(0.0, true);
    let mut a = stepping(scene.clone());
    let mut b = stepping(scene.clone());
    let mut alone = stepping(scene);
    let tau_z = a.variables().input_reference(5);
    let h = a.simulation().step_size();
    a.set(&[tau_z], &[3.0]).unwrap();
    alone.set(&[tau_z], &[3.0]).unwrap();
    b.set(&[tau_z], &[-3.0]).unwrap();
    let mut t = 0.0;
    for _ in 0..20 {
        a.do_step(t, 5.0 * h).unwrap();
        b.do_step(t, 5.0 * h).unwrap();
        alone.do_step(t, 5.0 * h).unwrap();
        t = a.simulation().time();
        assert_eq!(bits(&outputs(&mut a)), bits(&outputs(&mut alone)));
        assert_ne!(bits(&outputs(&mut a)), bits(&outputs(&mut b)));
    }
}

/// A call that sets two inputs, the second refused (a force out of the plane of a planar
/// scene), changes neither: the first, already handed to the simulation, gets its values
/// back, and the steps are those of an instance that never saw the call.
#[test]
fn a_call_refused_part_way_changes_no_input() {
    let mut scene = four_bar_with_motor(0.0, true);
    scene.forces.insert(
        0,
        Force::Load {
            name: "brake".into(),
            body: "crank3".into(),
            marker: "A".into(),
            force: V3([0.0; 3]),
            torque: V3([0.0, 0.0, 0.5]),
        },
    );
    scene.inputs.insert(
        0,
        Input {
            name: "brake".into(),
            kind: InputKind::Load {
                force: "brake".into(),
            },
        },
    );
    let mut fmu = stepping(scene.clone());
    let mut twin = stepping(scene);
    let names: Vec<&str> = fmu
        .variables()
        .inputs
        .iter()
        .map(|v| v.name.as_str())
        .collect();
    let vr = |name: &str| 1 + names.iter().position(|n| *n == name).unwrap() as u32;
    let (brake_tau, motor_fz) = (vr("brake.tau_z"), vr("motor.F_z"));
    let message = fmu.set(&[brake_tau, motor_fz], &[5.0, 1.0]).unwrap_err().0;
    assert!(message.contains("motor"), "{message}");
    let mut read = [0.0; 2];
    fmu.get(&[brake_tau, motor_fz], &mut read).unwrap();
    assert_eq!(read, [0.5, 0.0]);
    let h = fmu.simulation().step_size();
    fmu.do_step(0.0, 20.0 * h).unwrap();
    twin.do_step(0.0, 20.0 * h).unwrap();
    assert_eq!(bits(&outputs(&mut fmu)), bits(&outputs(&mut twin)));
}

/// A parameter (`solver.step`) set before the start gives the scene with that value
/// written in, bit for bit; in step mode it is refused; a path that is not a real number
/// of the scene is refused when the instance is made.
#[test]
fn a_parameter_set_before_the_start_gives_the_scene_with_it_written() {
    let scene = model("double_four_bar.ron");
    let parameters = ["solver.step".to_string()];
    let mut fmu = Instance::new(scene.clone(), &parameters).unwrap();
    let step = fmu.variables().parameter_reference(0);
    let mut start = [0.0];
    fmu.get(&[step], &mut start).unwrap();
    assert_eq!(start, [scene.solver.step]);
    fmu.enter_initialization(0.0).unwrap();
    fmu.set(&[step], &[5e-4]).unwrap();
    fmu.exit_initialization().unwrap();
    let mut written = scene.clone();
    written.solver.step = 5e-4;
    let mut library = Simulation::new(&written).unwrap();
    for k in 0..10 {
        fmu.do_step(k as f64 * 4e-3, 4e-3).unwrap();
        for _ in 0..8 {
            library.step().unwrap();
        }
        assert_eq!(bits(&outputs(&mut fmu)), bits(&library.sensors()));
    }
    let message = fmu.set(&[step], &[1e-3]).unwrap_err().0;
    assert!(
        message.contains("solver.step") && message.contains("fixed"),
        "{message}"
    );
    for path in ["solver.max_iterations", "solver.nothing", "name"] {
        let refused = Instance::new(scene.clone(), &[path.to_string()])
            .err()
            .unwrap();
        assert!(refused.0.contains(path), "{}", refused.0);
    }
}

/// A state serialised to bytes and read back restores as the state itself does: the same
/// steps bit for bit; bytes that are not a state are refused.
#[test]
fn a_serialised_state_restores_bit_for_bit() {
    let mut fmu = stepping(four_bar_with_motor(0.0, true));
    let tau_z = fmu.variables().input_reference(5);
    let h = fmu.simulation().step_size();
    fmu.set(&[tau_z], &[0.7]).unwrap();
    fmu.do_step(0.0, 37.0 * h).unwrap();
    let bytes = fmu.state().to_bytes().unwrap();
    let t1 = fmu.simulation().time();
    let run = |fmu: &mut Instance| {
        let mut rows = Vec::new();
        for k in 0..10 {
            fmu.set(&[tau_z], &[k as f64 * 0.1]).unwrap();
            fmu.do_step(t1 + (4 * k) as f64 * h, 4.0 * h).unwrap();
            rows.push(bits(&outputs(fmu)));
        }
        rows
    };
    let first = run(&mut fmu);
    let state = flexmbd_fmi::instance::FmuState::from_bytes(&bytes).unwrap();
    fmu.set_state(&state).unwrap();
    assert_eq!(fmu.simulation().time().to_bits(), t1.to_bits());
    assert_eq!(run(&mut fmu), first);
    for garbage in [
        &b"(not a state)"[..],
        &[0xff, 0xfe][..],
        &bytes[..bytes.len() / 2],
    ] {
        let message = flexmbd_fmi::instance::FmuState::from_bytes(garbage)
            .err()
            .unwrap()
            .0;
        assert!(message.contains("not a serialised state"), "{message}");
    }
}
