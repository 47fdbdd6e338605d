//! Work–precision (issue 16): error against CPU time for every stiffening method ×
//! formulation × inertia route over time steps and mode counts (on the 2D beam also the
//! kind of modes, with its own chart and table), with the Pareto front, on
//! the 2D and 3D spin-up beams (against the ANCF cable) and the double four-bar with its
//! five bars flexible (against its own converged run); and per scene the cheapest model
//! for 10 mm, 1 mm and 0.1 mm. Every run is a [`flexmbd::sweep`] grid point, reproducible
//! with `flexmbd simulate` and the arguments the sweep records; the choice of the cheapest
//! model is `flexmbd tune`'s rule ([`flexmbd::sweep::tune()`]).

use std::path::Path;

use flexmbd::ancf::{CableSpec, run_spin_up};
use flexmbd::body::InertiaMethod;
use flexmbd::core::Dim;
use flexmbd::fe::ModeSelection;
use flexmbd::model::{FormulationKind, Stiffening};
use flexmbd::sweep::{
    Axis, Grid, Reference, ReferenceTable, RunStatus, Setting, Sweep, SweepReport, Tuning,
    basis_name,
    grid::{formulation_name, inertia_name, stiffening_name},
    pareto_front, tune,
};

use super::StudyResult;
use crate::Settings;
use crate::chart::{LineChart, Series, SeriesLabelPosition};
use crate::report::Report;

/// The tolerances of the "cheapest model" table (m).
const TOLERANCES: [f64; 3] = [10e-3, 1e-3, 0.1e-3];
/// The tolerances of the "fewest modes per kind" table (m): the 2D spin-up beam's errors
/// over 20 s lie between about 1.5 and 11 mm.
const BASIS_TOLERANCES: [f64; 3] = [10e-3, 5e-3, 2e-3];
/// The five bars of the double four-bar made flexible.
const FLEXIBLE_BARS: [&str; 5] = ["crank1", "coupler1", "crank2", "coupler2", "crank3"];

/// One scene of the section: its sweep and how to describe it.
struct Case {
    /// Short name for files (`work_precision_NAME.svg`).
    file: &'static str,
    /// Title of the subsection.
    title: &'static str,
    /// What is judged against what.
    judged: String,
    sweep: Sweep,
    /// The kinds of modes on the grid's basis axis (empty: no basis axis, the lowest).
    bases: Vec<ModeSelection>,
}

/// The grid of a scene: both formulations and inertia routes, the stiffening methods
/// `methods`, the kinds of modes `bases` (none: no such axis, the lowest normal modes), the
/// mode counts `modes` of every flexible beam, the steps `steps`.
fn grid(methods: &[Stiffening], bases: &[ModeSelection], modes: &[usize], steps: &[f64]) -> Grid {
    let mut axes = vec![
        Axis::Formulation(vec![FormulationKind::Absolute, FormulationKind::Relative]),
        Axis::Inertia(vec![InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals]),
        Axis::Stiffening(methods.to_vec()),
    ];
    if !bases.is_empty() {
        axes.push(Axis::Basis {
            body: None,
            kinds: bases.to_vec(),
        });
    }
    axes.push(Axis::Modes {
        body: None,
        counts: modes.to_vec(),
    });
    axes.push(Axis::Step(steps.to_vec()));
    Grid { axes }
}

/// The ANCF cable's tip of the spin-up beam in `dim` (16 elements, h = 1 ms, 20 s, every
/// 0.01 s) as a reference table of the scene's displacement sensors.
fn ancf_reference(dim: Dim) -> Result<ReferenceTable, Box<dyn std::error::Error>> {
    let history = run_spin_up(&CableSpec::spin_up_beam(dim, 16), 1e-3, 20.0, 0.01)?;
    let column = |k: usize| history.tip.iter().map(|p| p[k]).collect::<Vec<f64>>();
    Ok(ReferenceTable::new(
        format!("ANCF cable, 16 elements, {dim:?}"),
        history.t.clone(),
        vec!["tip_ux".into(), "tip_uy".into(), "tip_uz".into()],
        vec![column(0), column(1), column(2)],
    )?)
}

