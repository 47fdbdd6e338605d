//! `cargo xtask reproduce-thesis [--quick] [--only NAME]`: runs the thesis's
//! comparisons and writes `docs/results/REPORT.md` with SVG charts.
//!
//! Each study is a module of `studies`; every later issue adds one.

mod chart;
mod report;
mod stills;
mod studies;
mod timing;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "xtask")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the thesis's comparisons and write docs/results/REPORT.md and charts.
    ReproduceThesis {
        /// Fewer grid points and repetitions: the whole report in a few minutes.
        #[arg(long)]
        quick: bool,
        /// Run only these studies (comma-separated names; see --list).
        #[arg(long, value_delimiter = ',')]
        only: Vec<String>,
        /// List the studies and exit.
        #[arg(long)]
        list: bool,
        /// Output directory (default: docs/results of the workspace).
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// Settings every study receives.
pub struct Settings {
    /// Coarse grids and fewer repetitions.
    pub quick: bool,
}

fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

fn main() -> ExitCode {
    let Cli {
        command:
            Command::ReproduceThesis {
                quick,
                only,
                list,
                out,
            },
    } = Cli::parse();
    let all = studies::all();
    if list {
        for s in &all {
            println!("{:20} {}", s.name, s.title);
        }
        return ExitCode::SUCCESS;
    }
    for name in &only {
        if !all.iter().any(|s| s.name == name) {
            let names: Vec<&str> = all.iter().map(|s| s.name).collect();
            eprintln!(
                "error: unknown study `{name}`; the studies are: {}",
                names.join(", ")
            );
            return ExitCode::FAILURE;
        }
    }
    let dir = out.unwrap_or_else(|| workspace_root().join("docs/results"));
    let mut report = match report::Report::new(&dir) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: cannot create {}: {e}", dir.display());
            return ExitCode::FAILURE;
        }
    };
    let settings = Settings { quick };
    let start = Instant::now();
    let mut failed = false;
    for s in all
        .iter()
        .filter(|s| only.is_empty() || only.iter().any(|o| o == s.name))
    {
        eprintln!("== {} ({})", s.title, s.name);
        let t = Instant::now();
        report.text(&format!("## {}\n", s.title));
        if let Err(e) = (s.run)(&settings, &mut report) {
            eprintln!("error in study {}: {e}", s.name);
            report.text(&format!("**This study failed:** {e}"));
            failed = true;
        }
        eprintln!("   {:.1} s", t.elapsed().as_secs_f64());
    }
    let header = format!(
        "# flexmbd: the thesis's comparisons, reproduced\n\n\
         Written by `cargo xtask reproduce-thesis{}{}`. Machine: {}. \
         Times are medians of several repetitions on one core.\n",
        if quick { " --quick" } else { "" },
        if only.is_empty() {
            String::new()
        } else {
            format!(" --only {}", only.join(","))
        },
        timing::machine()
    );
    match report.write(&header) {
        Ok(p) => {
            println!("report: {}", p.display());
            for f in &report.files {
                println!("chart:  {}", f.display());
            }
            println!("total:  {:.1} s", start.elapsed().as_secs_f64());
        }
        Err(e) => {
            eprintln!("error: cannot write the report: {e}");
            return ExitCode::FAILURE;
        }
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
