//! The reference a sweep judges its runs against: a table of times and sensor columns
//! (read from a CSV file, given in memory, or a converged run of the scene), linear
//! interpolation in it, and the error measures of one run (docs/methods.md §10.1).

use std::path::Path;

use serde::Serialize;

use super::SweepError;

/// Sensor histories to judge runs against: strictly increasing times and one column per
/// sensor, every value finite.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceTable {
    /// Where the table came from, named in errors (a file, or a label).
    pub origin: String,
    /// Output times (s), strictly increasing.
    pub t: Vec<f64>,
    /// Sensor names, one per column.
    pub names: Vec<String>,
    /// `columns[k][i]`: sensor `names[k]` at `t[i]`.
    pub columns: Vec<Vec<f64>>,
}

/// The error of one run on one sensor against the reference.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct SensorError {
    /// The sensor.
    pub sensor: String,
    /// Largest |run − reference| over the compared output times.
    pub max_abs: f64,
    /// Root mean square of run − reference over the compared output times.
    pub rms: f64,
}

impl ReferenceTable {
    /// A table from its parts, checked: as many values in every column as times, times
    /// strictly increasing and finite, values finite, at least two times.
    pub fn new(
        origin: impl Into<String>,
        t: Vec<f64>,
        names: Vec<String>,
        columns: Vec<Vec<f64>>,
    ) -> Result<Self, SweepError> {
        let table = ReferenceTable {
            origin: origin.into(),
            t,
            names,
            columns,
        };
        table.check()?;
        Ok(table)
    }

    fn check(&self) -> Result<(), SweepError> {
        let bad = |message: String| SweepError::Reference {
            origin: self.origin.clone(),
            line: None,
            message,
        };
        if self.t.len() < 2 {
            return Err(bad(format!(
                "{} time(s): interpolation needs at least two",
                self.t.len()
            )));
        }
        if self.names.len() != self.columns.len() {
            return Err(bad("as many column names as columns expected".into()));
        }
        for (k, w) in self.t.windows(2).enumerate() {
            if !w[0].is_finite() || !w[1].is_finite() || w[1] <= w[0] {
                return Err(bad(format!(
                    "times out of order: t[{}] = {} is not after t[{k}] = {}",
                    k + 1,
                    w[1],
                    w[0]
                )));
            }
        }
        for (name, column) in self.names.iter().zip(&self.columns) {
            if column.len() != self.t.len() {
                return Err(bad(format!(
                    "column `{name}` has {} values for {} times",
                    column.len(),
                    self.t.len()
                )));
            }
            if let Some(i) = column.iter().position(|v| !v.is_finite()) {
                return Err(bad(format!(
                    "column `{name}` is not finite at t = {}: {}",
                    self.t[i], column[i]
                )));
            }
        }
        Ok(())
    }

