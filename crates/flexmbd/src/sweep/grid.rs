//! The grid of a sweep: axes of model and solver choices, their Cartesian product in a
//! fixed order (the last axis varies fastest), and each grid point as the `flexmbd
//! simulate` arguments that reproduce it — formulation, inertia route and stiffening as
//! the named options, modes, their kind (basis), elements and step as `--set PATH=VALUE`
//! overrides — applied to a scene exactly as the command line applies them.
//!
//! A new kind of axis is one more [`Axis`] variant with its [`Setting`]: its arguments
//! and how it changes the scene.

use flexmbd_body::{InertiaMethod, InertiaTerms};
use flexmbd_fe::ModeSelection;
use flexmbd_model::{BodyModel, FormulationKind, Scene, Stiffening, parse_set};

use super::SweepError;

/// One axis of a sweep's grid: the values one model or solver choice takes.
#[derive(Clone, Debug, PartialEq)]
pub enum Axis {
    /// Natural (absolute) or relative coordinates.
    Formulation(Vec<FormulationKind>),
    /// The inertia route of the flexible bodies.
    Inertia(Vec<InertiaMethod>),
    /// The geometric stiffening method.
    Stiffening(Vec<Stiffening>),
    /// Fixed-interface normal modes (`normal_modes`) of the beam body `body`, or of every
    /// flexible beam body of the scene when `body` is `None`.
    Modes {
        /// The body, or every flexible beam body.
        body: Option<String>,
        /// The counts; 0 keeps the static modes alone (a body model may refuse more
        /// modes than its interior DOFs, and the run is then listed as failed).
        counts: Vec<usize>,
    },
    /// The kind of dynamic vectors (`mode_selection`, docs/methods.md §1.6) of the beam
    /// body `body`, or of every flexible beam body when `None`; `normal_modes` still
    /// counts them.
    Basis {
        /// The body, or every flexible beam body.
        body: Option<String>,
        /// The kinds.
        kinds: Vec<ModeSelection>,
    },
    /// FE elements per polyline segment (`geometry.elements_per_segment`) of the beam
    /// body `body`, or of every flexible beam body when `None`.
    Elements {
        /// The body, or every flexible beam body.
        body: Option<String>,
        /// The counts, each at least 1.
        counts: Vec<usize>,
    },
    /// The inertia terms kept (`inertia_terms`, issue 31) by the flexible beam body `body`,
    /// or by every flexible beam body when `None`; values are [`InertiaTerms::label`]s
    /// (`full`, `o1`, `o0-nc`, ...).
    Terms {
        /// The body, or every flexible beam body.
        body: Option<String>,
        /// The choices.
        terms: Vec<InertiaTerms>,
    },
    /// The inertia terms chosen to meet a tolerance (`terms[.BODY]=auto@X,…`, docs/design.md
    /// "Inertia terms by weight"): over one pilot run of the sweep's scene with every term
    /// kept, the flexible beam bodies (or `body`) take the first rung of the weights' ladder
    /// whose run moves the sweep's judged sensors by at most X of their range over the
    /// pilot ([`crate::term_weights::Pilot::confirm`]). The choice is made once, for the
    /// scene as the sweep gets it, and the same terms are set at every point of the grid.
    AutoTerms {
        /// The body, or every flexible beam body.
        body: Option<String>,
        /// The thresholds X, each in (0, 1).
        thresholds: Vec<f64>,
    },
    /// The time step h (s).
    Step(Vec<f64>),
}

