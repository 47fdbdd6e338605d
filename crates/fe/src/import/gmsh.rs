//! Gmsh MSH meshes, ASCII format 4.1 and 2.2 (Gmsh Reference Manual, §10.1 "MSH file
//! format" for 4.1 and §10.6 "Legacy formats" for 2.2; checked against the files Gmsh 4.8.4
//! writes, crates/fe/tests/data/gmsh/), read into an [`FeMesh`].
//!
//! - **Nodes**: every node of `$Nodes`, ids the node tags (decimal).
//! - **Elements**: the 3D elements become the mesh's elements, with the built-in solids' node
//!   order (Abaqus's, [`crate::solid::shape`]) and Abaqus names: Gmsh type 4 → C3D4,
//!   11 → C3D10 (Gmsh's mid-edge nodes 8 and 9, on edges 2–3 and 1–3, swapped), 5 → C3D8,
//!   17 → C3D20 (the mid-edge nodes reordered). Other 3D types (prisms, pyramids, 27-node
//!   hexahedra, higher orders) are refused by name. Points, lines, triangles and
//!   quadrangles (types 1–3, 8–10, 15, 16, 20, 21, 26–28) only give their nodes to the
//!   physical groups they belong to.
//! - **Physical groups** become **node sets**: all the nodes of the elements of every
//!   entity (4.1) or with the physical tag (2.2) of the group, named by `$PhysicalNames`,
//!   or `dim:tag` (e.g. `2:5`) when unnamed. Physical volumes are also element sets.
//!
//! Unknown sections (`$Comments`, `$NodeData`, …) are skipped; `$PartitionedEntities`,
//! parametric nodes are read (the parametric coordinates skipped), binary files and other
//! versions are refused. Every refusal names the file, the line and the field. No
//! allocation is sized from a count declared in the file.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use nalgebra::Vector3;

use super::mesh::{Element, FeMesh};
use super::nodes::NodeList;
use super::text::{At, format_error, numbered_lines, quote, read_file};
use crate::error::FeError;

/// A section's lines with their numbers, and the line of its header.
struct Section<'a> {
    name: &'a str,
    line: usize,
    lines: Vec<(usize, &'a str)>,
}

/// Split the file into `$Name … $EndName` sections.
fn sections<'a>(text: &'a str, file: &str) -> Result<Vec<Section<'a>>, FeError> {
    let mut out = Vec::new();
    let mut current: Option<Section<'a>> = None;
    for (line, raw) in numbered_lines(text) {
        let t = raw.trim();
        match current.as_mut() {
            None => {
                if let Some(name) = t.strip_prefix('$') {
                    current = Some(Section {
                        name,
                        line,
                        lines: Vec::new(),
                    });
                } else if !t.is_empty() {
                    return Err(format_error(
                        file,
                        line,
                        "section",
                        format!("expected a section header `$Name`, found {}", quote(t)),
                    ));
                }
            }
            Some(s) => {
                if t.strip_prefix("$End") == Some(s.name) {
                    out.extend(current.take());
                } else {
                    s.lines.push((line, raw));
                }
            }
        }
    }
    match current {
        Some(s) => Err(format_error(
            file,
            s.line,
            "section",
            format!("${} has no $End{}", s.name, s.name),
        )),
        None => Ok(out),
    }
}

/// White-space separated fields of a section, read in order with their line numbers.
struct Cursor<'a, 'f> {
    file: &'f str,
    lines: std::slice::Iter<'a, (usize, &'a str)>,
    words: std::str::SplitWhitespace<'a>,
    line: usize,
}

impl<'a, 'f> Cursor<'a, 'f> {
    fn new(file: &'f str, s: &'a Section<'a>) -> Self {
        Cursor {
            file,
            lines: s.lines.iter(),
            words: "".split_whitespace(),
            line: s.line,
        }
    }

