//! Roads: ground profiles z = h(x) of the ground x coordinate, the same for every y, on
//! which tyres roll (docs/methods.md §2.6, docs/scenes.md §3.2 and §3.5).
//!
//! - `Flat`: h = 0.
//! - `CosineBump { start, length, height }`: h(x) = height/2 · (1 − cos(2π(x − start)/length))
//!   on [start, start + length], 0 elsewhere (the IAVSD benchmark bump, S9 GroundContact.c).
//! - `Table { x, z }`: piecewise linear through (x_i, z_i), constant beyond the ends; x is
//!   non-decreasing and a value repeated (at most twice) is a step, where the road takes
//!   the right-hand value (h is continuous from the right).
//!
//! Evaluating a profile allocates nothing.

use std::f64::consts::PI;

use flexmbd_core::InvalidValue;
use flexmbd_fe::bounds;
use serde::{Deserialize, Serialize};

use crate::laws::check_abscissae;

/// A named road.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Road {
    /// Name, unique among roads; tyres name it.
    pub name: String,
    /// Its profile.
    pub profile: Profile,
}

/// How a tyre meets its road (docs/methods.md §2.6).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Contact {
    /// A point under the wheel centre W: F = K δ e_z, δ = R − (z_W − h(x_W)), while δ > 0
    /// (docs/scenes.md §2.5).
    #[default]
    Vertical,
    /// Radial, normal to the local profile (S9 GroundContact.c, docs/scenes.md §3.2):
    /// with s = h'(x_W) and H = √(1 + s²), F = K (R − (z_W − h))/H along
    /// n = (−s, 0, 1)/H while h(x_W) > z_W − R; equal to `Vertical` on a flat road.
    ProfileNormal,
}

/// A road profile z = h(x) (see the module documentation).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Profile {
    /// h = 0.
    #[default]
    Flat,
    /// One cosine bump.
    CosineBump {
        /// Ground x where it begins (m).
        start: f64,
        /// Its length along x (m, positive).
        length: f64,
        /// Its height (m; negative: a hollow).
        height: f64,
    },
    /// Piecewise linear, constant beyond the ends.
    Table {
        /// Ground x (m), non-decreasing; a repeated value is a step.
        x: Vec<f64>,
        /// Height at each x (m).
        z: Vec<f64>,
    },
}

impl Profile {
    /// The height h(x) and the slope h'(x) (0 at a step and beyond a table's ends).
    pub fn eval(&self, x: f64) -> (f64, f64) {
        match self {
            Profile::Flat => (0.0, 0.0),
            &Profile::CosineBump {
                start,
                length,
                height,
            } => {
                if x < start || x > start + length {
                    return (0.0, 0.0);
                }
                let w = 2.0 * PI / length;
                let phase = w * (x - start);
                (
                    0.5 * height * (1.0 - phase.cos()),
                    0.5 * height * w * phase.sin(),
                )
            }
            Profile::Table { x: xs, z } => {
                let after = xs.partition_point(|&v| v <= x);
                if after == 0 {
                    return (z[0], 0.0);
                }
                if after == xs.len() {
                    return (z[xs.len() - 1], 0.0);
                }
                let k = after - 1;
                let slope = (z[k + 1] - z[k]) / (xs[k + 1] - xs[k]);
                (z[k] + slope * (x - xs[k]), slope)
            }
        }
    }

    /// Check the profile at `field` (e.g. `roads[left].profile`).
    pub fn check(&self, field: &str) -> Result<(), InvalidValue> {
        match self {
            Profile::Flat => Ok(()),
            Profile::CosineBump {
                start,
                length,
                height,
            } => {
                let f = format!("{field}.CosineBump");
                bounds::POSITION.check(&format!("{f}.start"), *start)?;
                bounds::ROAD_LENGTH.check(&format!("{f}.length"), *length)?;
                bounds::POSITION.check(&format!("{f}.height"), *height)?;
                Ok(())
            }
            Profile::Table { x, z } => {
                let f = format!("{field}.Table");
                check_abscissae(&format!("{f}.x"), x, 1, true)?;
                if z.len() != x.len() {
                    return Err(InvalidValue::new(
                        format!("{f}.z"),
                        format!("{} values", z.len()),
                        format!("must have one height per x ({} of them)", x.len()),
                    ));
                }
                bounds::POSITION.check_all(&format!("{f}.z"), z)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cosine_bump_is_the_benchmark_profile() {
        let bump = Profile::CosineBump {
            start: 0.97,
            length: 5.0,
            height: 0.2,
        };
        // S9 GroundContact.c: 0.1 (1 − cos(2π(x − 0.97)/5)), slope 0.2π/5 sin(…).
        for &x in &[1.0, 2.3, 3.47, 5.0, 5.9] {
            let phase = 2.0 * PI * (x - 0.97) / 5.0;
            let (h, s) = bump.eval(x);
            assert!((h - 0.1 * (1.0 - phase.cos())).abs() < 1e-15);
            assert!((s - 0.2 * PI / 5.0 * phase.sin()).abs() < 1e-15);
        }
        assert_eq!(bump.eval(3.47).0, 0.2);
        assert_eq!(bump.eval(0.5), (0.0, 0.0));
        assert_eq!(bump.eval(6.0), (0.0, 0.0));
    }

    #[test]
    fn a_table_ramps_steps_and_stays_constant_beyond_its_ends() {
        let ramp = Profile::Table {
            x: vec![0.0, 3.0, 4.0, 10.0, 10.0, 20.0, 20.0],
            z: vec![0.0, 0.0, 0.1, 0.1, 0.0, 0.0, -0.1],
        };
        assert_eq!(ramp.eval(-5.0), (0.0, 0.0));
        let (h, s) = ramp.eval(3.5);
        assert!((h - 0.05).abs() < 1e-15 && (s - 0.1).abs() < 1e-15);
        assert_eq!(ramp.eval(9.999).0, 0.1);
        assert_eq!(ramp.eval(10.0), (0.0, 0.0));
        assert_eq!(ramp.eval(20.0), (-0.1, 0.0));
        assert_eq!(ramp.eval(25.0), (-0.1, 0.0));
    }

    #[test]
    fn bad_profiles_are_refused_by_field_and_value() {
        let three = Profile::Table {
            x: vec![0.0, 1.0, 1.0, 1.0],
            z: vec![0.0; 4],
        };
        let e = three.check("roads[r].profile").unwrap_err().to_string();
        assert!(e.contains("roads[r].profile.Table.x[3]"), "{e}");
        let back = Profile::Table {
            x: vec![0.0, 2.0, 1.0],
            z: vec![0.0; 3],
        };
        let e = back.check("p").unwrap_err().to_string();
        assert!(
            e.contains("p.Table.x[2]") && e.contains("non-decreasing"),
            "{e}"
        );
        let flat = Profile::CosineBump {
            start: 0.0,
            length: 0.0,
            height: 0.1,
        };
        let e = flat.check("p").unwrap_err().to_string();
        assert!(e.contains("p.CosineBump.length"), "{e}");
    }
}
