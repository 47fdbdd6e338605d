//! The `flexmbd modes` command: table, JSON, and errors that name the file.

use std::process::Command;

fn flexmbd() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexmbd"))
}

fn model(name: &str) -> String {
    format!("{}/../../models/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn modes_json_has_the_inventory() {
    let out = flexmbd()
        .args(["modes", &model("four_bar_bar_2d.ron"), "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
    let out = flexmbd()
        .args(["modes", &model("cantilever_2d.ron")])
        .output()
        .unwrap();
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
    let out = flexmbd()
        .args(["modes", bad.to_str().unwrap()])
        .output()
        .unwrap();
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
