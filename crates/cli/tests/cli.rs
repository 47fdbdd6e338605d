//! The `flexmbd` program: `modes` (table, JSON, errors that name the file), `simulate`
//! (CSV and JSON summary, failures), its exit codes, its panic report, and the checks of
//! `--output` made before a run starts.

mod common;
use common::{assert_contains_all, code, flexmbd, model, refused, run};

/// The command succeeded (else its standard error is the message).
fn assert_success(out: &std::process::Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
    assert!(
        v["static_modes"][0].get("interface").is_none(),
        "a beam's nodes are FE nodes"
    );
    assert_eq!(v["normal_modes"].as_array().unwrap().len(), 2);
    assert!((v["mass"].as_f64().unwrap() - 1.0).abs() < 1e-4);
    let f0 = v["normal_modes"][0]["frequency_hz"].as_f64().unwrap();
    let f1 = v["normal_modes"][1]["frequency_hz"].as_f64().unwrap();
    assert!(0.0 < f0 && f0 < f1);
}

/// The cantilever of `models/cantilever_3d.ron` (steel, 1 m, 10 mm square, m = 0.785 kg): its
/// centre of mass at mid-length and its inertia about it, ρ A L³/12 + ρ I L about y and z
/// (the section's own rotary inertia, which the 3D mass carries) and ρ (I_y + I_z) L about x.
#[test]
fn modes_prints_the_rigid_body_properties() {
    let out = run(["modes", &model("cantilever_3d.ron"), "--json"]);
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let (rho, a, i, l) = (7850.0, 1e-4, 1e-8 / 12.0, 1.0);
    let m = rho * a * l;
    let c: Vec<f64> = serde_json::from_value(v["center_of_mass"].clone()).unwrap();
    let inertia: Vec<Vec<f64>> = serde_json::from_value(v["inertia"].clone()).unwrap();
    assert!((c[0] - 0.5).abs() < 1e-12 && c[1].abs() < 1e-12 && c[2].abs() < 1e-12);
    let expected = [
        2.0 * rho * i * l,
        m * l * l / 12.0 + rho * i * l,
        m * l * l / 12.0 + rho * i * l,
    ];
    for (k, want) in expected.into_iter().enumerate() {
        let got = inertia[k][k];
        assert!(
            (got - want).abs() < 1e-9 * want,
            "I{k}{k} = {got}, expected {want}"
        );
    }
    let text = String::from_utf8(run(["modes", &model("cantilever_3d.ron")]).stdout).unwrap();
    assert!(
        text.contains("centre of mass (0.500000, 0.000000, 0.000000) m"),
        "{text}"
    );
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
    let err = refused(&["modes", bad.to_str().unwrap()]);
    assert_contains_all(
        &err,
        &["negative_modulus.ron", "young_modulus", "-210000000000"],
    );
    std::fs::remove_dir_all(&dir).ok();
}

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("flexmbd-cli-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `flexmbd simulate models/double_four_bar.ron ARGS… --output CSV`, waited for.
fn four_bar_into(csv: &std::path::Path, args: &[&str]) -> std::process::Output {
    flexmbd()
        .args(["simulate", &model("double_four_bar.ron")])
        .args(args)
        .args(["--output", csv.to_str().unwrap()])
        .output()
        .unwrap()
}

#[test]
fn simulate_writes_csv_and_json_summary() {
    let dir = temp_dir("sim");
    let csv = dir.join("out.csv");
    let out = four_bar_into(&csv, &["--duration", "1", "--json"]);
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
        let st = four_bar_into(&p, &["--duration", "2"]).status;
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
    let out = four_bar_into(
        &csv,
        &[
            "--step",
            "0.3",
            "--set",
            "solver.output_interval=0.3",
            "--json",
        ],
    );
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

/// A flexible crank under foreshortening: FS0 refuses it when compiling (its tip static
/// modes have axial content).
const FS0_FLEXIBLE_CRANK: [&str; 4] = [
    "--set",
    "bodies.crank1.flexible=true",
    "--stiffening",
    "foreshortening",
];

#[test]
fn simulate_refuses_unknown_set_paths_and_unsupported_options() {
    let scene = model("double_four_bar.ron");
    let err = refused(&["simulate", &scene, "--set", "bodies.crank9.flexible=true"]);
    assert!(err.contains("crank9"), "{err}");
    let err = refused(&[&["simulate", &scene][..], &FS0_FLEXIBLE_CRANK].concat());
    assert!(err.contains("foreshortening (FS0)"), "{err}");
    let err = refused(&["simulate", &scene, "--step", "-1"]);
    assert!(err.contains("solver.step"), "{err}");
}

#[test]
fn simulate_names_a_body_model_given_as_a_scene() {
    let err = refused(&["simulate", &model("cantilever_2d.ron")]);
    assert_contains_all(&err, &["cantilever_2d.ron", "body model", "flexmbd modes"]);
}

/// One exit code per kind of outcome: 2 usage, 3 invalid input (a refused value, a bad
/// `--set`, a missing file, a body model given as a scene, an unknown output directory),
/// 4 a failed run, 0 success; `--help` lists them.
#[test]
fn exit_codes_name_the_outcome() {
    assert_eq!(code(&run(["simulate", "--no-such-option"])), 2);
    assert_eq!(code(&run(["simulate"])), 2);
    let scene = model("double_four_bar.ron");
    for args in [
        vec!["simulate", &scene, "--step", "-1"],
        vec!["simulate", &scene, "--set", "bodies.crank9.flexible=true"],
        vec!["simulate", &scene, "--set", "solver.step"],
        vec!["simulate", "no/such/scene.ron"],
        vec!["simulate", &model("cantilever_2d.ron")],
        vec!["simulate", &scene, "--output", "no/such/dir/out.csv"],
        vec!["modes", "no/such/model.ron"],
    ] {
        refused(&args);
    }
    // The four-bar's first singular passage defeats a 0.3 s step: the run failed.
    let out = run(["simulate", &scene, "--step", "0.3", "--json"]);
    assert_eq!(code(&out), 4);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "failed");
    assert_eq!(code(&run(["simulate", &scene, "--duration", "0.01"])), 0);
    for help in [run(["--help"]), run(["simulate", "--help"])] {
        assert_eq!(code(&help), 0);
        let text = String::from_utf8(help.stdout).unwrap();
        for line in [
            "Exit codes:",
            "  0   success",
            "  2   usage error",
            "  3   invalid input",
            "  4   the run failed",
            "  5   interrupted",
            "  70  internal error",
        ] {
            assert!(text.contains(line), "--help lacks {line:?}:\n{text}");
        }
    }
}

/// A panic is one line on stderr, "flexmbd: internal error, please report: MESSAGE (at
/// FILE:LINE)", and exit code 70 (no backtrace hint, no exit 101).
#[test]
fn a_panic_is_an_internal_error_in_one_line() {
    let out = flexmbd()
        .args(["simulate", &model("double_four_bar.ron")])
        .env("FLEXMBD_TEST_INTERNAL_ERROR", "1")
        .output()
        .unwrap();
    assert_eq!(code(&out), 70);
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("flexmbd: internal error, please report: ")
            && err.contains("(at crates/cli/src/main.rs:"),
        "{err}"
    );
}

