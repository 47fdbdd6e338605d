//! Built-in isoparametric solid elements (issue 29): a mesh of 4- and 10-node tetrahedra and
//! 8- and 20-node hexahedra, isotropic linear elastic, assembled into the sparse K and M of
//! an [`FeModel`], which the imported-body pipeline ([`crate::imported`]) then reduces as it
//! reduces an export of a commercial code.
//!
//! - [`shape`]: node order (Abaqus's) and shape functions;
//! - [`quadrature`]: the integration rules;
//! - [`element`]: material, element K and consistent or lumped M, the Jacobian check;
//! - [`assembly`]: the sparse assembly;
//! - [`stress`]: modal stress shapes; [`geometric`]: the geometric stiffness per mode (FNL1);
//! - this module: from a mesh read from a file (Gmsh MSH, [`crate::import::gmsh`], or an
//!   Abaqus/CalculiX input file) to the [`FeModel`].
//!
//! The model keeps the nodes that some solid element holds (a mesh file may carry others,
//! e.g. the points of the geometry), in the file's order; node sets lose the others.
//! [`ImportOptions::length_scale`] scales the node positions **before** the elements are
//! computed, the material being in SI units; `stiffness_scale` and `mass_scale` then
//! multiply K and M as for any import, and point masses are added to M.

pub mod assembly;
pub mod element;
pub mod geometric;
pub mod quadrature;
pub mod shape;
pub mod stress;

use std::collections::BTreeMap;

use crate::error::FeError;
use crate::import::nodes::NodeList;
use crate::import::{Element, FeMesh, FeModel, ImportOptions};
use crate::reduced::{Dof, NodeDof};

pub use assembly::SolidElement;
pub use element::{IsotropicElastic, MassMatrix};
pub use shape::SolidKind;

/// The solid elements of `mesh` with their labels; an element type that is not built in is
/// refused by name.
pub fn solid_elements(mesh: &FeMesh, file: &str) -> Result<Vec<SolidElement>, FeError> {
    mesh.elements
        .iter()
        .map(|e| {
            let label = format!("element {} of {file}", e.id);
            let kind = SolidKind::from_abaqus_name(&e.kind).ok_or_else(|| {
                FeError::Invalid(flexmbd_core::InvalidValue::new(
                    format!("{label}: type"),
                    &e.kind,
                    "is not a built-in solid element (C3D4, C3D10, C3D8, C3D20)",
                ))
            })?;
            if e.nodes.len() != kind.n_nodes() {
                return Err(FeError::Invalid(flexmbd_core::InvalidValue::new(
                    format!("{label}: nodes"),
                    e.nodes.len(),
                    format!("a {kind} element has {} nodes", kind.n_nodes()),
                )));
            }
            Ok(SolidElement {
                label,
                kind,
                nodes: e.nodes.clone(),
            })
        })
        .collect()
}

/// The mesh restricted to the nodes its elements hold (module docs): the new mesh and, for
/// each old node index, its new one.
fn used_nodes(mesh: &FeMesh) -> (FeMesh, Vec<Option<usize>>) {
    let mut used = vec![false; mesh.nodes.len()];
    for e in &mesh.elements {
        for &n in &e.nodes {
            used[n] = true;
        }
    }
    let mut map = vec![None; used.len()];
    let mut nodes = NodeList::default();
    for (old, _) in used.iter().enumerate().filter(|(_, u)| **u) {
        let id = mesh.nodes.ids[old].clone();
        map[old] = Some(nodes.ids.len());
        nodes.index.insert(id.clone(), nodes.ids.len());
        nodes.ids.push(id);
        nodes.positions.push(mesh.nodes.positions[old]);
    }
    let node_sets: BTreeMap<String, Vec<usize>> = mesh
        .node_sets
        .iter()
        .map(|(name, set)| (name.clone(), set.iter().filter_map(|&n| map[n]).collect()))
        .collect();
    let elements: Vec<Element> = mesh
        .elements
        .iter()
        .map(|e| Element {
            nodes: e.nodes.iter().filter_map(|&n| map[n]).collect(),
            ..e.clone()
        })
        .collect();
    let out = FeMesh {
        nodes,
        elements,
        node_sets,
        element_sets: mesh.element_sets.clone(),
    };
    (out, map)
}

