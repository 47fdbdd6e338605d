//! `flexmbd terms` (issue 31 item 2): the weights of each flexible body's inertia terms over
//! a pilot run and the choice at a threshold, as a table and as JSON; bad input — a
//! threshold outside (0, 1), a scene without a flexible body, a pilot duration that is not
//! positive, a foreshortened body (FS0 cannot drop terms) — each a clear error naming the
//! value.

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
            "chosen at 1e-2:",
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
    let chosen = body["chosen"].as_str().unwrap();
    assert!(
        table.contains(&format!("chosen at 1e-2: {chosen}")),
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
    let rigid = model("double_four_bar.ron");
    let err = refused(&["terms", &rigid]);
    assert_contains_all(&err, &["no flexible body", "flexible=true"]);
}
