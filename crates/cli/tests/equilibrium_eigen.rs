//! `flexmbd equilibrium` and `flexmbd eigen`: the table and the JSON object, the options
//! that change the scene, both formulations agreeing, and the exit codes of a scene without
//! an equilibrium and of a refused one.

use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(args)
        .output()
        .unwrap()
}

fn assert_success(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn model(name: &str) -> String {
    format!("{}/../../models/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn json(out: &Output) -> serde_json::Value {
    assert_success(out);
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn equilibrium_table_lists_the_solve_sensors_coordinates_and_multipliers() {
    let out = run(&["equilibrium", &model("double_four_bar.ron")]);
    assert_success(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("double four-bar: static equilibrium, absolute formulation — 6 coordinates, 5 constraints"), "{text}");
    for line in [
        "sensors:",
        "coordinates q:",
        "multipliers λ",
        "  B0_y ",
        "  q5 ",
        "  λ4 ",
    ] {
        assert!(text.contains(line), "no {line:?} in\n{text}");
    }
}

#[test]
fn equilibrium_json_has_every_coordinate_and_the_sensors() {
    for formulation in ["absolute", "relative"] {
        let v = json(&run(&[
            "equilibrium",
            &model("double_four_bar.ron"),
            "--formulation",
            formulation,
            "--json",
        ]));
        assert_eq!(v["formulation"], formulation);
        let n = v["n_coordinates"].as_u64().unwrap() as usize;
        assert_eq!(v["coordinates"].as_array().unwrap().len(), n);
        let m = v["n_constraints"].as_u64().unwrap() as usize;
        assert_eq!(v["multipliers"].as_array().unwrap().len(), m);
        // The cranks stand upright where the scene puts them: B at (0, 1).
        let b0_y = &v["sensors"][1];
        assert_eq!(b0_y["name"], "B0_y");
        assert!((b0_y["value"].as_f64().unwrap() - 1.0).abs() < 1e-9, "{v}");
        assert!(v["residual"].as_f64().unwrap() < 1e-8);
    }
}

/// The rigid double four-bar with gravity turned upwards (`--set gravity.1=9.81`) hangs from
/// its upright cranks: one oscillation, the same in both formulations.
#[test]
fn eigen_json_both_formulations_give_the_four_bar_one_frequency() {
    let mut f = Vec::new();
    for formulation in ["absolute", "relative"] {
        let v = json(&run(&[
            "eigen",
            &model("double_four_bar.ron"),
            "--set",
            "gravity.1=9.81",
            "--formulation",
            formulation,
            "--json",
        ]));
        assert_eq!(v["dof"], 1);
        let modes = v["modes"].as_array().unwrap();
        assert_eq!(modes.len(), 1, "{v}");
        assert_eq!(modes[0]["kind"], "oscillatory");
        assert_eq!(modes[0]["index"], 1);
        assert_eq!(modes[0]["sensors"][0]["name"], "B0_x");
        f.push(modes[0]["frequency_hz"].as_f64().unwrap());
    }
    assert!(f[0] > 0.1 && ((f[0] - f[1]) / f[0]).abs() < 1e-6, "{f:?}");
}

/// Upright under the scene's own gravity the four-bar is unstable: the table flags the real
/// pair, sorted by frequency.
#[test]
fn eigen_table_flags_an_unstable_equilibrium() {
    let out = run(&["eigen", &model("double_four_bar.ron")]);
    assert_success(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[1].contains("frequency Hz") && lines[1].contains("damping"),
        "{text}"
    );
    assert_eq!(lines.len(), 4, "{text}");
    assert!(
        text.contains("unstable") && text.contains("overdamped"),
        "{text}"
    );
}

/// The floating platform under gravity is a free body falling: it has no static equilibrium,
/// and both commands fail with exit code 4, naming the scene.
#[test]
fn a_scene_without_an_equilibrium_fails_with_exit_4_naming_it() {
    for command in ["equilibrium", "eigen"] {
        let out = run(&[
            command,
            &model("floating_platform_3d.ron"),
            "--set",
            "gravity.2=-9.81",
        ]);
        assert_eq!(out.status.code(), Some(4), "{command}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("floating_platform_3d.ron: no static equilibrium"),
            "{command}: {err}"
        );
        assert!(out.stdout.is_empty());
    }
}

/// The flexible pendulum released from horizontal: its static tangent is singular at the guess
/// (turning about the pin does not change the weight's moment there, to first order),
/// which the statics' regularised second attempt gets past; it hangs, tip 1 m below the pin.
#[test]
fn the_flexible_pendulum_released_horizontal_is_found_hanging() {
    let out = run(&["equilibrium", &model("flexible_pendulum.ron"), "--json"]);
    assert_success(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let sensor = |name: &str| {
        v["sensors"]
            .as_array()
            .unwrap()
            .iter()
            .find(|s| s["name"] == name)
            .unwrap()["value"]
            .as_f64()
            .unwrap()
    };
    assert!(sensor("tip_x").abs() < 1e-9, "{v}");
    assert!((sensor("tip_y") + 1.0).abs() < 1e-6, "{v}");
}

#[test]
fn a_bad_set_is_refused_as_invalid_input() {
    let out = run(&[
        "eigen",
        &model("double_four_bar.ron"),
        "--set",
        "gravity.y=1",
    ]);
    assert_eq!(out.status.code(), Some(3));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("gravity.y"), "{err}");
}

#[test]
fn equilibrium_reports_every_joint_reaction_in_text_and_json() {
    // The double four-bar's seven pins: the table lists each, the JSON carries each with its
    // force and moment, the same (to round-off) in both formulations.
    let text =
        String::from_utf8(run(&["equilibrium", &model("double_four_bar.ron")]).stdout).unwrap();
    assert!(
        text.contains("joint reactions on body2 at its marker"),
        "{text}"
    );
    assert!(
        text.contains("  A0 ") && text.contains("Revolute"),
        "{text}"
    );
    let [absolute, relative] = ["absolute", "relative"].map(|formulation| {
        json(&run(&[
            "equilibrium",
            &model("double_four_bar.ron"),
            "--formulation",
            formulation,
            "--json",
        ]))
    });
    let joints = |v: &serde_json::Value| v["reactions"]["joints"].as_array().unwrap().clone();
    assert_eq!(joints(&absolute).len(), 7);
    assert_eq!(absolute["reactions"]["redundant"], false);
    for (a, r) in joints(&absolute).iter().zip(joints(&relative).iter()) {
        assert_eq!(a["name"], r["name"]);
        for key in ["force", "moment"] {
            for k in 0..3 {
                let (x, y) = (a[key][k].as_f64().unwrap(), r[key][k].as_f64().unwrap());
                assert!((x - y).abs() < 1e-9, "{}: {a} against {r}", a["name"]);
            }
        }
    }
}
