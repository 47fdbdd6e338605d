//! Proper orthogonal modes from a pilot run (`mode_selection: ProperOrthogonal`,
//! docs/methods.md §1.6): what the pilot sees makes the basis, both inertia routes run the
//! basis alike, a failed pilot is a failed run that names the body, a stopped pilot ends
//! the run as interrupted and leaves nothing behind, and a body run rigid needs no pilot.

use std::sync::atomic::AtomicBool;

use flexmbd::fe::ReferenceFrame;
use flexmbd::model::{BodyModel, Constraint, Marker, Scene, V3};
use flexmbd::simulation::{run, run_into};
use flexmbd::{Error, History, PilotOutcome, Simulation};

/// `file` of `models/`, changed by `edit`, then by `sets` (and validated again).
fn scene(file: &str, edit: impl FnOnce(&mut Scene), sets: &[(&str, &str)]) -> Scene {
    let path = format!("{}/../../models/{file}", env!("CARGO_MANIFEST_DIR"));
    let mut scene = Scene::load(path).unwrap();
    edit(&mut scene);
    let sets: Vec<(String, String)> = sets
        .iter()
        .map(|(p, v)| (p.to_string(), v.to_string()))
        .collect();
    scene.apply_sets(&sets).unwrap();
    scene
}

/// The flexible pendulum's bar simply supported — pinned at its end A, its end B held on
/// the ground's x axis (to µm: a link of 1 km from below), its frame the chord A–B — and
/// released under gravity, its `modes` normal modes chosen by `selection`.
fn supported_bar(selection: &str, modes: &str) -> Scene {
    let roller = |scene: &mut Scene| {
        if let BodyModel::Beam(spec) = &mut scene.bodies[0].model {
            spec.frame = ReferenceFrame::Chord { a: 0, b: 10 };
        }
        // A roller: a link 1 km long from far below B (B moves by µm).
        scene.ground.push(Marker {
            name: "below_B".into(),
            position: V3([1.0, -1000.0, 0.0]),
        });
        scene.constraints.push(Constraint::Distance {
            name: "roller".into(),
            body1: "ground".into(),
            marker1: "below_B".into(),
            body2: "bar".into(),
            marker2: "tip".into(),
            length: None,
        });
    };
    scene(
        "flexible_pendulum.ron",
        roller,
        &[
            ("bodies.bar.model.Beam.mode_selection", selection),
            ("bodies.bar.model.Beam.normal_modes", modes),
            ("solver.duration", "0.5"),
        ],
    )
}

#[test]
fn a_symmetric_load_gives_only_symmetric_proper_orthogonal_modes() {
    // Gravity on the simply supported bar is symmetric about mid-span: the pilot (the 4
    // lowest modes) moves modes 1 and 3 and leaves the antisymmetric modes 2 and 4 at rest,
    // so the two proper orthogonal modes are modes 1 and 3, where the lowest two are 1 and 2.
    let lowest = Simulation::new(&supported_bar("LowestFrequency", "4")).unwrap();
    let pod = Simulation::new(&supported_bar("ProperOrthogonal", "2")).unwrap();
    let hz = |sim: &Simulation| -> Vec<f64> {
        let inventory = sim.mode_inventory("bar").unwrap();
        inventory
            .normal_modes
            .iter()
            .map(|m| m.frequency_hz)
            .collect()
    };
    let (f_lowest, f_pod) = (hz(&lowest), hz(&pod));
    println!("lowest: {f_lowest:?} Hz; proper orthogonal: {f_pod:?} Hz");
    assert_eq!(f_pod.len(), 2);
    for (chosen, mode) in f_pod.iter().zip([f_lowest[0], f_lowest[2]]) {
        assert!(
            (chosen - mode).abs() < 1e-9 * mode,
            "{chosen} Hz against {mode} Hz"
        );
    }
}

#[test]
fn initial_modes_on_proper_orthogonal_modes_are_refused_by_name() {
    let start_deformed = |scene: &mut Scene| scene.bodies[0].initial_modes = vec![1e-3];
    let scene = scene(
        "flexible_pendulum.ron",
        start_deformed,
        &[
            ("bodies.bar.model.Beam.mode_selection", "ProperOrthogonal"),
            ("bodies.bar.model.Beam.normal_modes", "1"),
        ],
    );
    let e = Simulation::new(&scene).err().expect("refused").to_string();
    println!("{e}");
    assert!(e.contains("bodies[bar].initial_modes") && e.contains("[0.001]"));
}

