//! ALI3-P's predictor (docs/methods.md §5.2): per coordinate, the trapezoidal rule with
//! q̈_{n+1} = q̈_n, with the linear extrapolation q̈_{n+1} = 2q̈_n − q̈_{n−1}, or (for a
//! formulation that asks, `Formulation::predictor_repeats_miss`) the first plus the last
//! step's miss; after each step, the one that has recently been nearest the converged q
//! is chosen for the next.

use super::Ali3p;

impl Ali3p {
    /// Predictor (docs/methods.md §5.2): the Newmark constants q̂̇, q̂̈ of the step and the
    /// predicted q_{n+1}, per coordinate by q̈_{n+1} ≈ q̈_n or by the linear extrapolation
    /// (`extrapolate`); q̈_n becomes q̈_{n−1}.
    #[inline]
    pub(super) fn predict(&mut self) {
        let h = self.settings.step;
        let (a1, a2) = (2.0 / h, 4.0 / (h * h));
        // Predictor and the Newmark constants of the step.
        // q̂̇ = −(2/h) q − q̇, q̂̈ = −(4/h²) q − (4/h) q̇ − q̈ (the expressions of nalgebra's
        // axpy sequence, a x + b y, on slices).
        let a3 = -4.0 / h;
        for ((((dh, ddh), q), qd), qdd) in self
            .qd_hat
            .as_mut_slice()
            .iter_mut()
            .zip(self.qdd_hat.as_mut_slice())
            .zip(self.q.as_slice())
            .zip(self.qd.as_slice())
            .zip(self.qdd.as_slice())
        {
            *dh = -a1 * q + -1.0 * qd;
            *ddh = -a2 * q + (a3 * qd + -1.0 * qdd);
        }
        // Predictor: the trapezoidal rule with q̈_{n+1} ≈ q̈_n, q + h q̇ + h²/2 q̈_n, or with
        // the linear extrapolation q̈_{n+1} ≈ 2 q̈_n − q̈_{n−1}, which adds
        // d = h²/4 (q̈_n − q̈_{n−1}); per coordinate, whichever of the two was nearer the
        // solution in the last step (smooth rigid-body coordinates gain from the
        // extrapolation, stiff modal ones lose).
        if !self.have_qdd_prev {
            self.qdd_prev.copy_from(&self.qdd);
        }
        let (c2, c4) = (0.5 * h * h, 0.25 * h * h);
        let n = self.q.len();
        let (q, qd, qdd) = (
            &mut self.q.as_mut_slice()[..n],
            &self.qd.as_slice()[..n],
            &self.qdd.as_slice()[..n],
        );
        let (qdd_prev, pred, pred_d) = (
            &mut self.qdd_prev.as_mut_slice()[..n],
            &mut self.pred.as_mut_slice()[..n],
            &mut self.pred_d.as_mut_slice()[..n],
        );
        let extrapolate = &self.extrapolate[..n];
        let (miss, repeat_miss) = (&self.miss[..n], &self.repeat_miss[..n]);
        for i in 0..n {
            let p = q[i] + h * qd[i] + c2 * qdd[i];
            let d = c4 * qdd[i] - c4 * qdd_prev[i];
            pred[i] = p;
            pred_d[i] = d;
            q[i] = if repeat_miss[i] {
                p + miss[i]
            } else if extrapolate[i] {
                p + d
            } else {
                p
            };
            qdd_prev[i] = qdd[i];
        }
        self.have_qdd_prev = true;
    }

    /// Which predictor was nearer the converged q, per coordinate, for the next step.
    #[inline]
    pub(super) fn choose_predictor(&mut self) {
        let n = self.q.len();
        let (q, pred, pred_d) = (
            &self.q.as_slice()[..n],
            &self.pred.as_slice()[..n],
            &self.pred_d.as_slice()[..n],
        );
        let (err, extrapolate) = (&mut self.pred_err[..n], &mut self.extrapolate[..n]);
        for i in 0..n {
            let e = &mut err[i];
            e.0 = 0.5 * e.0 + (q[i] - pred[i]).abs();
            e.1 = 0.5 * e.1 + (q[i] - (pred[i] + pred_d[i])).abs();
            extrapolate[i] = e.1 < 0.5 * e.0;
        }
        if self.repeats_miss {
            let (miss, miss_err) = (&mut self.miss[..n], &mut self.miss_err[..n]);
            let repeat_miss = &mut self.repeat_miss[..n];
            for i in 0..n {
                let m = q[i] - pred[i];
                miss_err[i] = 0.5 * miss_err[i] + (m - miss[i]).abs();
                miss[i] = m;
                repeat_miss[i] = miss_err[i] < 0.5 * err[i].0.min(err[i].1);
            }
        }
    }
}
