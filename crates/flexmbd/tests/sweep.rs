//! `flexmbd::sweep` on a short spin-up of the 2D beam: the converged reference is the
//! grid's richest point (its own error zero, its half-step margin reported), the records
//! come back in grid order whatever the order of completion, and a refused sweep names what
//! is wrong.

use flexmbd::sweep::{Axis, Grid, Reference, RunStatus, Sweep, SweepError, Timing};

fn spin_up(reference: Reference, axes: Vec<Axis>) -> Sweep {
    Sweep {
        scene: concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../models/spin_up_beam_2d.ron"
        )
        .into(),
        sets: vec!["solver.duration=1".into()],
        sensors: vec!["tip_uy".into()],
        reference,
        grid: Grid { axes },
        error_cap: None,
        reference_cache: None,
    }
}

fn modes_and_steps() -> Vec<Axis> {
    vec![
        Axis::Modes {
            body: None,
            counts: vec![1, 2],
        },
        Axis::Step(vec![2e-3, 1e-3]),
    ]
}

#[test]
fn converged_reference_is_the_richest_point_at_the_smallest_step() {
    let report = spin_up(Reference::Converged, modes_and_steps())
        .run()
        .unwrap();
    assert_eq!(report.runs.len(), 4);
    let labels: Vec<&str> = report.runs.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "modes=1 h=0.002",
            "modes=1 h=0.001",
            "modes=2 h=0.002",
            "modes=2 h=0.001"
        ]
    );
    assert!(report.runs.iter().all(|r| r.status == RunStatus::Ok));
    // The reference is run 3 itself: the same run, the same output times.
    assert_eq!(report.runs[3].error, 0.0);
    assert!(
        report
            .reference
            .ends_with("normal_modes=2 --set solver.step=0.001")
    );
    let margin = &report.reference_margin.as_ref().unwrap()[0];
    assert!(0.0 < margin.max_abs && margin.max_abs < 1e-5, "{margin:?}");
    // One mode fewer is a visible error over the first second, far above the margin.
    assert!(
        report.runs[0].error > 100.0 * margin.max_abs,
        "{:?}",
        report.runs[0]
    );
    for &i in &report.pareto {
        assert_eq!(report.runs[i].timed, Timing::Alone);
    }
    assert!(
        report.pareto.contains(&3),
        "the zero-error run is on the front"
    );
}

#[test]
fn refused_sweeps_name_the_sensor_the_axis_and_the_reference() {
    let mut unknown = spin_up(Reference::Converged, modes_and_steps());
    unknown.sensors = vec!["tip_uw".into()];
    let e = unknown.run().unwrap_err();
    assert!(matches!(e, SweepError::UnknownSensor { .. }), "{e}");
    assert!(e.to_string().contains("tip_uw"));

    let e = spin_up(Reference::Converged, vec![]).run().unwrap_err();
    assert!(e.to_string().contains("empty grid"), "{e}");

    let e = spin_up(
        Reference::Csv("no/such/reference.csv".into()),
        modes_and_steps(),
    )
    .run()
    .unwrap_err();
    assert!(e.to_string().contains("no/such/reference.csv"), "{e}");

    // A step that is not a positive finite number, refused before any run.
    let e = spin_up(Reference::Converged, vec![Axis::Step(vec![f64::NAN])])
        .run()
        .unwrap_err();
    assert!(
        e.to_string().contains("step") && e.to_string().contains("NaN"),
        "{e}"
    );
}

/// A stop flag set before the sweep: with the converged or the faithful reference (the
/// ANCF cable here) nothing runs and the sweep ends with `Interrupted`; with a reference table every run of the grid is marked
/// interrupted, none counts on the front, and the report says so. With the flag clear the
/// same sweep is `run`'s, record for record.
#[test]
fn a_set_stop_flag_interrupts_the_sweep_and_keeps_no_half_run() {
    use std::sync::atomic::AtomicBool;
    let stop = AtomicBool::new(true);
    let converged = spin_up(Reference::Converged, modes_and_steps());
    match converged.run_or_stop(&stop) {
        Err(SweepError::Interrupted { label }) => assert!(label.contains("modes=2"), "{label}"),
        other => panic!("expected Interrupted, got {other:?}"),
    }
    // The faithful reference of the spin-up beam is the ANCF cable: its runs end too.
    let faithful = spin_up(Reference::Faithful, modes_and_steps());
    match faithful.run_or_stop(&stop) {
        Err(SweepError::Interrupted { label }) => assert!(label.contains("ANCF"), "{label}"),
        other => panic!("expected Interrupted, got {other:?}"),
    }
    let (table, _) = converged.converged_reference().unwrap();
    let judged = spin_up(Reference::Table(table), modes_and_steps());
    let report = judged.run_or_stop(&stop).unwrap();
    assert!(report.interrupted);
    assert!(report.pareto.is_empty());
    assert_eq!(report.runs.len(), 4);
    for run in &report.runs {
        assert_eq!(run.status, RunStatus::Interrupted, "{run:?}");
        assert!(
            run.reason.as_deref().unwrap().contains("interrupted"),
            "{run:?}"
        );
    }
    let whole = judged.run_or_stop(&AtomicBool::new(false)).unwrap();
    let plain = judged.run().unwrap();
    assert!(!whole.interrupted);
    let errors =
        |r: &flexmbd::sweep::SweepReport| r.runs.iter().map(|r| r.error).collect::<Vec<_>>();
    assert_eq!(errors(&whole), errors(&plain));
    assert!(whole.runs.iter().all(|r| r.status == RunStatus::Ok));
}