    /// Read a CSV file: a header `t,NAME,…` (the first column is the time, names may be
    /// quoted as `flexmbd simulate --output` writes them), then one row of numbers per
    /// output time.
    pub fn from_csv(path: &Path) -> Result<Self, SweepError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SweepError::Reference {
            origin: origin.clone(),
            line: None,
            message: format!("cannot read: {e}"),
        })?;
        Self::from_csv_str(&text, &origin)
    }

    /// Parse CSV text (see [`ReferenceTable::from_csv`]); `origin` names it in errors.
    pub fn from_csv_str(text: &str, origin: &str) -> Result<Self, SweepError> {
        let bad = |line: usize, message: String| SweepError::Reference {
            origin: origin.to_string(),
            line: Some(line),
            message,
        };
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let Some((_, header)) = lines.next() else {
            return Err(bad(1, "empty file: expected a header `t,SENSOR,…`".into()));
        };
        let names: Vec<String> = header
            .split(',')
            .map(|s| s.trim().trim_matches('"').to_string())
            .collect();
        if names[0] != "t" {
            return Err(bad(
                1,
                format!("the first column is `{}`; expected `t` (s)", names[0]),
            ));
        }
        let mut t = Vec::new();
        let mut columns = vec![Vec::new(); names.len() - 1];
        for (i, line) in lines {
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            if fields.len() != names.len() {
                return Err(bad(
                    i + 1,
                    format!("{} fields; the header has {}", fields.len(), names.len()),
                ));
            }
            for (k, f) in fields.iter().enumerate() {
                let v: f64 = f.parse().map_err(|_| {
                    bad(
                        i + 1,
                        format!("column `{}`: `{f}` is not a number", names[k]),
                    )
                })?;
                if !v.is_finite() {
                    return Err(bad(
                        i + 1,
                        format!("column `{}`: {v} is not finite", names[k]),
                    ));
                }
                if k == 0 {
                    if let Some(&last) = t.last()
                        && v <= last
                    {
                        return Err(bad(
                            i + 1,
                            format!("times out of order: t = {v} is not after {last}"),
                        ));
                    }
                    t.push(v);
                } else {
                    columns[k - 1].push(v);
                }
            }
        }
        Self::new(origin, t, names[1..].to_vec(), columns)
    }

    /// The column of `sensor`, refused by name when the table has none.
    pub fn column(&self, sensor: &str) -> Result<&[f64], SweepError> {
        self.names
            .iter()
            .position(|n| n == sensor)
            .map(|k| self.columns[k].as_slice())
            .ok_or_else(|| SweepError::Reference {
                origin: self.origin.clone(),
                line: Some(1),
                message: format!(
                    "no column `{sensor}` (columns: t, {})",
                    self.names.join(", ")
                ),
            })
    }

    /// The first and last time (s).
    pub fn span(&self) -> (f64, f64) {
        (self.t[0], self.t[self.t.len() - 1])
    }
}

/// `values` (given at the increasing `times`) linearly interpolated at `t`; `None` outside
/// `[times[0], times[last]]`, widened by a relative 10⁻⁹ of the span for round-off.
pub fn interpolate(times: &[f64], values: &[f64], t: f64) -> Option<f64> {
    let (t0, t1) = (times[0], times[times.len() - 1]);
    let slack = 1e-9 * (t1 - t0).abs().max(f64::MIN_POSITIVE);
    if !(t >= t0 - slack && t <= t1 + slack) {
        return None;
    }
    let t = t.clamp(t0, t1);
    // The interval [times[k], times[k+1]] holding t.
    let k = times.partition_point(|&x| x <= t).clamp(1, times.len() - 1) - 1;
    let (ta, tb) = (times[k], times[k + 1]);
    let s = (t - ta) / (tb - ta);
    Some(values[k] + s * (values[k + 1] - values[k]))
}

