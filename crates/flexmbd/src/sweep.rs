//! Work–precision sweeps: run one scene over a grid of model and solver choices
//! (formulation, inertia route, stiffening method, modes and FE elements per flexible
//! beam, time step), judge every run's sensors against a reference, and find the runs
//! that are cheapest for their accuracy (the Pareto front) or the cheapest that meets a
//! tolerance ([`tune()`]). docs/methods.md §10 states the measures and the rule.
//!
//! A [`Sweep`] is plain data: a scene file, base `--set` overrides, the sensors to judge,
//! a [`Reference`] and a [`Grid`]. Each grid point is exactly the run of `flexmbd simulate`
//! with the point's arguments ([`RunRecord::args`]).
//!
//! Every run records its status (`ok`, `failed` with the error's text, or `unstable`: a
//! non-finite judged value or an error above the cap), per judged sensor the largest
//! absolute difference and the RMS against the reference interpolated linearly to the
//! run's output times ([`reference::error_measures`]), its CPU time and real-time factor.
//!
//! The runs go in parallel over the cores (rayon; the records come back in grid order,
//! whatever the order of completion). A CPU time measured beside other runs only ranks
//! the candidates: the runs on the Pareto front are timed again alone, one after another,
//! and their CPU time is the median of [`RETIME_REPEATS`] such runs
//! ([`RETIME_REPEATS_SHORT`] for a run under [`SHORT_RUN`]; [`RunRecord::timed`] says which
//! time a record holds).
//!
//! [`Sweep::run_or_stop`] looks at a stop flag (Ctrl-C in `flexmbd sweep`) between the
//! steps of every run: once it is set the runs under way end `interrupted`, those not
//! started are not made, and the report holds what finished ([`SweepReport::interrupted`]).

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use flexmbd_model::Scene;
use rayon::prelude::*;
use serde::Serialize;

use crate::simulation;
use computed::Resolved;

mod cache;
mod computed;
mod error;
mod faithful;
pub mod grid;
mod pareto;
pub mod reference;
pub mod tune;

pub use error::SweepError;
pub use grid::{Axis, Grid, GridPoint, Setting, basis_name, parse_basis};
pub use pareto::pareto_front;
pub use reference::{ReferenceTable, SensorError};
pub use tune::{TIMING_TIE, Tuning, structurally_cheaper, tune};

/// How many times a Pareto candidate is run alone to time it (the median is kept), as the
/// report's CPU tables do: 3 times, or [`RETIME_REPEATS_SHORT`] when a run takes less than
/// [`SHORT_RUN`] seconds.
pub const RETIME_REPEATS: usize = 3;
/// Repeats of a short run (a few milliseconds of CPU time are at the mercy of the
/// scheduler).
pub const RETIME_REPEATS_SHORT: usize = 7;
/// A run shorter than this (s of CPU time) is timed [`RETIME_REPEATS_SHORT`] times.
pub const SHORT_RUN: f64 = 0.2;

/// What a sweep judges its runs against.
#[derive(Clone, Debug)]
pub enum Reference {
    /// A CSV file: `t`, then a column per judged sensor (more columns are ignored).
    Csv(PathBuf),
    /// A table in memory (e.g. the ANCF spin-up cable's tip).
    Table(ReferenceTable),
    /// The scene's own converged run: the grid's richest model at its smallest step
    /// ([`Grid::richest`]), run once more at half that step to report its own
    /// convergence margin ([`SweepReport::reference_margin`]).
    Converged,
    /// The most faithful model the project can build for the scene: the large-deformation
    /// ANCF cable where the scene is a beam on a spun-up hub (the spin-up beams), converged
    /// in mesh and step with its error estimated (`sweep/faithful.rs`); a scene with other
    /// flexible beams substructured (SB8 at a quarter of the grid's smallest step, its error
    /// estimated against SB4 and twice the step); a scene without flexible bodies at an eighth of the grid's smallest step;
    /// otherwise [`Reference::Converged`], and the report says why
    /// ([`SweepReport::reference_fallback`]).
    Faithful,
}

