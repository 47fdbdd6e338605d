//! The supervisor against real and fake workers: outcomes read back, and a hang, an
//! allocation failure, an abort and an exit each recorded as the class of the execution
//! in flight, with the next execution served by a new worker.

use std::os::unix::fs::PermissionsExt;
use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

use flexmbd::model::FormulationKind;
use flexmbd_fuzz::execute::Class;
use flexmbd_fuzz::supervise::{Supervisor, WorkerConfig};

/// The tests of this file run one at a time. A fake worker is a script written just before
/// it is executed; a test forking a worker meanwhile (on another thread) holds the script's
/// write descriptor from fork to exec, and executing the script inside that window fails
/// with ETXTBSY ("text file busy"), which the supervisor reports as a crash. Seen once in CI
/// (`a_worker_that_never_answers_is_a_hang_and_is_replaced`: Crash, not Hang).
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

fn one_at_a_time() -> MutexGuard<'static, ()> {
    ONE_AT_A_TIME
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

fn config(program: PathBuf, timeout: f64) -> WorkerConfig {
    WorkerConfig {
        program,
        memory_mib: 2048,
        max_steps: 2,
        timeout: Duration::from_secs_f64(timeout),
        directory: None,
    }
}

/// A fake worker: a shell script that ignores its arguments and runs `body`.
fn fake_worker(name: &str, body: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("flexmbd-fuzz-fake-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path
}

fn pendulum() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../models/flexible_pendulum.ron"
    ))
    .unwrap()
}

#[test]
fn the_real_worker_serves_several_executions_and_catches_a_refusal() {
    let _serial = one_at_a_time();
    let mut s = Supervisor::new(config(env!("CARGO_BIN_EXE_flexmbd-fuzz").into(), 60.0));
    let ok = s.execute(&pendulum(), FormulationKind::Relative);
    assert_eq!(
        (ok.class, ok.detail.as_str()),
        (Class::Ok, "2 steps to t = 0.002")
    );
    let refused = s.execute("(name: ", FormulationKind::Absolute);
    assert_eq!(refused.class, Class::Refused, "{}", refused.detail);
    let again = s.execute(&pendulum(), FormulationKind::Absolute);
    assert_eq!(again.class, Class::Ok, "{}", again.detail);
    assert_eq!(s.starts, 1, "one worker served all three");
}

/// A scene with an imported FE body names its export relative to itself: a worker
/// started in the scene's directory reads it (a mutant is loaded from text, so the
/// working directory is where its relative paths lead).
#[test]
fn a_worker_in_the_models_directory_runs_a_scene_with_an_imported_body() {
    let _serial = one_at_a_time();
    let models = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../models"));
    let scene = std::fs::read_to_string(models.join("imported_bar_pendulum.ron")).unwrap();
    let mut there = config(env!("CARGO_BIN_EXE_flexmbd-fuzz").into(), 60.0);
    there.directory = Some(models);
    let mut s = Supervisor::new(there);
    for f in [FormulationKind::Absolute, FormulationKind::Relative] {
        let o = s.execute(&scene, f);
        assert_eq!(o.class, Class::Ok, "{f:?}: {}", o.detail);
    }
    // A directory of its own, empty: the temp dir itself may hold an `fe/` of somebody else's.
    let empty = std::env::temp_dir().join(format!("flexmbd-fuzz-empty-{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    let mut elsewhere = config(env!("CARGO_BIN_EXE_flexmbd-fuzz").into(), 60.0);
    elsewhere.directory = Some(empty.clone());
    let o = Supervisor::new(elsewhere).execute(&scene, FormulationKind::Absolute);
    std::fs::remove_dir_all(&empty).unwrap();
    assert_eq!(o.class, Class::Refused, "{}", o.detail);
    assert!(o.detail.contains("cannot read"), "{}", o.detail);
}

#[test]
fn a_worker_that_never_answers_is_a_hang_and_is_replaced() {
    let _serial = one_at_a_time();
    let mut s = Supervisor::new(config(fake_worker("sleeper", "exec sleep 30"), 0.3));
    assert_eq!(s.execute("x", FormulationKind::Absolute).class, Class::Hang);
    assert_eq!(s.execute("x", FormulationKind::Absolute).class, Class::Hang);
    assert_eq!(s.starts, 2);
}

#[test]
fn a_worker_dying_on_an_allocation_failure_is_an_oom() {
    let _serial = one_at_a_time();
    let body = "echo 'memory allocation of 240000000000 bytes failed' >&2; kill -ABRT $$";
    let mut s = Supervisor::new(config(fake_worker("oom", body), 30.0));
    let o = s.execute("x", FormulationKind::Relative);
    assert_eq!(o.class, Class::Oom, "{}", o.detail);
    assert!(o.detail.contains("240000000000 bytes"), "{}", o.detail);
}

#[test]
fn other_aborts_signals_and_exits_are_told_apart() {
    let _serial = one_at_a_time();
    let cases = [
        (
            "abort",
            "echo 'fatal runtime error: x' >&2; kill -ABRT $$",
            Class::Abort,
        ),
        ("segv", "kill -SEGV $$", Class::Crash),
        ("exit", "exit 3", Class::Crash),
    ];
    for (name, body, class) in cases {
        let mut s = Supervisor::new(config(fake_worker(name, body), 30.0));
        let o = s.execute("x", FormulationKind::Absolute);
        assert_eq!(o.class, class, "{name}: {}", o.detail);
    }
}
