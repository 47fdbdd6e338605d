//! Interfaces of an imported body: node sets chosen by name or by geometry, each joined to
//! one interface point by a multipoint constraint, and the sparse map u = T ũ those
//! constraints make.
//!
//! An interface point P sits at the centroid c of its nodes and carries six coordinates
//! (u_P, θ_P). With d_s = x_s − c for every node s of the set:
//!
//! - **RBE2** (rigid spider): every DOF of every node follows P rigidly,
//!   u_s = u_P + θ_P × d_s and, where the node has rotational DOFs, θ_s = θ_P. The nodes'
//!   DOFs are all dependent; the spider adds stiffness.
//! - **RBE3** (weighted average, unit weights): P moves with the nodes' mean translation and
//!   their least-squares rotation, u_P = (1/n_s) Σ u_s,
//!   θ_P = J⁻¹ Σ d_s × u_s with J = Σ (|d_s|² 𝟙 − d_s d_sᵀ); the set deforms freely
//!   under these six conditions and the constraint adds no stiffness (MSC Nastran's RBE3 with
//!   unit weights on the translations; Abaqus's distributing coupling). The six equations
//!   G u_S = (u_P, θ_P) are solved for six of the nodes' DOFs, chosen by complete
//!   pivoting on G, which is then a function of P's coordinates and the other DOFs.
//!
//! The retained coordinates ũ are the FE DOFs no interface made dependent, in the model's
//! order, followed by the six coordinates of every interface point; T (N × Ñ) is sparse
//! but for the six rows of each RBE3.
//!
//! A point's rotation must be defined by its nodes: an interface of nodes without
//! rotational DOFs needs three that are not collinear (J non-singular).

use nalgebra::{Matrix3, SMatrix, Vector3};
use serde::{Deserialize, Serialize};
use sprs::{CsMat, TriMat};

use super::invalid;
use crate::assembly::dof_slot;
use crate::error::FeError;
use crate::import::FeModel;
use crate::reduced::Dof;
use flexmbd_core::Dim;

/// A point or direction written `[x, y, z]` (exactly three numbers).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<f64>", into = "Vec<f64>")]
pub struct Xyz(pub [f64; 3]);

impl TryFrom<Vec<f64>> for Xyz {
    type Error = String;
    fn try_from(v: Vec<f64>) -> Result<Self, String> {
        match v.as_slice() {
            [x, y, z] => Ok(Xyz([*x, *y, *z])),
            _ => Err(format!("expected [x, y, z], found {} numbers", v.len())),
        }
    }
}

impl From<Xyz> for Vec<f64> {
    fn from(v: Xyz) -> Self {
        v.0.to_vec()
    }
}

/// How an interface picks its FE nodes (positions in the model's units after
/// `length_scale`, i.e. metres, body components).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum NodeSelection {
    /// A node set of the export (Abaqus `*Nset`), by name (case-insensitive).
    Set(String),
    /// Nodes by id.
    Ids(Vec<String>),
    /// Nodes within `tolerance` of the plane through `point` with normal `normal`.
    Plane {
        /// A point of the plane.
        point: Xyz,
        /// Its normal (any length but zero).
        normal: Xyz,
        /// Largest distance from the plane (m).
        tolerance: f64,
    },
    /// Nodes within `radius` of `center`.
    Sphere {
        /// The centre.
        center: Xyz,
        /// The radius (m).
        radius: f64,
    },
    /// Nodes within `radius` of the axis through `point` along `axis`, and within
    /// `half_length` of `point` along it: a bore, a journal.
    Cylinder {
        /// A point of the axis (the middle of the selected length).
        point: Xyz,
        /// The axis direction (any length but zero).
        axis: Xyz,
        /// The largest distance from the axis (m).
        radius: f64,
        /// The largest distance from `point` along the axis (m).
        half_length: f64,
    },
    /// The one node nearest to a point.
    Nearest(Xyz),
}

