//! The references a sweep computes itself ([`Reference::Converged`],
//! [`Reference::Faithful`]), kept in and read from the reference cache.

use std::sync::atomic::AtomicBool;

use flexmbd_model::{FormulationKind, Scene, Stiffening};

use super::{
    GridPoint, Reference, ReferenceKind, ReferenceTable, SensorError, Setting, Sweep, SweepError,
    cache, faithful,
};

/// How many substructures each flexible beam is split into for the faithful reference of
/// a mechanism (SB8; its error is estimated against SB4).
pub const SUBSTRUCTURES: usize = 8;

/// A sweep's reference and what the report says of it.
pub(super) struct Resolved {
    pub table: ReferenceTable,
    pub label: String,
    pub kind: ReferenceKind,
    pub fallback: Option<String>,
    pub margin: Option<Vec<SensorError>>,
}

impl Resolved {
    /// A reference given by the user: no estimate of its error.
    pub fn given(table: ReferenceTable, label: String, kind: ReferenceKind) -> Resolved {
        Resolved {
            table,
            label,
            kind,
            fallback: None,
            margin: None,
        }
    }
}

impl Sweep {
    /// A reference the sweep computes ([`Reference::Converged`], [`Reference::Faithful`]),
    /// from the cache when it holds it (and whether it did), else computed and kept there.
    pub(super) fn computed_reference(
        &self,
        pristine: &Scene,
        base: &Scene,
        stop: &AtomicBool,
    ) -> Result<(Resolved, bool), SweepError> {
        let faithful = matches!(self.reference, Reference::Faithful);
        let key = match &self.reference_cache {
            Some(_) => {
                let richest = self.grid.richest(base, &self.sensors)?;
                let scene_ron = ron::to_string(base).unwrap_or_default();
                Some(cache::key(
                    if faithful { "faithful" } else { "converged" },
                    &self.sensors,
                    &scene_ron,
                    &richest.args(&self.scene_path(), &self.sets).join(" "),
                    &base.fe_files(),
                ))
            }
            None => None,
        };
        if let (Some(dir), Some(key)) = (&self.reference_cache, &key)
            && let Some(entry) = cache::load(dir, key)
            && let Some(table) = entry.table()
        {
            let resolved = Resolved {
                table,
                label: entry.label,
                kind: entry.kind,
                fallback: entry.fallback,
                margin: entry.margin,
            };
            return Ok((resolved, true));
        }
        let resolved = if faithful {
            self.faithful(pristine, base, stop)?
        } else {
            self.grid_richest(pristine, base, stop)?
        };
        if let (Some(dir), Some(key)) = (&self.reference_cache, &key) {
            let entry = cache::Entry::new(
                key,
                &resolved.table,
                resolved.kind,
                resolved.fallback.clone(),
                resolved.margin.clone(),
            );
            cache::store(dir, &entry);
        }
        Ok((resolved, false))
    }

    /// The most faithful reference for the scene ([`Reference::Faithful`]): the ANCF
    /// cable where it models the scene; else, for a scene with flexible beams, the
    /// substructured model SB[`SUBSTRUCTURES`] (relative formulation) at a quarter of the
    /// grid's smallest step, its error estimated against SB at half as many substructures
    /// and at twice the step; for a scene without
    /// flexible bodies, the scene at an eighth of the grid's smallest step, its error
    /// estimated against a quarter; where none applies (the reason kept), the grid's
    /// richest model at a quarter of its smallest step, its error estimated against twice
    /// that step ([`Sweep::refined_richest`]).
    fn faithful(
        &self,
        pristine: &Scene,
        base: &Scene,
        stop: &AtomicBool,
    ) -> Result<Resolved, SweepError> {
        let why_not_cable = match faithful::reference(base, &self.sensors, stop)? {
            Ok(f) => {
                return Ok(Resolved {
                    table: f.table,
                    label: f.label,
                    kind: ReferenceKind::LargeDeformation,
                    fallback: None,
                    margin: Some(f.margin),
                });
            }
            Err(why) => why,
        };
        let h = self.smallest_step(base)?;
        let flexible: Vec<&flexmbd_model::Body> =
            base.bodies.iter().filter(|b| b.runs_flexible()).collect();
        if flexible.is_empty() {
            let point = |h: f64| GridPoint {
                index: usize::MAX,
                settings: vec![Setting::Step(h)],
            };
            let (table, margin) =
                self.refined(pristine, &point(h / 8.0), &[point(h / 4.0)], stop)?;
            return Ok(Resolved {
                label: table.origin.clone(),
                table,
                kind: ReferenceKind::SmallStep,
                fallback: None,
                margin: Some(margin),
            });
        }
        if let Some(b) = flexible
            .iter()
            .find(|b| !matches!(b.model, flexmbd_model::BodyModel::Beam(_)))
        {
            let why = format!(
                "{why_not_cable}; body `{}` is no beam, which substructuring would split",
                b.name
            );
            return self.refined_richest(pristine, base, stop, why);
        }
        let substructured = |n: usize, h: f64| GridPoint {
            index: usize::MAX,
            settings: vec![
                Setting::Formulation(FormulationKind::Relative),
                Setting::Stiffening(Stiffening::Substructuring(n)),
                Setting::Step(h),
            ],
        };
        let n = SUBSTRUCTURES;
        // Only the judged sensors: substructuring refuses some others (a split beam's modal
        // coordinates).
        let mut judged_only = pristine.clone();
        judged_only
            .sensors
            .retain(|s| self.sensors.contains(&s.name));
        let pristine = &judged_only;
        // The steps are what limits the mechanisms' references (the double four-bar's
        // SB8: 3.6 mm between h = 1 and 0.5 ms, 0.47 mm between SB4 and SB8 at 0.5 ms).
        let coarser = [substructured(n / 2, h / 4.0), substructured(n, h / 2.0)];
        match self.refined(pristine, &substructured(n, h / 4.0), &coarser, stop) {
            Ok((table, margin)) => Ok(Resolved {
                label: table.origin.clone(),
                table,
                kind: ReferenceKind::Substructured,
                fallback: None,
                margin: Some(margin),
            }),
            Err(e @ SweepError::Interrupted { .. }) => Err(e),
            Err(e) => {
                let why = format!("{why_not_cable}; substructured SB{n}: {e}");
                self.refined_richest(pristine, base, stop, why)
            }
        }
    }

