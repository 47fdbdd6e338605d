//! Where the stiffening methods fail (issue 6, thesis ch. 4): for every method × formulation,
//! over the final speed Ωs of the spin-up manoeuvre and the step h, whether the 2D spin-up
//! beam (docs/scenes.md §5) is **accurate** (largest tip error below [`ACCURATE`] against the ANCF
//! reference at that Ωs), **bounded but inaccurate**, or **failed** (Newton failure or a tip
//! beyond [`DIVERGED`]), as a table and a chart.
//!
//! The linear floating-frame model softens with speed: in the turning frame its first
//! bending mode has ω² = ω₁² − Ωs², so above Ωs = ω₁ = 3.80 rad/s (the cantilever's first
//! bending frequency, docs/scenes.md §5 DERIVED) it has no restoring force and diverges.
//!
//! `--quick` runs a coarse map (3 speeds × 2 steps, 3 methods); the full map (10 × 7, all
//! six methods, both formulations: 840 runs of 20 s) is
//! `cargo xtask reproduce-thesis --only stability-map --out docs/results/stability-map`.

use std::path::Path;

use flexmbd::ancf::{CableSpec, History as Reference, run_spin_up};
use flexmbd::core::Dim;
use flexmbd::model::FormulationKind;
use plotters::prelude::*;

use super::StudyResult;
use super::spin_up::{ACCURATE, DIVERGED, METHODS, Outcome, run_one, scene_2d};
use crate::Settings;
use crate::report::Report;

/// First cantilever bending frequency of the spin-up beam (rad/s), docs/scenes.md §5 (DERIVED).
const OMEGA_1: f64 = 3.80;
/// Simulated time (s), docs/scenes.md §5.
const DURATION: f64 = 20.0;

/// One cell of the map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Cell {
    Accurate,
    Inaccurate,
    Failed,
    Unavailable,
}

impl Cell {
    fn letter(self) -> &'static str {
        match self {
            Cell::Accurate => "A",
            Cell::Inaccurate => "I",
            Cell::Failed => "F",
            Cell::Unavailable => "–",
        }
    }
    fn colour(self) -> RGBColor {
        match self {
            Cell::Accurate => RGBColor(44, 160, 44),
            Cell::Inaccurate => RGBColor(255, 170, 40),
            Cell::Failed => RGBColor(214, 39, 40),
            Cell::Unavailable => RGBColor(200, 200, 200),
        }
    }
}