/// What kind of reference a sweep was judged against.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ReferenceKind {
    /// A CSV file.
    File,
    /// A table given in memory.
    Table,
    /// The large-deformation solution of [`Reference::Faithful`].
    LargeDeformation,
    /// The grid's richest model ([`Reference::Converged`]: at the grid's smallest step;
    /// the fallback of [`Reference::Faithful`]: at a quarter of it): a model of the runs' own
    /// family.
    GridRichest,
    /// The scene's flexible beams substructured (SB8, relative formulation, a quarter of
    /// the grid's smallest step): a model of large rotations, of another family than the
    /// floating frame's linear ones.
    Substructured,
    /// A scene without flexible bodies at an eighth of the grid's smallest step.
    SmallStep,
}

/// A work–precision sweep: one scene over a grid of choices, judged on some sensors.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The scene file (named in every run's arguments as given).
    pub scene: PathBuf,
    /// `PATH=VALUE` overrides applied to every run, before the grid's.
    pub sets: Vec<String>,
    /// The sensors to judge (at least one, each a sensor of the scene).
    pub sensors: Vec<String>,
    /// The reference.
    pub reference: Reference,
    /// The grid.
    pub grid: Grid,
    /// An error (m, or the sensors' unit) above which a finished run counts as unstable;
    /// `None`: 10 times the largest |reference value| of the judged sensors.
    pub error_cap: Option<f64>,
    /// A folder where a computed reference ([`Reference::Converged`],
    /// [`Reference::Faithful`]) is kept and found again by the next sweep of the same scene
    /// (`sweep/cache.rs` says what the key holds); `None`: computed every time.
    pub reference_cache: Option<PathBuf>,
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    /// Finished, every judged value finite and the error below the cap.
    Ok,
    /// Refused or stopped (the scene variant was refused, a step failed).
    Failed,
    /// Finished, but a judged value is not finite or the error is above the cap.
    Unstable,
    /// Stopped by the sweep's stop flag, or not started once it was set.
    Interrupted,
}

/// Where a record's CPU time comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Timing {
    /// Measured during the parallel sweep, beside other runs: it only ranks candidates.
    InParallel,
    /// The median of [`RETIME_REPEATS`] runs timed alone, one after another
    /// ([`RETIME_REPEATS_SHORT`] for a run under [`SHORT_RUN`]).
    Alone,
}

/// One run of a sweep.
#[derive(Clone, Debug, Serialize)]
pub struct RunRecord {
    /// Position in the grid's order.
    pub index: usize,
    /// The point's settings, e.g. `relative fnl1 modes=3 h=0.001`.
    pub label: String,
    /// The `flexmbd simulate` arguments that reproduce the run, scene path first.
    pub args: Vec<String>,
    /// How the run ended.
    pub status: RunStatus,
    /// Why it failed or is unstable.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Coordinates of the compiled scene (`None` when it did not compile).
    pub n_coordinates: Option<usize>,
    /// Per judged sensor: the largest absolute and the RMS error.
    pub errors: Vec<SensorError>,
    /// The largest of the judged sensors' largest absolute errors (infinite unless ok).
    pub error: f64,
    /// CPU time of the integration (s; preprocessing excluded), see `timed`.
    pub cpu_seconds: f64,
    /// Where `cpu_seconds` comes from.
    pub timed: Timing,
    /// Simulated seconds per CPU second (from `cpu_seconds`).
    pub realtime_factor: f64,
    /// Simulated time reached (s).
    pub simulated_seconds: f64,
    /// Set by [`tune()`] for a candidate that meets the tolerance but was not timed alone:
    /// the index of a timed candidate that differs from it only by a larger step or fewer
    /// modes or elements ([`tune::structurally_cheaper`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub costlier_than: Option<usize>,
}

