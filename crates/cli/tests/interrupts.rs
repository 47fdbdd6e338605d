//! Issue 12: an interrupted run keeps what it computed. A long run is signalled once its
//! CSV has a few hundred rows: after SIGINT or SIGTERM it ends between two steps with exit
//! code 5 and a summary with status "interrupted"; after SIGKILL nothing ends it cleanly.
//! Either way the CSV holds a header and whole rows, equal bit for bit to the rows of an
//! uninterrupted run to the same time. A run still in the pilot run of its proper
//! orthogonal modes ends the same way, before its first row.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

fn scene() -> String {
    format!(
        "{}/../../models/double_four_bar.ron",
        env!("CARGO_MANIFEST_DIR")
    )
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("flexmbd-cli-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A run of 10⁶ steps (1000 s simulated, a row per 10 ms) streaming its CSV to `csv`.
fn start_long_run(csv: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args([
            "simulate",
            &scene(),
            "--duration",
            "1000",
            "--json",
            "--output",
        ])
        .arg(csv)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Wait until `csv` holds at least `rows` lines (the run is under way).
fn wait_for_rows(child: &mut Child, csv: &Path, rows: usize) {
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        let lines = std::fs::read(csv).map_or(0, |b| b.iter().filter(|&&c| c == b'\n').count());
        if lines >= rows {
            return;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before it was signalled"
        );
        assert!(Instant::now() < deadline, "no {rows} rows in 120 s");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Send `signal` (a name `kill -s` knows) to the child.
fn send(child: &Child, signal: &str) {
    let status = Command::new("kill")
        .args(["-s", signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success(), "kill -s {signal}");
}

/// The path of a scene of `models/`.
fn model(name: &str) -> String {
    format!("{}/../../models/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Start `flexmbd ARGS`, send it SIGINT a second later, and return its output once it has
/// ended.
fn interrupted_after_a_second(args: &[&str]) -> Output {
    let child = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_secs(1));
    send(&child, "INT");
    finish(child)
}

/// The child's output once it has ended (killed, and the test failed, if that takes over
/// 120 s: a hang).
fn finish(mut child: Child) -> Output {
    let deadline = Instant::now() + Duration::from_secs(120);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            child.kill().ok();
            panic!("the run did not end after the signal");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    child.wait_with_output().unwrap()
}

/// The lines of a CSV that must be a header and whole rows: it ends with a newline and
/// every row has the header's number of fields.
fn whole_rows(text: &str) -> Vec<&str> {
    assert!(
        text.ends_with('\n'),
        "the last row is cut: {:?}",
        text.lines().last()
    );
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "t,B0_x,B0_y,energy");
    for line in &lines[1..] {
        assert_eq!(line.split(',').count(), 4, "{line:?}");
    }
    lines
}

/// The CSV of an uninterrupted run to `t` (s), the time of an interrupted run's last row.
fn uninterrupted_to(t: &str, dir: &Path) -> String {
    let csv = dir.join("uninterrupted.csv");
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(["simulate", &scene(), "--duration", t, "--output"])
        .arg(&csv)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read_to_string(csv).unwrap()
}

/// Signal a long run once its CSV has 300 lines; check its rows against an uninterrupted
/// run to its last row's time, and return its output and number of rows.
fn interrupt_with(signal: &str) -> (Output, usize) {
    let dir = temp_dir(&format!("interrupt-{signal}"));
    let csv = dir.join("run.csv");
    let mut child = start_long_run(&csv);
    wait_for_rows(&mut child, &csv, 300);
    send(&child, signal);
    let out = finish(child);
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows = whole_rows(&text);
    assert!(rows.len() > 300, "{signal}: {} lines", rows.len());
    let t_last = rows.last().unwrap().split(',').next().unwrap();
    let reference = uninterrupted_to(t_last, &dir);
    assert!(
        text == reference,
        "{signal}: the {} rows to t = {t_last} s differ from an uninterrupted run's",
        rows.len() - 1
    );
    std::fs::remove_dir_all(&dir).ok();
    (out, rows.len() - 1)
}

/// SIGINT (Ctrl-C) and SIGTERM end the run between two steps: exit code 5, the JSON
/// summary with status "interrupted", its time and the rows written, every row so far in
/// the CSV.
#[test]
fn sigint_and_sigterm_end_the_run_as_interrupted_with_every_row() {
    for signal in ["INT", "TERM"] {
        let (out, rows) = interrupt_with(signal);
        assert_eq!(
            out.status.code(),
            Some(5),
            "{signal}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["status"], "interrupted", "{signal}");
        assert_eq!(v["rows"].as_u64(), Some(rows as u64), "{signal}");
        let t = v["simulated_seconds"].as_f64().unwrap();
        assert!(0.0 < t && t < 1000.0, "{signal}: {t}");
        let message = v["message"].as_str().unwrap();
        assert!(message.starts_with("interrupted at t = "), "{message}");
    }
}

/// SIGKILL cannot be caught: the CSV still holds a header and whole rows, equal to the
/// rows of an uninterrupted run.
#[test]
fn sigkill_leaves_a_header_and_whole_rows() {
    let (out, _) = interrupt_with("KILL");
    assert_eq!(out.status.code(), None, "killed by the signal");
    assert!(out.stdout.is_empty(), "no summary");
}

/// SIGINT during the pilot run of proper orthogonal modes (10⁸ pilot steps, minutes of
/// CPU): the pilot ends between two steps, exit code 5, a summary "interrupted" that names
/// the pilot, no row, and the CSV never written (the scene was not compiled).
#[test]
fn sigint_ends_the_pilot_run_of_proper_orthogonal_modes_as_interrupted() {
    let dir = temp_dir("interrupt-pilot");
    let csv = dir.join("run.csv");
    let pendulum = model("flexible_pendulum.ron");
    let csv_arg = csv.display().to_string();
    // Loading the scene and setting up the signal handlers take milliseconds; the pilot,
    // minutes. No row comes to wait for: a second is well inside the pilot.
    let out = interrupted_after_a_second(&[
        "simulate",
        &pendulum,
        "--set",
        "bodies.bar.model.Beam.mode_selection=ProperOrthogonal",
        "--set",
        "bodies.bar.model.Beam.normal_modes=1",
        "--duration",
        "1e5",
        "--json",
        "--output",
        &csv_arg,
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(5), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "interrupted");
    assert_eq!(
        (v["rows"].as_u64(), v["steps"].as_u64()),
        (Some(0), Some(0))
    );
    let message = v["message"].as_str().unwrap();
    for part in [
        "body `bar`",
        "pilot run",
        "was interrupted at t = ",
        "the run did not start",
    ] {
        assert!(message.contains(part), "`{part}` missing from: {message}");
    }
    assert!(!csv.exists(), "the CSV was written");
    std::fs::remove_dir_all(&dir).ok();
}

/// SIGINT during the runs of a sweep: exit 5, the table printed with the runs under way
/// marked interrupted, stderr saying how many finished. The reference is a file (so the
/// grid starts at once) and each run is 10⁷ steps, minutes: the signal comes during them.
#[test]
fn sigint_during_a_sweep_prints_what_finished_and_exits_interrupted() {
    let dir = temp_dir("interrupt-sweep");
    let reference = dir.join("reference.csv");
    let rows: String = (0..=1000).map(|k| format!("{},0\n", 10 * k)).collect();
    std::fs::write(&reference, format!("t,B0_x\n{rows}")).unwrap();
    let (four_bar, reference_arg) = (
        model("double_four_bar.ron"),
        reference.display().to_string(),
    );
    let out = interrupted_after_a_second(&[
        "sweep",
        &four_bar,
        "--sensor",
        "B0_x",
        "--set",
        "solver.duration=1e4",
        "--set",
        "solver.output_interval=10",
        "--grid",
        "step=1e-3,5e-4",
        "--reference",
        &reference_arg,
    ]);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert_eq!(out.status.code(), Some(5), "{stderr}");
    assert!(
        stderr.contains("interrupted: 0 of 2 runs finished"),
        "{stderr}"
    );
    let stopped = stdout
        .lines()
        .filter(|l| l.contains(" interrupted ") && l.contains("interrupted at t = "))
        .count();
    assert_eq!(stopped, 2, "{stdout}");
    std::fs::remove_dir_all(&dir).ok();
}
