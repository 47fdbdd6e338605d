//! Nonlinear force laws F(x) of one variable — a force element's length or its rate — as
//! scene data, with their value, slope and integral (docs/methods.md §2.6).
//!
//! - `Zero`: F = 0.
//! - `Polynomial { coefficients: [c₀, c₁, …], about: x₀ }`: F = Σ c_k (x − x₀)^k (x₀ = 0
//!   when omitted).
//! - `Piecewise { breakpoints: [b₀, …, b_{m−1}], pieces: [P₀, …, P_m], continuous }`: piece
//!   P_i on (b_{i−1}, b_i] (P₀ on (−∞, b₀], P_m on (b_{m−1}, ∞)); a `continuous` law (the
//!   default) must not jump at a breakpoint by more than 1e-6 of max(|left|, |right|, 1 N).
//! - `Table { x, y }`: piecewise linear through the points (x strictly increasing), and
//!   **linear extrapolation** beyond the ends along the first and last segments.
//!
//! These write S9's strut (cubic spring, piecewise-quartic damper) and leaf element (linear
//! with a bump stop) exactly as docs/scenes.md §2.4 gives them. Evaluating a law allocates
//! nothing.

use flexmbd_core::InvalidValue;
use flexmbd_fe::bounds::{self, Range};
use serde::{Deserialize, Serialize};

/// A force law F(x) (see the module documentation).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Law {
    /// F = 0.
    #[default]
    Zero,
    /// F = Σ c_k (x − about)^k.
    Polynomial {
        /// c₀, c₁, … (N per unit of x^k).
        coefficients: Vec<f64>,
        /// The expansion point x₀ (0 when omitted).
        #[serde(default)]
        about: f64,
    },
    /// Piece i on (b_{i−1}, b_i].
    Piecewise {
        /// The breakpoints b_i, strictly increasing.
        breakpoints: Vec<f64>,
        /// One more piece than breakpoints.
        pieces: Vec<Law>,
        /// Checked continuous at each breakpoint (the default).
        #[serde(default = "yes")]
        continuous: bool,
    },
    /// Piecewise linear through (x_i, y_i), extrapolated linearly beyond the ends.
    Table {
        /// Abscissae, strictly increasing (at least two).
        x: Vec<f64>,
        /// Values (N).
        y: Vec<f64>,
    },
}

fn yes() -> bool {
    true
}

/// The range of a law's numbers (coefficients, abscissae, values): wide, but finite so that
/// every product stays finite.
const LAW_NUMBER: Range = bounds::LAW_NUMBER;

/// The relative jump at a breakpoint a `continuous` law tolerates.
pub const CONTINUITY_TOLERANCE: f64 = 1e-6;

impl Law {
    /// The value F(x) and the slope dF/dx.
    pub fn eval(&self, x: f64) -> (f64, f64) {
        match self {
            Law::Zero => (0.0, 0.0),
            Law::Polynomial {
                coefficients,
                about,
            } => {
                let t = x - about;
                let (mut f, mut df) = (0.0, 0.0);
                for &c in coefficients.iter().rev() {
                    df = df * t + f;
                    f = f * t + c;
                }
                (f, df)
            }
            Law::Piecewise {
                breakpoints,
                pieces,
                ..
            } => pieces[piece_index(breakpoints, x)].eval(x),
            Law::Table { x: xs, y } => {
                let k = segment(xs, x);
                let slope = (y[k + 1] - y[k]) / (xs[k + 1] - xs[k]);
                (y[k] + slope * (x - xs[k]), slope)
            }
        }
    }

