//! Thesis ch. 4: the spin-up beam (scenes.md §5, methods.md §6). Every stiffening method
//! in both formulations against the project's own converged large-deformation reference
//! (ANCF cable elements, `flexmbd-ancf`, methods.md §7), beside the thesis's tables
//! (scenes.md §7.3–§7.4), and a stability map over the final speed Ωs and the step h
//! that shows where each method fails.

use flexmbd::ancf::{CableSpec, run_spin_up};
use flexmbd::core::Dim;
use flexmbd::model::{FormulationKind, MotionLaw, Scene, Stiffening};
use flexmbd::simulation::{self, History, Summary};

use super::StudyResult;
use crate::Settings;
use crate::chart::{LineChart, Series, SeriesLabelPosition};
use crate::report::Report;

type Error = Box<dyn std::error::Error>;
/// A tip history: (t, u_x, u_y) in metres.
type Tip = Vec<(f64, f64, f64)>;

/// The methods of the thesis's chapter-4 tables.
const METHODS: [(&str, Stiffening); 6] = [
    ("LIN", Stiffening::Linear),
    ("FNL1", Stiffening::Fnl1),
    ("FNL2", Stiffening::Fnl2),
    ("FS0", Stiffening::Foreshortening),
    ("SB10", Stiffening::Substructuring(10)),
    ("SB20", Stiffening::Substructuring(20)),
];
const FORMS: [(&str, FormulationKind); 2] = [
    ("AC", FormulationKind::Absolute),
    ("RC", FormulationKind::Relative),
];
/// Beam length (m), scenes.md §5.
const LENGTH: f64 = 10.0;
/// Thesis, 2D spin-up CPU times (s), AC / RC (scenes.md §7.3).
const THESIS_2D_CPU: [(&str, f64, f64); 3] = [
    ("FNL1", 0.266, 0.094),
    ("FNL2", 0.297, 0.125),
    ("FS0", 0.266, 0.094),
];
/// An error below this (m) counts as accurate in the stability map: 5 mm, about the
/// thesis's FS0 / SB20 transverse errors (scenes.md §7.4).
const ACCURATE: f64 = 5e-3;
/// A tip displacement beyond this (m) is a divergence: the beam is 10 m long.
const DIVERGED: f64 = 10.0;

/// The outcome of one run against the reference.
enum Outcome {
    /// The formulation or method refused the combination.
    Unsupported(String),
    /// The run stopped (Newton failure, divergence).
    Failed { at: f64, message: String },
    /// The run finished: largest tip errors (m) and its summary.
    Done {
        dx: f64,
        dy: f64,
        summary: Box<Summary>,
        tip: Vec<(f64, f64, f64)>,
    },
}

/// Tip displacement (t, u_x, u_y) from a history: `tip_ux`, `tip_uy` when the scene has
/// them, else `tip_x − L`, `tip_y` (positions in the turning beam frame).
fn tip_of(h: &History) -> Option<Tip> {
    let t = h.column("t")?;
    let (ux, uy) = match (h.column("tip_ux"), h.column("tip_uy")) {
        (Some(ux), Some(uy)) => (ux, uy),
        _ => (
            h.column("tip_x")?.iter().map(|x| x - LENGTH).collect(),
            h.column("tip_y")?,
        ),
    };
    Some(
        t.into_iter()
            .zip(ux)
            .zip(uy)
            .map(|((t, x), y)| (t, x, y))
            .collect(),
    )
}

fn scene_2d(
    stiffening: Stiffening,
    form: FormulationKind,
    omega_s: f64,
    h: f64,
    duration: f64,
) -> Result<Scene, Error> {
    let mut scene = Scene::load(crate::workspace_root().join("models/spin_up_beam_2d.ron"))?;
    scene.solver.stiffening = stiffening;
    scene.solver.formulation = form;
    scene.solver.step = h;
    scene.solver.duration = duration;
    scene.solver.output_interval = Some(0.01f64.max(h));
    for d in &mut scene.drivers {
        if let MotionLaw::SpinUp { omega_s: w, .. } = &mut d.law {
            *w = omega_s;
        }
    }
    scene.validate()?;
    Ok(scene)
}

/// Largest |Δ| of the tip components against the reference, on the reference's 0.01 s grid.
fn errors(tip: &[(f64, f64, f64)], reference: &flexmbd::ancf::History) -> (f64, f64) {
    let (mut dx, mut dy) = (0.0f64, 0.0f64);
    for &(t, x, y) in tip {
        let k = (t / 0.01).round() as usize;
        if k < reference.t.len() && (reference.t[k] - t).abs() < 1e-9 {
            dx = dx.max((x - reference.tip[k][0]).abs());
            dy = dy.max((y - reference.tip[k][1]).abs());
        }
    }
    (dx, dy)
}