    fn at(&self) -> At<'f> {
        At {
            file: self.file,
            line: self.line,
        }
    }

    fn word(&mut self, field: &str) -> Result<&'a str, FeError> {
        loop {
            if let Some(w) = self.words.next() {
                return Ok(w);
            }
            match self.lines.next() {
                Some((n, l)) => {
                    self.line = *n;
                    self.words = l.split_whitespace();
                }
                None => {
                    return Err(self
                        .at()
                        .error(field, "the section ends before this field".to_string()));
                }
            }
        }
    }

    fn count(&mut self, field: &str) -> Result<usize, FeError> {
        let w = self.word(field)?;
        self.at().count(field, w)
    }

    fn integer(&mut self, field: &str) -> Result<i64, FeError> {
        let w = self.word(field)?;
        self.at().integer(field, w)
    }

    fn real(&mut self, field: &str) -> Result<f64, FeError> {
        let w = self.word(field)?;
        self.at().real(field, w)
    }

    /// Nothing may follow the section's data.
    fn finish(mut self, section: &str) -> Result<(), FeError> {
        match self.word("") {
            Ok(w) => Err(self.at().error(
                section,
                format!("unexpected {} after the section's data", quote(w)),
            )),
            Err(_) => Ok(()),
        }
    }
}

/// What the reader knows of a Gmsh element type: dimension, nodes, and for the solids
/// the built-in kind and the Gmsh index of each node in Abaqus order.
struct GmshType {
    dim: usize,
    nodes: usize,
    name: &'static str,
    solid: Option<(&'static str, &'static [usize])>,
}

const TET10_ORDER: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];
const HEX20_ORDER: [usize; 20] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15,
];
const IDENTITY: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];

fn gmsh_type(t: i64) -> Option<GmshType> {
    let g = |dim, nodes, name, solid| {
        Some(GmshType {
            dim,
            nodes,
            name,
            solid,
        })
    };
    match t {
        15 => g(0, 1, "1-node point", None),
        1 => g(1, 2, "2-node line", None),
        8 => g(1, 3, "3-node line", None),
        26 => g(1, 4, "4-node line", None),
        27 => g(1, 5, "5-node line", None),
        28 => g(1, 6, "6-node line", None),
        2 => g(2, 3, "3-node triangle", None),
        9 => g(2, 6, "6-node triangle", None),
        20 => g(2, 9, "9-node triangle", None),
        21 => g(2, 10, "10-node triangle", None),
        3 => g(2, 4, "4-node quadrangle", None),
        16 => g(2, 8, "8-node quadrangle", None),
        10 => g(2, 9, "9-node quadrangle", None),
        4 => g(3, 4, "4-node tetrahedron", Some(("C3D4", &IDENTITY[..4]))),
        11 => g(3, 10, "10-node tetrahedron", Some(("C3D10", &TET10_ORDER))),
        5 => g(3, 8, "8-node hexahedron", Some(("C3D8", &IDENTITY))),
        17 => g(3, 20, "20-node hexahedron", Some(("C3D20", &HEX20_ORDER))),
        6 => g(3, 6, "6-node prism", None),
        7 => g(3, 5, "5-node pyramid", None),
        12 => g(3, 27, "27-node hexahedron", None),
        13 => g(3, 18, "18-node prism", None),
        14 => g(3, 14, "14-node pyramid", None),
        18 => g(3, 15, "15-node prism", None),
        19 => g(3, 13, "13-node pyramid", None),
        29 => g(3, 20, "20-node tetrahedron", None),
        _ => None,
    }
}

/// The type of a `type` field, refused by name when it is no built-in solid or facet.
fn element_type(at: At, field: &str, t: i64) -> Result<GmshType, FeError> {
    let ty = gmsh_type(t).ok_or_else(|| {
        at.error(
            field,
            format!("Gmsh element type {t} is not supported (solids: 4, 11, 5, 17)"),
        )
    })?;
    if ty.dim == 3 && ty.solid.is_none() {
        return Err(at.error(
            field,
            format!(
                "the {} (Gmsh type {t}) is not a built-in solid element: mesh with 4- or \
                 10-node tetrahedra or 8- or 20-node hexahedra",
                ty.name
            ),
        ));
    }
    Ok(ty)
}

/// The mesh being read.
#[derive(Default)]
struct Builder {
    nodes: NodeList,
    /// Physical group names by (dim, tag).
    names: HashMap<(usize, i64), String>,
    /// Physical tags of each entity (4.1), by (dim, entity tag).
    entity_groups: HashMap<(usize, i64), Vec<i64>>,
    /// Node tags of each physical group, by (dim, tag).
    group_nodes: BTreeMap<(usize, i64), BTreeSet<usize>>,
    /// Element indices of each physical volume.
    group_elements: BTreeMap<i64, Vec<usize>>,
    elements: Vec<Element>,
    /// Every element tag seen, of any dimension.
    element_tags: std::collections::HashSet<i64>,
}

