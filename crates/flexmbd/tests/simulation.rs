//! The stepping interface: `Simulation::step` and `read_sensors` reproduce `run`'s history
//! bit for bit, `advance_to` lands on the step grid, a checkpoint restored replays the same
//! steps, a failed step leaves the last good state, and a step allocates nothing.

use flexmbd::model::FormulationKind;
use flexmbd::simulation::run;
use flexmbd::{Error, Simulation, integrators::IntegratorError};
use flexmbd_test_support::scenes::model;

mod common;
use common::flexible_pendulums;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

/// Stepping by hand and reading the sensors after each step gives `run`'s rows exactly
/// (output interval = one step), in both formulations.
#[test]
fn stepping_by_hand_reproduces_run() {
    for scene in flexible_pendulums(0.05, None) {
        let form = scene.solver.formulation;
        let (summary, history) = run(&scene, |_| {}).unwrap();
        assert_eq!(summary.status, "ok");
        let mut sim = Simulation::new(&scene).unwrap();
        assert_eq!(sim.sensor_names(), &history.header[1..]);
        assert_eq!(sim.n_coordinates(), summary.n_coordinates);
        let mut values = vec![0.0; sim.sensor_names().len()];
        for row in &history.rows {
            if row[0] > 0.0 {
                sim.step().unwrap();
            }
            sim.read_sensors(&mut values);
            assert_eq!(sim.time().to_bits(), row[0].to_bits(), "{form:?}");
            assert_eq!(values, row[1..], "{form:?} at t = {}", row[0]);
        }
        assert_eq!(sim.stats().steps, summary.steps);
        assert_eq!(sim.stats().newton_iterations, summary.newton_iterations);
    }
}

/// `advance_to` stops on the multiple of h nearest the target and never steps backwards.
#[test]
fn advance_to_lands_on_the_step_grid() {
    let mut sim = Simulation::new(&model("double_four_bar.ron")).unwrap();
    let h = sim.step_size();
    sim.advance_to(10.4 * h).unwrap();
    assert_eq!(sim.stats().steps, 10);
    sim.advance_to(10.6 * h).unwrap();
    assert_eq!(sim.stats().steps, 11);
    sim.advance_to(0.0).unwrap();
    assert_eq!(sim.stats().steps, 11);
    assert!((sim.time() - 11.0 * h).abs() < 1e-15);
}

/// After `restore` the next steps are the same steps again, bit for bit.
#[test]
fn restored_checkpoint_replays_the_same_steps() {
    let mut sim = Simulation::new(&model("double_four_bar.ron")).unwrap();
    sim.advance_to(0.02).unwrap();
    let start = sim.checkpoint();
    sim.advance_to(0.05).unwrap();
    let first = sim.sensors();
    let t = sim.time();
    sim.restore(&start);
    assert!(sim.time() < t);
    sim.advance_to(0.05).unwrap();
    assert_eq!(sim.time(), t);
    assert_eq!(sim.sensors(), first);
}

/// A 0.3 s step cannot follow the four-bar through its first singular passage: the error
/// carries the time of the failed step, and the simulation stays at the last good state.
#[test]
fn a_failed_step_keeps_the_last_good_state() {
    let mut scene = model("double_four_bar.ron");
    scene.solver.step = 0.3;
    let mut sim = Simulation::new(&scene).unwrap();
    let (mut before, mut t_before) = (sim.sensors(), sim.time());
    let error = loop {
        match sim.step() {
            Ok(()) => (before, t_before) = (sim.sensors(), sim.time()),
            Err(e) => break e,
        }
        assert!(sim.time() < 10.0, "no failure within 10 s");
    };
    assert!(
        matches!(
            error,
            Error::Integrator(IntegratorError::NoConvergence { .. })
        ),
        "{error:?}"
    );
    let failed_at = error.failed_at().unwrap();
    assert!((failed_at - (t_before + 0.3)).abs() < 1e-12, "{failed_at}");
    assert_eq!(sim.time(), t_before);
    assert_eq!(sim.sensors(), before);
    assert_eq!(sim.stats().failed_steps, 1);
    // `run` reports the same failure, with the typed error behind its message.
    let (summary, _) = run(&scene, |_| {}).unwrap();
    assert_eq!(summary.failed_at, Some(failed_at));
    let typed = summary.error.as_deref().expect("typed error");
    assert_eq!(summary.message.as_deref(), Some(typed.to_string().as_str()));
}

/// The vehicle force elements (links of nonlinear laws along their markers and along a body
/// axis, tyres on a cosine bump and on a stepped table) and their sensors allocate nothing
/// per step, in either formulation.
#[test]
fn vehicle_force_elements_do_not_allocate() {
    for form in [FormulationKind::Absolute, FormulationKind::Relative] {
        let mut scene = flexmbd::model::Scene::from_ron_str(
            flexmbd_test_support::scenes::VEHICLE_CORNER,
            "corner",
        )
        .unwrap();
        scene.solver.formulation = form;
        scene.sensors.push(flexmbd::model::Sensor {
            name: "energy".into(),
            kind: flexmbd::model::SensorKind::Energy,
            displacement: false,
        });
        let mut sim = Simulation::new(&scene).unwrap();
        let mut values = vec![0.0; sim.sensor_names().len()];
        for _ in 0..3 {
            sim.step().unwrap();
        }
        let before = flexmbd_test_support::allocations();
        for _ in 0..20 {
            sim.step().unwrap();
        }
        sim.read_sensors(&mut values);
        let made = flexmbd_test_support::allocations() - before;
        assert_eq!(
            made, 0,
            "{form:?}: {made} allocations in 20 steps and a reading"
        );
        assert!(
            values[1] > 0.0,
            "{form:?}: the tyre carries the corner: {values:?}"
        );
    }
}