/// Issue 12: `--duration 1e17` panicked ("capacity overflow") and `--duration 1e8`
/// aborted allocating 240 GB. Both are refused as invalid input: a duration beyond the
/// solver's time range naming solver.duration and the range, and a duration within it but
/// of more steps than a run may take naming the number of steps and the limit.
#[test]
fn duration_1e17_is_refused_not_a_panic() {
    let cases = [
        (["1e17", "1e-3"], "solver.duration = 1e17: out of range"),
        (["1e8", "1e-3"], "solver.duration = 100000000: out of range"),
        (["1e5", "1e-5"], "10000000000 steps"),
    ];
    let scene = model("double_four_bar.ron");
    for ([duration, step], refusal) in cases {
        let err = refused(&["simulate", &scene, "--duration", duration, "--step", step]);
        assert_contains_all(&err, &["double_four_bar.ron", refusal]);
        if refusal.ends_with("steps") {
            assert!(err.contains("limit of 1000000000 steps"), "{err}");
        }
    }
}

/// Issue 12: `--output /dev/full` was found only after the whole run, without the path.
/// The header is written and flushed before the first step: a run of 10⁸ steps is refused
/// at once, naming the file, with no summary.
#[test]
fn output_dev_full_is_refused_before_the_run() {
    // `refused` checks that nothing is on standard output: no summary, the run did not start.
    let err = refused(&[
        "simulate",
        &model("double_four_bar.ron"),
        "--duration",
        "100000",
        "--json",
        "--output",
        "/dev/full",
    ]);
    assert_contains_all(&err, &["cannot write /dev/full", "No space left"]);
}

