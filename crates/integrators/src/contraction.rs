//! Newton's contraction measured across steps, to stop after the first correction when the
//! second would be far below the tolerance (issue 26 item 4).
//!
//! The convergence test of a step needs an estimate of the error left in q after the last
//! correction Δq_i. From the second iteration on, the step measures its own contraction
//! θ = ‖Δq_i‖/‖Δq_{i−1}‖ and uses θ/(1−θ)‖Δq_i‖ (Hairer & Wanner II, §IV.8). After the first
//! correction there is no θ of the step. Without one the test could only accept
//! ‖Δq₁‖ ≤ ε_q: a predictor's miss must be within the tolerance itself, so a step whose miss
//! is 100 × ε_q takes a second, full iteration that moves q by 10⁻⁵ ε_q.
//!
//! Taken here from the steps before: every step that makes a second full-Newton iteration
//! records its first two corrections d₁, d₂ as a linear rate θ = d₂/d₁ and a quadratic
//! constant κ = d₂/d₁². Newton with an exact tangent contracts quadratically (d₂ ≈ κ d₁²);
//! with the formulations' approximate tangents (the inertia forces' derivatives are left
//! out, methods.md §4.6) and the multiplier update of the augmented Lagrangian, linearly
//! (d₂ ≈ θ d₁). The error after the first correction is estimated as the larger of the two
//! models, each from the largest of the last [`SAMPLES`] records: max(θ̂ d₁, κ̂ d₁²). This is
//! the size of the second correction a step would have made, as the records measured it.
//!
//! The estimate is only used while it is fresh. Until [`SAMPLES`] records exist, and when
//! [`REMEASURE`] steps have passed since the last record, the first iterate is judged as
//! before (by ‖Δq₁‖ itself). Such a step usually makes the second iteration, which records
//! again. So a run stops at the first iterate only on contraction measured within the last
//! [`REMEASURE`] steps.

/// The records an estimate takes the largest of.
pub const SAMPLES: usize = 4;

/// Steps after the last record from which the first iterate is judged by ‖Δq₁‖ again.
pub const REMEASURE: usize = 16;

/// The last [`SAMPLES`] records of Newton's contraction (module documentation). It is part
/// of the integrator's state: a checkpoint keeps it, so a restored run repeats its bits.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Contraction {
    /// θ = d₂/d₁ of the last records (a ring, `records` modulo [`SAMPLES`]).
    linear: [f64; SAMPLES],
    /// κ = d₂/d₁² of the same records.
    quadratic: [f64; SAMPLES],
    /// Records made since the start.
    records: usize,
    /// Steps completed since the last record.
    since_record: usize,
}

impl Contraction {
    /// The estimated error left in q after a first correction of size `d1`, when the
    /// records are fresh enough to give one.
    pub fn first_iterate_error(&self, d1: f64) -> Option<f64> {
        if self.records < SAMPLES || self.since_record >= REMEASURE {
            return None;
        }
        let theta = self.linear.iter().copied().fold(0.0, f64::max);
        let kappa = self.quadratic.iter().copied().fold(0.0, f64::max);
        Some((theta * d1).max(kappa * d1 * d1))
    }

    /// Record a step's first two full-Newton corrections (a step with d₁ = 0 gives nothing
    /// to measure).
    pub fn record(&mut self, d1: f64, d2: f64) {
        if !(d1 > 0.0 && d1.is_finite() && d2.is_finite()) {
            return;
        }
        let slot = self.records % SAMPLES;
        self.linear[slot] = d2 / d1;
        self.quadratic[slot] = d2 / (d1 * d1);
        self.records += 1;
        self.since_record = 0;
    }

    /// A step was completed (after any [`record`](Self::record) of it).
    pub fn step_done(&mut self, recorded: bool) {
        if !recorded {
            self.since_record += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_estimate_before_enough_records_or_once_stale() {
        let mut c = Contraction::default();
        for _ in 0..SAMPLES - 1 {
            c.record(1e-6, 1e-11);
            c.step_done(true);
        }
        assert_eq!(c.first_iterate_error(1e-6), None);
        c.record(1e-6, 1e-11);
        c.step_done(true);
        assert!(c.first_iterate_error(1e-6).is_some());
        for _ in 0..REMEASURE {
            c.step_done(false);
        }
        assert_eq!(c.first_iterate_error(1e-6), None);
        c.record(1e-6, 1e-11);
        c.step_done(true);
        assert!(c.first_iterate_error(1e-6).is_some());
    }

    #[test]
    fn the_estimate_is_the_larger_model_of_the_largest_records() {
        let mut c = Contraction::default();
        // Quadratic records: κ = 10, θ = 1e-5 … 1e-4.
        for d1 in [1e-6, 2e-6, 4e-6, 1e-5] {
            c.record(d1, 10.0 * d1 * d1);
            c.step_done(true);
        }
        // θ̂ = 1e-4 (d₁ = 1e-5), κ̂ = 10: at d₁ = 1e-3 the quadratic model is the larger.
        assert!((c.first_iterate_error(1e-3).unwrap() - 1e-5).abs() < 1e-18);
        // At d₁ = 1e-6 the linear one: 1e-4 · 1e-6.
        assert!((c.first_iterate_error(1e-6).unwrap() - 1e-10).abs() < 1e-22);
        // A linearly converging record (θ = 0.3) dominates the next estimates.
        c.record(1e-6, 3e-7);
        c.step_done(true);
        assert!((c.first_iterate_error(1e-6).unwrap() - 3e-7).abs() < 1e-19);
        // A zero first correction records nothing.
        let before = c;
        c.record(0.0, 0.0);
        assert_eq!(c, before);
    }
}
