//! `flexmbd tune --grid terms=auto@X` (issue 31 item 2, "tune may use it"; docs/design.md
//! "Inertia terms by weight") end to end on the double four-bar with its five bars flexible
//! (docs/scenes.md §1; 1 s, relative coordinates, h = 1 ms), judged on the joint B0
//! (`B0_x`, `B0_y`) against the full model at h = 0.25 ms written by `flexmbd simulate`:
//!
//! * each threshold is one candidate, labelled with the terms confirmed per bar and that
//!   choice's pilot error, which is at most the threshold; at 1e-2 the bars drop terms (the
//!   axis does something), and each candidate's arguments set every bar's terms;
//! * the recommended run meets the tolerance, and `flexmbd simulate` with its arguments,
//!   run alone, gives the same error against the same reference (the arguments reproduce
//!   the run).

mod common;
use common::{code, flexmbd, model};

use std::path::{Path, PathBuf};

use flexmbd::sweep::{ReferenceTable, reference::error_measures};
use serde_json::Value;

/// The flexible bars.
const BARS: [&str; 5] = ["crank1", "coupler1", "crank2", "coupler2", "crank3"];

/// The judged sensors.
const SENSORS: [&str; 2] = ["B0_x", "B0_y"];

/// The tolerance of the tuning (m): about three times the step's error at h = 1 ms.
const TOLERANCE: f64 = 1e-4;

/// A scratch file under the test target directory, unique to this process.
fn scratch(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("tune_terms_{}_{name}", std::process::id()))
}

/// The scene and its overrides: the five bars flexible, 1 s.
fn scene_args() -> Vec<String> {
    let mut args = vec![model("double_four_bar.ron")];
    for bar in BARS {
        args.extend(["--set".into(), format!("bodies.{bar}.flexible=true")]);
    }
    args.extend(["--set".into(), "solver.duration=1".into()]);
    args
}

/// `flexmbd simulate ARGS --output CSV`, checked to finish.
fn simulate(args: &[String], csv: &Path) {
    let out = flexmbd()
        .arg("simulate")
        .args(args)
        .args(["--output", csv.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
}

/// The largest |run − reference| over the judged sensors, as the sweep measures it.
fn largest_error(run: &Path, reference: &Path) -> f64 {
    let (run, reference) = (
        ReferenceTable::from_csv(run).unwrap(),
        ReferenceTable::from_csv(reference).unwrap(),
    );
    SENSORS
        .iter()
        .map(|s| {
            error_measures(
                &run.t,
                run.column(s).unwrap(),
                &reference.t,
                reference.column(s).unwrap(),
            )
            .unwrap()
            .0
        })
        .fold(0.0, f64::max)
}

/// The terms per bar and the pilot error of a label `… terms=auto@X(T1,…,T5;pilot=E) …`.
fn chosen(label: &str) -> (Vec<String>, f64) {
    let inner = label
        .split_once('(')
        .and_then(|(_, rest)| rest.split_once(')'))
        .map(|(inner, _)| inner)
        .unwrap_or_else(|| panic!("no choice in {label}"));
    let (terms, pilot) = inner.split_once(";pilot=").unwrap();
    (
        terms.split(',').map(str::to_string).collect(),
        pilot.parse().unwrap(),
    )
}

#[test]
fn tune_takes_the_terms_confirmed_at_each_threshold_and_its_choice_reproduces() {
    let reference = scratch("reference.csv");
    let mut full = scene_args();
    full.extend(["--formulation", "relative", "--step", "0.00025"].map(String::from));
    simulate(&full, &reference);

    let out = flexmbd()
        .arg("tune")
        .args(scene_args())
        .args(["--sensor", &SENSORS.join(",")])
        .args(["--reference", reference.to_str().unwrap()])
        .args(["--grid", "formulation=relative"])
        .args(["--grid", "terms=auto@0.01,auto@0.001"])
        .args(["--grid", "step=0.001"])
        .args(["--tolerance", &TOLERANCE.to_string(), "--json"])
        .output()
        .unwrap();
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let tuning: Value = serde_json::from_slice(&out.stdout).unwrap();

    let candidates = tuning["candidates"].as_array().unwrap();
    assert_eq!(candidates.len(), 2, "{tuning}");
    for (c, threshold) in candidates.iter().zip([1e-2, 1e-3]) {
        let label = c["label"].as_str().unwrap();
        eprintln!("{label}: error {} m", c["error"]);
        assert!(
            label.starts_with(&format!("relative terms=auto@{threshold}(")),
            "{label}"
        );
        let (terms, pilot) = chosen(label);
        assert_eq!(terms.len(), BARS.len(), "{label}");
        assert!((0.0..=threshold).contains(&pilot), "{label}");
        if threshold == 1e-2 {
            assert!(terms.iter().all(|t| t != "full"), "{label}");
        }
        let args = c["args"].as_array().unwrap();
        for bar in BARS {
            let order = format!("bodies.{bar}.inertia_terms.order=");
            assert!(
                args.iter().any(|a| a.as_str().unwrap().starts_with(&order)),
                "{label}: {args:?}"
            );
        }
    }

    let recommended = &tuning["recommended"];
    assert_eq!(recommended["status"], "ok", "{tuning}");
    let error = recommended["error"].as_f64().unwrap();
    assert!(error <= TOLERANCE, "{recommended}");
    let args: Vec<String> = recommended["args"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.as_str().unwrap().to_string())
        .collect();
    let run = scratch("recommended.csv");
    simulate(&args, &run);
    let again = largest_error(&run, &reference);
    eprintln!(
        "recommended {}: error {error:e} m, simulated again {again:e} m",
        recommended["label"]
    );
    assert!(
        (again - error).abs() <= 1e-9 * error,
        "{again:e} vs {error:e}"
    );
    std::fs::remove_file(run).ok();
    std::fs::remove_file(reference).ok();
}