#[test]
fn both_inertia_routes_run_the_same_proper_orthogonal_modes() {
    let bars = ["crank1", "coupler1", "crank2", "coupler2", "crank3"];
    let history = |inertia: &str| {
        let mut sets: Vec<(String, String)> = vec![
            ("solver.duration".into(), "1".into()),
            ("solver.inertia".into(), inertia.into()),
        ];
        for b in bars {
            sets.push((format!("bodies.{b}.flexible"), "true".into()));
            sets.push((
                format!("bodies.{b}.model.Beam.mode_selection"),
                "ProperOrthogonal".into(),
            ));
            sets.push((format!("bodies.{b}.model.Beam.normal_modes"), "2".into()));
        }
        let sets: Vec<(&str, &str)> = sets.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
        let (summary, history) = run(&scene("double_four_bar.ron", |_| {}, &sets), |_| {}).unwrap();
        assert_eq!(summary.status, "ok", "{:?}", summary.message);
        (
            history.column("B0_x").unwrap(),
            history.column("B0_y").unwrap(),
        )
    };
    let (a, b) = (history("BMatrix"), history("ShapeIntegrals"));
    let worst =
        a.0.iter()
            .zip(&b.0)
            .chain(a.1.iter().zip(&b.1))
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
    println!("B0: largest difference between the routes {worst:.2e} m");
    assert!(worst < 1e-9);
}

/// The flexible pendulum's bar on one proper orthogonal mode, `sets` applied after.
fn pod_pendulum(sets: &[(&str, &str)]) -> Scene {
    let mut all = vec![
        ("bodies.bar.model.Beam.mode_selection", "ProperOrthogonal"),
        ("bodies.bar.model.Beam.normal_modes", "1"),
    ];
    all.extend_from_slice(sets);
    scene("flexible_pendulum.ron", |_| {}, &all)
}

#[test]
fn a_failed_pilot_is_a_failed_run_that_names_the_body_and_the_failure() {
    // A quarter-second step: the pilot's Newton iteration wanders off in its first step
    // (it used to be accepted at the iteration limit, tips at 1e105, before the leading
    // matrix turned singular at t = 0.5 s; issue 26 item 5).
    let scene = pod_pendulum(&[("solver.step", "0.25")]);
    let e = Simulation::new(&scene).err().expect("the pilot fails");
    let text = e.to_string();
    println!("{text}");
    for part in [
        "body `bar`",
        "mode_selection",
        "ProperOrthogonal",
        "pilot run",
        "failed: Newton did not converge at t = 0.25",
        "try a smaller step",
    ] {
        assert!(text.contains(part), "`{part}` missing from: {text}");
    }
    // A failure of the run, typed: not a refusal of the scene.
    let Error::Pilot(pilot) = &e else {
        panic!("not a pilot failure: {e:?}")
    };
    assert_eq!(pilot.body, "bar");
    assert!(!pilot.interrupted());
    let PilotOutcome::Failed(cause) = &pilot.outcome else {
        panic!("not a failed step: {:?}", pilot.outcome)
    };
    assert_eq!(
        cause.failed_at(),
        Some(0.25),
        "the pilot's own time: {cause}"
    );
    // A run of the scene: failed, with the pilot's message, no row.
    let (summary, history) = run(&scene, |_| {}).unwrap();
    assert_eq!(summary.status, "failed");
    assert_eq!(summary.message.as_deref(), Some(text.as_str()));
    assert!(matches!(summary.error.as_deref(), Some(Error::Pilot(_))));
    assert_eq!((summary.rows, history.rows.len()), (0, 0));
}

