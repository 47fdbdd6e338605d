//! The spatial (3D) natural-coordinate formulation (docs/methods.md §3, §2.5–§2.6).
//!
//! **Coordinates (the choice).** Every body has its own frame coordinates
//! `q_b = {r0; u; v; w; y}`: the origin, the three body axes `A = [u v w]` in ground
//! components, and the modal coordinates of a flexible body (12 + n per body, n = 0 for
//! rigid bodies and for beams run rigid). Six orthonormality constraints per body
//! (`u·u = v·v = w·w = 1`, `u·v = v·w = w·u = 0`) leave 6 + n freedoms. This is the same
//! set for rigid and flexible bodies, so the body crate's natural-set inertia
//! (`inertia_natural`, both routes) and gravity (`gravity_natural`) apply unchanged; a
//! rigid body's 12 × 12 mass matrix and gravity force are constant and computed once at
//! compile time. Points and vectors are **not** shared between bodies (the classical
//! fully-Cartesian economy): every joint is a set of constraint equations between the
//! bodies' markers. It costs more coordinates (12 per rigid body against 6–9 with shared
//! points) but treats every joint, body and marker alike; the counts are below.
//!
//! **Body vectors.** A joint uses body points and body-fixed directions, both of the form
//!
//! ```text
//! x(q) = δ r0 + A (x̄ + V y),  δ = 1 for a point, 0 for a direction,
//! ```
//!
//! bilinear in (A, y) (docs/methods.md §3.3): a marker point on a flexible body sits on an FE
//! node P, `x̄ = r̄_P`, `V = X_P` (translation rows); a direction ā at a node P turns with
//! the node, `a_P = A (I + θ̃_P) ā` with `θ̄_P = X^r_P y`, i.e. `V = [X^r_j × ā]_j`. On a
//! rigid body V is empty. The Jacobian is `[δ I  x̃_1 I  x̃_2 I  x̃_3 I  A V]` with
//! `x̃ = x̄ + V y`, the velocity `δ ṙ0 + Ȧ x̃ + A V ẏ` and the bias (the second derivative
//! at q̈ = 0) `2 Ȧ V ẏ`. Ground markers and ground directions are constants.
//!
//! **Joints** (body 1 carries the joint axis a; `n1 ⟂ n2 ⟂ a` are fixed unit vectors built
//! from the axis at t = 0, the same global vectors fixed in both bodies):
//!
//! | joint | equations | rows |
//! |---|---|---|
//! | spherical | `r_P2 − r_P1 = 0` | 3 |
//! | revolute | point + `a¹·n²₁ = 0`, `a¹·n²₂ = 0` | 5 |
//! | universal | point + `a¹₁·a²₂ = 0` (cross arms) | 4 |
//! | cylindrical | `a¹·n²₁ = a¹·n²₂ = 0`, `(r_P2 − r_P1)·n¹₁ = c₁`, `(r_P2 − r_P1)·n¹₂ = c₂` | 4 |
//! | prismatic | cylindrical + `n¹₁·n²₂ = 0` (φ₀ = 90°, docs/methods.md §3.2 correction) | 5 |
//! | rigid | point + `e¹_x·e²_y = e¹_y·e²_z = e¹_z·e²_x = 0` | 6 |
//!
//! (superscripts: the body the vector is fixed in; `c₁, c₂` are the values at t = 0, so a
//! sliding joint's markers need not coincide). Two free bodies joined by one of these
//! have mobility 9, 7, 8, 8, 7, 6 (tested by the rank of Φ_q).
//!
//! **Drivers.** A revolute joint is driven by `Φ = σ cos θ(t) − κ sin θ(t) = sin(φ − θ)`
//! with `σ = (p¹ × p²)·a¹`, `κ = p¹·p²`, `p = n₁` fixed in each body (docs/methods.md §3.2);
//! a prismatic joint by `(r_P2 − r_P1)·a¹ = s₀ + s(t)`. Other drivers are refused.
//!
//! **Coordinate counts.** n = Σ (12 + n_b); m = 6 · (bodies) + Σ joint rows + drivers.
//! The rigid 3D double pendulum (spherical + revolute): 24 coordinates, 20 constraints.
//! The flexible 3D pendulum (6 modes, spherical): 18 and 9. The double four-bar written
//! in 3D (5 bodies, 7 revolutes about z): 60 and 65 (Φ_q rank 59: each closed planar loop
//! of revolutes brings 3 redundant out-of-plane rows, which ALI3-P tolerates).
//!
//! **Sensors**, as the planar code reports them: a marker's position and velocity in
//! ground components or in a body frame (`Aᵀ (r − r0)`, `Aᵀ ṙ`), the angle of a revolute
//! joint (`atan2(σ, κ)`, unwrapped, relative to t = 0) or the slide of a prismatic joint,
//! a modal coordinate, and the total energy (kinetic `½ q̇ᵀ M q̇`, gravity, elastic).
//!
//! **Foreshortening (FS0, methods.md §6.3).** A foreshortened beam's inertia comes from the body
//! crate like any other (either route); a point term at an FE node of such a body adds the node's
//! axial shift −½ ē₁ yᵀF y to `x̃`, its rate −ē₁ (F y)·ẏ to the velocity, `A (−ē₁ ẏᵀF ẏ)` to the
//! bias and −A ē₁ (F y)ᵀ to the y columns of the Jacobian (joints sit at the root, where F = 0;
//! the tip sensors see the shift).
//!
//! **Allocation.** `evaluate` allocates nothing: every workspace is sized at compile time.

