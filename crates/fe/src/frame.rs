//! Beam frames: a body's FE model as named nodes joined by members, branches allowed, each
//! member with its own element count, section and orientation vector (issue 14; the A-arm of
//! docs/scenes.md §2.8 is a V of two legs with a bracket from an interior node).
//!
//! A frame is written in a spec's [`Geometry`](crate::spec::Geometry) instead of its polyline
//! `points`:
//!
//! ```ron
//! geometry: (
//!     elements_per_segment: 1,                       // for a member that gives no count
//!     nodes: [(name: "B", position: [0.0, 0.0, 0.0]), (name: "P", position: [0.1, 0.3, 0.0]),
//!             (name: "S", position: [0.05, 0.05, 0.0])],
//!     members: [(from: "B", to: "P", elements: 4),
//!               (from: "B", to: "S", section: Some(Circle(diameter: 0.01)))],
//! ),
//! ```
//!
//! **Node numbering.** The named nodes come first, in the order written (node k is
//! `nodes[k]`, which is how `frame` and `boundary` name them), then the interior nodes of each
//! member in member order, from its `from` end. A member of n elements from A to B has the
//! nodes A + (B − A) j/n, j = 0 … n. Element axes follow docs/methods.md §1.2 with the member's
//! orientation vector (else the geometry's, else the default). Markers sit on nodes by
//! position, as on a polyline.
//!
//! The checks refuse, by field and value: a name given twice, a member naming a node that
//! does not exist, a member joining a node to itself, members of zero length or elements
//! outside [`bounds::ELEMENT_LENGTH`], an orientation parallel to a member, and a frame that
//! is not connected (a free part would be a mechanism of the FE model).

use std::collections::HashMap;

use flexmbd_core::{Dim, InvalidValue};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::bounds::{self, MAX_FE_DOFS};
use crate::spec::{BeamBodySpec, Section};

/// A named node of a beam frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameNode {
    /// Name, unique in the frame.
    pub name: String,
    /// Position (m), body components: `[x, y]` in 2D, `[x, y, z]` in 3D.
    pub position: Vec<f64>,
}

/// A straight member of a beam frame between two named nodes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Member {
    /// The node it starts at.
    pub from: String,
    /// The node it ends at.
    pub to: String,
    /// Equal elements along it (the geometry's `elements_per_segment` when omitted).
    #[serde(default)]
    pub elements: Option<usize>,
    /// Its section (the body's `section` when omitted).
    #[serde(default)]
    pub section: Option<Section>,
    /// Its orientation vector k̄ (the geometry's `orientation` when omitted).
    #[serde(default)]
    pub orientation: Option<[f64; 3]>,
}

impl FrameNode {
    /// The node `name` at `position` (body components; z is dropped in 2D).
    pub fn new(name: &str, position: [f64; 3]) -> Self {
        FrameNode {
            name: name.to_string(),
            position: position.to_vec(),
        }
    }
}

impl Member {
    /// A member from `from` to `to` in `elements` equal elements, with the body's section
    /// and orientation vector.
    pub fn new(from: &str, to: &str, elements: usize) -> Self {
        Member {
            from: from.to_string(),
            to: to.to_string(),
            elements: Some(elements),
            section: None,
            orientation: None,
        }
    }

    /// Its own section.
    pub fn section(mut self, section: Section) -> Self {
        self.section = Some(section);
        self
    }

    /// Its own orientation vector k̄ (body components).
    pub fn orientation(mut self, k: [f64; 3]) -> Self {
        self.orientation = Some(k);
        self
    }
}

impl BeamBodySpec {
    /// A beam frame of `nodes` and `members` (see the module documentation), the frame of
    /// reference clamped at the first node, no static and no normal modes yet (set `frame`,
    /// `boundary` and `normal_modes`, naming nodes with [`BeamBodySpec::frame_node`]), no
    /// damping. For scenes built in code; not validated.
    pub fn frame(
        dim: Dim,
        material: crate::spec::Material,
        section: Section,
        nodes: Vec<FrameNode>,
        members: Vec<Member>,
    ) -> Self {
        let mut spec = BeamBodySpec::straight(dim, material, section, 1.0, 1);
        spec.geometry.points.clear();
        spec.geometry.nodes = nodes;
        spec.geometry.members = members;
        spec
    }

    /// The index of the frame node `name` (its place in `geometry.nodes`).
    pub fn frame_node(&self, name: &str) -> Option<usize> {
        self.geometry.nodes.iter().position(|n| n.name == name)
    }
}

/// One element of a frame's mesh, before its axes and properties are computed.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameElement {
    /// First and second node.
    pub nodes: [usize; 2],
    /// The member it belongs to.
    pub member: usize,
}

