//! What each body looks like, in its own frame: a polyline beam is a tube of its section
//! along its nodes, with one morph target per mode when it runs flexible (through its
//! polyline's points when it runs rigid); any other body is a set of sticks from its
//! centre to its markers.
//!
//! A vertex at section offset o = a ȳ_e + b z̄_e from beam node P moves with the modal
//! coordinates y as u = Φ y, Φ's column j being X^t_P,j + X^r_P,j × o (the node's
//! translation and small-rotation rows, `flexmbd::body::NodeRows`): the linear
//! floating-frame displacement field (Shabana, *Dynamics of Multibody Systems*, ch. 5;
//! docs/methods.md §1.1), so the morph targets Φ_j weighted by y_j draw the deformed body
//! exactly at the nodes of a body linear in y.

use flexmbd::fe::Section;
use flexmbd::fe::frame;
use flexmbd::fe::spec::BeamBodySpec;
use flexmbd::model::{BodyModel, PreparedBody, PreparedScene, Scene};
use nalgebra::{DMatrix, Vector3};

/// A body's mesh in its frame: vertices, normals, triangles and one morph target (vertex
/// displacements) per modal coordinate.
#[derive(Clone, Debug, Default)]
pub struct BodyShape {
    /// The body's name.
    pub name: String,
    /// Vertex positions (m, body components).
    pub positions: Vec<Vector3<f64>>,
    /// Unit vertex normals.
    pub normals: Vec<Vector3<f64>>,
    /// Triangles (vertex indices, counter-clockwise seen from outside).
    pub triangles: Vec<[u32; 3]>,
    /// Per morph target, the displacement of every vertex: first one per mode (m per unit
    /// modal coordinate), then the [`quadratic`](Self::quadratic) ones of a foreshortened
    /// body.
    pub targets: Vec<Vec<Vector3<f64>>>,
    /// The FE node each vertex moves with (`None`: a vertex on no node), the first
    /// `positions.len()` entries or fewer (the rest on no node).
    pub vertex_nodes: Vec<Option<usize>>,
    /// For each target after the modes' (a foreshortened body's, [`crate::quadratic`]), the
    /// symmetric n × n matrix Q of its weight yᵀ Q y.
    pub quadratic: Vec<DMatrix<f64>>,
}

/// A closed section outline: points (a, b) along (ȳ_e, z̄_e) with their outward normals,
/// and the pairs of consecutive points that bound a face of the tube.
struct Outline {
    points: Vec<([f64; 2], [f64; 2])>,
    edges: Vec<(usize, usize)>,
}

impl Outline {
    fn circle(radius: f64) -> Outline {
        let n = 12;
        let points = (0..n)
            .map(|k| {
                let (s, c) = (std::f64::consts::TAU * k as f64 / n as f64).sin_cos();
                ([radius * c, radius * s], [c, s])
            })
            .collect();
        Outline {
            points,
            edges: (0..n).map(|k| (k, (k + 1) % n)).collect(),
        }
    }

    /// A rectangle, each corner twice (one normal per face).
    fn rectangle(width: f64, height: f64) -> Outline {
        let (a, b) = (width / 2.0, height / 2.0);
        let corners = [[a, -b], [a, b], [-a, b], [-a, -b]];
        let normals = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]];
        let mut points = Vec::new();
        for (face, normal) in normals.iter().enumerate() {
            points.push((corners[face], *normal));
            points.push((corners[(face + 1) % 4], *normal));
        }
        Outline {
            points,
            edges: (0..4).map(|f| (2 * f, 2 * f + 1)).collect(),
        }
    }

    fn of(section: &Section) -> Outline {
        match *section {
            Section::Rectangle { width, height } => Outline::rectangle(width, height),
            Section::Circle { diameter } => Outline::circle(diameter / 2.0),
            Section::General { area, .. } => Outline::circle((area / std::f64::consts::PI).sqrt()),
        }
    }
}

/// The radius of the sticks: 1 % of the scene's extent (the largest distance of a body
/// marker from the ground origin at the start, at least 0.1 m).
pub fn stick_radius(prepared: &PreparedScene) -> f64 {
    let scene = prepared.scene();
    let markers = scene.bodies.iter().flat_map(|b| {
        b.markers
            .iter()
            .map(|m| (b.origin.vec() + m.position.vec()).norm())
    });
    0.01 * markers.fold(0.1_f64, f64::max)
}

