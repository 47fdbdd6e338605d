//! The terms chosen to meet a tolerance: the weights rank the choices, runs judge them
//! (docs/design.md "Inertia terms by weight").
//!
//! A weight bounds the force a group of terms adds, not the error of the trajectory
//! without it (a workless force integrated over a resonant spin-up shifts the phase of the
//! bending vibration), so the weights alone do not meet a tolerance. Here they only order
//! the choices. The **ladder** at tolerance X: the weights' choice at threshold t (per body
//! the cheapest candidate whose dropped terms weigh at most t, [`WeightTable::choose`]),
//! for t falling from X through the weights of the candidates below it, each distinct
//! choice once, down to every term kept (t → 0). Each rung is costlier than the one above
//! it, and drops lighter terms. Each rung is **run in place of the full model** over the
//! pilot's horizon (the pilot's scene: relative coordinates, shape integrals, its step,
//! output instants and duration) and judged against the pilot's sensors:
//!
//! ```text
//! e = max over the judged sensors s of  max_t |s_rung(t) − s_full(t)| / range_t s_full
//! ```
//!
//! (range = max − min over the pilot; a sensor that does not move in the pilot counts any
//! difference as infinite). The first rung with `e ≤ X` is the choice; the last rung, every
//! term kept, is the pilot itself (e = 0), so there always is one.
//!
//! **What is guaranteed:** on the pilot's horizon, at the pilot's step and output instants,
//! the choice's judged sensors differ from the full model's by at most X of their range
//! (relative coordinates with shape integrals; the absolute formulation carries the same
//! physics per truncation, to 5e-5 of the range at h = 1 ms, `tests/inertia_terms.rs`).
//! **What is not:** a longer run (an error that grows with time, as a phase shift does, can
//! pass X later), other sensors, another step, mode count or stiffening method than the
//! pilot's.
//!
//! [`WeightTable::choose`]: flexmbd_body::weights::WeightTable::choose

use std::sync::{Arc, Mutex};

use flexmbd_body::InertiaTerms;
use flexmbd_body::weights::{check_threshold, kernel_work};
use flexmbd_core::InvalidValue;
use flexmbd_model::Scene;

use super::{BodyWeights, Pilot, pilot, pilot_scene, run_rows};
use crate::{Error, Simulation};

/// One rung of the ladder: a choice of terms per body, and the largest weight of what it
/// drops (max over the bodies of the rigid, modal and deformation max weights).
#[derive(Clone, Debug, PartialEq)]
pub struct Ladder {
    /// One choice per body, in the order of the bodies given to [`ladder`].
    pub terms: Vec<InertiaTerms>,
    /// The largest weight of what the rung drops.
    pub weight: f64,
}

/// The ladder at `threshold` over the bodies `weights` (module doc): the weights' choice at
/// `threshold` first, every term kept last. A threshold outside (0, 1) is refused by name.
pub fn ladder(weights: &[&BodyWeights], threshold: f64) -> Result<Vec<Ladder>, Error> {
    check_threshold(threshold).map_err(Error::Input)?;
    let at = |t: f64| -> Ladder {
        let picks: Vec<(InertiaTerms, f64)> = weights
            .iter()
            .map(|w| {
                w.table
                    .candidates
                    .iter()
                    .find(|(_, x)| x.max() <= t)
                    .map_or((InertiaTerms::FULL, 0.0), |(c, x)| (*c, x.max()))
            })
            .collect();
        Ladder {
            terms: picks.iter().map(|p| p.0).collect(),
            weight: picks.iter().map(|p| p.1).fold(0.0, f64::max),
        }
    };
    let full = Ladder {
        terms: vec![InertiaTerms::FULL; weights.len()],
        weight: 0.0,
    };
    let mut rungs: Vec<Ladder> = Vec::new();
    let mut t = threshold;
    loop {
        let rung = at(t);
        if rung.terms == full.terms {
            break;
        }
        // Below the rung's heaviest drop the next weight down decides the next rung: every
        // t in [next, weight) gives the same choices.
        let next = weights
            .iter()
            .flat_map(|w| w.table.candidates.iter().map(|(_, x)| x.max()))
            .filter(|&x| x < rung.weight)
            .fold(f64::NEG_INFINITY, f64::max);
        if rungs.last().map(|r| &r.terms) != Some(&rung.terms) {
            rungs.push(rung);
        }
        if next == f64::NEG_INFINITY {
            break;
        }
        t = next;
    }
    rungs.push(full);
    Ok(rungs)
}

