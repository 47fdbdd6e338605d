//! The mesh part of an imported model: nodes, elements and named sets.

use std::collections::BTreeMap;

use super::nodes::NodeList;

/// One element: id, type and connectivity (node indices into [`FeMesh::nodes`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    /// Element id as in the file (`instance.label` inside an Abaqus instance).
    pub id: String,
    /// Element type as in the file, upper case (`C3D10`, `S4R`, …).
    pub kind: String,
    /// Node indices, in the file's order.
    pub nodes: Vec<usize>,
}

/// Nodes, elements and named sets of an FE model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FeMesh {
    /// The nodes (ids, positions, id → index).
    pub nodes: NodeList,
    /// The elements (empty for a matrix-only import).
    pub elements: Vec<Element>,
    /// Node sets by name: sorted node indices.
    pub node_sets: BTreeMap<String, Vec<usize>>,
    /// Element sets by name: sorted element indices.
    pub element_sets: BTreeMap<String, Vec<usize>>,
}

impl FeMesh {
    /// A mesh of nodes only.
    pub fn from_nodes(nodes: NodeList) -> Self {
        FeMesh {
            nodes,
            ..FeMesh::default()
        }
    }
}