impl Builder {
    /// Node index of a node tag.
    fn node(&self, at: At, field: &str, tag: i64) -> Result<usize, FeError> {
        self.nodes
            .index
            .get(&tag.to_string())
            .copied()
            .ok_or_else(|| at.error(field, format!("node {tag} is not in $Nodes")))
    }

    /// One element: its nodes into its groups, and a solid into the mesh.
    fn element(
        &mut self,
        at: At,
        id: i64,
        ty: &GmshType,
        nodes: Vec<usize>,
        groups: &[i64],
    ) -> Result<(), FeError> {
        if !self.element_tags.insert(id) {
            return Err(at.error("elementTag", format!("element {id} is defined twice")));
        }
        for &g in groups {
            self.group_nodes
                .entry((ty.dim, g))
                .or_default()
                .extend(nodes.iter().copied());
        }
        if let Some((kind, order)) = ty.solid {
            for &g in groups {
                self.group_elements
                    .entry(g)
                    .or_default()
                    .push(self.elements.len());
            }
            self.elements.push(Element {
                id: id.to_string(),
                kind: kind.to_string(),
                nodes: order.iter().map(|&k| nodes[k]).collect(),
            });
        }
        Ok(())
    }

    fn finish(self) -> FeMesh {
        let name = |dim: usize, tag: i64| {
            self.names
                .get(&(dim, tag))
                .cloned()
                .unwrap_or_else(|| format!("{dim}:{tag}"))
        };
        let node_sets = self
            .group_nodes
            .iter()
            .map(|(&(dim, tag), set)| (name(dim, tag), set.iter().copied().collect()))
            .collect();
        let element_sets = self
            .group_elements
            .iter()
            .map(|(&tag, set)| (name(3, tag), set.clone()))
            .collect();
        FeMesh {
            nodes: self.nodes,
            elements: self.elements,
            node_sets,
            element_sets,
        }
    }
}

/// Parse a Gmsh MSH file's text (module docs); `file` names it in errors.
pub fn parse_gmsh(text: &str, file: &str) -> Result<FeMesh, FeError> {
    let sections = sections(text, file)?;
    let Some(format) = sections.iter().find(|s| s.name == "MeshFormat") else {
        return Err(format_error(
            file,
            1,
            "$MeshFormat",
            "no $MeshFormat section: not a Gmsh MSH file".to_string(),
        ));
    };
    let version = mesh_format(file, format)?;
    let mut b = Builder::default();
    for s in &sections {
        match s.name {
            "PhysicalNames" => physical_names(file, s, &mut b)?,
            "Entities" if version == 4 => entities(file, s, &mut b)?,
            "PartitionedEntities" => {
                return Err(format_error(
                    file,
                    s.line,
                    "$PartitionedEntities",
                    "partitioned meshes are not supported: save the mesh unpartitioned".to_string(),
                ));
            }
            "Nodes" if version == 4 => nodes_41(file, s, &mut b)?,
            "Nodes" => nodes_22(file, s, &mut b)?,
            "Elements" if version == 4 => elements_41(file, s, &mut b)?,
            "Elements" => elements_22(file, s, &mut b)?,
            _ => {}
        }
    }
    Ok(b.finish())
}

/// [`parse_gmsh`] on a file.
pub fn read_gmsh(path: &std::path::Path) -> Result<FeMesh, FeError> {
    let text = read_file(path)?;
    parse_gmsh(&text, &path.display().to_string())
}

/// `version file-type data-size`: 4.1 or 2.2, ASCII. Returns the major version.
fn mesh_format(file: &str, s: &Section) -> Result<u32, FeError> {
    let mut c = Cursor::new(file, s);
    let version = c.word("version")?;
    let major = match version {
        "4.1" => 4,
        "2.2" => 2,
        v => {
            return Err(c.at().error(
                "version",
                format!("MSH version {} is not supported (4.1 or 2.2)", quote(v)),
            ));
        }
    };
    if c.integer("file-type")? != 0 {
        return Err(c.at().error(
            "file-type",
            "binary MSH files are not supported: save as ASCII (Mesh.Binary = 0)".to_string(),
        ));
    }
    c.integer("data-size")?;
    Ok(major)
}