/// A choice of terms run in place of the full model over the pilot's horizon.
#[derive(Clone, Debug, PartialEq)]
pub struct Trial {
    /// Each body and its terms.
    pub choices: Vec<(String, InertiaTerms)>,
    /// The largest weight of what it drops ([`Ladder::weight`]).
    pub weight: f64,
    /// Per judged sensor, `max_t |run − pilot| / range of the pilot` (module doc).
    pub errors: Vec<(String, f64)>,
    /// The largest of [`errors`](Self::errors); infinite for a run that failed.
    pub error: f64,
    /// CPU time of its steps (s; the pilot's for every term kept).
    pub cpu_seconds: f64,
    /// The kernels' n² work summed over the bodies, `Σ kernel_work(terms) n²`
    /// ([`kernel_work`]; multiply-adds per kernel call).
    pub kernel_work: u64,
    /// Why its run failed, if it did.
    pub failure: Option<String>,
}

impl Trial {
    /// The choices as a short label: `o2-nv` when every body has the same, else
    /// `crank1=o1,coupler1=o1-nv,…`.
    pub fn label(&self) -> String {
        let first = self.choices.first().map(|c| c.1);
        if self.choices.iter().all(|c| Some(c.1) == first) {
            return first.map_or(String::new(), |t| t.label());
        }
        let each: Vec<String> = self
            .choices
            .iter()
            .map(|(b, t)| format!("{b}={t}"))
            .collect();
        each.join(",")
    }
}

/// The terms chosen at a tolerance and how they were confirmed ([`Pilot::confirm`]).
#[derive(Clone, Debug, PartialEq)]
pub struct TermChoice {
    /// The tolerance X (a fraction of each judged sensor's range).
    pub tolerance: f64,
    /// The choice: the first rung whose run met the tolerance.
    pub chosen: Trial,
    /// The rungs run before it and rejected, in the ladder's order (empty when the weights'
    /// choice met the tolerance).
    pub rejected: Vec<Trial>,
    /// The full model's CPU time over the horizon (the pilot's steps, s).
    pub full_cpu_seconds: f64,
    /// The full model's kernel work ([`Trial::kernel_work`]).
    pub full_kernel_work: u64,
    /// The horizon judged (s): the pilot's duration.
    pub horizon: f64,
    /// The sensors judged.
    pub sensors: Vec<String>,
}

impl TermChoice {
    /// The weights' choice alone (the first rung of the ladder).
    pub fn weights_choice(&self) -> &Trial {
        self.rejected.first().unwrap_or(&self.chosen)
    }

    /// `scene` with each chosen body's terms set (bodies it does not name are left alone).
    pub fn apply(&self, scene: &Scene) -> Scene {
        let mut out = scene.clone();
        for (name, terms) in &self.chosen.choices {
            if let Some(b) = out.bodies.iter_mut().find(|b| &b.name == name) {
                b.inertia_terms = *terms;
            }
        }
        out
    }
}

