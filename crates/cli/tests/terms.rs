//! `flexmbd terms` (issue 31 item 2): the weights of each flexible body's inertia terms over
//! a pilot run, the weights' choice and the choice confirmed at the tolerance (its pilot
//! error, CPU and kernel work), as a table and as JSON; bad input — a threshold outside
//! (0, 1), a scene without a flexible body, a pilot duration that is not positive, a
//! foreshortened body (FS0 cannot drop terms), an unknown sensor — each a clear error
//! naming the value.

mod common;

use common::{assert_contains_all, code, model, refused, run};

#[test]
fn the_table_and_the_json_agree_on_the_choice() {
    let scene = model("spin_up_beam_2d.ron");
    let out = run(["terms", &scene, "--duration", "2", "--threshold", "0.01"]);
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let table = String::from_utf8(out.stdout).unwrap();
    assert_contains_all(
        &table,
        &[
            "body beam (6 modes, 201 samples)",
            "second-order",
            "gyroscopic",
            "deform max",
            "weights' choice at 1e-2:",
            "confirmed at 1e-2",
            "pilot error",
            "kernel work",
        ],
    );
    let out = run([
        "terms",
        &scene,
        "--duration",
        "2",
        "--threshold",
        "0.01",
        "--json",
    ]);
    assert_eq!(code(&out), 0);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let body = &json["bodies"][0];
    assert_eq!(body["body"], "beam");
    assert_eq!(body["groups"].as_array().unwrap().len(), 4);
    assert_eq!(body["candidates"].as_array().unwrap().len(), 8);
    let weights_choice = body["chosen"].as_str().unwrap();
    assert!(
        table.contains(&format!("weights' choice at 1e-2: {weights_choice}")),
        "{weights_choice} vs {table}"
    );
    let confirmed = &json["confirmed"];
    assert_eq!(confirmed["weights_choice"], weights_choice);
    assert_eq!(confirmed["horizon_seconds"], 2.0);
    let chosen = confirmed["chosen"]["terms"]["beam"].as_str().unwrap();
    let error = confirmed["chosen"]["pilot_error"].as_f64().unwrap();
    assert!((0.0..=0.01).contains(&error), "{confirmed}");
    for rejected in confirmed["rejected"].as_array().unwrap() {
        let e = &rejected["pilot_error"];
        assert!(e == "inf" || e.as_f64().unwrap() > 0.01, "{confirmed}");
    }
    assert!(
        table.contains(&format!("chosen at 1e-2: {chosen} (pilot error")),
        "{chosen} vs {table}"
    );
}

#[test]
fn bad_input_is_named() {
    let scene = model("spin_up_beam_2d.ron");
    for t in ["1", "0", "-0.1", "NaN"] {
        let err = refused(&["terms", &scene, "--threshold", t]);
        assert_contains_all(&err, &["--threshold", "must be in (0, 1)"]);
    }
    let err = refused(&["terms", &scene, "--duration", "-1"]);
    assert_contains_all(&err, &["duration = -1", "positive"]);
    let err = refused(&["terms", &scene, "--stiffening", "fs0", "--duration", "0.1"]);
    assert_contains_all(
        &err,
        &["bodies[beam] = foreshortened (FS0)", "cannot be dropped"],
    );
    let err = refused(&["terms", &scene, "--duration", "0.1", "--sensor", "tip_q"]);
    assert_contains_all(&err, &["sensor = tip_q", "is not a sensor", "tip_uy"]);
    let rigid = model("double_four_bar.ron");
    let err = refused(&["terms", &rigid]);
    assert_contains_all(&err, &["no flexible body", "flexible=true"]);
}
