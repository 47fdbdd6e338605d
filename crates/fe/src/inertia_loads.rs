//! The load distributions a body's motion puts on its interior DOFs (docs/methods.md §1.6):
//! the inputs of the participation ranking ([`crate::participation`]) and of the
//! load-dependent Ritz basis ([`crate::ritz`]).
//!
//! A reduced body is excited through its rigid-body (frame) motion and its interfaces.
//! With the body frame accelerating, every point feels the inertia load −ρ a(r̄) of a
//! field a(r̄) linear in the undeformed position r̄:
//!
//! - translation a = ā (gravity acts the same way): one field per body axis;
//! - angular acceleration (Euler load) a = α × r̄, with node rotation α: one field per
//!   rotation axis (2D: z only);
//! - centrifugal a = ω × (ω × r̄) = (ω ωᵀ − |ω|² I) r̄: over all ω these span S r̄ for every
//!   symmetric S (3D: six fields e_a r̄_b + e_b r̄_a, a ≤ b; 2D, ω ∥ z only: (x, y)), with
//!   no node rotation (a symmetric gradient has no rotation part).
//!
//! An interface (static-mode) acceleration η̈_k moves the body as the static mode X_s,k.
//! The consistent nodal load of a field u is f = (M u) restricted to the interior rows
//! i — the coupling mass M_ir u_r + M_ib u_b + M_ii u_i (for a static mode, the M_ib
//! coupling of the Craig–Bampton mass matrix). The fields that depend on position are
//! divided by the largest node distance R from the body origin, so that every field moves
//! the body by at most one unit: the loads are then comparable in size, and the ranking and
//! the pivoting of the Ritz sequence do not depend on the unit of length.
//!
//! The body does not know which of these motions its scene drives: it takes them all
//! (a scene that never accelerates the body along x still gets the axial fields).

use flexmbd_core::Dim;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use crate::assembly::{DofSets, Mesh};

/// The interior load distributions (n_i × L, one column per field) of `mesh` with free-floating
/// mass `m`, split `sets` and static modes `x_static` (N × n_b): translations, rotations
/// (Euler), centrifugal fields and the interface fields, in that order.
pub fn inertia_loads(
    mesh: &Mesh,
    m: &DMatrix<f64>,
    sets: &DofSets,
    x_static: &DMatrix<f64>,
) -> DMatrix<f64> {
    let fields = rigid_fields(mesh);
    let n_fields = fields.len() + x_static.ncols();
    let mut loads = DMatrix::zeros(sets.i.len(), n_fields);
    let all = fields
        .into_iter()
        .chain(x_static.column_iter().map(|c| c.into_owned()));
    for (l, u) in all.enumerate() {
        let f = m * u;
        for (a, &dof) in sets.i.iter().enumerate() {
            loads[(a, l)] = f[dof];
        }
    }
    loads
}

/// The rigid-acceleration fields over all N DOFs, in the order of [`inertia_loads`].
fn rigid_fields(mesh: &Mesh) -> Vec<DVector<f64>> {
    let r_max = mesh.nodes.iter().map(|r| r.norm()).fold(0.0, f64::max);
    let scale = if r_max > 0.0 { 1.0 / r_max } else { 1.0 };
    let zero = Vector3::zeros();
    let (translations, rotations): (&[usize], &[usize]) = match mesh.dim {
        Dim::Planar => (&[0, 1], &[2]),
        Dim::Spatial => (&[0, 1, 2], &[0, 1, 2]),
    };
    let mut fields = Vec::new();
    for &a in translations {
        fields.push(mesh.rigid_field(&Vector3::ith(a, 1.0), &zero));
    }
    for &a in rotations {
        fields.push(mesh.rigid_field(&zero, &Vector3::ith(a, scale)));
    }
    for s in centrifugal_tensors(mesh.dim) {
        fields.push(linear_field(mesh, &(s * scale)));
    }
    fields
}

/// The symmetric tensors S whose fields S r̄ span the centrifugal accelerations.
pub(crate) fn centrifugal_tensors(dim: Dim) -> Vec<Matrix3<f64>> {
    match dim {
        Dim::Planar => vec![Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0)],
        Dim::Spatial => {
            let mut out = Vec::new();
            for a in 0..3 {
                for b in a..3 {
                    let mut s = Matrix3::zeros();
                    s[(a, b)] = 1.0;
                    s[(b, a)] = 1.0;
                    out.push(s);
                }
            }
            out
        }
    }
}

/// Node translations S r̄ and no node rotation (S symmetric: the field is rotation-free).
fn linear_field(mesh: &Mesh, s: &Matrix3<f64>) -> DVector<f64> {
    let d = mesh.dofs_per_node();
    let n_translations = match mesh.dim {
        Dim::Planar => 2,
        Dim::Spatial => 3,
    };
    let mut u = DVector::zeros(mesh.n_dofs());
    for (k, r) in mesh.nodes.iter().enumerate() {
        let du = s * r;
        for a in 0..n_translations {
            u[k * d + a] = du[a];
        }
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::{BeamBodySpec, Material, Section};

    #[test]
    fn fields_per_dimension_and_scaled_to_unit_motion() {
        let material = Material {
            young_modulus: 2.1e11,
            density: 7850.0,
            poisson_ratio: Some(0.3),
            shear_modulus: None,
        };
        let section = Section::Circle { diameter: 0.01 };
        let planar = BeamBodySpec::straight(Dim::Planar, material.clone(), section.clone(), 4.0, 4);
        let fields = rigid_fields(&Mesh::from_spec(&planar));
        assert_eq!(fields.len(), 2 + 1 + 1);
        // The rotation field moves the tip (4 m out) by exactly one unit, its node rotation 1/4.
        let tip = 4 * 3;
        assert_eq!(fields[2][tip + 1], 1.0);
        assert_eq!(fields[2][tip + 2], 0.25);
        // The centrifugal field is radial and rotation-free.
        assert_eq!((fields[3][tip], fields[3][tip + 2]), (1.0, 0.0));
        let spatial = BeamBodySpec::straight(Dim::Spatial, material, section, 4.0, 4);
        assert_eq!(rigid_fields(&Mesh::from_spec(&spatial)).len(), 3 + 3 + 6);
    }
}
