//! Abaqus input files (`.inp`): the mesh — `*Node`, `*Element`, `*Nset`, `*Elset`,
//! `*Part`/`*End Part`, `*Assembly`/`*End Assembly`, `*Instance`/`*End Instance`.
//!
//! Syntax as in the Abaqus Analysis User's Guide, "Input syntax rules" (§1.2.1):
//! a keyword line starts with `*`, its parameters follow after commas as
//! `name=value` or a bare `name`; keywords and parameter names are case-insensitive
//! and may contain spaces (`*End Part`, `*Solid Section`); `**` starts a comment line;
//! data lines are comma separated. Every other keyword (materials, sections, steps,
//! surfaces, …) is skipped with its data lines; `*Include` and `*Node, input=…` are
//! refused (merge the files first), as is a `*Node, system=…` other than `R`. Parts and
//! the assembly nest as Abaqus writes them (`*Part … *End Part` outside the assembly,
//! `*Instance … *End Instance` inside it); anything else, or a file that ends inside
//! one of them, is refused.
//!
//! - `*Node[, nset=N]`: `label, x[, y[, z]]` (missing coordinates are 0; further fields,
//!   the normal of a shell node, are ignored).
//! - `*Element, type=T[, elset=E]`: `label, n1, n2, …`; a line ending in a comma
//!   continues on the next one, and for the types whose node count is known
//!   ([`nodes_of_type`]) lines are joined until it is reached, then checked.
//! - `*Nset, nset=N` / `*Elset, elset=E` [`, generate`][`, instance=I`][`, elset=E`
//!   for a node set made of an element set's nodes]: labels or set names, or with
//!   `generate` lines `first, last[, step]`.
//! - Parts and instances: what a `*Part` defines is instantiated by each `*Instance,
//!   name=I, part=P`; node and element ids become `I.label` and set names `I.N`.
//!   The instance's optional data lines are a translation `tx, ty, tz` and a rotation
//!   `ax, ay, az, bx, by, bz, angle` (degrees, right-handed about the axis from point
//!   a to point b), applied in that order: p' = a + R (p + t − a). A mesh given inside
//!   `*Instance … *End Instance` belongs to that instance. Nodes, elements and sets at
//!   the assembly level or outside any part keep plain ids; an assembly set with
//!   `instance=I` refers to the nodes of I. A data-line item `I.label` always names the
//!   node of instance I. Set names are case-insensitive in Abaqus and are stored upper
//!   case (`BLOCK-1.SET-1`); node and element ids keep the file's case.
//!
//! Source checked against: the Abaqus Keywords Reference (`*NODE`, `*ELEMENT`,
//! `*NSET`, `*ELSET`, `*INSTANCE`) and a real Abaqus/CAE job, Exudyn's
//! `sliderCrankACME/job_matrix_generate_crank.inp` (tests/data/import/README.md).

use std::collections::HashMap;

use nalgebra::Vector3;

use super::abaqus_resolve::resolve;
use super::mesh::FeMesh;
use super::text::{At, comma_fields, format_error, numbered_lines, quote};
use crate::error::FeError;

/// A `*Node` data line as read.
#[derive(Clone, Debug)]
pub(crate) struct RawNode {
    pub label: i64,
    pub position: Vector3<f64>,
    pub line: usize,
}

/// An `*Element` data record as read (continuation lines joined).
#[derive(Clone, Debug)]
pub(crate) struct RawElement {
    pub label: i64,
    pub kind: String,
    pub nodes: Vec<String>,
    pub line: usize,
}

/// An `*Nset` or `*Elset` keyword with its data lines.
#[derive(Clone, Debug, Default)]
pub(crate) struct RawSet {
    pub name: String,
    pub is_node_set: bool,
    pub generate: bool,
    pub instance: Option<String>,
    pub from_elset: Option<String>,
    pub line: usize,
    pub items: Vec<(usize, Vec<String>)>,
}

/// What one scope (the file outside parts, a part, an instance, the assembly) defines.
#[derive(Clone, Debug, Default)]
pub(crate) struct Block {
    pub nodes: Vec<RawNode>,
    pub elements: Vec<RawElement>,
    pub sets: Vec<RawSet>,
}

