//! Finite-element preprocessing for flexmbd (docs/methods.md §1–§2.3, §6.1).
//!
//! [`reduce`] turns a [`BeamBodySpec`] into a [`ReducedBody`]:
//! mesh → sparse assembly (§1.2) → Craig–Bampton (§1.3–§1.4; the dynamic vectors
//! chosen by [`ModeSelection`], §1.6; on dense matrices below [`SPARSE_FROM_DOFS`] FE DOFs,
//! on sparse ones from there, [`sparse_reduction`]) → damping (§1.5)
//! → the reference condition ([`mod@reference`]: interface-fixed, or the Buckens projection)
//! → mass cloud (§2.7) → shape integrals (§2.3) → nodal mode rows → K_G (§6.1).
//! The mesh is a polyline or a beam frame of named nodes and members, each with its own
//! section ([`frame`]).

#![warn(missing_docs)]

pub mod assembly;
pub mod beam;
pub mod bounds;
pub mod cloud;
pub mod craig_bampton;
pub mod error;
pub mod foreshortening;
pub mod frame;
pub mod import;
pub mod imported;
pub mod inertia_loads;
pub mod modal;
pub mod participation;
pub mod pod;
pub mod reduced;
pub mod reference;
pub mod rigid;
pub mod ritz;
pub mod section;
pub mod selection;
pub mod solid;
pub mod solid_box;
pub mod sparse;
pub mod sparse_eigen;
pub mod sparse_reduction;
pub mod spec;
pub mod stiffening;

use flexmbd_core::Dim;
use nalgebra::{DMatrix, Vector3};
use sprs::CsMat;

pub use assembly::{DofSets, Mesh};
pub use bounds::SPARSE_FROM_DOFS;
pub use craig_bampton::Reduction;
pub use error::FeError;
pub use foreshortening::ForeshorteningData;
pub use reduced::{
    Dof, MassCloud, ModeInventory, NodeDof, NodeModes, ReducedBody, ShapeIntegrals,
    StiffeningIntegrals,
};
pub use reference::ReferenceCondition;
pub use selection::ModeSelection;
pub use spec::{BeamBodySpec, Damping, Geometry, Material, ReferenceFrame, Section};

/// Everything [`reduce`] computes, including the FE-level intermediates that
/// tests and the `modes` command may want to inspect.
#[derive(Clone, Debug)]
pub struct Preprocessed {
    /// The mesh.
    pub mesh: Mesh,
    /// Free-floating stiffness K (sparse, N × N).
    pub k: CsMat<f64>,
    /// Free-floating mass M (sparse, N × N; the default mass model of the dimension).
    pub m: CsMat<f64>,
    /// The Craig–Bampton reduction.
    pub reduction: Reduction,
    /// The reduced body.
    pub body: ReducedBody,
}

/// Validate, mesh, assemble, reduce and fill a [`ReducedBody`].
pub fn reduce(spec: &BeamBodySpec) -> Result<ReducedBody, FeError> {
    preprocess(spec).map(|p| p.body)
}

