//! What the program's test binaries share: running `flexmbd`, the models of `models/`, and
//! the checks of a refusal.
#![allow(dead_code)]

use std::process::{Command, Output};

/// The program under test.
pub fn flexmbd() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexmbd"))
}

/// Run the binary with `args` and wait for its output.
pub fn run<const N: usize>(args: [&str; N]) -> Output {
    flexmbd().args(args).output().unwrap()
}

/// The path of `models/NAME`.
pub fn model(name: &str) -> String {
    format!("{}/../../models/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// The exit code of a finished command (not killed by a signal).
pub fn code(out: &Output) -> i32 {
    out.status.code().expect("the program exited by itself")
}

/// The standard error of `flexmbd ARGS…`, checked to be a refusal of invalid input: exit
/// code 3 (not a success, a failed run or a panic) and nothing on standard output (no
/// summary, no rows: the run did not start).
pub fn refused(args: &[&str]) -> String {
    let out = flexmbd().args(args).output().unwrap();
    let (exit, stdout) = (
        code(&out),
        String::from_utf8_lossy(&out.stdout).into_owned(),
    );
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(exit, 3, "{args:?}: {err}");
    assert!(stdout.is_empty(), "{args:?} wrote {stdout}");
    err
}

/// `text` contains each of `parts`.
pub fn assert_contains_all(text: &str, parts: &[&str]) {
    for part in parts {
        assert!(text.contains(part), "lacks {part:?}: {text}");
    }
}