/// An `*Instance` with its placement and its own mesh lines.
#[derive(Clone, Debug)]
pub(crate) struct RawInstance {
    pub name: String,
    pub part: String,
    pub line: usize,
    pub translation: Option<Vector3<f64>>,
    pub rotation: Option<(Vector3<f64>, Vector3<f64>, f64)>,
    pub own: Block,
}

/// The whole file, scanned.
#[derive(Clone, Debug, Default)]
pub(crate) struct RawInput {
    pub top: Block,
    pub parts: HashMap<String, Block>,
    pub instances: Vec<RawInstance>,
    pub assembly: Block,
}

#[derive(Clone, Debug, PartialEq)]
enum Scope {
    Top,
    Part(String),
    Assembly,
    Instance(usize),
}

/// What the data lines that follow the current keyword are.
enum Data {
    Skip,
    /// `*Node`; the `nset=` name and the index of its first node in the block.
    Nodes(Option<(String, usize)>),
    /// `*Element` of a type; the `elset=` name and the index of its first element.
    Elements(String, Option<(String, usize)>),
    Set(RawSet),
    Placement(usize),
}

/// Number of nodes of the common element types (None for others).
pub fn nodes_of_type(kind: &str) -> Option<usize> {
    let k = kind.to_ascii_uppercase();
    let base = k.trim_end_matches(['R', 'H', 'I', 'M', 'T']);
    Some(match base {
        "C3D4" => 4,
        "C3D6" => 6,
        "C3D8" => 8,
        "C3D10" => 10,
        "C3D15" => 15,
        "C3D20" => 20,
        "S3" | "STRI3" | "CPS3" | "CPE3" => 3,
        "S4" | "CPS4" | "CPE4" => 4,
        "S6" | "STRI65" | "CPS6" | "CPE6" => 6,
        "S8" | "CPS8" | "CPE8" => 8,
        "S9" => 9,
        _ => return None,
    })
}

/// Parse Abaqus input text into a mesh; `file` names it in errors.
pub fn parse_abaqus_inp(text: &str, file: &str) -> Result<FeMesh, FeError> {
    let raw = scan(text, file)?;
    resolve(raw, file)
}

/// A keyword line: upper-case name with single spaces, parameters (upper-case names).
struct Keyword {
    name: String,
    params: HashMap<String, String>,
}

fn parse_keyword(t: &str) -> Keyword {
    let mut parts = t[1..].split(',');
    let name = parts
        .next()
        .unwrap_or("")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_ascii_uppercase();
    let params = parts
        .filter(|p| !p.trim().is_empty())
        .map(|p| match p.split_once('=') {
            Some((k, v)) => (norm(k), v.trim().trim_matches('"').to_string()),
            None => (norm(p), String::new()),
        })
        .collect();
    Keyword { name, params }
}

fn norm(k: &str) -> String {
    k.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_ascii_uppercase()
}

fn scan(text: &str, file: &str) -> Result<RawInput, FeError> {
    let mut raw = RawInput::default();
    let mut scope = Scope::Top;
    let mut data = Data::Skip;
    let mut pending: Option<(usize, Vec<String>)> = None; // an element record being joined
    for (line, l) in numbered_lines(text) {
        let t = l.trim();
        let at = At { file, line };
        if t.is_empty() || t.starts_with("**") {
            continue;
        }
        if t.starts_with('*') {
            flush_element(&mut raw, &scope, &data, &mut pending, file)?;
            close(&mut raw, &scope, std::mem::replace(&mut data, Data::Skip));
            let kw = parse_keyword(t);
            data = open(&mut raw, &mut scope, &kw, at)?;
            continue;
        }
        match &mut data {
            Data::Skip => {}
            Data::Nodes(_) => {
                let node = parse_node_line(at, t)?;
                block(&mut raw, &scope).nodes.push(node);
            }
            Data::Elements(kind, _) => {
                let mut f: Vec<String> = comma_fields(t).into_iter().map(String::from).collect();
                let (start, mut acc) = pending.take().unwrap_or((line, Vec::new()));
                acc.append(&mut f);
                let want = nodes_of_type(kind).map(|n| n + 1);
                let more = match want {
                    Some(w) => acc.len() < w,
                    None => t.ends_with(','),
                };
                if more {
                    pending = Some((start, acc));
                } else {
                    let e = element_record(At { file, line: start }, kind, acc)?;
                    block(&mut raw, &scope).elements.push(e);
                }
            }
            Data::Set(set) => set.items.push((
                line,
                comma_fields(t).into_iter().map(String::from).collect(),
            )),
            Data::Placement(i) => place(&mut raw.instances[*i], at, t)?,
        }
    }
    flush_element(&mut raw, &scope, &data, &mut pending, file)?;
    close(&mut raw, &scope, data);
    if scope != Scope::Top {
        let last = numbered_lines(text).count();
        return Err(format_error(
            file,
            last,
            "end of file",
            format!("the file ends {}", scope_name(&scope)),
        ));
    }
    Ok(raw)
}