/// What a sweep found.
#[derive(Clone, Debug, Serialize)]
pub struct SweepReport {
    /// The scene's name.
    pub scene: String,
    /// The judged sensors.
    pub sensors: Vec<String>,
    /// The reference: a file, a label, or the converged run's arguments.
    pub reference: String,
    /// What kind of reference it is.
    pub reference_kind: ReferenceKind,
    /// For [`Reference::Faithful`] on a scene without a large-deformation model: why.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference_fallback: Option<String>,
    /// Wall-clock seconds spent making the reference (reading it from the cache, when it
    /// was there), apart from the runs'.
    pub reference_seconds: f64,
    /// The reference was found in [`Sweep::reference_cache`].
    pub reference_cached: bool,
    /// The reference's own error estimate, per judged sensor: for the grid's richest model
    /// ([`Reference::Converged`]), the largest difference from the same at half its step;
    /// for the large-deformation cable, the larger of its differences from the cable with
    /// twice the elements and at half the step.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference_margin: Option<Vec<SensorError>>,
    /// The error above which a finished run counts as unstable.
    pub error_cap: f64,
    /// Every run, in grid order.
    pub runs: Vec<RunRecord>,
    /// Indices of the runs on the Pareto front of (error, CPU time), every one timed alone.
    pub pareto: Vec<usize>,
    /// How the CPU times were measured.
    pub timing: String,
    /// Worker threads of the parallel phase.
    pub threads: usize,
    /// Wall-clock time of the parallel phase (s).
    pub parallel_wall_seconds: f64,
    /// The wall-clock times of its runs added up (s): about `threads` times the above
    /// when the cores are kept busy.
    pub sum_run_seconds: f64,
    /// The stop flag ended the sweep ([`Sweep::run_or_stop`]): some runs are
    /// [`RunStatus::Interrupted`], and the front is of the finished runs, timed in
    /// parallel (none was timed alone).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub interrupted: bool,
}

/// A sweep checked and ready to run: the scene as loaded, its grid points, the reference.
struct Prepared {
    pristine: Scene,
    points: Vec<grid::GridPoint>,
    reference: ReferenceTable,
    reference_label: String,
    reference_kind: ReferenceKind,
    reference_fallback: Option<String>,
    reference_seconds: f64,
    reference_cached: bool,
    margin: Option<Vec<SensorError>>,
    cap: f64,
}

/// What one run gave, before its record is judged.
struct Outcome {
    summary: Option<simulation::Summary>,
    history: Option<crate::History>,
    failure: Option<String>,
    /// Stopped by the flag, or not started because it was set.
    interrupted: bool,
    wall_seconds: f64,
}

impl Sweep {
    fn scene_path(&self) -> String {
        self.scene.display().to_string()
    }

    /// The arguments of `flexmbd sweep` and `flexmbd tune` (after the command's name) that
    /// make this sweep: the scene, the overrides, the sensors, the grid, the reference
    /// file and the error cap; `None` when the reference is neither a file nor the default
    /// ([`Reference::Faithful`]): a table in memory or [`Reference::Converged`].
    pub fn cli_args(&self) -> Option<Vec<String>> {
        let mut args = vec![self.scene_path()];
        for set in &self.sets {
            args.extend(["--set".into(), set.clone()]);
        }
        args.extend(["--sensor".into(), self.sensors.join(",")]);
        for axis in &self.grid.axes {
            args.extend(["--grid".into(), axis.arg()]);
        }
        match &self.reference {
            Reference::Faithful => {}
            Reference::Csv(path) => {
                args.extend(["--reference".into(), path.display().to_string()]);
            }
            Reference::Table(_) | Reference::Converged => return None,
        }
        if let Some(cap) = self.error_cap {
            args.extend(["--error-cap".into(), format!("{cap}")]);
        }
        Some(args)
    }

    /// Run `point`: build its scene and run it to the scene's duration, or until `stop` is
    /// set (not at all if it is set already).
    fn execute(&self, pristine: &Scene, point: &grid::GridPoint, stop: &AtomicBool) -> Outcome {
        let clock = Instant::now();
        let ended = |failure: String, interrupted: bool| Outcome {
            summary: None,
            history: None,
            failure: Some(failure),
            interrupted,
            wall_seconds: clock.elapsed().as_secs_f64(),
        };
        if stop.load(Ordering::Relaxed) {
            return ended("not run: the sweep was interrupted".into(), true);
        }
        let scene = match point.scene(pristine, &self.sets) {
            Ok(s) => s,
            Err(e) => return ended(e.to_string(), false),
        };
        let mut history = crate::History::default();
        let summary = match simulation::run_into(&scene, &mut history, stop, |_| {}) {
            Ok(s) => s,
            Err(e) => return ended(e.to_string(), false),
        };
        let failure = (summary.status != "ok").then(|| {
            let at = summary
                .failed_at
                .map_or(String::new(), |t| format!("at t = {t} s: "));
            format!(
                "{at}{}",
                summary
                    .message
                    .clone()
                    .unwrap_or_else(|| summary.status.clone())
            )
        });
        Outcome {
            interrupted: summary.status == "interrupted",
            summary: Some(summary),
            history: Some(history),
            failure,
            wall_seconds: clock.elapsed().as_secs_f64(),
        }
    }