/// Issue 12: an output in a directory that does not exist is refused before the scene is
/// even loaded (the scene here is a body model, which would be refused too), naming it.
#[test]
fn output_missing_directory_is_refused_before_loading() {
    let dir = temp_dir("missing-dir");
    let out_path = dir.join("no-such-dir").join("out.csv");
    let out_path = out_path.to_str().unwrap();
    let err = refused(&[
        "simulate",
        &model("cantilever_2d.ron"),
        "--output",
        out_path,
    ]);
    assert_contains_all(&err, &[out_path, "does not exist"]);
    assert!(!err.contains("body model"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// What an earlier run left in its output, which a refused run leaves as it was.
const EARLIER_RUN: &str = "an earlier run\n";

/// A scratch directory (see [`temp_dir`]) holding an earlier run's output `old.csv`:
/// (the directory, the file).
fn with_earlier_output(tag: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = temp_dir(tag);
    let csv = dir.join("old.csv");
    std::fs::write(&csv, EARLIER_RUN).unwrap();
    (dir, csv)
}

/// Issue 12: a read-only output file is refused before the run (for root as for anyone)
/// and left as it was.
#[test]
fn output_read_only_file_is_refused_and_left_untouched() {
    use std::os::unix::fs::PermissionsExt;
    let (dir, csv) = with_earlier_output("read-only");
    std::fs::set_permissions(&csv, std::fs::Permissions::from_mode(0o444)).unwrap();
    let path = csv.to_str().unwrap();
    let err = refused(&["simulate", &model("double_four_bar.ron"), "--output", path]);
    assert_contains_all(&err, &[path, "read-only"]);
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), EARLIER_RUN);
    std::fs::remove_dir_all(&dir).ok();
}

/// Issue 12: `--output` equal to the scene's path overwrote the scene. The paths are
/// compared canonicalised, so another spelling of the same file is refused too, and the
/// scene is left as it was.
#[test]
fn output_equal_to_scene_is_refused() {
    let dir = temp_dir("scene-as-output");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    let scene = dir.join("scene.ron");
    let text = std::fs::read_to_string(model("double_four_bar.ron")).unwrap();
    std::fs::write(&scene, &text).unwrap();
    let same = dir.join("sub").join("..").join("scene.ron");
    for output in [&scene, &same] {
        let (scene, output) = (scene.to_str().unwrap(), output.to_str().unwrap());
        let err = refused(&["simulate", scene, "--output", output]);
        assert!(err.contains("is the scene file"), "{err}");
    }
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), text);
    std::fs::remove_dir_all(&dir).ok();
}

/// Issue 12: an existing output file is replaced only when the run writes its header, so
/// a run refused at validation (a negative step) or when compiling (FS0 refuses a flexible
/// crank) leaves an earlier run's file as it was; a run that starts replaces it.
#[test]
fn refused_scene_leaves_existing_output_untouched() {
    let (dir, csv) = with_earlier_output("untouched");
    let scene = model("double_four_bar.ron");
    let path = csv.to_str().unwrap();
    for args in [
        vec!["simulate", &scene, "--step", "-1", "--output", path],
        [
            &["simulate", &scene][..],
            &FS0_FLEXIBLE_CRANK,
            &["--output", path],
        ]
        .concat(),
    ] {
        refused(&args);
        assert_eq!(std::fs::read_to_string(&csv).unwrap(), EARLIER_RUN);
    }
    let out = run(["simulate", &scene, "--duration", "0.02", "--output", path]);
    assert_eq!(code(&out), 0);
    assert!(std::fs::read_to_string(&csv).unwrap().starts_with("t,B0_x"));
    std::fs::remove_dir_all(&dir).ok();
}