/// How an interface's nodes are joined to its point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Coupling {
    /// Rigid spider: the nodes follow the point rigidly.
    #[default]
    Rbe2,
    /// Weighted average (unit weights): the point follows the nodes' mean motion.
    Rbe3,
}

/// One interface of an imported body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InterfaceSpec {
    /// Its name: markers and the frame refer to it.
    pub name: String,
    /// Its nodes.
    pub nodes: NodeSelection,
    /// How they are joined to the point.
    #[serde(default)]
    pub coupling: Coupling,
}

/// An interface resolved on a model: its nodes (indices into the model's nodes) and point.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolvedInterface {
    /// The interface's name.
    pub name: String,
    /// Node indices, ascending.
    pub nodes: Vec<usize>,
    /// The point: the nodes' centroid (m, body components).
    pub point: Vector3<f64>,
    /// The coupling.
    pub coupling: Coupling,
}

/// Resolve every interface's nodes and point; an interface with no nodes, a node in two
/// interfaces or a point whose rotation the nodes leave free is refused.
pub fn resolve(
    specs: &[InterfaceSpec],
    model: &FeModel,
    body: &str,
) -> Result<Vec<ResolvedInterface>, FeError> {
    let has_rotations = node_has_rotations(model);
    let mut owner: Vec<Option<usize>> = vec![None; model.mesh.nodes.positions.len()];
    let mut out = Vec::with_capacity(specs.len());
    for (k, spec) in specs.iter().enumerate() {
        let field = format!("{body}.interfaces[{}].nodes", spec.name);
        let nodes = select(&spec.nodes, model, &field)?;
        for &node in &nodes {
            if let Some(other) = owner[node] {
                return Err(invalid(
                    field,
                    &model.mesh.nodes.ids[node],
                    format!(
                        "node {} is also in interface {}: an FE node belongs to one interface",
                        model.mesh.nodes.ids[node], specs[other].name
                    ),
                ));
            }
            owner[node] = Some(k);
        }
        let positions = &model.mesh.nodes.positions;
        let point = nodes.iter().map(|&s| positions[s]).sum::<Vector3<f64>>() / nodes.len() as f64;
        let any_rotation = nodes.iter().any(|&s| has_rotations[s]);
        let needs_spread = spec.coupling == Coupling::Rbe3 || !any_rotation;
        if needs_spread && !well_spread(&spread(&nodes, positions, &point)) {
            return Err(invalid(
                field,
                format!("{} nodes", nodes.len()),
                "the nodes leave the interface point's rotation free: they need rotational \
                 DOFs (RBE2) or three nodes that are not collinear",
            ));
        }
        out.push(ResolvedInterface {
            name: spec.name.clone(),
            nodes,
            point,
            coupling: spec.coupling,
        });
    }
    Ok(out)
}

/// J = Σ (|d|² 𝟙 − d dᵀ), d = x_s − c: the nodes' spread about the point.
fn spread(nodes: &[usize], positions: &[Vector3<f64>], c: &Vector3<f64>) -> Matrix3<f64> {
    nodes.iter().fold(Matrix3::zeros(), |j, &s| {
        let d = positions[s] - c;
        j + Matrix3::identity() * d.norm_squared() - d * d.transpose()
    })
}

/// J is well conditioned: its smallest eigenvalue above 1e-9 of its largest.
fn well_spread(j: &Matrix3<f64>) -> bool {
    let e = j.symmetric_eigenvalues();
    e.max() > 0.0 && e.min() > 1e-9 * e.max()
}

fn node_has_rotations(model: &FeModel) -> Vec<bool> {
    let mut has = vec![false; model.mesh.nodes.positions.len()];
    for d in &model.dofs {
        if matches!(d.dof, Dof::Rx | Dof::Ry | Dof::Rz) {
            has[d.node] = true;
        }
    }
    has
}

fn vector(field: &str, v: Xyz) -> Result<Vector3<f64>, FeError> {
    let v = Vector3::from(v.0);
    if v.iter().all(|x| x.is_finite()) {
        Ok(v)
    } else {
        Err(invalid(
            field.to_string(),
            format!("{v:?}"),
            "must be finite",
        ))
    }
}

