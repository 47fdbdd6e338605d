//! Proper orthogonal modes from the command line (docs/methods.md §1.6): the pilot run is
//! deterministic — two processes write the same CSV byte for byte —, a failed pilot is a
//! failed run (exit 4) that names the body and the pilot's failure, and a body model on its
//! own (`flexmbd modes`), which has no pilot, is refused by name.

mod common;
use common::{assert_contains_all, code, flexmbd, model};

fn simulate_bars(csv: &std::path::Path) -> std::process::Output {
    let mut cmd = flexmbd();
    cmd.args([
        "simulate",
        &model("double_four_bar.ron"),
        "--set",
        "solver.duration=1",
        "--formulation",
        "relative",
        "--output",
        &csv.display().to_string(),
    ]);
    for b in ["crank1", "coupler1", "crank3"] {
        cmd.args(["--set", &format!("bodies.{b}.flexible=true")]);
        cmd.args([
            "--set",
            &format!("bodies.{b}.model.Beam.mode_selection=ProperOrthogonal"),
        ]);
    }
    cmd.output().unwrap()
}

#[test]
fn two_processes_run_the_same_proper_orthogonal_modes_bit_for_bit() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let id = std::process::id();
    let (a, b) = (
        dir.join(format!("pod_{id}_a.csv")),
        dir.join(format!("pod_{id}_b.csv")),
    );
    for path in [&a, &b] {
        let out = simulate_bars(path);
        assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    }
    let (ta, tb) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert!(ta.len() > 1000);
    assert!(ta == tb, "the two runs' CSVs differ");
    let _ = (std::fs::remove_file(a), std::fs::remove_file(b));
}

#[test]
fn a_body_model_on_its_own_has_no_pilot() {
    let bar = std::fs::read_to_string(model("four_bar_bar_2d.ron")).unwrap();
    let pod = bar.replace(
        "normal_modes: 2,",
        "normal_modes: 2, mode_selection: ProperOrthogonal,",
    );
    assert_ne!(pod, bar, "the bar model names its normal modes");
    let path = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("proper_orthogonal_{}_bar.ron", std::process::id()));
    std::fs::write(&path, pod).unwrap();
    let out = flexmbd()
        .args(["modes", &path.display().to_string()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_ne!(code(&out), 0);
    assert_contains_all(&err, &["mode_selection", "ProperOrthogonal", "pilot"]);
    let _ = std::fs::remove_file(path);
}

/// The flexible pendulum's bar on a proper orthogonal mode, at a quarter-second step: the
/// pilot's Newton iteration does not converge in its first step (t = 0.25 s).
const FAILING_PILOT: [&str; 6] = [
    "--set",
    "bodies.bar.model.Beam.mode_selection=ProperOrthogonal",
    "--set",
    "bodies.bar.model.Beam.normal_modes=1",
    "--set",
    "solver.step=0.25",
];

#[test]
fn a_failed_pilot_exits_as_a_failed_run_naming_the_body_and_the_failure() {
    let csv = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("failed_pilot_{}.csv", std::process::id()));
    let _ = std::fs::remove_file(&csv);
    let pendulum = model("flexible_pendulum.ron");
    let csv_arg = csv.display().to_string();
    let mut args = vec!["simulate", &pendulum, "--json", "--output", &csv_arg];
    args.extend(FAILING_PILOT);
    let out = flexmbd().args(&args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(code(&out), 4, "the scene is valid, its run failed: {err}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "failed");
    assert_eq!(v["rows"], 0);
    assert_contains_all(
        v["message"].as_str().unwrap(),
        &[
            "flexible_pendulum.ron",
            "body `bar`",
            "mode_selection = ProperOrthogonal",
            "pilot run",
            "failed: Newton did not converge at t = 0.25",
        ],
    );
    assert!(!csv.exists(), "no header: the scene was never compiled");
    // Without --json the summary is text on stderr: no model size for a scene never compiled.
    let mut args = vec!["simulate", &pendulum];
    args.extend(FAILING_PILOT);
    let out = flexmbd().args(&args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(code(&out), 4, "{err}");
    assert!(
        err.contains("failed before the scene was compiled") && !err.contains("0 coordinates"),
        "{err}"
    );

    // The static analyses prepare the scene too: the same failure, the same exit code.
    for command in ["equilibrium", "eigen"] {
        let mut args = vec![command, &pendulum];
        args.extend(FAILING_PILOT);
        let out = flexmbd().args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(code(&out), 4, "{command}: {err}");
        assert_contains_all(
            &err,
            &["body `bar`", "pilot run", "Newton did not converge"],
        );
    }
}
