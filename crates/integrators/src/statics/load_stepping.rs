//! Load stepping by the Newton homotopy, and the test that a level has stalled
//! (the parent module's documentation, "Globalisation" and "Neutral directions").

use flexmbd_core::Formulation;
use nalgebra::DVector;

use super::{Level, Solver, StaticError};

/// Iterations without progress after which a level near its tolerance is [`Level::Stalled`].
const STALL_ITERATIONS: usize = 5;
/// "Near": ‖g‖∞ at most this fraction of f_ref (10⁴ times the default tolerance).
const STALL_RESIDUAL: f64 = 1e-6;

/// Counts the iterations of a level that did not lower ‖g‖∞ by half, near the tolerance.
#[derive(Default)]
pub(super) struct Stall {
    best: Option<f64>,
    without_progress: usize,
}

impl Stall {
    /// Record `res`; true when the level has made no progress for [`STALL_ITERATIONS`]
    /// iterations with ‖g‖∞ ≤ [`STALL_RESIDUAL`] f_ref.
    pub(super) fn stuck(&mut self, res: f64, f_ref: f64) -> bool {
        match self.best {
            Some(best) if res > 0.5 * best => self.without_progress += 1,
            _ => {
                self.best = Some(res);
                self.without_progress = 0;
            }
        }
        self.without_progress >= STALL_ITERATIONS && res <= STALL_RESIDUAL * f_ref
    }
}

impl Solver<'_> {
    /// Load stepping by the Newton homotopy from (q, λ) at load 0: increments from
    /// 1/`load_steps`, halved after a failed level, doubled (up to the first) after one that
    /// took ≤ 6 iterations. (converged, largest load factor solved, levels solved).
    pub(super) fn load_stepping<F: Formulation + ?Sized>(
        &mut self,
        f: &mut F,
        q: &mut DVector<f64>,
        lambda: &mut DVector<f64>,
    ) -> Result<(bool, f64, usize), StaticError> {
        let mut load = 0.0;
        let mut load_steps = 0;
        let first = 1.0 / self.s.load_steps.max(1) as f64;
        let mut inc = first;
        let (mut q_save, mut l_save) = (q.clone(), lambda.clone());
        loop {
            let target = if load + inc > 1.0 - 1e-12 {
                1.0
            } else {
                load + inc
            };
            let before = self.iterations;
            if matches!(self.level(f, q, lambda, target)?, Level::Converged) {
                load = target;
                load_steps += 1;
                q_save.copy_from(q);
                l_save.copy_from(lambda);
                if load >= 1.0 {
                    return Ok((true, load, load_steps));
                }
                if self.iterations - before <= 6 {
                    inc = (2.0 * inc).min(first);
                }
            } else {
                q.copy_from(&q_save);
                lambda.copy_from(&l_save);
                inc *= 0.5;
                if inc < self.s.min_increment {
                    return Ok((false, load, load_steps));
                }
            }
        }
    }
}