/// Run the map and append its section.
pub fn run(settings: &Settings, report: &mut Report) -> StudyResult {
    let (speeds, steps, n_methods): (Vec<f64>, Vec<f64>, usize) = if settings.quick {
        (vec![2.0, 6.0, 12.0], vec![1e-3, 1e-2], 3)
    } else {
        (
            vec![1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0, 15.0, 20.0],
            vec![1e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2],
            METHODS.len(),
        )
    };
    let methods = &METHODS[..n_methods];
    let forms = [
        ("RC", FormulationKind::Relative),
        ("AC", FormulationKind::Absolute),
    ];
    report.text(&format!(
        "For each method and formulation over the final speed Ωs and the step h (2D spin-up beam, \
         20 s, Ts = 15 s): **A** accurate (largest tip error below {:.0} mm against the ANCF \
         reference at that Ωs, 16 elements, h = 1 ms), **I** bounded but inaccurate, **F** failed \
         (Newton failure, or a tip beyond {DIVERGED} m), **–** not available in that formulation. \
         The linear model must fail above Ωs = ω₁ = {OMEGA_1} rad/s, the beam's first bending \
         frequency: in the turning frame its first mode has ω² = ω₁² − Ωs² (centrifugal softening \
         without the geometric stiffening that the other methods add). {}",
        ACCURATE * 1e3,
        if settings.quick {
            "`--quick` runs a coarse map; the full one is `cargo xtask reproduce-thesis --only \
             stability-map --out docs/results/stability-map` ([its report](stability-map/REPORT.md))."
        } else {
            ""
        }
    ));
    // References, then every run.
    let mut references = Vec::new();
    for &w in &speeds {
        eprintln!("   reference at Ωs = {w}");
        let mut spec = CableSpec::spin_up_beam(Dim::Planar, 16);
        spec.omega_s = w;
        references.push(run_spin_up(&spec, 1e-3, DURATION, 0.01)?);
    }
    let cells = run_cells(methods.len(), &forms, &steps, &speeds, &references);
    let at = |m: usize, f: usize, k: usize, i: usize| {
        cells[((m * forms.len() + f) * steps.len() + k) * speeds.len() + i]
    };

    let mut header: Vec<String> = vec!["method".into(), "h".into()];
    header.extend(speeds.iter().map(|w| format!("Ωs = {w}")));
    let mut rows = Vec::new();
    for (m, (name, _)) in methods.iter().enumerate() {
        for (f, (form, _)) in forms.iter().enumerate() {
            for (k, &h) in steps.iter().enumerate() {
                let mut row = vec![format!("{name} {form}"), format!("{} ms", h * 1e3)];
                row.extend((0..speeds.len()).map(|i| at(m, f, k, i).letter().to_string()));
                rows.push(row);
            }
        }
    }
    let header_refs: Vec<&str> = header.iter().map(String::as_str).collect();
    report.table(&header_refs, &rows);

    // Where LIN fails against ω₁: the lowest speed at which it fails at h = 1 ms (or the
    // smallest step run), per formulation.
    let k_ref = steps
        .iter()
        .position(|&h| (h - 1e-3).abs() < 1e-12)
        .unwrap_or(0);
    for (f, (form, _)) in forms.iter().enumerate() {
        let first = (0..speeds.len()).find(|&i| at(0, f, k_ref, i) == Cell::Failed);
        let last_ok = (0..speeds.len())
            .rev()
            .find(|&i| at(0, f, k_ref, i) != Cell::Failed);
        report.text(&format!(
            "LIN {form} at h = {} ms: {}; {} (ω₁ = {OMEGA_1} rad/s).",
            steps[k_ref] * 1e3,
            first.map_or("never fails on this grid".into(), |i| format!(
                "fails from Ωs = {} rad/s",
                speeds[i]
            )),
            last_ok.map_or("fails at every speed".into(), |i| format!(
                "runs through at Ωs = {} rad/s",
                speeds[i]
            )),
        ));
    }

    let file = "stability_map.svg";
    let path = report.chart_path(file);
    draw(
        &path,
        methods.iter().map(|m| m.0).collect(),
        &forms.map(|f| f.0),
        &speeds,
        &steps,
        &at,
    )?;
    report.image(
        file,
        "stability map: accurate / inaccurate / failed over Ωs and h",
    );
    Ok(())
}

/// Every cell of the map, method-major then formulation, step and speed: the runs are
/// independent, so two threads share them (each run is itself sequential and deterministic).
fn run_cells(
    n_methods: usize,
    forms: &[(&str, FormulationKind)],
    steps: &[f64],
    speeds: &[f64],
    references: &[Reference],
) -> Vec<Cell> {
    let mut jobs = Vec::new();
    for m in 0..n_methods {
        for (f, _) in forms.iter().enumerate() {
            for (k, _) in steps.iter().enumerate() {
                for (i, _) in speeds.iter().enumerate() {
                    jobs.push((m, f, k, i));
                }
            }
        }
    }
    let next = std::sync::atomic::AtomicUsize::new(0);
    let cells = std::sync::Mutex::new(vec![Cell::Unavailable; jobs.len()]);
    let run_job = |&(m, f, k, i): &(usize, usize, usize, usize), refs: &[Reference]| -> Cell {
        let (name, stiffening) = METHODS[m];
        let (h, w) = (steps[k], speeds[i]);
        eprintln!("   {name} {} h = {h} Ωs = {w}", forms[f].0);
        match run_one(scene_2d(stiffening, forms[f].1, w, h, DURATION), &refs[i]) {
            Outcome::Unsupported(_) => Cell::Unavailable,
            Outcome::Failed { .. } => Cell::Failed,
            Outcome::Done { dx, dy, .. } if dx.max(dy) < ACCURATE => Cell::Accurate,
            Outcome::Done { .. } => Cell::Inaccurate,
        }
    };
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| {
                loop {
                    let j = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    if j >= jobs.len() {
                        break;
                    }
                    let c = run_job(&jobs[j], references);
                    cells.lock().expect("no panics while held")[j] = c;
                }
            });
        }
    });
    cells.into_inner().expect("threads joined")
}