/// The inertia terms as an axis (issue 31): each choice reaches the beam through its
/// `--set` overrides, the full model (the first value) is the converged reference, and
/// dropping terms shows as an error against it.
#[test]
fn inertia_terms_are_an_axis() {
    use flexmbd::body::InertiaTerms;
    use flexmbd::model::FormulationKind;
    let terms = ["full", "o1", "o0-nc"].map(|l| InertiaTerms::parse(l).unwrap());
    let axes = vec![
        Axis::Formulation(vec![FormulationKind::Relative]),
        Axis::Terms {
            body: None,
            terms: terms.to_vec(),
        },
        Axis::Step(vec![1e-3]),
    ];
    let report = spin_up(Reference::Converged, axes).run().unwrap();
    let labels: Vec<&str> = report.runs.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "relative terms=full h=0.001",
            "relative terms=o1 h=0.001",
            "relative terms=o0-nc h=0.001"
        ]
    );
    assert!(report.runs.iter().all(|r| r.status == RunStatus::Ok));
    assert_eq!(report.runs[0].error, 0.0);
    assert!(report.runs[1].error > 0.0 && report.runs[2].error > 0.0);
    let args = report.runs[2].args.join(" ");
    assert!(
        args.contains("--set bodies.beam.inertia_terms.order=0")
            && args.contains("--set bodies.beam.inertia_terms.coupling=false"),
        "{args}"
    );
}

/// `terms=absolute` too: the absolute formulation takes `inertia_terms` (shape integrals).
/// Each choice runs from its `--set` overrides; against the absolute full model (the
/// reference), a truncation moves the tip by far more than the relative full model differs
/// from the absolute one, and the relative run of the same truncation agrees with the
/// absolute one to that difference (the two formulations carry the same physics per
/// truncation), so the axis changes the absolute run and not only its label.
#[test]
fn inertia_terms_are_an_axis_of_the_absolute_formulation() {
    use flexmbd::body::InertiaTerms;
    use flexmbd::model::FormulationKind;
    let terms = ["full", "o1", "o0-nc"].map(|l| InertiaTerms::parse(l).unwrap());
    let axes = vec![
        Axis::Formulation(vec![FormulationKind::Absolute, FormulationKind::Relative]),
        Axis::Terms {
            body: None,
            terms: terms.to_vec(),
        },
        Axis::Step(vec![1e-3]),
    ];
    let report = spin_up(Reference::Converged, axes).run().unwrap();
    let labels: Vec<&str> = report.runs.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(labels[1], "absolute terms=o1 h=0.001");
    assert!(
        report.runs.iter().all(|r| r.status == RunStatus::Ok),
        "{:?}",
        report.runs
    );
    let e: Vec<f64> = report.runs.iter().map(|r| r.error).collect();
    eprintln!("{labels:?}\n{e:?}");
    // Absolute full is the reference; relative full differs by the formulations' own
    // discretisation difference.
    assert_eq!(e[0], 0.0);
    let between = e[3];
    for k in [1, 2] {
        assert!(
            e[k] > 10.0 * between,
            "absolute {}: {:e} vs {between:e}",
            labels[k],
            e[k]
        );
        // Relative and absolute runs of one truncation: within the formulations' difference.
        assert!(
            (e[k + 3] - e[k]).abs() <= 2.0 * between + 1e-3 * e[k],
            "{}: {:e} vs {:e}",
            labels[k],
            e[k + 3],
            e[k]
        );
    }
}

/// `terms=auto@X`: one pilot of the sweep's scene weighs the beam's terms, each tolerance
/// takes the first rung of the weights' ladder whose run meets it on the sweep's judged
/// sensor over the pilot, and the label carries that pilot error; a tolerance no dropped
/// term can meet keeps them all.
#[test]
fn inertia_terms_chosen_by_their_weights_are_an_axis() {
    use flexmbd::model::FormulationKind;
    let axes = vec![
        Axis::Formulation(vec![FormulationKind::Relative]),
        Axis::AutoTerms {
            body: None,
            thresholds: vec![1e-12, 0.5],
        },
        Axis::Step(vec![1e-3]),
    ];
    let report = spin_up(Reference::Converged, axes).run().unwrap();
    let labels: Vec<&str> = report.runs.iter().map(|r| r.label.as_str()).collect();
    eprintln!("{labels:?}");
    assert_eq!(
        labels[0],
        "relative terms=auto@0.000000000001(full;pilot=0.0e0) h=0.001"
    );
    assert!(
        labels[1].starts_with("relative terms=auto@0.5(o"),
        "{labels:?}"
    );
    assert!(!labels[1].contains("(full"), "{labels:?}");
    let pilot_error: f64 = labels[1]
        .split("pilot=")
        .nth(1)
        .and_then(|s| s.split(')').next())
        .and_then(|s| s.parse().ok())
        .unwrap();
    assert!(pilot_error > 0.0 && pilot_error <= 0.5, "{labels:?}");
    assert!(report.runs.iter().all(|r| r.status == RunStatus::Ok));
    // The reference is the smallest threshold's point: every term kept.
    assert_eq!(report.runs[0].error, 0.0);
    let args = report.runs[1].args.join(" ");
    assert!(
        args.contains("--set bodies.beam.inertia_terms.order="),
        "{args}"
    );
    // A threshold outside (0, 1) is refused by name before any run.
    let bad = spin_up(
        Reference::Converged,
        vec![Axis::AutoTerms {
            body: None,
            thresholds: vec![1.0],
        }],
    )
    .run()
    .unwrap_err();
    assert!(matches!(bad, SweepError::Grid { .. }), "{bad}");
    assert!(
        bad.to_string()
            .contains("auto@1: a threshold must be in (0, 1)"),
        "{bad}"
    );
}