fn run_one(scene: Result<Scene, Error>, reference: &flexmbd::ancf::History) -> Outcome {
    let scene = match scene {
        Ok(s) => s,
        Err(e) => return Outcome::Unsupported(e.to_string()),
    };
    match simulation::run(&scene, |_| {}) {
        Err(e) => Outcome::Unsupported(e.to_string()),
        Ok((summary, history)) => {
            let Some(tip) = tip_of(&history) else {
                return Outcome::Unsupported("the scene has no tip sensors".into());
            };
            let blew_up = tip.iter().find(|p| {
                p.1.abs().max(p.2.abs()) > DIVERGED || !p.1.is_finite() || !p.2.is_finite()
            });
            if summary.status != "ok" || blew_up.is_some() {
                let at = summary
                    .failed_at
                    .or(blew_up.map(|p| p.0))
                    .unwrap_or(f64::NAN);
                let message = summary
                    .message
                    .clone()
                    .unwrap_or_else(|| format!("tip displacement above {DIVERGED} m"));
                return Outcome::Failed { at, message };
            }
            let (dx, dy) = errors(&tip, reference);
            Outcome::Done {
                dx,
                dy,
                summary: Box::new(summary),
                tip,
            }
        }
    }
}

/// Run the study and append its section to the report.
pub fn run(settings: &Settings, report: &mut Report) -> StudyResult {
    let (omega_s, h) = (6.0, 1e-3);
    eprintln!("   reference: ANCF cable, 16 elements, Ωs = 6 rad/s");
    let reference = run_spin_up(&CableSpec::spin_up_beam(Dim::Planar, 16), h, 20.0, 0.01)?;
    let ref_min_y = reference
        .tip
        .iter()
        .map(|p| p[1])
        .fold(f64::INFINITY, f64::min);
    report.text(&format!(
        "The 2D spin-up beam of scenes.md §5 (L = 10 m, EA = 2.8e7 N, EI = 1.4e4 N·m², ρA = 1.2 kg/m; \
         Ωs = 6 rad/s reached in Ts = 15 s, 20 s, h = 1 ms) with every stiffening method in both \
         formulations, against the project's reference: ANCF cable elements (`flexmbd-ancf`, 16 \
         elements; methods.md §7: its convergence study changes the tip by < 1e-6 m from 16 to 32 \
         elements, far below the errors judged here). Reference tip: min u_y = {:.4} m. Errors are the \
         largest |Δu| over the 20 s, in mm. CPU time of the 20 s run, one run (the thesis's 2008 \
         figures beside, scenes.md §7.3). Inertia by shape integrals (for FS0 the body's FS0 shape integrals, \
         methods.md §6.3; they equal the B-matrix projection to round-off). FNL2 carries every axial FE DOF as a mode (methods.md §6.2 correction), hence \
         its coordinate count and cost.",
        ref_min_y
    ));
    let mut rows = Vec::new();
    let mut histories: Vec<(String, Tip)> = Vec::new();
    for &(name, stiffening) in &METHODS {
        for &(fname, form) in &FORMS {
            eprintln!("   {name} {fname}");
            let outcome = run_one(scene_2d(stiffening, form, omega_s, h, 20.0), &reference);
            let thesis = THESIS_2D_CPU
                .iter()
                .find(|r| r.0 == name)
                .map(|r| if fname == "AC" { r.1 } else { r.2 });
            let thesis = thesis.map_or("–".to_string(), |v| format!("{v:.3}"));
            match outcome {
                Outcome::Unsupported(msg) => rows.push(vec![
                    name.into(),
                    fname.into(),
                    "not available".into(),
                    "–".into(),
                    "–".into(),
                    "–".into(),
                    thesis,
                    "–".into(),
                    msg.chars().take(120).collect(),
                ]),
                Outcome::Failed { at, message } => rows.push(vec![
                    name.into(),
                    fname.into(),
                    format!("**failed** at t = {at:.2} s"),
                    "–".into(),
                    "–".into(),
                    "–".into(),
                    thesis,
                    "–".into(),
                    message.chars().take(120).collect(),
                ]),
                Outcome::Done {
                    dx,
                    dy,
                    summary,
                    tip,
                } => {
                    rows.push(vec![
                        name.into(),
                        fname.into(),
                        "ok".into(),
                        format!("{:.2}", dx * 1e3),
                        format!("{:.2}", dy * 1e3),
                        format!("{:.3}", summary.cpu_seconds),
                        thesis,
                        format!(
                            "{:.2}",
                            summary.newton_iterations as f64 / summary.steps.max(1) as f64
                        ),
                        format!("{} coordinates", summary.n_coordinates),
                    ]);
                    histories.push((format!("{name} {fname}"), tip));
                }
            }
        }
    }
    report.table(
        &[
            "method",
            "formulation",
            "status",
            "max |Δu_x| (mm)",
            "max |Δu_y| (mm)",
            "CPU (s)",
            "thesis CPU (s)",
            "Newton it./step",
            "notes",
        ],
        &rows,
    );
    report.text(
        "What the thesis found (scenes.md §7.4, 3D): SB is the most accurate and improves with n but is \
         slow; FNL1 has the largest axial error (it has no foreshortening); FS0 is nearly as accurate as \
         SB at FNL cost; the linear floating frame fails at 6 rad/s. Why the linear method must fail: its \
         first bending frequency, 3.80 rad/s (scenes.md §5, DERIVED), is below Ωs = 6 rad/s, and without \
         geometric stiffening the centrifugal field only softens the beam, so above the critical speed \
         the bending mode has negative stiffness and grows without bound.",
    );
    // Charts: tip histories over the reference.
    let mut sy = vec![Series {
        label: "ANCF reference".into(),
        points: reference
            .t
            .iter()
            .zip(&reference.tip)
            .map(|(&t, p)| (t, p[1]))
            .collect(),
        dashed: false,
        colour: 0,
    }];
    let mut sx = vec![Series {
        label: "ANCF reference".into(),
        points: reference
            .t
            .iter()
            .zip(&reference.tip)
            .map(|(&t, p)| (t, p[0] * 1e3))
            .collect(),
        dashed: false,
        colour: 0,
    }];
    for (i, (label, tip)) in histories.iter().enumerate() {
        sy.push(Series {
            label: label.clone(),
            points: tip.iter().map(|p| (p.0, p.2)).collect(),
            dashed: true,
            colour: i + 1,
        });
        sx.push(Series {
            label: label.clone(),
            points: tip.iter().map(|p| (p.0, p.1 * 1e3)).collect(),
            dashed: true,
            colour: i + 1,
        });
    }
    for (file, title, ylabel, series) in [
        (
            "spin_up_uy.svg",
            "2D spin-up: transverse tip displacement",
            "u_y (m)",
            sy,
        ),
        (
            "spin_up_ux.svg",
            "2D spin-up: axial tip displacement",
            "u_x (mm)",
            sx,
        ),
    ] {
        let chart = LineChart {
            title: title.into(),
            x_label: "t (s)".into(),
            y_label: ylabel.into(),
            log_x: false,
            log_y: false,
            series,
            legend: SeriesLabelPosition::LowerLeft,
        };
        let path = report.chart_path(file);
        chart.write_svg(&path)?;
        report.image(file, title);
    }
    stability_map(settings, report)?;
    Ok(())
}