/// `n`, then `dim tag "name"` per line.
fn physical_names<'a>(file: &str, s: &Section<'a>, b: &mut Builder) -> Result<(), FeError> {
    let mut lines = s.lines.iter();
    let (first, text) = lines.next().copied().unwrap_or((s.line, ""));
    let n = At { file, line: first }.count("numPhysicalNames", text)?;
    for k in 0..n {
        let Some(&(line, text)) = lines.next() else {
            return Err(format_error(
                file,
                first,
                "numPhysicalNames",
                format!("declares {n} names but the section holds {k}"),
            ));
        };
        let at = At { file, line };
        let word = |t: &'a str| {
            let t = t.trim_start();
            t.split_once(char::is_whitespace).unwrap_or((t, ""))
        };
        let (dim, rest) = word(text);
        let (tag, name) = word(rest);
        let dim = at.count("dimension", dim)?;
        let tag = at.integer("physicalTag", tag)?;
        let name = name.trim();
        let name = name
            .strip_prefix('"')
            .and_then(|n| n.strip_suffix('"'))
            .ok_or_else(|| {
                at.error(
                    "name",
                    format!("expected a quoted name, found {}", quote(name)),
                )
            })?;
        if dim > 3 {
            return Err(at.error("dimension", format!("{dim} is not 0, 1, 2 or 3")));
        }
        b.names.insert((dim, tag), name.to_string());
    }
    if let Some(&(line, text)) = lines.find(|(_, t)| !t.trim().is_empty()) {
        return Err(format_error(
            file,
            line,
            "$PhysicalNames",
            format!(
                "unexpected {} after the {n} declared names",
                quote(text.trim())
            ),
        ));
    }
    Ok(())
}

/// `$Entities` (4.1): the physical tags of each point, curve, surface and volume.
fn entities(file: &str, s: &Section, b: &mut Builder) -> Result<(), FeError> {
    let mut c = Cursor::new(file, s);
    let counts = [
        c.count("numPoints")?,
        c.count("numCurves")?,
        c.count("numSurfaces")?,
        c.count("numVolumes")?,
    ];
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let tag = c.integer("entityTag")?;
            let box_values = if dim == 0 { 3 } else { 6 };
            for _ in 0..box_values {
                c.real("boundingBox")?;
            }
            let np = c.count("numPhysicalTags")?;
            let mut groups = Vec::new();
            for _ in 0..np {
                groups.push(c.integer("physicalTag")?);
            }
            if dim > 0 {
                let nb = c.count("numBoundingEntities")?;
                for _ in 0..nb {
                    c.integer("boundingEntityTag")?;
                }
            }
            b.entity_groups.insert((dim, tag), groups);
        }
    }
    c.finish("$Entities")
}

/// `$Nodes` (4.1): blocks of tags then coordinates.
fn nodes_41(file: &str, s: &Section, b: &mut Builder) -> Result<(), FeError> {
    let mut c = Cursor::new(file, s);
    let blocks = c.count("numEntityBlocks")?;
    let total = c.count("numNodes")?;
    c.integer("minNodeTag")?;
    c.integer("maxNodeTag")?;
    let mut read = 0usize;
    for _ in 0..blocks {
        let dim = c.count("entityDim")?;
        c.integer("entityTag")?;
        let parametric = c.count("parametric")?;
        let n = c.count("numNodesInBlock")?;
        let mut tags = Vec::new();
        for _ in 0..n {
            tags.push((c.integer("nodeTag")?, c.at()));
        }
        let extra = if parametric == 1 { dim.min(3) } else { 0 };
        for (tag, at) in tags {
            let p = Vector3::new(c.real("x")?, c.real("y")?, c.real("z")?);
            for _ in 0..extra {
                c.real("parametric coordinate")?;
            }
            b.nodes.push(at, tag.to_string(), p)?;
        }
        read += n;
    }
    if read != total {
        return Err(c.at().error(
            "numNodes",
            format!("the header declares {total} nodes but the blocks hold {read}"),
        ));
    }
    c.finish("$Nodes")
}

