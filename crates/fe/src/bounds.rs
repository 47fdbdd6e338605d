//! The ranges input values must lie in, in one place, for the FE spec and for the scene
//! (`flexmbd-model` checks its positions, velocities, gravity, drivers and forces against
//! the same constants).
//!
//! A value outside its range is refused when the model is loaded, naming the field, the
//! value and the range, instead of overflowing later into a NaN state or a singular matrix.
//! The bounds are wide: they keep every product the formulations form (stiffness
//! E·I/L³, inertia forces m·ω²·r, penalty terms) finite in `f64`, not physically plausible.
//! The sizes (elements, FE DOFs) are bounded so that the FE model fits in memory (a beam of
//! at least [`SPARSE_FROM_DOFS`] DOFs is reduced on sparse matrices, whose memory grows
//! linearly with its DOFs); a refusal states what the model would need.

use flexmbd_core::InvalidValue;

/// A closed range `[min, max]` with its unit, as named in refusals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Smallest allowed value.
    pub min: f64,
    /// Largest allowed value.
    pub max: f64,
    /// Whether `min` itself is excluded (a strictly positive quantity).
    pub open_min: bool,
    /// SI unit, for the message.
    pub unit: &'static str,
}

impl Range {
    /// The closed range `[min, max]`.
    const fn closed(min: f64, max: f64, unit: &'static str) -> Range {
        Range {
            min,
            max,
            open_min: false,
            unit,
        }
    }

    const fn symmetric(max: f64, unit: &'static str) -> Range {
        Range::closed(-max, max, unit)
    }

    const fn positive(max: f64, unit: &'static str) -> Range {
        Range {
            open_min: true,
            ..Range::closed(0.0, max, unit)
        }
    }

    const fn non_negative(max: f64, unit: &'static str) -> Range {
        Range::closed(0.0, max, unit)
    }

    /// Whether `x` is finite and in the range.
    pub fn contains(&self, x: f64) -> bool {
        x.is_finite()
            && x <= self.max
            && if self.open_min {
                x > self.min
            } else {
                x >= self.min
            }
    }

    /// `Ok(x)` when `x` is in the range, else a refusal of `field` naming the value and range.
    pub fn check(&self, field: &str, x: f64) -> Result<f64, InvalidValue> {
        if self.contains(x) {
            return Ok(x);
        }
        let what = if x.is_finite() {
            "out of range"
        } else {
            "must be finite"
        };
        Err(InvalidValue::new(
            field,
            number(x),
            format!("{what}: allowed {self}"),
        ))
    }

    /// Each component of `v` (named `field[k]`) in the range.
    pub fn check_all(&self, field: &str, v: &[f64]) -> Result<(), InvalidValue> {
        for (k, x) in v.iter().enumerate() {
            self.check(&format!("{field}[{k}]"), *x)?;
        }
        Ok(())
    }
}

impl std::fmt::Display for Range {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let open = if self.open_min { '(' } else { '[' };
        let bound = |x: f64| {
            if x == 0.0 || x.abs() == 1.0 {
                format!("{x}")
            } else {
                format!("{x:e}")
            }
        };
        write!(
            f,
            "{open}{}, {}] {}",
            bound(self.min),
            bound(self.max),
            self.unit
        )
    }
}

