//! The `flexmbd modes` command: table, JSON, and errors that name the file.

use std::process::Command;

fn flexmbd() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexmbd"))
}

/// Run the binary with `args` and wait for its output.
fn run<const N: usize>(args: [&str; N]) -> std::process::Output {
    flexmbd().args(args).output().unwrap()
}

/// The command succeeded (else its standard error is the message).
fn assert_success(out: &std::process::Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn model(name: &str) -> String {
    format!("{}/../../models/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn modes_json_has_the_inventory() {
    let out = run(["modes", &model("four_bar_bar_2d.ron"), "--json"]);
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["n_fe_dofs"], 33);
    assert_eq!(v["static_modes"][0]["node"], 10);
    assert_eq!(v["static_modes"][0]["dof"], "ux");
    assert_eq!(v["static_modes"][1]["dof"], "uy");
    assert_eq!(v["normal_modes"].as_array().unwrap().len(), 2);
    assert!((v["mass"].as_f64().unwrap() - 1.0).abs() < 1e-4);
    let f0 = v["normal_modes"][0]["frequency_hz"].as_f64().unwrap();
    let f1 = v["normal_modes"][1]["frequency_hz"].as_f64().unwrap();
    assert!(0.0 < f0 && f0 < f1);
}

#[test]
fn modes_table_names_frame_and_modes() {
    let out = run(["modes", &model("cantilever_2d.ron")]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("frame takes  ux@0 uy@0 rz@0"), "{text}");
    assert!(text.contains("4 (0 static + 4 normal)"), "{text}");
}

#[test]
fn a_bad_model_is_refused_with_file_and_field() {
    let dir = std::env::temp_dir().join(format!("flexmbd-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(model("cantilever_2d.ron")).unwrap();
    let bad = dir.join("negative_modulus.ron");
    std::fs::write(
        &bad,
        text.replace("young_modulus: 2.1e11", "young_modulus: -2.1e11"),
    )
    .unwrap();
    let out = run(["modes", bad.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("negative_modulus.ron")
            && err.contains("young_modulus")
            && err.contains("-210000000000"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("flexmbd-cli-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn simulate_writes_csv_and_json_summary() {
    let dir = temp_dir("sim");
    let csv = dir.join("out.csv");
    let out = run([
        "simulate",
        &model("double_four_bar.ron"),
        "--duration",
        "1",
        "--json",
        "--output",
        csv.to_str().unwrap(),
    ]);
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in [
        "steps",
        "newton_iterations",
        "cpu_seconds",
        "simulated_seconds",
        "realtime_factor",
        "n_coordinates",
        "n_constraints",
        "formulation",
        "inertia",
        "stiffening",
        "status",
    ] {
        assert!(v.get(key).is_some(), "summary lacks {key}: {v}");
    }
    assert_eq!(v["status"], "ok");
    assert_eq!(v["steps"], 1000);
    assert_eq!(v["n_coordinates"], 6);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "t,B0_x,B0_y,energy");
    assert_eq!(
        text.lines().count(),
        1 + 101,
        "one row per 10 ms output interval, t = 0 included"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn simulate_is_deterministic_bit_for_bit() {
    let dir = temp_dir("det");
    let csv_of_a_run = |name: &str| {
        let p = dir.join(name);
        let st = run([
            "simulate",
            &model("double_four_bar.ron"),
            "--duration",
            "2",
            "--output",
            p.to_str().unwrap(),
        ])
        .status;
        assert!(st.success());
        std::fs::read(p).unwrap()
    };
    assert_eq!(csv_of_a_run("a.csv"), csv_of_a_run("b.csv"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn simulate_failure_keeps_rows_and_reports_time_and_residual() {
    let dir = temp_dir("fail");
    let csv = dir.join("fail.csv");
    // A 0.3 s step cannot follow the mechanism through its first singular passage.
    let out = run([
        "simulate",
        &model("double_four_bar.ron"),
        "--step",
        "0.3",
        "--set",
        "solver.output_interval=0.3",
        "--json",
        "--output",
        csv.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "failed");
    let t = v["failed_at"].as_f64().unwrap();
    assert!(t > 0.3, "failed at {t}");
    let msg = v["message"].as_str().unwrap();
    assert!(
        msg.contains("‖Φ‖∞") && msg.contains("smaller step"),
        "{msg}"
    );
    let rows = std::fs::read_to_string(&csv).unwrap().lines().count() - 1;
    assert_eq!(rows as u64, v["rows"].as_u64().unwrap());
    assert!(rows >= 2, "the rows before the failure are kept");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn simulate_refuses_unknown_set_paths_and_unsupported_options() {
    let out = run([
        "simulate",
        &model("double_four_bar.ron"),
        "--set",
        "bodies.crank9.flexible=true",
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("crank9"), "{err}");
    let out = run([
        "simulate",
        &model("double_four_bar.ron"),
        "--set",
        "bodies.crank1.flexible=true",
        "--stiffening",
        "foreshortening",
    ]);
    // FS0 refuses the flexible crank (its tip static modes have axial content).
    assert!(!out.status.success());
    assert!(
        String::from_utf8(out.stderr)
            .unwrap()
            .contains("foreshortening (FS0)")
    );
    let out = run(["simulate", &model("double_four_bar.ron"), "--step", "-1"]);
    assert!(!out.status.success());
    assert!(
        String::from_utf8(out.stderr)
            .unwrap()
            .contains("solver.step")
    );
}

#[test]
fn simulate_names_a_body_model_given_as_a_scene() {
    let out = run(["simulate", &model("cantilever_2d.ron")]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("cantilever_2d.ron")
            && err.contains("body model")
            && err.contains("flexmbd modes"),
        "{err}"
    );
}
