//! `flexmbd tune` and `flexmbd sweep` on the 2D spin-up beam (Ωs = 6 rad/s) against its
//! large-deformation reference, the ANCF cable (`flexmbd::ancf`, 16 elements, as the
//! report's spin-up study uses it), written to a CSV reference `t,tip_uy`.
//!
//! The runs are shortened to the first 5 s of the spin-up (`--set solver.duration=5`) and
//! the grid reduced (the relative formulation, both inertia routes, FS0 and FNL2, 1 to 3
//! modes, h = 2 and 1 ms: 24 runs), so that a tuning takes seconds. The tolerances stay
//! meaningful there: one mode meets 5 mm but not 1 mm (3.2 mm), two modes meet 1 mm
//! (0.71 mm); over the whole 20 s no method of the grid comes under 2 mm. One formulation
//! only: on this beam the two cost about the same (the relative one has a coordinate
//! fewer), so which is cheaper is a timing tie that a loaded machine's noise (more than the
//! rule's 25 % under a load of 4 on 2 cores) can decide either way; the check of the second
//! tuning is about the rule, not about the machine's load.

mod common;
use common::{code, flexmbd, model, refused};

use std::path::PathBuf;
use std::sync::{Mutex, OnceLock};

use flexmbd::ancf::{CableSpec, run_spin_up};
use flexmbd::core::Dim;
use flexmbd::sweep::{ReferenceTable, TIMING_TIE, reference::error_measures};
use serde_json::Value;

/// Held by each test while it runs `flexmbd`: the tunings time their candidates alone,
/// and the tests of this binary would otherwise run beside them.
static ALONE: Mutex<()> = Mutex::new(());

/// Wait for the other tests of this file to finish running `flexmbd`.
fn alone() -> std::sync::MutexGuard<'static, ()> {
    ALONE
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// A scratch file under the test target directory, unique to this process.
fn scratch(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("tune_{}_{name}", std::process::id()))
}

/// The ANCF cable's tip deflection u_y (16 elements, h = 1 ms, every 0.01 s, 20 s) as a
/// reference CSV `t,tip_uy`, written once per test binary.
fn ancf_reference() -> &'static str {
    static PATH: OnceLock<String> = OnceLock::new();
    PATH.get_or_init(|| {
        let history = run_spin_up(&CableSpec::spin_up_beam(Dim::Planar, 16), 1e-3, 20.0, 0.01)
            .expect("the ANCF spin-up runs");
        let mut csv = String::from("t,tip_uy\n");
        for (t, tip) in history.t.iter().zip(&history.tip) {
            csv += &format!("{t:?},{:?}\n", tip[1]);
        }
        let path = scratch("ancf.csv");
        std::fs::write(&path, csv).unwrap();
        path.display().to_string()
    })
}

/// The reduced grid and the short run of this file's tunings.
const GRID: [&str; 12] = [
    "--set",
    "solver.duration=5",
    "--grid",
    "formulation=relative",
    "--grid",
    "inertia=shape-integrals,b-matrix",
    "--grid",
    "stiffening=foreshortening,fnl2",
    "--grid",
    "modes=1,2,3",
    "--grid",
    "step=2e-3,1e-3",
];

