//! Node-coordinate lists: the generic `id x y z` file and Ansys `NLIST` output.
//!
//! One node per line: an integer node number and three coordinates, separated by
//! white space and/or commas (`id, x, y, z` is a CSV export). Blank lines and lines
//! starting with `#`, `!` or `%` are comments. A line starting with a letter or `*`
//! is a header and skipped (`NLIST` prints `LIST ALL SELECTED NODES. DSYS= 0`,
//! `NODE X Y Z THXY THYZ THZX` and `*** ANSYS …` page headers). A line of seven fields
//! is an `NLIST` line whose last three are the nodal coordinate system's rotation
//! angles THXY, THYZ, THZX (degrees): they must be zero, since the matrices of a
//! rotated nodal system are in nodal axes (`NROTAT`), which this reader does not
//! turn back. A line that does not split into 4 or 7 fields is tried as a line of an
//! Ansys `NWRITE` node file (`Jobname.node`; Ansys Command Reference, `NWRITE`: format
//! (I9, 6G21.13E3), trailing zero fields left blank, so fields may be missing or touch).
//! A line holding a tab is a table exported by Ansys Workbench (a named
//! selection of mesh nodes, *Export*): its fields are separated by tabs only and a
//! decimal comma is read as a point (`1,e-001` = 0.1), as that export writes numbers in
//! the user's locale. Node numbers must be unique.

use std::collections::HashMap;

use nalgebra::Vector3;

use super::text::{At, fields, format_error, numbered_lines};
use crate::error::FeError;

/// Nodes as read: ids (as written), positions, and the 1-based line of each.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeList {
    /// Node ids as in the file (decimal integers, or `instance.label` for Abaqus).
    pub ids: Vec<String>,
    /// Positions in file units (the length scale is applied by the model).
    pub positions: Vec<Vector3<f64>>,
    /// id → index into `ids`.
    pub index: HashMap<String, usize>,
}

impl NodeList {
    /// Add a node; a duplicate id is an error at `at`.
    pub(crate) fn push(&mut self, at: At, id: String, p: Vector3<f64>) -> Result<(), FeError> {
        if self.index.contains_key(&id) {
            return Err(at.error("node", format!("node {id} is defined twice")));
        }
        self.index.insert(id.clone(), self.ids.len());
        self.ids.push(id);
        self.positions.push(p);
        Ok(())
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True when there is no node.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }
}

/// Parse a node-coordinate list (generic or `NLIST`); `file` names it in errors.
pub fn parse_node_list(text: &str, file: &str) -> Result<NodeList, FeError> {
    let mut nodes = NodeList::default();
    for (line, raw) in numbered_lines(text) {
        let t = raw.trim();
        let Some(first) = t.chars().next() else {
            continue;
        };
        if matches!(first, '#' | '!' | '%' | '*') || first.is_alphabetic() {
            continue;
        }
        let at = At { file, line };
        let (id, values) = delimited(at, t).or_else(|e| nwrite(at, raw).ok_or(e))?;
        let p = Vector3::new(values[0], values[1], values[2]);
        for (k, name) in ["thxy", "thyz", "thzx"].iter().enumerate() {
            if values[3 + k] != 0.0 {
                return Err(at.error(
                    name,
                    format!(
                        "node {id} has a rotated nodal coordinate system ({name} = {}); \
                         its matrix rows are in nodal axes, which is not supported",
                        values[3 + k]
                    ),
                ));
            }
        }
        nodes.push(at, id.to_string(), p)?;
    }
    if nodes.is_empty() {
        return Err(format_error(
            file,
            1,
            "node",
            "the file lists no node".into(),
        ));
    }
    Ok(nodes)
}

