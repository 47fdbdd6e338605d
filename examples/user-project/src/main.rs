//! A user's program outside the flexmbd workspace: it builds the double four-bar of
//! `models/double_four_bar.ron` (docs/scenes.md §1) with the builders, no RON, runs it and
//! writes the history as CSV in the form `flexmbd simulate --output` writes, so that the two
//! files can be compared byte for byte (`.ci/run` does).
//!
//! ```text
//! cargo run --release --manifest-path examples/user-project/Cargo.toml -- b0.csv
//! ```

mod four_bar;

use std::fmt::Write as _;
use std::process::ExitCode;

fn main() -> ExitCode {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: flexmbd-user-project OUTPUT.csv");
        return ExitCode::from(2);
    };
    let scene = match four_bar::double_four_bar() {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let (summary, history) = match flexmbd::simulation::run(&scene, |_| {}) {
        Ok(run) => run,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    if let Err(e) = std::fs::write(&path, csv_text(&history)) {
        eprintln!("{path}: {e}");
        return ExitCode::FAILURE;
    }
    eprintln!(
        "{}: {} rows written to {path}, {:.4} s CPU",
        scene.name,
        history.rows.len(),
        summary.cpu_seconds
    );
    ExitCode::SUCCESS
}

/// The history as `flexmbd simulate --output` writes it: the column names (plain words, so
/// no quoting), then every value in Rust's shortest round-trip form (`{:?}`).
fn csv_text(history: &flexmbd::History) -> String {
    let mut text = history.header.join(",");
    text.push('\n');
    for row in &history.rows {
        for (i, v) in row.iter().enumerate() {
            let separator = if i == 0 { "" } else { "," };
            write!(text, "{separator}{v:?}").expect("writing into a String does not fail");
        }
        text.push('\n');
    }
    text
}
