//! From the scanned Abaqus input to a mesh: parts instantiated, ids qualified by
//! their instance, connectivity and sets resolved to indices (see [`super::abaqus_inp`]).

use std::collections::{HashMap, HashSet};

use nalgebra::{Rotation3, Unit, Vector3};

use super::abaqus_inp::{Block, RawInput, RawInstance, RawSet, label, no_nodes};
use super::mesh::{Element, FeMesh};
use super::text::{At, format_error, quote};
use crate::error::FeError;

/// A scope being resolved: the id prefix (instance name) and the placement.
struct Scope<'a> {
    prefix: Option<&'a str>,
    place: Box<dyn Fn(Vector3<f64>) -> Vector3<f64> + 'a>,
}

/// The id of `token` in a scope: `I.token`, or `token` itself when it already names an
/// instance (`J.5`) or at the top level.
fn qualify(prefix: Option<&str>, token: &str) -> String {
    match prefix {
        Some(p) if !token.contains('.') => format!("{p}.{token}"),
        _ => token.to_string(),
    }
}

/// Build the mesh.
pub(crate) fn resolve(raw: RawInput, file: &str) -> Result<FeMesh, FeError> {
    let mut mesh = FeMesh::default();
    let mut element_index = HashMap::new();
    let mut scoped: Vec<(Scope, Vec<&Block>)> = vec![
        (identity(None), vec![&raw.top]),
        (identity(None), vec![&raw.assembly]),
    ];
    for inst in &raw.instances {
        let part = raw.parts.get(&inst.part).ok_or_else(|| {
            format_error(
                file,
                inst.line,
                "part",
                format!(
                    "instance {} refers to part {}, which is not defined",
                    inst.name, inst.part
                ),
            )
        })?;
        scoped.push((placed(inst), vec![part, &inst.own]));
    }
    for (scope, blocks) in &scoped {
        for b in blocks {
            for n in &b.nodes {
                let at = At { file, line: n.line };
                let id = qualify(scope.prefix, &n.label.to_string());
                mesh.nodes.push(at, id, (scope.place)(n.position))?;
            }
        }
    }
    if mesh.nodes.is_empty() {
        return Err(no_nodes(file));
    }
    for (scope, blocks) in &scoped {
        for b in blocks {
            add_elements(&mut mesh, &mut element_index, b, scope.prefix, file)?;
        }
    }
    // Sets: the assembly's last, since they may name the instances' sets.
    let mut budget = SET_WORK_PER_ENTITY * (mesh.nodes.len() + mesh.elements.len());
    for (scope, blocks) in scoped.iter().skip(2).chain(scoped.iter().take(2)) {
        for b in blocks {
            for set in &b.sets {
                let mut members = Members::new(&mut budget, file, set.line);
                add_set(&mut mesh, &element_index, set, scope.prefix, &mut members)?;
            }
        }
    }
    Ok(mesh)
}

fn identity(prefix: Option<&str>) -> Scope<'_> {
    Scope {
        prefix,
        place: Box::new(|p| p),
    }
}

fn placed(inst: &RawInstance) -> Scope<'_> {
    let t = inst.translation.unwrap_or_else(Vector3::zeros);
    let rot = inst.rotation.map(|(a, b, angle)| {
        (
            a,
            Rotation3::from_axis_angle(&Unit::new_normalize(b - a), angle.to_radians()),
        )
    });
    Scope {
        prefix: Some(&inst.name),
        place: Box::new(move |p| {
            let p = p + t;
            match &rot {
                Some((a, r)) => a + r * (p - a),
                None => p,
            }
        }),
    }
}