fn length(field: &str, v: f64) -> Result<f64, FeError> {
    flexmbd_core::require_positive(field, v).map_err(FeError::Invalid)
}

fn direction(field: &str, v: Xyz) -> Result<Vector3<f64>, FeError> {
    let v = vector(field, v)?;
    let n = v.norm();
    if n > 0.0 {
        Ok(v / n)
    } else {
        Err(invalid(
            field.to_string(),
            format!("{v:?}"),
            "must not be zero",
        ))
    }
}

/// The nodes a selection picks, ascending; none is an error.
fn select(sel: &NodeSelection, model: &FeModel, field: &str) -> Result<Vec<usize>, FeError> {
    let positions = &model.mesh.nodes.positions;
    let within = |keep: &dyn Fn(&Vector3<f64>) -> bool| -> Vec<usize> {
        (0..positions.len())
            .filter(|&s| keep(&positions[s]))
            .collect()
    };
    let nodes = match sel {
        NodeSelection::Set(name) => {
            let found = model
                .mesh
                .node_sets
                .iter()
                .find(|(n, _)| n.eq_ignore_ascii_case(name));
            match found {
                Some((_, nodes)) => nodes.clone(),
                None => {
                    let known: Vec<&str> =
                        model.mesh.node_sets.keys().map(String::as_str).collect();
                    return Err(invalid(
                        field.to_string(),
                        name,
                        format!(
                            "the model has no such node set (its sets: {})",
                            if known.is_empty() {
                                "none".to_string()
                            } else {
                                known.join(", ")
                            }
                        ),
                    ));
                }
            }
        }
        NodeSelection::Ids(ids) => {
            let mut nodes = Vec::with_capacity(ids.len());
            for id in ids {
                match model.mesh.nodes.index.get(id) {
                    Some(&s) => nodes.push(s),
                    None => {
                        return Err(invalid(field.to_string(), id, "the model has no such node"));
                    }
                }
            }
            nodes.sort_unstable();
            nodes.dedup();
            nodes
        }
        NodeSelection::Plane {
            point,
            normal,
            tolerance,
        } => {
            let (p, n) = (vector(field, *point)?, direction(field, *normal)?);
            let tol = length(&format!("{field}.tolerance"), *tolerance)?;
            within(&|x| (x - p).dot(&n).abs() <= tol)
        }
        NodeSelection::Sphere { center, radius } => {
            let c = vector(field, *center)?;
            let r = length(&format!("{field}.radius"), *radius)?;
            within(&|x| (x - c).norm() <= r)
        }
        NodeSelection::Cylinder {
            point,
            axis,
            radius,
            half_length,
        } => {
            let (p, a) = (vector(field, *point)?, direction(field, *axis)?);
            let r = length(&format!("{field}.radius"), *radius)?;
            let h = length(&format!("{field}.half_length"), *half_length)?;
            within(&|x| {
                let d = x - p;
                let along = d.dot(&a);
                along.abs() <= h && (d - a * along).norm() <= r
            })
        }
        NodeSelection::Nearest(point) => {
            let p = vector(field, *point)?;
            let nearest = (0..positions.len()).min_by(|&a, &b| {
                (positions[a] - p)
                    .norm()
                    .total_cmp(&(positions[b] - p).norm())
            });
            nearest.into_iter().collect()
        }
    };
    if nodes.is_empty() {
        return Err(invalid(
            field.to_string(),
            format!("{sel:?}"),
            "selects no node of the model",
        ));
    }
    Ok(nodes)
}

/// The map u = T ũ from the retained coordinates to the FE DOFs (module docs).
#[derive(Clone, Debug)]
pub struct RetainedMap {
    /// T (N × Ñ), CSC.
    pub t: CsMat<f64>,
    /// Retained index of every FE DOF left independent (`None`: dependent).
    pub independent: Vec<Option<usize>>,
    /// Number of independent FE DOFs; interface point p's coordinates are
    /// `n_independent + 6p .. n_independent + 6p + 6`.
    pub n_independent: usize,
}

