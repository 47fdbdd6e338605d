//! `flexmbd animate` (issue 30): what it writes, and its bad input — an output it cannot
//! write, a scale that is not finite, an unknown extension, a run that fails — each a
//! clear error or a marked file, never a broken one.

mod common;

use common::{assert_contains_all, code, model, refused, run};

fn temp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("flexmbd-animate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn a_glb_and_a_page_are_written_whole() {
    let scene = model("double_pendulum_3d.ron");
    let glb = temp("dp.glb");
    let out = run([
        "animate",
        &scene,
        "--output",
        glb.to_str().unwrap(),
        "--fps",
        "30",
    ]);
    assert_eq!(code(&out), 0, "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_contains_all(&stdout, &["61 frames to t = 2 s", "2 bodies", "kB"]);
    let bytes = std::fs::read(&glb).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!(
        u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize,
        bytes.len()
    );
    let html = temp("dp.html");
    let out = run(["animate", &scene, "--output", html.to_str().unwrap()]);
    assert_eq!(code(&out), 0);
    let page = std::fs::read_to_string(&html).unwrap();
    assert_contains_all(
        &page,
        &[
            "<!DOCTYPE html>",
            "THREE.GLTFLoader",
            "const GLB = \"Z2xURg",
        ],
    );
    assert!(
        !page.contains("src=\"http"),
        "nothing fetched from the network"
    );
}

#[test]
fn bad_options_are_refused_before_the_run() {
    let scene = model("double_pendulum_3d.ron");
    let glb = temp("refused.glb");
    let path = glb.to_str().unwrap();
    for scale in ["NaN", "inf", "-inf"] {
        let err = refused(&[
            "animate",
            &scene,
            "--output",
            path,
            &format!("--scale={scale}"),
        ]);
        assert_contains_all(&err, &["--scale", "must be a finite number"]);
    }
    let err = refused(&["animate", &scene, "--output", path, "--fps", "0"]);
    assert_contains_all(&err, &["frames per second", "positive finite"]);
    let err = refused(&["animate", &scene, "--output", "/nonexistent-dir/run.glb"]);
    assert_contains_all(
        &err,
        &["--output /nonexistent-dir/run.glb", "does not exist"],
    );
    let err = refused(&[
        "animate",
        &scene,
        "--output",
        temp("run.gltf").to_str().unwrap(),
    ]);
    assert_contains_all(&err, &[".glb", ".html"]);
    assert!(!glb.exists(), "nothing written");
}

#[test]
fn a_failed_run_is_written_up_to_its_failure_marked_with_exit_code_4() {
    let glb = temp("failed.glb");
    let path = glb.to_str().unwrap();
    let scene = model("flexible_pendulum.ron");
    let out = run([
        "animate",
        &scene,
        "--set",
        "solver.step=2",
        "--set",
        "solver.duration=4",
        "--output",
        path,
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(code(&out), 4, "{stderr}");
    assert_contains_all(
        &stderr,
        &["the run failed at t = 2 s", "marked in the file"],
    );
    let bytes = std::fs::read(&glb).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    assert_contains_all(&text, &["\"status\":\"failed\"", "\"failed_at\":2.0"]);
    let html = temp("failed.html");
    let out = run([
        "animate",
        &scene,
        "--set",
        "solver.step=2",
        "--set",
        "solver.duration=4",
        "--output",
        html.to_str().unwrap(),
    ]);
    assert_eq!(code(&out), 4);
    let page = std::fs::read_to_string(&html).unwrap();
    assert_contains_all(
        &page,
        &[
            "\"failure\":{\"message\":",
            "\"t\":2.0}",
            "run failed at t = ",
        ],
    );
}

/// SIGINT during a long run (the flexible pendulum for 10⁵ s: several minutes; the double
/// four-bar, rigid, ran 1000 s in about a second on a quiet machine, and fails at its dead
/// point at 6.5 s with a flexible coupler): the animation up to there
/// is written, marked interrupted, and the program ends with exit code 5.
#[test]
fn an_interrupted_run_is_written_up_to_the_signal_with_exit_code_5() {
    let glb = temp("interrupted.glb");
    let mut child = common::flexmbd()
        .args([
            "animate",
            &model("flexible_pendulum.ron"),
            "--duration",
            "100000",
            "--fps",
            "10",
            "--output",
        ])
        .arg(&glb)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the run ended before the signal"
    );
    let killed = std::process::Command::new("kill")
        .args(["-s", "INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(code(&out), 5, "{stderr}");
    assert_contains_all(&stderr, &["interrupted at t = ", "marked in the file"]);
    let text = String::from_utf8_lossy(&std::fs::read(&glb).unwrap()).into_owned();
    assert_contains_all(
        &text,
        &["\"status\":\"interrupted\"", "run interrupted at t = "],
    );
}