/// The mesh of a validated frame: node positions (named nodes first) and elements.
pub fn frame_mesh(spec: &BeamBodySpec) -> (Vec<Vector3<f64>>, Vec<FrameElement>) {
    let geometry = &spec.geometry;
    let index = node_index(spec);
    let mut nodes: Vec<Vector3<f64>> = geometry.nodes.iter().map(|n| vector(&n.position)).collect();
    let mut elements = Vec::new();
    for (m, member) in geometry.members.iter().enumerate() {
        let (a, b) = (index[member.from.as_str()], index[member.to.as_str()]);
        let n = member_elements(spec, m);
        let (pa, pb) = (nodes[a], nodes[b]);
        let mut previous = a;
        for j in 1..=n {
            let next = if j == n {
                b
            } else {
                nodes.push(pa + (pb - pa) * (j as f64 / n as f64));
                nodes.len() - 1
            };
            elements.push(FrameElement {
                nodes: [previous, next],
                member: m,
            });
            previous = next;
        }
    }
    (nodes, elements)
}

/// The number of FE nodes of a frame: the named nodes and every member's interior nodes.
pub fn frame_node_count(spec: &BeamBodySpec) -> usize {
    let interior = (0..spec.geometry.members.len())
        .map(|m| member_elements(spec, m).saturating_sub(1))
        .fold(0usize, usize::saturating_add);
    spec.geometry.nodes.len().saturating_add(interior)
}

/// The section of member `m`.
pub fn member_section(spec: &BeamBodySpec, m: usize) -> &Section {
    spec.geometry.members[m]
        .section
        .as_ref()
        .unwrap_or(&spec.section)
}

/// The orientation vector of member `m`, if any is given.
pub fn member_orientation(spec: &BeamBodySpec, m: usize) -> Option<[f64; 3]> {
    spec.geometry.members[m]
        .orientation
        .or(spec.geometry.orientation)
}

fn member_elements(spec: &BeamBodySpec, m: usize) -> usize {
    spec.geometry.members[m]
        .elements
        .unwrap_or(spec.geometry.elements_per_segment)
}

fn node_index(spec: &BeamBodySpec) -> HashMap<&str, usize> {
    spec.geometry
        .nodes
        .iter()
        .enumerate()
        .map(|(k, n)| (n.name.as_str(), k))
        .collect()
}

fn vector(p: &[f64]) -> Vector3<f64> {
    Vector3::new(
        p.first().copied().unwrap_or(0.0),
        p.get(1).copied().unwrap_or(0.0),
        p.get(2).copied().unwrap_or(0.0),
    )
}

/// Check a frame geometry (see the module documentation); `check_section` checks a
/// member's own section under its field prefix.
pub fn check_frame_geometry(
    spec: &BeamBodySpec,
    check_section: impl Fn(&Section, &str) -> Result<(), InvalidValue>,
) -> Result<(), InvalidValue> {
    let geometry = &spec.geometry;
    if !geometry.points.is_empty() {
        return Err(InvalidValue::new(
            "geometry.points",
            format!("{} point(s)", geometry.points.len()),
            "give either a polyline (points) or a frame (nodes and members), not both",
        ));
    }
    check_nodes(spec)?;
    if geometry.members.is_empty() {
        return Err(InvalidValue::new(
            "geometry.members",
            "[]",
            "a frame needs at least one member",
        ));
    }
    let index = node_index(spec);
    for (m, member) in geometry.members.iter().enumerate() {
        check_member(spec, &index, m, member)?;
        if let Some(section) = &member.section {
            check_section(section, &format!("geometry.members[{m}].section"))?;
        }
    }
    check_size(spec)?;
    check_connected(spec, &index)
}

/// Names unique and non-empty; positions with the dimension's components, in range.
fn check_nodes(spec: &BeamBodySpec) -> Result<(), InvalidValue> {
    let nodes = &spec.geometry.nodes;
    if nodes.len() < 2 {
        return Err(InvalidValue::new(
            "geometry.nodes",
            format!("{} node(s)", nodes.len()),
            "a frame needs at least 2 named nodes",
        ));
    }
    let want = spec.dim.n_trans();
    let mut seen = HashMap::new();
    for (k, node) in spec.geometry.nodes.iter().enumerate() {
        let field = format!("geometry.nodes[{k}]");
        if node.name.is_empty() {
            return Err(InvalidValue::new(
                format!("{field}.name"),
                "\"\"",
                "a frame node needs a name",
            ));
        }
        if let Some(first) = seen.insert(node.name.as_str(), k) {
            return Err(InvalidValue::new(
                format!("{field}.name"),
                &node.name,
                format!("already the name of geometry.nodes[{first}]"),
            ));
        }
        let position = &node.position;
        if position.len() != want {
            return Err(InvalidValue::new(
                format!("{field}.position"),
                format!("{position:?}"),
                format!("a {} point has {want} components", spec.dim),
            ));
        }
        bounds::POSITION.check_all(&format!("{field}.position"), position)?;
    }
    Ok(())
}