/// `$Nodes` (2.2): `n`, then `tag x y z`.
fn nodes_22(file: &str, s: &Section, b: &mut Builder) -> Result<(), FeError> {
    let mut c = Cursor::new(file, s);
    let n = c.count("numNodes")?;
    for _ in 0..n {
        let tag = c.integer("nodeTag")?;
        let at = c.at();
        let p = Vector3::new(c.real("x")?, c.real("y")?, c.real("z")?);
        b.nodes.push(at, tag.to_string(), p)?;
    }
    c.finish("$Nodes")
}

/// `$Elements` (4.1): blocks of one entity and type.
fn elements_41(file: &str, s: &Section, b: &mut Builder) -> Result<(), FeError> {
    let mut c = Cursor::new(file, s);
    let blocks = c.count("numEntityBlocks")?;
    let total = c.count("numElements")?;
    c.integer("minElementTag")?;
    c.integer("maxElementTag")?;
    let mut read = 0usize;
    for _ in 0..blocks {
        let dim = c.count("entityDim")?;
        let entity = c.integer("entityTag")?;
        let t = c.integer("elementType")?;
        let ty = element_type(c.at(), "elementType", t)?;
        if ty.dim != dim {
            return Err(c.at().error(
                "entityDim",
                format!(
                    "a block of {} elements is on an entity of dimension {dim}",
                    ty.name
                ),
            ));
        }
        let groups = b
            .entity_groups
            .get(&(dim, entity))
            .cloned()
            .unwrap_or_default();
        let n = c.count("numElementsInBlock")?;
        for _ in 0..n {
            let id = c.integer("elementTag")?;
            let at = c.at();
            let mut nodes = Vec::with_capacity(ty.nodes);
            for _ in 0..ty.nodes {
                let tag = c.integer("nodeTag")?;
                nodes.push(b.node(c.at(), "nodeTag", tag)?);
            }
            b.element(at, id, &ty, nodes, &groups)?;
        }
        read += n;
    }
    if read != total {
        return Err(c.at().error(
            "numElements",
            format!("the header declares {total} elements but the blocks hold {read}"),
        ));
    }
    c.finish("$Elements")
}

/// `$Elements` (2.2): `n`, then `tag type numTags tags… nodes…` per line; the first tag
/// is the physical group (0: none).
fn elements_22(file: &str, s: &Section, b: &mut Builder) -> Result<(), FeError> {
    let mut lines = s.lines.iter().filter(|(_, t)| !t.trim().is_empty());
    let (first, text) = lines.next().copied().unwrap_or((s.line, ""));
    let n = At { file, line: first }.count("numElements", text.trim())?;
    for k in 0..n {
        let Some(&(line, text)) = lines.next() else {
            return Err(format_error(
                file,
                first,
                "numElements",
                format!("declares {n} elements but the section holds {k}"),
            ));
        };
        let at = At { file, line };
        let f: Vec<&str> = text.split_whitespace().collect();
        let field = |i: usize, name: &str| {
            f.get(i)
                .copied()
                .ok_or_else(|| at.error(name, "the line ends before this field".to_string()))
        };
        let id = at.integer("elementTag", field(0, "elementTag")?)?;
        let t = at.integer("elementType", field(1, "elementType")?)?;
        let ty = element_type(at, "elementType", t)?;
        let ntags = at.count("numTags", field(2, "numTags")?)?;
        let physical = if ntags > 0 {
            at.integer("physicalTag", field(3, "physicalTag")?)?
        } else {
            0
        };
        let first_node = 3usize.saturating_add(ntags);
        if f.len() != first_node.saturating_add(ty.nodes) {
            return Err(at.error(
                "nodeTags",
                format!(
                    "a {} with {ntags} tags needs {} fields, the line has {}",
                    ty.name,
                    first_node.saturating_add(ty.nodes),
                    f.len()
                ),
            ));
        }
        let nodes = f[first_node..]
            .iter()
            .map(|w| b.node(at, "nodeTag", at.integer("nodeTag", w)?))
            .collect::<Result<Vec<_>, _>>()?;
        let groups: Vec<i64> = if physical != 0 {
            vec![physical]
        } else {
            vec![]
        };
        b.element(at, id, &ty, nodes, &groups)?;
    }
    if let Some(&(line, text)) = lines.next() {
        return Err(format_error(
            file,
            line,
            "$Elements",
            format!(
                "unexpected {} after the {n} declared elements",
                quote(text.trim())
            ),
        ));
    }
    Ok(())
}
