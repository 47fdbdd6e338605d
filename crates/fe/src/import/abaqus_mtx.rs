//! Abaqus matrix output of `*MATRIX GENERATE, STIFFNESS, MASS` with
//! `*MATRIX OUTPUT, STIFFNESS, MASS[, FORMAT=…]` (`jobname_STIFn.mtx`,
//! `jobname_MASSn.mtx`, n the step number).
//!
//! - `FORMAT=MATRIX INPUT` (the default): one entry per line,
//!   `row node, row dof, column node, column dof, value`, the layout of `*MATRIX INPUT`
//!   data lines (Abaqus Keywords Reference, `*MATRIX INPUT`: "a symmetric matrix in
//!   lower triangular, upper triangular, or square format"). Abaqus writes one
//!   triangle, column by column; a square file must be symmetric. A node is a label
//!   (`12`) or an instance-qualified label (`PART-1-1.12`, the instance name in any
//!   case); a plain label that is not a
//!   node id is tried as `I.label` when the input file has exactly one instance I.
//!   DOFs 1…6 are Ux, Uy, Uz, Rx, Ry, Rz. Refused: negative labels (Abaqus's internal
//!   nodes, e.g. Lagrange multipliers of hybrid elements or constraints), other DOF
//!   numbers, and a stiffness diagonal of 1e36 or more — Abaqus's marker of a DOF
//!   held by a boundary condition: export the free model. `**` lines are comments.
//!   The matrix rows are the (node, DOF) pairs that occur in K or M, ordered by the
//!   node's place in the input file, then by DOF.
//! - `FORMAT=COORDINATE`: `row, column, value` (commas and/or white space), 1-based
//!   equation numbers. The file does not say which DOF an equation is, so the caller
//!   gives the DOFs each node carries; equations are taken node-major in the input
//!   file's node order (the convention of Exudyn's `FEMinterface`, which reads these
//!   files for solid meshes with three DOFs per node). This ordering is an assumption
//!   the file cannot confirm; only the size is checked.
//!
//! Source: the Abaqus Keywords Reference (`*MATRIX GENERATE`, `*MATRIX OUTPUT`,
//! `*MATRIX INPUT`), the Abaqus Analysis User's Guide "Generating matrices", and
//! published `.mtx` excerpts (JuliaFEM `FEMBeam.jl` tests: negative internal labels and
//! the 1e36 boundary marker).

use std::collections::{BTreeMap, BTreeSet, HashMap};

use super::dof_map::dof_of_number;
use super::mesh::FeMesh;
use super::symmetric::{Entry, Storage};
use super::text::{At, comma_fields, format_error, import_error, numbered_lines, quote};
use crate::error::FeError;
use crate::reduced::{Dof, NodeDof};

/// Diagonal stiffness at or above which Abaqus marks a constrained DOF.
pub const ABAQUS_BC_MARKER: f64 = 1e30;

/// One `MATRIX INPUT` line: row and column (node index, DOF), value, line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LabelledEntry {
    pub row: NodeDof,
    pub col: NodeDof,
    pub value: f64,
    pub line: usize,
}

/// Parse a `FORMAT=MATRIX INPUT` file against the mesh of its input file.
pub(crate) fn parse_labelled(
    text: &str,
    file: &str,
    mesh: &FeMesh,
) -> Result<Vec<LabelledEntry>, FeError> {
    let lookup = NodeLookup::new(mesh);
    let mut out = Vec::new();
    for (line, raw) in numbered_lines(text) {
        let t = raw.trim();
        if t.is_empty() || t.starts_with("**") {
            continue;
        }
        let at = At { file, line };
        if t.starts_with('*') {
            return Err(at.error(
                "line",
                format!(
                    "keyword {} in a matrix file (expected `node, dof, node, dof, value`)",
                    quote(t)
                ),
            ));
        }
        let f = comma_fields(t);
        at.expect_fields(&f, 5, "row node, row dof, column node, column dof, value")?;
        out.push(LabelledEntry {
            row: lookup.node_dof(at, f[0], f[1], "row")?,
            col: lookup.node_dof(at, f[2], f[3], "column")?,
            value: at.real("value", f[4])?,
            line,
        });
    }
    if out.is_empty() {
        return Err(format_error(
            file,
            1,
            "entry",
            "the matrix file has no entry".into(),
        ));
    }
    Ok(out)
}

/// Node ids of the mesh, case-insensitive (Abaqus may write instance names upper
/// case), with the single-instance fallback for plain labels.
struct NodeLookup<'a> {
    mesh: &'a FeMesh,
    upper: HashMap<String, usize>,
    single_instance: Option<String>,
}