/// One panel per method × formulation: Ωs across, h up, a coloured cell per run.
fn draw(
    path: &Path,
    methods: Vec<&str>,
    forms: &[&str],
    speeds: &[f64],
    steps: &[f64],
    at: &dyn Fn(usize, usize, usize, usize) -> Cell,
) -> Result<(), Box<dyn std::error::Error>> {
    let (cols, rows) = (forms.len(), methods.len());
    let root =
        SVGBackend::new(path, (420 * cols as u32, 60 + 230 * rows as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(60);
    title.draw(&Text::new(
        "Stability map, 2D spin-up beam: A accurate (green), I inaccurate (orange), F failed (red), – n/a (grey)",
        (10, 20),
        ("sans-serif", 16),
    ))?;
    let panels = body.split_evenly((rows, cols));
    for (p, panel) in panels.iter().enumerate() {
        let (m, f) = (p / cols, p % cols);
        let mut chart = ChartBuilder::on(panel)
            .caption(format!("{} {}", methods[m], forms[f]), ("sans-serif", 16))
            .margin(8)
            .x_label_area_size(34)
            .y_label_area_size(56)
            .build_cartesian_2d(
                -0.5..speeds.len() as f64 - 0.5,
                -0.5..steps.len() as f64 - 0.5,
            )?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(speeds.len())
            .y_labels(steps.len())
            .x_label_formatter(&|v| category(*v, speeds, 1.0))
            .y_label_formatter(&|v| category(*v, steps, 1e3))
            .x_desc("Ωs (rad/s)")
            .y_desc("h (ms)")
            .draw()?;
        chart.draw_series((0..steps.len()).flat_map(|k| {
            (0..speeds.len()).map(move |i| {
                let c = at(m, f, k, i);
                let (x, y) = (i as f64, k as f64);
                Rectangle::new(
                    [(x - 0.45, y - 0.45), (x + 0.45, y + 0.45)],
                    c.colour().filled(),
                )
            })
        }))?;
    }
    root.present()?;
    Ok(())
}

/// Axis label of a category axis: the value of the cell centred at an integer position.
fn category(v: f64, values: &[f64], scale: f64) -> String {
    let r = v.round();
    if (v - r).abs() > 1e-6 || r < 0.0 {
        return String::new();
    }
    values
        .get(r as usize)
        .map_or(String::new(), |x| format!("{}", x * scale))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_chart_has_a_panel_per_method_and_formulation_and_a_cell_per_run() {
        let dir = std::env::temp_dir().join(format!("flexmbd-map-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("map.svg");
        let (speeds, steps) = ([2.0, 6.0, 12.0], [1e-3, 1e-2]);
        let at = |m: usize, f: usize, k: usize, i: usize| match (m + f + k + i) % 4 {
            0 => Cell::Accurate,
            1 => Cell::Inaccurate,
            2 => Cell::Failed,
            _ => Cell::Unavailable,
        };
        draw(
            &path,
            vec!["LIN", "FNL1"],
            &["RC", "AC"],
            &speeds,
            &steps,
            &at,
        )
        .unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        for caption in [
            "LIN RC",
            "LIN AC",
            "FNL1 RC",
            "FNL1 AC",
            "Ωs (rad/s)",
            "h (ms)",
        ] {
            assert!(svg.contains(caption), "missing {caption}");
        }
        // 2 methods × 2 formulations × 2 steps × 3 speeds cells, in all four colours.
        let cells: usize = [
            Cell::Accurate,
            Cell::Inaccurate,
            Cell::Failed,
            Cell::Unavailable,
        ]
        .iter()
        .map(|c| {
            let RGBColor(r, g, b) = c.colour();
            svg.matches(&format!("fill=\"#{r:02X}{g:02X}{b:02X}\""))
                .count()
        })
        .sum();
        assert_eq!(cells, 24, "{svg}");
        assert_eq!(category(1.0, &speeds, 1.0), "6");
        assert_eq!(category(0.5, &speeds, 1.0), "");
        assert_eq!(category(1.0, &steps, 1e3), "10");
    }
}
