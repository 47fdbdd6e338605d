//! The layout of a run to the scene's duration, fixed when the scene is compiled: how many
//! steps, a row every how many steps, and the warnings the rounding to whole steps calls
//! for. A run longer than [`MAX_STEPS`] is refused here, before any preprocessing, so that
//! [`Simulation::new`](crate::Simulation::new), [`run`](super::run) and
//! [`run_into`](super::run_into) all refuse it the same way.

use flexmbd_core::InvalidValue;
use flexmbd_model::{ModelError, Scene};

/// The most steps a run may take (10⁹: some hours of CPU for the smallest scene, and
/// far beyond any duration the scenes in `models/` ask for).
pub const MAX_STEPS: u64 = 1_000_000_000;

/// A ratio of two times within this relative distance of a whole number is that number.
const WHOLE_TOLERANCE: f64 = 1e-9;

/// The steps and output instants of a run to the scene's duration.
#[derive(Clone, Debug)]
pub(super) struct RunPlan {
    /// Steps to the end: solver.duration / solver.step rounded, at least 1.
    pub(super) steps: usize,
    /// A row every this many steps (and at the last step): solver.output_interval /
    /// solver.step rounded, at least 1.
    pub(super) every: usize,
    /// The roundings a reader should know about.
    pub(super) warnings: Vec<String>,
}

impl RunPlan {
    /// The plan of `scene`'s solver settings; a run of more than [`MAX_STEPS`] steps is
    /// refused, naming `solver.duration`, the step count and the limit.
    pub(super) fn of(scene: &Scene) -> Result<RunPlan, ModelError> {
        let s = &scene.solver;
        let h = s.step;
        let ratio = s.duration / h;
        let steps = ratio.round().max(1.0);
        // `max` makes a NaN ratio 1 step: `steps` is a number, possibly infinite.
        if steps > MAX_STEPS as f64 {
            return Err(scene.invalid(InvalidValue::new(
                    "solver.duration",
                    number(s.duration),
                    format!(
                        "{} steps of solver.step = {} s, more than the limit of {MAX_STEPS} steps per run",
                        number(ratio),
                        number(h)
                    ),
                )));
        }
        let mut warnings = Vec::new();
        if !is_whole(ratio) {
            warnings.push(format!(
                "solver.duration {} s is not a whole number of {} s steps: the run is {steps} steps, to t = {} s",
                number(s.duration),
                number(h),
                number(steps * h)
            ));
        }
        let every = match s.output_interval {
            None => 1.0,
            Some(o) => {
                let every = (o / h).round().max(1.0);
                if !is_whole(o / h) {
                    warnings.push(format!(
                        "solver.output_interval {} s is not a whole number of {} s steps: a row every {every} steps ({} s)",
                        number(o),
                        number(h),
                        number(every * h)
                    ));
                }
                every
            }
        };
        Ok(RunPlan {
            steps: steps as usize,
            // Saturates: an interval longer than the run gives the first and last rows.
            every: every.min(MAX_STEPS as f64) as usize,
            warnings,
        })
    }

    /// The rows a run from step `done` to the end writes: the current state, one per
    /// output interval, the last step.
    pub(super) fn rows(&self, done: usize) -> usize {
        self.steps.saturating_sub(done) / self.every + 2
    }
}

/// `ratio` is a whole number ≥ 1, within [`WHOLE_TOLERANCE`] relative.
fn is_whole(ratio: f64) -> bool {
    ratio.round() >= 1.0 && (ratio - ratio.round()).abs() <= WHOLE_TOLERANCE * ratio.abs()
}

/// A time or count for a message: 12 significant digits (1001 × 0.001 reads 1.001, not
/// 1.0010000000000001), exponent notation when very large or small.
pub(super) fn number(x: f64) -> String {
    let rounded: f64 = format!("{x:.11e}").parse().unwrap_or(x);
    if rounded == 0.0 || (1e-4..1e15).contains(&rounded.abs()) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_as_written() {
        assert_eq!(number(1001.0 * 0.001), "1.001");
        assert_eq!(number(1e17), "1e17");
        assert_eq!(number(0.001), "0.001");
        assert_eq!(number(f64::INFINITY), "inf");
    }

    #[test]
    fn whole_ratios() {
        assert!(is_whole(1.0 / 0.001));
        assert!(is_whole(0.01 / 0.001));
        assert!(!is_whole(1.0005 / 0.001));
        assert!(!is_whole(0.3));
        assert!(!is_whole(1e-12));
    }
}