fn add_elements(
    mesh: &mut FeMesh,
    index: &mut HashMap<String, usize>,
    b: &Block,
    prefix: Option<&str>,
    file: &str,
) -> Result<(), FeError> {
    for e in &b.elements {
        let at = At { file, line: e.line };
        let id = qualify(prefix, &e.label.to_string());
        let nodes = e
            .nodes
            .iter()
            .map(|tok| {
                let nid = qualify(prefix, tok);
                mesh.nodes.index.get(&nid).copied().ok_or_else(|| {
                    at.error(
                        "*Element",
                        format!(
                            "element {id} refers to node {}, which is not defined",
                            quote(&nid)
                        ),
                    )
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        if index.insert(id.clone(), mesh.elements.len()).is_some() {
            return Err(at.error("label", format!("element {id} is defined twice")));
        }
        mesh.elements.push(Element {
            id,
            kind: e.kind.clone(),
            nodes,
        });
    }
    Ok(())
}

fn add_set(
    mesh: &mut FeMesh,
    element_index: &HashMap<String, usize>,
    set: &RawSet,
    prefix: Option<&str>,
    members: &mut Members,
) -> Result<(), FeError> {
    let file = members.file;
    let name = qualify(prefix, &set.name).to_uppercase();
    let item_prefix = set.instance.as_deref().or(prefix);
    if let Some(elset) = &set.from_elset {
        let at = At {
            file,
            line: set.line,
        };
        for &e in named_set(&mesh.element_sets, &qualify(item_prefix, elset), at)? {
            members.extend(&mesh.elements[e].nodes)?;
        }
    }
    let (ids, sets) = if set.is_node_set {
        (&mesh.nodes.index, &mesh.node_sets)
    } else {
        (element_index, &mesh.element_sets)
    };
    for (line, items) in &set.items {
        let at = At { file, line: *line };
        if set.generate {
            generated(at, items, item_prefix, ids, members)?;
            continue;
        }
        for tok in items {
            let is_label = tok
                .rsplit('.')
                .next()
                .is_some_and(|l| l.parse::<i64>().is_ok());
            if is_label {
                let id = qualify(item_prefix, tok);
                members.add(*ids.get(&id).ok_or_else(|| unknown(at, set, &id))?)?;
            } else {
                members.extend(named_set(sets, &qualify(item_prefix, tok), at)?)?;
            }
        }
    }
    let target = if set.is_node_set {
        &mut mesh.node_sets
    } else {
        &mut mesh.element_sets
    };
    let entry = target.entry(name).or_default();
    entry.append(&mut members.list);
    entry.sort_unstable();
    entry.dedup();
    Ok(())
}

/// Work allowed to the sets of a file, per node and element: each member a set
/// definition adds (a label, a `generate` step, a member of a named set) costs one.
/// Legitimate files stay far below; a hostile one that names a large set or range
/// many times would otherwise cost time quadratic in its length.
const SET_WORK_PER_ENTITY: usize = 64;

/// The members of one set definition, each index once, within the file's budget.
struct Members<'b> {
    seen: HashSet<usize>,
    list: Vec<usize>,
    budget: &'b mut usize,
    file: &'b str,
    line: usize,
}

impl<'b> Members<'b> {
    fn new(budget: &'b mut usize, file: &'b str, line: usize) -> Self {
        Members {
            seen: HashSet::new(),
            list: Vec::new(),
            budget,
            file,
            line,
        }
    }

    fn add(&mut self, i: usize) -> Result<(), FeError> {
        if *self.budget == 0 {
            return Err(format_error(
                self.file,
                self.line,
                "set",
                format!(
                    "the sets of this file name more than {SET_WORK_PER_ENTITY} members per \
                     node and element in all; refused"
                ),
            ));
        }
        *self.budget -= 1;
        if self.seen.insert(i) {
            self.list.push(i);
        }
        Ok(())
    }

    fn extend(&mut self, items: &[usize]) -> Result<(), FeError> {
        items.iter().try_for_each(|&i| self.add(i))
    }
}

fn unknown(at: At, set: &RawSet, id: &str) -> FeError {
    let what = if set.is_node_set { "node" } else { "element" };
    at.error(&set.name, format!("{what} {} is not defined", quote(id)))
}

/// A set by name (case-insensitive, as Abaqus names are: sets are stored upper case).
fn named_set<'a>(
    sets: &'a std::collections::BTreeMap<String, Vec<usize>>,
    name: &str,
    at: At,
) -> Result<&'a [usize], FeError> {
    sets.get(&name.to_uppercase())
        .map(Vec::as_slice)
        .ok_or_else(|| {
            at.error(
                "set",
                format!("set {} is not defined (before this line)", quote(name)),
            )
        })
}

/// `first, last[, step]` of a `generate` set line.
fn generated(
    at: At,
    items: &[String],
    prefix: Option<&str>,
    ids: &HashMap<String, usize>,
    members: &mut Members,
) -> Result<(), FeError> {
    if items.len() != 2 && items.len() != 3 {
        return Err(at.error(
            "generate",
            format!(
                "expected `first, last[, step]`, found {} fields",
                items.len()
            ),
        ));
    }
    let first = label(at, "first", &items[0])?;
    let last = label(at, "last", &items[1])?;
    let step = match items.get(2) {
        Some(s) => label(at, "step", s)?,
        None => 1,
    };
    if last < first {
        return Err(at.error("last", format!("last {last} is below first {first}")));
    }
    let count = (last - first) / step + 1;
    if count as u64 > ids.len() as u64 {
        return Err(at.error(
            "generate",
            format!(
                "{first}…{last} step {step} names {count} labels, more than the {} defined",
                ids.len()
            ),
        ));
    }
    let mut l = first;
    while l <= last {
        let id = qualify(prefix, &l.to_string());
        members.add(*ids.get(&id).ok_or_else(|| {
            at.error("generate", format!("label {} is not defined", quote(&id)))
        })?)?;
        match l.checked_add(step) {
            Some(next) => l = next,
            None => break,
        }
    }
    Ok(())
}
