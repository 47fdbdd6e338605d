//! The exit codes of `flexmbd`, one per kind of outcome, and the panic hook that turns a
//! panic (a bug) into one line on stderr and [`INTERNAL_ERROR`].

use std::panic::PanicHookInfo;

/// The run ended as asked (or `modes` printed its inventory).
pub const SUCCESS: u8 = 0;
/// The command line is wrong (clap's usage error).
pub const USAGE: u8 = 2;
/// The input was refused: scene, body model or `--set`, or a file that cannot be read or
/// written.
pub const INVALID_INPUT: u8 = 3;
/// The run failed: a step did not converge or diverged, no static equilibrium, no
/// consistent initial conditions, the pilot run of proper orthogonal modes failed.
pub const RUN_FAILED: u8 = 4;
/// The run (or the pilot run of its proper orthogonal modes) was interrupted (SIGINT,
/// SIGTERM).
pub const INTERRUPTED: u8 = 5;
/// `flexmbd tune`: no run of the sweep meets the tolerance (the table is printed all the
/// same).
pub const NO_CANDIDATE: u8 = 6;
/// A bug: a panic inside flexmbd (sysexits' EX_SOFTWARE).
pub const INTERNAL_ERROR: u8 = 70;

/// The exit codes as `--help` and the README list them.
pub const HELP: &str = "\
Exit codes:
  0   success
  2   usage error (unknown option, missing or malformed argument)
  3   invalid input: the scene, a body model or a --set refused, a file unreadable or unwritable
  4   the run failed: a step did not converge or diverged, no static equilibrium, no consistent start,
      the pilot run of proper orthogonal modes failed
  5   interrupted by Ctrl-C (SIGINT) or SIGTERM: the rows so far are written, the summary says
      \"interrupted\" (during the pilot run: no row, the output files untouched; a second
      signal ends the program at once, without the summary); sweep and tune: the runs
      finished are printed, the others marked \"interrupted\" (none when it came during the
      converged reference)
  6   tune: no run of the sweep meets the tolerance (the candidates are printed all the same)
  70  internal error: a bug in flexmbd, please report it";

/// The exit code of a run that ended with summary status `status`.
pub fn of_status(status: &str) -> u8 {
    match status {
        "ok" => SUCCESS,
        "interrupted" => INTERRUPTED,
        _ => RUN_FAILED,
    }
}

/// Report a panic as one line, `flexmbd: internal error, please report: MESSAGE (at
/// FILE:LINE)`, instead of the default message and backtrace hint.
pub fn report_panic(info: &PanicHookInfo<'_>) {
    let payload = info.payload();
    let message = payload
        .downcast_ref::<&str>()
        .copied()
        .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("(no message)");
    let location = info
        .location()
        .map_or_else(String::new, |l| format!(" (at {}:{})", l.file(), l.line()));
    eprintln!(
        "flexmbd: internal error, please report: {}{location}",
        message.replace('\n', " ")
    );
}
