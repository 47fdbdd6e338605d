//! How the cost of a step grows with the coordinate count on scene C (issue 14: "no faster
//! than the cube"): a least-squares fit of log(CPU per step) = a + p log(n) per formulation
//! (shape integrals) over the rows of the CPU table, the same fit per Newton iteration and per
//! phase (evaluation, factorisation, projections), and which phase grows fastest. No runs of
//! its own: the points are the table's (median) runs.

use super::{Case, FORMS, Which};
use crate::report::Report;

/// The bound on the exponent: the cost per step grows no faster than n³.
const CUBE: f64 = 3.0;

/// The least-squares slope p of ln y = a + p ln x over `points` (x, y); None when fewer than
/// two distinct x, or a point is not positive and finite.
pub(super) fn log_log_slope(points: &[(f64, f64)]) -> Option<f64> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if points.iter().any(|&(x, y)| !ok(x) || !ok(y)) || points.is_empty() {
        return None;
    }
    let logs: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x.ln(), y.ln())).collect();
    let m = logs.len() as f64;
    let (mx, my) = (
        logs.iter().map(|p| p.0).sum::<f64>() / m,
        logs.iter().map(|p| p.1).sum::<f64>() / m,
    );
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    // Equal x within round-off leave the slope undetermined.
    (sxx > 1e-12).then(|| sxy / sxx)
}

/// A phase's seconds in the median run of a case.
type PhaseTime = fn(&Case) -> f64;

/// The phases of the table, with what each takes from a run's summary.
const PHASES: [(&str, PhaseTime); 3] = [
    ("evaluation", |c| c.median.time_evaluation),
    ("factorisation", |c| c.median.time_factorization),
    ("projections", |c| c.median.time_projection),
];

fn fmt_slope(p: Option<f64>) -> String {
    p.map_or_else(|| "undetermined".to_string(), |p| format!("{p:.2}"))
}

/// One formulation's sentence: the slope per step and per Newton iteration, the coordinate
/// range, each phase's slope and its share at the ends; and the slope per step.
fn formulation_sentence(form: &str, runs: &[&Case]) -> (String, Option<f64>) {
    let per = |f: &dyn Fn(&Case) -> f64| -> Vec<(f64, f64)> {
        runs.iter()
            .map(|c| (c.median.n_coordinates as f64, f(c)))
            .collect()
    };
    let steps = |c: &Case| c.median.steps.max(1) as f64;
    let p_step = log_log_slope(&per(&|c| c.cpu_median() / steps(c)));
    let p_newton = log_log_slope(&per(&|c| {
        c.cpu_median() / c.median.newton_iterations.max(1) as f64
    }));
    let mut phases: Vec<(&str, Option<f64>, f64, f64)> = PHASES
        .iter()
        .map(|&(name, time)| {
            let share = |c: &Case| 100.0 * time(c) / c.cpu_median();
            let (first, last) = (runs[0], runs[runs.len() - 1]);
            let p = log_log_slope(&per(&|c| time(c) / steps(c)));
            (name, p, share(first), share(last))
        })
        .collect();
    phases.sort_by(|a, b| {
        b.1.unwrap_or(f64::NEG_INFINITY)
            .total_cmp(&a.1.unwrap_or(f64::NEG_INFINITY))
    });
    let ks: Vec<String> = runs.iter().map(|c| c.k.to_string()).collect();
    let (n0, n1) = (
        runs[0].median.n_coordinates,
        runs[runs.len() - 1].median.n_coordinates,
    );
    let fastest = phases[0];
    let others: Vec<String> = phases[1..]
        .iter()
        .map(|(name, p, s0, s1)| format!("{name} p = {} ({s0:.0} % → {s1:.0} %)", fmt_slope(*p)))
        .collect();
    let sentence = format!(
        "{form}: **p = {}** over n = {n0} … {n1} (k = {}; per Newton iteration p = {}); the \
         {} grows fastest, p = {} (its share {:.0} % → {:.0} %), then {}",
        fmt_slope(p_step),
        ks.join(", "),
        fmt_slope(p_newton),
        fastest.0,
        fmt_slope(fastest.1),
        fastest.2,
        fastest.3,
        others.join(", ")
    );
    (sentence, p_step)
}

/// The slope of the cost per step against the coordinate count, per formulation, beside the
/// target p ≤ 3, and which phase grows fastest.
pub(super) fn cost_slope(report: &mut Report, cases: &[Case], reps: usize) {
    let mut sentences = Vec::new();
    let mut verdicts = Vec::new();
    for &(_, form) in &FORMS {
        let mut runs: Vec<&Case> = cases
            .iter()
            .filter(|c| c.which == Which::Vehicle && c.form == form)
            .filter(|c| c.method == "shape-integrals")
            .collect();
        runs.sort_by_key(|c| c.median.n_coordinates);
        if runs.is_empty() {
            continue;
        }
        let (sentence, p) = formulation_sentence(form, &runs);
        sentences.push(sentence);
        verdicts.push(match p {
            Some(p) if p <= CUBE => format!("{form} meets it"),
            Some(_) => format!("{form} **misses** it"),
            None => format!("{form} cannot be judged"),
        });
    }
    let how = if reps > 1 {
        format!("the medians of {reps} runs")
    } else {
        "one run each".to_string()
    };
    report.text(&format!(
        "**Cost per step against the coordinate count** (scene C, shape integrals; the \
         table's rows, {how}): the least-squares fit of log(CPU per step) = a + p log(n), n \
         the coordinates, per formulation, and the same fit of each phase's time per step \
         (shares of the CPU at the smallest → largest n). {}. Target: the cost per step grows \
         no faster than the cube of the coordinate count, p ≤ {CUBE}: {}. The flexible bodies \
         add elastic coordinates to a fixed rigid skeleton, so n spans a narrow range \
         (especially in the absolute formulation, whose rigid bodies carry most of its \
         coordinates): p is the local growth over this vehicle, not an asymptotic order; the \
         Newton iterations per step grow with k too (table), which the fit per Newton \
         iteration removes.",
        sentences.join("; "),
        verdicts.join(", ")
    ));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// y = 2 x^2.5 gives p = 2.5; scattered points give the least-squares slope.
    #[test]
    fn slope_of_a_power_law_and_of_scattered_points() {
        let power: Vec<(f64, f64)> = [40.0, 80.0, 120.0, 280.0]
            .iter()
            .map(|&x: &f64| (x, 2.0 * x.powf(2.5)))
            .collect();
        let p = log_log_slope(&power).unwrap();
        assert!((p - 2.5).abs() < 1e-12, "{p}");
        // ln x = 0, 1, 2 and ln y = 0, 2, 3: Σ(x − x̄)(y − ȳ) / Σ(x − x̄)² = 3 / 2.
        let e = std::f64::consts::E;
        let scattered = [(1.0, 1.0), (e, e * e), (e * e, e.powi(3))];
        let p = log_log_slope(&scattered).unwrap();
        assert!((p - 1.5).abs() < 1e-12, "{p}");
    }

    /// One point, equal x, or a zero or NaN time give no slope instead of NaN or infinity.
    #[test]
    fn slope_undetermined_without_two_distinct_positive_points() {
        assert_eq!(log_log_slope(&[]), None);
        assert_eq!(log_log_slope(&[(100.0, 1.0)]), None);
        assert_eq!(log_log_slope(&[(100.0, 1.0), (100.0, 2.0)]), None);
        assert_eq!(log_log_slope(&[(100.0, 0.0), (200.0, 2.0)]), None);
        assert_eq!(log_log_slope(&[(100.0, f64::NAN), (200.0, 2.0)]), None);
    }
}