/// What one grid point sets on one axis.
#[derive(Clone, Debug, PartialEq)]
pub enum Setting {
    /// `--formulation`.
    Formulation(FormulationKind),
    /// `--inertia`.
    Inertia(InertiaMethod),
    /// `--stiffening`.
    Stiffening(Stiffening),
    /// `--set bodies.BODY.model.Beam.normal_modes=N`, one per body.
    Modes {
        /// The bodies.
        bodies: Vec<String>,
        /// The count.
        count: usize,
    },
    /// `--set bodies.BODY.model.Beam.mode_selection=KIND`, one per body.
    Basis {
        /// The bodies.
        bodies: Vec<String>,
        /// The kind.
        kind: ModeSelection,
    },
    /// `--set bodies.BODY.model.Beam.geometry.elements_per_segment=N`, one per body.
    Elements {
        /// The bodies.
        bodies: Vec<String>,
        /// The count.
        count: usize,
    },
    /// `--set bodies.BODY.inertia_terms.{order,velocity,coupling}=…`, per body.
    Terms {
        /// The bodies.
        bodies: Vec<String>,
        /// The choice.
        terms: InertiaTerms,
    },
    /// The terms chosen at tolerance `threshold` ([`Axis::AutoTerms`]):
    /// `--set bodies.BODY.inertia_terms.{order,velocity,coupling}=…` for each body's choice.
    ChosenTerms {
        /// The tolerance.
        threshold: f64,
        /// Each body and its choice.
        choices: Vec<(String, InertiaTerms)>,
        /// The choice's error against the full model over the pilot, on the sweep's
        /// judged sensors (largest |Δ| over the sensor's range,
        /// [`crate::term_weights::Trial::error`]).
        pilot_error: f64,
    },
    /// `--set solver.step=H`.
    Step(f64),
}

/// `--set bodies.BODY.inertia_terms.{order,velocity,coupling}=…` for `terms` on `body`.
fn terms_args(body: &str, terms: &InertiaTerms) -> Vec<String> {
    let path = |f: &str| format!("bodies.{body}.inertia_terms.{f}");
    let set = |path: String, value: String| vec!["--set".to_string(), format!("{path}={value}")];
    [
        set(path("order"), terms.order.to_string()),
        set(path("velocity"), terms.velocity.to_string()),
        set(path("coupling"), terms.coupling.to_string()),
    ]
    .concat()
}

/// The name of a formulation on the command line.
pub fn formulation_name(f: FormulationKind) -> &'static str {
    match f {
        FormulationKind::Absolute => "absolute",
        FormulationKind::Relative => "relative",
    }
}

/// The name of an inertia route on the command line.
pub fn inertia_name(i: InertiaMethod) -> &'static str {
    match i {
        InertiaMethod::BMatrix => "b-matrix",
        InertiaMethod::ShapeIntegrals => "shape-integrals",
    }
}

/// The name of a mode selection on a `basis` axis: `lowest`, `participation`, `ritz`,
/// `pod`.
pub fn basis_name(m: ModeSelection) -> &'static str {
    match m {
        ModeSelection::LowestFrequency => "lowest",
        ModeSelection::Participation => "participation",
        ModeSelection::LoadRitz => "ritz",
        ModeSelection::ProperOrthogonal => "pod",
    }
}

/// The mode selection a `basis` axis names (see [`basis_name`]).
pub fn parse_basis(name: &str) -> Option<ModeSelection> {
    ModeSelection::ALL
        .into_iter()
        .find(|&m| basis_name(m) == name)
}

/// The name of a stiffening method on the command line (`--stiffening`).
pub fn stiffening_name(s: Stiffening) -> String {
    match s {
        Stiffening::Linear => "linear".into(),
        Stiffening::Fnl1 => "fnl1".into(),
        Stiffening::Fnl2 => "fnl2".into(),
        Stiffening::Foreshortening => "foreshortening".into(),
        Stiffening::Substructuring(n) => format!("substructuring:{n}"),
    }
}

