//! `flexmbd fmu SCENE --output NAME.fmu [--fmi 3|2]`: the FMI 3.0 (or 2.0) co-simulation
//! FMU of a scene
//! (`flexmbd_fmi`): the scene with its `--set` values applied and the files it reads go
//! into the FMU's `resources/`, the shared library `libflexmbd_fmi` (built with
//! `cargo build --release -p flexmbd-fmi`, found beside this program or named with
//! `--library`) into `binaries/`; with `--target TRIPLE`, a library cross-built for
//! another platform (`cargo build --release -p flexmbd-fmi --target TRIPLE`).

use std::path::PathBuf;

use clap::Args;
use flexmbd_fmi::package::{Platform, Version};

use crate::{CliResult, SceneInput, exit};

/// The arguments of `flexmbd fmu`.
#[derive(Args)]
pub(crate) struct FmuArgs {
    #[command(flatten)]
    input: SceneInput,
    /// Time step h of the scene inside the FMU (s); the master's communication step must
    /// be a whole number of it.
    #[arg(long, allow_negative_numbers = true)]
    step: Option<f64>,
    /// The FMU file to write (NAME.fmu; NAME, made a C identifier, is the model identifier).
    #[arg(long)]
    output: PathBuf,
    /// FMI version: 3 or 2 (one library serves both).
    #[arg(long, default_value_t = 3)]
    fmi: u8,
    /// A real number of the scene (a --set path, e.g. solver.step or
    /// bodies.chassis.model.Rigid.mass) offered as an FMU parameter, set before the start.
    #[arg(long = "parameter", value_name = "PATH")]
    parameters: Vec<String>,
    /// The platform of the FMU's binary, a Rust target triple (e.g.
    /// aarch64-unknown-linux-gnu; default: this machine's), for a library built with
    /// `cargo build --release -p flexmbd-fmi --target TRIPLE`.
    #[arg(long, value_name = "TRIPLE")]
    target: Option<String>,
    /// The FMU's shared library (default: libflexmbd_fmi beside this program, or with
    /// --target in cargo's folder for that triple, ../TRIPLE/release/ from this program).
    #[arg(long)]
    library: Option<PathBuf>,
}

/// `flexmbd fmu`: load the scene, apply the command line, validate it and write the FMU.
pub(crate) fn fmu(args: &FmuArgs) -> CliResult {
    let version = match args.fmi {
        3 => Version::Fmi3,
        2 => Version::Fmi2,
        other => {
            return Err(format!("--fmi {other}: the FMI versions written are 3 and 2").into());
        }
    };
    if args.output.extension().is_none_or(|e| e != "fmu") {
        return Err(format!(
            "--output {}: an FMU's name ends in .fmu",
            args.output.display()
        )
        .into());
    }
    let mut scene = args.input.load()?;
    if let Some(h) = args.step {
        scene.solver.step = h;
    }
    scene.validate()?;
    let platform = match &args.target {
        Some(triple) => Platform::of_triple(triple)?,
        None => {
            Platform::host().ok_or("no FMI platform for this machine: name one with --target")?
        }
    };
    let library = match &args.library {
        Some(path) => path.clone(),
        None => default_library(&platform, args.target.as_deref())?,
    };
    flexmbd_fmi::package::write_fmu(
        &scene,
        &args.output,
        &library,
        &platform,
        version,
        &args.parameters,
    )?;
    println!("wrote {}", args.output.display());
    Ok(exit::SUCCESS)
}

/// `libflexmbd_fmi` beside this program (cargo builds both into the same folder), or for a
/// target triple where cargo puts it: `target/TRIPLE/release/` beside `target/release/`.
fn default_library(platform: &Platform, triple: Option<&str>) -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?;
    let folder = exe.parent().ok_or("cannot find this program's folder")?;
    let folder = match triple {
        None => folder.to_path_buf(),
        Some(triple) => folder
            .parent()
            .ok_or("cannot find cargo's target folder")?
            .join(triple)
            .join("release"),
    };
    Ok(folder.join(platform.library_name()))
}
