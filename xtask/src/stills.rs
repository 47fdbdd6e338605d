//! Still images of a scene's animation for the report: the scene is recorded
//! (`flexmbd_viewer::record`) and written as the web page that `flexmbd animate` writes,
//! which headless Chromium opens at each chosen instant (`page.html#t=T` opens paused
//! there, as the CI browser check does) and screenshots, all instants at once. Without
//! Chromium (`chromium` or `chromium-browser` on the PATH), or when it fails or takes over
//! a minute, the stills are skipped with a printed note and a line in the report: the
//! report never fails for them.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use flexmbd::model::Scene;
use flexmbd_viewer::{Format, record, render};

use crate::report::Report;

/// Frames per second of simulated time of a still's recording (the page interpolates
/// between frames; a still shows one instant).
const FRAMES_PER_SECOND: f64 = 50.0;

/// The longest one screenshot may take.
const TIMEOUT: Duration = Duration::from_secs(60);

/// The page's size (pixels).
const WINDOW: &str = "900,600";

/// The Chromium program on the PATH, if any.
fn chromium() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser"].iter().find_map(|name| {
        std::env::split_paths(&path)
            .map(|dir| dir.join(name))
            .find(|p| p.is_file())
    })
}

/// Add to `report` a still of `scene` (run to the last of `times`) at each of `times`
/// (s), the deformation drawn `scale` times, as `NAME_tT.png` beside REPORT.md, with
/// `caption`; or a note why not.
pub fn add(
    report: &mut Report,
    scene: &Scene,
    name: &str,
    times: &[f64],
    scale: f64,
    caption: &str,
) {
    let clock = Instant::now();
    match stills(report, scene, name, times, scale) {
        Ok(files) => {
            let shown: Vec<String> = times.iter().map(|t| format!("{t} s")).collect();
            report.text(&format!(
                "{caption} At t = {} (deformation drawn {scale} times; the page of `flexmbd \
                 animate`, screenshot by headless Chromium):",
                shown.join(" and ")
            ));
            for (file, t) in files.iter().zip(times) {
                report.image(file, &format!("{} at t = {t} s", scene.name));
            }
            eprintln!(
                "   stills of {name}: {} images in {:.1} s",
                files.len(),
                clock.elapsed().as_secs_f64()
            );
        }
        Err(why) => {
            eprintln!("   note: the animation stills of {name} are skipped: {why}");
            report.text(&format!(
                "*The animation stills of this scene were skipped: {why}.*"
            ));
        }
    }
}

/// The stills' file names (in the report directory), or why there are none.
fn stills(
    report: &mut Report,
    scene: &Scene,
    name: &str,
    times: &[f64],
    scale: f64,
) -> Result<Vec<String>, String> {
    let program = chromium()
        .ok_or("Chromium was not found on the PATH (the Debian package `chromium` draws them)")?;
    let mut scene = scene.clone();
    scene.solver.duration = times.iter().copied().fold(0.0, f64::max);
    let recording = record(&scene, FRAMES_PER_SECOND).map_err(|e| format!("{name}: {e}"))?;
    if let Some((t, message)) = &recording.failure {
        return Err(format!("{name}: the run failed at t = {t} s: {message}"));
    }
    let page = report.dir.join(format!(".{name}.html"));
    std::fs::write(&page, render(&recording, &scene, Format::Html, scale))
        .map_err(|e| format!("{}: {e}", page.display()))?;
    let files: Vec<String> = times.iter().map(|t| format!("{name}_t{t}.png")).collect();
    let started: Result<Vec<_>, String> = times
        .iter()
        .zip(&files)
        .enumerate()
        .map(|(k, (t, file))| {
            let profile = std::env::temp_dir()
                .join(format!("flexmbd-still-{}-{name}-{k}", std::process::id()));
            let shot = report.dir.join(file);
            let _ = std::fs::remove_file(&shot);
            let child = screenshot(&program, &page, *t, &shot, &profile)?;
            Ok((child, shot, profile))
        })
        .collect();
    let result = started.and_then(|children| {
        children
            .into_iter()
            .map(|(child, shot, profile)| {
                let done = wait(child);
                let _ = std::fs::remove_dir_all(&profile);
                done?;
                match std::fs::metadata(&shot) {
                    Ok(m) if m.len() > 0 => Ok(()),
                    _ => Err(format!("Chromium wrote no {}", shot.display())),
                }
            })
            .collect::<Result<Vec<()>, String>>()
    });
    let _ = std::fs::remove_file(&page);
    result?;
    for file in &files {
        report.chart_path(file);
    }
    Ok(files)
}

/// Start Chromium screenshotting `page` at `t` into `shot`, with a profile of its own (the
/// screenshots run at once), the network off.
fn screenshot(
    program: &Path,
    page: &Path,
    t: f64,
    shot: &Path,
    profile: &Path,
) -> Result<Child, String> {
    let url = format!(
        "file://{}#t={t}",
        page.canonicalize().map_err(|e| e.to_string())?.display()
    );
    Command::new(program)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--proxy-server=127.0.0.1:9",
            "--virtual-time-budget=5000",
        ])
        .arg(format!("--window-size={WINDOW}"))
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(url)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| format!("{} could not be started: {e}", program.display()))
}

/// Wait for Chromium, killing it after [`TIMEOUT`].
fn wait(mut child: Child) -> Result<(), String> {
    let clock = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(status)) if status.success() => return Ok(()),
            Ok(Some(status)) => return Err(format!("Chromium ended with {status}")),
            Ok(None) if clock.elapsed() > TIMEOUT => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(format!("Chromium took over {} s", TIMEOUT.as_secs()));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(50)),
            Err(e) => return Err(e.to_string()),
        }
    }
}