    /// The scene as loaded, and with the base overrides applied.
    fn scenes(&self) -> Result<(Scene, Scene), SweepError> {
        let pristine = Scene::load(&self.scene).map_err(|e| SweepError::Scene(Box::new(e)))?;
        let base = grid::GridPoint {
            index: 0,
            settings: Vec::new(),
        }
        .scene(&pristine, &self.sets)?;
        Ok((pristine, base))
    }

    /// The reference [`Reference::Converged`] makes of this sweep's grid — the richest model
    /// at the smallest step ([`Grid::richest`]) — and its convergence margin against the
    /// same at half the step, per judged sensor. For a reference finer than the sweep's
    /// grid, call it on a sweep whose grid holds the finer step and pass the table on as
    /// [`Reference::Table`].
    pub fn converged_reference(&self) -> Result<(ReferenceTable, Vec<SensorError>), SweepError> {
        let (pristine, base) = self.scenes()?;
        self.check_sensors(&base)?;
        let (table, _, margin) = self.converged(&pristine, &base, &simulation::NO_STOP)?;
        Ok((table, margin.unwrap_or_default()))
    }

    /// The judged sensors: at least one, each a sensor of `scene`.
    fn check_sensors(&self, scene: &Scene) -> Result<(), SweepError> {
        if self.sensors.is_empty() {
            return Err(SweepError::NoSensor);
        }
        let known: Vec<&str> = scene.sensors.iter().map(|s| s.name.as_str()).collect();
        if let Some(s) = self.sensors.iter().find(|s| !known.contains(&s.as_str())) {
            return Err(SweepError::UnknownSensor {
                scene: self.scene_path(),
                sensor: s.clone(),
                known: known.join(", "),
            });
        }
        Ok(())
    }

    /// Check the sweep and make its reference: the scene loads with the base overrides,
    /// the sensors are the scene's, the grid is not empty, the reference has every judged
    /// sensor and covers the run.
    fn prepare(&self, stop: &AtomicBool) -> Result<Prepared, SweepError> {
        let (pristine, base) = self.scenes()?;
        self.check_sensors(&base)?;
        let points = self.grid.points(&base, &self.sensors)?;
        let clock = Instant::now();
        let (resolved, reference_cached) = match &self.reference {
            Reference::Csv(path) => {
                let table = ReferenceTable::from_csv(path)?;
                let label = path.display().to_string();
                (Resolved::given(table, label, ReferenceKind::File), false)
            }
            Reference::Table(table) => {
                let label = table.origin.clone();
                (
                    Resolved::given(table.clone(), label, ReferenceKind::Table),
                    false,
                )
            }
            Reference::Converged | Reference::Faithful => {
                self.computed_reference(&pristine, &base, stop)?
            }
        };
        let reference_seconds = clock.elapsed().as_secs_f64();
        let Resolved {
            table: reference,
            label: reference_label,
            kind: reference_kind,
            fallback: reference_fallback,
            margin,
        } = resolved;
        self.check_reference(&reference, &base)?;
        let largest = self
            .sensors
            .iter()
            .map(|s| {
                reference
                    .column(s)
                    .map(|c| c.iter().fold(0.0f64, |m, v| m.max(v.abs())))
            })
            .collect::<Result<Vec<_>, _>>()?
            .into_iter()
            .fold(0.0f64, f64::max);
        let cap = self.error_cap.unwrap_or(if largest > 0.0 {
            10.0 * largest
        } else {
            f64::INFINITY
        });
        Ok(Prepared {
            pristine,
            points,
            reference,
            reference_label,
            reference_kind,
            reference_fallback,
            reference_seconds,
            reference_cached,
            margin,
            cap,
        })
    }

