//! The kind of a beam's modes from the command line (docs/methods.md §1.6):
//! `--set bodies.NAME.model.Beam.mode_selection=KIND` (a unit variant) and
//! `mode_candidates=N` (an omitted optional count), and the sweep's `basis` axis; bad
//! values refused by name and value.

mod common;
use common::{assert_contains_all, code, flexmbd, model, refused};

const BEAM: &str = "bodies.beam.model.Beam";

fn simulate(sets: &[String]) -> std::process::Output {
    let mut cmd = flexmbd();
    cmd.args([
        "simulate",
        &model("spin_up_beam_2d.ron"),
        "--set",
        "solver.duration=0.2",
    ]);
    for s in sets {
        cmd.args(["--set", s]);
    }
    cmd.output().unwrap()
}

#[test]
fn mode_selection_and_candidates_are_set_from_the_command_line() {
    for sets in [
        vec![format!("{BEAM}.mode_selection=LoadRitz")],
        vec![
            format!("{BEAM}.mode_selection=Participation"),
            format!("{BEAM}.mode_candidates=6"),
        ],
    ] {
        let out = simulate(&sets);
        assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    }
}

#[test]
fn bad_mode_selections_are_refused_by_name_and_value() {
    let scene = model("spin_up_beam_2d.ron");
    let args = |sets: &[String]| -> Vec<String> {
        let mut a = vec!["simulate".to_string(), scene.clone()];
        for s in sets {
            a.extend(["--set".to_string(), s.clone()]);
        }
        a
    };
    let refuse = |sets: &[String]| {
        let a = args(sets);
        refused(&a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    let e = refuse(&[format!("{BEAM}.mode_selection=Krylov")]);
    assert_contains_all(&e, &["mode_selection", "Krylov", "LoadRitz"]);
    let e = refuse(&[format!("{BEAM}.mode_candidates=3")]);
    assert_contains_all(
        &e,
        &[
            "mode_candidates = 3",
            "only used with mode_selection: Participation",
        ],
    );
    let e = refuse(&[
        format!("{BEAM}.mode_selection=Participation"),
        format!("{BEAM}.mode_candidates=100"),
    ]);
    assert_contains_all(
        &e,
        &["body `beam`", "mode_candidates = 100", "interior DOFs"],
    );
    // Within the interior DOFs, but more than the 40 bending modes (20 are axial).
    let e = refuse(&[
        format!("{BEAM}.mode_selection=Participation"),
        format!("{BEAM}.mode_candidates=50"),
    ]);
    assert_contains_all(
        &e,
        &[
            "mode_candidates = 50",
            "only 40 normal modes that are not purely axial",
        ],
    );
    let e = refuse(&[
        format!("{BEAM}.mode_selection=Participation"),
        format!("{BEAM}.mode_candidates=2"),
    ]);
    assert_contains_all(&e, &["mode_candidates = 2", "at least normal_modes (4)"]);
}

#[test]
fn the_sweep_basis_axis_takes_every_kind_and_refuses_others() {
    let scene = model("spin_up_beam_2d.ron");
    let out = flexmbd()
        .args([
            "sweep",
            &scene,
            "--sensor",
            "tip_uy",
            "--set",
            "solver.duration=0.2",
            "--grid",
            "basis=lowest,participation,ritz,pod",
            "--grid",
            "modes=2",
            "--json",
        ])
        .output()
        .unwrap();
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let runs = v["runs"].as_array().unwrap();
    let labels: Vec<&str> = runs.iter().map(|r| r["label"].as_str().unwrap()).collect();
    assert_eq!(
        labels,
        [
            "basis=lowest modes=2",
            "basis=participation modes=2",
            "basis=ritz modes=2",
            "basis=pod modes=2"
        ]
    );
    assert!(runs.iter().all(|r| r["status"] == "ok"), "{runs:?}");
    let out = flexmbd()
        .args([
            "sweep",
            &scene,
            "--sensor",
            "tip_uy",
            "--grid",
            "basis=krylov",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_ne!(code(&out), 0);
    assert_contains_all(&err, &["--grid basis", "`krylov`"]);
}

#[test]
fn modes_names_ritz_vectors_and_how_they_were_chosen() {
    let bar = std::fs::read_to_string(model("four_bar_bar_2d.ron")).unwrap();
    let ritz = bar.replace(
        "normal_modes: 2,",
        "normal_modes: 3, mode_selection: LoadRitz,",
    );
    assert_ne!(ritz, bar, "the bar model names its normal modes");
    let path = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("mode_selection_{}_bar.ron", std::process::id()));
    std::fs::write(&path, ritz).unwrap();
    let path = path.display().to_string();
    let out = flexmbd().args(["modes", &path]).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_contains_all(
        &text,
        &["(2 static + 3 Ritz)", "chosen by    LoadRitz", "[ 4] ritz"],
    );
    let out = flexmbd().args(["modes", "--json", &path]).output().unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["selection"], "LoadRitz");
    assert_eq!(v["normal_modes"].as_array().unwrap().len(), 3);
    // The bar's lowest Ritz frequency lies just above its lowest normal frequency.
    let f = v["normal_modes"][0]["frequency_hz"].as_f64().unwrap();
    assert!((40.41..40.42).contains(&f), "{f}");
}