/// Assemble the model of a solid mesh (positions in file units; module docs). `file` names
/// the mesh in errors.
pub fn solid_model(
    mesh: &FeMesh,
    file: &str,
    material: &IsotropicElastic,
    mass_matrix: MassMatrix,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    solid_model_with_mass_points(
        mesh,
        file,
        material,
        mass_matrix,
        options,
        element::mass_rule,
    )
}

/// [`solid_model`] with M integrated by other points
/// ([`assembly::assemble_with_mass_points`]).
pub fn solid_model_with_mass_points(
    mesh: &FeMesh,
    file: &str,
    material: &IsotropicElastic,
    mass_matrix: MassMatrix,
    options: &ImportOptions,
    mass_points: fn(SolidKind) -> Vec<quadrature::Point>,
) -> Result<FeModel, FeError> {
    material.validate("material")?;
    options.validate()?;
    if mesh.elements.is_empty() {
        return Err(FeError::Invalid(flexmbd_core::InvalidValue::new(
            file.to_string(),
            "no solid element",
            "a solid body needs a mesh of 3D elements",
        )));
    }
    let (mut mesh, _) = used_nodes(mesh);
    for p in &mut mesh.nodes.positions {
        *p *= options.length_scale;
    }
    let elements = solid_elements(&mesh, file)?;
    let (k, m) = assembly::assemble_with_mass_points(
        &mesh.nodes.positions,
        &elements,
        material,
        mass_matrix,
        mass_points,
    )?;
    let dofs: Vec<NodeDof> = (0..mesh.nodes.len())
        .flat_map(|node| [Dof::Ux, Dof::Uy, Dof::Uz].map(|dof| NodeDof { node, dof }))
        .collect();
    let unscaled = ImportOptions {
        length_scale: 1.0,
        ..options.clone()
    };
    crate::import::model_from_matrices(file.to_string(), mesh, dofs, &k, &m, &unscaled)
}

/// The modal stress shapes ([`stress::StressShapes`]) of a body reduced from a solid model:
/// `model` is the one [`solid_model`] assembled (its mesh the solid elements, positions in
/// SI), `body` its reduction ([`crate::imported::reduce_imported`]), whose node rows from
/// `first` on (after the interface points) are the model's nodes in order; `file` names the
/// mesh in errors.
pub fn body_stress_shapes(
    model: &FeModel,
    material: &IsotropicElastic,
    body: &crate::reduced::ReducedBody,
    first: usize,
    file: &str,
) -> Result<stress::StressShapes, FeError> {
    let elements = solid_elements(&model.mesh, file)?;
    let modes = fe_node_modes(model, body, first, file)?;
    stress::StressShapes::new(&model.mesh.nodes.positions, &elements, material, &modes)
}

/// The geometric stiffness K_Gk per mode ([`geometric`], for FNL1) of a body reduced from a
/// solid model: `model`, `body`, `first` and `file` as for [`body_stress_shapes`].
pub fn body_geometric_stiffness(
    model: &FeModel,
    material: &IsotropicElastic,
    body: &crate::reduced::ReducedBody,
    first: usize,
    file: &str,
) -> Result<Vec<nalgebra::DMatrix<f64>>, FeError> {
    let elements = solid_elements(&model.mesh, file)?;
    let modes = fe_node_modes(model, body, first, file)?;
    geometric::geometric_stiffness(&model.mesh.nodes.positions, &elements, material, &modes)
}

/// The translational mode rows of the model's FE nodes ((3 · nodes) × modes, node-major),
/// read from the body's node rows `first`, `first` + 1, … (after the interface points).
fn fe_node_modes(
    model: &FeModel,
    body: &crate::reduced::ReducedBody,
    first: usize,
    file: &str,
) -> Result<nalgebra::DMatrix<f64>, FeError> {
    let n_nodes = model.mesh.nodes.len();
    let n_modes = body.n_modes();
    if body.nodes.len() < first + n_nodes {
        return Err(FeError::Invalid(flexmbd_core::InvalidValue::new(
            file.to_string(),
            body.nodes.len(),
            format!("the reduced body has fewer node rows than {first} + {n_nodes} FE nodes"),
        )));
    }
    let mut modes = nalgebra::DMatrix::zeros(3 * n_nodes, n_modes);
    for node in 0..n_nodes {
        let rows = &body.nodes[first + node].translation;
        modes.rows_mut(3 * node, 3).copy_from(rows);
    }
    Ok(modes)
}