    /// ∫ₐᵇ F(x) dx, exact: the polynomials' antiderivatives, piece by piece between the
    /// breakpoints, and the trapezoids of a table.
    pub fn integral(&self, a: f64, b: f64) -> f64 {
        if b < a {
            return -self.integral(b, a);
        }
        match self {
            Law::Zero => 0.0,
            Law::Polynomial {
                coefficients,
                about,
            } => {
                let antiderivative = |t: f64| {
                    coefficients
                        .iter()
                        .enumerate()
                        .rev()
                        .fold(0.0, |acc, (k, &c)| acc * t + c / (k + 1) as f64)
                        * t
                };
                antiderivative(b - about) - antiderivative(a - about)
            }
            Law::Piecewise {
                breakpoints,
                pieces,
                ..
            } => {
                let mut total = 0.0;
                let mut from = a;
                for i in piece_index(breakpoints, a)..pieces.len() {
                    let to = breakpoints.get(i).map_or(b, |&bp| bp.min(b));
                    total += pieces[i].integral(from, to);
                    from = to;
                    if to >= b {
                        break;
                    }
                }
                total
            }
            Law::Table { x: xs, .. } => {
                let mut total = 0.0;
                let mut from = a;
                for k in segment(xs, a)..xs.len() - 1 {
                    let to = if k + 2 < xs.len() {
                        xs[k + 1].min(b)
                    } else {
                        b
                    };
                    let (fa, fb) = (self.eval_on(k, from), self.eval_on(k, to));
                    total += 0.5 * (fa + fb) * (to - from);
                    from = to;
                    if to >= b {
                        break;
                    }
                }
                total
            }
        }
    }

    /// A table's value at x along its segment k.
    fn eval_on(&self, k: usize, x: f64) -> f64 {
        let Law::Table { x: xs, y } = self else {
            return 0.0;
        };
        y[k] + (y[k + 1] - y[k]) / (xs[k + 1] - xs[k]) * (x - xs[k])
    }

    /// Check the law at `field` (e.g. `forces[strut_fl].damper`): finite numbers in range,
    /// breakpoints and table abscissae strictly increasing, lengths that match, a
    /// `continuous` law continuous at its breakpoints.
    pub fn check(&self, field: &str) -> Result<(), InvalidValue> {
        match self {
            Law::Zero => Ok(()),
            Law::Polynomial {
                coefficients,
                about,
            } => {
                let f = format!("{field}.Polynomial");
                if coefficients.is_empty() {
                    return Err(InvalidValue::new(
                        format!("{f}.coefficients"),
                        "[]",
                        "needs at least one coefficient (write `Zero` for no force)",
                    ));
                }
                LAW_NUMBER.check_all(&format!("{f}.coefficients"), coefficients)?;
                bounds::POSITION.check(&format!("{f}.about"), *about)?;
                Ok(())
            }
            Law::Piecewise {
                breakpoints,
                pieces,
                continuous,
            } => check_piecewise(
                &format!("{field}.Piecewise"),
                breakpoints,
                pieces,
                *continuous,
            ),
            Law::Table { x, y } => {
                let f = format!("{field}.Table");
                check_abscissae(&format!("{f}.x"), x, 2, false)?;
                if y.len() != x.len() {
                    return Err(InvalidValue::new(
                        format!("{f}.y"),
                        format!("{} values", y.len()),
                        format!("must have one value per x ({} of them)", x.len()),
                    ));
                }
                LAW_NUMBER.check_all(&format!("{f}.y"), y)
            }
        }
    }
}