impl Setting {
    /// The `flexmbd simulate` arguments that make this choice.
    pub fn args(&self) -> Vec<String> {
        let set = |path: String, value: String| vec!["--set".into(), format!("{path}={value}")];
        match self {
            Setting::Formulation(f) => vec!["--formulation".into(), formulation_name(*f).into()],
            Setting::Inertia(i) => vec!["--inertia".into(), inertia_name(*i).into()],
            Setting::Stiffening(s) => vec!["--stiffening".into(), stiffening_name(*s)],
            Setting::Modes { bodies, count } => bodies
                .iter()
                .flat_map(|b| {
                    set(
                        format!("bodies.{b}.model.Beam.normal_modes"),
                        count.to_string(),
                    )
                })
                .collect(),
            Setting::Basis { bodies, kind } => bodies
                .iter()
                .flat_map(|b| {
                    set(
                        format!("bodies.{b}.model.Beam.mode_selection"),
                        kind.name().into(),
                    )
                })
                .collect(),
            Setting::Elements { bodies, count } => bodies
                .iter()
                .flat_map(|b| {
                    set(
                        format!("bodies.{b}.model.Beam.geometry.elements_per_segment"),
                        count.to_string(),
                    )
                })
                .collect(),
            Setting::Terms { bodies, terms } => {
                bodies.iter().flat_map(|b| terms_args(b, terms)).collect()
            }
            Setting::ChosenTerms { choices, .. } => choices
                .iter()
                .flat_map(|(b, terms)| terms_args(b, terms))
                .collect(),
            // `{}` prints the shortest text that reads back as the same f64.
            Setting::Step(h) => set("solver.step".into(), format!("{h}")),
        }
    }

    /// A short label: `relative`, `fnl1`, `modes=3`, `basis=ritz`, `h=0.0005`.
    pub fn label(&self) -> String {
        match self {
            Setting::Formulation(f) => formulation_name(*f).into(),
            Setting::Inertia(i) => inertia_name(*i).into(),
            Setting::Stiffening(s) => stiffening_name(*s),
            Setting::Modes { count, .. } => format!("modes={count}"),
            Setting::Basis { kind, .. } => format!("basis={}", basis_name(*kind)),
            Setting::Elements { count, .. } => format!("elements={count}"),
            Setting::Terms { terms, .. } => format!("terms={terms}"),
            Setting::ChosenTerms {
                threshold,
                choices,
                pilot_error,
            } => {
                let chosen: Vec<String> = choices.iter().map(|(_, t)| t.label()).collect();
                format!(
                    "terms=auto@{threshold}({};pilot={pilot_error:.1e})",
                    chosen.join(",")
                )
            }
            Setting::Step(h) => format!("h={h}"),
        }
    }

    /// The `--set` overrides of this choice (`PATH=VALUE`).
    fn sets(&self) -> Vec<String> {
        let args = self.args();
        if args.first().map(String::as_str) == Some("--set") {
            args.into_iter().skip(1).step_by(2).collect()
        } else {
            Vec::new()
        }
    }

    /// Apply a named option (formulation, inertia, stiffening) to the solver settings, as
    /// `flexmbd simulate` does after the `--set` overrides.
    fn apply_option(&self, scene: &mut Scene) {
        match self {
            Setting::Formulation(f) => scene.solver.formulation = *f,
            Setting::Inertia(i) => scene.solver.inertia = *i,
            Setting::Stiffening(s) => scene.solver.stiffening = *s,
            _ => {}
        }
    }
}

/// One point of a grid: its index in the grid's order and one setting per axis.
#[derive(Clone, Debug, PartialEq)]
pub struct GridPoint {
    /// Position in the grid's order (the last axis varies fastest).
    pub index: usize,
    /// One per axis, in the grid's axis order.
    pub settings: Vec<Setting>,
}

impl GridPoint {
    /// The settings' labels joined by spaces.
    pub fn label(&self) -> String {
        let labels: Vec<String> = self.settings.iter().map(Setting::label).collect();
        labels.join(" ")
    }

    /// The scene at `scene_path` loaded afresh (`pristine`) with the base overrides `sets`
    /// and this point's `--set` overrides applied in one pass, then its named options, then
    /// validated: what `flexmbd simulate SCENE` with [`GridPoint::args`] runs.
    pub fn scene(&self, pristine: &Scene, sets: &[String]) -> Result<Scene, SweepError> {
        let mut scene = pristine.clone();
        let all: Vec<String> = sets
            .iter()
            .cloned()
            .chain(self.settings.iter().flat_map(Setting::sets))
            .collect();
        let parsed = all
            .iter()
            .map(|s| parse_set(s))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| SweepError::Scene(Box::new(e)))?;
        scene
            .apply_sets(&parsed)
            .map_err(|e| SweepError::Scene(Box::new(e)))?;
        for s in &self.settings {
            s.apply_option(&mut scene);
        }
        scene
            .validate()
            .map_err(|e| SweepError::Scene(Box::new(e)))?;
        Ok(scene)
    }

    /// The `flexmbd simulate` arguments that reproduce this point: the scene path, the
    /// base overrides `sets`, then this point's settings.
    pub fn args(&self, scene_path: &str, sets: &[String]) -> Vec<String> {
        std::iter::once(scene_path.to_string())
            .chain(sets.iter().flat_map(|s| ["--set".to_string(), s.clone()]))
            .chain(self.settings.iter().flat_map(Setting::args))
            .collect()
    }
}