/// Parts and instances nest as `*Part … *End Part` at the top and
/// `*Assembly (*Instance … *End Instance)* *End Assembly`.
fn nesting_ok(scope: &Scope, keyword: &str) -> bool {
    matches!(
        (scope, keyword),
        (Scope::Top, "PART" | "ASSEMBLY")
            | (Scope::Part(_), "END PART")
            | (Scope::Assembly, "INSTANCE" | "END ASSEMBLY")
            | (Scope::Instance(_), "END INSTANCE")
    )
}

fn scope_name(scope: &Scope) -> String {
    match scope {
        Scope::Top => "outside any part or assembly".into(),
        Scope::Part(p) => format!("inside *Part {p}, before its *End Part"),
        Scope::Assembly => "inside *Assembly, before its *End Assembly".into(),
        Scope::Instance(_) => "inside *Instance, before its *End Instance".into(),
    }
}

fn block<'a>(raw: &'a mut RawInput, scope: &Scope) -> &'a mut Block {
    match scope {
        Scope::Top => &mut raw.top,
        Scope::Part(p) => raw.parts.entry(p.clone()).or_default(),
        Scope::Assembly => &mut raw.assembly,
        Scope::Instance(i) => &mut raw.instances[*i].own,
    }
}

/// An element record still waiting for continuation lines when a keyword comes.
fn flush_element(
    raw: &mut RawInput,
    scope: &Scope,
    data: &Data,
    pending: &mut Option<(usize, Vec<String>)>,
    file: &str,
) -> Result<(), FeError> {
    if let (Some((line, acc)), Data::Elements(kind, _)) = (pending.take(), data) {
        let e = element_record(At { file, line }, kind, acc)?;
        block(raw, scope).elements.push(e);
    }
    Ok(())
}

/// End of a keyword's data: a set is stored; `nset=`/`elset=` of `*Node`/`*Element`
/// become sets of what was just read.
fn close(raw: &mut RawInput, scope: &Scope, data: Data) {
    match data {
        Data::Set(set) => block(raw, scope).sets.push(set),
        Data::Nodes(Some((name, start))) => {
            let b = block(raw, scope);
            let items = b.nodes[start..]
                .iter()
                .map(|n| (n.line, vec![n.label.to_string()]))
                .collect();
            b.sets.push(RawSet {
                name,
                is_node_set: true,
                items,
                ..RawSet::default()
            });
        }
        Data::Elements(_, Some((name, start))) => {
            let b = block(raw, scope);
            let items = b.elements[start..]
                .iter()
                .map(|e| (e.line, vec![e.label.to_string()]))
                .collect();
            b.sets.push(RawSet {
                name,
                items,
                ..RawSet::default()
            });
        }
        _ => {}
    }
}

