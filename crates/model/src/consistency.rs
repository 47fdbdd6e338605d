//! The checks of a scene as a whole, done once at load for every formulation alike: joined
//! markers coincide at t = 0, a joint takes at most one driver, there is a body to move, and
//! the sizes the formulations will allocate (substructures, coordinates) are bounded, each
//! refusal stating the memory the scene would need.

use flexmbd_core::{Dim, InvalidValue};
use flexmbd_fe::bounds::{dense_matrix_bytes, human_bytes};

use crate::error::ModelError;
use crate::scene::{BodyModel, JointKind, Scene, Stiffening};

/// The largest distance (m) between two joined markers at t = 0 that counts as coincident
/// (the absolute formulation's shared points are exact to this).
pub const COINCIDENCE_TOLERANCE: f64 = 1e-6;

/// The most substructures `Stiffening::Substructuring(n)` may split a beam into.
pub const MAX_SUBSTRUCTURES: usize = 1_000;

/// The most coordinates a scene may have (rigid-body DOFs and modal coordinates of every
/// body, after the stiffening rewrite): the formulations hold dense matrices of this size.
pub const MAX_COORDINATES: usize = 4_000;

impl Scene {
    /// Every revolute, spherical, universal and rigid joint joins markers that coincide at
    /// t = 0 (within [`COINCIDENCE_TOLERANCE`]); in a planar scene only x and y count.
    /// Prismatic and cylindrical joints slide, Free joints join nothing.
    pub(crate) fn check_joined_markers_coincide(&self) -> Result<(), ModelError> {
        for j in &self.joints {
            let shares_a_point = matches!(
                j.kind,
                JointKind::Revolute { .. }
                    | JointKind::Spherical
                    | JointKind::Universal { .. }
                    | JointKind::Rigid
            );
            if !shares_a_point {
                continue;
            }
            let (Some(p1), Some(p2)) = (
                self.marker_global(&j.body1, &j.marker1),
                self.marker_global(&j.body2, &j.marker2),
            ) else {
                continue; // names are checked with the joint
            };
            let gap = (p2 - p1).norm();
            if gap.is_nan() || gap > COINCIDENCE_TOLERANCE {
                let at = |p: nalgebra::Vector3<f64>| match self.dim {
                    Dim::Planar => format!("({:.6}, {:.6})", p.x, p.y),
                    Dim::Spatial => format!("({:.6}, {:.6}, {:.6})", p.x, p.y, p.z),
                };
                return Err(self.invalid(InvalidValue::new(
                    format!("joints[{}].marker2", j.name),
                    format!("{}.{} at {}", j.body2, j.marker2, at(p2)),
                    format!(
                        "does not coincide with {}.{} at {} (distance {gap:.3e} m, tolerance \
                         {COINCIDENCE_TOLERANCE:e} m): joined markers must coincide at t = 0",
                        j.body1,
                        j.marker1,
                        at(p1)
                    ),
                )));
            }
        }
        Ok(())
    }

    /// No joint has two drivers (the second would be ignored by one formulation and
    /// over-constrain the other).
    pub(crate) fn check_one_driver_per_joint(&self) -> Result<(), ModelError> {
        for (k, d) in self.drivers.iter().enumerate() {
            if let Some(first) = self.drivers[..k].iter().find(|e| e.joint == d.joint) {
                return Err(self.invalid(InvalidValue::new(
                    format!("drivers[{}].joint", d.name),
                    &d.joint,
                    format!(
                        "joint `{}` is already driven by `{}`: a joint takes one driver",
                        d.joint, first.name
                    ),
                )));
            }
        }
        Ok(())
    }

    /// At least one moving body; at most [`MAX_SUBSTRUCTURES`] substructures; at most
    /// [`MAX_COORDINATES`] coordinates after the stiffening rewrite. Runs after the bodies
    /// are checked (their FE meshes are then bounded, so the counts below cannot overflow).
    pub(crate) fn check_sizes(&self) -> Result<(), ModelError> {
        if self.bodies.is_empty() {
            return Err(self.invalid(InvalidValue::new(
                "bodies",
                "[]",
                "the scene has no moving body",
            )));
        }
        let coordinates = self.coordinate_estimate();
        let need = || {
            format!(
                "the scene would have about {coordinates} coordinates, whose dense \
                 {coordinates} × {coordinates} matrices need {} each",
                human_bytes(dense_matrix_bytes(coordinates))
            )
        };
        if let Stiffening::Substructuring(n) = self.solver.stiffening
            && n > MAX_SUBSTRUCTURES
        {
            return Err(self.invalid(InvalidValue::new(
                "solver.stiffening",
                format!("Substructuring({n})"),
                format!(
                    "too many substructures: at most {MAX_SUBSTRUCTURES}; {}",
                    need()
                ),
            )));
        }
        if coordinates > MAX_COORDINATES {
            return Err(self.invalid(InvalidValue::new(
                "bodies",
                format!("{} bodies", self.bodies.len()),
                format!(
                    "too large: {}; at most {MAX_COORDINATES} are allowed",
                    need()
                ),
            )));
        }
        Ok(())
    }

    /// The coordinates the scene will have once rewritten for its stiffening method:
    /// per body its rigid-body DOFs and its modal coordinates (FNL2 adds a static mode per
    /// node, SBn makes n bodies of a flexible beam, each with the rigid-body DOFs, the
    /// static modes of one node and one or two normal modes). Saturating.
    fn coordinate_estimate(&self) -> usize {
        let rigid = self.dim.n_rigid();
        let per_substructure = 2 * rigid + if self.dim == Dim::Planar { 1 } else { 2 };
        self.bodies
            .iter()
            .map(|b| match &b.model {
                BodyModel::Beam(spec) if b.flexible => match self.solver.stiffening {
                    Stiffening::Substructuring(n) => n.saturating_mul(per_substructure),
                    s => {
                        let axial = if s == Stiffening::Fnl2 {
                            spec.n_nodes()
                        } else {
                            spec.axial_modes
                        };
                        rigid
                            .saturating_add(spec.boundary.len())
                            .saturating_add(spec.normal_modes)
                            .saturating_add(axial)
                    }
                },
                _ => rigid.saturating_add(b.declared_modes()),
            })
            .fold(0usize, usize::saturating_add)
    }
}
