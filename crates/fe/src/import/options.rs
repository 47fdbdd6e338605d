//! Import options: unit scales and point masses (docs/import.md, "Options").
//!
//! Each scale multiplies exactly what it names, once, after reading:
//! - `length_scale`: every node coordinate (x_SI = length_scale · x_file);
//! - `mass_scale`: every entry of M;
//! - `stiffness_scale`: every entry of K.
//!
//! For a model of translational DOFs only (solids) in a consistent unit system with
//! seconds, the factors that convert to SI are the length and mass units in metres
//! and kilograms: mm/t/s/N gives `length_scale = 1e-3`, `mass_scale = 1e3`
//! (t → kg) and `stiffness_scale = 1e3` (N/mm → N/m); ω² = k/m is unchanged, as it
//! must be. Rotational rows and columns scale differently (K_rr in N·mm/rad → ×1e-3,
//! K_tr ×1), which uniform factors cannot express: convert such models before export.
//! `stiffness_scale` alone is also the stiffness scale of a design study: every
//! frequency scales by its square root.
//!
//! Point masses are added after the scales, in SI units: `mass` (kg) on each
//! translational DOF of the node, `inertia` (kg·m², about the node, global axes,
//! [Ixx, Iyy, Izz, Ixy, Iyz, Izx]) on its rotational DOFs, which must then all exist.

use nalgebra::Matrix3;
use serde::{Deserialize, Deserializer, Serialize};

use flexmbd_core::{InvalidValue, require_positive};

/// Options applied to an imported model (serde: every field optional).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ImportOptions {
    /// Factor on every node coordinate (file length unit in metres; default 1).
    pub length_scale: f64,
    /// Factor on every entry of M (file mass unit in kilograms; default 1).
    pub mass_scale: f64,
    /// Factor on every entry of K (default 1).
    pub stiffness_scale: f64,
    /// Point masses added to M after scaling (default none).
    pub point_masses: Vec<PointMass>,
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions {
            length_scale: 1.0,
            mass_scale: 1.0,
            stiffness_scale: 1.0,
            point_masses: Vec::new(),
        }
    }
}

/// A point mass at a node (SI units).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointMass {
    /// Node id as in the file (an integer or a string such as `"PART-1-1.12"`).
    #[serde(deserialize_with = "node_id")]
    pub node: String,
    /// Mass (kg), added to each translational DOF of the node.
    pub mass: f64,
    /// Rotational inertia about the node in global axes (kg·m²),
    /// [Ixx, Iyy, Izz, Ixy, Iyz, Izx]; the node needs Rx, Ry and Rz.
    #[serde(default)]
    pub inertia: Option<[f64; 6]>,
}

impl PointMass {
    /// The inertia tensor, if any.
    pub fn inertia_tensor(&self) -> Option<Matrix3<f64>> {
        self.inertia
            .map(|[xx, yy, zz, xy, yz, zx]| Matrix3::new(xx, xy, zx, xy, yy, yz, zx, yz, zz))
    }
}

fn node_id<'de, D: Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Id {
        Int(i64),
        Text(String),
    }
    Ok(match Id::deserialize(d)? {
        Id::Int(i) => i.to_string(),
        Id::Text(s) => s,
    })
}

impl ImportOptions {
    /// Refuse scales that are not finite and positive, and point masses that are not
    /// physical (mass ≤ 0, inertia not symmetric positive semi-definite).
    pub fn validate(&self) -> Result<(), InvalidValue> {
        require_positive("length_scale", self.length_scale)?;
        require_positive("mass_scale", self.mass_scale)?;
        require_positive("stiffness_scale", self.stiffness_scale)?;
        for (k, pm) in self.point_masses.iter().enumerate() {
            require_positive(&format!("point_masses[{k}].mass"), pm.mass)?;
            if let Some(j) = pm.inertia_tensor() {
                let field = format!("point_masses[{k}].inertia");
                let value = format!("{:?}", pm.inertia.unwrap_or_default());
                if j.iter().any(|v| !v.is_finite()) {
                    return Err(InvalidValue::new(field, value, "must be finite"));
                }
                let min = j.symmetric_eigenvalues().min();
                if min < -1e-12 * j.abs().max() {
                    return Err(InvalidValue::new(
                        field,
                        value,
                        format!("is not positive semi-definite (eigenvalue {min:e})"),
                    ));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deserialises_with_defaults_and_either_kind_of_node_id() {
        let o: ImportOptions = ron::from_str(
            "(length_scale: 1e-3, point_masses: [(node: 12, mass: 2.0), \
             (node: \"PART-1-1.3\", mass: 1.0, inertia: Some((1, 1, 1, 0, 0, 0)))])",
        )
        .unwrap();
        assert_eq!(o.length_scale, 1e-3);
        assert_eq!(o.mass_scale, 1.0);
        assert_eq!(o.point_masses[0].node, "12");
        assert_eq!(o.point_masses[1].node, "PART-1-1.3");
        assert!(o.validate().is_ok());
        assert!(ron::from_str::<ImportOptions>("(lenght_scale: 1)").is_err());
    }

    #[test]
    fn refuses_unphysical_options() {
        let mut o = ImportOptions {
            stiffness_scale: 0.0,
            ..ImportOptions::default()
        };
        assert_eq!(o.validate().unwrap_err().field, "stiffness_scale");
        o.stiffness_scale = f64::NAN;
        assert_eq!(o.validate().unwrap_err().field, "stiffness_scale");
        o.stiffness_scale = 1.0;
        o.point_masses.push(PointMass {
            node: "1".into(),
            mass: 1.0,
            inertia: Some([1.0, 1.0, 1.0, 5.0, 0.0, 0.0]),
        });
        let e = o.validate().unwrap_err();
        assert_eq!(e.field, "point_masses[0].inertia");
        o.point_masses[0].inertia = None;
        o.point_masses[0].mass = -1.0;
        assert_eq!(o.validate().unwrap_err().field, "point_masses[0].mass");
    }
}