/// The axes of a sweep; their Cartesian product is the set of runs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Grid {
    /// The axes, in the order of the points' settings.
    pub axes: Vec<Axis>,
}

/// The flexible beam bodies of a scene, by name.
pub fn flexible_beams(scene: &Scene) -> Vec<String> {
    scene
        .bodies
        .iter()
        .filter(|b| b.flexible && matches!(b.model, BodyModel::Beam(_)))
        .map(|b| b.name.clone())
        .collect()
}

impl Axis {
    /// The axis's name in messages and on the command line (`--grid NAME=…`).
    pub fn name(&self) -> &'static str {
        match self {
            Axis::Formulation(_) => "formulation",
            Axis::Inertia(_) => "inertia",
            Axis::Stiffening(_) => "stiffening",
            Axis::Modes { .. } => "modes",
            Axis::Basis { .. } => "basis",
            Axis::Elements { .. } => "elements",
            Axis::Terms { .. } | Axis::AutoTerms { .. } => "terms",
            Axis::Step(_) => "step",
        }
    }

    /// The axis as `flexmbd sweep`/`tune` take it: the value of `--grid NAME=V1,V2,...`
    /// (`modes.BODY=…` for one body).
    pub fn arg(&self) -> String {
        fn list<T>(values: &[T], name: impl Fn(&T) -> String) -> String {
            values.iter().map(name).collect::<Vec<_>>().join(",")
        }
        let named = |body: &Option<String>| match body {
            Some(b) => format!("{}.{b}", self.name()),
            None => self.name().to_string(),
        };
        let (name, values) = match self {
            Axis::Formulation(v) => (named(&None), list(v, |f| formulation_name(*f).into())),
            Axis::Inertia(v) => (named(&None), list(v, |i| inertia_name(*i).into())),
            Axis::Stiffening(v) => (named(&None), list(v, |s| stiffening_name(*s))),
            Axis::Modes { body, counts } | Axis::Elements { body, counts } => {
                (named(body), list(counts, usize::to_string))
            }
            Axis::Basis { body, kinds } => (named(body), list(kinds, |k| basis_name(*k).into())),
            Axis::Terms { body, terms } => (named(body), list(terms, InertiaTerms::label)),
            Axis::AutoTerms { body, thresholds } => {
                (named(body), list(thresholds, |t| format!("auto@{t}")))
            }
            // `{}` prints the shortest text that reads back as the same f64.
            Axis::Step(v) => (named(&None), list(v, |h| format!("{h}"))),
        };
        format!("{name}={values}")
    }

    fn len(&self) -> usize {
        match self {
            Axis::Formulation(v) => v.len(),
            Axis::Inertia(v) => v.len(),
            Axis::Stiffening(v) => v.len(),
            Axis::Modes { counts, .. } | Axis::Elements { counts, .. } => counts.len(),
            Axis::Basis { kinds, .. } => kinds.len(),
            Axis::Terms { terms, .. } => terms.len(),
            Axis::AutoTerms { thresholds, .. } => thresholds.len(),
            Axis::Step(v) => v.len(),
        }
    }

    /// The beam bodies a modes, basis or elements axis changes, checked against `scene`.
    fn bodies(&self, body: &Option<String>, scene: &Scene) -> Result<Vec<String>, SweepError> {
        let beams = flexible_beams(scene);
        let bad = |message: String| SweepError::Grid {
            axis: self.name().into(),
            message,
        };
        match body {
            None if beams.is_empty() => Err(bad(format!(
                "scene `{}` has no flexible beam body",
                scene.name
            ))),
            None => Ok(beams),
            Some(b) if beams.contains(b) => Ok(vec![b.clone()]),
            Some(b) => Err(bad(format!(
                "`{b}` is not a flexible beam body of scene `{}` (flexible beams: {})",
                scene.name,
                beams.join(", ")
            ))),
        }
    }

    /// The settings of this axis for `scene`, checked: at least one value, element counts
    /// at least 1, steps positive and finite, bodies that are flexible beams; the terms
    /// chosen by their weights are confirmed on the sensors `judged` (none named: every
    /// sensor but the energy).
    fn settings(&self, scene: &Scene, judged: &[String]) -> Result<Vec<Setting>, SweepError> {
        let bad = |message: String| SweepError::Grid {
            axis: self.name().into(),
            message,
        };
        if self.len() == 0 {
            return Err(bad("no values: an axis needs at least one".into()));
        }
        let elements = |counts: &[usize]| match counts.iter().find(|&&n| n == 0) {
            Some(_) => Err(bad("0 is not a count: at least 1".into())),
            None => Ok(()),
        };
        Ok(match self {
            Axis::Formulation(v) => v.iter().map(|&f| Setting::Formulation(f)).collect(),
            Axis::Inertia(v) => v.iter().map(|&i| Setting::Inertia(i)).collect(),
            Axis::Stiffening(v) => {
                if v.contains(&Stiffening::Substructuring(0)) {
                    return Err(bad("substructuring:0: N must be at least 1".into()));
                }
                v.iter().map(|&s| Setting::Stiffening(s)).collect()
            }
            Axis::Modes { body, counts: c } => {
                let bodies = self.bodies(body, scene)?;
                c.iter()
                    .map(|&count| Setting::Modes {
                        bodies: bodies.clone(),
                        count,
                    })
                    .collect()
            }
            Axis::Basis { body, kinds } => {
                let bodies = self.bodies(body, scene)?;
                kinds
                    .iter()
                    .map(|&kind| Setting::Basis {
                        bodies: bodies.clone(),
                        kind,
                    })
                    .collect()
            }
            Axis::Elements { body, counts: c } => {
                elements(c)?;
                let bodies = self.bodies(body, scene)?;
                c.iter()
                    .map(|&count| Setting::Elements {
                        bodies: bodies.clone(),
                        count,
                    })
                    .collect()
            }
            Axis::Terms { body, terms } => {
                let bodies = self.bodies(body, scene)?;
                terms
                    .iter()
                    .map(|&terms| Setting::Terms {
                        bodies: bodies.clone(),
                        terms,
                    })
                    .collect()
            }
            Axis::AutoTerms { body, thresholds } => {
                if let Some(t) = thresholds.iter().find(|t| !(**t > 0.0 && **t < 1.0)) {
                    return Err(bad(format!("auto@{t}: a threshold must be in (0, 1)")));
                }
                let bodies = self.bodies(body, scene)?;
                let pilot = crate::term_weights::cached_pilot(scene, judged).map_err(|e| {
                    bad(format!(
                        "the pilot run that weighs the inertia terms failed: {e}"
                    ))
                })?;
                let mut settings = Vec::new();
                for &threshold in thresholds {
                    let choice = pilot
                        .confirm(threshold, Some(&bodies))
                        .map_err(|e| bad(e.to_string()))?;
                    settings.push(Setting::ChosenTerms {
                        threshold,
                        choices: choice.chosen.choices,
                        pilot_error: choice.chosen.error,
                    });
                }
                settings
            }
            Axis::Step(v) => {
                if let Some(h) = v.iter().find(|h| !(h.is_finite() && **h > 0.0)) {
                    return Err(bad(format!("{h}: a step must be positive and finite")));
                }
                v.iter().map(|&h| Setting::Step(h)).collect()
            }
        })
    }
}