use flexmbd_body::{FlexibleBody, InertiaMethod, NaturalState, NaturalWorkspace};
use flexmbd_core::{Dim, MarkerKinematics, Request, SystemTerms};
use flexmbd_model::force_elements::ForceElements;
use flexmbd_model::{
    Axis, FormulationKind, GROUND, JointKind, MarkerId, ModelError, MotionLaw, PreparedScene,
    Scene, SensorKind,
};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// Scratch of one flexible body, sized once.
struct FlexWs {
    ws: NaturalWorkspace,
    gravity: Vec<f64>,
    elastic: Vec<f64>,
    /// Scratch mass matrix and forces for the energy sensor.
    m: DMatrix<f64>,
    qv: DVector<f64>,
}

struct Body3 {
    body: FlexibleBody,
    /// Index of r0 in q; u, v, w follow, then y at `off + 12`.
    off: usize,
    n: usize,
    /// Rigid bodies: the constant 12 × 12 mass matrix and gravity force.
    m_const: DMatrix<f64>,
    q_const: DVector<f64>,
    /// Markers: undeformed body position and FE node (flexible bodies).
    markers: Vec<(Vector3<f64>, Option<usize>)>,
    flex: Option<FlexWs>,
}

/// A body point or body-fixed direction `x = δ r0 + A (x̄ + V y)`, or a ground constant.
#[derive(Clone, Debug)]
pub struct Term {
    /// `None`: a ground constant `xbar`.
    body: Option<usize>,
    /// δ = 1 (point) or 0 (direction).
    point: bool,
    xbar: Vector3<f64>,
    /// V, 3 × n row-major (empty for rigid bodies).
    rows: Vec<f64>,
    /// FS0 (docs/methods.md §6.3): the FE node of a point on a foreshortened body, whose axial
    /// shift −½ ē₁ yᵀF y joins x̄ + V y.
    fs_node: Option<usize>,
}

/// Value, rate and bias of a term, and its local vector x̃ = x̄ + V y (for the Jacobian).
#[derive(Clone, Copy, Debug, Default)]
struct TermEval {
    x: Vector3<f64>,
    xd: Vector3<f64>,
    bias: Vector3<f64>,
    local: Vector3<f64>,
}

#[inline]
fn v3(s: &[f64], i: usize) -> Vector3<f64> {
    Vector3::new(s[i], s[i + 1], s[i + 2])
}

#[inline]
fn frame_of(q: &[f64], off: usize) -> (Vector3<f64>, Matrix3<f64>) {
    (
        v3(q, off),
        Matrix3::from_columns(&[v3(q, off + 3), v3(q, off + 6), v3(q, off + 9)]),
    )
}

impl Term {
    fn eval(&self, bodies: &[Body3], q: &DVector<f64>, qd: &DVector<f64>) -> TermEval {
        let Some(bi) = self.body else {
            return TermEval {
                x: self.xbar,
                local: self.xbar,
                ..Default::default()
            };
        };
        let b = &bodies[bi];
        let (q, qd) = (q.as_slice(), qd.as_slice());
        let (r0, a) = frame_of(q, b.off);
        let (r0d, ad) = frame_of(qd, b.off);
        let mut local = self.xbar;
        let mut vyd = Vector3::zeros();
        let n = b.n;
        if !self.rows.is_empty() {
            let (y, yd) = (
                &q[b.off + 12..b.off + 12 + n],
                &qd[b.off + 12..b.off + 12 + n],
            );
            for c in 0..3 {
                let r = &self.rows[c * n..(c + 1) * n];
                for j in 0..n {
                    local[c] += r[j] * y[j];
                    vyd[c] += r[j] * yd[j];
                }
            }
        }
        // FS0: x̃ gains −½ ē₁ yᵀF y, its rate −ē₁ (F y)·ẏ and the bias A (−ē₁ ẏᵀF ẏ).
        let mut fs_bias = Vector3::zeros();
        if let Some(node) = self.fs_node {
            let (y, yd) = (
                &q[b.off + 12..b.off + 12 + n],
                &qd[b.off + 12..b.off + 12 + n],
            );
            if let Some(sh) = b.body.node_foreshortening(node, y, yd) {
                local += sh.position;
                vyd += sh.velocity;
                fs_bias = sh.bias;
            }
        }
        let d = if self.point { 1.0 } else { 0.0 };
        TermEval {
            x: d * r0 + a * local,
            xd: d * r0d + ad * local + a * vyd,
            bias: 2.0 * (ad * vyd) + a * fs_bias,
            local,
        }
    }

    /// Add `wᵀ ∂x/∂q` to `row` of Φ_q.
    fn add_jacobian(
        &self,
        bodies: &[Body3],
        ev: &TermEval,
        w: &Vector3<f64>,
        q: &DVector<f64>,
        phi_q: &mut DMatrix<f64>,
        row: usize,
    ) {
        let Some(bi) = self.body else { return };
        let b = &bodies[bi];
        let o = b.off;
        if self.point {
            for i in 0..3 {
                phi_q[(row, o + i)] += w[i];
            }
        }
        for c in 0..3 {
            for i in 0..3 {
                phi_q[(row, o + 3 + 3 * c + i)] += ev.local[c] * w[i];
            }
        }
        if !self.rows.is_empty() {
            let (_, a) = frame_of(q.as_slice(), o);
            let aw = a.tr_mul(w);
            let n = b.n;
            for j in 0..n {
                phi_q[(row, o + 12 + j)] +=
                    aw.x * self.rows[j] + aw.y * self.rows[n + j] + aw.z * self.rows[2 * n + j];
            }
            // FS0: the shift's Jacobian −ē₁ (F y)ᵀ.
            if let Some(node) = self.fs_node {
                let y = &q.as_slice()[o + 12..o + 12 + n];
                for j in 0..n {
                    let c = b.body.node_foreshortening_column(node, y, j);
                    phi_q[(row, o + 12 + j)] += aw.dot(&c);
                }
            }
        }
    }
}

