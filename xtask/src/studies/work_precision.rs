//! Work–precision (issue 16): error against CPU time for every stiffening method ×
//! formulation × inertia route over time steps and mode counts, with the Pareto front, on
//! the 2D and 3D spin-up beams, the double four-bar with its five bars flexible and the
//! Iltis vehicle (scene C) with its beams flexible; on every scene also the kind of modes,
//! with its own chart and table; and per scene the cheapest model for 10 mm, 1 mm and
//! 0.1 mm. Each scene is judged against `flexmbd tune`'s default reference, the most
//! faithful model the project has for it ([`Reference::Faithful`]: the ANCF cable for the
//! spin-up beams, the substructured bars for the four-bar, the richest model at a quarter
//! of the step for the vehicle), with its own error estimate, and the choice of the
//! cheapest model is `flexmbd tune`'s ([`flexmbd::sweep::tune()`]), so that each table is
//! what the `flexmbd tune` command printed under it answers (issue 27 item 3). Every run is
//! a [`flexmbd::sweep`] grid point, reproducible with `flexmbd simulate` and the arguments
//! the sweep records.
//!
//! This file holds the scenes, their grids and references and the section's text;
//! [`charts`] the charts, [`tables`] the tables, [`vehicle`] the Iltis vehicle's sweep.

use flexmbd::body::InertiaMethod;
use flexmbd::fe::ModeSelection;
use flexmbd::model::{FormulationKind, Stiffening};
use flexmbd::sweep::{
    Axis, Grid, Reference, ReferenceKind, ReferenceTable, RunStatus, Sweep, SweepReport, tune,
};

use super::StudyResult;
use crate::Settings;
use crate::report::Report;

pub(super) mod charts;
mod tables;
mod vehicle;

use charts::chart;
use tables::{basis_section, tolerance_row};
use vehicle::vehicle_case;

/// The tolerances of the "cheapest model" table (m).
const TOLERANCES: [f64; 3] = [10e-3, 1e-3, 0.1e-3];
/// The tolerances of the "fewest modes per kind" table (m): the 2D spin-up beam's errors
/// over 20 s lie between about 1.5 and 11 mm.
const BASIS_TOLERANCES: [f64; 3] = [10e-3, 5e-3, 2e-3];
/// The lowest normal modes per bar of the double four-bar's reference (`four_bar_sweep`).
const REFERENCE_MODES_BARS: usize = 8;
/// The five bars of the double four-bar made flexible.
const FLEXIBLE_BARS: [&str; 5] = ["crank1", "coupler1", "crank2", "coupler2", "crank3"];
/// The tolerances of the 3D spin-up beam's kinds table (m): its errors over 20 s lie above
/// about 8 mm.
const BASIS_TOLERANCES_3D: [f64; 3] = [20e-3, 10e-3, 5e-3];
/// What the kinds-of-modes section of the spin-up beams adds to the common text.
const SPIN_UP_KINDS_NOTE: &str = "FS0 keeps no axial modes and refuses a basis with axial \
     content: from the third Ritz vector on (the responses to the axial translation and \
     centrifugal loads) those runs are listed as failed.";

/// What the kinds-of-modes section of the double four-bar adds to the common text.
const FOUR_BAR_KINDS_NOTE: &str = "On this scene the kinds are judged on their basis alone: \
     relative coordinates with shape integrals at h = 1 ms, each run against the lowest 8 normal \
     modes per bar at the same step and route (below the table). The \
     work–precision chart above judges every run against the bars substructured at h/4, and \
     there the step's own error (millimetres at h = 1 ms: the margin below; not falling monotonically \
     with h, as the mechanism passes its singular configurations, all bars parallel) is as \
     large as the basis's and the same for every kind.";