/// A node line split at white space and/or commas (or at tabs, decimal commas read
/// as points): `id x y z` or `id x y z thxy thyz thzx`.
fn delimited(at: At, t: &str) -> Result<(i64, [f64; 6]), FeError> {
    let tabbed: Vec<String>;
    let f: Vec<&str> = if t.contains('\t') {
        tabbed = t
            .split('\t')
            .map(|x| x.trim().replace(',', "."))
            .filter(|x| !x.is_empty())
            .collect();
        tabbed.iter().map(String::as_str).collect()
    } else {
        fields(t)
    };
    if f.len() != 4 && f.len() != 7 {
        return Err(at.error(
            "line",
            format!(
                "expected `id x y z` (or NLIST's `id x y z thxy thyz thzx`), found {} fields",
                f.len()
            ),
        ));
    }
    let id = at.integer("id", f[0])?;
    let mut v = [0.0; 6];
    for (k, name) in ["x", "y", "z", "thxy", "thyz", "thzx"].iter().enumerate() {
        if let Some(s) = f.get(k + 1) {
            v[k] = at.real(name, s)?;
        }
    }
    Ok((id, v))
}

/// Width of NWRITE's integer and real fields, format (I9, 6G21.13E3).
const NWRITE_ID: usize = 9;
const NWRITE_REAL: usize = 21;

/// A line of an Ansys `NWRITE` node file, read by column: blank fields (NWRITE leaves
/// trailing zeros blank) are 0, and fields may touch. None if the line is not one.
fn nwrite(at: At, raw: &str) -> Option<(i64, [f64; 6])> {
    let raw = raw.trim_end();
    if !raw.is_ascii() || raw.len() <= NWRITE_ID || raw.len() > NWRITE_ID + 6 * NWRITE_REAL {
        return None;
    }
    let id = raw[..NWRITE_ID].trim().parse::<i64>().ok()?;
    let mut v = [0.0; 6];
    for (k, chunk) in raw.as_bytes()[NWRITE_ID..].chunks(NWRITE_REAL).enumerate() {
        let s = std::str::from_utf8(chunk).ok()?.trim();
        if !s.is_empty() {
            v[k] = at.real("x", s).ok()?;
        }
    }
    Some((id, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_generic_csv_and_nlist() {
        let g = parse_node_list("# id x y z\n1 0 0 0\n2, 1.5, 0, 0\r\n", "n.txt").unwrap();
        assert_eq!(g.ids, vec!["1", "2"]);
        assert_eq!(g.positions[1].x, 1.5);
        let nlist = " LIST ALL SELECTED NODES.   DSYS=      0\n\n    NODE        X     Y     Z     THXY     THYZ     THZX\n        7   1.0   2.0   3.0   0.00   0.00   0.00\n";
        let n = parse_node_list(nlist, "nlist.lis").unwrap();
        assert_eq!(n.ids, vec!["7"]);
        assert_eq!(n.index["7"], 0);
        let wb = "Knotennummer\tX-Position (m)\tY-Position (m)\tZ-Position (m)\t\n3\t-7,5e-011\t2,1e-014\t1,e-001\t\n";
        let w = parse_node_list(wb, "wb.txt").unwrap();
        assert_eq!(w.ids, vec!["3"]);
        assert_eq!(w.positions[0].z, 0.1);
        // NWRITE: fields of 21 characters that touch, trailing zeros left blank.
        let nw = format!(
            "{:>9}{:>21}{:>21}\n{:>9}{:>21}\n",
            4, "-0.1234567890123E+003", "0.5", 5, "2."
        );
        let n = parse_node_list(&nw, "j.node").unwrap();
        assert_eq!(n.ids, vec!["4", "5"]);
        assert_eq!(n.positions[0], Vector3::new(-123.4567890123, 0.5, 0.0));
        assert_eq!(n.positions[1], Vector3::new(2.0, 0.0, 0.0));
    }

    #[test]
    fn refuses_bad_lists() {
        let cases: &[(&str, &str)] = &[
            ("", "n:1: node: the file lists no node"),
            ("# only comments\n", "lists no node"),
            ("1 0 0\n", "n:1: line: expected `id x y z`"),
            ("1.5 0 0 0\n", "id: expected an integer"),
            ("1 0 0 nan\n", "z: value `nan` is not finite"),
            ("1 0 0 0\n1 1 1 1\n", "n:2: node: node 1 is defined twice"),
            (
                "1 0 0 0 0 0 30\n",
                "thzx: node 1 has a rotated nodal coordinate system",
            ),
        ];
        for (text, want) in cases {
            let e = parse_node_list(text, "n").unwrap_err().to_string();
            assert!(e.contains(want), "{text:?}: {e}");
        }
    }
}