enum Con3 {
    /// The six orthonormality conditions of the body at `off`.
    Ortho { off: usize },
    /// a − b = 0 (3 rows).
    Coincide { a: Term, b: Term },
    /// (x − x2)·z − c0 − s(t) = 0 (1 row).
    Dot {
        x: Term,
        x2: Option<Term>,
        z: Term,
        c0: f64,
        law: Option<MotionLaw>,
    },
    /// σ cos θ − κ sin θ = 0, σ = (p1 × p2)·a, κ = p1·p2, θ = φ0 + θ(t) (1 row).
    Angle {
        p1: Term,
        p2: Term,
        a: Term,
        phi0: f64,
        law: MotionLaw,
    },
}

impl Con3 {
    fn rows(&self) -> usize {
        match self {
            Con3::Ortho { .. } => 6,
            Con3::Coincide { .. } => 3,
            _ => 1,
        }
    }
}

enum Sensor3 {
    Position {
        term: Term,
        axis: usize,
        frame: Option<usize>,
    },
    Velocity {
        term: Term,
        axis: usize,
        frame: Option<usize>,
    },
    Angle {
        p1: Term,
        p2: Term,
        a: Term,
        phi0: f64,
        last: f64,
        turns: f64,
    },
    Slide {
        x: Term,
        x2: Term,
        z: Term,
        s0: f64,
    },
    Modal {
        q: usize,
    },
    Energy,
}

/// The compiled spatial scene.
pub struct Spatial {
    n: usize,
    m: usize,
    gravity: Vector3<f64>,
    bodies: Vec<Body3>,
    cons: Vec<Con3>,
    q0: DVector<f64>,
    qd0: DVector<f64>,
    held: Vec<usize>,
    sensor_names: Vec<String>,
    sensors: Vec<Sensor3>,
    method: InertiaMethod,
    force_elements: ForceElements<Term>,
    /// Zero rates (n), to evaluate a term's position alone.
    zero_rates: DVector<f64>,
}

fn unsupported(what: String) -> ModelError {
    ModelError::Unsupported(what)
}

/// Two unit vectors n1, n2 with (n1, n2, a) right-handed orthonormal.
fn perpendiculars(a: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let a = a.normalize();
    let k = a.iamin();
    let mut e = Vector3::zeros();
    e[k] = 1.0;
    let n1 = e.cross(&a).normalize();
    let n2 = a.cross(&n1);
    (n1, n2)
}

fn triple_angle(p1: &Vector3<f64>, p2: &Vector3<f64>, a: &Vector3<f64>) -> f64 {
    p1.cross(p2).dot(a).atan2(p1.dot(p2))
}

/// Compile-time lookups: marker terms and initial frames.
struct Lookup<'a> {
    scene: &'a Scene,
    bodies: &'a [Body3],
    frames: Vec<(Vector3<f64>, Matrix3<f64>)>,
    node_rot: Vec<Vec<Option<DMatrix<f64>>>>,
}

impl Lookup<'_> {
    fn body(&self, name: &str) -> Option<usize> {
        if name == GROUND {
            None
        } else {
            Some(
                self.scene
                    .bodies
                    .iter()
                    .position(|b| b.name == name)
                    .expect("validated"),
            )
        }
    }
    fn marker(&self, body: Option<usize>, marker: &str) -> usize {
        match body {
            None => self.scene.ground.iter().position(|m| m.name == marker),
            Some(bi) => self.scene.bodies[bi]
                .markers
                .iter()
                .position(|m| m.name == marker),
        }
        .expect("validated")
    }
    /// The global position of a marker at t = 0 (undeformed).
    fn position0(&self, t: &Term) -> Vector3<f64> {
        match t.body {
            None => t.xbar,
            Some(bi) => {
                let (o, a) = self.frames[bi];
                o + a * t.xbar
            }
        }
    }
    /// A direction fixed in the marker's body (at its node on a flexible body), given in
    /// ground components at t = 0.
    fn direction(&self, body: &str, marker: &str, global: &Vector3<f64>) -> Term {
        let bi = self.body(body);
        let g = global.normalize();
        match bi {
            None => Term {
                body: None,
                point: false,
                xbar: g,
                rows: Vec::new(),
                fs_node: None,
            },
            Some(bi) => {
                let k = self.marker(Some(bi), marker);
                let abar = self.frames[bi].1.tr_mul(&g);
                let rows = match &self.node_rot[bi][k] {
                    Some(xr) => {
                        let n = xr.ncols();
                        let mut rows = vec![0.0; 3 * n];
                        for j in 0..n {
                            let th = Vector3::new(xr[(0, j)], xr[(1, j)], xr[(2, j)]);
                            let c = th.cross(&abar);
                            for a in 0..3 {
                                rows[a * n + j] = c[a];
                            }
                        }
                        rows
                    }
                    None => Vec::new(),
                };
                Term {
                    body: Some(bi),
                    point: false,
                    xbar: abar,
                    rows,
                    fs_node: None,
                }
            }
        }
    }
}