/// The member's ends exist and differ, its elements are at least one and of a length in
/// range, and its orientation vector (if any) is usable for it.
fn check_member(
    spec: &BeamBodySpec,
    index: &HashMap<&str, usize>,
    m: usize,
    member: &Member,
) -> Result<(), InvalidValue> {
    let field = format!("geometry.members[{m}]");
    let end = |name: &str, which: &str| {
        index.get(name).copied().ok_or_else(|| {
            InvalidValue::new(
                format!("{field}.{which}"),
                name,
                "no frame node has this name",
            )
        })
    };
    let (a, b) = (end(&member.from, "from")?, end(&member.to, "to")?);
    if a == b {
        return Err(InvalidValue::new(
            format!("{field}.to"),
            &member.to,
            "a member cannot join a node to itself",
        ));
    }
    let elements = member_elements(spec, m);
    if elements == 0 {
        let which = if member.elements.is_some() {
            format!("{field}.elements")
        } else {
            "geometry.elements_per_segment".to_string()
        };
        return Err(InvalidValue::new(which, 0, "must be at least 1"));
    }
    let d = vector(&spec.geometry.nodes[b].position) - vector(&spec.geometry.nodes[a].position);
    let length = d.norm() / elements as f64;
    if !bounds::ELEMENT_LENGTH.contains(length) {
        return Err(InvalidValue::new(
            field,
            format!("{} → {}, {elements} element(s)", member.from, member.to),
            format!(
                "gives elements {length:e} m long: allowed {}",
                bounds::ELEMENT_LENGTH
            ),
        ));
    }
    check_member_orientation(spec, m, &d.normalize())
}

/// The orientation vector a member uses, when given: finite, non-zero, +ē₃ in 2D, not
/// parallel to the member in 3D.
fn check_member_orientation(
    spec: &BeamBodySpec,
    m: usize,
    x: &Vector3<f64>,
) -> Result<(), InvalidValue> {
    let Some(k) = member_orientation(spec, m) else {
        return Ok(());
    };
    let field = if spec.geometry.members[m].orientation.is_some() {
        format!("geometry.members[{m}].orientation")
    } else {
        "geometry.orientation".to_string()
    };
    bounds::AXIS_COMPONENT.check_all(&field, &k)?;
    let kv = Vector3::from(k);
    let refuse = |reason: String| Err(InvalidValue::new(field.clone(), format!("{k:?}"), reason));
    if kv.norm() < bounds::MIN_AXIS_NORM {
        return refuse(format!(
            "must be a non-zero vector (norm at least {:e})",
            bounds::MIN_AXIS_NORM
        ));
    }
    match spec.dim {
        Dim::Planar if kv.x != 0.0 || kv.y != 0.0 || kv.z <= 0.0 => refuse(
            "in 2D the element axes are fixed by k = +e3; omit it or give [0, 0, 1]".to_string(),
        ),
        Dim::Spatial if kv.normalize().cross(x).norm() < 1e-9 => refuse(format!(
            "is parallel to member {m}; its element axes are undefined"
        )),
        _ => Ok(()),
    }
}

/// At most [`MAX_FE_DOFS`] DOFs.
fn check_size(spec: &BeamBodySpec) -> Result<(), InvalidValue> {
    let dofs = frame_node_count(spec).saturating_mul(spec.dofs_per_node());
    if dofs > MAX_FE_DOFS {
        return Err(InvalidValue::new(
            "geometry.members",
            format!("{} members", spec.geometry.members.len()),
            format!(
                "too large: {dofs} FE DOFs; {}",
                bounds::too_many_dofs(dofs as u128)
            ),
        ));
    }
    Ok(())
}

/// Every named node is reached from the first one through the members.
fn check_connected(spec: &BeamBodySpec, index: &HashMap<&str, usize>) -> Result<(), InvalidValue> {
    let n = spec.geometry.nodes.len();
    let mut reached = vec![false; n];
    reached[0] = true;
    let mut changed = true;
    while changed {
        changed = false;
        for member in &spec.geometry.members {
            let (a, b) = (index[member.from.as_str()], index[member.to.as_str()]);
            if reached[a] != reached[b] {
                reached[a] = true;
                reached[b] = true;
                changed = true;
            }
        }
    }
    match reached.iter().position(|r| !r) {
        None => Ok(()),
        Some(k) => Err(InvalidValue::new(
            format!("geometry.nodes[{k}]"),
            &spec.geometry.nodes[k].name,
            format!(
                "the frame is not connected: no chain of members joins it to `{}`",
                spec.geometry.nodes[0].name
            ),
        )),
    }
}
