//! The description of a uniform cable clamped to a driven hub (docs/methods.md §7.3;
//! docs/scenes.md §5 for the spin-up data), with validation that names the bad field.

use flexmbd_core::{Dim, InvalidValue, require_non_negative, require_positive};
use serde::{Deserialize, Serialize};

/// A uniform ANCF cable along +x from the origin, its root clamped to a hub turning
/// about z with the spin-up law θ(t) of docs/methods.md §6.5.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CableSpec {
    /// Planar (x–y) or spatial.
    pub dim: Dim,
    /// Beam length L (m).
    pub length: f64,
    /// Axial stiffness EA (N).
    pub ea: f64,
    /// Bending stiffness EI (N·m², isotropic in 3D).
    pub ei: f64,
    /// Mass per unit length ρA (kg/m).
    pub rho_a: f64,
    /// Number of equal elements.
    pub elements: usize,
    /// Gravity (m/s²); in 2D the z component must be 0.
    pub gravity: [f64; 3],
    /// Final hub speed Ω_s (rad/s); 0 holds the hub still (a cantilever).
    pub omega_s: f64,
    /// Spin-up time T_s (s).
    pub t_s: f64,
}

impl CableSpec {
    /// The spin-up beam of docs/scenes.md §5: L = 10 m, EA = 2.8e7 N, EI = 1.4e4 N·m²,
    /// ρA = 1.2 kg/m, Ω_s = 6 rad/s, T_s = 15 s; 2D without gravity, 3D with g = 9.81 m/s²
    /// along −z.
    pub fn spin_up_beam(dim: Dim, elements: usize) -> Self {
        CableSpec {
            dim,
            length: 10.0,
            ea: 2.8e7,
            ei: 1.4e4,
            rho_a: 1.2,
            elements,
            gravity: match dim {
                Dim::Planar => [0.0; 3],
                Dim::Spatial => [0.0, 0.0, -9.81],
            },
            omega_s: 6.0,
            t_s: 15.0,
        }
    }

    /// The static check of docs/methods.md §7.3 (Exudyn ANCFCable example): a 2 m cantilever,
    /// ρA = 78 kg/m, EA = 1e6 N, EI = 1e4/12 = 833.333… N·m², g = 9.81 m/s² along −y.
    /// The example sets `EI = 833.3333333333333`; the rounded 833.333 of methods.md
    /// moves the tip by 2.3e-7 m.
    pub fn exudyn_cantilever(dim: Dim, elements: usize) -> Self {
        CableSpec {
            dim,
            length: 2.0,
            ea: 1e6,
            ei: 1e4 / 12.0,
            rho_a: 78.0,
            elements,
            gravity: [0.0, -9.81, 0.0],
            omega_s: 0.0,
            t_s: 1.0,
        }
    }

    /// Refuse non-physical values, naming the field.
    pub fn validate(&self) -> Result<(), InvalidValue> {
        require_positive("length", self.length)?;
        require_positive("ea", self.ea)?;
        require_positive("ei", self.ei)?;
        require_positive("rho_a", self.rho_a)?;
        if self.elements == 0 {
            return Err(InvalidValue::new("elements", 0, "must be at least 1"));
        }
        for (k, g) in self.gravity.iter().enumerate() {
            if !g.is_finite() {
                return Err(InvalidValue::new(
                    format!("gravity[{k}]"),
                    g,
                    "must be finite",
                ));
            }
        }
        if self.dim == Dim::Planar && self.gravity[2] != 0.0 {
            return Err(InvalidValue::new(
                "gravity[2]",
                self.gravity[2],
                "must be 0 for a planar (2D) cable",
            ));
        }
        if !self.omega_s.is_finite() {
            return Err(InvalidValue::new("omega_s", self.omega_s, "must be finite"));
        }
        require_positive("t_s", self.t_s)?;
        Ok(())
    }
}

/// Refuse a bad step, duration or output interval of [`crate::run_spin_up`].
pub(crate) fn validate_run(
    h: f64,
    duration: f64,
    output_interval: f64,
) -> Result<(), InvalidValue> {
    require_positive("step", h)?;
    require_non_negative("duration", duration)?;
    require_positive("output_interval", output_interval)?;
    if output_interval < h * (1.0 - 1e-9) {
        return Err(InvalidValue::new(
            "output_interval",
            output_interval,
            format!("must not be shorter than the step {h}"),
        ));
    }
    Ok(())
}