    /// The grid's richest model at its smallest step ([`Reference::Converged`]).
    fn grid_richest(
        &self,
        pristine: &Scene,
        base: &Scene,
        stop: &AtomicBool,
    ) -> Result<Resolved, SweepError> {
        let (table, label, margin) = self.converged(pristine, base, stop)?;
        Ok(Resolved {
            table,
            label,
            kind: ReferenceKind::GridRichest,
            fallback: None,
            margin,
        })
    }

    /// Where the faithful reference has no model of another family (`why`): the grid's
    /// richest model at a quarter of its smallest step h, its error estimated against the
    /// same at h/2. Refined in the step as the substructured reference is, so that no run
    /// of the grid is its own reference; its modelling error stays unestimated, which
    /// [`reference_warnings`](super::reference_warnings) says.
    fn refined_richest(
        &self,
        pristine: &Scene,
        base: &Scene,
        stop: &AtomicBool,
        why: String,
    ) -> Result<Resolved, SweepError> {
        let richest = self.grid.richest(base, &self.sensors)?;
        let h = self.smallest_step(base)?;
        let at = |h: f64| {
            let mut point = richest.clone();
            point.index = usize::MAX;
            point.settings.retain(|s| !matches!(s, Setting::Step(_)));
            point.settings.push(Setting::Step(h));
            point
        };
        let (table, margin) = self.refined(pristine, &at(h / 4.0), &[at(h / 2.0)], stop)?;
        Ok(Resolved {
            label: table.origin.clone(),
            table,
            kind: ReferenceKind::GridRichest,
            fallback: Some(why),
            margin: Some(margin),
        })
    }

    /// The grid's smallest step (the scene's when the grid has no step axis).
    fn smallest_step(&self, base: &Scene) -> Result<f64, SweepError> {
        Ok(self
            .grid
            .richest(base, &self.sensors)?
            .settings
            .iter()
            .find_map(|s| match s {
                Setting::Step(h) => Some(*h),
                _ => None,
            })
            .unwrap_or(base.solver.step))
    }

    /// The run of `point` as a reference table, and per judged sensor its largest
    /// difference from each run of `coarser` (its error estimate: the difference from a
    /// less refined run bounds the more refined one's error where the runs converge).
    fn refined(
        &self,
        pristine: &Scene,
        point: &GridPoint,
        coarser: &[GridPoint],
        stop: &AtomicBool,
    ) -> Result<(ReferenceTable, Vec<SensorError>), SweepError> {
        let reference = self.reference_run(pristine, point, stop)?;
        let mut margin: Vec<SensorError> = Vec::new();
        for other in coarser {
            let other = self.reference_run(pristine, other, stop)?;
            let errors = self.measure(&other.t, &other.columns, &reference);
            if margin.is_empty() {
                margin = errors;
            } else {
                for (m, e) in margin.iter_mut().zip(errors) {
                    if e.max_abs > m.max_abs {
                        *m = e;
                    }
                }
            }
        }
        Ok((reference, margin))
    }

    /// The run of `point` as a reference table of the judged sensors, labelled by its
    /// arguments.
    fn reference_run(
        &self,
        pristine: &Scene,
        point: &GridPoint,
        stop: &AtomicBool,
    ) -> Result<ReferenceTable, SweepError> {
        let label = point.args(&self.scene_path(), &self.sets).join(" ");
        let fail = |message: String| SweepError::ReferenceRun {
            label: label.clone(),
            message,
        };
        let outcome = self.execute(pristine, point, stop);
        if outcome.interrupted {
            return Err(SweepError::Interrupted { label });
        }
        if let Some(f) = outcome.failure {
            return Err(fail(f));
        }
        let history = outcome
            .history
            .expect("a run without failure has a history");
        let column = |name: &str| history.column(name).expect("the scene's own sensor");
        let columns = self.sensors.iter().map(|s| column(s)).collect();
        ReferenceTable::new(label.clone(), column("t"), self.sensors.clone(), columns)
            .map_err(|e| fail(e.to_string()))
    }

    /// The richest point at the smallest step, and its convergence margin against the same
    /// at half the step.
    pub(super) fn converged(
        &self,
        pristine: &Scene,
        base: &Scene,
        stop: &AtomicBool,
    ) -> Result<(ReferenceTable, String, Option<Vec<SensorError>>), SweepError> {
        let richest = self.grid.richest(base, &self.sensors)?;
        let h = self.smallest_step(base)?;
        let mut half = richest.clone();
        half.settings.retain(|s| !matches!(s, Setting::Step(_)));
        half.settings.push(Setting::Step(h / 2.0));
        let reference = self.reference_run(pristine, &richest, stop)?;
        let finer = self.reference_run(pristine, &half, stop)?;
        let margin = self.measure(&finer.t, &finer.columns, &reference);
        Ok((reference.clone(), reference.origin.clone(), Some(margin)))
    }
}