impl Spatial {
    /// Compile a spatial scene.
    pub fn compile(prepared: &PreparedScene) -> Result<Spatial, ModelError> {
        let scene = prepared.scene();
        debug_assert_eq!(scene.solver.formulation, FormulationKind::Absolute);
        debug_assert_eq!(scene.dim, Dim::Spatial);
        let method = scene.solver.inertia;
        let mut n = 0usize;
        let mut q0 = Vec::new();
        let mut qd0 = Vec::new();
        let mut bodies = Vec::new();
        let mut frames = Vec::new();
        let mut node_rot = Vec::new();
        let mut node_trans = Vec::new();
        let g = scene.gravity.vec();
        for (b, prep) in scene.bodies.iter().zip(prepared.bodies()) {
            let body = prep.body.clone();
            let nm = if prep.flexible { body.n_modes() } else { 0 };
            debug_assert_eq!(nm, body.n_modes());
            let a0 = b.orientation.matrix();
            let o = b.origin.vec();
            frames.push((o, a0));
            let off = n;
            // q: r0, u, v, w, y; q̇: ṙ0, ω̃ A, 0.
            q0.extend(o.iter());
            let om = b.velocity.angular.vec();
            qd0.extend(b.velocity.linear.vec().iter());
            for c in 0..3 {
                let e = a0.column(c).into_owned();
                q0.extend(e.iter());
                qd0.extend(om.cross(&e).iter());
            }
            q0.extend((0..nm).map(|j| b.initial_modes.get(j).copied().unwrap_or(0.0)));
            qd0.extend(std::iter::repeat_n(0.0, nm));
            n += 12 + nm;
            let markers: Vec<(Vector3<f64>, Option<usize>)> = b
                .markers
                .iter()
                .zip(&prep.marker_nodes)
                .map(|(m, node)| (m.position.vec(), if nm > 0 { *node } else { None }))
                .collect();
            node_rot.push(
                markers
                    .iter()
                    .map(|(_, node)| node.map(|k| prep.reduced.nodes[k].rotation.clone()))
                    .collect::<Vec<_>>(),
            );
            node_trans.push(
                markers
                    .iter()
                    .map(|(_, node)| node.map(|k| prep.reduced.nodes[k].translation.clone()))
                    .collect::<Vec<_>>(),
            );
            let (mut m_const, mut q_const) = (DMatrix::zeros(0, 0), DVector::zeros(0));
            let flex = if nm > 0 {
                Some(FlexWs {
                    ws: body.natural_workspace(),
                    gravity: vec![0.0; 12 + nm],
                    elastic: vec![0.0; nm],
                    m: DMatrix::zeros(12 + nm, 12 + nm),
                    qv: DVector::zeros(12 + nm),
                })
            } else {
                // Constant M and gravity: any state will do (n = 0).
                m_const = DMatrix::zeros(12, 12);
                let mut qv = DVector::zeros(12);
                let (qs, qds) = (&q0[off..off + 12], &qd0[off..off + 12]);
                let st = NaturalState::from_coords(Dim::Spatial, qs, qds);
                let mut ws = body.natural_workspace();
                body.inertia_natural(&st, method, &mut ws, &mut m_const, &mut qv);
                let mut gv = vec![0.0; 12];
                body.gravity_natural(&st, &g, &mut gv);
                q_const = DVector::from_vec(gv);
                None
            };
            bodies.push(Body3 {
                body,
                off,
                n: nm,
                m_const,
                q_const,
                markers,
                flex,
            });
        }
        let mut cons: Vec<Con3> = bodies.iter().map(|b| Con3::Ortho { off: b.off }).collect();
        let lk = Lookup {
            scene,
            bodies: &bodies,
            frames,
            node_rot,
        };
        // Point terms with the node translation rows.
        let point_of = |bi: Option<usize>, k: usize| -> Term {
            match bi {
                None => Term {
                    body: None,
                    point: true,
                    xbar: scene.ground[k].position.vec(),
                    rows: Vec::new(),
                    fs_node: None,
                },
                Some(bi) => {
                    let b = &lk.bodies[bi];
                    let rows = match &node_trans[bi][k] {
                        Some(xt) => {
                            let nn = xt.ncols();
                            let mut rows = vec![0.0; 3 * nn];
                            for a in 0..3 {
                                for j in 0..nn {
                                    rows[a * nn + j] = xt[(a, j)];
                                }
                            }
                            rows
                        }
                        None => Vec::new(),
                    };
                    let fs_node = if b.body.has_foreshortening() && !rows.is_empty() {
                        b.markers[k].1
                    } else {
                        None
                    };
                    Term {
                        body: Some(bi),
                        point: true,
                        xbar: b.markers[k].0,
                        rows,
                        fs_node,
                    }
                }
            }
        };
        let point = |body: &str, marker: &str| -> Term {
            let bi = lk.body(body);
            point_of(bi, lk.marker(bi, marker))
        };
        let point_at = |id: MarkerId| point_of(id.body.map(|b| b.0), id.index);
        let force_markers: std::collections::HashMap<MarkerId, Term> = prepared
            .force_markers()
            .iter()
            .flat_map(|pair| [pair.first, pair.second])
            .map(|id| (id, point_at(id)))
            .collect();
        let joint_err = |j: &flexmbd_model::Joint, what: &str| -> ModelError {
            unsupported(format!("{}: joint `{}`: {what}", scene.origin, j.name))
        };
        for j in &scene.joints {
            let p1 = point(&j.body1, &j.marker1);
            let p2 = point(&j.body2, &j.marker2);
            let gap = lk.position0(&p2) - lk.position0(&p1);
            let coincide = |cons: &mut Vec<Con3>| -> Result<(), ModelError> {
                if gap.norm() > 1e-6 {
                    return Err(joint_err(
                        j,
                        &format!(
                            "markers `{}.{}` and `{}.{}` are {:.3e} m apart at t = 0; they must coincide",
                            j.body1,
                            j.marker1,
                            j.body2,
                            j.marker2,
                            gap.norm()
                        ),
                    ));
                }
                cons.push(Con3::Coincide {
                    a: p2.clone(),
                    b: p1.clone(),
                });
                Ok(())
            };
            let dir1 = |v: &Vector3<f64>| lk.direction(&j.body1, &j.marker1, v);
            let dir2 = |v: &Vector3<f64>| lk.direction(&j.body2, &j.marker2, v);
            let axis_of = |v: &flexmbd_model::V3| -> Result<Vector3<f64>, ModelError> {
                let a = v.vec();
                if !(a.norm() > 1e-12 && a.iter().all(|x| x.is_finite())) {
                    return Err(joint_err(j, "the axis must be a finite non-zero vector"));
                }
                Ok(a.normalize())
            };
            let perp = |x: Term, z: Term, cons: &mut Vec<Con3>| {
                cons.push(Con3::Dot {
                    x,
                    x2: None,
                    z,
                    c0: 0.0,
                    law: None,
                });
            };
            let driver: Vec<_> = scene.drivers.iter().filter(|d| d.joint == j.name).collect();
            if driver.len() > 1 {
                return Err(joint_err(j, "more than one driver names this joint"));
            }
            let driver = driver.first().map(|d| d.law.clone());
            match &j.kind {
                // A floating base: no equation.
                JointKind::Free => {}
                JointKind::Spherical => coincide(&mut cons)?,
                JointKind::Revolute { axis } => {
                    let Some(axis) = axis else {
                        return Err(joint_err(
                            j,
                            "a revolute joint of a 3D scene needs its axis (`Revolute(axis: Some((x, y, z)))`)",
                        ));
                    };
                    let a = axis_of(axis)?;
                    let (n1, n2) = perpendiculars(&a);
                    coincide(&mut cons)?;
                    perp(dir1(&a), dir2(&n1), &mut cons);
                    perp(dir1(&a), dir2(&n2), &mut cons);
                    if let Some(law) = driver {
                        cons.push(Con3::Angle {
                            p1: dir1(&n1),
                            p2: dir2(&n1),
                            a: dir1(&a),
                            phi0: 0.0,
                            law,
                        });
                    }
                }
                JointKind::Universal { axis1, axis2 } => {
                    let (a1, a2) = (axis_of(axis1)?, axis_of(axis2)?);
                    if a1.dot(&a2).abs() > 1e-6 {
                        return Err(joint_err(
                            j,
                            &format!(
                                "the cross arms must be perpendicular at t = 0 (cos = {:.3e})",
                                a1.dot(&a2)
                            ),
                        ));
                    }
                    coincide(&mut cons)?;
                    perp(dir1(&a1), dir2(&a2), &mut cons);
                }
                JointKind::Cylindrical { axis } | JointKind::Prismatic { axis } => {
                    let a = axis_of(axis)?;
                    let (n1, n2) = perpendiculars(&a);
                    perp(dir1(&a), dir2(&n1), &mut cons);
                    perp(dir1(&a), dir2(&n2), &mut cons);
                    for nk in [n1, n2] {
                        cons.push(Con3::Dot {
                            x: p2.clone(),
                            x2: Some(p1.clone()),
                            z: dir1(&nk),
                            c0: gap.dot(&nk),
                            law: None,
                        });
                    }
                    let prismatic = matches!(j.kind, JointKind::Prismatic { .. });
                    if prismatic {
                        perp(dir1(&n1), dir2(&n2), &mut cons);
                    }
                    match (driver, prismatic) {
                        (Some(law), true) => cons.push(Con3::Dot {
                            x: p2.clone(),
                            x2: Some(p1.clone()),
                            z: dir1(&a),
                            c0: gap.dot(&a),
                            law: Some(law),
                        }),
                        (Some(_), false) => {
                            return Err(joint_err(
                                j,
                                "a cylindrical joint cannot be driven (which coordinate?); drive a revolute or a prismatic joint",
                            ));
                        }
                        (None, _) => {}
                    }
                }
                JointKind::Rigid => {
                    coincide(&mut cons)?;
                    let e = Matrix3::<f64>::identity();
                    for (x, y) in [(0, 1), (1, 2), (2, 0)] {
                        let (ex, ey) = (e.column(x).into_owned(), e.column(y).into_owned());
                        perp(dir1(&ex), dir2(&ey), &mut cons);
                    }
                }
            }
            if driver_refused(&j.kind, scene, &j.name) {
                return Err(joint_err(
                    j,
                    "only revolute (angle) and prismatic (distance) joints can be driven",
                ));
            }
        }
        let m = cons.iter().map(Con3::rows).sum();
        let mut sensors = Vec::new();
        for s in &scene.sensors {
            let frame_of_name = |f: &Option<String>| f.as_deref().and_then(|f| lk.body(f));
            let sensor = match &s.kind {
                SensorKind::Position {
                    body,
                    marker,
                    component,
                    frame,
                } => Sensor3::Position {
                    term: point(body, marker),
                    axis: axis_index(*component),
                    frame: frame_of_name(frame),
                },
                SensorKind::Velocity {
                    body,
                    marker,
                    component,
                    frame,
                } => Sensor3::Velocity {
                    term: point(body, marker),
                    axis: axis_index(*component),
                    frame: frame_of_name(frame),
                },
                SensorKind::JointCoordinate { joint } => {
                    let j = scene
                        .joints
                        .iter()
                        .find(|j| &j.name == joint)
                        .expect("validated");
                    let dir1 = |v: &Vector3<f64>| lk.direction(&j.body1, &j.marker1, v);
                    let dir2 = |v: &Vector3<f64>| lk.direction(&j.body2, &j.marker2, v);
                    match &j.kind {
                        JointKind::Revolute { axis: Some(axis) } => {
                            let a = axis.vec().normalize();
                            let (n1, _) = perpendiculars(&a);
                            Sensor3::Angle {
                                p1: dir1(&n1),
                                p2: dir2(&n1),
                                a: dir1(&a),
                                phi0: 0.0,
                                last: 0.0,
                                turns: 0.0,
                            }
                        }
                        JointKind::Prismatic { axis } => {
                            let a = axis.vec().normalize();
                            let (p1, p2) =
                                (point(&j.body1, &j.marker1), point(&j.body2, &j.marker2));
                            let s0 = (lk.position0(&p2) - lk.position0(&p1)).dot(&a);
                            Sensor3::Slide {
                                x: p2,
                                x2: p1,
                                z: dir1(&a),
                                s0,
                            }
                        }
                        k => {
                            return Err(unsupported(format!(
                                "{}: sensor `{}`: a joint coordinate is defined for revolute (angle) and prismatic (slide) joints only; joint `{}` is {k:?}",
                                scene.origin, s.name, j.name
                            )));
                        }
                    }
                }
                SensorKind::Modal { body, index } => {
                    let bi = lk.body(body).ok_or_else(|| {
                        unsupported(format!(
                            "{}: sensor `{}`: the ground has no modes",
                            scene.origin, s.name
                        ))
                    })?;
                    let b = &lk.bodies[bi];
                    if *index >= b.n {
                        return Err(unsupported(format!(
                            "{}: sensor `{}`: body `{body}` runs with {} modal coordinates",
                            scene.origin, s.name, b.n
                        )));
                    }
                    Sensor3::Modal {
                        q: b.off + 12 + index,
                    }
                }
                SensorKind::Energy => Sensor3::Energy,
            };
            sensors.push(sensor);
        }
        drop(lk);
        let mut sp = Spatial {
            n,
            m,
            gravity: g,
            bodies,
            cons,
            q0: DVector::from_vec(q0),
            qd0: DVector::from_vec(qd0),
            held: Vec::new(),
            sensor_names: scene.sensors.iter().map(|s| s.name.clone()).collect(),
            sensors,
            method,
            force_elements: ForceElements::default(),
            zero_rates: DVector::zeros(n),
        };
        // Reference angles of the angle drivers and sensors at t = 0.
        let z = DVector::zeros(n);
        let q0 = sp.q0.clone();
        let mut phis = Vec::new();
        for c in &sp.cons {
            if let Con3::Angle { p1, p2, a, .. } = c {
                phis.push(sp.angle(p1, p2, a, &q0, &z));
            }
        }
        let mut it = phis.into_iter();
        for c in &mut sp.cons {
            if let Con3::Angle { phi0, .. } = c {
                *phi0 = it.next().expect("one angle per driver");
            }
        }
        let mut phis = Vec::new();
        for s in &sp.sensors {
            if let Sensor3::Angle { p1, p2, a, .. } = s {
                phis.push(sp.angle(p1, p2, a, &q0, &z));
            }
        }
        let mut it = phis.into_iter();
        for s in &mut sp.sensors {
            if let Sensor3::Angle { phi0, .. } = s {
                *phi0 = it.next().expect("one angle per sensor");
            }
        }
        let (q0, qd0) = (sp.q0.clone(), sp.qd0.clone());
        sp.force_elements =
            ForceElements::new(prepared, |id| force_markers[&id].clone(), &sp, &q0, &qd0, n)?;
        Ok(sp)
    }

