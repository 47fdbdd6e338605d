//! The planar natural-coordinate formulation (docs/methods.md §3, thesis ch. 2).
//!
//! **Coordinates.** Basic points are shared by the bodies they join: every group of
//! markers connected by revolute joints is one point, fixed when it touches the ground
//! and two coordinates otherwise. Each body is described by a basis x_b = (a, b) of two
//! 2-vectors taken from the coordinates (or the fixed points):
//!
//! - a rigid body with two or more joint points uses its first two points (i, j), with
//!   the constant-distance constraint |r_j − r_i|² = L² (the classical natural-coordinate
//!   bar);
//! - a rigid body with one joint point, and every flexible body, uses a point (the joint
//!   point at the frame's reference node, or its own origin) and its own unit vector u
//!   along the body x axis, with |u|² = 1;
//! - a flexible body adds its modal coordinates y.
//!
//! The body frame (r0, u), A = [u  E u], is a constant linear map of the basis,
//! f = T x_b (two points: u = R(−φ)(r_j − r_i)/L, r0 = r_i − (r̄_i1 I + r̄_i2 E) u), so the
//! body's natural-set mass matrix and forces (docs/methods.md §2.5–§2.6) are projected with
//! the constant T: M_b = Tᵀ M_f T, Q_b = Tᵀ Q_f, and no velocity terms arise from T.
//!
//! **Constraints.** Joint points of a body that are not in its basis are tied to it by
//! r0 + A (r̄_P + X_P y) − r_point = 0 (linear for rigid bodies, bilinear for flexible
//! ones, docs/methods.md §3.3). Angle drivers and brackets use Φ = σ cos θ − κ sin θ
//! = sin(φ − θ) with σ = d₁ × d₂, κ = d₁ · d₂ (docs/methods.md §3.2), never singular at
//! its root. A body-fixed direction is d = A (I + θ_P E) ā (θ_P the node rotation at a
//! flexible node, docs/methods.md §3.3).
//!
//! **Prismatic joints.** The markers are not shared points: the marker P2 of body 2 slides
//! along the axis d₁ fixed in body 1 through its marker P1, (r_P2 − r_P1) × d₁ = 0, and the
//! relative rotation is locked by the angle constraint with θ ≡ 0. A driver adds
//! (r_P2 − r_P1) · d₁ − s₀ − s(t) = 0; the joint-coordinate sensor reports
//! (r_P2 − r_P1) · d₁ − s₀.
//!
//! **Spring–dampers** between two markers add Q −= Jᵀ f n with J = ∂(r_P2 − r_P1)/∂q and
//! f = k (l − l₀) + c l̇, and their (state-dependent) tangents to K and C.

use flexmbd_body::{FlexibleBody, InertiaMethod};
use flexmbd_core::{MarkerKinematics, Request, SystemTerms};
use flexmbd_model::force_elements::ForceElements;
use flexmbd_model::{
    Axis, BodyId, FormulationKind, GROUND, JointKind, MarkerId, ModelError, MotionLaw,
    PreparedScene, SensorKind,
};
use nalgebra::{DMatrix, DVector, Matrix2, Matrix4, Vector2, Vector3};

use crate::flex;

/// One scalar of a basis: a coordinate or a fixed value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Slot {
    Q(usize),
    Fixed(f64),
}

impl Slot {
    #[inline]
    fn get(self, q: &DVector<f64>) -> f64 {
        match self {
            Slot::Q(i) => q[i],
            Slot::Fixed(v) => v,
        }
    }
    #[inline]
    fn rate(self, qd: &DVector<f64>) -> f64 {
        match self {
            Slot::Q(i) => qd[i],
            Slot::Fixed(_) => 0.0,
        }
    }
}

/// E = [[0, −1], [1, 0]]: e_z × a = E a.
#[inline]
pub(crate) fn e_mat() -> Matrix2<f64> {
    Matrix2::new(0.0, -1.0, 1.0, 0.0)
}

/// C(p) = p₁ I + p₂ E, so that A p = C(p) u for A = [u  E u].
#[inline]
pub(crate) fn c_of(p: &Vector2<f64>) -> Matrix2<f64> {
    Matrix2::new(p.x, -p.y, p.y, p.x)
}