/// Neither `step` (after a few steps have sized everything) nor `read_sensors` allocates,
/// in either formulation (the flexible pendulum reads body-frame positions and the energy;
/// the solid cantilever its stress sensors, σ = S y over a node set; the unbalanced rotor its
/// journal's interface force, the rotor's balance with its bearing links; the solid
/// slider-crank its rod's pin force, every body's balance solved together; the spin-up beams
/// step without their driven coordinates).
#[test]
fn steps_do_not_allocate() {
    for (name, form) in [
        ("double_four_bar.ron", FormulationKind::Absolute),
        ("flexible_pendulum.ron", FormulationKind::Absolute),
        ("flexible_pendulum.ron", FormulationKind::Relative),
        ("flexible_pendulum_3d.ron", FormulationKind::Absolute),
        ("flexible_pendulum_3d.ron", FormulationKind::Relative),
        ("solid_cantilever.ron", FormulationKind::Absolute),
        ("solid_cantilever.ron", FormulationKind::Relative),
        ("unbalanced_rotor.ron", FormulationKind::Absolute),
        ("unbalanced_rotor.ron", FormulationKind::Relative),
        ("solid_slider_crank_gmsh.ron", FormulationKind::Absolute),
        ("solid_slider_crank_gmsh.ron", FormulationKind::Relative),
        // Driven hub joints out of the unknowns (`flexmbd_core::DrivenEliminated`).
        ("spin_up_beam_2d.ron", FormulationKind::Absolute),
        ("spin_up_beam_2d.ron", FormulationKind::Relative),
        ("spin_up_beam_3d.ron", FormulationKind::Relative),
    ] {
        let mut scene = model(name);
        scene.solver.formulation = form;
        let mut sim = Simulation::new(&scene).unwrap();
        let mut values = vec![0.0; sim.sensor_names().len()];
        for _ in 0..3 {
            sim.step().unwrap();
        }
        let before = flexmbd_test_support::allocations();
        for _ in 0..20 {
            sim.step().unwrap();
        }
        let made = flexmbd_test_support::allocations() - before;
        assert_eq!(made, 0, "{name} ({form:?}): {made} allocations in 20 steps");
        let before = flexmbd_test_support::allocations();
        sim.read_sensors(&mut values);
        let made = flexmbd_test_support::allocations() - before;
        assert_eq!(
            made, 0,
            "{name} ({form:?}): {made} allocations in read_sensors"
        );
    }
}

/// `advance_to_or_stop` with its flag set takes no step and says `t` was not reached; with
/// the flag clear it reaches `t` as `advance_to` does, bit for bit.
#[test]
fn advance_to_or_stop_stays_put_while_stopped_and_otherwise_advances_as_advance_to() {
    use std::sync::atomic::{AtomicBool, Ordering};
    let scene = model("double_four_bar.ron");
    let mut plain = Simulation::new(&scene).unwrap();
    plain.advance_to(0.25).unwrap();
    let mut host = Simulation::new(&scene).unwrap();
    let stop = AtomicBool::new(true);
    assert!(!host.advance_to_or_stop(0.25, &stop).unwrap());
    assert_eq!((host.time(), host.stats().steps), (0.0, 0));
    stop.store(false, Ordering::Relaxed);
    assert!(host.advance_to_or_stop(0.25, &stop).unwrap());
    assert_eq!(host.time().to_bits(), plain.time().to_bits());
    let bits = |s: &Simulation| {
        s.positions()
            .iter()
            .map(|x| x.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&host), bits(&plain));
}

/// A target time that is NaN, infinite or more than `MAX_STEPS` steps ahead is refused by
/// name (`t`) before any step, where it used to loop without end (infinite, huge) or
/// return silently (NaN); the simulation stays usable.
#[test]
fn advance_to_refuses_nan_infinite_and_too_far_targets() {
    let mut sim = Simulation::new(&model("double_four_bar.ron")).unwrap();
    let h = sim.step_size();
    let far = (flexmbd::simulation::MAX_STEPS as f64 + 2.0) * h;
    for t in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, far] {
        match sim.advance_to(t) {
            Err(Error::Input(e)) => {
                assert_eq!(e.field, "t", "{t}: {e}");
                assert!(e.to_string().contains("finite") || e.to_string().contains("limit"));
            }
            other => panic!("advance_to({t}): expected an input error, got {other:?}"),
        }
        assert_eq!(sim.stats().steps, 0, "advance_to({t}) took a step");
    }
    // The largest target allowed is not refused (checked on a stop flag already set, so
    // that no step is taken), and the simulation goes on.
    let stop = std::sync::atomic::AtomicBool::new(true);
    let reached = sim
        .advance_to_or_stop(flexmbd::simulation::MAX_STEPS as f64 * h, &stop)
        .unwrap();
    assert!(!reached);
    sim.advance_to(10.0 * h).unwrap();
    assert_eq!(sim.stats().steps, 10);
}