impl Pilot {
    /// The terms of the bodies `bodies` (every weighed body of the scene when `None`)
    /// that meet `tolerance` on the pilot's horizon and sensors: the ladder's first rung
    /// whose run does (module doc). The runs are kept, so a second tolerance reuses them. A
    /// tolerance outside (0, 1), a body that was not weighed, a pilot without a judged
    /// sensor are refused by name.
    pub fn confirm(&self, tolerance: f64, bodies: Option<&[String]>) -> Result<TermChoice, Error> {
        check_threshold(tolerance)
            .map_err(|e| Error::Input(InvalidValue::new("tolerance", tolerance, e.reason)))?;
        if self.sensors.is_empty() {
            return Err(Error::Input(InvalidValue::new(
                "sensor",
                "none",
                "the scene has no sensor to judge a choice of terms by (the energy is not \
                 judged: each truncation has its own); add a Position or Modal sensor",
            )));
        }
        let weighed: Vec<&BodyWeights> = self
            .weights
            .iter()
            .filter(|w| self.scene.bodies.iter().any(|b| b.name == w.body))
            .collect();
        let chosen: Vec<&BodyWeights> =
            match bodies {
                None => weighed,
                Some(names) => names
                    .iter()
                    .map(|n| {
                        weighed.iter().find(|w| &w.body == n).copied().ok_or_else(|| {
                        Error::Input(InvalidValue::new(
                            "body",
                            n,
                            "was not weighed: not a flexible body with modes of the scene (a \
                             substructured beam runs as pieces)",
                        ))
                    })
                    })
                    .collect::<Result<_, _>>()?,
            };
        if chosen.is_empty() {
            return Err(Error::Input(InvalidValue::new(
                "scene",
                &self.scene.name,
                "no flexible body of the scene was weighed (a substructured beam runs as pieces)",
            )));
        }
        let work = |terms: &[InertiaTerms]| -> u64 {
            chosen
                .iter()
                .zip(terms)
                .map(|(w, &t)| u64::from(kernel_work(t)) * (w.modes * w.modes) as u64)
                .sum()
        };
        let full_kernel_work = work(&vec![InertiaTerms::FULL; chosen.len()]);
        let mut rejected = Vec::new();
        for rung in ladder(&chosen, tolerance)? {
            let choices: Vec<(String, InertiaTerms)> = chosen
                .iter()
                .zip(&rung.terms)
                .map(|(w, &t)| (w.body.clone(), t))
                .collect();
            let trial = if rung.terms.iter().all(|t| t.is_full()) {
                Trial {
                    choices,
                    weight: 0.0,
                    errors: self.sensors.iter().map(|s| (s.clone(), 0.0)).collect(),
                    error: 0.0,
                    cpu_seconds: self.cpu_seconds,
                    kernel_work: full_kernel_work,
                    failure: None,
                }
            } else {
                Trial {
                    weight: rung.weight,
                    kernel_work: work(&rung.terms),
                    ..self.trial(choices)
                }
            };
            if trial.error <= tolerance {
                return Ok(TermChoice {
                    tolerance,
                    chosen: trial,
                    rejected,
                    full_cpu_seconds: self.cpu_seconds,
                    full_kernel_work,
                    horizon: self.scene.solver.duration,
                    sensors: self.sensors.clone(),
                });
            }
            rejected.push(trial);
        }
        unreachable!("the last rung keeps every term: the pilot itself, error 0")
    }

    /// The run of `choices` over the pilot's horizon, judged against the pilot (made once).
    fn trial(&self, choices: Vec<(String, InertiaTerms)>) -> Trial {
        let mut trials = self.trials.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = trials.iter().find(|t| t.choices == choices) {
            return t.clone();
        }
        let mut scene = self.scene.clone();
        for (name, terms) in &choices {
            if let Some(b) = scene.bodies.iter_mut().find(|b| &b.name == name) {
                b.inertia_terms = *terms;
            }
        }
        let run =
            Simulation::new(&scene).and_then(|sim| run_rows(sim, &scene, &self.sensors, |_| {}));
        let trial = match run {
            Ok((rows, cpu_seconds)) => {
                let errors: Vec<(String, f64)> = self
                    .sensors
                    .iter()
                    .zip(&self.columns)
                    .enumerate()
                    .map(|(k, (s, full))| (s.clone(), relative_error(&rows, k + 1, full)))
                    .collect();
                Trial {
                    error: errors.iter().map(|e| e.1).fold(0.0, f64::max),
                    errors,
                    cpu_seconds,
                    ..failed(choices, None)
                }
            }
            Err(e) => failed(choices, Some(e.to_string())),
        };
        trials.push(trial.clone());
        trial
    }
}

/// A trial not (yet) judged: infinite error.
fn failed(choices: Vec<(String, InertiaTerms)>, failure: Option<String>) -> Trial {
    Trial {
        choices,
        weight: 0.0,
        errors: Vec::new(),
        error: f64::INFINITY,
        cpu_seconds: 0.0,
        kernel_work: 0,
        failure,
    }
}

/// `max_t |rows[·][column] − full| / range(full)` (module doc); rows of another length, a
/// value that is not finite: infinite.
fn relative_error(rows: &[Vec<f64>], column: usize, full: &[f64]) -> f64 {
    if rows.len() != full.len() {
        return f64::INFINITY;
    }
    let hi = full.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let lo = full.iter().copied().fold(f64::INFINITY, f64::min);
    let mut largest = 0.0f64;
    for (row, &f) in rows.iter().zip(full) {
        let d = (row[column] - f).abs();
        if !d.is_finite() {
            return f64::INFINITY;
        }
        largest = largest.max(d);
    }
    match (largest == 0.0, hi > lo) {
        (true, _) => 0.0,
        (false, true) => largest / (hi - lo),
        (false, false) => f64::INFINITY,
    }
}

/// How many pilots [`cached_pilot`] keeps.
const CACHED_PILOTS: usize = 8;