#[inline]
fn cross(a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

pub(crate) struct Body2 {
    pub(crate) body: FlexibleBody,
    slots: [Slot; 4],
    /// (r0, u) = T x_b.
    t: Matrix4<f64>,
    /// First modal coordinate in q.
    pub(crate) y_off: usize,
    pub(crate) n: usize,
    /// Rigid bodies: constant Tᵀ M_f T and Tᵀ Q_gravity.
    m_const: Matrix4<f64>,
    q_const: nalgebra::Vector4<f64>,
    /// Markers: undeformed position and FE node (flexible bodies).
    markers: Vec<(String, Vector2<f64>, Option<usize>)>,
    /// Per-evaluation storage of a flexible body (frame-coordinate terms).
    flex_ws: Option<flex::Flex2>,
}

/// A point of the scene in the coordinates.
#[derive(Clone, Copy, Debug)]
struct PointRef {
    x: Slot,
    y: Slot,
}

/// A body-fixed direction d = A (I + θ_node E) ā = C(ā)(I + θ_node E) u: the body-frame
/// direction ā, turned with the frame and, at a flexible node, by the node rotation.
#[derive(Clone, Copy, Debug)]
struct Dir {
    /// `None`: the ground (d = ā, ground components).
    body: Option<usize>,
    node: Option<usize>,
    /// Body-frame components of the direction (the x axis (1, 0) for angle constraints).
    abar: Vector2<f64>,
}

/// A marker: a ground point, or a body point r_P = r0 + A (r̄_P + X_P y) (the node term on
/// flexible bodies only).
#[derive(Clone, Copy, Debug)]
pub enum PlanarMarker {
    /// A ground point (m, ground components).
    Ground(Vector2<f64>),
    /// A point of a body.
    Body {
        /// Index of the body.
        body: usize,
        /// Position r̄_P in the body frame, undeformed (m).
        rbar: Vector2<f64>,
        /// The FE node it sits on (flexible bodies only).
        node: Option<usize>,
    },
}

enum Con {
    Distance {
        a: PointRef,
        b: PointRef,
        l2: f64,
    },
    Unit {
        u: [Slot; 2],
    },
    /// r_P(q) − r_point = 0 for a joint point P of a body not in its basis.
    PointOnBody {
        mk: PlanarMarker,
        point: PointRef,
    },
    /// Prismatic: (r_P2 − r_P1) × d₁ = 0 (`along` = None), or its driver
    /// (r_P2 − r_P1) · d₁ − s₀ − s(t) = 0 (`along` = (s₀, s)).
    Slide {
        p1: PlanarMarker,
        p2: PlanarMarker,
        d1: Dir,
        along: Option<(f64, MotionLaw)>,
    },
    Angle {
        d1: Dir,
        d2: Dir,
        phi0: f64,
        law: MotionLaw,
    },
}

impl Con {
    fn rows(&self) -> usize {
        match self {
            Con::PointOnBody { .. } => 2,
            _ => 1,
        }
    }
}

enum Sensor2 {
    Position {
        body: Option<usize>,
        marker: usize,
        axis: usize,
        frame: Option<usize>,
    },
    Velocity {
        body: Option<usize>,
        marker: usize,
        axis: usize,
        frame: Option<usize>,
    },
    Joint {
        d1: Dir,
        d2: Dir,
        phi0: f64,
        last: f64,
        turns: f64,
    },
    /// Prismatic joint coordinate: (r_P2 − r_P1) · d₁ − s₀.
    Slide {
        p1: PlanarMarker,
        p2: PlanarMarker,
        d1: Dir,
        s0: f64,
    },
    Modal {
        q: Option<usize>,
    },
    Energy,
}

/// The compiled planar scene.
pub struct Planar {
    pub(crate) n: usize,
    m: usize,
    gravity: Vector2<f64>,
    pub(crate) bodies: Vec<Body2>,
    cons: Vec<Con>,
    force_elements: ForceElements<PlanarMarker>,
    /// Σ over rigid bodies of Tᵀ M_f T and Tᵀ Q_gravity, scattered (constant).
    rigid_mass: DMatrix<f64>,
    rigid_forces: DVector<f64>,
    ground_markers: Vec<Vector2<f64>>,
    q0: DVector<f64>,
    qd0: DVector<f64>,
    held: Vec<usize>,
    sensor_names: Vec<String>,
    sensors: Vec<Sensor2>,
    method: InertiaMethod,
    /// Scratch for one body's local dense terms.
    local_m: DMatrix<f64>,
    local_q: DVector<f64>,
    local_idx: Vec<Option<usize>>,
}

struct UnionFind(Vec<usize>);
impl UnionFind {
    fn find(&mut self, i: usize) -> usize {
        let mut r = i;
        while self.0[r] != r {
            r = self.0[r];
        }
        let mut i = i;
        while self.0[i] != r {
            let next = self.0[i];
            self.0[i] = r;
            i = next;
        }
        r
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
}

fn unsupported(what: String) -> ModelError {
    ModelError::Unsupported(what)
}

impl Planar {
    /// Compile a planar scene.
    pub fn compile(prepared: &PreparedScene) -> Result<Planar, ModelError> {
        let scene = prepared.scene();
        debug_assert_eq!(scene.solver.formulation, FormulationKind::Absolute);
        // Marker table: ground markers first, then every body's.
        let mut marker_of: Vec<(Option<usize>, usize)> = Vec::new();
        let mut marker_pos: Vec<Vector2<f64>> = Vec::new(); // ground: global; bodies: body frame
        for (k, m) in scene.ground.iter().enumerate() {
            marker_of.push((None, k));
            marker_pos.push(Vector2::new(m.position.0[0], m.position.0[1]));
        }
        let mut first_marker = Vec::new();
        for (bi, b) in scene.bodies.iter().enumerate() {
            first_marker.push(marker_of.len());
            for (k, m) in b.markers.iter().enumerate() {
                marker_of.push((Some(bi), k));
                marker_pos.push(Vector2::new(m.position.0[0], m.position.0[1]));
            }
        }
        let global_index = |body: &str, marker: &str| -> usize {
            if body == GROUND {
                scene
                    .ground
                    .iter()
                    .position(|m| m.name == marker)
                    .expect("validated")
            } else {
                let bi = scene
                    .bodies
                    .iter()
                    .position(|b| b.name == body)
                    .expect("validated");
                first_marker[bi]
                    + scene.bodies[bi]
                        .markers
                        .iter()
                        .position(|m| m.name == marker)
                        .expect("validated")
            }
        };
        let body_index = |name: &str| -> Option<usize> {
            if name == GROUND {
                None
            } else {
                scene.bodies.iter().position(|b| b.name == name)
            }
        };
        // Initial frames.
        let frames: Vec<(Vector2<f64>, f64)> = scene
            .bodies
            .iter()
            .map(|b| {
                let a = b.orientation.matrix();
                (
                    Vector2::new(b.origin.0[0], b.origin.0[1]),
                    a[(1, 0)].atan2(a[(0, 0)]),
                )
            })
            .collect();
        let global_pos = |gi: usize| -> Vector2<f64> {
            match marker_of[gi] {
                (None, _) => marker_pos[gi],
                (Some(bi), _) => {
                    let (o, th) = frames[bi];
                    let (s, c) = th.sin_cos();
                    o + Matrix2::new(c, -s, s, c) * marker_pos[gi]
                }
            }
        };

        // Points: revolute and bracket joints share their point.
        let mut uf = UnionFind((0..marker_of.len()).collect());
        for j in &scene.joints {
            match j.kind {
                JointKind::Revolute { .. } | JointKind::Rigid => {
                    uf.union(
                        global_index(&j.body1, &j.marker1),
                        global_index(&j.body2, &j.marker2),
                    );
                }
                // Its markers are not shared points: they slide on each other.
                JointKind::Prismatic { .. } => {}
                // A floating base: no equation.
                JointKind::Free => {}
                ref k => {
                    return Err(unsupported(format!(
                        "joint `{}`: {:?} joints are not supported by the planar absolute formulation (revolute, prismatic and rigid are)",
                        j.name, k
                    )));
                }
            }
        }
        let mut n = 0usize;
        let mut q0 = Vec::new();
        let mut point_of_root: std::collections::HashMap<usize, PointRef> = Default::default();
        // Which marker groups are joint points (appear in a joint).
        let mut in_joint = vec![false; marker_of.len()];
        for j in &scene.joints {
            if matches!(j.kind, JointKind::Revolute { .. } | JointKind::Rigid) {
                in_joint[global_index(&j.body1, &j.marker1)] = true;
                in_joint[global_index(&j.body2, &j.marker2)] = true;
            }
        }
        // Ground-touching groups are fixed.
        for gi in 0..marker_of.len() {
            if !in_joint[gi] {
                continue;
            }
            let root = uf.find(gi);
            if marker_of[gi].0.is_none() {
                let p = marker_pos[gi];
                point_of_root.insert(
                    root,
                    PointRef {
                        x: Slot::Fixed(p.x),
                        y: Slot::Fixed(p.y),
                    },
                );
            }
        }
        for gi in 0..marker_of.len() {
            if !in_joint[gi] {
                continue;
            }
            let root = uf.find(gi);
            if let std::collections::hash_map::Entry::Vacant(e) = point_of_root.entry(root) {
                let p = global_pos(gi);
                e.insert(PointRef {
                    x: Slot::Q(n),
                    y: Slot::Q(n + 1),
                });
                q0.extend([p.x, p.y]);
                n += 2;
            }
        }
        for gi in 0..marker_of.len() {
            if in_joint[gi] {
                let p = global_pos(gi);
                let root_p = global_pos(uf.find(gi));
                if (p - root_p).norm() > 1e-6 {
                    let (b, k) = marker_of[gi];
                    let name = b.map_or(GROUND, |b| scene.bodies[b].name.as_str());
                    let mname = match b {
                        None => scene.ground[k].name.as_str(),
                        Some(b) => scene.bodies[b].markers[k].name.as_str(),
                    };
                    return Err(unsupported(format!(
                        "{}: marker `{name}.{mname}` is at ({:.6}, {:.6}) but the joint point it shares is at ({:.6}, {:.6}); joined markers must coincide at t = 0",
                        scene.origin, p.x, p.y, root_p.x, root_p.y
                    )));
                }
            }
        }
        let point_at = |gi: usize, uf: &mut UnionFind| -> Option<PointRef> {
            if in_joint[gi] {
                point_of_root.get(&uf.find(gi)).copied()
            } else {
                None
            }
        };

        let method = scene.solver.inertia;
        let mut bodies = Vec::new();
        let mut cons = Vec::new();
        let mut qd0_pending: Vec<(usize, f64)> = Vec::new();
        for (bi, (b, prep)) in scene.bodies.iter().zip(prepared.bodies()).enumerate() {
            let body = prep.body.clone();
            let nm = body.n_modes();
            let flexible = prep.flexible;
            let (o, th) = frames[bi];
            let u0 = Vector2::new(th.cos(), th.sin());
            let markers: Vec<(String, Vector2<f64>, Option<usize>)> = b
                .markers
                .iter()
                .enumerate()
                .map(|(k, m)| {
                    (
                        m.name.clone(),
                        marker_pos[first_marker[bi] + k],
                        prep.marker_nodes[k],
                    )
                })
                .collect();
            // Joint points of this body, in marker order.
            let joint_markers: Vec<usize> = (0..b.markers.len())
                .filter(|&k| in_joint[first_marker[bi] + k])
                .collect();
            let reference_node = prep.reference_node;
            let mut basis_markers: Vec<usize> = Vec::new();
            let v = &b.velocity;
            let (v0, w) = (Vector2::new(v.linear.0[0], v.linear.0[1]), v.angular.0[2]);
            let a0 = Matrix2::new(th.cos(), -th.sin(), th.sin(), th.cos());
            // Velocity of a body point r̄ of the rigid initial motion (ṙ0, ω).
            let vel_of = |rbar: Vector2<f64>| v0 + w * e_mat() * (a0 * rbar);
            let (slots, t, basis_vel);
            let two = if flexible {
                None
            } else {
                // Two distinct joint points.
                let mut pick = None;
                'outer: for (x, &ka) in joint_markers.iter().enumerate() {
                    for &kb in &joint_markers[x + 1..] {
                        let (pa, pb) = (markers[ka].1, markers[kb].1);
                        if (pb - pa).norm() > 1e-9 {
                            pick = Some((ka, kb));
                            break 'outer;
                        }
                    }
                }
                pick
            };
            if let Some((ka, kb)) = two {
                let pa = point_at(first_marker[bi] + ka, &mut uf).expect("joint point");
                let pb = point_at(first_marker[bi] + kb, &mut uf).expect("joint point");
                let (ra, rb) = (markers[ka].1, markers[kb].1);
                let d = rb - ra;
                let length = d.norm();
                let phi = d.y.atan2(d.x);
                // u = R(−φ)(r_j − r_i)/L ; r0 = r_i − C(r̄_i) u.
                let rot = Matrix2::new(phi.cos(), phi.sin(), -phi.sin(), phi.cos()) / length;
                let mut tm = Matrix4::zeros();
                tm.fixed_view_mut::<2, 2>(2, 0).copy_from(&(-rot));
                tm.fixed_view_mut::<2, 2>(2, 2).copy_from(&rot);
                let ci = c_of(&ra);
                let r0_a = Matrix2::identity() + ci * rot;
                let r0_b = -(ci * rot);
                tm.fixed_view_mut::<2, 2>(0, 0).copy_from(&r0_a);
                tm.fixed_view_mut::<2, 2>(0, 2).copy_from(&r0_b);
                slots = [pa.x, pa.y, pb.x, pb.y];
                t = tm;
                basis_vel = [vel_of(ra), vel_of(rb)];
                basis_markers.extend([ka, kb]);
                cons.push(Con::Distance {
                    a: pa,
                    b: pb,
                    l2: length * length,
                });
            } else {
                // A point (joint point at the reference node, the first joint point, or the own origin) + own u.
                let anchor = match reference_node {
                    Some(node) => joint_markers
                        .iter()
                        .copied()
                        .find(|&k| markers[k].2 == Some(node)),
                    None => joint_markers.first().copied(),
                };
                let (p, rbar) = match anchor {
                    Some(k) => {
                        basis_markers.push(k);
                        (
                            point_at(first_marker[bi] + k, &mut uf).expect("joint point"),
                            markers[k].1,
                        )
                    }
                    None => {
                        let rbar = match reference_node {
                            Some(node) => {
                                let pos = prep.reduced.nodes[node].position;
                                Vector2::new(pos.x, pos.y)
                            }
                            None => Vector2::zeros(),
                        };
                        let (s, c) = th.sin_cos();
                        let p = o + Matrix2::new(c, -s, s, c) * rbar;
                        let pr = PointRef {
                            x: Slot::Q(n),
                            y: Slot::Q(n + 1),
                        };
                        q0.extend([p.x, p.y]);
                        n += 2;
                        (pr, rbar)
                    }
                };
                let u_slots = [Slot::Q(n), Slot::Q(n + 1)];
                q0.extend([u0.x, u0.y]);
                n += 2;
                let mut tm = Matrix4::identity();
                tm.fixed_view_mut::<2, 2>(0, 2).copy_from(&(-c_of(&rbar)));
                slots = [p.x, p.y, u_slots[0], u_slots[1]];
                t = tm;
                basis_vel = [vel_of(rbar), w * e_mat() * u0];
                cons.push(Con::Unit { u: u_slots });
            }
            let y_off = n;
            q0.extend((0..nm).map(|j| b.initial_modes.get(j).copied().unwrap_or(0.0)));
            n += nm;
            // Other joint points: tied to the body.
            for &k in &joint_markers {
                if basis_markers.contains(&k) {
                    continue;
                }
                let point = point_at(first_marker[bi] + k, &mut uf).expect("joint point");
                cons.push(Con::PointOnBody {
                    mk: PlanarMarker::Body {
                        body: bi,
                        rbar: markers[k].1,
                        node: if flexible { markers[k].2 } else { None },
                    },
                    point,
                });
            }
            for (k, slot) in slots.iter().enumerate() {
                if let Slot::Q(i) = slot {
                    qd0_pending.push((*i, basis_vel[k / 2][k % 2]));
                }
            }
            // Rigid constant terms in basis coordinates.
            let mut m_const = Matrix4::zeros();
            let mut q_const = nalgebra::Vector4::zeros();
            let g = Vector2::new(scene.gravity.0[0], scene.gravity.0[1]);
            if !flexible {
                let mass = body.mass();
                let mb = body.first_moment();
                let p = body.second_moment();
                let cm = c_of(&Vector2::new(mb.x, mb.y));
                let mut mf = Matrix4::zeros();
                mf.fixed_view_mut::<2, 2>(0, 0)
                    .copy_from(&(Matrix2::identity() * mass));
                mf.fixed_view_mut::<2, 2>(0, 2).copy_from(&cm);
                mf.fixed_view_mut::<2, 2>(2, 0).copy_from(&cm.transpose());
                mf.fixed_view_mut::<2, 2>(2, 2)
                    .copy_from(&(Matrix2::identity() * (p[(0, 0)] + p[(1, 1)])));
                m_const = t.transpose() * mf * t;
                let mut qf = nalgebra::Vector4::zeros();
                qf.fixed_rows_mut::<2>(0).copy_from(&(g * mass));
                qf.fixed_rows_mut::<2>(2).copy_from(&(cm.transpose() * g));
                q_const = t.transpose() * qf;
            }
            let flex_ws = if flexible {
                Some(flex::Flex2::new(&body, &prep.reduced))
            } else {
                None
            };
            bodies.push(Body2 {
                body,
                slots,
                t,
                y_off,
                n: nm,
                m_const,
                q_const,
                markers,
                flex_ws,
            });
        }
        let mut qd0 = DVector::zeros(n);
        for (i, v) in qd0_pending {
            qd0[i] = v;
        }
        // Drivers and brackets: angle constraints.
        let dir_of = |body: &str, marker: &str, bodies: &[Body2]| -> Dir {
            match body_index(body) {
                None => Dir {
                    body: None,
                    node: None,
                    abar: Vector2::new(1.0, 0.0),
                },
                Some(bi) => {
                    let k = scene.bodies[bi]
                        .markers
                        .iter()
                        .position(|m| m.name == marker)
                        .expect("validated");
                    Dir {
                        body: Some(bi),
                        node: if bodies[bi].n > 0 {
                            bodies[bi].markers[k].2
                        } else {
                            None
                        },
                        abar: Vector2::new(1.0, 0.0),
                    }
                }
            }
        };
        let mk_of = |body: &str, marker: &str, bodies: &[Body2]| -> PlanarMarker {
            match body_index(body) {
                None => {
                    let m = scene
                        .ground
                        .iter()
                        .find(|m| m.name == marker)
                        .expect("validated");
                    PlanarMarker::Ground(Vector2::new(m.position.0[0], m.position.0[1]))
                }
                Some(bi) => {
                    let b = &bodies[bi];
                    let k = b
                        .markers
                        .iter()
                        .position(|m| m.0 == marker)
                        .expect("validated");
                    PlanarMarker::Body {
                        body: bi,
                        rbar: b.markers[k].1,
                        node: if b.n > 0 { b.markers[k].2 } else { None },
                    }
                }
            }
        };
        let q0v = DVector::from_vec(q0);
        let mut planar = Planar {
            n,
            m: 0,
            gravity: Vector2::new(scene.gravity.0[0], scene.gravity.0[1]),
            bodies,
            cons: Vec::new(),
            force_elements: ForceElements::default(),
            rigid_mass: DMatrix::zeros(0, 0),
            rigid_forces: DVector::zeros(0),
            ground_markers: scene
                .ground
                .iter()
                .map(|m| Vector2::new(m.position.0[0], m.position.0[1]))
                .collect(),
            q0: q0v.clone(),
            qd0,
            held: Vec::new(),
            sensor_names: scene.sensors.iter().map(|s| s.name.clone()).collect(),
            sensors: Vec::new(),
            method,
            local_m: DMatrix::zeros(0, 0),
            local_q: DVector::zeros(0),
            local_idx: Vec::new(),
        };
        let zero = DVector::zeros(n);
        for j in &scene.joints {
            let driver = scene.drivers.iter().find(|d| d.joint == j.name);
            if let JointKind::Prismatic { axis } = &j.kind {
                let (p1, p2, d1) =
                    planar.prismatic_parts(j, axis, &mk_of, &dir_of, &q0v, &scene.origin)?;
                cons.push(Con::Slide {
                    p1,
                    p2,
                    d1,
                    along: None,
                });
                // The relative rotation is locked.
                let a1 = dir_of(&j.body1, &j.marker1, &planar.bodies);
                let a2 = dir_of(&j.body2, &j.marker2, &planar.bodies);
                let phi0 = planar.angle(&a1, &a2, &q0v);
                cons.push(Con::Angle {
                    d1: a1,
                    d2: a2,
                    phi0,
                    law: MotionLaw::Locked,
                });
                if let Some(d) = driver {
                    let s0 = planar.slide(&p1, &p2, &d1, &q0v, &zero);
                    cons.push(Con::Slide {
                        p1,
                        p2,
                        d1,
                        along: Some((s0, d.law.clone())),
                    });
                }
                continue;
            }
            let law = match (&j.kind, driver) {
                (JointKind::Rigid, _) => Some(MotionLaw::Locked),
                (_, Some(d)) => Some(d.law.clone()),
                _ => None,
            };
            if let Some(law) = law {
                let d1 = dir_of(&j.body1, &j.marker1, &planar.bodies);
                let d2 = dir_of(&j.body2, &j.marker2, &planar.bodies);
                let phi0 = planar.angle(&d1, &d2, &q0v);
                cons.push(Con::Angle { d1, d2, phi0, law });
            }
        }
        planar.m = cons.iter().map(Con::rows).sum();
        planar.cons = cons;
        // Force elements.
        let marker_of_id = |id: MarkerId| -> PlanarMarker {
            match id.body {
                None => {
                    let p = prepared.marker_position(id);
                    PlanarMarker::Ground(Vector2::new(p.x, p.y))
                }
                Some(BodyId(bi)) => {
                    let b = &planar.bodies[bi];
                    PlanarMarker::Body {
                        body: bi,
                        rbar: b.markers[id.index].1,
                        node: if b.n > 0 { b.markers[id.index].2 } else { None },
                    }
                }
            }
        };
        planar.force_elements =
            ForceElements::new(prepared, marker_of_id, &planar, &q0v, &zero, planar.n)?;
        // Sensors.
        for s in &scene.sensors {
            let marker_index = |body: &str, marker: &str| -> (Option<usize>, usize) {
                match body_index(body) {
                    None => (
                        None,
                        scene
                            .ground
                            .iter()
                            .position(|m| m.name == marker)
                            .expect("validated"),
                    ),
                    Some(bi) => (
                        Some(bi),
                        scene.bodies[bi]
                            .markers
                            .iter()
                            .position(|m| m.name == marker)
                            .expect("validated"),
                    ),
                }
            };
            let sensor = match &s.kind {
                SensorKind::Position {
                    body,
                    marker,
                    component,
                    frame,
                } => {
                    let (b, k) = marker_index(body, marker);
                    Sensor2::Position {
                        body: b,
                        marker: k,
                        axis: planar_axis(*component, &s.name)?,
                        frame: frame.as_deref().and_then(body_index),
                    }
                }
                SensorKind::Velocity {
                    body,
                    marker,
                    component,
                    frame,
                } => {
                    let (b, k) = marker_index(body, marker);
                    Sensor2::Velocity {
                        body: b,
                        marker: k,
                        axis: planar_axis(*component, &s.name)?,
                        frame: frame.as_deref().and_then(body_index),
                    }
                }
                SensorKind::JointCoordinate { joint } => {
                    let j = scene
                        .joints
                        .iter()
                        .find(|j| &j.name == joint)
                        .expect("validated");
                    if let JointKind::Prismatic { axis } = &j.kind {
                        let (p1, p2, d1) = planar.prismatic_parts(
                            j,
                            axis,
                            &mk_of,
                            &dir_of,
                            &q0v,
                            &scene.origin,
                        )?;
                        let s0 = planar.slide(&p1, &p2, &d1, &q0v, &zero);
                        planar.sensors.push(Sensor2::Slide { p1, p2, d1, s0 });
                        continue;
                    }
                    let d1 = dir_of(&j.body1, &j.marker1, &planar.bodies);
                    let d2 = dir_of(&j.body2, &j.marker2, &planar.bodies);
                    let phi0 = planar.angle(&d1, &d2, &q0v);
                    Sensor2::Joint {
                        d1,
                        d2,
                        phi0,
                        last: 0.0,
                        turns: 0.0,
                    }
                }
                SensorKind::Modal { body, index } => {
                    let bi = body_index(body).expect("validated");
                    let b = &planar.bodies[bi];
                    Sensor2::Modal {
                        q: (*index < b.n).then_some(b.y_off + index),
                    }
                }
                SensorKind::Energy => Sensor2::Energy,
            };
            planar.sensors.push(sensor);
        }
        let max_local = planar.bodies.iter().map(|b| 4 + b.n).max().unwrap_or(4);
        planar.local_m = DMatrix::zeros(max_local, max_local);
        planar.local_q = DVector::zeros(max_local);
        planar.local_idx = vec![None; max_local];
        let mut rigid = SystemTerms::new(planar.n, 0);
        for bi in 0..planar.bodies.len() {
            if planar.bodies[bi].n == 0 {
                let b = &planar.bodies[bi];
                planar
                    .local_m
                    .view_mut((0, 0), (4, 4))
                    .copy_from(&b.m_const);
                planar.local_q.rows_mut(0, 4).copy_from(&b.q_const);
                planar.scatter(bi, 4, &mut rigid);
            }
        }
        planar.rigid_mass = rigid.mass;
        planar.rigid_forces = rigid.forces;
        Ok(planar)
    }

    /// Coordinates of the body's basis and frame: (r0, u) and their rates.
    fn frame(
        &self,
        b: &Body2,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        let x = nalgebra::Vector4::from_fn(|i, _| b.slots[i].get(q));
        let xd = nalgebra::Vector4::from_fn(|i, _| b.slots[i].rate(qd));
        let f = b.t * x;
        let fd = b.t * xd;
        (
            Vector2::new(f[0], f[1]),
            Vector2::new(f[2], f[3]),
            Vector2::new(fd[0], fd[1]),
            Vector2::new(fd[2], fd[3]),
        )
    }

    /// Direction d of a `Dir` (global), its rate, its bias (second derivative at q̈ = 0),
    /// and the Jacobian rows: (∂d/∂(basis u part), ∂d/∂y).
    fn direction(
        &self,
        d: &Dir,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        match d.body {
            None => (d.abar, Vector2::zeros(), Vector2::zeros()),
            Some(bi) => {
                let b = &self.bodies[bi];
                let (_, u, _, ud) = self.frame(b, q, qd);
                // (I + θE) u, then C(ā) (commutes with E).
                let (x, xd, xb) = match d.node {
                    None => (u, ud, Vector2::zeros()),
                    Some(node) => {
                        let (th, thd) = b.node_rotation(node, q, qd);
                        let e = e_mat();
                        (
                            u + th * (e * u),
                            ud + th * (e * ud) + thd * (e * u),
                            2.0 * thd * (e * ud),
                        )
                    }
                };
                let ca = c_of(&d.abar);
                (ca * x, ca * xd, ca * xb)
            }
        }
    }

    fn angle(&self, d1: &Dir, d2: &Dir, q: &DVector<f64>) -> f64 {
        let z = DVector::zeros(q.len());
        let (a, _, _) = self.direction(d1, q, &z);
        let (b, _, _) = self.direction(d2, q, &z);
        cross(&a, &b).atan2(a.dot(&b))
    }

    /// Add ∂d/∂q (row vector `w`ᵀ ∂d/∂q) to `row` of Φ_q, scaled.
    fn add_direction_jacobian(
        &self,
        d: &Dir,
        w: &Vector2<f64>,
        q: &DVector<f64>,
        phi_q: &mut DMatrix<f64>,
        row: usize,
    ) {
        let Some(bi) = d.body else { return };
        let b = &self.bodies[bi];
        // d = C(ā) d_x: wᵀ ∂d/∂q = (C(ā)ᵀ w)ᵀ ∂d_x/∂q.
        let w = &(c_of(&d.abar).transpose() * w);
        let (th, u) = match d.node {
            Some(node) => {
                let x = nalgebra::Vector4::from_fn(|i, _| b.slots[i].get(q));
                let f = b.t * x;
                let u = Vector2::new(f[2], f[3]);
                let th: f64 = (0..b.n).map(|j| b.rot_row(node)[j] * q[b.y_off + j]).sum();
                (th, u)
            }
            None => (0.0, Vector2::zeros()),
        };
        // ∂d/∂u = I + θ E ; ∂u/∂x_b = T[2..4, :]
        let e = e_mat();
        let du = Matrix2::identity() + th * e;
        let wt_du = du.transpose() * w; // 2
        for k in 0..4 {
            if let Slot::Q(i) = b.slots[k] {
                phi_q[(row, i)] += wt_du.x * b.t[(2, k)] + wt_du.y * b.t[(3, k)];
            }
        }
        if let Some(node) = d.node {
            // ∂d/∂y_j = E u · X^r_{node, j}
            let eu = e * u;
            let s = w.dot(&eu);
            let rr = b.rot_row(node);
            for j in 0..b.n {
                phi_q[(row, b.y_off + j)] += s * rr[j];
            }
        }
    }

    /// Global position of marker `k` of body `bi` (or a ground marker), and velocity.
    fn marker_state(
        &self,
        body: Option<usize>,
        k: usize,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector2<f64>, Vector2<f64>) {
        let mk = match body {
            None => PlanarMarker::Ground(self.ground_markers[k]),
            Some(bi) => {
                let b = &self.bodies[bi];
                PlanarMarker::Body {
                    body: bi,
                    rbar: b.markers[k].1,
                    node: b.markers[k].2,
                }
            }
        };
        let (r, v, _) = self.mk_state(&mk, q, qd);
        (r, v)
    }

    /// A marker's position r_P, velocity ṙ_P and bias r̈_P|q̈=0 = 2 C(Ẋ_P ẏ) u̇
    /// (r_P is bilinear in (u, y)).
    fn mk_state(
        &self,
        mk: &PlanarMarker,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        match *mk {
            PlanarMarker::Ground(p) => (p, Vector2::zeros(), Vector2::zeros()),
            PlanarMarker::Body { body, rbar, node } => {
                let b = &self.bodies[body];
                let (r0, u, r0d, ud) = self.frame(b, q, qd);
                let (p, pd) = b.local_point(rbar, node, q, qd);
                let (cp, cpd) = (c_of(&p), c_of(&pd));
                (r0 + cp * u, r0d + cp * ud + cpd * u, 2.0 * (cpd * ud))
            }
        }
    }

    /// The non-zero columns ∂r_P/∂q_i of a marker, visited as (i, column):
    /// ∂r_P/∂(r0, u) = [I  C(r̄_P + X_P y)] times T for the basis, A X_P for the modes.
    fn mk_columns(
        &self,
        mk: &PlanarMarker,
        q: &DVector<f64>,
        mut visit: impl FnMut(usize, Vector2<f64>),
    ) {
        let PlanarMarker::Body { body, rbar, node } = *mk else {
            return;
        };
        let b = &self.bodies[body];
        let x = nalgebra::Vector4::from_fn(|i, _| b.slots[i].get(q));
        let f = b.t * x;
        let u = Vector2::new(f[2], f[3]);
        let mut p = rbar;
        let flex = match (node, &b.flex_ws) {
            (Some(node), Some(fw)) => {
                let (tx, ty) = fw.trans_rows(node);
                for j in 0..b.n {
                    let yj = q[b.y_off + j];
                    p.x += tx[j] * yj;
                    p.y += ty[j] * yj;
                }
                Some((tx, ty))
            }
            _ => None,
        };
        let cp = c_of(&p);
        for k in 0..4 {
            if let Slot::Q(i) = b.slots[k] {
                let col = Vector2::new(b.t[(0, k)], b.t[(1, k)])
                    + cp * Vector2::new(b.t[(2, k)], b.t[(3, k)]);
                visit(i, col);
            }
        }
        if let Some((tx, ty)) = flex {
            let eu = e_mat() * u;
            for j in 0..b.n {
                visit(b.y_off + j, u * tx[j] + eu * ty[j]);
            }
        }
    }

    /// Slide (r_P2 − r_P1) · d₁ of a prismatic joint.
    fn slide(
        &self,
        p1: &PlanarMarker,
        p2: &PlanarMarker,
        d1: &Dir,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> f64 {
        let (r1, _, _) = self.mk_state(p1, q, qd);
        let (r2, _, _) = self.mk_state(p2, q, qd);
        let (d, _, _) = self.direction(d1, q, qd);
        (r2 - r1).dot(&d)
    }

    /// Markers and sliding direction of a prismatic joint: d₁ is fixed in body 1 (at its
    /// marker's node on a flexible body) and equals the unit axis at q0.
    #[allow(clippy::too_many_arguments)]
    fn prismatic_parts(
        &self,
        j: &flexmbd_model::Joint,
        axis: &flexmbd_model::V3,
        mk_of: &impl Fn(&str, &str, &[Body2]) -> PlanarMarker,
        dir_of: &impl Fn(&str, &str, &[Body2]) -> Dir,
        q0: &DVector<f64>,
        file: &str,
    ) -> Result<(PlanarMarker, PlanarMarker, Dir), ModelError> {
        let a = Vector2::new(axis.0[0], axis.0[1]);
        let norm = a.norm();
        if !norm.is_finite() || norm <= 1e-12 || axis.0[2].abs() > 1e-9 * norm {
            return Err(ModelError::Invalid {
                file: file.to_string(),
                error: flexmbd_core::InvalidValue::new(
                    format!("joints[{}].kind.Prismatic.axis", j.name),
                    format!("{:?}", axis.0),
                    "a planar sliding axis must be a non-zero vector in the x–y plane",
                ),
            });
        }
        let a = a / a.norm();
        let p1 = mk_of(&j.body1, &j.marker1, &self.bodies);
        let p2 = mk_of(&j.body2, &j.marker2, &self.bodies);
        let mut d1 = dir_of(&j.body1, &j.marker1, &self.bodies);
        // C(ā) d_x(q0) = a  ⇒  ā = (a · d_x, a · E d_x) / |d_x|².
        let (dx, _, _) = self.direction(&d1, q0, &DVector::zeros(q0.len()));
        let edx = e_mat() * dx;
        d1.abar = Vector2::new(a.dot(&dx), a.dot(&edx)) / dx.norm_squared();
        Ok((p1, p2, d1))
    }

    fn frame_rotation(&self, bi: usize, q: &DVector<f64>) -> Matrix2<f64> {
        let z = DVector::zeros(q.len());
        let (_, u, _, _) = self.frame(&self.bodies[bi], q, &z);
        let u = u / u.norm();
        Matrix2::new(u.x, -u.y, u.y, u.x)
    }
}

fn planar_axis(a: Axis, name: &str) -> Result<usize, ModelError> {
    match a {
        Axis::X => Ok(0),
        Axis::Y => Ok(1),
        Axis::Z => Err(ModelError::Unsupported(format!(
            "sensor `{name}`: a planar scene has no z component"
        ))),
    }
}

impl Body2 {
    /// Rotation row X^r_z of a node (1 × n).
    fn rot_row(&self, node: usize) -> &[f64] {
        self.flex_ws.as_ref().map_or(&[], |f| f.rot_row(node))
    }

    /// Node rotation θ = X^r_z y and its rate.
    fn node_rotation(&self, node: usize, q: &DVector<f64>, qd: &DVector<f64>) -> (f64, f64) {
        let r = self.rot_row(node);
        let mut th = 0.0;
        let mut thd = 0.0;
        for j in 0..self.n {
            th += r[j] * q[self.y_off + j];
            thd += r[j] * qd[self.y_off + j];
        }
        (th, thd)
    }

    /// Local (body-frame) position r̄_P + X_P y of a marker (FS0: plus the node's
    /// foreshortening), and its rate.
    fn local_point(
        &self,
        rbar: Vector2<f64>,
        node: Option<usize>,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector2<f64>, Vector2<f64>) {
        match (node, &self.flex_ws) {
            (Some(node), Some(f)) => {
                let (tx, ty) = f.trans_rows(node);
                let (mut p, mut pd) = (rbar, Vector2::zeros());
                for j in 0..self.n {
                    let (yj, ydj) = (q[self.y_off + j], qd[self.y_off + j]);
                    p.x += tx[j] * yj;
                    p.y += ty[j] * yj;
                    pd.x += tx[j] * ydj;
                    pd.y += ty[j] * ydj;
                }
                // FS0 (docs/methods.md §6.3): the node's axial shift −½ ē₁ yᵀF y and its rate.
                let ys = self.y_off..self.y_off + self.n;
                let (y, yd) = (&q.as_slice()[ys.clone()], &qd.as_slice()[ys]);
                if let Some(sh) = self.body.node_foreshortening(node, y, yd) {
                    p += sh.position.xy();
                    pd += sh.velocity.xy();
                }
                (p, pd)
            }
            _ => (rbar, Vector2::zeros()),
        }
    }
}

impl flexmbd_core::Formulation for Planar {
    fn n_coordinates(&self) -> usize {
        self.n
    }
    fn n_constraints(&self) -> usize {
        self.m
    }
    fn initial_guess(&self, q: &mut DVector<f64>, qd: &mut DVector<f64>) {
        q.copy_from(&self.q0);
        qd.copy_from(&self.qd0);
    }
    fn specified_coordinates(&self) -> &[usize] {
        &self.held
    }
    fn evaluate(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        req: Request,
        out: &mut SystemTerms,
    ) {
        if req.dynamics {
            self.dynamics(q, qd, req.tangents, out);
        }
        if req.constraints || req.jacobian || req.accel_term {
            self.constraints(t, q, qd, req, out);
        }
    }
    fn constant_mass(&self) -> bool {
        // Natural coordinates: a rigid body's mass matrix is constant.
        self.bodies.iter().all(|b| b.n == 0)
    }
    fn constant_tangents(&self) -> bool {
        // Rigid bodies and linear elasticity: K = K_ff and C = C_ff blocks only; spring
        // tangents turn with the spring's direction.
        self.force_elements.is_empty()
            && self
                .bodies
                .iter()
                .all(|b| b.body.elastic_model().is_linear())
    }
    fn symmetric_tangent(&self) -> bool {
        self.bodies
            .iter()
            .all(|b| b.body.elastic_model().is_symmetric())
    }
    fn sensor_names(&self) -> &[String] {
        &self.sensor_names
    }
    fn sensors(&mut self, _t: f64, q: &DVector<f64>, qd: &DVector<f64>, out: &mut [f64]) {
        for k in 0..self.sensors.len() {
            out[k] = match &self.sensors[k] {
                Sensor2::Position {
                    body,
                    marker,
                    axis,
                    frame,
                } => {
                    let (p, _) = self.marker_state(*body, *marker, q, qd);
                    match frame {
                        None => p[*axis],
                        Some(fb) => {
                            let z = DVector::zeros(q.len());
                            let (r0, _, _, _) = self.frame(&self.bodies[*fb], q, &z);
                            (self.frame_rotation(*fb, q).transpose() * (p - r0))[*axis]
                        }
                    }
                }
                Sensor2::Velocity {
                    body,
                    marker,
                    axis,
                    frame,
                } => {
                    let (_, v) = self.marker_state(*body, *marker, q, qd);
                    match frame {
                        None => v[*axis],
                        Some(fb) => (self.frame_rotation(*fb, q).transpose() * v)[*axis],
                    }
                }
                Sensor2::Joint { d1, d2, phi0, .. } => {
                    let a = self.angle(d1, d2, q) - phi0;
                    let Sensor2::Joint { last, turns, .. } = &mut self.sensors[k] else {
                        unreachable!()
                    };
                    let tau = std::f64::consts::TAU;
                    let mut v = a + *turns * tau;
                    while v - *last > std::f64::consts::PI {
                        *turns -= 1.0;
                        v -= tau;
                    }
                    while v - *last < -std::f64::consts::PI {
                        *turns += 1.0;
                        v += tau;
                    }
                    *last = v;
                    v
                }
                Sensor2::Slide { p1, p2, d1, s0 } => self.slide(p1, p2, d1, q, qd) - s0,
                Sensor2::Modal { q: idx } => idx.map_or(0.0, |i| q[i]),
                Sensor2::Energy => self.energy(q, qd),
            };
        }
    }
}

impl Planar {
    /// Scatter a body's local terms (basis order, then modes) into the system.
    fn scatter(&mut self, bi: usize, nl: usize, out: &mut SystemTerms) {
        let b = &self.bodies[bi];
        for k in 0..4 {
            self.local_idx[k] = match b.slots[k] {
                Slot::Q(i) => Some(i),
                Slot::Fixed(_) => None,
            };
        }
        for j in 0..b.n {
            self.local_idx[4 + j] = Some(b.y_off + j);
        }
        for c in 0..nl {
            let Some(qc) = self.local_idx[c] else {
                continue;
            };
            out.forces[qc] += self.local_q[c];
            for r in 0..nl {
                if let Some(qr) = self.local_idx[r] {
                    out.mass[(qr, qc)] += self.local_m[(r, c)];
                }
            }
        }
    }

    fn dynamics(
        &mut self,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        tangents: bool,
        out: &mut SystemTerms,
    ) {
        // Rigid bodies: their constant M and gravity, assembled once at compile time.
        out.mass
            .as_mut_slice()
            .copy_from_slice(self.rigid_mass.as_slice());
        out.forces
            .as_mut_slice()
            .copy_from_slice(self.rigid_forces.as_slice());
        for bi in 0..self.bodies.len() {
            let nl = 4 + self.bodies[bi].n;
            if self.bodies[bi].n == 0 {
                continue;
            }
            let (r0, u, r0d, ud) = self.frame(&self.bodies[bi], q, qd);
            let b = &mut self.bodies[bi];
            let ws = b.flex_ws.as_mut().expect("flexible body has a workspace");
            let (o, nb) = (b.y_off, b.n);
            ws.evaluate(
                &b.body,
                self.method,
                r0,
                u,
                r0d,
                ud,
                &q.as_slice()[o..o + nb],
                &qd.as_slice()[o..o + nb],
                self.gravity,
                &b.t,
            );
            self.local_m.view_mut((0, 0), (nl, nl)).copy_from(&ws.m_b);
            self.local_q.rows_mut(0, nl).copy_from(&ws.q_b);
            self.scatter(bi, nl, out);
            if tangents {
                let b = &self.bodies[bi];
                let (o, nb) = (b.y_off, b.n);
                let (y, yd) = (&q.as_slice()[o..o + nb], &qd.as_slice()[o..o + nb]);
                b.body.add_elastic_tangents(
                    y,
                    yd,
                    1.0,
                    0.0,
                    out.stiffness.view_mut((o, o), (nb, nb)),
                );
                b.body.add_elastic_tangents(
                    y,
                    yd,
                    0.0,
                    1.0,
                    out.damping.view_mut((o, o), (nb, nb)),
                );
            }
        }
        if !self.force_elements.is_empty() {
            let mut force_elements = std::mem::take(&mut self.force_elements);
            force_elements.add_forces(self, q, qd, tangents, out);
            self.force_elements = force_elements;
        }
    }

    fn constraints(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        req: Request,
        out: &mut SystemTerms,
    ) {
        let mut row = 0;
        for ci in 0..self.cons.len() {
            match &self.cons[ci] {
                Con::Distance { a, b, l2 } => {
                    let pa = Vector2::new(a.x.get(q), a.y.get(q));
                    let pb = Vector2::new(b.x.get(q), b.y.get(q));
                    let d = pb - pa;
                    if req.constraints {
                        out.phi[row] = d.norm_squared() - l2;
                    }
                    if req.jacobian {
                        for (slot, v) in [
                            (a.x, -2.0 * d.x),
                            (a.y, -2.0 * d.y),
                            (b.x, 2.0 * d.x),
                            (b.y, 2.0 * d.y),
                        ] {
                            if let Slot::Q(i) = slot {
                                out.phi_q[(row, i)] += v;
                            }
                        }
                    }
                    if req.accel_term {
                        let dd =
                            Vector2::new(b.x.rate(qd) - a.x.rate(qd), b.y.rate(qd) - a.y.rate(qd));
                        out.accel_term[row] = 2.0 * dd.norm_squared();
                    }
                    row += 1;
                }
                Con::Unit { u } => {
                    let v = Vector2::new(u[0].get(q), u[1].get(q));
                    if req.constraints {
                        out.phi[row] = v.norm_squared() - 1.0;
                    }
                    if req.jacobian {
                        for (slot, x) in [(u[0], v.x), (u[1], v.y)] {
                            if let Slot::Q(i) = slot {
                                out.phi_q[(row, i)] += 2.0 * x;
                            }
                        }
                    }
                    if req.accel_term {
                        let vd = Vector2::new(u[0].rate(qd), u[1].rate(qd));
                        out.accel_term[row] = 2.0 * vd.norm_squared();
                    }
                    row += 1;
                }
                Con::PointOnBody { mk, point } => {
                    let (r, _, bias) = self.mk_state(mk, q, qd);
                    if req.constraints {
                        let target = Vector2::new(point.x.get(q), point.y.get(q));
                        out.phi[row] = r.x - target.x;
                        out.phi[row + 1] = r.y - target.y;
                    }
                    if req.jacobian {
                        let phi_q = &mut out.phi_q;
                        self.mk_columns(mk, q, |i, col| {
                            phi_q[(row, i)] += col.x;
                            phi_q[(row + 1, i)] += col.y;
                        });
                        for (a, slot) in [point.x, point.y].into_iter().enumerate() {
                            if let Slot::Q(i) = slot {
                                out.phi_q[(row + a, i)] -= 1.0;
                            }
                        }
                    }
                    if req.accel_term {
                        out.accel_term[row] = bias.x;
                        out.accel_term[row + 1] = bias.y;
                    }
                    row += 2;
                }
                Con::Slide { p1, p2, d1, along } => {
                    let (r1, v1, b1) = self.mk_state(p1, q, qd);
                    let (r2, v2, b2) = self.mk_state(p2, q, qd);
                    let (d, dd, db) = self.direction(d1, q, qd);
                    let (x, xd, xb) = (r2 - r1, v2 - v1, b2 - b1);
                    let e = e_mat();
                    // Φ = x × d (∂/∂x = −E d, ∂/∂d = E x), or x · d − s₀ − s(t).
                    let (phi, w_x, w_d, phi_t, bias) = match along {
                        None => (
                            cross(&x, &d),
                            -(e * d),
                            e * x,
                            0.0,
                            cross(&xb, &d) + 2.0 * cross(&xd, &dd) + cross(&x, &db),
                        ),
                        Some((s0, law)) => {
                            let (sv, svd, svdd) = law.eval(t);
                            (
                                x.dot(&d) - s0 - sv,
                                d,
                                x,
                                -svd,
                                xb.dot(&d) + 2.0 * xd.dot(&dd) + x.dot(&db) - svdd,
                            )
                        }
                    };
                    if req.constraints {
                        out.phi[row] = phi;
                    }
                    if req.jacobian {
                        let phi_q = &mut out.phi_q;
                        self.mk_columns(p2, q, |i, col| phi_q[(row, i)] += w_x.dot(&col));
                        self.mk_columns(p1, q, |i, col| phi_q[(row, i)] -= w_x.dot(&col));
                        let d1c = *d1;
                        self.add_direction_jacobian(&d1c, &w_d, q, &mut out.phi_q, row);
                        out.phi_t[row] = phi_t;
                    }
                    if req.accel_term {
                        out.accel_term[row] = bias;
                    }
                    row += 1;
                }
                Con::Angle { d1, d2, phi0, law } => {
                    let (th_l, thd, thdd) = law.eval(t);
                    let th = phi0 + th_l;
                    let (s, c) = th.sin_cos();
                    let (a, ad, a_bias) = self.direction(d1, q, qd);
                    let (bv, bd, b_bias) = self.direction(d2, q, qd);
                    let sigma = cross(&a, &bv);
                    let kappa = a.dot(&bv);
                    if req.constraints {
                        out.phi[row] = sigma * c - kappa * s;
                    }
                    if req.jacobian {
                        // ∂σ/∂a = −E b, ∂σ/∂b = E a; ∂κ/∂a = b, ∂κ/∂b = a.
                        let e = e_mat();
                        let wa = -(e * bv) * c - bv * s;
                        let wb = (e * a) * c - a * s;
                        let (d1c, d2c) = (*d1, *d2);
                        self.add_direction_jacobian(&d1c, &wa, q, &mut out.phi_q, row);
                        self.add_direction_jacobian(&d2c, &wb, q, &mut out.phi_q, row);
                        out.phi_t[row] = -thd * (sigma * s + kappa * c);
                    }
                    if req.accel_term {
                        let sigma_d = cross(&ad, &bv) + cross(&a, &bd);
                        let kappa_d = ad.dot(&bv) + a.dot(&bd);
                        let sigma_b =
                            2.0 * cross(&ad, &bd) + cross(&a_bias, &bv) + cross(&a, &b_bias);
                        let kappa_b = 2.0 * ad.dot(&bd) + a_bias.dot(&bv) + a.dot(&b_bias);
                        out.accel_term[row] = sigma_b * c
                            - kappa_b * s
                            - 2.0 * thd * (sigma_d * s + kappa_d * c)
                            - thdd * (sigma * s + kappa * c)
                            - thd * thd * (sigma * c - kappa * s);
                    }
                    row += 1;
                }
            }
        }
    }

    /// Total mechanical energy: kinetic + gravity + elastic.
    fn energy(&mut self, q: &DVector<f64>, qd: &DVector<f64>) -> f64 {
        let mut e = 0.0;
        for bi in 0..self.bodies.len() {
            let b = &self.bodies[bi];
            let nl = 4 + b.n;
            let (r0, u, r0d, ud) = self.frame(b, q, qd);
            let xd = nalgebra::Vector4::from_fn(|i, _| b.slots[i].rate(qd));
            if b.n == 0 {
                e += 0.5 * xd.dot(&(b.m_const * xd));
                // −gᵀ(m r0 + A m̄)
                let mb = b.body.first_moment();
                e -= self
                    .gravity
                    .dot(&(r0 * b.body.mass() + c_of(&Vector2::new(mb.x, mb.y)) * u));
                continue;
            }
            let b = &mut self.bodies[bi];
            let ws = b.flex_ws.as_mut().expect("workspace");
            let (o, nb) = (b.y_off, b.n);
            let (y, yd) = (&q.as_slice()[o..o + nb], &qd.as_slice()[o..o + nb]);
            ws.evaluate(
                &b.body,
                self.method,
                r0,
                u,
                r0d,
                ud,
                y,
                yd,
                self.gravity,
                &b.t,
            );
            // ½ vᵀ M_b v with v = (ẋ_b, ẏ).
            let v = |i: usize| if i < 4 { xd[i] } else { yd[i - 4] };
            let mut kin = 0.0;
            for r in 0..nl {
                for c in 0..nl {
                    kin += v(r) * ws.m_b[(r, c)] * v(c);
                }
            }
            e += 0.5 * kin;
            e += ws.potential(&b.body, r0, u, y, self.gravity);
        }
        e + self.force_elements.potential_energy(self, q, qd)
    }
}

impl MarkerKinematics for Planar {
    type Marker = PlanarMarker;

    fn marker_state(
        &self,
        marker: &PlanarMarker,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let (r, v, _) = self.mk_state(marker, q, qd);
        (Vector3::new(r.x, r.y, 0.0), Vector3::new(v.x, v.y, 0.0))
    }

    fn marker_jacobian(
        &mut self,
        marker: &PlanarMarker,
        q: &DVector<f64>,
        visit: &mut dyn FnMut(usize, Vector3<f64>),
    ) {
        self.mk_columns(marker, q, |i, c| visit(i, Vector3::new(c.x, c.y, 0.0)));
    }
}
