//! The imported model and the checks every reader's output goes through.

use std::collections::HashMap;

use sprs::CsMat;

use super::dof_map::DofEntry;
use super::mesh::FeMesh;
use super::options::ImportOptions;
use super::symmetric::{Entry, FullSymmetric, Storage, symmetrise};
use super::text::{format_error, import_error};
use crate::error::FeError;
use crate::reduced::{Dof, NodeDof};

/// An imported FE model: mesh, DOF map, K and M (SI units after [`ImportOptions`]).
///
/// K and M are `sprs` CSC matrices in full storage (both triangles), symmetric to
/// [`super::SYMMETRY_TOL`] of their largest entry, with row and column `r` the DOF
/// `dofs[r]`; M has a positive diagonal and K a non-negative one.
#[derive(Clone, Debug)]
pub struct FeModel {
    /// The file(s) the model came from, for messages.
    pub source: String,
    /// Nodes (positions scaled by `length_scale`), elements and sets.
    pub mesh: FeMesh,
    /// Matrix row r ↔ (node index into `mesh.nodes`, DOF).
    pub dofs: Vec<NodeDof>,
    /// Stiffness (CSC, full storage).
    pub k: CsMat<f64>,
    /// Mass (CSC, full storage).
    pub m: CsMat<f64>,
}

impl FeModel {
    /// Number of DOFs (matrix order).
    pub fn n_dofs(&self) -> usize {
        self.dofs.len()
    }

    /// The matrix row of a node's DOF, by node id.
    pub fn dof_row(&self, node_id: &str, dof: Dof) -> Option<usize> {
        let node = *self.mesh.nodes.index.get(node_id)?;
        self.dofs.iter().position(|d| *d == NodeDof { node, dof })
    }
}

/// A matrix as read from its file, before symmetrisation.
pub(crate) struct MatrixInput {
    pub file: String,
    pub n: usize,
    pub entries: Vec<Entry>,
    pub storage: Storage,
}

/// Node indices of a DOF map; an unknown node is refused at its line.
pub(crate) fn resolve_dofs(
    entries: &[DofEntry],
    mesh: &FeMesh,
    file: &str,
) -> Result<Vec<NodeDof>, FeError> {
    entries
        .iter()
        .map(|e| {
            let node = *mesh.nodes.index.get(&e.node).ok_or_else(|| {
                format_error(
                    file,
                    e.line,
                    "node",
                    format!("node {} is not in the node list", e.node),
                )
            })?;
            Ok(NodeDof { node, dof: e.dof })
        })
        .collect()
}

/// Check sizes and symmetry, apply the options, check the diagonals, build CSC.
pub(crate) fn assemble(
    source: String,
    mut mesh: FeMesh,
    dofs: Vec<NodeDof>,
    k: MatrixInput,
    m: MatrixInput,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    options.validate()?;
    check_dof_map(&source, &mesh, &dofs, &[&k, &m])?;
    let mut ks = symmetrise(&k.file, "K", k.n, k.entries, k.storage)?;
    let mut ms = symmetrise(&m.file, "M", m.n, m.entries, m.storage)?;
    for p in &mut mesh.nodes.positions {
        *p *= options.length_scale;
    }
    ks.scale(options.stiffness_scale);
    ms.scale(options.mass_scale);
    add_point_masses(&mut ms, &mesh, &dofs, options, &source)?;
    let model = FeModel {
        source,
        k: ks.into_csc(),
        m: ms.into_csc(),
        mesh,
        dofs,
    };
    check_diagonals(&model, &k.file, &m.file)?;
    Ok(model)
}

fn dof_name(mesh: &FeMesh, d: NodeDof) -> String {
    format!("node {} {}", mesh.nodes.ids[d.node], d.dof.name())
}

fn check_dof_map(
    source: &str,
    mesh: &FeMesh,
    dofs: &[NodeDof],
    matrices: &[&MatrixInput],
) -> Result<(), FeError> {
    for a in matrices {
        if a.n != dofs.len() {
            return Err(import_error(
                &a.file,
                "size",
                format!(
                    "the matrix is {n} × {n} but the DOF map lists {} DOFs",
                    dofs.len(),
                    n = a.n
                ),
            ));
        }
    }
    let mut seen: HashMap<NodeDof, usize> = HashMap::new();
    for (r, d) in dofs.iter().enumerate() {
        if let Some(first) = seen.insert(*d, r) {
            return Err(import_error(
                source,
                "dofs",
                format!(
                    "{} is listed twice (rows {} and {})",
                    dof_name(mesh, *d),
                    first + 1,
                    r + 1
                ),
            ));
        }
    }
    Ok(())
}

fn add_point_masses(
    m: &mut FullSymmetric,
    mesh: &FeMesh,
    dofs: &[NodeDof],
    options: &ImportOptions,
    source: &str,
) -> Result<(), FeError> {
    let row: HashMap<NodeDof, usize> = dofs.iter().enumerate().map(|(r, d)| (*d, r)).collect();
    for (k, pm) in options.point_masses.iter().enumerate() {
        let field = format!("point_masses[{k}].node");
        let node = *mesh.nodes.index.get(&pm.node).ok_or_else(|| {
            import_error(
                source,
                &field,
                format!("node {} is not in the model", pm.node),
            )
        })?;
        let rows = |ds: [Dof; 3]| ds.map(|dof| row.get(&NodeDof { node, dof }).copied());
        let t = rows([Dof::Ux, Dof::Uy, Dof::Uz]);
        if t.iter().all(Option::is_none) {
            return Err(import_error(
                source,
                &field,
                format!(
                    "node {} has no translational DOF to carry the mass",
                    pm.node
                ),
            ));
        }
        for r in t.into_iter().flatten() {
            m.add_symmetric(r, r, pm.mass);
        }
        if let Some(j) = pm.inertia_tensor() {
            let r = rows([Dof::Rx, Dof::Ry, Dof::Rz]);
            let [Some(a), Some(b), Some(c)] = r else {
                return Err(import_error(
                    source,
                    &format!("point_masses[{k}].inertia"),
                    format!(
                        "node {} lacks rotational DOFs (Rx, Ry, Rz) to carry the inertia",
                        pm.node
                    ),
                ));
            };
            let rr = [a, b, c];
            for i in 0..3 {
                for jj in 0..=i {
                    m.add_symmetric(rr[i], rr[jj], j[(i, jj)]);
                }
            }
        }
    }
    Ok(())
}

/// M needs a positive diagonal, K a non-negative one (cheap checks of definiteness).
fn check_diagonals(model: &FeModel, k_file: &str, m_file: &str) -> Result<(), FeError> {
    for (r, d) in model.dofs.iter().enumerate() {
        let mr = model.m.get(r, r).copied().unwrap_or(0.0);
        if mr <= 0.0 {
            return Err(import_error(
                m_file,
                &format!("M[{0}, {0}]", r + 1),
                format!(
                    "the mass diagonal of {} is {mr:e}; every DOF needs a positive mass \
                     (M is not positive definite)",
                    dof_name(&model.mesh, *d)
                ),
            ));
        }
        let kr = model.k.get(r, r).copied().unwrap_or(0.0);
        if kr < 0.0 {
            return Err(import_error(
                k_file,
                &format!("K[{0}, {0}]", r + 1),
                format!(
                    "the stiffness diagonal of {} is {kr:e} < 0 (K is indefinite)",
                    dof_name(&model.mesh, *d)
                ),
            ));
        }
    }
    Ok(())
}
