//! Beam cross-sections ([`Section`]) and the constants derived from them
//! ([`SectionProps`]): area, second moments and torsion constant (docs/methods.md §1.2).

use flexmbd_core::InvalidValue;
use serde::{Deserialize, Serialize};

use crate::bounds;

/// Cross-section. Element axes y_e, z_e are those of docs/methods.md §1.2 ("Element axes").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Section {
    /// Solid rectangle: `width` along element y, `height` along element z (m).
    Rectangle {
        /// Extent along element y (m).
        width: f64,
        /// Extent along element z (m).
        height: f64,
    },
    /// Solid circle of diameter d (m).
    Circle {
        /// Diameter (m).
        diameter: f64,
    },
    /// Explicit section constants.
    General {
        /// Area A (m²).
        area: f64,
        /// I_y = ∫ z² dA (m⁴), bending in the x–z plane (w).
        iy: f64,
        /// I_z = ∫ y² dA (m⁴), bending in the x–y plane (v); the in-plane inertia in 2D.
        iz: f64,
        /// Saint-Venant torsion constant J (m⁴).
        torsion_j: f64,
    },
}

/// Derived section constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionProps {
    /// Area (m²).
    pub area: f64,
    /// I_y = ∫ z² dA (m⁴).
    pub iy: f64,
    /// I_z = ∫ y² dA (m⁴).
    pub iz: f64,
    /// Saint-Venant J (m⁴), torsion stiffness.
    pub j: f64,
}

impl SectionProps {
    /// Polar moment I_p = I_y + I_z (m⁴), torsion inertia (methods.md §1.2, "Torsion constants").
    pub fn ip(&self) -> f64 {
        self.iy + self.iz
    }
}

impl Section {
    /// Area, inertias and Saint-Venant torsion constant.
    ///
    /// Rectangle J: the standard approximation (Roark) with long side t₁ and short
    /// side t₂: J = t₁ t₂³ [1/3 − 0.21 (t₂/t₁)(1 − t₂⁴/(12 t₁⁴))]. Circle: J = π d⁴ / 32.
    pub fn props(&self) -> SectionProps {
        match *self {
            Section::Rectangle { width, height } => {
                let (t1, t2) = if width >= height {
                    (width, height)
                } else {
                    (height, width)
                };
                let r = t2 / t1;
                SectionProps {
                    area: width * height,
                    iy: width * height.powi(3) / 12.0,
                    iz: height * width.powi(3) / 12.0,
                    j: t1 * t2.powi(3) * (1.0 / 3.0 - 0.21 * r * (1.0 - r.powi(4) / 12.0)),
                }
            }
            Section::Circle { diameter } => {
                let i = std::f64::consts::PI * diameter.powi(4) / 64.0;
                SectionProps {
                    area: std::f64::consts::PI * diameter * diameter / 4.0,
                    iy: i,
                    iz: i,
                    j: 2.0 * i,
                }
            }
            Section::General {
                area,
                iy,
                iz,
                torsion_j,
            } => SectionProps {
                area,
                iy,
                iz,
                j: torsion_j,
            },
        }
    }
}

/// Every dimension or section constant of `section` positive and in range ([`bounds`]);
/// `field` is its path (`section`, `geometry.members[2].section`).
pub fn check_section(section: &Section, field: &str) -> Result<(), InvalidValue> {
    let (dimension, area, inertia) = (
        bounds::SECTION_DIMENSION,
        bounds::SECTION_AREA,
        bounds::SECTION_INERTIA,
    );
    match *section {
        Section::Rectangle { width, height } => {
            dimension.check(&format!("{field}.width"), width)?;
            dimension.check(&format!("{field}.height"), height)?;
        }
        Section::Circle { diameter } => {
            dimension.check(&format!("{field}.diameter"), diameter)?;
        }
        Section::General {
            area: a,
            iy,
            iz,
            torsion_j,
        } => {
            area.check(&format!("{field}.area"), a)?;
            inertia.check(&format!("{field}.iy"), iy)?;
            inertia.check(&format!("{field}.iz"), iz)?;
            inertia.check(&format!("{field}.torsion_j"), torsion_j)?;
        }
    }
    Ok(())
}