/// The double four-bar with its five bars flexible over `modes` and `steps`, judged on point
/// B against the richest model at a step 8 (`quick`) or 16 times smaller than the grid's.
fn four_bar_sweep(
    modes_bars: &[usize],
    steps: &[f64],
    quick: bool,
) -> Result<Sweep, Box<dyn std::error::Error>> {
    let root = crate::workspace_root();
    let mut bars = Sweep {
        scene: root.join("models/double_four_bar.ron"),
        sets: FLEXIBLE_BARS
            .iter()
            .map(|b| format!("bodies.{b}.flexible=true"))
            .collect(),
        sensors: vec!["B0_x".into(), "B0_y".into()],
        reference: Reference::Converged,
        grid: grid(&[Stiffening::Linear], &[], modes_bars, steps),
        error_cap: None,
    };
    // The grid's richest model at its smallest step is no reference: the mechanism passes
    // its singular configurations (all bars parallel) where the trajectory is sensitive, and
    // h = 1 ms against 0.5 ms differs by millimetres at B over 5 s (not monotonically in h).
    // The reference is that model at a step `refine` times smaller, its margin against half
    // that step reported.
    let mut finer = bars.clone();
    let refine = if quick { 8.0 } else { 16.0 };
    let smallest = steps.iter().copied().fold(f64::INFINITY, f64::min);
    finer.grid = grid(&[Stiffening::Linear], &[], modes_bars, &[smallest / refine]);
    eprintln!(
        "   reference of the double four-bar: h = {:e} s",
        smallest / refine
    );
    let (table, margin) = finer.converged_reference()?;
    bars.reference = Reference::Table(ReferenceTable {
        origin: format!(
            "the richest model of the grid at h = {:e} s (its margin against half that step: {:.1e} m)",
            smallest / refine,
            margin.iter().map(|m| m.max_abs).fold(0.0f64, f64::max)
        ),
        ..table
    });
    Ok(bars)
}

/// The three scenes with their grids (`quick`: a coarse grid).
fn cases(quick: bool) -> Result<Vec<Case>, Box<dyn std::error::Error>> {
    let root = crate::workspace_root();
    let h = 1e-3;
    let steps: Vec<f64> = if quick {
        vec![2.0 * h, h]
    } else {
        vec![2.0 * h, h, h / 2.0]
    };
    let methods: Vec<Stiffening> = if quick {
        vec![Stiffening::Fnl1, Stiffening::Foreshortening]
    } else {
        vec![
            Stiffening::Fnl1,
            Stiffening::Fnl2,
            Stiffening::Foreshortening,
        ]
    };
    let (modes_2d, modes_3d, modes_bars): (Vec<usize>, Vec<usize>, Vec<usize>) = if quick {
        (vec![1, 2, 4], vec![4, 8], vec![1, 2])
    } else {
        (vec![1, 2, 3, 4], vec![2, 4, 6, 8], vec![1, 2, 3])
    };
    // The kinds of modes on the 2D beam; --quick leaves out the participation ranking, which
    // keeps the lowest modes there under FNL1 and FNL2 (the same runs).
    let bases_2d = if quick {
        vec![ModeSelection::LowestFrequency, ModeSelection::LoadRitz]
    } else {
        ModeSelection::ALL.to_vec()
    };
    eprintln!("   references: ANCF cables (2D, 3D), 16 elements");
    let spin_up = |file: &str,
                   sensors: &[&str],
                   reference: ReferenceTable,
                   bases: &[ModeSelection],
                   modes: &[usize]| Sweep {
        scene: root.join("models").join(file),
        sets: Vec::new(),
        sensors: sensors.iter().map(|s| s.to_string()).collect(),
        reference: Reference::Table(reference),
        grid: grid(&methods, bases, modes, &steps),
        error_cap: None,
    };
    let bars = four_bar_sweep(&modes_bars, &steps, quick)?;
    Ok(vec![
        Case {
            file: "spin_up_2d",
            title: "2D spin-up beam (Ωs = 6 rad/s, 20 s)",
            judged: "the tip deflection `tip_uy` against the ANCF cable".into(),
            sweep: spin_up(
                "spin_up_beam_2d.ron",
                &["tip_uy"],
                ancf_reference(Dim::Planar)?,
                &bases_2d,
                &modes_2d,
            ),
            bases: bases_2d.clone(),
        },
        Case {
            file: "spin_up_3d",
            title: "3D spin-up beam (Ωs = 6 rad/s, gravity, 20 s)",
            judged:
                "the tip deflections `tip_uy` and `tip_uz` (the larger) against the 3D ANCF cable"
                    .into(),
            sweep: spin_up(
                "spin_up_beam_3d.ron",
                &["tip_uy", "tip_uz"],
                ancf_reference(Dim::Spatial)?,
                &[],
                &modes_3d,
            ),
            bases: Vec::new(),
        },
        Case {
            file: "double_four_bar",
            title: "Double four-bar, five flexible bars (5 s)",
            judged: "the position of point B (`B0_x`, `B0_y`, the larger); linear elasticity, one \
                 stiffening method"
                .into(),
            sweep: bars,
            bases: Vec::new(),
        },
    ])
}