    fn angle(&self, p1: &Term, p2: &Term, a: &Term, q: &DVector<f64>, qd: &DVector<f64>) -> f64 {
        let (e1, e2, ea) = (
            p1.eval(&self.bodies, q, qd),
            p2.eval(&self.bodies, q, qd),
            a.eval(&self.bodies, q, qd),
        );
        triple_angle(&e1.x, &e2.x, &ea.x)
    }

    fn dynamics(
        &mut self,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        tangents: bool,
        out: &mut SystemTerms,
    ) {
        let g = self.gravity;
        for b in &mut self.bodies {
            let (o, nb) = (b.off, b.n);
            let nl = 12 + nb;
            let Some(f) = b.flex.as_mut() else {
                out.mass.view_mut((o, o), (12, 12)).copy_from(&b.m_const);
                out.forces.rows_mut(o, 12).copy_from(&b.q_const);
                continue;
            };
            let (qs, qds) = (&q.as_slice()[o..o + nl], &qd.as_slice()[o..o + nl]);
            let st = NaturalState::from_coords(Dim::Spatial, qs, qds);
            b.body.inertia_natural(
                &st,
                self.method,
                &mut f.ws,
                &mut out.mass.view_mut((o, o), (nl, nl)),
                &mut out.forces.rows_mut(o, nl),
            );
            b.body.gravity_natural(&st, &g, &mut f.gravity);
            b.body.elastic_forces(st.y, st.y_dot, &mut f.elastic);
            for (i, gv) in f.gravity.iter().enumerate() {
                out.forces[o + i] += gv;
            }
            for (j, e) in f.elastic.iter().enumerate() {
                out.forces[o + 12 + j] += e;
            }
            if tangents {
                let (y, yd) = (st.y, st.y_dot);
                let oy = o + 12;
                b.body.add_elastic_tangents(
                    y,
                    yd,
                    1.0,
                    0.0,
                    out.stiffness.view_mut((oy, oy), (nb, nb)),
                );
                b.body.add_elastic_tangents(
                    y,
                    yd,
                    0.0,
                    1.0,
                    out.damping.view_mut((oy, oy), (nb, nb)),
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
        &self,
        t: f64,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        req: Request,
        out: &mut SystemTerms,
    ) {
        let bodies = &self.bodies;
        let mut row = 0;
        for con in &self.cons {
            match con {
                Con3::Ortho { off } => {
                    let (_, a) = frame_of(q.as_slice(), *off);
                    let (_, ad) = frame_of(qd.as_slice(), *off);
                    // (u,u), (v,v), (w,w), (u,v), (v,w), (w,u).
                    const PAIRS: [(usize, usize); 6] =
                        [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)];
                    for (k, &(i, j)) in PAIRS.iter().enumerate() {
                        let (ei, ej) = (a.column(i), a.column(j));
                        if req.constraints {
                            out.phi[row + k] = ei.dot(&ej) - if i == j { 1.0 } else { 0.0 };
                        }
                        if req.jacobian {
                            for c in 0..3 {
                                out.phi_q[(row + k, off + 3 + 3 * i + c)] += ej[c];
                                out.phi_q[(row + k, off + 3 + 3 * j + c)] += ei[c];
                            }
                        }
                        if req.accel_term {
                            out.accel_term[row + k] = 2.0 * ad.column(i).dot(&ad.column(j));
                        }
                    }
                }
                Con3::Coincide { a, b } => {
                    let (ea, eb) = (a.eval(bodies, q, qd), b.eval(bodies, q, qd));
                    if req.constraints {
                        out.phi.fixed_rows_mut::<3>(row).copy_from(&(ea.x - eb.x));
                    }
                    if req.jacobian {
                        for k in 0..3 {
                            let mut w = Vector3::zeros();
                            w[k] = 1.0;
                            a.add_jacobian(bodies, &ea, &w, q, &mut out.phi_q, row + k);
                            b.add_jacobian(bodies, &eb, &(-w), q, &mut out.phi_q, row + k);
                        }
                    }
                    if req.accel_term {
                        out.accel_term
                            .fixed_rows_mut::<3>(row)
                            .copy_from(&(ea.bias - eb.bias));
                    }
                }
                Con3::Dot { x, x2, z, c0, law } => {
                    let ex = x.eval(bodies, q, qd);
                    let ex2 = x2.as_ref().map(|x2| x2.eval(bodies, q, qd));
                    let ez = z.eval(bodies, q, qd);
                    let (mut d, mut dd, mut db) = (ex.x, ex.xd, ex.bias);
                    if let Some(e2) = &ex2 {
                        d -= e2.x;
                        dd -= e2.xd;
                        db -= e2.bias;
                    }
                    let (s, sd, sdd) = law.as_ref().map_or((0.0, 0.0, 0.0), |l| l.eval(t));
                    if req.constraints {
                        out.phi[row] = d.dot(&ez.x) - c0 - s;
                    }
                    if req.jacobian {
                        x.add_jacobian(bodies, &ex, &ez.x, q, &mut out.phi_q, row);
                        if let (Some(x2), Some(e2)) = (x2, &ex2) {
                            x2.add_jacobian(bodies, e2, &(-ez.x), q, &mut out.phi_q, row);
                        }
                        z.add_jacobian(bodies, &ez, &d, q, &mut out.phi_q, row);
                        out.phi_t[row] = -sd;
                    }
                    if req.accel_term {
                        out.accel_term[row] =
                            db.dot(&ez.x) + d.dot(&ez.bias) + 2.0 * dd.dot(&ez.xd) - sdd;
                    }
                }
                Con3::Angle {
                    p1,
                    p2,
                    a,
                    phi0,
                    law,
                } => {
                    let (th_l, thd, thdd) = law.eval(t);
                    let (s, c) = (phi0 + th_l).sin_cos();
                    let (e1, e2, ea) = (
                        p1.eval(bodies, q, qd),
                        p2.eval(bodies, q, qd),
                        a.eval(bodies, q, qd),
                    );
                    let (x1, x2, xa) = (e1.x, e2.x, ea.x);
                    let sigma = x1.cross(&x2).dot(&xa);
                    let kappa = x1.dot(&x2);
                    if req.constraints {
                        out.phi[row] = sigma * c - kappa * s;
                    }
                    if req.jacobian {
                        let w1 = x2.cross(&xa) * c - x2 * s;
                        let w2 = xa.cross(&x1) * c - x1 * s;
                        let wa = x1.cross(&x2) * c;
                        p1.add_jacobian(bodies, &e1, &w1, q, &mut out.phi_q, row);
                        p2.add_jacobian(bodies, &e2, &w2, q, &mut out.phi_q, row);
                        a.add_jacobian(bodies, &ea, &wa, q, &mut out.phi_q, row);
                        out.phi_t[row] = -thd * (sigma * s + kappa * c);
                    }
                    if req.accel_term {
                        let (d1, d2, da) = (e1.xd, e2.xd, ea.xd);
                        let sigma_d = d1.cross(&x2).dot(&xa)
                            + x1.cross(&d2).dot(&xa)
                            + x1.cross(&x2).dot(&da);
                        let kappa_d = d1.dot(&x2) + x1.dot(&d2);
                        let sigma_b = e1.bias.cross(&x2).dot(&xa)
                            + x1.cross(&e2.bias).dot(&xa)
                            + x1.cross(&x2).dot(&ea.bias)
                            + 2.0
                                * (d1.cross(&d2).dot(&xa)
                                    + d1.cross(&x2).dot(&da)
                                    + x1.cross(&d2).dot(&da));
                        let kappa_b = e1.bias.dot(&x2) + x1.dot(&e2.bias) + 2.0 * d1.dot(&d2);
                        out.accel_term[row] = sigma_b * c
                            - kappa_b * s
                            - 2.0 * thd * (sigma_d * s + kappa_d * c)
                            - thdd * (sigma * s + kappa * c)
                            - thd * thd * (sigma * c - kappa * s);
                    }
                }
            }
            row += con.rows();
        }
    }

    /// Total mechanical energy: kinetic + gravity + elastic.
    fn energy(&mut self, q: &DVector<f64>, qd: &DVector<f64>) -> f64 {
        let g = self.gravity;
        let mut e = 0.0;
        for b in &mut self.bodies {
            let (o, nb) = (b.off, b.n);
            let nl = 12 + nb;
            let (qs, qds) = (&q.as_slice()[o..o + nl], &qd.as_slice()[o..o + nl]);
            let st = NaturalState::from_coords(Dim::Spatial, qs, qds);
            let m = match b.flex.as_mut() {
                None => &b.m_const,
                Some(f) => {
                    b.body
                        .inertia_natural(&st, self.method, &mut f.ws, &mut f.m, &mut f.qv);
                    &f.m
                }
            };
            let mut kin = 0.0;
            for r in 0..nl {
                for c in 0..nl {
                    kin += qds[r] * m[(r, c)] * qds[c];
                }
            }
            e += 0.5 * kin + b.body.natural_potential_energy(&st, &g);
            if nb > 0 {
                e += b.body.strain_energy(st.y);
            }
        }
        e + self.force_elements.potential_energy(self, q, qd)
    }

    /// The rotation of a body frame, `A = [u v w]`.
    fn rotation(&self, bi: usize, q: &DVector<f64>) -> (Vector3<f64>, Matrix3<f64>) {
        frame_of(q.as_slice(), self.bodies[bi].off)
    }
}

/// True when a driver names a joint of a kind that cannot be driven.
fn driver_refused(kind: &JointKind, scene: &Scene, joint: &str) -> bool {
    let driven = scene.drivers.iter().any(|d| d.joint == joint);
    driven
        && !matches!(
            kind,
            JointKind::Revolute { .. }
                | JointKind::Prismatic { .. }
                | JointKind::Cylindrical { .. }
        )
}

fn axis_index(a: Axis) -> usize {
    a.index()
}

impl flexmbd_core::Formulation for Spatial {
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
                Sensor3::Position { term, axis, frame } => {
                    let p = term.eval(&self.bodies, q, qd).x;
                    match frame {
                        None => p[*axis],
                        Some(fb) => {
                            let (r0, a) = self.rotation(*fb, q);
                            a.tr_mul(&(p - r0))[*axis]
                        }
                    }
                }
                Sensor3::Velocity { term, axis, frame } => {
                    let v = term.eval(&self.bodies, q, qd).xd;
                    match frame {
                        None => v[*axis],
                        Some(fb) => self.rotation(*fb, q).1.tr_mul(&v)[*axis],
                    }
                }
                Sensor3::Angle {
                    p1, p2, a, phi0, ..
                } => {
                    let ang = self.angle(p1, p2, a, q, qd) - phi0;
                    let Sensor3::Angle { last, turns, .. } = &mut self.sensors[k] else {
                        unreachable!()
                    };
                    let tau = std::f64::consts::TAU;
                    let mut v = ang + *turns * tau;
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
                Sensor3::Slide { x, x2, z, s0 } => {
                    let d = x.eval(&self.bodies, q, qd).x - x2.eval(&self.bodies, q, qd).x;
                    d.dot(&z.eval(&self.bodies, q, qd).x) - s0
                }
                Sensor3::Modal { q: i } => q[*i],
                Sensor3::Energy => self.energy(q, qd),
            };
        }
    }
}

