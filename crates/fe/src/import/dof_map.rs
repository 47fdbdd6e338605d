//! DOF maps: which node and which DOF each matrix row stands for.
//!
//! - **Generic** (`parse_dof_map`): one line per matrix row, in row order,
//!   `node_id dof` with `dof` one of `ux uy uz rx ry rz` (any case) or `1`…`6`;
//!   white space and/or a comma between; `#` starts a comment line; blank lines skipped.
//! - **Ansys** (`parse_ansys_mapping`): the `Fname.mapping` file of `HBMAT, …,
//!   Mapping=YES`: an optional header line (`Matrix Eqn   Node   DOF`), then one line per
//!   equation, `eqn node label`, label one of `UX UY UZ ROTX ROTY ROTZ`; each
//!   equation 1…N exactly once (N = number of lines), any order. Checked against the
//!   Ansys Command Reference (`HBMAT`: `Mapping=YES` writes `Fname.mapping`) and a public
//!   reader of such files (HelioAB/CableSSB-zh, `InputAnsysMapping`: `eqn node label`
//!   lines, labels UX…ROTZ); no real `.mapping` file was available to test.
//! - **Ansys node vector** (`parse_ansys_node_vector`): a Matrix Market
//!   `array integer general` file of N × 1 entries, the user node number of each
//!   block of three matrix rows (UX, UY, UZ): rows 3k…3k+2 are node v_k. This is the
//!   vector Exudyn's `FEMinterface.ReadMassMatrixFromAnsys` takes with Ansys MMF
//!   exports (three DOFs per node, solid meshes); the export command is not documented
//!   there, and the three-DOF layout is its assumption.
//! - **CalculiX** (`parse_calculix_dof`): the `jobname.dof` file of `*FREQUENCY,
//!   SOLVER=MATRIXSTORAGE`: one line per equation, in order, `node.dof` (e.g. `12.3`).
//!
//! Node ids are resolved against the node list by the model
//! (an unknown node is refused there, naming this file and line).

use super::text::{At, fields, format_error, numbered_lines, quote};
use crate::error::FeError;
use crate::reduced::Dof;

/// One matrix row: the node id as written, the DOF and the 1-based line it came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DofEntry {
    /// Node id as written in the file.
    pub node: String,
    /// The DOF.
    pub dof: Dof,
    /// 1-based line of the DOF-map file.
    pub line: usize,
}

/// The DOF of Abaqus/CalculiX/generic DOF number 1…6.
pub(crate) fn dof_of_number(k: i64) -> Option<Dof> {
    Some(match k {
        1 => Dof::Ux,
        2 => Dof::Uy,
        3 => Dof::Uz,
        4 => Dof::Rx,
        5 => Dof::Ry,
        6 => Dof::Rz,
        _ => return None,
    })
}

fn dof_of_name(s: &str) -> Option<Dof> {
    Some(match s.to_ascii_lowercase().as_str() {
        "ux" | "1" => Dof::Ux,
        "uy" | "2" => Dof::Uy,
        "uz" | "3" => Dof::Uz,
        "rx" | "4" => Dof::Rx,
        "ry" | "5" => Dof::Ry,
        "rz" | "6" => Dof::Rz,
        _ => return None,
    })
}

fn dof_of_ansys_label(s: &str) -> Option<Dof> {
    Some(match s.to_ascii_uppercase().as_str() {
        "UX" => Dof::Ux,
        "UY" => Dof::Uy,
        "UZ" => Dof::Uz,
        "ROTX" => Dof::Rx,
        "ROTY" => Dof::Ry,
        "ROTZ" => Dof::Rz,
        _ => return None,
    })
}

/// Parse a generic DOF-map file.
pub fn parse_dof_map(text: &str, file: &str) -> Result<Vec<DofEntry>, FeError> {
    let mut out = Vec::new();
    for (line, raw) in numbered_lines(text) {
        let t = raw.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        let at = At { file, line };
        let f = fields(t);
        at.expect_fields(&f, 2, "node_id dof")?;
        let node = at.integer("node_id", f[0])?.to_string();
        let dof = dof_of_name(f[1]).ok_or_else(|| {
            at.error(
                "dof",
                format!(
                    "expected ux, uy, uz, rx, ry, rz or 1…6, found {}",
                    quote(f[1])
                ),
            )
        })?;
        out.push(DofEntry { node, dof, line });
    }
    non_empty(out, file)
}