/// The error of the run values `run` (at the run's output times `t`) against the
/// reference `(ref_t, ref_values)` interpolated linearly to those times: the largest
/// absolute difference and the root mean square, over the run times that lie in the
/// reference's span. `None` when no run time does. A non-finite run value makes both
/// measures infinite.
pub fn error_measures(
    t: &[f64],
    run: &[f64],
    ref_t: &[f64],
    ref_values: &[f64],
) -> Option<(f64, f64)> {
    let (mut max_abs, mut sum_sq, mut n) = (0.0f64, 0.0f64, 0usize);
    for (&ti, &yi) in t.iter().zip(run) {
        let Some(r) = interpolate(ref_t, ref_values, ti) else {
            continue;
        };
        let d = if yi.is_finite() {
            (yi - r).abs()
        } else {
            f64::INFINITY
        };
        max_abs = max_abs.max(d);
        sum_sq += d * d;
        n += 1;
    }
    (n > 0).then(|| (max_abs, (sum_sq / n as f64).sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_is_linear_between_samples_and_exact_at_them() {
        let (t, v) = ([0.0, 1.0, 3.0], [2.0, 4.0, 0.0]);
        assert_eq!(interpolate(&t, &v, 0.0), Some(2.0));
        assert_eq!(interpolate(&t, &v, 0.5), Some(3.0));
        assert_eq!(interpolate(&t, &v, 1.0), Some(4.0));
        assert_eq!(interpolate(&t, &v, 2.5), Some(1.0));
        assert_eq!(interpolate(&t, &v, 3.0), Some(0.0));
        assert_eq!(interpolate(&t, &v, -0.1), None);
        assert_eq!(interpolate(&t, &v, 3.1), None);
        // Round-off past the end is still inside.
        assert_eq!(interpolate(&t, &v, 3.0 + 1e-12), Some(0.0));
    }

    #[test]
    fn error_measures_of_a_constant_offset_are_the_offset() {
        let ref_t = [0.0, 1.0, 2.0];
        let ref_v = [0.0, 1.0, 2.0];
        // Run sampled between the reference's samples, 0.25 above the line y = t.
        let t = [0.5, 1.5];
        let run = [0.75, 1.75];
        let (max_abs, rms) = error_measures(&t, &run, &ref_t, &ref_v).unwrap();
        assert!((max_abs - 0.25).abs() < 1e-15 && (rms - 0.25).abs() < 1e-15);
    }

    #[test]
    fn rms_and_max_differ_for_a_single_spike() {
        let ref_t = [0.0, 3.0];
        let ref_v = [0.0, 0.0];
        let (max_abs, rms) =
            error_measures(&[0.0, 1.0, 2.0, 3.0], &[0.0, 2.0, 0.0, 0.0], &ref_t, &ref_v).unwrap();
        assert_eq!(max_abs, 2.0);
        assert_eq!(rms, 1.0); // sqrt(4 / 4)
    }

    #[test]
    fn run_times_outside_the_reference_are_not_compared_and_nan_is_infinite_error() {
        let (ref_t, ref_v) = ([0.0, 1.0], [0.0, 0.0]);
        assert_eq!(
            error_measures(&[2.0, 3.0], &[1.0, 1.0], &ref_t, &ref_v),
            None
        );
        let (m, _) = error_measures(&[0.5, 5.0], &[0.1, 9.0], &ref_t, &ref_v).unwrap();
        assert_eq!(m, 0.1, "the value at t = 5 lies outside the reference");
        let (m, r) = error_measures(&[0.5], &[f64::NAN], &ref_t, &ref_v).unwrap();
        assert!(m.is_infinite() && r.is_infinite());
    }

    #[test]
    fn csv_reference_is_read_with_quoted_names_and_bad_tables_are_refused_by_line() {
        let table =
            ReferenceTable::from_csv_str("\"t\",\"tip_uy\"\n0,0.0\n0.01,-1e-3\n", "r.csv").unwrap();
        assert_eq!(table.names, ["tip_uy"]);
        assert_eq!(table.column("tip_uy").unwrap(), [0.0, -1e-3]);
        let missing = table.column("tip_ux").unwrap_err().to_string();
        assert!(
            missing.contains("r.csv") && missing.contains("no column `tip_ux`"),
            "{missing}"
        );

        let order = ReferenceTable::from_csv_str("t,a\n0,1\n0.2,1\n0.1,1\n", "r.csv")
            .unwrap_err()
            .to_string();
        assert!(
            order.contains("r.csv:4") && order.contains("out of order"),
            "{order}"
        );
        let nan = ReferenceTable::from_csv_str("t,a\n0,1\n1,NaN\n", "r.csv")
            .unwrap_err()
            .to_string();
        assert!(
            nan.contains("r.csv:3") && nan.contains("not finite"),
            "{nan}"
        );
        let first = ReferenceTable::from_csv_str("time,a\n0,1\n", "r.csv")
            .unwrap_err()
            .to_string();
        assert!(first.contains("expected `t`"), "{first}");
        let short = ReferenceTable::from_csv_str("t,a\n0,1\n1\n", "r.csv")
            .unwrap_err()
            .to_string();
        assert!(
            short.contains("r.csv:3") && short.contains("1 fields"),
            "{short}"
        );
    }
}