impl BodyShape {
    /// The morph weights of modal coordinates `y` at deformation scale `s`: s y_j for each
    /// mode's target, then s yᵀ Q y for each quadratic one.
    pub fn weights(&self, y: &[f64], s: f64) -> Vec<f64> {
        let n_linear = self.targets.len() - self.quadratic.len();
        let y_vec = nalgebra::DVector::from_column_slice(y);
        y[..n_linear]
            .iter()
            .map(|&y| s * y)
            .chain(self.quadratic.iter().map(|q| s * y_vec.dot(&(q * &y_vec))))
            .collect()
    }

    /// Note that the vertices from `first` on move with `node` (those before it unset
    /// stay on no node).
    fn on_node(&mut self, first: usize, node: Option<usize>) {
        self.vertex_nodes.resize(first, None);
        self.vertex_nodes.resize(self.positions.len(), node);
    }

    /// A cylinder of `radius` along the y axis from 0 to 1 (a spring, placed and scaled).
    pub fn cylinder(name: &str, radius: f64) -> BodyShape {
        let mut shape = BodyShape {
            name: name.into(),
            ..BodyShape::default()
        };
        let rings = [
            (Vector3::zeros(), Vector3::y()),
            (Vector3::y(), Vector3::y()),
        ];
        shape.tube(&rings, &Outline::circle(radius), Vector3::z(), &|_, _| {
            Vec::new()
        });
        shape
    }

    /// The shape of every body of `prepared` (in its order); the sticks of a body that is
    /// not a flexible polyline beam go to the markers `scene` gives it (the prepared scene
    /// adds markers of its own), with a radius of 1 % of the scene's extent.
    pub fn of(prepared: &PreparedScene, scene: &Scene) -> Vec<BodyShape> {
        let radius = stick_radius(prepared);
        prepared
            .bodies()
            .iter()
            .map(|body| {
                let spec = &prepared.scene().bodies[body.index];
                let mut shape = BodyShape {
                    name: spec.name.clone(),
                    ..BodyShape::default()
                };
                match &spec.model {
                    BodyModel::Beam(beam) if !beam.geometry.is_frame() => {
                        let axis = beam
                            .geometry
                            .orientation
                            .map_or(Vector3::z(), Vector3::from);
                        let outline = Outline::of(&beam.section);
                        if body.flexible {
                            let along: Vec<usize> = (0..body.nodes.len()).collect();
                            shape.beam(&body.nodes, &along, &outline, axis);
                        } else {
                            // Run rigid: the tube through the polyline's points.
                            let point = |p: &Vec<f64>| {
                                Vector3::from_iterator(p.iter().copied().chain([0.0; 3]).take(3))
                            };
                            let points: Vec<_> = beam.geometry.points.iter().map(point).collect();
                            shape.polyline(&points, &outline, axis);
                        }
                    }
                    BodyModel::Beam(beam) if shape.frame(beam, body) => {}
                    BodyModel::Imported(_) if shape.surface(body) => {}
                    _ => {
                        let markers = scene
                            .bodies
                            .iter()
                            .find(|b| b.name == spec.name)
                            .unwrap_or(spec)
                            .markers
                            .iter()
                            .map(|m| m.position.vec());
                        shape.sticks(markers.collect(), radius);
                    }
                }
                shape.joints(prepared, body, 1.5 * radius);
                if let Some(fs) = &body.reduced.foreshortening {
                    crate::quadratic::foreshorten(&mut shape, fs, body.nodes.n_modes());
                }
                shape
            })
            .collect()
    }

    /// A sphere at the marker of each joint on this body (the body2 side, the body1 side of
    /// a joint to the ground), moving with the FE node it sits on in a flexible body.
    fn joints(&mut self, prepared: &PreparedScene, body: &PreparedBody, radius: f64) {
        let scene = prepared.scene();
        let name = &scene.bodies[body.index].name;
        for joint in &scene.joints {
            let (on, marker) = match joint.body2.as_str() {
                "ground" => (&joint.body1, &joint.marker1),
                _ => (&joint.body2, &joint.marker2),
            };
            let markers = &scene.bodies[body.index].markers;
            let Some(m) = markers
                .iter()
                .filter(|_| on == name)
                .find(|m| &m.name == marker)
            else {
                continue;
            };
            let centre = m.position.vec();
            let node = body.nodes.node_at(&centre, 1e-9);
            let shift: Vec<_> = (0..self.targets.len())
                .map(|j| {
                    node.map_or(Vector3::zeros(), |n| {
                        Vector3::from_fn(|a, _| body.nodes.translation_entry(n, a, j))
                    })
                })
                .collect();
            let first = self.positions.len();
            self.sphere(centre, radius, &shift);
            self.on_node(first, node);
        }
    }