fn open(raw: &mut RawInput, scope: &mut Scope, kw: &Keyword, at: At) -> Result<Data, FeError> {
    let p = |k: &str| kw.params.get(k).cloned();
    Ok(match kw.name.as_str() {
        "INCLUDE" => {
            return Err(at.error(
                "*Include",
                "included files are not read; merge them into one input file".into(),
            ));
        }
        "PART" | "ASSEMBLY" | "INSTANCE" | "END PART" | "END ASSEMBLY" | "END INSTANCE"
            if !nesting_ok(scope, &kw.name) =>
        {
            return Err(at.error(
                &format!("*{}", kw.name),
                format!("not allowed here ({})", scope_name(scope)),
            ));
        }
        "PART" => {
            let name = required(at, kw, "NAME")?.to_ascii_uppercase();
            raw.parts.entry(name.clone()).or_default();
            *scope = Scope::Part(name);
            Data::Skip
        }
        "END PART" | "END ASSEMBLY" => {
            *scope = Scope::Top;
            Data::Skip
        }
        "ASSEMBLY" => {
            *scope = Scope::Assembly;
            Data::Skip
        }
        "INSTANCE" => {
            raw.instances.push(RawInstance {
                name: required(at, kw, "NAME")?,
                part: required(at, kw, "PART")?.to_ascii_uppercase(),
                line: at.line,
                translation: None,
                rotation: None,
                own: Block::default(),
            });
            *scope = Scope::Instance(raw.instances.len() - 1);
            Data::Placement(raw.instances.len() - 1)
        }
        "END INSTANCE" => {
            *scope = Scope::Assembly;
            Data::Skip
        }
        "NODE" => {
            if p("INPUT").is_some() {
                return Err(at.error("*Node", "input= files are not read; merge them".into()));
            }
            if let Some(sys) = p("SYSTEM").filter(|s| !s.eq_ignore_ascii_case("R")) {
                return Err(at.error(
                    "system",
                    format!(
                        "only rectangular coordinates (system=R) are read, found {}",
                        quote(&sys)
                    ),
                ));
            }
            let start = block(raw, scope).nodes.len();
            Data::Nodes(p("NSET").map(|n| (n, start)))
        }
        "ELEMENT" => {
            let kind = required(at, kw, "TYPE")?.to_ascii_uppercase();
            let start = block(raw, scope).elements.len();
            Data::Elements(kind, p("ELSET").map(|n| (n, start)))
        }
        "NSET" | "ELSET" => {
            let is_node_set = kw.name == "NSET";
            let key = if is_node_set { "NSET" } else { "ELSET" };
            Data::Set(RawSet {
                name: required(at, kw, key)?,
                is_node_set,
                generate: kw.params.contains_key("GENERATE"),
                instance: p("INSTANCE"),
                from_elset: if is_node_set { p("ELSET") } else { None },
                line: at.line,
                items: Vec::new(),
            })
        }
        _ => Data::Skip,
    })
}

fn required(at: At, kw: &Keyword, key: &str) -> Result<String, FeError> {
    match kw.params.get(key) {
        Some(v) if !v.is_empty() => Ok(v.clone()),
        _ => Err(at.error(
            &format!("*{}", kw.name),
            format!("the parameter {}= is missing", key.to_ascii_lowercase()),
        )),
    }
}

fn parse_node_line(at: At, t: &str) -> Result<RawNode, FeError> {
    let f = comma_fields(t);
    if f.len() < 2 || f.len() > 7 {
        return Err(at.error(
            "*Node",
            format!("expected `label, x[, y[, z]]`, found {} fields", f.len()),
        ));
    }
    let label = label(at, "label", f[0])?;
    let mut p = Vector3::zeros();
    for (k, name) in ["x", "y", "z"].iter().enumerate() {
        if let Some(s) = f.get(k + 1).filter(|s| !s.is_empty()) {
            p[k] = at.real(name, s)?;
        }
    }
    Ok(RawNode {
        label,
        position: p,
        line: at.line,
    })
}

/// A positive integer label.
pub(crate) fn label(at: At, field: &str, s: &str) -> Result<i64, FeError> {
    let v = at.integer(field, s)?;
    if v <= 0 {
        return Err(at.error(field, format!("labels are positive integers, found {v}")));
    }
    Ok(v)
}