#[test]
fn a_stop_flag_set_before_the_pilot_interrupts_it_and_nothing_of_it_is_kept() {
    // 10⁸ pilot steps (10⁵ s at 1 ms): minutes, were the flag not looked at.
    let long = pod_pendulum(&[("solver.duration", "1e5")]);
    let mut sink = History::default();
    let summary = run_into(&long, &mut sink, &AtomicBool::new(true), |_| {}).unwrap();
    println!("{:?}", summary.message);
    assert_eq!(summary.status, "interrupted");
    let message = summary.message.unwrap();
    for part in [
        "body `bar`",
        "pilot run",
        "was interrupted at t = 0 s",
        "after 0 of 100000000 steps",
    ] {
        assert!(message.contains(part), "`{part}` missing from: {message}");
    }
    assert_eq!((summary.steps, summary.rows), (0, 0));
    assert!(
        sink.header.is_empty() && sink.rows.is_empty(),
        "no header, no row"
    );
    assert!(summary.error.is_none());

    // The same pilot, stopped then run with the flag clear, gives the basis of a pilot
    // that never was stopped (the scene renamed: another entry of the pilot cache) bit for
    // bit: the stopped pilot left nothing behind.
    let short = pod_pendulum(&[("solver.duration", "0.5")]);
    let stopped = run_into(
        &short,
        &mut History::default(),
        &AtomicBool::new(true),
        |_| {},
    );
    assert_eq!(stopped.unwrap().status, "interrupted");
    let tip = |scene: &Scene| {
        let mut history = History::default();
        let summary = run_into(scene, &mut history, &AtomicBool::new(false), |_| {}).unwrap();
        assert_eq!(summary.status, "ok", "{:?}", summary.message);
        assert_eq!(history.rows.len(), 51);
        history.column("tip_y").unwrap()
    };
    let fresh = Scene {
        name: "never stopped".into(),
        ..short.clone()
    };
    let (after_stop, never_stopped) = (tip(&short), tip(&fresh));
    assert!(
        after_stop
            .iter()
            .map(|v| v.to_bits())
            .eq(never_stopped.iter().map(|v| v.to_bits())),
        "the run after the stopped pilot differs from a fresh one"
    );
}

#[test]
fn a_beam_run_rigid_needs_no_pilot() {
    // The bar's modal sensor goes: a rigid bar has no modal coordinates.
    let no_modal = |scene: &mut Scene| scene.sensors.retain(|s| s.name != "y0");
    let scene = scene(
        "flexible_pendulum.ron",
        no_modal,
        &[
            ("bodies.bar.model.Beam.mode_selection", "ProperOrthogonal"),
            ("bodies.bar.flexible", "false"),
            ("bodies.bar.model.Beam.pilot_duration", "1e7"),
            ("solver.duration", "0.1"),
        ],
    );
    // A pilot of 1e7 s would be refused: there is none.
    let (summary, _) = run(&scene, |_| {}).unwrap();
    assert_eq!(summary.status, "ok", "{:?}", summary.message);
    assert_eq!(
        summary.n_coordinates,
        Simulation::new(&scene).unwrap().n_coordinates()
    );
}

#[test]
fn a_pilot_longer_than_the_scene_runs_to_the_scene_end() {
    // Unbounded, 1e7 s at 1 ms would be 1e10 steps: refused, over the step limit.
    let history = |pilot: Option<&str>| {
        let mut sets = vec![
            ("bodies.bar.model.Beam.mode_selection", "ProperOrthogonal"),
            ("bodies.bar.model.Beam.normal_modes", "1"),
            ("solver.duration", "0.2"),
        ];
        if let Some(d) = pilot {
            sets.push(("bodies.bar.model.Beam.pilot_duration", d));
        }
        let (summary, history) =
            run(&scene("flexible_pendulum.ron", |_| {}, &sets), |_| {}).unwrap();
        assert_eq!(summary.status, "ok", "{:?}", summary.message);
        history.column("tip_y").unwrap()
    };
    assert_eq!(history(Some("1e5")), history(None));
}

#[test]
fn a_sweep_row_whose_pilot_fails_is_a_failed_row_and_the_sweep_goes_on() {
    use flexmbd::sweep::{Axis, Grid, Reference, RunStatus, Sweep};
    let sweep = Sweep {
        scene: concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../models/flexible_pendulum.ron"
        )
        .into(),
        sets: vec![
            "bodies.bar.model.Beam.mode_selection=ProperOrthogonal".into(),
            "bodies.bar.model.Beam.normal_modes=1".into(),
            "solver.duration=0.5".into(),
        ],
        sensors: vec!["tip_y".into()],
        reference: Reference::Converged,
        // At h = 0.25 s the pilot's Newton iteration does not converge.
        grid: Grid {
            axes: vec![Axis::Step(vec![0.25, 1e-3])],
        },
        error_cap: None,
        reference_cache: None,
    };
    let report = sweep.run().expect("the sweep runs");
    let (failed, ok) = (&report.runs[0], &report.runs[1]);
    assert_eq!(failed.status, RunStatus::Failed, "{failed:?}");
    let reason = failed.reason.as_deref().unwrap_or_default();
    for part in ["body `bar`", "pilot run", "Newton did not converge"] {
        assert!(reason.contains(part), "`{part}` missing from: {reason}");
    }
    assert_eq!(ok.status, RunStatus::Ok, "{ok:?}");
}