    /// A sphere (6 bands of 12 facets), each mode moving it by `shift`.
    fn sphere(&mut self, centre: Vector3<f64>, radius: f64, shift: &[Vector3<f64>]) {
        let (bands, around) = (6u32, 12u32);
        let first = self.positions.len() as u32;
        let mut vertex = |direction: Vector3<f64>| {
            self.positions.push(centre + radius * direction);
            self.normals.push(direction);
            for (target, d) in self.targets.iter_mut().zip(shift) {
                target.push(*d);
            }
        };
        vertex(Vector3::z());
        for i in 1..bands {
            let (st, ct) = (std::f64::consts::PI * i as f64 / bands as f64).sin_cos();
            for k in 0..around {
                let (sp, cp) = (std::f64::consts::TAU * k as f64 / around as f64).sin_cos();
                vertex(Vector3::new(st * cp, st * sp, ct));
            }
        }
        vertex(-Vector3::z());
        let ring = |i: u32, k: u32| first + 1 + (i - 1) * around + k % around;
        let bottom = first + 1 + (bands - 1) * around;
        for k in 0..around {
            self.triangles.push([first, ring(1, k), ring(1, k + 1)]);
            self.triangles
                .push([bottom, ring(bands - 1, k + 1), ring(bands - 1, k)]);
            for i in 1..bands - 1 {
                self.triangles
                    .push([ring(i, k), ring(i + 1, k), ring(i + 1, k + 1)]);
                self.triangles
                    .push([ring(i, k), ring(i + 1, k + 1), ring(i, k + 1)]);
            }
        }
    }

    /// Sticks from the centroid of `markers` to each (none for a body without markers).
    fn sticks(&mut self, markers: Vec<Vector3<f64>>, radius: f64) {
        if markers.is_empty() {
            return;
        }
        let centre = markers.iter().sum::<Vector3<f64>>() / markers.len() as f64;
        let outline = Outline::circle(radius);
        for m in markers {
            if (m - centre).norm() > radius {
                let rings = [centre, m].map(|p| (p, (m - centre).normalize()));
                self.tube(&rings, &outline, Vector3::z(), &|_, _| Vec::new());
            }
        }
    }

    /// A tube through `points`, without morph targets (a beam run rigid).
    fn polyline(&mut self, points: &[Vector3<f64>], outline: &Outline, k: Vector3<f64>) {
        let n = points.len();
        if n < 2 {
            return;
        }
        let rings: Vec<_> = (0..n)
            .map(|i| {
                (
                    points[i],
                    (points[(i + 1).min(n - 1)] - points[i.saturating_sub(1)]).normalize(),
                )
            })
            .collect();
        self.tube(&rings, outline, k, &|_, _| Vec::new());
    }

    /// A tube along the nodes `along` of a beam (a polyline's, numbered along it, or a
    /// frame member's), the section's axes ȳ_e = k̄ × x̄_e / |k̄ × x̄_e|, z̄_e = x̄_e × ȳ_e with
    /// k̄ the beam's orientation vector.
    fn beam(
        &mut self,
        nodes: &flexmbd::body::NodeRows,
        along: &[usize],
        outline: &Outline,
        k: Vector3<f64>,
    ) {
        let n = along.len();
        if n < 2 {
            return;
        }
        let p = |i: usize| nodes.position(along[i]);
        let rings: Vec<_> = (0..n)
            .map(|i| {
                let tangent = (p((i + 1).min(n - 1)) - p(i.saturating_sub(1))).normalize();
                (p(i), tangent)
            })
            .collect();
        let modes = nodes.n_modes();
        let shift = |ring: usize, offset: Vector3<f64>| {
            let node = along[ring];
            let (t, r) = (nodes.translation_matrix(node), nodes.rotation_matrix(node));
            (0..modes)
                .map(|j| {
                    let tj = Vector3::new(t[(0, j)], t[(1, j)], t[(2, j)]);
                    let rj = Vector3::new(r[(0, j)], r[(1, j)], r[(2, j)]);
                    tj + rj.cross(&offset)
                })
                .collect::<Vec<_>>()
        };
        self.targets.resize(modes, Vec::new());
        let first = self.positions.len();
        self.tube(&rings, outline, k, &shift);
        self.vertex_nodes.resize(first, None);
        for &node in along {
            let ring = std::iter::repeat_n(Some(node), outline.points.len());
            self.vertex_nodes.extend(ring);
        }
    }