/// The pilots of this process, by their key (most recent last).
type PilotCache = Vec<(String, Arc<Pilot>)>;
static PILOT_CACHE: Mutex<PilotCache> = Mutex::new(Vec::new());

/// The pilot of `scene` over its whole duration judging `judged` ([`pilot`]), taken from
/// the last 8 (`CACHED_PILOTS`) of this process when one ran the same pilot scene with the
/// same sensors (the pilot is deterministic), so that a sweep that expands its grid more
/// than once (its reference, a retiming) runs one pilot and each rung of its ladders once.
pub fn cached_pilot(scene: &Scene, judged: &[String]) -> Result<Arc<Pilot>, Error> {
    let key = format!("{:?} {judged:?}", pilot_scene(scene, None)?);
    let lookup = |cache: &PilotCache| {
        cache
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, p)| Arc::clone(p))
    };
    if let Some(p) = lookup(&PILOT_CACHE.lock().unwrap_or_else(|e| e.into_inner())) {
        return Ok(p);
    }
    let made = Arc::new(pilot(scene, None, judged)?);
    let mut cache = PILOT_CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(p) = lookup(&cache) {
        return Ok(p);
    }
    if cache.len() == CACHED_PILOTS {
        cache.remove(0);
    }
    cache.push((key, Arc::clone(&made)));
    Ok(made)
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd_body::weights::{Weight, WeightTable, candidates};

    /// A body whose candidates drop the given max weights (cheapest first, full last).
    fn body(name: &str, drops: [f64; 8]) -> BodyWeights {
        let weight = |w: f64| Weight {
            rigid_max: w,
            ..Weight::default()
        };
        BodyWeights {
            body: name.into(),
            modes: 4,
            table: WeightTable {
                groups: Vec::new(),
                candidates: candidates().into_iter().zip(drops.map(weight)).collect(),
                samples: 1,
            },
        }
    }

    #[test]
    fn the_ladder_starts_at_the_weights_choice_and_climbs_to_every_term() {
        let c = candidates();
        // Weights falling with cost, as dropping fewer terms does.
        let a = body("a", [0.5, 0.4, 0.3, 0.05, 0.02, 0.01, 0.004, 0.0]);
        let rungs = ladder(&[&a], 0.03).unwrap();
        let terms: Vec<InertiaTerms> = rungs.iter().map(|r| r.terms[0]).collect();
        assert_eq!(terms[0], a.table.choose(0.03).unwrap());
        assert_eq!(terms, [c[4], c[5], c[6], InertiaTerms::FULL]);
        let weights: Vec<f64> = rungs.iter().map(|r| r.weight).collect();
        assert_eq!(weights, [0.02, 0.01, 0.004, 0.0]);
        // Two bodies: each rung lowers the heaviest drop; the body whose drop is lighter
        // keeps its choice until the threshold passes below its weight.
        let b = body("b", [0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 1e-3, 0.0]);
        let rungs = ladder(&[&a, &b], 0.03).unwrap();
        let pairs: Vec<(InertiaTerms, InertiaTerms)> =
            rungs.iter().map(|r| (r.terms[0], r.terms[1])).collect();
        assert_eq!(
            pairs,
            [
                (c[4], c[6]),
                (c[5], c[6]),
                (c[6], c[6]),
                (InertiaTerms::FULL, c[6]),
                (InertiaTerms::FULL, InertiaTerms::FULL)
            ]
        );
        assert!(
            ladder(&[&a], 1.0)
                .unwrap_err()
                .to_string()
                .contains("threshold")
        );
    }

    #[test]
    fn the_relative_error_is_over_the_range_and_a_still_sensor_counts_any_difference() {
        let rows = |v: &[f64]| v.iter().map(|&x| vec![0.0, x]).collect::<Vec<_>>();
        assert_eq!(
            relative_error(&rows(&[0.0, 1.5, 1.0]), 1, &[0.0, 2.0, 1.0]),
            0.25
        );
        assert_eq!(relative_error(&rows(&[3.0, 3.0]), 1, &[3.0, 3.0]), 0.0);
        assert!(relative_error(&rows(&[3.0, 3.1]), 1, &[3.0, 3.0]).is_infinite());
        assert!(relative_error(&rows(&[f64::NAN, 3.0]), 1, &[3.0, 2.0]).is_infinite());
        assert!(relative_error(&rows(&[3.0]), 1, &[3.0, 2.0]).is_infinite());
    }
}