fn element_record(at: At, kind: &str, f: Vec<String>) -> Result<RawElement, FeError> {
    let Some((first, nodes)) = f.split_first() else {
        return Err(at.error("*Element", "empty element line".into()));
    };
    let label = label(at, "label", first)?;
    if let Some(n) = nodes_of_type(kind)
        && nodes.len() != n
    {
        return Err(at.error(
            "*Element",
            format!(
                "element {label} of type {kind} has {} nodes, expected {n}",
                nodes.len()
            ),
        ));
    }
    if nodes.is_empty() {
        return Err(at.error("*Element", format!("element {label} has no node")));
    }
    Ok(RawElement {
        label,
        kind: kind.to_string(),
        nodes: nodes.to_vec(),
        line: at.line,
    })
}

/// The data lines of `*Instance`: translation, then rotation.
fn place(inst: &mut RawInstance, at: At, t: &str) -> Result<(), FeError> {
    let f = comma_fields(t);
    let nums: Vec<f64> = f
        .iter()
        .enumerate()
        .map(|(k, s)| at.real(&format!("*Instance field {}", k + 1), s))
        .collect::<Result<_, _>>()?;
    if inst.rotation.is_some() {
        return Err(at.error("*Instance", "more than two placement lines".into()));
    }
    if nums.len() == 3 && inst.translation.is_none() {
        inst.translation = Some(Vector3::new(nums[0], nums[1], nums[2]));
    } else if nums.len() == 7 {
        let a = Vector3::new(nums[0], nums[1], nums[2]);
        let b = Vector3::new(nums[3], nums[4], nums[5]);
        if (b - a).norm() == 0.0 {
            return Err(at.error("*Instance", "the rotation axis points coincide".into()));
        }
        inst.rotation = Some((a, b, nums[6]));
    } else {
        return Err(at.error(
            "*Instance",
            format!(
                "expected a translation `tx, ty, tz` then a rotation `ax, ay, az, bx, by, bz, angle`, found {} fields",
                nums.len()
            ),
        ));
    }
    Ok(())
}

/// Check a file-level condition of the scan (used by the resolver too).
pub(crate) fn no_nodes(file: &str) -> FeError {
    format_error(file, 1, "*Node", "the input file defines no node".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shells_solids_spacing_case_and_continuations() {
        let text = "*HEADING\nshell and solid\n**comment\n\
                    *node , NSET = All\n1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n5,0,0,1\n6,.5,0,0\n7,.5,.5,0\n\
                    8,0,.5,0\n9,0,0,.5\n10,.5,0,.5\n11,0,.5,.5\n\
                    *Element ,  TYPE = s4r , ELSET = Shell\n1, 1, 2, 3, 4\n\
                    *element, type=S3\n2, 1, 2, 3\n\
                    *ELEMENT, TYPE=C3D10\n3, 1, 2, 4, 5, 6, 7,\n 8, 9, 10, 11\n\
                    *Element, type=C3D10M\n4, 1, 2, 4, 5, 6, 7\n 8, 9, 10, 11\n\
                    *Element, type=SPRINGA\n5, 1,\n 2\n\
                    *Solid Section, elset=Shell, material=steel\n1.0,\n\
                    *end step\n";
        let mesh = parse_abaqus_inp(text, "t.inp").unwrap();
        let kinds: Vec<(&str, usize)> = mesh
            .elements
            .iter()
            .map(|e| (e.kind.as_str(), e.nodes.len()))
            .collect();
        assert_eq!(
            kinds,
            vec![
                ("S4R", 4),
                ("S3", 3),
                ("C3D10", 10),
                ("C3D10M", 10),
                ("SPRINGA", 2)
            ]
        );
        assert_eq!(mesh.node_sets["ALL"].len(), 11);
        assert_eq!(mesh.element_sets["SHELL"], vec![0]);
        assert_eq!(nodes_of_type("c3d20r"), Some(20));
        assert_eq!(nodes_of_type("C3D8I"), Some(8));
        assert_eq!(nodes_of_type("B31"), None);
    }

    #[test]
    fn an_element_cut_short_by_a_keyword_is_refused() {
        let text = "*Node\n1,0,0,0\n*Element, type=C3D8\n1, 1, 1, 1,\n*Nset, nset=A\n1\n";
        let e = parse_abaqus_inp(text, "t.inp").unwrap_err().to_string();
        assert!(
            e.contains("t.inp:4: *Element: element 1 of type C3D8 has 3 nodes, expected 8"),
            "{e}"
        );
    }
}