    /// A beam frame, each member a tube of its section along its FE nodes (named end, the
    /// interior nodes from its `from` end, named end: `flexmbd::fe::frame`), deformed by
    /// the nodes' mode rows when the body runs flexible, through the members' undeformed
    /// nodes when it runs rigid. False (nothing drawn) for a polyline beam, or when the
    /// body's node rows are not the frame's mesh (another numbering).
    fn frame(&mut self, beam: &BeamBodySpec, body: &PreparedBody) -> bool {
        if !beam.geometry.is_frame() {
            return false;
        }
        let (positions, elements) = frame::frame_mesh(beam);
        let same_nodes = body.nodes.len() == positions.len()
            && (0..positions.len()).all(|k| (body.nodes.position(k) - positions[k]).norm() < 1e-9);
        if body.flexible && !same_nodes {
            return false;
        }
        for m in 0..beam.geometry.members.len() {
            let mut along: Vec<usize> = Vec::new();
            for e in elements.iter().filter(|e| e.member == m) {
                if along.is_empty() {
                    along.push(e.nodes[0]);
                }
                along.push(e.nodes[1]);
            }
            let outline = Outline::of(frame::member_section(beam, m));
            let axis = frame::member_orientation(beam, m).map_or(Vector3::z(), Vector3::from);
            if body.flexible {
                self.beam(&body.nodes, &along, &outline, axis);
            } else {
                let points: Vec<_> = along.iter().map(|&k| positions[k]).collect();
                self.polyline(&points, &outline, axis);
            }
        }
        true
    }

    /// An imported FE body's outer surface (`PreparedBody::surface`): one vertex per
    /// surface node, its normal the area-weighted mean of its triangles', each mode moving
    /// it by its node's translation rows X^t_P (the surface's vertices are FE nodes, so the
    /// morphed surface is exact at every vertex). False (nothing drawn) for a body without
    /// a surface.
    fn surface(&mut self, body: &PreparedBody) -> bool {
        let nodes = &body.nodes;
        if body.surface.is_empty() || body.surface.iter().flatten().any(|&k| k >= nodes.len()) {
            return false;
        }
        let first = self.positions.len();
        let mut vertex = vec![usize::MAX; nodes.len()];
        let mut used = Vec::new();
        for &k in body.surface.iter().flatten() {
            if vertex[k] == usize::MAX {
                vertex[k] = first + used.len();
                used.push(k);
            }
        }
        let mut normals = vec![Vector3::zeros(); used.len()];
        for t in &body.surface {
            let p = |i: usize| nodes.position(t[i]);
            let area_normal = (p(1) - p(0)).cross(&(p(2) - p(0)));
            for &k in t {
                normals[vertex[k] - first] += area_normal;
            }
            self.triangles.push(t.map(|k| vertex[k] as u32));
        }
        let modes = nodes.n_modes();
        self.targets.resize(modes, Vec::new());
        for (&k, normal) in used.iter().zip(normals) {
            self.on_node(self.positions.len(), None);
            self.vertex_nodes.push(Some(k));
            self.positions.push(nodes.position(k));
            self.normals
                .push(normal.try_normalize(0.0).unwrap_or_else(Vector3::z));
            for (j, target) in self.targets.iter_mut().enumerate() {
                target.push(Vector3::from_fn(|a, _| nodes.translation_entry(k, a, j)));
            }
        }
        true
    }

    /// Rings of `outline` at `rings` (point, tangent), joined face by face; `shift(ring,
    /// offset)` gives each mode's displacement of a vertex at `offset` from its ring's point.
    fn tube(
        &mut self,
        rings: &[(Vector3<f64>, Vector3<f64>)],
        outline: &Outline,
        k: Vector3<f64>,
        shift: &dyn Fn(usize, Vector3<f64>) -> Vec<Vector3<f64>>,
    ) {
        let first = self.positions.len() as u32;
        let per_ring = outline.points.len() as u32;
        for (i, (point, tangent)) in rings.iter().enumerate() {
            let k = if k.cross(tangent).norm() < 1e-9 {
                Vector3::y()
            } else {
                k
            };
            let y = k.cross(tangent).normalize();
            let z = tangent.cross(&y);
            for &([a, b], [na, nb]) in &outline.points {
                let offset = a * y + b * z;
                self.positions.push(point + offset);
                self.normals.push((na * y + nb * z).normalize());
                for (target, d) in self.targets.iter_mut().zip(shift(i, offset)) {
                    target.push(d);
                }
            }
        }
        for i in 0..rings.len() as u32 - 1 {
            let (r0, r1) = (first + i * per_ring, first + (i + 1) * per_ring);
            for &(a, b) in &outline.edges {
                let (a, b) = (a as u32, b as u32);
                self.triangles.push([r0 + a, r0 + b, r1 + b]);
                self.triangles.push([r0 + a, r1 + b, r1 + a]);
            }
        }
    }
}