/// One scene of the section: its sweep and how to describe it.
struct Case {
    /// Short name for files (`work_precision_NAME.svg`).
    file: &'static str,
    /// Title of the subsection.
    title: String,
    /// What is judged against what.
    judged: String,
    /// What the subsection says of the scene and its grid before the chart (`None`: the
    /// section's introduction says it all).
    note: Option<String>,
    sweep: Sweep,
    /// The kinds of modes on the grid's basis axis (empty: no basis axis, the lowest).
    bases: Vec<ModeSelection>,
    /// The tolerances of the kinds-of-modes table.
    basis_tolerances: &'static [f64],
    /// Where the kinds of modes are compared ("this beam").
    basis_where: &'static str,
    /// What the kinds section adds for this scene (may be empty).
    basis_note: &'static str,
    /// After the kinds table, say how much the modes and the step change the error.
    spreads: bool,
    /// The sweep the kinds table judges instead of `sweep` (`None`: `sweep`'s runs): the
    /// basis alone, against a richer basis at the runs' own step and route.
    basis_sweep: Option<Sweep>,
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

/// The double four-bar with its five bars flexible over `grid`, judged on point B against
/// its own converged run until a reference is set.
fn four_bar(grid: Grid) -> Sweep {
    Sweep {
        scene: crate::workspace_root().join("models/double_four_bar.ron"),
        sets: FLEXIBLE_BARS
            .iter()
            .map(|b| format!("bodies.{b}.flexible=true"))
            .collect(),
        sensors: vec!["B0_x".into(), "B0_y".into()],
        reference: Reference::Converged,
        grid,
        error_cap: None,
        reference_cache: None,
    }
}

/// The double four-bar with its five bars flexible over `modes` and `steps`, judged on point
/// B against `flexmbd tune`'s default reference: the bars substructured (SB8, relative
/// coordinates) at a quarter of the grid's smallest step, its error estimated against SB4
/// and twice the step. The grid's richest model at its smallest step would be no
/// reference: the mechanism passes its singular configurations (all bars parallel) where
/// the trajectory is sensitive to the step (h = 1 ms against 0.5 ms differs by millimetres
/// at B over 5 s, not monotonically in h), and a model of the runs' own family would judge
/// the lowest modes by their step alone.
fn four_bar_sweep(modes_bars: &[usize], bases: &[ModeSelection], steps: &[f64]) -> Sweep {
    Sweep {
        reference: Reference::Faithful,
        ..four_bar(grid(&[Stiffening::Linear], bases, modes_bars, steps))
    }
}

/// The kinds of modes of the double four-bar judged on their basis alone: relative
/// coordinates, shape integrals, the scene's step h, `modes_bars` of every kind in `bases`,
/// against the lowest [`REFERENCE_MODES_BARS`] per bar at the same h and route (their margin
/// against h/2 in the label), so that the step's own error, the same for every kind, does
/// not hide the basis's.
fn four_bar_basis_sweep(
    modes_bars: &[usize],
    bases: &[ModeSelection],
    h: f64,
) -> Result<Sweep, Box<dyn std::error::Error>> {
    let axes = |bases: &[ModeSelection], modes: &[usize]| Grid {
        axes: vec![
            Axis::Formulation(vec![FormulationKind::Relative]),
            Axis::Inertia(vec![InertiaMethod::ShapeIntegrals]),
            Axis::Stiffening(vec![Stiffening::Linear]),
            Axis::Basis {
                body: None,
                kinds: bases.to_vec(),
            },
            Axis::Modes {
                body: None,
                counts: modes.to_vec(),
            },
            Axis::Step(vec![h]),
        ],
    };
    let mut alone = four_bar(axes(
        &[ModeSelection::LowestFrequency],
        &[REFERENCE_MODES_BARS],
    ));
    eprintln!(
        "   reference of the four-bar's kinds: the lowest {REFERENCE_MODES_BARS} modes, h = {h:e} s"
    );
    let (table, margin) = alone.converged_reference()?;
    alone.reference = Reference::Table(ReferenceTable {
        origin: format!(
            "the lowest {REFERENCE_MODES_BARS} normal modes per bar in relative coordinates \
             with shape integrals at h = {h:e} s, the runs' own (its margin against half that \
             step, the same for every kind and left out of the comparison: {:.1e} m)",
            margin.iter().map(|m| m.max_abs).fold(0.0f64, f64::max)
        ),
        ..table
    });
    alone.grid = axes(bases, modes_bars);
    Ok(alone)
}

/// The four scenes with their grids (`quick`: a coarse grid).
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
    // The kinds of modes on every scene; --quick leaves out the participation ranking, which
    // keeps the lowest modes on every scene of the section (the same runs).
    let bases = if quick {
        vec![
            ModeSelection::LowestFrequency,
            ModeSelection::LoadRitz,
            ModeSelection::ProperOrthogonal,
        ]
    } else {
        ModeSelection::ALL.to_vec()
    };
    let bases_2d = bases.clone();
    let spin_up = |file: &str, sensors: &[&str], bases: &[ModeSelection], modes: &[usize]| Sweep {
        scene: root.join("models").join(file),
        sets: Vec::new(),
        sensors: sensors.iter().map(|s| s.to_string()).collect(),
        reference: Reference::Faithful,
        grid: grid(&methods, bases, modes, &steps),
        error_cap: None,
        reference_cache: None,
    };
    let bars = four_bar_sweep(&modes_bars, &bases, &steps);
    let modes_bars_alone: Vec<usize> = if quick {
        vec![1, 2, 3]
    } else {
        vec![1, 2, 3, 4]
    };
    let bars_alone = four_bar_basis_sweep(&modes_bars_alone, &bases, h)?;
    Ok(vec![
        Case {
            bases: bases_2d.clone(),
            basis_tolerances: &BASIS_TOLERANCES,
            basis_where: "this beam",
            basis_note: SPIN_UP_KINDS_NOTE,
            ..Case::plain(
                "spin_up_2d",
                "2D spin-up beam (Ωs = 6 rad/s, 20 s)",
                "the tip deflection `tip_uy`",
                spin_up("spin_up_beam_2d.ron", &["tip_uy"], &bases_2d, &modes_2d),
            )
        },
        Case {
            bases: bases.clone(),
            basis_tolerances: &BASIS_TOLERANCES_3D,
            basis_where: "this beam",
            basis_note: SPIN_UP_KINDS_NOTE,
            ..Case::plain(
                "spin_up_3d",
                "3D spin-up beam (Ωs = 6 rad/s, gravity, 20 s)",
                "the tip deflections `tip_uy` and `tip_uz` (the larger)",
                spin_up(
                    "spin_up_beam_3d.ron",
                    &["tip_uy", "tip_uz"],
                    &bases,
                    &modes_3d,
                ),
            )
        },
        Case {
            bases: bases.clone(),
            basis_tolerances: &TOLERANCES,
            basis_where: "the five bars",
            basis_note: FOUR_BAR_KINDS_NOTE,
            basis_sweep: Some(bars_alone),
            ..Case::plain(
                "double_four_bar",
                "Double four-bar, five flexible bars (5 s)",
                "the position of point B (`B0_x`, `B0_y`, the larger); linear elasticity, one \
                 stiffening method",
                bars,
            )
        },
        vehicle_case(quick, &steps)?,
    ])
}

