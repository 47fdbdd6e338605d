//! A free beam released at rest bent in its first mode (`models/free_beam.ron`; no joint, no
//! load, no damping): the exact motion conserves its energy. With Buckens modes (issue 31
//! item 3) the floating frame is the linearised mean axes and hardly turns, so the
//! trapezoidal rule keeps the energy to round-off in both formulations, which agree on the
//! modal history. With interface-fixed modes the frame is node 0's cross-section, whose
//! rotation carries the under-resolved top frequency of the basis (about 1.1 kHz) through
//! the rotation's nonlinearity: the energy error is large at h = 1 ms but the model is
//! consistent, so it falls with the step (docs/design.md "Reference conditions").

use flexmbd::model::FormulationKind;
use flexmbd::simulation::run;

const FORMULATIONS: [FormulationKind; 2] = [FormulationKind::Absolute, FormulationKind::Relative];

/// The run's status, Newton iterations per step, largest |E − E₀| / E₀ and y0 history.
fn release(
    reference: &str,
    formulation: FormulationKind,
    y0: f64,
    h: f64,
) -> (String, f64, f64, Vec<f64>) {
    let mut scene = flexmbd_test_support::scenes::model_with(
        "free_beam.ron",
        formulation,
        &[
            format!("bodies.bar.model.Beam.reference={reference}"),
            format!("bodies.bar.initial_modes.0={y0}"),
        ],
    );
    scene.solver.step = h;
    let (summary, history) = run(&scene, |_| {}).unwrap();
    let e = history.column("energy").unwrap();
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / e[0];
    let per_step = summary.newton_iterations as f64 / summary.steps as f64;
    (
        summary.status,
        per_step,
        drift,
        history.column("y0").unwrap(),
    )
}

#[test]
fn a_free_buckens_beam_released_bent_keeps_its_energy_in_both_formulations() {
    // Measured at h = 1 ms: energy 3.2e-10 (absolute), 5.2e-14 (relative) at a 4 mm bend,
    // 3.2e-8 / 2.9e-14 at 40 mm; both at 2.00 Newton iterations a step; the two formulations'
    // y0 histories differ by 2.7e-13 / 2.7e-10 (the absolute run's energy error, cubic in y0).
    for (y0, bound) in [(2e-3, 1e-9), (2e-2, 1e-7)] {
        let runs: Vec<_> = FORMULATIONS
            .iter()
            .map(|&f| release("Buckens", f, y0, 1e-3))
            .collect();
        for ((status, iterations, drift, _), f) in runs.iter().zip(FORMULATIONS) {
            eprintln!("y0 {y0:e} {f:?}: {status}, {iterations:.2} it./step, energy {drift:.2e}");
            assert_eq!(status, "ok");
            assert!(*iterations <= 2.0 + 1e-12, "{f:?}: {iterations}");
            assert!(*drift < bound, "{f:?}: energy error {drift:e}");
        }
        let gap = runs[0]
            .3
            .iter()
            .zip(&runs[1].3)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        eprintln!("y0 {y0:e}: absolute − relative y0 {gap:.2e}");
        assert!(gap < 1e-7 * y0, "formulations differ on y0 by {gap:e}");
    }
}

#[test]
fn a_free_interface_fixed_beam_released_bent_converges_with_the_step() {
    // Measured (4 mm bend): energy 8.2e-1 → 7.1e-2 (absolute), 9.3e-2 → 1.9e-3 (relative) from
    // h = 1 ms to 0.1 ms, with 5.4 → 3.0 and 4.0 → 2.1 Newton iterations a step.
    for f in FORMULATIONS {
        let (s1, it1, coarse, _) = release("InterfaceFixed", f, 2e-3, 1e-3);
        let (s2, it2, fine, _) = release("InterfaceFixed", f, 2e-3, 1e-4);
        eprintln!("{f:?}: energy {coarse:.2e} ({it1:.2} it.) → {fine:.2e} ({it2:.2} it.)");
        assert_eq!((s1.as_str(), s2.as_str()), ("ok", "ok"));
        assert!(fine < coarse / 10.0, "{f:?}: {coarse:e} → {fine:e}");
        assert!(it2 < it1, "{f:?}: {it1} → {it2}");
    }
}
