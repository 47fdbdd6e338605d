//! The `flexmbd` command-line program.
//!
//! `flexmbd modes MODEL.ron [--json]` prints the mode inventory of a flexible body:
//! each static mode with the boundary DOF it belongs to, each normal mode with its
//! frequency, and the DOFs the floating frame takes.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use flexmbd::fe::{BeamBodySpec, reduce};
use flexmbd::inventory::Inventory;

#[derive(Parser)]
#[command(
    name = "flexmbd",
    version,
    about = "Real-time flexible multibody dynamics"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Reduce a flexible body model and print its mode inventory.
    Modes {
        /// A body model file (RON), e.g. models/cantilever_2d.ron.
        model: PathBuf,
        /// Print one JSON object on stdout instead of a table.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Modes { model, json } => match modes(&model, json) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
    }
}

fn modes(model: &std::path::Path, json: bool) -> Result<(), Box<dyn std::error::Error>> {
    let spec = BeamBodySpec::from_file(model)?;
    let body = reduce(&spec).map_err(|e| format!("{}: {e}", model.display()))?;
    let inv = Inventory::of(&model.display().to_string(), &body);
    if json {
        println!("{}", serde_json::to_string(&inv)?);
    } else {
        print!("{}", inv.to_text());
    }
    Ok(())
}