    /// Every judged sensor in `reference`, which spans the base scene's run `[0, duration]`.
    fn check_reference(&self, reference: &ReferenceTable, base: &Scene) -> Result<(), SweepError> {
        for s in &self.sensors {
            reference.column(s)?;
        }
        let (t0, t1) = reference.span();
        let end = base.solver.duration;
        let slack = 1e-9 * end.abs().max(1.0);
        if t0 > slack || t1 < end - slack {
            return Err(SweepError::Reference {
                origin: reference.origin.clone(),
                line: None,
                message: format!(
                    "covers t = {t0} … {t1} s; the runs go from 0 to {end} s (solver.duration)"
                ),
            });
        }
        Ok(())
    }

    /// The error measures of the columns `run` (the judged sensors, at times `t`).
    fn measure(&self, t: &[f64], run: &[Vec<f64>], reference: &ReferenceTable) -> Vec<SensorError> {
        self.sensors
            .iter()
            .zip(run)
            .map(|(s, values)| {
                let ref_values = reference.column(s).expect("checked in prepare");
                let (max_abs, rms) = reference::error_measures(t, values, &reference.t, ref_values)
                    .unwrap_or((f64::INFINITY, f64::INFINITY));
                SensorError {
                    sensor: s.clone(),
                    max_abs,
                    rms,
                }
            })
            .collect()
    }

    /// Judge one run's outcome against the reference.
    fn record(&self, point: &grid::GridPoint, outcome: Outcome, prepared: &Prepared) -> RunRecord {
        let summary = outcome.summary.as_ref();
        let mut record = RunRecord {
            index: point.index,
            label: point.label(),
            args: point.args(&self.scene_path(), &self.sets),
            status: RunStatus::Failed,
            reason: outcome.failure.clone(),
            n_coordinates: summary.map(|s| s.n_coordinates),
            errors: Vec::new(),
            error: f64::INFINITY,
            cpu_seconds: summary.map_or(0.0, |s| s.cpu_seconds),
            timed: Timing::InParallel,
            realtime_factor: summary.map_or(0.0, |s| s.realtime_factor),
            simulated_seconds: summary.map_or(0.0, |s| s.simulated_seconds),
            costlier_than: None,
        };
        if outcome.interrupted {
            record.status = RunStatus::Interrupted;
        }
        if outcome.failure.is_some() {
            return record;
        }
        let history = outcome
            .history
            .expect("a run without failure has a history");
        let t = history.column("t").expect("every history has t");
        let columns: Vec<Vec<f64>> = self
            .sensors
            .iter()
            .map(|s| history.column(s).expect("checked in prepare"))
            .collect();
        record.errors = self.measure(&t, &columns, &prepared.reference);
        let error = record.errors.iter().fold(0.0f64, |m, e| m.max(e.max_abs));
        record.error = error;
        if !error.is_finite() || error > prepared.cap {
            record.status = RunStatus::Unstable;
            record.reason = Some(if error.is_finite() {
                format!("error {error:e} above the cap {:e}", prepared.cap)
            } else {
                "a judged sensor is not finite".into()
            });
            record.error = f64::INFINITY;
        } else {
            record.status = RunStatus::Ok;
        }
        record
    }

    /// Run the sweep: check it, run every grid point in parallel, judge each, and time the
    /// runs of the Pareto front alone.
    pub fn run(&self) -> Result<SweepReport, SweepError> {
        self.run_or_stop(&simulation::NO_STOP)
    }