/// The piecewise law's checks (see [`Law::check`]).
fn check_piecewise(
    f: &str,
    breakpoints: &[f64],
    pieces: &[Law],
    continuous: bool,
) -> Result<(), InvalidValue> {
    check_abscissae(&format!("{f}.breakpoints"), breakpoints, 0, false)?;
    if pieces.len() != breakpoints.len() + 1 {
        return Err(InvalidValue::new(
            format!("{f}.pieces"),
            format!("{} pieces", pieces.len()),
            format!(
                "must be one more than the breakpoints ({} breakpoints: {} pieces)",
                breakpoints.len(),
                breakpoints.len() + 1
            ),
        ));
    }
    for (i, piece) in pieces.iter().enumerate() {
        piece.check(&format!("{f}.pieces[{i}]"))?;
    }
    if continuous {
        for (i, &b) in breakpoints.iter().enumerate() {
            let (left, right) = (pieces[i].eval(b).0, pieces[i + 1].eval(b).0);
            let scale = left.abs().max(right.abs()).max(1.0);
            if (left - right).abs() > CONTINUITY_TOLERANCE * scale {
                return Err(InvalidValue::new(
                    format!("{f}.breakpoints[{i}]"),
                    bounds::number(b),
                    format!(
                        "the law jumps there: piece {i} gives {left} and piece {} gives {right} \
                         (more than {CONTINUITY_TOLERANCE:e} relative); fix the pieces or write \
                         `continuous: false`",
                        i + 1
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Abscissae at `field`: at least `min_len`, finite, in range, strictly increasing (or,
/// with `steps`, non-decreasing with at most two equal in a row).
pub(crate) fn check_abscissae(
    field: &str,
    x: &[f64],
    min_len: usize,
    steps: bool,
) -> Result<(), InvalidValue> {
    if x.len() < min_len {
        return Err(InvalidValue::new(
            field,
            format!("{} values", x.len()),
            format!("needs at least {min_len}"),
        ));
    }
    bounds::POSITION.check_all(field, x)?;
    for k in 1..x.len() {
        let ok = if steps {
            x[k] >= x[k - 1] && !(k >= 2 && x[k] == x[k - 2])
        } else {
            x[k] > x[k - 1]
        };
        if !ok {
            let rule = if steps {
                "must be non-decreasing, with at most two equal values (a step)"
            } else {
                "must be strictly increasing"
            };
            return Err(InvalidValue::new(
                format!("{field}[{k}]"),
                bounds::number(x[k]),
                format!("{rule}: it follows {}", bounds::number(x[k - 1])),
            ));
        }
    }
    Ok(())
}

/// The piece of x: the number of breakpoints below it (piece i on (b_{i−1}, b_i]).
fn piece_index(breakpoints: &[f64], x: f64) -> usize {
    breakpoints.partition_point(|&b| b < x)
}

/// The table segment [x_k, x_{k+1}] that evaluates x: the one holding it, the first below
/// x₀ and the last above the end.
fn segment(xs: &[f64], x: f64) -> usize {
    xs.partition_point(|&v| v <= x).clamp(1, xs.len() - 1) - 1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strut_damper() -> Law {
        Law::Piecewise {
            breakpoints: vec![-0.20, 0.21],
            pieces: vec![
                Law::Polynomial {
                    coefficients: vec![-416.42, 1844.3],
                    about: 0.0,
                },
                Law::Polynomial {
                    coefficients: vec![0.0, 9945.627, 33955.72, -59832.25, -395651.0],
                    about: 0.0,
                },
                Law::Polynomial {
                    coefficients: vec![1919.1638, 1634.727],
                    about: 0.0,
                },
            ],
            continuous: true,
        }
    }

    fn table() -> Law {
        Law::Table {
            x: vec![-1.0, 0.5, 2.0],
            y: vec![3.0, -1.0, 4.0],
        }
    }

    /// dF/dx against central differences, away from kinks.
    #[test]
    fn slopes_match_finite_differences() {
        for law in [strut_damper(), table()] {
            for &x in &[-0.7, -0.3, -0.1, 0.05, 0.2, 0.3, 1.1, 3.0, -2.0] {
                let h = 1e-6;
                let fd = (law.eval(x + h).0 - law.eval(x - h).0) / (2.0 * h);
                let (_, df) = law.eval(x);
                assert!(
                    (fd - df).abs() <= 1e-6 * (1.0 + df.abs()),
                    "{x}: {fd} vs {df}"
                );
            }
        }
    }

    #[test]
    fn the_strut_damper_gives_the_closed_forms_of_scenes_2_4() {
        let law = strut_damper();
        let v: f64 = 0.1;
        let quartic =
            9945.627 * v + 33955.72 * v.powi(2) - 59832.25 * v.powi(3) - 395651.0 * v.powi(4);
        assert_eq!(law.eval(v).0, quartic);
        assert!((law.eval(-0.5).0 - (-416.42 - 0.5 * 1844.3)).abs() < 1e-12);
        assert!((law.eval(0.5).0 - (1919.1638 + 0.5 * 1634.727)).abs() < 1e-12);
        // Piece i is on (b_{i−1}, b_i]: the breakpoint itself belongs to the left piece.
        assert_eq!(law.eval(0.21).1, {
            let Law::Piecewise { pieces, .. } = &law else {
                unreachable!()
            };
            pieces[1].eval(0.21).1
        });
        assert!(law.check("d").is_ok());
    }

    #[test]
    fn a_table_extrapolates_linearly_beyond_its_ends() {
        let law = table();
        assert_eq!(law.eval(0.5), (-1.0, 5.0 / 1.5));
        assert!((law.eval(-2.0).0 - (3.0 + 4.0 / 1.5)).abs() < 1e-12);
        assert!((law.eval(3.0).0 - (4.0 + 5.0 / 1.5)).abs() < 1e-12);
    }

    #[test]
    fn integrals_match_closed_forms_and_quadrature() {
        let cubic = Law::Polynomial {
            coefficients: vec![1.0, -2.0, 0.5, 3.0],
            about: 0.25,
        };
        let p = |x: f64| {
            let t = x - 0.25;
            t - t * t + 0.5 * t.powi(3) / 3.0 + 0.75 * t.powi(4)
        };
        assert!((cubic.integral(-0.4, 1.3) - (p(1.3) - p(-0.4))).abs() < 1e-12);
        for law in [strut_damper(), table(), cubic] {
            for &(a, b) in &[(-0.9, 0.8), (0.3, -2.5), (1.0, 3.0), (-0.1, -0.05)] {
                let n = 200_000;
                let h = (b - a) / n as f64;
                let simpson: f64 = (0..n)
                    .map(|k| {
                        let x = a + k as f64 * h;
                        h / 6.0
                            * (law.eval(x).0 + 4.0 * law.eval(x + 0.5 * h).0 + law.eval(x + h).0)
                    })
                    .sum();
                let exact = law.integral(a, b);
                assert!(
                    (simpson - exact).abs() < 1e-6 * (1.0 + exact.abs()),
                    "{law:?} on [{a}, {b}]: {exact} vs {simpson}"
                );
            }
        }
    }

    #[test]
    fn a_jump_at_a_breakpoint_of_a_continuous_law_is_refused_with_both_values() {
        let Law::Piecewise {
            breakpoints,
            mut pieces,
            continuous,
        } = strut_damper()
        else {
            unreachable!()
        };
        pieces[2] = Law::Polynomial {
            coefficients: vec![1900.0, 1634.727],
            about: 0.0,
        };
        let law = Law::Piecewise {
            breakpoints,
            pieces,
            continuous,
        };
        let e = law.check("forces[s].damper").unwrap_err().to_string();
        assert!(
            e.contains("forces[s].damper.Piecewise.breakpoints[1]") && e.contains("jumps"),
            "{e}"
        );
        assert!(e.contains("2262.") && e.contains("2243."), "{e}");
        let Law::Piecewise {
            breakpoints,
            pieces,
            ..
        } = law
        else {
            unreachable!()
        };
        let allowed = Law::Piecewise {
            breakpoints,
            pieces,
            continuous: false,
        };
        assert!(allowed.check("d").is_ok());
    }

    #[test]
    fn out_of_order_or_mismatched_data_is_refused_by_field() {
        let bad = Law::Table {
            x: vec![0.0, 1.0, 1.0],
            y: vec![0.0, 1.0, 2.0],
        };
        let e = bad.check("f").unwrap_err().to_string();
        assert!(
            e.contains("f.Table.x[2]") && e.contains("strictly increasing"),
            "{e}"
        );
        let bad = Law::Piecewise {
            breakpoints: vec![0.0],
            pieces: vec![Law::Zero],
            continuous: true,
        };
        let e = bad.check("f").unwrap_err().to_string();
        assert!(
            e.contains("f.Piecewise.pieces") && e.contains("1 pieces"),
            "{e}"
        );
        let bad = Law::Polynomial {
            coefficients: vec![1.0, f64::NAN],
            about: 0.0,
        };
        let e = bad.check("f").unwrap_err().to_string();
        assert!(e.contains("f.Polynomial.coefficients[1]"), "{e}");
        let bad = Law::Piecewise {
            breakpoints: vec![0.3, 0.1],
            pieces: vec![Law::Zero, Law::Zero, Law::Zero],
            continuous: true,
        };
        let e = bad.check("f").unwrap_err().to_string();
        assert!(e.contains("f.Piecewise.breakpoints[1]"), "{e}");
    }
}