/// The label of a run's method: formulation, inertia, stiffening.
fn method_of(settings: &[Setting]) -> String {
    let parts: Vec<String> = settings
        .iter()
        .filter_map(|s| match s {
            Setting::Formulation(f) => Some(formulation_name(*f).to_string()),
            Setting::Inertia(i) => Some(inertia_name(*i).to_string()),
            Setting::Stiffening(m) => Some(stiffening_name(*m)),
            _ => None,
        })
        .collect();
    parts.join(" ")
}

/// A method's label without its inertia route: the runs of one colour.
fn colour_key(method: &str) -> String {
    method
        .replace(" b-matrix", "")
        .replace(" shape-integrals", "")
}

/// The chart: per method its own front of (CPU, error) over steps and modes, and the front
/// of all runs.
fn chart(case: &Case, report: &SweepReport, settings: &[Vec<Setting>], path: &Path) -> StudyResult {
    let mut methods: Vec<String> = settings.iter().map(|s| method_of(s)).collect();
    methods.sort();
    methods.dedup();
    let ok = |i: usize| plotted(report, i);
    let front_of = |members: Vec<usize>| front(report, &members);
    // One colour per formulation and stiffening method; the B-matrix route dashed.
    let mut colours: Vec<String> = methods.iter().map(|m| colour_key(m)).collect();
    colours.sort();
    colours.dedup();
    let mut series: Vec<Series> = methods
        .iter()
        .map(|m| Series {
            label: m.clone(),
            points: front_of(
                (0..settings.len())
                    .filter(|&i| ok(i) && method_of(&settings[i]) == *m)
                    .collect(),
            ),
            dashed: m.contains("b-matrix"),
            colour: colours
                .iter()
                .position(|c| *c == colour_key(m))
                .unwrap_or(0),
        })
        .collect();
    series.push(Series {
        label: "Pareto front (all runs)".into(),
        points: front_of((0..settings.len()).filter(|&i| ok(i)).collect()),
        dashed: false,
        colour: 8,
    });
    error_against_cpu(format!("Work–precision: {}", case.title), series).write_svg(path)
}

/// A log–log chart of the largest error over time against the run's CPU time.
fn error_against_cpu(title: String, series: Vec<Series>) -> LineChart {
    LineChart {
        title,
        x_label: "CPU time of the run (s)".into(),
        y_label: "largest error over time (m)".into(),
        log_x: true,
        log_y: true,
        series,
        legend: SeriesLabelPosition::UpperRight,
    }
}

/// Run `i` finished with a positive error (a point of a log–log chart).
fn plotted(report: &SweepReport, i: usize) -> bool {
    report.runs[i].status == RunStatus::Ok && report.runs[i].error > 0.0
}

/// The Pareto front of the runs `members` as (CPU time, error), by CPU time.
fn front(report: &SweepReport, members: &[usize]) -> Vec<(f64, f64)> {
    let points: Vec<(f64, f64)> = members
        .iter()
        .map(|&i| (report.runs[i].error, report.runs[i].cpu_seconds))
        .collect();
    let mut front: Vec<(f64, f64)> = pareto_front(&points)
        .into_iter()
        .map(|k| (points[k].1, points[k].0))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    front
}

/// The kind of modes of a run (the lowest normal modes without a basis axis).
fn basis_of(settings: &[Setting]) -> ModeSelection {
    settings
        .iter()
        .find_map(|s| match s {
            Setting::Basis { kind, .. } => Some(*kind),
            _ => None,
        })
        .unwrap_or_default()
}