    /// [`run`](Sweep::run), with `stop` looked at between the steps of every run (the
    /// converged reference's too): set during the reference, the sweep ends with
    /// [`SweepError::Interrupted`]; during the grid, the runs under way end
    /// [`RunStatus::Interrupted`], the others are not made, and the report of what finished
    /// says [`interrupted`](SweepReport::interrupted), its front not timed alone.
    pub fn run_or_stop(&self, stop: &AtomicBool) -> Result<SweepReport, SweepError> {
        let prepared = self.prepare(stop)?;
        let clock = Instant::now();
        let outcomes: Vec<(RunRecord, f64)> = prepared
            .points
            .par_iter()
            .map(|p| {
                let outcome = self.execute(&prepared.pristine, p, stop);
                let wall = outcome.wall_seconds;
                (self.record(p, outcome, &prepared), wall)
            })
            .collect();
        let parallel_wall_seconds = clock.elapsed().as_secs_f64();
        let sum_run_seconds = outcomes.iter().map(|o| o.1).sum();
        let interrupted = outcomes
            .iter()
            .any(|o| o.0.status == RunStatus::Interrupted);
        let mut report = SweepReport {
            scene: prepared.pristine.name.clone(),
            sensors: self.sensors.clone(),
            reference: prepared.reference_label.clone(),
            reference_kind: prepared.reference_kind,
            reference_fallback: prepared.reference_fallback.clone(),
            reference_seconds: prepared.reference_seconds,
            reference_cached: prepared.reference_cached,
            reference_margin: prepared.margin.clone(),
            error_cap: prepared.cap,
            runs: outcomes.into_iter().map(|o| o.0).collect(),
            pareto: Vec::new(),
            timing: format!(
                "CPU times of the integration (preprocessing excluded). Runs marked `alone` \
                 (every run on the Pareto front, and the candidates a tuning compares) are the \
                 median of {RETIME_REPEATS} runs ({RETIME_REPEATS_SHORT} for runs under \
                 {SHORT_RUN} s) timed alone, one after another, after the parallel sweep; the others were measured during the parallel sweep \
                 ({} runs at once) and only rank the candidates.",
                rayon::current_num_threads()
            ),
            threads: rayon::current_num_threads(),
            parallel_wall_seconds,
            sum_run_seconds,
            interrupted,
        };
        if interrupted {
            report.pareto = front_of(&report);
        } else {
            self.settle_front(&mut report)?;
        }
        Ok(report)
    }

    /// Time alone every run on the Pareto front until the front holds only runs timed
    /// alone.
    fn settle_front(&self, report: &mut SweepReport) -> Result<(), SweepError> {
        loop {
            let front = front_of(report);
            let pending: Vec<usize> = front
                .iter()
                .copied()
                .filter(|&i| report.runs[i].timed == Timing::InParallel)
                .collect();
            if pending.is_empty() {
                report.pareto = front;
                return Ok(());
            }
            self.retime(report, &pending)?;
        }
    }

    /// The settings of every grid point, in grid order.
    pub fn point_settings(&self) -> Result<Vec<Vec<Setting>>, SweepError> {
        let (_, base) = self.scenes()?;
        Ok(self
            .grid
            .points(&base, &self.sensors)?
            .into_iter()
            .map(|p| p.settings)
            .collect())
    }

    /// Time the runs `indices` of `report` alone, one after another, [`RETIME_REPEATS`]
    /// times each ([`RETIME_REPEATS_SHORT`] under [`SHORT_RUN`]), and keep the median CPU
    /// time. A run that fails on a repeat (it did not
    /// before) is marked failed.
    pub fn retime(&self, report: &mut SweepReport, indices: &[usize]) -> Result<(), SweepError> {
        let (pristine, base) = self.scenes()?;
        let points = self.grid.points(&base, &self.sensors)?;
        for &i in indices {
            let mut times = Vec::with_capacity(RETIME_REPEATS_SHORT);
            let mut repeats = RETIME_REPEATS;
            while times.len() < repeats {
                let outcome = self.execute(&pristine, &points[i], &simulation::NO_STOP);
                match (outcome.failure, outcome.summary) {
                    (None, Some(s)) => {
                        if s.cpu_seconds < SHORT_RUN {
                            repeats = RETIME_REPEATS_SHORT;
                        }
                        times.push(s.cpu_seconds);
                    }
                    (failure, _) => {
                        let run = &mut report.runs[i];
                        run.status = RunStatus::Failed;
                        run.error = f64::INFINITY;
                        run.reason = failure.or(Some("failed when timed alone".into()));
                        break;
                    }
                }
            }
            let run = &mut report.runs[i];
            run.timed = Timing::Alone;
            if times.len() == repeats {
                times.sort_by(f64::total_cmp);
                run.cpu_seconds = times[repeats / 2];
                run.realtime_factor =
                    run.simulated_seconds / run.cpu_seconds.max(f64::MIN_POSITIVE);
            }
        }
        Ok(())
    }
}

/// The Pareto front of the report's ok runs in (error, CPU time).
fn front_of(report: &SweepReport) -> Vec<usize> {
    let points: Vec<(f64, f64)> = report
        .runs
        .iter()
        .map(|r| match r.status {
            RunStatus::Ok => (r.error, r.cpu_seconds),
            _ => (f64::INFINITY, f64::INFINITY),
        })
        .collect();
    pareto_front(&points)
}
