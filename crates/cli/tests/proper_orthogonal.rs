//! Proper orthogonal modes from the command line (docs/methods.md §1.6): the pilot run is
//! deterministic — two processes write the same CSV byte for byte — and a body model on its
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
