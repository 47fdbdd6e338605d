//! The reference condition of the floating frame (issue 31 item 3): which of the body's
//! motions the frame carries and which the modes do.
//!
//! - [`ReferenceCondition::InterfaceFixed`] (default): the modes vanish on the frame's DOFs
//!   (docs/methods.md §1.4), so the frame follows the interface node's cross-section.
//! - [`ReferenceCondition::Buckens`]: the linearised mean-axis (Tisserand, Buckens)
//!   conditions [R: Agrawal & Shabana, "Dynamic analysis of multibody systems using
//!   component modes", Comput. Struct. 21 (1985) 1303–1312; Géradin & Cardona, *Flexible
//!   Multibody Dynamics: A Finite Element Approach*, Wiley 2001, the floating frame;
//!   Shabana 2005, the reference conditions]: every mode is M-orthogonal to the
//!   body's rigid-body motions about the frame,
//!   `∫ ρ φ_i dV = 0`, `∫ ρ r̄_u × φ_i dV = 0` (`Rᵀ M φ_i = 0`),
//!   obtained from the interface-fixed basis by the M-orthogonal projection
//!   `X ← X − R (Rᵀ M R)⁻¹ Rᵀ M X`,
//!   R the rigid-body modes in FE DOFs (2D: u_x, u_y and θ_z about the frame's origin, node
//!   rows (1, 0, 0), (0, 1, 0), (−y, x, 1); 3D: the three translations and the three
//!   rotations θ_a, node rows (e_a × r̄, e_a); [`rigid_modes_of_dofs`] for any layout of
//!   DOFs, such as an imported body's retained coordinates, `crate::imported::reduction`). The projection subtracts from each mode a
//!   rigid motion, so X spans the same deformations modulo rigid motion and the strain is
//!   unchanged: K R = 0, hence K_ff = XᵀKX and the damping on it are those of the
//!   interface-fixed basis, while M_ff = XᵀMX is formed anew (it loses the rigid part,
//!   M_ff ← M_ff − Bᵀ (RᵀMR)⁻¹ B, B = RᵀMX).
//!
//! **Shape integrals that vanish** (docs/methods.md §2.3; the cloud reproduces M exactly,
//! §2.7, so the conditions hold on the cloud to round-off — `tests/reference_condition.rs`):
//! the translational coupling S = ∫ X dm = 0, so m̄ = m̄_u + S y is constant and the
//! translational–modal block of M̄ is zero at every y; the skew part of Sᵃ,
//! (∫ r̄_u × X dm)_c = ε_cab Sᵃ_b = 0, so the rotational–modal block C(y) has no constant
//! part (it is C(Sᵃ) = 0 at y = 0; only its part linear in y, from Sᵃᵇ, remains). So at the
//! undeformed state M̄ is block-diagonal: the first-order coupling terms are gone. The
//! symmetric part of Sᵃ (the inertia tensor's change with y, Ī's first-order part) and the
//! second-order Sᵃᵇ remain.
//!
//! The two conditions give the same motion only to first order in the deformation: the
//! floating frame's model is linear in y, so the rigid rotation the projection moves from
//! the modes into the frame (or back) is linearised in one and exact in the other, a
//! difference of order α² L (α ~ δ/L) that does not fall with the modes or the step
//! (`crates/validation/tests/reference_condition.rs`; docs/design.md "Reference conditions").
//!
//! The frame no longer stays at the interface node: that node moves with the modes
//! (non-zero node rows), so a joint there attaches through the node's modal displacement
//! (the absolute formulation does this for any node; the relative one needs a joint at a
//! node with zero rows to hang a body from its parent and refuses such a body by name).

use nalgebra::{DMatrix, Vector3};
use serde::{Deserialize, Serialize};
use sprs::CsMat;

use crate::assembly::Mesh;
use crate::error::FeError;
use crate::reduced::Dof;
use crate::sparse_reduction::{sparse_times_dense, symmetrise};
use flexmbd_core::{Dim, InvalidValue};

/// Which conditions tie the floating frame to the body (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ReferenceCondition {
    /// The modes vanish on the frame's DOFs: the frame follows the interface node.
    #[default]
    InterfaceFixed,
    /// The modes are M-orthogonal to the rigid-body motions (linearised mean axes).
    Buckens,
}