impl Case {
    /// A scene without a note or a basis axis.
    fn plain(file: &'static str, title: &str, judged: &str, sweep: Sweep) -> Case {
        Case {
            file,
            title: title.into(),
            judged: judged.into(),
            note: None,
            sweep,
            bases: Vec::new(),
            basis_tolerances: &BASIS_TOLERANCES,
            basis_where: "",
            basis_note: "",
            spreads: false,
            basis_sweep: None,
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
    let mut warnings: Vec<String> = Vec::new();
    for tolerance in TOLERANCES {
        let tuning = tune(&case.sweep, &mut result, tolerance)?;
        rows.push(tolerance_row(tolerance, &tuning, &result));
        rule = tuning.rule;
        for w in tuning.warnings {
            if !warnings.contains(&w) {
                warnings.push(w);
            }
        }
    }
    let count = |s: RunStatus| result.runs.iter().filter(|r| r.status == s).count();
    report.text(&format!(
        "### {}\n\n{} runs judged on {}; {} ok, {} failed, {} unstable. {} Parallel \
         phase: {:.1} s wall on {} threads for {:.1} s of runs.",
        case.title,
        result.runs.len(),
        case.judged,
        count(RunStatus::Ok),
        count(RunStatus::Failed),
        count(RunStatus::Unstable),
        reference_text(&result),
        result.parallel_wall_seconds,
        result.threads,
        result.sum_run_seconds,
    ));
    let file = format!("work_precision_{}.svg", case.file);
    let path = report.chart_path(&file);
    chart(case, &result, &settings, &path)?;
    if let Some(note) = &case.note {
        report.text(note);
    }
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
    report.text(&tune_text(&case.sweep, &warnings));
    match (&case.basis_sweep, case.bases.is_empty()) {
        (_, true) => {}
        (None, false) => basis_section(case, &result, &settings, report)?,
        (Some(alone), false) => {
            eprintln!("   {}: the kinds of modes alone", case.title);
            let result = alone.run()?;
            basis_section(case, &result, &alone.point_settings()?, report)?;
            report.text(&format!(
                "Reference of this kinds table: {}.",
                result.reference
            ));
        }
    }
    Ok(())
}

/// What a sweep was judged against: `flexmbd tune`'s default reference, its kind, its own
/// error estimate and its cost.
fn reference_text(result: &SweepReport) -> String {
    let kind = match result.reference_kind {
        ReferenceKind::LargeDeformation => "the large-deformation ANCF cable",
        ReferenceKind::Substructured => "the flexible beams substructured",
        ReferenceKind::SmallStep => "the scene at a far smaller step",
        ReferenceKind::GridRichest => "the grid's richest model at a smaller step",
        ReferenceKind::File | ReferenceKind::Table => "a given table",
    };
    let bound = result
        .reference_margin
        .iter()
        .flatten()
        .map(|m| m.max_abs)
        .fold(0.0f64, f64::max);
    format!(
        "Reference (`flexmbd tune`'s default, the most faithful model the project has for the \
         scene): {kind}, `{}`; its own error estimate {:.4} mm (its difference from the same \
         model less refined), which a run's error must leave room for; made in {:.1} s apart \
         from the runs.",
        result.reference.replace(&root_prefix(), ""),
        bound * 1e3,
        result.reference_seconds,
    )
}

/// The workspace root as it starts the sweeps' scene paths, to print them relative.
fn root_prefix() -> String {
    format!("{}/", crate::workspace_root().display())
}

/// The `flexmbd tune` command whose answers the table above gives, and the warnings tune
/// prints with them.
fn tune_text(sweep: &Sweep, warnings: &[String]) -> String {
    let args = sweep
        .cli_args()
        .expect("the section's sweeps take tune's default reference")
        .join(" ")
        .replace(&root_prefix(), "");
    let mut text = format!(
        "Each row is `flexmbd tune {args} --tolerance X` (X in metres), which gives the same \
         run."
    );
    for w in warnings {
        text.push_str(&format!(
            " Warning from tune: {}.",
            w.replace(&root_prefix(), "")
        ));
    }
    text
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
         their kind ({}), steps 2h, h{} about h = 1 ms. The automatic choices of modes \
         (the participation ranking, the Ritz vectors, the proper orthogonal modes of a pilot \
         run) are judged against the lowest normal modes in each scene's kinds table: the \
         fewest coordinates that meet a tolerance, per kind. The proper orthogonal modes' \
         pilot run (the scene itself on the lowest max(2n, 4) modes, to its end) is part of \
         preparing the scene, so its time is preprocessing, outside the CPU times charted.",
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
            "lowest normal modes, load-dependent Ritz vectors and proper orthogonal modes; \
             not the participation ranking, which keeps the lowest modes on every scene"
        } else {
            "lowest normal modes, participation-ranked modes, load-dependent Ritz vectors and \
             proper orthogonal modes"
        },
        if settings.quick { "" } else { ", h/2" },
    ));
    for (k, case) in cases(settings.quick)?.iter().enumerate() {
        run_case(case, k == 0, report)?;
    }
    Ok(())
}