impl RetainedMap {
    /// Number of retained coordinates Ñ.
    pub fn n_retained(&self) -> usize {
        self.t.cols()
    }

    /// The first retained coordinate of interface point `p`.
    pub fn point_start(&self, p: usize) -> usize {
        self.n_independent + 6 * p
    }

    /// Build T for the interfaces of a model.
    pub fn new(
        model: &FeModel,
        interfaces: &[ResolvedInterface],
        body: &str,
    ) -> Result<Self, FeError> {
        let n = model.n_dofs();
        let rows = dof_rows(model);
        // Each dependent DOF's expression: (retained index, coefficient) pairs, where
        // retained indices of points are offsets into the point block for now.
        let mut dependent: Vec<Option<Vec<Term>>> = vec![None; n];
        for (p, itf) in interfaces.iter().enumerate() {
            match itf.coupling {
                Coupling::Rbe2 => rbe2(model, &rows, itf, p, &mut dependent),
                Coupling::Rbe3 => rbe3(model, &rows, itf, p, &mut dependent, body)?,
            }
        }
        let mut independent = vec![None; n];
        let mut n_independent = 0;
        for r in 0..n {
            if dependent[r].is_none() {
                independent[r] = Some(n_independent);
                n_independent += 1;
            }
        }
        let n_retained = n_independent + 6 * interfaces.len();
        let mut t = TriMat::new((n, n_retained));
        for r in 0..n {
            match &dependent[r] {
                None => t.add_triplet(r, independent[r].unwrap_or_default(), 1.0),
                Some(terms) => {
                    for term in terms {
                        let col = match term.to {
                            Target::Point(p, c) => n_independent + 6 * p + c,
                            Target::Dof(row) => match independent[row] {
                                Some(col) => col,
                                None => unreachable!("RBE3 expresses through independent DOFs"),
                            },
                        };
                        if term.coefficient != 0.0 {
                            t.add_triplet(r, col, term.coefficient);
                        }
                    }
                }
            }
        }
        Ok(RetainedMap {
            t: t.to_csc(),
            independent,
            n_independent,
        })
    }
}

/// What a dependent DOF is expressed through.
#[derive(Clone, Copy, Debug)]
enum Target {
    /// Coordinate c (0..6) of interface point p.
    Point(usize, usize),
    /// An FE DOF (matrix row) left independent.
    Dof(usize),
}

#[derive(Clone, Copy, Debug)]
struct Term {
    to: Target,
    coefficient: f64,
}

/// Matrix row of every (node, DOF slot 0..6), if the DOF exists.
fn dof_rows(model: &FeModel) -> Vec<[Option<usize>; 6]> {
    let mut rows = vec![[None; 6]; model.mesh.nodes.positions.len()];
    for (r, d) in model.dofs.iter().enumerate() {
        if let Some(slot) = dof_slot(Dim::Spatial, d.dof) {
            rows[d.node][slot] = Some(r);
        }
    }
    rows
}

/// u_s = u_P + θ_P × d_s (row a: u_Pa + Σ_b (−d̃)_ab θ_Pb), θ_s = θ_P.
fn rbe2(
    model: &FeModel,
    rows: &[[Option<usize>; 6]],
    itf: &ResolvedInterface,
    p: usize,
    dependent: &mut [Option<Vec<Term>>],
) {
    for &s in &itf.nodes {
        let d = model.mesh.nodes.positions[s] - itf.point;
        let minus_skew = -flexmbd_core::skew(&d);
        for a in 0..3 {
            if let Some(r) = rows[s][a] {
                let mut terms = vec![Term {
                    to: Target::Point(p, a),
                    coefficient: 1.0,
                }];
                terms.extend((0..3).map(|b| Term {
                    to: Target::Point(p, 3 + b),
                    coefficient: minus_skew[(a, b)],
                }));
                dependent[r] = Some(terms);
            }
            if let Some(r) = rows[s][3 + a] {
                dependent[r] = Some(vec![Term {
                    to: Target::Point(p, 3 + a),
                    coefficient: 1.0,
                }]);
            }
        }
    }
}