/// Issue 12: the duration was rounded to whole steps without notice. The summary names
/// it in `warnings` (JSON) and on stderr (text).
#[test]
fn duration_rounded_to_whole_steps_is_warned() {
    let scene = model("double_four_bar.ron");
    let out = run(["simulate", &scene, "--duration", "0.0206", "--json"]);
    assert_eq!(code(&out), 0);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["steps"], 21);
    assert_eq!(
        v["warnings"][0],
        "solver.duration 0.0206 s is not a whole number of 0.001 s steps: the run is 21 steps, to t = 0.021 s"
    );
    let out = run(["simulate", &scene, "--duration", "0.0206"]);
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("warning: solver.duration 0.0206 s"), "{err}");
    let out = run(["simulate", &scene, "--duration", "0.02", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["warnings"], serde_json::json!([]));
}

/// `--jsonl` writes the same rows as `--output`, one JSON object per row keyed by the CSV
/// header, values bit for bit; it may not name the `--output` file.
#[test]
fn jsonl_rows_are_the_csv_rows() {
    let dir = temp_dir("jsonl");
    let (csv, jsonl) = (dir.join("run.csv"), dir.join("run.jsonl"));
    let scene = model("double_four_bar.ron");
    let out = run([
        "simulate",
        &scene,
        "--duration",
        "0.1",
        "--output",
        csv.to_str().unwrap(),
        "--jsonl",
        jsonl.to_str().unwrap(),
    ]);
    assert_success(&out);
    let csv_text = std::fs::read_to_string(&csv).unwrap();
    let mut csv_lines = csv_text.lines();
    let header: Vec<&str> = csv_lines.next().unwrap().split(',').collect();
    let jsonl_text = std::fs::read_to_string(&jsonl).unwrap();
    assert_eq!(jsonl_text.lines().count(), 11);
    for (row, line) in csv_lines.zip(jsonl_text.lines()) {
        let object: serde_json::Value = serde_json::from_str(line).unwrap();
        let mut keys: Vec<&str> = object
            .as_object()
            .unwrap()
            .keys()
            .map(|k| k.as_str())
            .collect();
        let mut names = header.clone();
        keys.sort();
        names.sort();
        assert_eq!(keys, names);
        // The fields as written, in column order (serde_json's default parser is not exact
        // to the last bit, and its map sorts the keys).
        let fields = line[1..line.len() - 1]
            .split(',')
            .map(|f| f.split_once(':').unwrap());
        for ((key, number), (name, value)) in fields.zip(header.iter().zip(row.split(','))) {
            assert_eq!(key, format!("{name:?}"));
            let (a, b): (f64, f64) = (number.parse().unwrap(), value.parse().unwrap());
            assert_eq!(a.to_bits(), b.to_bits(), "{line}");
        }
    }
    let csv = csv.to_str().unwrap();
    let err = refused(&["simulate", &scene, "--output", csv, "--jsonl", csv]);
    assert!(err.contains("is the --output file"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Given a scene, `modes` says so and lists its bodies; `--body` reduces one of them as the
/// scene runs it: the flexible pendulum's bar is a clamped–free Euler–Bernoulli beam, whose
/// first frequency is (1.8751²/2π) √(EI/(ρA L⁴)) = 9.2155 Hz (E I = 2.1e11 · 1.2914e-9,
/// ρ A = 7850 · 1.2739e-4, L = 1, models/flexible_pendulum.ron), to 1e-4 with 10 elements.
#[test]
fn modes_on_a_scene_lists_its_bodies_and_reduces_one_with_body() {
    let scene = model("flexible_pendulum.ron");
    let err = refused(&["modes", &scene]);
    assert_contains_all(&err, &["is a scene", "bar (flexible beam)", "--body NAME"]);
    let err = refused(&["modes", &scene, "--body", "beam"]);
    assert_contains_all(
        &err,
        &["--body beam", "no such body", "bar (flexible beam)"],
    );
    let err = refused(&["modes", &model("double_four_bar.ron"), "--body", "crank1"]);
    assert_contains_all(&err, &["crank1", "rigid", "flexible: true"]);
    let err = refused(&["modes", &model("cantilever_2d.ron"), "--body", "bar"]);
    assert_contains_all(&err, &["cantilever_2d.ron", "body model, not a scene"]);

    let out = run(["modes", &scene, "--body", "bar", "--json"]);
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let f0 = v["normal_modes"][0]["frequency_hz"].as_f64().unwrap();
    let (ei, rho_a): (f64, f64) = (2.1e11 * 1.2914e-9, 7850.0 * 1.2739e-4);
    let analytic = 1.8751_f64.powi(2) / (2.0 * std::f64::consts::PI) * (ei / rho_a).sqrt();
    assert!(
        (f0 / analytic - 1.0).abs() < 1e-4,
        "{f0} Hz against {analytic} Hz"
    );
}

/// `modes` on an imported body's model file: its export read relative to the file and
/// reduced (the bar's fixed-interface modes, root and tip held: CalculiX mesh, the
/// lowest pair 3847.13 Hz); a missing export is named, exit 3.
#[test]
fn modes_reads_an_imported_body_model() {
    let out = run(["modes", &model("imported_bar.ron"), "--json"]);
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["n_fe_dofs"], 84);
    assert_eq!(v["static_modes"].as_array().unwrap().len(), 6);
    // Interface points are named: the tip's static modes, the frame at the root.
    assert_eq!(v["static_modes"][0]["interface"], "tip");
    assert_eq!(v["frame_dofs"][0]["interface"], "root");
    let f0 = v["normal_modes"][0]["frequency_hz"].as_f64().unwrap();
    assert!((f0 - 3847.1277).abs() < 1e-3, "{f0}");
    let dir = std::env::temp_dir().join(format!("flexmbd-cli-import-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(model("imported_bar.ron")).unwrap();
    let moved = dir.join("imported_bar.ron");
    std::fs::write(&moved, text).unwrap();
    let err = refused(&["modes", moved.to_str().unwrap()]);
    assert_contains_all(&err, &["bar_mesh.inp"]);
    std::fs::remove_dir_all(&dir).ok();
}

/// `modes` on a solid body's model file: the same bar meshed by Gmsh and assembled by the
/// built-in C3D8 gives the CalculiX import's modes; a bad Poisson ratio is refused by field.
#[test]
fn modes_reads_a_solid_body_model() {
    let json = |file: &str| {
        let out = run(["modes", &model(file), "--json"]);
        assert_success(&out);
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let (solid, imported) = (json("solid_bar.ron"), json("imported_bar.ron"));
    assert_eq!(solid["n_fe_dofs"], 84);
    for k in 0..4 {
        let f = |v: &serde_json::Value| v["normal_modes"][k]["frequency_hz"].as_f64().unwrap();
        assert!((f(&solid) / f(&imported) - 1.0).abs() < 1e-9, "mode {k}");
    }
    let dir = std::env::temp_dir().join(format!("flexmbd-cli-solid-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("fe")).unwrap();
    std::fs::copy(
        model("fe/bar_solid.msh"),
        dir.join("fe").join("bar_solid.msh"),
    )
    .unwrap();
    let text = std::fs::read_to_string(model("solid_bar.ron")).unwrap();
    let bad = dir.join("solid_bar.ron");
    std::fs::write(&bad, text.replace("poisson: 0.3", "poisson: 0.5")).unwrap();
    let err = refused(&["modes", bad.to_str().unwrap()]);
    assert_contains_all(&err, &["source.Solid.material.poisson", "0.5"]);
    std::fs::remove_dir_all(&dir).ok();
}