impl Grid {
    /// The default grid of `flexmbd sweep` and `flexmbd tune` for `scene`: both
    /// formulations; for a scene with flexible beams also both inertia routes, the
    /// stiffening methods linear, FNL1, FNL2 and foreshortening (the scene's own first) and
    /// 1 to max(4, the scene's) normal modes per flexible beam; the steps 2h, h and h/2 about
    /// the scene's step h. Substructuring and the FE mesh stay as the scene has them.
    pub fn default_for(scene: &Scene) -> Grid {
        let h = scene.solver.step;
        let mut axes = vec![Axis::Formulation(vec![
            FormulationKind::Absolute,
            FormulationKind::Relative,
        ])];
        let beams = flexible_beams(scene);
        if !beams.is_empty() {
            axes.push(Axis::Inertia(vec![
                InertiaMethod::BMatrix,
                InertiaMethod::ShapeIntegrals,
            ]));
            let mut methods = vec![scene.solver.stiffening];
            for m in [
                Stiffening::Linear,
                Stiffening::Fnl1,
                Stiffening::Fnl2,
                Stiffening::Foreshortening,
            ] {
                if !methods.contains(&m) {
                    methods.push(m);
                }
            }
            axes.push(Axis::Stiffening(methods));
            let most = scene
                .bodies
                .iter()
                .filter(|b| beams.contains(&b.name))
                .filter_map(|b| match &b.model {
                    BodyModel::Beam(spec) => Some(spec.normal_modes),
                    BodyModel::Rigid { .. } | BodyModel::Imported(_) => None,
                })
                .max()
                .unwrap_or(0)
                .max(4);
            axes.push(Axis::Modes {
                body: None,
                counts: (1..=most).collect(),
            });
        }
        axes.push(Axis::Step(vec![2.0 * h, h, h / 2.0]));
        Grid { axes }
    }