/// `flexmbd tune` of the spin-up beam on `tip_uy` with `tolerance`, its JSON object.
fn tune(tolerance: &str) -> Value {
    let spin_up = model("spin_up_beam_2d.ron");
    let out = flexmbd()
        .args([
            "tune",
            &spin_up,
            "--sensor",
            "tip_uy",
            "--reference",
            ancf_reference(),
        ])
        .args(GRID)
        .args(["--tolerance", tolerance, "--json"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(code(&out), 0, "{err}");
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The largest |u_y − reference| of `flexmbd simulate ARGS` (run alone, its CSV read back).
fn error_of_simulate(args: &[String], name: &str) -> f64 {
    let csv = scratch(name);
    let out = flexmbd()
        .arg("simulate")
        .args(args)
        .args(["--output", csv.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let run = ReferenceTable::from_csv(&csv).unwrap();
    let reference = ReferenceTable::from_csv(ancf_reference().as_ref()).unwrap();
    let (max_abs, _) = error_measures(
        &run.t,
        run.column("tip_uy").unwrap(),
        &reference.t,
        reference.column("tip_uy").unwrap(),
    )
    .unwrap();
    std::fs::remove_file(csv).ok();
    max_abs
}

/// The recommended run meets the tolerance; no compared candidate that meets it (each
/// timed alone) is cheaper beyond the timing tie, and one within it loses by the stated
/// rule; a meeting candidate not compared names a compared one that is cheaper by
/// construction; a failed or unstable candidate is never chosen.
fn check_choice(tuning: &Value, tolerance: f64) {
    let rec = &tuning["recommended"];
    assert_eq!(rec["status"], "ok");
    let (rec_cpu, rec_error) = (
        rec["cpu_seconds"].as_f64().unwrap(),
        rec["error"].as_f64().unwrap(),
    );
    assert!(rec_error <= tolerance, "{rec}");
    let key = |c: &Value| {
        (
            c["n_coordinates"].as_u64().unwrap(),
            c["index"].as_u64().unwrap(),
        )
    };
    let candidates = tuning["candidates"].as_array().unwrap();
    for c in candidates {
        let meets = c["status"] == "ok" && c["error"].as_f64().unwrap() <= tolerance;
        if !meets {
            continue;
        }
        if let Some(cheaper) = c["costlier_than"].as_u64() {
            // Not compared: a compared candidate differs from it only by a larger step or
            // fewer modes.
            let by = &candidates[cheaper as usize];
            assert!(by["costlier_than"].is_null(), "{by}");
            assert_eq!(by["timed"], "alone", "{by}");
            assert!(by["error"].as_f64().unwrap() <= tolerance, "{by}");
        } else {
            assert_eq!(c["timed"], "alone", "a compared candidate: {c}");
            let cpu = c["cpu_seconds"].as_f64().unwrap();
            assert!(
                rec_cpu <= cpu * (1.0 + TIMING_TIE),
                "{c} is cheaper than {rec}"
            );
            if cpu < rec_cpu {
                assert!(key(c) > key(rec), "{c} wins the tie against {rec}");
            }
        }
    }
}

#[test]
fn tune_picks_the_cheapest_configuration_that_meets_5_mm_and_1_mm_reproducibly() {
    let _alone = alone();
    for (tolerance, text) in [(5e-3, "5e-3"), (1e-3, "1e-3")] {
        let first = tune(text);
        check_choice(&first, tolerance);
        let args: Vec<String> = first["recommended"]["args"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a.as_str().unwrap().to_string())
            .collect();
        assert_eq!(
            args[0],
            model("spin_up_beam_2d.ron"),
            "the scene path first"
        );
        let error = error_of_simulate(&args, &format!("recommended_{text}.csv"));
        assert!(
            error <= tolerance,
            "run alone: {error} m > {tolerance} m ({args:?})"
        );
        assert_eq!(
            error,
            first["recommended"]["error"].as_f64().unwrap(),
            "the arguments reproduce the recorded run"
        );
        let second = tune(text);
        check_choice(&second, tolerance);
        assert_eq!(
            second["recommended"]["args"], first["recommended"]["args"],
            "the second tuning at {text} chose differently"
        );
    }
}

#[test]
fn sweep_json_lists_every_run_in_grid_order_with_the_pareto_front_timed_alone() {
    let _alone = alone();
    let spin_up = model("spin_up_beam_2d.ron");
    let out = flexmbd()
        .args([
            "sweep",
            &spin_up,
            "--sensor",
            "tip_uy",
            "--reference",
            ancf_reference(),
        ])
        .args([
            "--set",
            "solver.duration=2",
            "--grid",
            "modes=1,2",
            "--grid",
            "step=2e-3,1e-3",
        ])
        .args(["--grid", "stiffening=linear,foreshortening", "--json"])
        .output()
        .unwrap();
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let runs = report["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 8);
    for (k, run) in runs.iter().enumerate() {
        assert_eq!(run["index"], k);
        let errors = run["errors"].as_array().unwrap();
        if run["status"] == "ok" {
            let (max, rms) = (
                errors[0]["max_abs"].as_f64().unwrap(),
                errors[0]["rms"].as_f64().unwrap(),
            );
            assert!(0.0 < rms && rms <= max, "{run}");
        }
    }
    let front = report["pareto"].as_array().unwrap();
    assert!(!front.is_empty());
    for i in front {
        let run = &runs[i.as_u64().unwrap() as usize];
        assert_eq!(
            (&run["status"], &run["timed"]),
            (&"ok".into(), &"alone".into()),
            "{run}"
        );
    }
    assert!(
        report["timing"]
            .as_str()
            .unwrap()
            .contains("median of 3 runs")
    );
}

#[test]
fn bad_sweep_input_is_refused_by_name() {
    let _alone = alone();
    let spin_up = model("spin_up_beam_2d.ron");
    let tune_args = |extra: &[&str]| -> Vec<String> {
        let mut args: Vec<String> = [
            "tune",
            &spin_up,
            "--set",
            "solver.duration=1",
            "--grid",
            "step=2e-3",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        args.extend(extra.iter().map(|s| s.to_string()));
        args
    };
    let refuse = |extra: &[&str]| {
        let args = tune_args(extra);
        refused(&args.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let reference = ancf_reference();
    let err = refuse(&[
        "--sensor",
        "tip_uz",
        "--reference",
        reference,
        "--tolerance",
        "1e-3",
    ]);
    assert!(
        err.contains("no sensor `tip_uz`") && err.contains("tip_uy"),
        "{err}"
    );

    let no_column = scratch("no_column.csv");
    std::fs::write(&no_column, "t,tip_ux\n0,0\n1,0\n").unwrap();
    let err = refuse(&[
        "--sensor",
        "tip_uy",
        "--reference",
        no_column.to_str().unwrap(),
        "--tolerance",
        "1e-3",
    ]);
    assert!(
        err.contains("no column `tip_uy`") && err.contains("no_column.csv"),
        "{err}"
    );

    let disorder = scratch("disorder.csv");
    std::fs::write(&disorder, "t,tip_uy\n0,0\n0.5,0\n0.25,0\n1,0\n").unwrap();
    let err = refuse(&[
        "--sensor",
        "tip_uy",
        "--reference",
        disorder.to_str().unwrap(),
        "--tolerance",
        "1e-3",
    ]);
    assert!(
        err.contains("disorder.csv:4") && err.contains("out of order"),
        "{err}"
    );

    for tolerance in ["0", "-1e-3"] {
        let err = refuse(&[
            "--sensor",
            "tip_uy",
            "--reference",
            reference,
            "--tolerance",
            tolerance,
        ]);
        assert!(
            err.contains("tolerance") && err.contains("positive"),
            "{err}"
        );
    }
    let err = refuse(&[
        "--sensor",
        "tip_uy",
        "--reference",
        reference,
        "--tolerance",
        "1e-3",
        "--grid",
        "modes=",
    ]);
    assert!(err.contains("modes") && err.contains("no values"), "{err}");
    std::fs::remove_file(no_column).ok();
    std::fs::remove_file(disorder).ok();
}

#[test]
fn no_candidate_meeting_the_tolerance_is_its_own_exit_code() {
    let _alone = alone();
    let spin_up = model("spin_up_beam_2d.ron");
    let out = flexmbd()
        .args([
            "tune",
            &spin_up,
            "--sensor",
            "tip_uy",
            "--reference",
            ancf_reference(),
        ])
        .args([
            "--set",
            "solver.duration=2",
            "--grid",
            "modes=1",
            "--grid",
            "step=2e-3",
        ])
        .args(["--tolerance", "1e-9"])
        .output()
        .unwrap();
    assert_eq!(code(&out), 6, "{}", String::from_utf8_lossy(&out.stderr));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no candidate meets the tolerance 1e-9"),
        "{err}"
    );
}

/// Issue 27 items 1 and 2: without `--reference`, tune judges each scene against the most
/// faithful model the project has for it — the spin-up beam against the large-deformation
/// ANCF cable (its error estimate: its difference from the cable refined), the flexible
/// pendulum against its beam substructured (SB8), the rigid double four-bar against
/// itself at an eighth of the step — and a scene with none (the imported bar pendulum:
/// neither a cable nor splittable) against the grid's own richest model, whose modelling
/// error its margin does not hold: the answer says so, and why. A tolerance within the
/// reference's own error estimate is warned of. With a reference CSV, no warning.
#[test]
fn tune_warns_when_its_reference_is_of_the_grids_own_family() {
    let _alone = alone();
    let run =
        |scene: &str, sensor: &str, grid: &[&str], reference: Option<&str>, tolerance: &str| {
            let mut cmd = flexmbd();
            cmd.args([
                "tune",
                &model(scene),
                "--sensor",
                sensor,
                "--no-reference-cache",
            ]);
            if let Some(r) = reference {
                cmd.args(["--reference", r]);
            }
            let out = cmd
                .args(grid)
                .args(["--tolerance", tolerance, "--json"])
                .output()
                .unwrap();
            let json: Value = serde_json::from_slice(&out.stdout).unwrap();
            let warnings: Vec<String> = json["warnings"]
                .as_array()
                .unwrap()
                .iter()
                .map(|w| w.as_str().unwrap().to_string())
                .collect();
            (code(&out), json, warnings)
        };
    let (spin_up, beam_grid) = (
        "spin_up_beam_2d.ron",
        [
            "--set",
            "solver.duration=2",
            "--grid",
            "modes=1,2",
            "--grid",
            "step=2e-3",
        ],
    );
    let (status, json, warnings) = run(spin_up, "tip_uy", &beam_grid, None, "1e-2");
    assert_eq!(status, 0, "{json}");
    assert_eq!(json["reference_kind"], "large-deformation", "{json}");
    assert!(warnings.is_empty(), "{warnings:?}");
    // Below the reference's own error estimate: no run can be judged there (exit 6, no
    // candidate), and the warning names the estimate.
    let margin = json["reference_margin"][0]["max_abs"].as_f64().unwrap();
    assert!(margin > 0.0 && margin < 1e-4, "{json}");
    let tight = format!("{:e}", margin / 2.0);
    let (status, _, warnings) = run(spin_up, "tip_uy", &beam_grid, None, &tight);
    assert_eq!(status, 6);
    assert!(
        warnings.iter().any(|w| w.contains("cannot be trusted")),
        "{warnings:?}"
    );
    let short = ["--set", "solver.duration=0.5", "--grid", "step=2e-3,1e-3"];
    let (status, json, warnings) = run("flexible_pendulum.ron", "tip_y", &short, None, "1e-1");
    assert_eq!(status, 0, "{json}");
    assert_eq!(json["reference_kind"], "substructured", "{json}");
    assert!(
        json["reference"]
            .as_str()
            .unwrap()
            .contains("substructuring:8"),
        "{json}"
    );
    assert!(warnings.is_empty(), "{warnings:?}");
    let (status, json, warnings) = run("double_four_bar.ron", "B0_x", &short, None, "1e-2");
    assert_eq!(status, 0, "{json}");
    assert_eq!(json["reference_kind"], "small-step", "{json}");
    assert!(
        json["reference"]
            .as_str()
            .unwrap()
            .contains("solver.step=0.000125"),
        "{json}"
    );
    assert!(warnings.is_empty(), "{warnings:?}");
    let (status, json, warnings) = run("imported_bar_pendulum.ron", "tip_x", &short, None, "1e-2");
    assert_eq!(status, 0, "{json}");
    assert_eq!(json["reference_kind"], "grid-richest", "{json}");
    // Refined in the step, so that no run of the grid is its own reference: a quarter of
    // the smallest step, its estimate against twice that.
    assert!(
        json["reference"]
            .as_str()
            .unwrap()
            .contains("solver.step=0.00025"),
        "{json}"
    );
    assert!(json["reference_margin"][0]["max_abs"].as_f64().unwrap() > 0.0);
    for run in json["candidates"].as_array().unwrap() {
        assert!(
            run["error"].as_f64().unwrap() > 0.0,
            "its own reference: {run}"
        );
    }
    let why = json["reference_fallback"].as_str().unwrap();
    assert!(
        why.contains("not a beam") && why.contains("substructuring"),
        "{why}"
    );
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].contains("the grid's own richest model")
            && warnings[0].contains("no large-deformation reference"),
        "{warnings:?}"
    );
    let (status, json, warnings) = run(
        spin_up,
        "tip_uy",
        &beam_grid,
        Some(ancf_reference()),
        "1e-2",
    );
    assert_eq!(status, 0, "{json}");
    assert_eq!(json["reference_kind"], "file", "{json}");
    assert!(warnings.is_empty(), "{warnings:?}");
}

/// Issue 27's own case: on the spin-up beam, a grid whose richest model is FNL1 (which
/// misses the beam's foreshortening by millimetres) judged against itself let tune
/// recommend an FNL1 run 9 mm off for a 5 mm tolerance. Judged by default against the
/// large-deformation cable, no FNL1 run meets 5 mm over the 20 s (exit 6), and with
/// foreshortening in the grid the recommendation, run alone by `flexmbd simulate`, is
/// within the tolerance of the cable.
#[test]
fn tune_by_default_no_longer_recommends_a_run_whose_true_error_exceeds_the_tolerance() {
    let _alone = alone();
    let spin_up = model("spin_up_beam_2d.ron");
    let tune = |stiffening: &str| {
        flexmbd()
            .args([
                "tune",
                &spin_up,
                "--sensor",
                "tip_uy",
                "--tolerance",
                "5e-3",
                "--json",
            ])
            .args(["--grid", "formulation=relative", "--grid", stiffening])
            .args(["--grid", "modes=2,4", "--grid", "step=2e-3"])
            .output()
            .unwrap()
    };
    let out = tune("stiffening=fnl1");
    assert_eq!(code(&out), 6, "{}", String::from_utf8_lossy(&out.stderr));
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["reference_kind"], "large-deformation", "{json}");
    for run in json["candidates"].as_array().unwrap() {
        assert!(run["error"].as_f64().unwrap() > 5e-3, "{run}");
    }
    let out = tune("stiffening=fnl1,foreshortening");
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let args: Vec<String> = json["recommended"]["args"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.as_str().unwrap().to_string())
        .collect();
    assert!(args.contains(&"foreshortening".to_string()), "{args:?}");
    let error = error_of_simulate(&args, "recommended.csv");
    assert!(
        error <= 5e-3,
        "the recommendation is {error} m off the cable"
    );
    let judged = json["recommended"]["error"].as_f64().unwrap();
    assert!((error - judged).abs() < 1e-5, "{error} against {judged}");
}

/// Issue 27 item 4: the default reference is made once and kept (FLEXMBD_CACHE_DIR); the
/// next sweep of the same scene reads it back, judging every run bit for bit as before,
/// and says so, with the time of each apart from the runs'; another scene (a longer run)
/// or `--no-reference-cache` makes its own.
#[test]
fn the_default_reference_is_made_once_and_read_back_from_the_cache() {
    let _alone = alone();
    let dir = scratch("cache");
    std::fs::remove_dir_all(&dir).ok();
    let spin_up = model("spin_up_beam_2d.ron");
    let sweep = |duration: &str, extra: &[&str]| -> Value {
        let out = flexmbd()
            .env("FLEXMBD_CACHE_DIR", &dir)
            .args(["sweep", &spin_up, "--sensor", "tip_uy", "--json"])
            .args(["--set", &format!("solver.duration={duration}")])
            .args(["--grid", "formulation=relative", "--grid", "modes=1,2"])
            .args(["--grid", "stiffening=foreshortening", "--grid", "step=2e-3"])
            .args(extra)
            .output()
            .unwrap();
        assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let errors = |report: &Value| -> Vec<u64> {
        report["runs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["error"].as_f64().unwrap().to_bits())
            .collect()
    };
    let first = sweep("2", &[]);
    assert_eq!(first["reference_cached"], false, "{first}");
    assert!(first["reference_seconds"].as_f64().unwrap() > 0.0);
    let second = sweep("2", &[]);
    assert_eq!(second["reference_cached"], true, "{second}");
    assert_eq!(errors(&first), errors(&second));
    assert_eq!(first["reference_margin"], second["reference_margin"]);
    assert_eq!(sweep("3", &[])["reference_cached"], false);
    let uncached = sweep("2", &["--no-reference-cache"]);
    assert_eq!(uncached["reference_cached"], false);
    assert_eq!(errors(&first), errors(&uncached));
    std::fs::remove_dir_all(&dir).ok();
}