/// The mode count of a run.
fn modes_of(settings: &[Setting]) -> Option<usize> {
    settings.iter().find_map(|s| match s {
        Setting::Modes { count, .. } => Some(*count),
        _ => None,
    })
}

/// The chart of the kinds of modes: per kind the front of all its runs (every method,
/// step and mode count).
fn basis_chart(
    case: &Case,
    report: &SweepReport,
    settings: &[Vec<Setting>],
    path: &Path,
) -> StudyResult {
    let series = case
        .bases
        .iter()
        .enumerate()
        .map(|(k, &kind)| Series {
            label: format!("{} modes", basis_name(kind)),
            points: front(
                report,
                &(0..settings.len())
                    .filter(|&i| plotted(report, i) && basis_of(&settings[i]) == kind)
                    .collect::<Vec<_>>(),
            ),
            dashed: false,
            colour: k,
        })
        .collect();
    error_against_cpu(format!("Kind of modes: {}", case.title), series).write_svg(path)
}

/// Per tolerance of [`BASIS_TOLERANCES`] and kind of modes: the fewest modes with which
/// some run of that kind meets the tolerance (that run: the fewest coordinates, then the
/// smallest error).
fn basis_rows(case: &Case, report: &SweepReport, settings: &[Vec<Setting>]) -> Vec<Vec<String>> {
    let mut rows = Vec::new();
    for tolerance in BASIS_TOLERANCES {
        let mut row = vec![mm(tolerance)];
        for &kind in &case.bases {
            let best = (0..settings.len())
                .filter(|&i| {
                    let r = &report.runs[i];
                    r.status == RunStatus::Ok
                        && r.error <= tolerance
                        && basis_of(&settings[i]) == kind
                })
                .min_by(|&a, &b| {
                    let key = |i: usize| (modes_of(&settings[i]), report.runs[i].n_coordinates);
                    key(a)
                        .cmp(&key(b))
                        .then(report.runs[a].error.total_cmp(&report.runs[b].error))
                });
            row.push(best.map_or("none on the grid".into(), |i| {
                let r = &report.runs[i];
                format!(
                    "{}: {} ({:.2} mm, {} coordinates)",
                    match modes_of(&settings[i]) {
                        Some(1) => "1 mode".to_string(),
                        Some(n) => format!("{n} modes"),
                        None => "–".into(),
                    },
                    method_of(&settings[i]),
                    r.error * 1e3,
                    r.n_coordinates.map_or("–".into(), |n| n.to_string())
                )
            }));
        }
        rows.push(row);
    }
    rows
}