/// G u_S = (u_P, θ_P) solved for six pivot DOFs of the set (module docs).
fn rbe3(
    model: &FeModel,
    rows: &[[Option<usize>; 6]],
    itf: &ResolvedInterface,
    p: usize,
    dependent: &mut [Option<Vec<Term>>],
    body: &str,
) -> Result<(), FeError> {
    let positions = &model.mesh.nodes.positions;
    let mut columns = Vec::with_capacity(3 * itf.nodes.len());
    for &s in &itf.nodes {
        for a in 0..3 {
            match rows[s][a] {
                Some(r) => columns.push((s, a, r)),
                None => {
                    return Err(invalid(
                        format!("{body}.interfaces[{}].nodes", itf.name),
                        &model.mesh.nodes.ids[s],
                        "an RBE3 node needs its three translational DOFs",
                    ));
                }
            }
        }
    }
    let j_inv = spread(&itf.nodes, positions, &itf.point)
        .try_inverse()
        .unwrap_or_else(Matrix3::zeros);
    let inv_n = 1.0 / itf.nodes.len() as f64;
    // G: 6 × 3n_s, column (s, a): e_a / n_s on top, J⁻¹ d̃_s e_a below.
    let mut g: Vec<[f64; 6]> = columns
        .iter()
        .map(|&(s, a, _)| {
            let rot = j_inv * flexmbd_core::skew(&(positions[s] - itf.point));
            let mut col = [0.0; 6];
            col[a] = inv_n;
            for b in 0..3 {
                col[3 + b] = rot[(b, a)];
            }
            col
        })
        .collect();
    // Gauss–Jordan with complete pivoting on G u_S = E (u_P, θ_P), E = 𝟙 at the start.
    let mut e = SMatrix::<f64, 6, 6>::identity();
    let mut pivots = Vec::with_capacity(6);
    let mut used = vec![false; g.len()];
    let mut row_done = [false; 6];
    for _ in 0..6 {
        let mut best = (0.0, 0, 0);
        for (c, col) in g.iter().enumerate().filter(|(c, _)| !used[*c]) {
            for i in (0..6).filter(|&i| !row_done[i]) {
                if col[i].abs() > best.0 {
                    best = (col[i].abs(), i, c);
                }
            }
        }
        let (size, i, c) = best;
        if size == 0.0 {
            return Err(invalid(
                format!("{body}.interfaces[{}].nodes", itf.name),
                format!("{} nodes", itf.nodes.len()),
                "the RBE3 averaging equations are singular",
            ));
        }
        used[c] = true;
        row_done[i] = true;
        pivots.push((i, c));
        let scale = 1.0 / g[c][i];
        for col in g.iter_mut() {
            col[i] *= scale;
        }
        for k in 0..6 {
            e[(i, k)] *= scale;
        }
        for other in (0..6).filter(|&o| o != i) {
            let f = g[c][other];
            if f != 0.0 {
                for col in g.iter_mut() {
                    col[other] -= f * col[i];
                }
                for k in 0..6 {
                    e[(other, k)] -= f * e[(i, k)];
                }
            }
        }
    }
    // Row i now reads u_c + Σ_free G_ic' u_c' = Σ_k E_ik (u_P, θ_P)_k for its pivot c.
    for (i, c) in pivots {
        let mut terms: Vec<Term> = (0..6)
            .map(|k| Term {
                to: Target::Point(p, k),
                coefficient: e[(i, k)],
            })
            .collect();
        for (free, col) in g.iter().enumerate() {
            if !used[free] && col[i] != 0.0 {
                terms.push(Term {
                    to: Target::Dof(columns[free].2),
                    coefficient: -col[i],
                });
            }
        }
        dependent[columns[c].2] = Some(terms);
    }
    Ok(())
}
