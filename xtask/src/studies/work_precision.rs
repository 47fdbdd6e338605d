//! Work–precision (issue 16): error against CPU time for every stiffening method ×
//! formulation × inertia route over time steps and mode counts, with the Pareto front, on
//! the 2D and 3D spin-up beams (against the ANCF cable), the double four-bar with its five
//! bars flexible and the Iltis vehicle (scene C) with its beams flexible (each against its
//! own converged run, [`refined_reference`]); on the 2D beam and the vehicle also the kind
//! of modes, with its own chart and table; and per scene the cheapest model for 10 mm, 1 mm
//! and 0.1 mm. Every run is a [`flexmbd::sweep`] grid point, reproducible with `flexmbd
//! simulate` and the arguments the sweep records; the choice of the cheapest model is
//! `flexmbd tune`'s rule ([`flexmbd::sweep::tune()`]).
//!
//! This file holds the scenes, their grids and references and the section's text;
//! [`charts`] the charts, [`tables`] the tables, [`vehicle`] the Iltis vehicle's sweep.

use flexmbd::ancf::{CableSpec, run_spin_up};
use flexmbd::body::InertiaMethod;
use flexmbd::core::Dim;
use flexmbd::fe::ModeSelection;
use flexmbd::model::{FormulationKind, Stiffening};
use flexmbd::sweep::{
    Axis, Grid, Reference, ReferenceTable, RunStatus, Sweep,
    grid::{formulation_name, inertia_name},
    tune,
};

use super::StudyResult;
use crate::Settings;
use crate::report::Report;

mod charts;
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
     work–precision chart above judges every run against a reference at h/8, and there the \
     step's own error (millimetres at h = 1 ms: the margin below; not falling monotonically \
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
/// B against the richest model at a step 8 (`quick`) or 16 times smaller than the grid's.
fn four_bar_sweep(
    modes_bars: &[usize],
    bases: &[ModeSelection],
    steps: &[f64],
    quick: bool,
) -> Result<Sweep, Box<dyn std::error::Error>> {
    let mut bars = four_bar(grid(&[Stiffening::Linear], bases, modes_bars, steps));
    // The grid's richest model at its smallest step is no reference: the mechanism passes
    // its singular configurations (all bars parallel) where the trajectory is sensitive, and
    // h = 1 ms against 0.5 ms differs by millimetres at B over 5 s (not monotonically in h).
    // Nor are the grid's mode counts: a reference of the lowest modes would judge the lowest
    // modes by their step alone and every other kind also by its basis. The lowest
    // REFERENCE_MODES_BARS per bar stand for the converged basis (the lowest 4 differ from
    // them by 0.05 mm over 5 s at h = 1 ms, validation/tests/proper_orthogonal_four_bar.rs).
    let refine = if quick { 8.0 } else { 16.0 };
    refined_reference(
        &mut bars,
        "double four-bar",
        refine,
        RichestModel {
            modes: Some(REFERENCE_MODES_BARS),
            ..RichestModel::default()
        },
    )?;
    Ok(bars)
}

/// What the reference model of [`refined_reference`] takes instead of the grid's richest
/// choice: a formulation and inertia route, and the lowest `modes` normal modes per
/// flexible beam.
#[derive(Clone, Copy, Default)]
struct RichestModel {
    route: Option<(FormulationKind, InertiaMethod)>,
    modes: Option<usize>,
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

/// Judge `sweep` against its grid's richest model ([`Grid::richest`]) at a step `refine`
/// times smaller than the grid's smallest, with its margin against half that step
/// ([`Sweep::converged_reference`]) in the reference's label. `model` overrides the
/// richest model's formulation and inertia route (the grid's first otherwise) and its modes
/// (the grid's most, of the grid's first kind, otherwise).
fn refined_reference(
    sweep: &mut Sweep,
    name: &str,
    refine: f64,
    model: RichestModel,
) -> StudyResult {
    let mut finer = sweep.clone();
    let mut h = f64::NAN;
    for axis in &mut finer.grid.axes {
        match (axis, model.route, model.modes) {
            (Axis::Step(steps), _, _) => {
                h = steps.iter().copied().fold(f64::INFINITY, f64::min) / refine;
                *steps = vec![h];
            }
            (Axis::Formulation(forms), Some((form, _)), _) => *forms = vec![form],
            (Axis::Inertia(routes), Some((_, route)), _) => *routes = vec![route],
            (Axis::Modes { counts, .. }, _, Some(k)) => *counts = vec![k],
            (Axis::Basis { kinds, .. }, _, Some(_)) => {
                *kinds = vec![ModeSelection::LowestFrequency]
            }
            _ => {}
        }
    }
    eprintln!("   reference of the {name}: h = {h:e} s");
    let (table, margin) = finer.converged_reference()?;
    let which = model.route.map_or(String::new(), |(form, route)| {
        format!(" ({}, {})", formulation_name(form), inertia_name(route))
    });
    let reference_model = match model.modes {
        None => format!("the richest model of the grid{which}"),
        Some(k) => format!(
            "the grid's first model{which} with the lowest {k} normal modes per flexible beam"
        ),
    };
    sweep.reference = Reference::Table(ReferenceTable {
        origin: format!(
            "{reference_model} at h = {h:e} s (its margin against half that step: {:.1e} m)",
            margin.iter().map(|m| m.max_abs).fold(0.0f64, f64::max)
        ),
        ..table
    });
    Ok(())
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
        reference_cache: None,
    };
    let bars = four_bar_sweep(&modes_bars, &bases, &steps, quick)?;
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
                "the tip deflection `tip_uy` against the ANCF cable",
                spin_up(
                    "spin_up_beam_2d.ron",
                    &["tip_uy"],
                    ancf_reference(Dim::Planar)?,
                    &bases_2d,
                    &modes_2d,
                ),
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
                "the tip deflections `tip_uy` and `tip_uz` (the larger) against the 3D ANCF \
                 cable",
                spin_up(
                    "spin_up_beam_3d.ron",
                    &["tip_uy", "tip_uz"],
                    ancf_reference(Dim::Spatial)?,
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