impl<'a> NodeLookup<'a> {
    fn new(mesh: &'a FeMesh) -> Self {
        let prefixes: BTreeSet<&str> = mesh
            .nodes
            .ids
            .iter()
            .filter_map(|id| id.rsplit_once('.').map(|(p, _)| p))
            .collect();
        let single_instance = (prefixes.len() == 1).then(|| prefixes.first().unwrap().to_string());
        let upper = mesh
            .nodes
            .ids
            .iter()
            .enumerate()
            .map(|(i, id)| (id.to_uppercase(), i))
            .collect();
        NodeLookup {
            mesh,
            upper,
            single_instance,
        }
    }

    fn node_dof(&self, at: At, node: &str, dof: &str, which: &str) -> Result<NodeDof, FeError> {
        let field = format!("{which} node");
        if node.starts_with('-') {
            return Err(at.error(
                &field,
                format!(
                    "negative label {node} is an Abaqus internal node (Lagrange multiplier or \
                     internal element node); such models are not supported"
                ),
            ));
        }
        let index = &self.mesh.nodes.index;
        let found = index
            .get(node)
            .or_else(|| self.upper.get(&node.to_uppercase()))
            .or_else(|| {
                let inst = self.single_instance.as_ref()?;
                index.get(&format!("{inst}.{node}"))
            });
        let node_index = *found.ok_or_else(|| {
            at.error(
                &field,
                format!("node {} is not in the input file", quote(node)),
            )
        })?;
        let k = at.integer(&format!("{which} dof"), dof)?;
        let dof = dof_of_number(k).ok_or_else(|| {
            at.error(
                &format!("{which} dof"),
                format!("DOF {k} is not a displacement or rotation (1…6)"),
            )
        })?;
        Ok(NodeDof {
            node: node_index,
            dof,
        })
    }
}

/// The matrix rows of K and M read in `MATRIX INPUT` format: every (node, DOF) that
/// occurs, by node index then DOF.
pub(crate) fn dof_rows(k: &[LabelledEntry], m: &[LabelledEntry]) -> Vec<NodeDof> {
    let rows: BTreeMap<(usize, usize), NodeDof> = k
        .iter()
        .chain(m)
        .flat_map(|e| [e.row, e.col])
        .map(|d| ((d.node, d.dof as usize), d))
        .collect();
    rows.into_values().collect()
}

/// Entries with equation numbers from the row list; the 1e36 marker refused.
pub(crate) fn numbered(
    entries: &[LabelledEntry],
    rows: &[NodeDof],
    file: &str,
    is_stiffness: bool,
    mesh: &FeMesh,
) -> Result<Vec<Entry>, FeError> {
    let row_of: HashMap<NodeDof, usize> = rows.iter().enumerate().map(|(r, d)| (*d, r)).collect();
    entries
        .iter()
        .map(|e| {
            if is_stiffness && e.row == e.col && e.value >= ABAQUS_BC_MARKER {
                return Err(format_error(
                    file,
                    e.line,
                    "value",
                    format!(
                        "stiffness {:e} on node {} {} is Abaqus's marker of a DOF held by a \
                         boundary condition; export the model without boundary conditions",
                        e.value,
                        mesh.nodes.ids[e.row.node],
                        e.row.dof.name()
                    ),
                ));
            }
            Ok(Entry {
                row: row_of[&e.row],
                col: row_of[&e.col],
                value: e.value,
                line: e.line,
            })
        })
        .collect()
}

/// Storage of `MATRIX INPUT` files: either triangle, or both.
pub(crate) const LABELLED_STORAGE: Storage = Storage::Either;

/// Parse a `FORMAT=COORDINATE` file of order `n`.
pub(crate) fn parse_coordinate(text: &str, file: &str, n: usize) -> Result<Vec<Entry>, FeError> {
    let mut out = Vec::new();
    for (line, raw) in numbered_lines(text) {
        let t = raw.trim();
        if t.is_empty() || t.starts_with("**") {
            continue;
        }
        let at = At { file, line };
        let f = at.three(t, "row, column, value")?;
        out.push(Entry {
            row: at.index1("row", f[0], n)?,
            col: at.index1("column", f[1], n)?,
            value: at.real("value", f[2])?,
            line,
        });
    }
    if out.is_empty() {
        return Err(format_error(
            file,
            1,
            "entry",
            "the matrix file has no entry".into(),
        ));
    }
    Ok(out)
}

/// Node-major rows over the mesh's nodes with `per_node` DOFs each.
pub(crate) fn node_major_rows(
    mesh: &FeMesh,
    per_node: &[Dof],
    file: &str,
) -> Result<Vec<NodeDof>, FeError> {
    if per_node.is_empty() {
        return Err(import_error(
            file,
            "dofs_per_node",
            "no DOF per node given".into(),
        ));
    }
    Ok((0..mesh.nodes.len())
        .flat_map(|node| per_node.iter().map(move |&dof| NodeDof { node, dof }))
        .collect())
}
