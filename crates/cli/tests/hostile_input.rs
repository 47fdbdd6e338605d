//! Hostile input through the `flexmbd` program (issue 12): minimal bad scenes and `--set`
//! values that used to panic, hang, abort on allocation or run into NaN rows are refused
//! before the run, in both formulations, naming the file, line (where the field is in the
//! file) and field. Each test is named after what it reproduces.

use std::path::PathBuf;

mod common;
use common::{assert_contains_all, model, refused};

/// `models/NAME` after `edit`, written to a scratch file named after the test.
fn edited_model(name: &str, test: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("flexmbd-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{test}.ron"));
    let text = std::fs::read_to_string(model(name)).unwrap();
    std::fs::write(&path, edit(text)).unwrap();
    path
}

/// `flexmbd simulate SCENE ARGS… --formulation F` for each formulation: both must refuse
/// ([`refused`]: exit code 3, so no success and no panic's exit code 101; nothing on standard
/// output) with the same message on standard error, returned.
fn refused_in_both(scene: &str, args: &[&str]) -> String {
    let [a, r] = ["absolute", "relative"].map(|formulation| {
        let mut all = vec!["simulate", scene, "--duration", "0.01"];
        all.extend(["--formulation", formulation]);
        all.extend(args);
        refused(&all)
    });
    assert_eq!(a, r, "the formulations refuse differently");
    a
}

#[test]
fn nan_marker_position_in_the_file_is_refused_with_file_line_and_field() {
    let path = edited_model("double_four_bar.ron", "nan_marker", |t| {
        t.replacen(
            r#"(name: "A", position: [0.0, 0.0])"#,
            r#"(name: "A", position: [NaN, 0.0])"#,
            1,
        )
    });
    let path = path.display().to_string();
    let e = refused_in_both(&path, &[]);
    assert!(
        e.contains(&format!(
            "{path}:33: bodies[crank1].markers[A].position[0] = NaN: must be finite"
        )),
        "{e}"
    );
}

#[test]
fn relative_with_no_bodies_does_not_panic() {
    let path = edited_model("flexible_pendulum.ron", "no_bodies", |t| {
        let start = t.find("bodies: [").unwrap();
        let end = t.find("solver:").unwrap();
        format!("{}bodies: [],\n    {}", &t[..start], &t[end..])
    });
    let e = refused_in_both(&path.display().to_string(), &[]);
    assert_contains_all(&e, &["bodies = []: the scene has no moving body"]);
}

#[test]
fn huge_gravity_is_refused_instead_of_running_into_nan() {
    let e = refused_in_both(&model("double_four_bar.ron"), &["--set", "gravity.1=1e308"]);
    assert_contains_all(
        &e,
        &[":16: gravity[1] = 1e308: out of range: allowed [-1e4, 1e4] m/s²"],
    );
}

#[test]
fn substructuring_100000_is_refused_with_memory() {
    let e = refused_in_both(
        &model("spin_up_beam_2d.ron"),
        &["--stiffening", "substructuring:100000"],
    );
    assert_contains_all(
        &e,
        &[
            "Substructuring(100000): too many substructures: at most 1000",
            "dense 700000 × 700000 matrices need 3.9 TB each",
        ],
    );
}

#[test]
fn a_million_elements_per_segment_is_refused_with_memory() {
    let e = refused_in_both(
        &model("flexible_pendulum.ron"),
        &[
            "--set",
            "bodies.bar.model.Beam.geometry.elements_per_segment=1000000",
        ],
    );
    assert_contains_all(
        &e,
        &[
            "body `bar`: geometry.elements_per_segment = 1000000: too large",
            "3000003 FE DOFs",
            "72.0 TB each",
        ],
    );
}

#[test]
fn axial_modes_error_names_axial_modes() {
    let e = refused_in_both(
        &model("spin_up_beam_2d.ron"),
        &["--set", "bodies.beam.model.Beam.axial_modes=50"],
    );
    assert_contains_all(&e, &["body `beam`: axial_modes = 50"]);
    assert!(!e.contains("normal modes requested"), "{e}");
}
