//! `flexmbd animate SCENE --output run.glb|run.html [--fps F] [--scale S]`: run the scene
//! and write its animation (`flexmbd_viewer`): a glTF 2.0 binary, or a web page that plays
//! it offline. The output path, its extension and the scale are checked before the run;
//! the file is written whole to a temporary file beside it and renamed, so a failure
//! leaves no partial file. A run that fails is animated up to the failure, the failure
//! marked in the file, and ends with [`exit::RUN_FAILED`]; Ctrl-C or SIGTERM ends the run
//! between two steps, the animation written up to there, marked, with
//! [`exit::INTERRUPTED`].

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use flexmbd_viewer::{DEFAULT_FRAMES_PER_SECOND, Format, check_scale, record_or_stop, render};

use crate::output_file::OutputFile;
use crate::{CliResult, SceneInput, exit};

/// The arguments of `flexmbd animate`.
#[derive(Args)]
pub(crate) struct AnimateArgs {
    #[command(flatten)]
    input: SceneInput,
    /// Time step (s).
    #[arg(long, allow_negative_numbers = true)]
    step: Option<f64>,
    /// Simulated time (s).
    #[arg(long, allow_negative_numbers = true)]
    duration: Option<f64>,
    /// The animation to write: NAME.glb (glTF 2.0 binary) or NAME.html (self-contained web
    /// page with a player).
    #[arg(long)]
    output: PathBuf,
    /// Frames per second of simulated time (each frame at the nearest whole step).
    #[arg(long, default_value_t = DEFAULT_FRAMES_PER_SECOND, allow_negative_numbers = true)]
    fps: f64,
    /// Deformation scale factor of the flexible bodies (any finite number; 1: true size).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    scale: f64,
}

/// `flexmbd animate`: check the options and the output path, run the scene sampling its
/// frames, write the animation and print what was written.
pub(crate) fn animate(args: &AnimateArgs) -> CliResult {
    let format = Format::of(&args.output).map_err(|e| format!("--output {e}"))?;
    let scale = check_scale(args.scale).map_err(|e| format!("--scale: {e}"))?;
    OutputFile::check(
        "--output",
        &args.output,
        &[("the scene file", &args.input.scene)],
    )?;
    let mut scene = args.input.load()?;
    if let Some(h) = args.step {
        scene.solver.step = h;
    }
    if let Some(d) = args.duration {
        scene.solver.duration = d;
    }
    scene.validate()?;
    let clock = Instant::now();
    let stop = crate::stop_on_signals()?;
    let recording = record_or_stop(&scene, args.fps, &stop)?;
    let run_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let bytes = render(&recording, &scene, format, scale);
    write_whole(&args.output, &bytes)?;
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "wrote {}: {} frames to t = {} s, {} bodies, {:.1} kB ({:.2} s run, {:.3} s written)",
        args.output.display(),
        recording.times.len(),
        recording.times.last().copied().unwrap_or(0.0),
        recording.bodies.len(),
        bytes.len() as f64 / 1e3,
        run_seconds,
        clock.elapsed().as_secs_f64()
    )?;
    Ok(match &recording.failure {
        None => exit::SUCCESS,
        Some((_, message)) if recording.interrupted => {
            eprintln!("{message} (animated up to there, marked in the file)");
            exit::INTERRUPTED
        }
        Some((t, message)) => {
            eprintln!(
                "error: the run failed at t = {t} s: {message} (animated up to there, marked in the file)"
            );
            exit::RUN_FAILED
        }
    })
}

/// Write `bytes` to a temporary file beside `path`, then rename it to `path`: the file is
/// whole or absent.
fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy())
        .unwrap_or_default();
    let temporary = path.with_file_name(format!(".{name}.{}.part", std::process::id()));
    let refuse = |e: std::io::Error| format!("--output {}: cannot be written: {e}", path.display());
    let written = std::fs::File::create(&temporary)
        .and_then(|mut f| f.write_all(bytes).and_then(|()| f.sync_all()))
        .and_then(|()| std::fs::rename(&temporary, path));
    if let Err(e) = written {
        let _ = std::fs::remove_file(&temporary);
        return Err(refuse(e));
    }
    Ok(())
}