/// `x` as written in a refusal: plain when of moderate size, else in scientific notation
/// (`1e308`, not 309 digits).
pub fn number(x: f64) -> String {
    let a = x.abs();
    if x.is_finite() && a != 0.0 && !(1e-4..1e16).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// Coordinates of a point (markers, ground markers, body origins, centres of mass, polyline
/// points) and lengths (free length of a spring), m.
pub const POSITION: Range = Range::symmetric(1e6, "m");
/// The length of one finite element (segment length / elements per segment), m: above zero
/// by enough that E·I/L³ stays finite.
pub const ELEMENT_LENGTH: Range = Range::closed(1e-6, 2e6, "m");
/// A body's initial linear velocity components, m/s.
pub const VELOCITY: Range = Range::symmetric(1e4, "m/s");
/// A body's initial angular velocity components and driver rates, rad/s.
pub const ANGULAR_VELOCITY: Range = Range::symmetric(1e4, "rad/s");
/// Gravity components, m/s².
pub const GRAVITY: Range = Range::symmetric(1e4, "m/s²");
/// Angles (orientations, driver phases), rad.
pub const ANGLE: Range = Range::symmetric(1e6, "rad");
/// Components of a direction vector (axes); its norm must also reach [`MIN_AXIS_NORM`].
pub const AXIS_COMPONENT: Range = Range::symmetric(1e6, "");
/// The smallest norm of a direction vector that is normalised on use.
pub const MIN_AXIS_NORM: f64 = 1e-6;
/// Young's and shear moduli, Pa. Bounded below as well: a modulus or density near the
/// smallest `f64` (1e-308) makes the FE matrices subnormal, and the eigensolver then spends
/// seconds in subnormal arithmetic before it gives up (found by the fuzzer).
pub const MODULUS: Range = Range::closed(1.0, 1e15, "Pa");
/// Density, kg/m³ (bounded below as [`MODULUS`] is).
pub const DENSITY: Range = Range::closed(1e-3, 1e6, "kg/m³");
/// Section dimensions (width, height, diameter), m.
pub const SECTION_DIMENSION: Range = Range::closed(1e-6, 1e3, "m");
/// Section area, m².
pub const SECTION_AREA: Range = Range::closed(1e-12, 1e6, "m²");
/// Section second moments and torsion constant, m⁴.
pub const SECTION_INERTIA: Range = Range::closed(1e-24, 1e12, "m⁴");
/// Stiffness-proportional damping coefficients a_K, s.
pub const DAMPING_COEFFICIENT: Range = Range::non_negative(1e3, "s");
/// Modal damping ratio ζ.
pub const DAMPING_RATIO: Range = Range::non_negative(1e3, "");
/// The mass of a rigid body, kg.
pub const MASS: Range = Range::closed(1e-9, 1e12, "kg");
/// Components of an inertia tensor, kg·m².
pub const INERTIA: Range = Range::symmetric(1e15, "kg·m²");
/// Spring stiffness, N/m.
pub const SPRING_STIFFNESS: Range = Range::non_negative(1e15, "N/m");
/// Damper coefficient, N·s/m.
pub const SPRING_DAMPING: Range = Range::non_negative(1e15, "N·s/m");
/// The numbers of a force law (polynomial coefficients, table values), in the units of the
/// law.
pub const LAW_NUMBER: Range = Range::symmetric(1e15, "");
/// A tyre's unloaded radius, m.
pub const TYRE_RADIUS: Range = Range::positive(1e3, "m");
/// A tyre's radial stiffness, N/m.
pub const TYRE_STIFFNESS: Range = Range::positive(1e15, "N/m");
/// A road's lengths (the cosine bump's length), m.
pub const ROAD_LENGTH: Range = Range::positive(1e6, "m");
/// Initial modal coordinates (their scale is that of the modes: metres for the static modes).
pub const MODAL_COORDINATE: Range = Range::symmetric(1e6, "");
/// A driver's amplitude, rad or m.
pub const AMPLITUDE: Range = Range::symmetric(1e6, "rad or m");
/// A driver's frequency, Hz.
pub const FREQUENCY: Range = Range::symmetric(1e4, "Hz");
/// A time constant (the spin-up time), s: at least a nanosecond (a spin-up time of
/// 1e-308 s made Ωs/Ts infinite and the hub's angle NaN at t = 0, found by the fuzzer).
pub const TIME_CONSTANT: Range = Range::closed(1e-9, 1e6, "s");
/// The solver's times: step, duration, output interval, s (a step of 1e308 s made
/// t = 1e308 s and a singular leading matrix instead of a refusal).
pub const SOLVER_TIME: Range = Range::positive(1e6, "s");

/// The Newton tolerance ε (relative in q, absolute in Φ): at most 1, a tolerance that
/// accepts anything.
pub const NEWTON_TOLERANCE: Range = Range::positive(1.0, "");
/// An explicit penalty factor α (docs/methods.md §5.3): large enough for any scene, small
/// enough that α·Φ stays finite.
pub const PENALTY: Range = Range::positive(1e30, "");

/// The largest Newton iteration limit per step: a step that diverges ends after at most this
/// many iterations.
pub const MAX_NEWTON_ITERATIONS: usize = 10_000;

/// Beams with at least this many FE DOFs are reduced on sparse matrices
/// ([`crate::sparse_reduction`]); below it, on dense N × N matrices
/// ([`crate::craig_bampton`]), whose memory (8 N² bytes each, 32 MB at 2 000 DOFs) and
/// time (N³) grow too fast beyond it.
pub const SPARSE_FROM_DOFS: usize = 2_000;

/// The most FE DOFs one beam may have: the sparse reduction's memory is about
/// [`SPARSE_BYTES_PER_DOF`] per DOF (3 GB at 10⁶ DOFs; [`sparse_beam_bytes`]).
pub const MAX_FE_DOFS: usize = 1_000_000;

/// Peak memory of a beam's sparse preprocessing per FE DOF, bytes: the peak RSS
/// (`/usr/bin/time -v`, release, `examples/large_beam.rs`) of a 3D grillage with 6 static
/// and 6 normal modes was 684 MB at 240 000 DOFs (2.9 kB per DOF) and 92.6 MB at 23 814
/// (3.9 kB per DOF, the process's fixed part included): the sparse K and M and their
/// interior blocks, the Cholesky factor of K_ii, the Lanczos basis (N × 24 twice), the mode
/// matrix (N × n), the mass cloud and the per-element stiffening data.
pub const SPARSE_BYTES_PER_DOF: u128 = 3_000;

/// Estimated peak memory of the sparse preprocessing of a beam of `n` FE DOFs, bytes,
/// saturating (for messages).
pub fn sparse_beam_bytes(n: u128) -> u128 {
    n.saturating_mul(SPARSE_BYTES_PER_DOF)
}

/// Why a beam of `n` > [`MAX_FE_DOFS`] FE DOFs is refused: memory.
pub fn too_many_dofs(n: u128) -> String {
    format!(
        "at most {MAX_FE_DOFS} FE DOFs are allowed, for memory: reduced on sparse matrices \
         this beam would need about {} ({SPARSE_BYTES_PER_DOF} bytes per DOF), its dense \
         stiffness and mass matrices {} each",
        human_bytes(sparse_beam_bytes(n)),
        human_bytes(n.saturating_mul(n).saturating_mul(8))
    )
}

/// Bytes of one dense N × N matrix of `f64`, saturating (for messages).
pub fn dense_matrix_bytes(n: usize) -> u128 {
    let n = n as u128;
    n.saturating_mul(n).saturating_mul(8)
}

/// A byte count in words: "3.2 GB", "512 MB", "12 kB".
pub fn human_bytes(bytes: u128) -> String {
    const UNITS: [(&str, f64); 4] = [("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)];
    let b = bytes as f64;
    if b >= 1e15 {
        return format!("{b:.1e} bytes");
    }
    for (unit, size) in UNITS {
        if b >= size {
            return format!("{:.1} {unit}", b / size);
        }
    }
    format!("{bytes} B")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_range_refuses_non_finite_and_outside_values_naming_the_range() {
        assert!(MODULUS.check("E", 2.1e11).is_ok());
        let e = MODULUS.check("E", 1e20).unwrap_err().to_string();
        assert_eq!(e, "E = 1e20: out of range: allowed [1, 1e15] Pa");
        let e = POSITION.check("p", f64::NAN).unwrap_err().to_string();
        assert!(e.contains("must be finite"), "{e}");
        assert!(MODULUS.check("E", 0.0).is_err());
        assert!(SPRING_STIFFNESS.check("k", 0.0).is_ok());
    }

    #[test]
    fn byte_counts_read_in_units() {
        assert_eq!(human_bytes(dense_matrix_bytes(100_000)), "80.0 GB");
        assert_eq!(human_bytes(12), "12 B");
        assert_eq!(dense_matrix_bytes(usize::MAX), u128::MAX);
        assert_eq!(human_bytes(u128::MAX), "3.4e38 bytes");
        assert_eq!(number(1e308), "1e308");
        assert_eq!(number(-9.81), "-9.81");
    }
}