    /// Every point of the grid for `scene`, in order (the last axis varies fastest), the
    /// terms chosen to a tolerance judged on the sensors `judged` (none named: every sensor
    /// but the energy). Refused: a grid without axes, an axis without values, a bad value.
    pub fn points(&self, scene: &Scene, judged: &[String]) -> Result<Vec<GridPoint>, SweepError> {
        if self.axes.is_empty() {
            return Err(SweepError::Grid {
                axis: "grid".into(),
                message: "empty grid: name at least one axis".into(),
            });
        }
        let values = self
            .axes
            .iter()
            .map(|a| a.settings(scene, judged))
            .collect::<Result<Vec<_>, _>>()?;
        let total: usize = values.iter().map(Vec::len).product();
        Ok((0..total)
            .map(|index| {
                let mut rest = index;
                let mut settings = vec![None; values.len()];
                for (k, v) in values.iter().enumerate().rev() {
                    settings[k] = Some(v[rest % v.len()].clone());
                    rest /= v.len();
                }
                GridPoint {
                    index,
                    settings: settings.into_iter().map(Option::unwrap).collect(),
                }
            })
            .collect())
    }

    /// The richest model of the grid at its smallest step: on each categorical axis
    /// (formulation, inertia, stiffening) the first value, the most modes and elements,
    /// the smallest step, the smallest tolerance of the terms (`judged` as in
    /// [`points`](Self::points)). The reference of [`Reference::Converged`](super::Reference).
    pub fn richest(&self, scene: &Scene, judged: &[String]) -> Result<GridPoint, SweepError> {
        let mut settings = Vec::new();
        for axis in &self.axes {
            let all = axis.settings(scene, judged)?;
            let pick = match axis {
                Axis::Modes { counts, .. } | Axis::Elements { counts, .. } => {
                    let k = (0..counts.len()).max_by_key(|&k| counts[k]).unwrap_or(0);
                    all[k].clone()
                }
                Axis::Step(steps)
                | Axis::AutoTerms {
                    thresholds: steps, ..
                } => {
                    let k = (0..steps.len())
                        .min_by(|&a, &b| steps[a].total_cmp(&steps[b]))
                        .unwrap_or(0);
                    all[k].clone()
                }
                _ => all[0].clone(),
            };
            settings.push(pick);
        }
        Ok(GridPoint {
            index: usize::MAX,
            settings,
        })
    }
}

#[cfg(test)]
mod tests;