impl MarkerKinematics for Spatial {
    type Marker = Term;

    fn marker_state(
        &self,
        marker: &Term,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let ev = marker.eval(&self.bodies, q, qd);
        (ev.x, ev.xd)
    }

    /// ∂x/∂r0 = I, ∂x/∂(column c of A) = x̃_c I, ∂x/∂y_j = A (V_j + FS0 shift column).
    fn marker_jacobian(
        &mut self,
        marker: &Term,
        q: &DVector<f64>,
        visit: &mut dyn FnMut(usize, Vector3<f64>),
    ) {
        let Some(bi) = marker.body else { return };
        let ev = marker.eval(&self.bodies, q, &self.zero_rates);
        let b = &self.bodies[bi];
        let o = b.off;
        let unit = Matrix3::<f64>::identity();
        if marker.point {
            for i in 0..3 {
                visit(o + i, unit.column(i).into_owned());
            }
        }
        for c in 0..3 {
            for i in 0..3 {
                visit(o + 3 + 3 * c + i, ev.local[c] * unit.column(i));
            }
        }
        if marker.rows.is_empty() {
            return;
        }
        let (_, a) = frame_of(q.as_slice(), o);
        let n = b.n;
        let y = &q.as_slice()[o + 12..o + 12 + n];
        for j in 0..n {
            let rows = &marker.rows;
            let mut column = Vector3::new(rows[j], rows[n + j], rows[2 * n + j]);
            if let Some(node) = marker.fs_node {
                column += b.body.node_foreshortening_column(node, y, j);
            }
            visit(o + 12 + j, a * column);
        }
    }
}