/// The kind-of-modes chart and table of a case with a basis axis.
fn basis_section(
    case: &Case,
    report: &SweepReport,
    settings: &[Vec<Setting>],
    out: &mut Report,
) -> StudyResult {
    let file = format!("work_precision_{}_basis.svg", case.file);
    basis_chart(case, report, settings, &out.chart_path(&file))?;
    out.text(&format!(
        "Kind of modes on this beam (docs/methods.md §1.6): {} — the lowest fixed-interface \
         normal modes, the modes the body's inertia and interface loads excite most \
         (participation), load-dependent Ritz vectors of the same loads (ritz). The chart \
         shows per kind the front of all its runs; the table the fewest modes per kind that \
         meet a tolerance, with the run that does. FS0 keeps no axial modes and refuses a \
         basis with axial content: from the third Ritz vector on (the responses to the axial \
         translation and centrifugal loads) those runs are listed as failed.",
        case.bases
            .iter()
            .map(|&k| basis_name(k))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    out.image(&file, &format!("kinds of modes, {}", case.title));
    let mut header = vec!["tolerance".to_string()];
    header.extend(
        case.bases
            .iter()
            .map(|&k| format!("{} modes", basis_name(k))),
    );
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    out.table(&header, &basis_rows(case, report, settings));
    Ok(())
}

/// A tolerance in mm for a reader.
fn mm(x: f64) -> String {
    format!("{} mm", x * 1e3)
}

/// The table row of one tolerance.
fn tolerance_row(tolerance: f64, tuning: &Tuning, report: &SweepReport) -> Vec<String> {
    match &tuning.recommended {
        Some(r) => vec![
            mm(tolerance),
            r.label.clone(),
            format!("{:.3}", r.error * 1e3),
            format!("{:.4}", r.cpu_seconds),
            r.n_coordinates.map_or("–".into(), |n| n.to_string()),
            tuning.runner_up.as_ref().map_or("–".into(), |u| {
                format!(
                    "{} ({:.3} mm, {:.4} s)",
                    u.label,
                    u.error * 1e3,
                    u.cpu_seconds
                )
            }),
        ],
        None => {
            let best = report
                .runs
                .iter()
                .filter(|r| r.status == RunStatus::Ok)
                .map(|r| r.error)
                .fold(f64::INFINITY, f64::min);
            vec![
                mm(tolerance),
                format!("none on the grid (smallest error {:.3} mm)", best * 1e3),
                "–".into(),
                "–".into(),
                "–".into(),
                "–".into(),
            ]
        }
    }
}

/// Run one scene's sweep and append its subsection (the `first` also states the rule of
/// the tables and how the times were measured).
fn run_case(case: &Case, first: bool, report: &mut Report) -> StudyResult {
    eprintln!("   {}", case.title);
    let mut result = case.sweep.run()?;
    let settings = case.sweep.point_settings()?;
    let mut rows = Vec::new();
    let mut rule = String::new();
    for tolerance in TOLERANCES {
        let tuning = tune(&case.sweep, &mut result, tolerance)?;
        rows.push(tolerance_row(tolerance, &tuning, &result));
        rule = tuning.rule;
    }
    let count = |s: RunStatus| result.runs.iter().filter(|r| r.status == s).count();
    report.text(&format!(
        "### {}\n\n{} runs judged on {}; {} ok, {} failed, {} unstable. Reference: {}. Parallel \
         phase: {:.1} s wall on {} threads for {:.1} s of runs.",
        case.title,
        result.runs.len(),
        case.judged,
        count(RunStatus::Ok),
        count(RunStatus::Failed),
        count(RunStatus::Unstable),
        result.reference,
        result.parallel_wall_seconds,
        result.threads,
        result.sum_run_seconds,
    ));
    let file = format!("work_precision_{}.svg", case.file);
    let path = report.chart_path(&file);
    chart(case, &result, &settings, &path)?;
    report.image(&file, &format!("work–precision, {}", case.title));
    if first {
        report.text(&format!(
            "The cheapest model per tolerance follows `flexmbd tune`'s rule: {rule}. {} Each \
             row is reproduced by `flexmbd simulate` with the run's arguments (`flexmbd tune \
             --json` prints them).",
            result.timing
        ));
    }
    report.table(
        &[
            "tolerance",
            "cheapest model",
            "error (mm)",
            "CPU (s)",
            "coordinates",
            "runner-up",
        ],
        &rows,
    );
    if !case.bases.is_empty() {
        basis_section(case, &result, &settings, report)?;
    }
    Ok(())
}

/// Run the study and append its section to the report.
pub fn run(settings: &Settings, report: &mut Report) -> StudyResult {
    report.text(&format!(
        "Error against CPU time for every stiffening method × formulation × inertia route over \
         time steps and mode counts (issue 16; docs/methods.md §10). Each chart shows, per \
         method, the runs no other run of that method beats on both error and CPU time \
         (dashed: B-matrix route), and the Pareto front of all runs. The error of a run is the \
         largest |run − reference| over time on the judged sensors, the reference \
         interpolated linearly to the run's output times. Grid{}: both formulations, both \
         inertia routes, the stiffening methods {}, the modes of every flexible beam {}, \
         on the 2D beam their kind ({}), steps 2h, h{} about h = 1 ms.",
        if settings.quick {
            " (--quick, coarse)"
        } else {
            ""
        },
        if settings.quick {
            "FNL1 and FS0"
        } else {
            "FNL1, FNL2 and FS0"
        },
        if settings.quick {
            "1, 2 and 4 (2D), 4 and 8 (3D), 1 and 2 (bars)"
        } else {
            "1–4 (2D), 2, 4, 6, 8 (3D), 1–3 (bars)"
        },
        if settings.quick {
            "lowest normal modes and load-dependent Ritz vectors"
        } else {
            "lowest normal modes, participation-ranked modes and load-dependent Ritz vectors"
        },
        if settings.quick { "" } else { ", h/2" },
    ));
    for (k, case) in cases(settings.quick)?.iter().enumerate() {
        run_case(case, k == 0, report)?;
    }
    Ok(())
}