/// Parse an Ansys `HBMAT` mapping file.
pub fn parse_ansys_mapping(text: &str, file: &str) -> Result<Vec<DofEntry>, FeError> {
    let mut rows: Vec<(usize, DofEntry)> = Vec::new();
    let mut seen_data = false;
    for (line, raw) in numbered_lines(text) {
        let t = raw.trim();
        if t.is_empty() || t.starts_with('%') || t.starts_with('!') {
            continue;
        }
        let at = At { file, line };
        let f = fields(t);
        if !seen_data && f.first().is_some_and(|x| x.parse::<i64>().is_err()) {
            continue; // the header line
        }
        seen_data = true;
        at.expect_fields(&f, 3, "equation node dof-label")?;
        let eqn = at.count("equation", f[0])?;
        let node = at.integer("node", f[1])?.to_string();
        let dof = dof_of_ansys_label(f[2]).ok_or_else(|| {
            at.error(
                "dof",
                format!(
                    "{} is not a structural DOF label (accepted: UX, UY, UZ, ROTX, ROTY, ROTZ)",
                    quote(f[2])
                ),
            )
        })?;
        rows.push((eqn, DofEntry { node, dof, line }));
    }
    let n = rows.len();
    rows.sort_by_key(|(eqn, _)| *eqn);
    for (k, (eqn, e)) in rows.iter().enumerate() {
        if *eqn != k + 1 {
            let msg = if *eqn == k {
                format!("equation {eqn} is given twice")
            } else {
                format!("equation numbers must be 1…{n}, each once; found {eqn}")
            };
            return Err(format_error(file, e.line, "equation", msg));
        }
    }
    non_empty(rows.into_iter().map(|(_, e)| e).collect(), file)
}

/// Parse an Ansys node vector (Matrix Market `array integer general`, N × 1).
pub fn parse_ansys_node_vector(text: &str, file: &str) -> Result<Vec<DofEntry>, FeError> {
    let mut lines = numbered_lines(text).filter(|(_, l)| {
        let t = l.trim();
        !t.is_empty() && !t.starts_with('%')
    });
    let banner = numbered_lines(text)
        .next()
        .map(|(_, l)| l.to_ascii_lowercase());
    let array = banner.is_some_and(|b| {
        b.split_whitespace().collect::<Vec<_>>()
            == ["%%matrixmarket", "matrix", "array", "integer", "general"]
    });
    if !array {
        return Err(format_error(
            file,
            1,
            "header",
            "expected the banner `%%MatrixMarket matrix array integer general`".into(),
        ));
    }
    let (line, size) = lines
        .next()
        .ok_or_else(|| format_error(file, 1, "size", "no size line `N 1`".into()))?;
    let at = At { file, line };
    let f = fields(size);
    at.expect_fields(&f, 2, "rows 1")?;
    let n = at.count("rows", f[0])?;
    if at.count("cols", f[1])? != 1 {
        return Err(at.error(
            "cols",
            format!("a node vector has 1 column, found {}", f[1]),
        ));
    }
    if n > text.len() {
        return Err(at.error(
            "rows",
            format!("{n} rows cannot be held by a file of {} bytes", text.len()),
        ));
    }
    let mut out = Vec::with_capacity(3 * n);
    for (line, l) in lines {
        let at = At { file, line };
        if out.len() == 3 * n {
            return Err(at.error("node", format!("more than the {n} declared entries")));
        }
        let node = at.integer("node", l.trim())?.to_string();
        for dof in [Dof::Ux, Dof::Uy, Dof::Uz] {
            out.push(DofEntry {
                node: node.clone(),
                dof,
                line,
            });
        }
    }
    if out.len() != 3 * n {
        return Err(format_error(
            file,
            numbered_lines(text).count(),
            "node",
            format!(
                "the file ends after {} of the {n} declared entries",
                out.len() / 3
            ),
        ));
    }
    non_empty(out, file)
}

/// Parse a CalculiX `.dof` file.
pub fn parse_calculix_dof(text: &str, file: &str) -> Result<Vec<DofEntry>, FeError> {
    let mut out = Vec::new();
    for (line, raw) in numbered_lines(text) {
        let t = raw.trim();
        if t.is_empty() {
            continue;
        }
        let at = At { file, line };
        let (node, dof) = t.split_once('.').ok_or_else(|| {
            at.error(
                "node.dof",
                format!("expected `node.dof`, found {}", quote(t)),
            )
        })?;
        let node = at.integer("node", node)?.to_string();
        let k = at.integer("dof", dof)?;
        let dof = dof_of_number(k)
            .ok_or_else(|| at.error("dof", format!("DOF {k} is not one of 1…6")))?;
        out.push(DofEntry { node, dof, line });
    }
    non_empty(out, file)
}