/// Like [`reduce`], keeping the FE-level intermediates.
pub fn preprocess(spec: &BeamBodySpec) -> Result<Preprocessed, FeError> {
    spec.validate()?;
    let mesh = Mesh::from_spec(spec);
    let asm = mesh.assemble(mesh.default_mass_model());
    let frame_dofs = spec.frame_dofs();
    let sets = DofSets::from_node_dofs(spec.dim, mesh.n_dofs(), &frame_dofs, &spec.boundary);
    let frame_txt = format_dofs(&frame_dofs);
    let name = if spec.origin.is_empty() {
        "<beam body spec>"
    } else {
        spec.origin.as_str()
    };
    let mut red = if mesh.n_dofs() >= SPARSE_FROM_DOFS {
        // The spec's checks refused other selections and axial modes here.
        sparse_reduction::reduce_sparse(
            &asm.k,
            &asm.m,
            &sets,
            spec.normal_modes,
            sparse_reduction::BEAM_EIGEN_TOL,
            Some(0.0),
            name,
            &frame_txt,
        )?
    } else {
        reduce_dense(spec, &mesh, &asm, &sets, name, &frame_txt)?
    };
    let c_ff = craig_bampton::damping_matrix(&spec.damping, &red);
    // Buckens: the same deformations modulo rigid motion, so K_ff and C_ff stay (K R = 0).
    if spec.reference == ReferenceCondition::Buckens {
        let r = reference::rigid_modes(&mesh);
        let (x, m_ff) = reference::buckens_basis(&red.x, &asm.m, &r, name)?;
        red.x = x;
        red.m_ff = m_ff;
    }
    let cloud = cloud::build_cloud(&mesh, &red.x);
    let shape_integrals = ShapeIntegrals::from_cloud(&cloud);
    let nodes = node_modes(&mesh, &red.x);
    let k_g = stiffening::geometric_stiffness(&mesh, &red.x);
    let (g_mean, h_weight) = stiffening::element_mean_g(&mesh, &red.x);
    let inventory = ModeInventory {
        n_fe_dofs: mesh.n_dofs(),
        frame_dofs,
        static_modes: spec.boundary.clone(),
        selection: spec.mode_selection,
        reference: spec.reference,
        point_names: Vec::new(),
        normal_frequencies_hz: red
            .omega_sq
            .iter()
            .map(|w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect(),
    };
    let body = ReducedBody {
        dim: spec.dim,
        inventory,
        modes: red.x.clone(),
        m_ff: red.m_ff.clone(),
        k_ff: red.k_ff.clone(),
        c_ff,
        cloud,
        shape_integrals,
        nodes,
        stiffening: StiffeningIntegrals {
            k_g,
            g_mean,
            h_weight,
        },
        foreshortening: None,
    };
    Ok(Preprocessed {
        mesh,
        k: asm.k,
        m: asm.m,
        reduction: red,
        body,
    })
}

/// The Craig–Bampton reduction of a beam below [`SPARSE_FROM_DOFS`] FE DOFs, on dense K and M.
fn reduce_dense(
    spec: &BeamBodySpec,
    mesh: &Mesh,
    asm: &assembly::Assembled,
    sets: &DofSets,
    name: &str,
    frame_txt: &str,
) -> Result<Reduction, FeError> {
    let k = assembly::to_dense(&asm.k);
    let m = assembly::to_dense(&asm.m);
    if spec.mode_selection != ModeSelection::LowestFrequency {
        craig_bampton::reduce_with_basis(&k, &m, sets, name, frame_txt, |p| {
            selection::dynamic_basis(spec, mesh, &m, sets, p)
        })
    } else if spec.axial_modes == 0 {
        craig_bampton::reduce_matrices(&k, &m, sets, spec.normal_modes, name, frame_txt)
    } else {
        let all = craig_bampton::reduce_matrices(&k, &m, sets, sets.i.len(), name, frame_txt)?;
        select_axial(all, mesh, spec.normal_modes, spec.axial_modes)
    }
}

/// Nodal mode rows: translation X^t and rotation X^r (3 × n each, body components).
/// In 2D the z translation row and the x, y rotation rows are zero.
pub fn node_modes(mesh: &Mesh, x: &DMatrix<f64>) -> Vec<NodeModes> {
    let n = x.ncols();
    let d = mesh.dofs_per_node();
    mesh.nodes
        .iter()
        .enumerate()
        .map(|(k, pos)| {
            let mut t = DMatrix::zeros(3, n);
            let mut r = DMatrix::zeros(3, n);
            for j in 0..n {
                match mesh.dim {
                    Dim::Planar => {
                        t[(0, j)] = x[(k * d, j)];
                        t[(1, j)] = x[(k * d + 1, j)];
                        r[(2, j)] = x[(k * d + 2, j)];
                    }
                    Dim::Spatial => {
                        for a in 0..3 {
                            t[(a, j)] = x[(k * d + a, j)];
                            r[(a, j)] = x[(k * d + 3 + a, j)];
                        }
                    }
                }
            }
            NodeModes {
                position: Vector3::new(pos.x, pos.y, pos.z),
                translation: t,
                rotation: r,
            }
        })
        .collect()
}

/// Keep the static modes, the `n_other` lowest normal modes that are not purely axial
/// and the `n_axial` lowest purely axial ones (only Ux rows non-zero) of a reduction
/// with every normal mode (`BeamBodySpec::axial_modes`).
fn select_axial(
    all: Reduction,
    mesh: &Mesh,
    n_other: usize,
    n_axial: usize,
) -> Result<Reduction, FeError> {
    let d = mesh.dofs_per_node();
    let nb = all.n_static();
    let (mut other, mut axial) = (Vec::new(), Vec::new());
    for j in 0..all.n_dynamic() {
        let col = all.x.column(nb + j);
        let (mut ux, mut rest) = (0.0_f64, 0.0_f64);
        for (r, v) in col.iter().enumerate() {
            if r % d == 0 {
                ux = ux.max(v.abs());
            } else {
                rest = rest.max(v.abs());
            }
        }
        if rest <= 1e-8 * ux {
            if axial.len() < n_axial {
                axial.push(nb + j);
            }
        } else if other.len() < n_other {
            other.push(nb + j);
        }
    }
    if axial.len() < n_axial {
        return Err(FeError::Invalid(flexmbd_core::InvalidValue::new(
            "axial_modes",
            n_axial,
            format!(
                "the model has only {} purely axial normal modes (a straight beam along body x \
                 has one per interior axial DOF)",
                axial.len()
            ),
        )));
    }
    if other.len() < n_other {
        return Err(FeError::Invalid(flexmbd_core::InvalidValue::new(
            "normal_modes",
            n_other,
            format!(
                "the model has only {} normal modes that are not purely axial",
                other.len()
            ),
        )));
    }
    let mut keep: Vec<usize> = (0..nb).collect();
    let mut dynamic: Vec<usize> = other.into_iter().chain(axial).collect();
    dynamic.sort_unstable();
    keep.extend(&dynamic);
    let pick =
        |m: &DMatrix<f64>| DMatrix::from_fn(keep.len(), keep.len(), |i, j| m[(keep[i], keep[j])]);
    Ok(Reduction {
        x: all.x.select_columns(&keep),
        m_ff: pick(&all.m_ff),
        k_ff: pick(&all.k_ff),
        omega_sq: dynamic.iter().map(|&c| all.omega_sq[c - nb]).collect(),
        sets: all.sets,
    })
}

fn format_dofs(d: &[NodeDof]) -> String {
    let parts: Vec<String> = d
        .iter()
        .map(|nd| format!("{}@{}", nd.dof.name(), nd.node))
        .collect();
    format!("{{{}}}", parts.join(", "))
}