impl ReferenceCondition {
    /// The name used in scenes and messages.
    pub fn name(self) -> &'static str {
        match self {
            ReferenceCondition::InterfaceFixed => "InterfaceFixed",
            ReferenceCondition::Buckens => "Buckens",
        }
    }
}

/// The rigid-body modes R (N × 3 in 2D, N × 6 in 3D) of `mesh` in its FE DOFs, about the
/// body frame's origin: translations along the body axes, then rotations about them.
pub fn rigid_modes(mesh: &Mesh) -> DMatrix<f64> {
    match mesh.dim {
        Dim::Planar => {
            let d = mesh.dofs_per_node();
            let mut r = DMatrix::zeros(mesh.n_dofs(), 3);
            for (k, p) in mesh.nodes.iter().enumerate() {
                let o = k * d;
                r[(o, 0)] = 1.0;
                r[(o + 1, 1)] = 1.0;
                r[(o, 2)] = -p.y;
                r[(o + 1, 2)] = p.x;
                r[(o + 2, 2)] = 1.0;
            }
            r
        }
        Dim::Spatial => rigid_modes_of_dofs(mesh.nodes.iter().flat_map(|p| {
            [Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz].map(|dof| (*p, dof))
        })),
    }
}

/// The six rigid-body modes (3D) of any DOF layout, one row per `(position, dof)` in order
/// (an imported body's retained coordinates: FE DOFs of nodes, and interface points' six):
/// [`rigid_row`] of each.
pub fn rigid_modes_of_dofs(dofs: impl IntoIterator<Item = (Vector3<f64>, Dof)>) -> DMatrix<f64> {
    let rows: Vec<[f64; 6]> = dofs
        .into_iter()
        .map(|(p, dof)| rigid_row(&p, dof))
        .collect();
    DMatrix::from_fn(rows.len(), 6, |i, j| rows[i][j])
}

/// The row of R (3D) of one DOF of a point at `p` (body components, about the frame's
/// origin): columns the translations t_a, then the rotations θ_a, whose displacement at
/// `p` is e_a × p and whose rotation is e_a. A translational DOF u_b reads (e_b; (e_a × p)_b),
/// a rotational one θ_b reads (0; e_b).
pub fn rigid_row(p: &Vector3<f64>, dof: Dof) -> [f64; 6] {
    let mut row = [0.0; 6];
    let (rotational, b) = match dof {
        Dof::Ux => (false, 0),
        Dof::Uy => (false, 1),
        Dof::Uz => (false, 2),
        Dof::Rx => (true, 0),
        Dof::Ry => (true, 1),
        Dof::Rz => (true, 2),
    };
    if rotational {
        row[3 + b] = 1.0;
    } else {
        row[b] = 1.0;
        for a in 0..3 {
            let mut e = Vector3::zeros();
            e[a] = 1.0;
            row[3 + a] = e.cross(p)[b];
        }
    }
    row
}

/// The Buckens basis of `x` (module documentation): X − R (RᵀMR)⁻¹ RᵀMX, and its mass
/// matrix XᵀMX. `name` names the body in the error of a singular rigid-body mass.
pub fn buckens_basis(
    x: &DMatrix<f64>,
    m: &CsMat<f64>,
    r: &DMatrix<f64>,
    name: &str,
) -> Result<(DMatrix<f64>, DMatrix<f64>), FeError> {
    let mr = sparse_times_dense(m, r);
    let rmr = symmetrise(&(r.transpose() * &mr));
    let Some(chol) = rmr.clone().cholesky() else {
        return Err(FeError::Invalid(InvalidValue::new(
            "reference",
            "Buckens",
            format!("{name}: the rigid-body mass RᵀMR is not positive definite"),
        )));
    };
    // B = RᵀMX = (MR)ᵀX, M symmetric.
    let b = mr.transpose() * x;
    let projected = x - r * chol.solve(&b);
    let m_ff = symmetrise(&(projected.transpose() * sparse_times_dense(m, &projected)));
    Ok((projected, m_ff))
}