fn non_empty(v: Vec<DofEntry>, file: &str) -> Result<Vec<DofEntry>, FeError> {
    if v.is_empty() {
        return Err(format_error(file, 1, "dof", "the DOF map is empty".into()));
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_three_layouts() {
        let g = parse_dof_map("# node dof\n1 ux\n1, 2\n2 RZ\n", "d").unwrap();
        assert_eq!(
            g.iter()
                .map(|e| (e.node.as_str(), e.dof))
                .collect::<Vec<_>>(),
            vec![("1", Dof::Ux), ("1", Dof::Uy), ("2", Dof::Rz)]
        );
        let a = parse_ansys_mapping(
            "Matrix Eqn   Node   DOF\n 2 5 UY\n 1 5 UX\n 3 6 ROTZ\n",
            "m",
        )
        .unwrap();
        assert_eq!(
            a.iter()
                .map(|e| (e.node.as_str(), e.dof))
                .collect::<Vec<_>>(),
            vec![("5", Dof::Ux), ("5", Dof::Uy), ("6", Dof::Rz)]
        );
        let v = parse_ansys_node_vector(
            "%%MatrixMarket matrix array integer general\n% c\n2 1\n7\n3\n",
            "v",
        )
        .unwrap();
        assert_eq!(v.len(), 6);
        assert_eq!((v[3].node.as_str(), v[3].dof, v[3].line), ("3", Dof::Ux, 5));
        for (text, want) in [
            ("", "header"),
            (
                "%%MatrixMarket matrix array integer general\n",
                "no size line",
            ),
            (
                "%%MatrixMarket matrix array integer general\n2 2\n",
                "1 column",
            ),
            (
                "%%MatrixMarket matrix array integer general\n2 1\n1\n",
                "ends after 1 of the 2",
            ),
            (
                "%%MatrixMarket matrix array integer general\n1 1\n1\n2\n",
                "more than the 1",
            ),
            (
                "%%MatrixMarket matrix array integer general\n99999 1\n1\n",
                "cannot be held",
            ),
            (
                "%%MatrixMarket matrix array integer general\n1 1\nx\n",
                "node: expected an integer",
            ),
        ] {
            let e = parse_ansys_node_vector(text, "v").unwrap_err().to_string();
            assert!(e.contains(want), "{text:?}: {e}");
        }
        let c = parse_calculix_dof("1.1\n1.2\n12.3\n", "c.dof").unwrap();
        assert_eq!(
            (c[2].node.as_str(), c[2].dof, c[2].line),
            ("12", Dof::Uz, 3)
        );
    }

    #[test]
    fn refuses_bad_maps() {
        let cases: &[(&str, &str)] = &[
            ("", "d:1: dof: the DOF map is empty"),
            ("1 ux uy\n", "d:1: line: expected 2 fields"),
            ("1 wx\n", "d:1: dof: expected ux"),
            ("a ux\n", "node_id: expected an integer"),
            ("1 7\n", "dof: expected ux"),
        ];
        for (text, want) in cases {
            let e = parse_dof_map(text, "d").unwrap_err().to_string();
            assert!(e.contains(want), "{text:?}: {e}");
        }
        let cases: &[(&str, &str)] = &[
            ("1 1 TEMP\n", "m:1: dof: `TEMP` is not a structural DOF"),
            ("1 1 UX\n1 1 UY\n", "equation 1 is given twice"),
            (
                "1 1 UX\n3 1 UY\n",
                "m:2: equation: equation numbers must be 1…2",
            ),
            ("1 1\n", "expected 3 fields"),
        ];
        for (text, want) in cases {
            let e = parse_ansys_mapping(text, "m").unwrap_err().to_string();
            assert!(e.contains(want), "{text:?}: {e}");
        }
        for (text, want) in [
            ("12\n", "expected `node.dof`"),
            ("1.9\n", "DOF 9 is not"),
            ("x.1\n", "node: expected"),
        ] {
            let e = parse_calculix_dof(text, "c").unwrap_err().to_string();
            assert!(e.contains(want), "{text:?}: {e}");
        }
    }
}