/// Where methods fail: accurate / inaccurate / failed over Ωs × h.
fn stability_map(settings: &Settings, report: &mut Report) -> StudyResult {
    let duration = 20.0;
    let (speeds, steps, methods): (Vec<f64>, Vec<f64>, &[(&str, Stiffening)]) = if settings.quick {
        (vec![2.0, 6.0, 12.0], vec![1e-3, 1e-2], &METHODS[..3])
    } else {
        (
            vec![1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0, 15.0, 20.0],
            vec![1e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2],
            &METHODS[..],
        )
    };
    report.text(&format!(
        "### Stability map\n\nFor each method (relative formulation) over the final speed Ωs and the step h: \
         **A** accurate (largest tip error below {:.0} mm against the ANCF reference at that Ωs, run at \
         h = 1 ms), **I** bounded but inaccurate, **F** failed (Newton failure or a tip beyond {DIVERGED} m), \
         **–** not available. {}",
        ACCURATE * 1e3,
        if settings.quick { "`--quick` runs a coarse map; the full map is `cargo xtask reproduce-thesis --only spin-up`." } else { "" }
    ));
    let mut header: Vec<String> = vec!["method".into(), "h".into()];
    header.extend(speeds.iter().map(|w| format!("Ωs = {w}")));
    let mut rows = Vec::new();
    let mut references = Vec::new();
    for &w in &speeds {
        eprintln!("   reference at Ωs = {w}");
        let mut spec = CableSpec::spin_up_beam(Dim::Planar, 16);
        spec.omega_s = w;
        references.push(run_spin_up(&spec, 1e-3, duration, 0.01)?);
    }
    for &(name, stiffening) in methods {
        for &h in &steps {
            let mut row = vec![name.to_string(), format!("{} ms", h * 1e3)];
            for (i, &w) in speeds.iter().enumerate() {
                eprintln!("   {name} h = {h} Ωs = {w}");
                let outcome = run_one(
                    scene_2d(stiffening, FormulationKind::Relative, w, h, duration),
                    &references[i],
                );
                row.push(
                    match outcome {
                        Outcome::Unsupported(_) => "–",
                        Outcome::Failed { .. } => "F",
                        Outcome::Done { dx, dy, .. } if dx.max(dy) < ACCURATE => "A",
                        Outcome::Done { .. } => "I",
                    }
                    .to_string(),
                );
            }
            rows.push(row);
        }
    }
    let header_refs: Vec<&str> = header.iter().map(String::as_str).collect();
    report.table(&header_refs, &rows);
    Ok(())
}
