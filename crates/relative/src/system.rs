//! The compiled scene and its one evaluation pass (docs/methods.md §4.5 steps 1–7, §4.6).
//!
//! Storage: for every frame F of the augmented tree its position r_F, rotation A_F,
//! velocity Z^r_F = {ṡ; ω} and velocity-product acceleration D_F (6-vectors in the 3D
//! layout; a planar scene uses the x, y, θz entries); per body its rigid block of M̄_k
//! and P_k, per elementary joint its twist v_e and the accumulated 𝕄, ℙ of its subtree;
//! the w-space M_w, Q_w, Φ_w. All sized at compile time: the pass allocates nothing.
//!
//! The pass does only what the [`Request`] needs: positions and twists are recomputed
//! only when z changed (a Newton iteration's M, Q, Φ_q reuse those of the Φ-only pass
//! after the update; the projections those of the last one), Z and D only for M, Q or
//! c and only when z or ż changed, Φ_w only for a Jacobian, the body terms only for M
//! and Q. M_w is never cleared (its structural non-zeros are rewritten every pass) and
//! its z × z block is written into M in place.

use flexmbd_body::{BodyState, FlexibleBody, InertiaMethod};
use flexmbd_core::{Dim, Request, SystemTerms};
use flexmbd_model::force_elements::ForceElements;
use flexmbd_model::{JointKind, MarkerId, ModelError, MotionLaw, PreparedScene, Scene, SensorKind};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Rotation3, Unit, Vector2, Vector3, Vector6};

use crate::marker_kinematics::MarkerJacobian;
use crate::topology::{BodyInfo, CoordRef, ElemKind, FrameKind, NodeRows, Side, Topology, side_of};

/// One body at run time.
pub(crate) struct BodyRt {
    pub(crate) body: FlexibleBody,
    pub(crate) frame: usize,
    /// Number of modal coordinates.
    pub(crate) n: usize,
    /// Index of the first modal coordinate in z (and in w).
    pub(crate) y_off: usize,
    pub(crate) rows: NodeRows,
    /// M̄_k, Q̄_k in the s form (nr + n).
    pub(crate) m_bar: DMatrix<f64>,
    pub(crate) q_bar: DVector<f64>,
    grav: Vec<f64>,
    elastic: Vec<f64>,
}

/// A constraint (docs/methods.md §4.6).
#[derive(Clone, Debug)]
pub(crate) enum Con {
    /// r_i − r_j = 0 (2 rows in 2D, 3 in 3D).
    Point { i: Side, j: Side },
    /// 2D angle: sin(ψ − ψ0 − s θ(t)) = 0, ψ = θ_j − θ_i (node rotations included).
    Angle2 {
        i: Side,
        j: Side,
        psi0: f64,
        law: MotionLaw,
        sign: f64,
    },
    /// n · (r_j − r_i) = 0 with n fixed at side i.
    Slide {
        i: Side,
        nbar: Vector3<f64>,
        j: Side,
    },
    /// a · b = 0, a fixed at side i, b at side j.
    Perp {
        i: Side,
        abar: Vector3<f64>,
        j: Side,
        bbar: Vector3<f64>,
    },
    /// z_c − s θ(t) = 0 (driven tree joint).
    Coord { z: usize, law: MotionLaw, sign: f64 },
}

impl Con {
    fn rows(&self, dim: Dim) -> usize {
        match self {
            Con::Point { .. } => dim.n_trans(),
            _ => 1,
        }
    }
}

pub(crate) enum SensorRt {
    Position {
        side: Side,
        axis: usize,
        frame: Option<usize>,
    },
    Velocity {
        side: Side,
        axis: usize,
        frame: Option<usize>,
    },
    /// 2D joint angle between the two markers' directions (node rotations included).
    Angle2 {
        i: Side,
        j: Side,
        psi0: f64,
        last: f64,
        turns: f64,
    },
    /// A joint coordinate of the tree.
    Coord {
        z: usize,
        sign: f64,
    },
    /// Displacement of j's marker relative to i's along an axis fixed at i.
    Slide {
        i: Side,
        nbar: Vector3<f64>,
        j: Side,
        d0: f64,
    },
    Modal(Option<usize>),
    Energy,
}

/// The semi-recursive relative-coordinate formulation of one scene.
pub struct Relative {
    pub(crate) dim: Dim,
    /// Number of rigid velocity entries per body (3 or 6) and their places in a 6-vector.
    pub(crate) nr: usize,
    pub(crate) rmap: [usize; 6],
    pub(crate) method: InertiaMethod,
    pub(crate) gravity: Vector3<f64>,
    pub(crate) n_z: usize,
    pub(crate) n_w: usize,
    pub(crate) n_con: usize,
    pub(crate) topo: Topology,
    pub(crate) bodies: Vec<BodyRt>,
    /// w index of each elementary joint.
    pub(crate) elem_w: Vec<usize>,
    /// Elementary joints on the path root → frame (inclusive), per frame.
    pub(crate) paths: Vec<Vec<usize>>,
    /// w → z: (z index, coefficient).
    pub(crate) l_rows: Vec<Vec<(usize, f64)>>,
    /// M = Lᵀ M_w L over the structural non-zeros of M_w outside its z × z block (which
    /// the pass writes into M directly): (index in M, index in M_w, coefficient),
    /// column-major indices.
    mass_map: Vec<(usize, usize, f64)>,
    /// Scratch of the largest body size (P_k).
    p_buf: Vec<f64>,
    /// Elementary-joint value coefficients, resolved to z.
    pub(crate) elem_rate: Vec<Vec<(usize, f64)>>,
    pub(crate) cons: Vec<Con>,
    // Workspace.
    pub(crate) fr_r: Vec<Vector3<f64>>,
    pub(crate) fr_a: Vec<Matrix3<f64>>,
    pub(crate) fr_z: Vec<Vector6<f64>>,
    pub(crate) fr_d: Vec<Vector6<f64>>,
    /// Per body: its rigid block of M̄_k and its P_k in the 6-layout (step 4).
    body_m: Vec<Matrix6<f64>>,
    body_p: Vec<Vector6<f64>>,
    /// Per elementary joint: 𝕄 and ℙ of the subtree its frame carries (step 5). Fixed
    /// frames only relabel the same global quantities, so the accumulation runs over the
    /// tree of elementary joints: an elementary joint's children, and the bodies whose
    /// nearest elementary joint towards the root it is.
    el_m: Vec<Matrix6<f64>>,
    el_p: Vec<Vector6<f64>>,
    el_children: Vec<Vec<usize>>,
    /// Per elementary joint: its nearest elementary joint towards the root (frames in
    /// between are fixed: the same Z and D).
    el_parent: Vec<Option<usize>>,
    el_bodies: Vec<Vec<usize>>,
    pub(crate) ev: Vec<Vector6<f64>>,
    pub(crate) m_w: DMatrix<f64>,
    pub(crate) q_w: DVector<f64>,
    phi_w: DMatrix<f64>,
    // Initial state and outputs.
    q0: DVector<f64>,
    qd0: DVector<f64>,
    held: Vec<usize>,
    sensor_names: Vec<String>,
    sensors: Vec<SensorRt>,
    /// Names of the coordinates.
    pub(crate) z_names: Vec<String>,
    /// z and ż of the last kinematics pass.
    pub(crate) last_z: DVector<f64>,
    pub(crate) last_zd: DVector<f64>,
    /// The frame positions and twists are those of `last_z`.
    pos_ok: bool,
    /// The frame velocities and D are those of `last_z` and `vel_zd`.
    vel_ok: bool,
    vel_zd: DVector<f64>,
    /// Per frame: a `Fixed` frame whose rotation is exactly I.
    fixed_identity: Vec<bool>,
    /// Planar scene whose every rotation is about z (fixed rotations and revolute axes):
    /// frame rotations then have the form [R 0; 0 1] and the fixed-frame products run
    /// on the 2 × 2 blocks (the dropped terms are exact zeros, so the values are the same).
    planar_frames: bool,
    /// The current constraint pass writes Φ_w (a Jacobian was requested).
    jac: bool,
    /// Spring–dampers and their Jacobian scratch.
    pub(crate) force_elements: ForceElements<Side>,
    /// Scratch of one marker's Jacobian (the force elements' query).
    pub(crate) marker_jacobian: MarkerJacobian,
}

fn unsupported(s: String) -> ModelError {
    ModelError::Unsupported(s)
}

/// Two unit vectors perpendicular to a and to each other.
fn perpendiculars(a: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let t = if a.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let n1 = a.cross(&t).normalize();
    let n2 = a.cross(&n1);
    (n1, n2)
}

fn angle_of(a: &Matrix3<f64>) -> f64 {
    a[(1, 0)].atan2(a[(0, 0)])
}

impl Relative {
    /// Compile a scene (planar or spatial) for the relative formulation.
    pub fn compile(prepared: &PreparedScene) -> Result<Relative, ModelError> {
        let scene = prepared.scene();
        let dim = scene.dim;
        let mut infos = Vec::new();
        let mut flex = Vec::new();
        for (b, prep) in scene.bodies.iter().zip(prepared.bodies()) {
            let body = prep.body.clone();
            let n = if prep.flexible { body.n_modes() } else { 0 };
            if !prep.flexible && body.n_modes() > 0 {
                return Err(unsupported(format!(
                    "body `{}`: modes on a body run rigid",
                    b.name
                )));
            }
            let rows = NodeRows {
                n,
                rows: if n > 0 {
                    prep.reduced
                        .nodes
                        .iter()
                        .map(|nd| {
                            let mut v = Vec::with_capacity(6 * n);
                            for a in 0..3 {
                                v.extend((0..n).map(|m| nd.translation[(a, m)]));
                            }
                            for a in 0..3 {
                                v.extend((0..n).map(|m| nd.rotation[(a, m)]));
                            }
                            v
                        })
                        .collect()
                } else {
                    Vec::new()
                },
            };
            let markers = b
                .markers
                .iter()
                .enumerate()
                .map(|(k, m)| Side {
                    body: Some(infos.len()),
                    rbar: m.position.vec(),
                    node: if n > 0 { prep.marker_nodes[k] } else { None },
                })
                .collect();
            let mut a0 = b.orientation.matrix();
            let mut r0 = b.origin.vec();
            if dim == Dim::Planar {
                r0.z = 0.0;
                let th = angle_of(&a0);
                a0 = *Rotation3::from_axis_angle(&Vector3::z_axis(), th).matrix();
            }
            infos.push(BodyInfo {
                name: b.name.clone(),
                flexible: n > 0,
                n_modes: n,
                r0,
                a0,
                center_of_mass: body.center_of_mass(),
                omega0: b.velocity.angular.vec(),
                markers,
                rows,
            });
            flex.push(body);
        }
        let topo = Topology::build(scene, &infos)?;

        // Coordinates: joint coordinates, then every body's modes.
        let n_joint = topo.n_joint;
        let mut y_off = Vec::new();
        let mut n_z = n_joint;
        for info in &infos {
            y_off.push(n_z);
            n_z += info.n_modes;
        }
        let resolve = |c: CoordRef| match c {
            CoordRef::Joint(k) => k,
            CoordRef::Mode(b, m) => y_off[b] + m,
        };
        let elem_rate: Vec<Vec<(usize, f64)>> = topo
            .elems
            .iter()
            .map(|e| e.rate.iter().map(|&(c, v)| (resolve(c), v)).collect())
            .collect();
        // w: joint elementary joints (= joint coordinates), modes, then node elementary joints.
        let mut elem_w = vec![usize::MAX; topo.elems.len()];
        for (k, &e) in topo.coord_elem.iter().enumerate() {
            elem_w[e] = k;
        }
        let mut n_w = n_z;
        let mut l_rows: Vec<Vec<(usize, f64)>> = (0..n_z).map(|c| vec![(c, 1.0)]).collect();
        for (e, w) in elem_w.iter_mut().enumerate() {
            if *w == usize::MAX {
                *w = n_w;
                n_w += 1;
                l_rows.push(elem_rate[e].clone());
            }
        }
        // Paths.
        let nf = topo.frames.len();
        let mut paths: Vec<Vec<usize>> = Vec::with_capacity(nf);
        for f in 0..nf {
            let fr = &topo.frames[f];
            let mut p = fr.parent.map_or_else(Vec::new, |pf| paths[pf].clone());
            if let FrameKind::Elem(e) = fr.kind {
                p.push(e);
            }
            paths.push(p);
        }
        let (nr, rmap) = match dim {
            Dim::Planar => (3, [0, 1, 5, 0, 0, 0]),
            Dim::Spatial => (6, [0, 1, 2, 3, 4, 5]),
        };
        let mut bodies = Vec::new();
        for (k, (info, body)) in infos.iter().zip(flex).enumerate() {
            let nc = nr + info.n_modes;
            bodies.push(BodyRt {
                body,
                frame: topo.body_frame[k],
                n: info.n_modes,
                y_off: y_off[k],
                rows: info.rows.clone(),
                m_bar: DMatrix::zeros(nc, nc),
                q_bar: DVector::zeros(nc),
                grav: vec![0.0; nc],
                elastic: vec![0.0; info.n_modes],
            });
        }
        let mut z_names: Vec<String> = (0..n_joint)
            .map(|k| format!("joint coordinate {k}"))
            .collect();
        for info in &infos {
            z_names.extend((0..info.n_modes).map(|m| format!("{}.y{m}", info.name)));
        }

        // Cut joints and drivers.
        let mut cons = Vec::new();
        let side = |b: &str, m: &str| side_of(scene, &infos, b, m);
        let a0_of = |s: &Side| s.body.map_or(Matrix3::identity(), |b| infos[b].a0);
        let psi_of = |i: &Side, j: &Side| angle_of(&a0_of(j)) - angle_of(&a0_of(i));
        for &ji in &topo.cuts {
            let j = &scene.joints[ji];
            let (si, sj) = (side(&j.body1, &j.marker1), side(&j.body2, &j.marker2));
            let driver = scene.drivers.iter().find(|d| d.joint == j.name);
            let what = format!("{}: cut joint `{}`", scene.origin, j.name);
            // Axis helpers: a ground-component axis at t = 0 in a side's body components.
            let body_axis = |s: &Side, v: Vector3<f64>| a0_of(s).transpose() * v;
            match (dim, &j.kind) {
                (Dim::Planar, JointKind::Revolute { .. }) => {
                    cons.push(Con::Point { i: si, j: sj });
                    if let Some(d) = driver {
                        cons.push(Con::Angle2 {
                            i: si,
                            j: sj,
                            psi0: psi_of(&si, &sj),
                            law: d.law.clone(),
                            sign: 1.0,
                        });
                    }
                }
                // A cut Free joint (its body reached through other joints) adds nothing.
                (_, JointKind::Free) => {}
                (Dim::Planar, JointKind::Rigid) => {
                    cons.push(Con::Point { i: si, j: sj });
                    cons.push(Con::Angle2 {
                        i: si,
                        j: sj,
                        psi0: psi_of(&si, &sj),
                        law: MotionLaw::Locked,
                        sign: 1.0,
                    });
                }
                (Dim::Planar, JointKind::Prismatic { axis }) => {
                    if driver.is_some() {
                        return Err(unsupported(format!(
                            "{what}: a driven prismatic joint must be in the tree (drive a joint of the spanning tree instead)"
                        )));
                    }
                    let mut a = axis.vec();
                    a.z = 0.0;
                    let n = Vector3::new(-a.y, a.x, 0.0).normalize();
                    cons.push(Con::Slide {
                        i: si,
                        nbar: body_axis(&si, n),
                        j: sj,
                    });
                    cons.push(Con::Angle2 {
                        i: si,
                        j: sj,
                        psi0: psi_of(&si, &sj),
                        law: MotionLaw::Locked,
                        sign: 1.0,
                    });
                }
                (Dim::Spatial, kind) => {
                    if driver.is_some() {
                        return Err(unsupported(format!(
                            "{what}: driven cut joints are not supported in 3D yet (drive a joint of the spanning tree)"
                        )));
                    }
                    let perp = |cons: &mut Vec<Con>, a: Vector3<f64>, b: Vector3<f64>| {
                        cons.push(Con::Perp {
                            i: si,
                            abar: body_axis(&si, a),
                            j: sj,
                            bbar: body_axis(&sj, b),
                        })
                    };
                    let need_axis = |v: Option<flexmbd_model::V3>| {
                        v.map(|v| v.vec().normalize()).ok_or_else(|| {
                            unsupported(format!("{what}: a 3D revolute joint needs an axis"))
                        })
                    };
                    match kind {
                        JointKind::Free => {}
                        JointKind::Spherical => cons.push(Con::Point { i: si, j: sj }),
                        JointKind::Revolute { axis } => {
                            let a = need_axis(*axis)?;
                            let (n1, n2) = perpendiculars(&a);
                            cons.push(Con::Point { i: si, j: sj });
                            perp(&mut cons, a, n1);
                            perp(&mut cons, a, n2);
                        }
                        JointKind::Universal { axis1, axis2 } => {
                            cons.push(Con::Point { i: si, j: sj });
                            perp(&mut cons, axis1.vec().normalize(), axis2.vec().normalize());
                        }
                        JointKind::Cylindrical { axis } | JointKind::Prismatic { axis } => {
                            let a = axis.vec().normalize();
                            let (n1, n2) = perpendiculars(&a);
                            perp(&mut cons, a, n1);
                            perp(&mut cons, a, n2);
                            for n in [n1, n2] {
                                cons.push(Con::Slide {
                                    i: si,
                                    nbar: body_axis(&si, n),
                                    j: sj,
                                });
                            }
                            if matches!(kind, JointKind::Prismatic { .. }) {
                                perp(&mut cons, n1, n2);
                            }
                        }
                        JointKind::Rigid => {
                            cons.push(Con::Point { i: si, j: sj });
                            let e = [Vector3::x(), Vector3::y(), Vector3::z()];
                            for k in 0..3 {
                                perp(&mut cons, e[k], e[(k + 1) % 3]);
                            }
                        }
                    }
                }
                (d, k) => {
                    return Err(unsupported(format!("{what}: {k:?} is not a {d} joint")));
                }
            }
        }
        for d in &scene.drivers {
            let ji = scene
                .joints
                .iter()
                .position(|j| j.name == d.joint)
                .expect("validated");
            let Some(tj) = &topo.tree[ji] else { continue };
            if tj.coords.len() != 1 {
                return Err(unsupported(format!(
                    "{}: driver `{}`: joint `{}` has {} coordinates; only one-coordinate joints (revolute, prismatic) can be driven",
                    scene.origin,
                    d.name,
                    d.joint,
                    tj.coords.len()
                )));
            }
            cons.push(Con::Coord {
                z: tj.coords[0],
                law: d.law.clone(),
                sign: if tj.reversed { -1.0 } else { 1.0 },
            });
        }
        let n_con = cons.iter().map(|c| c.rows(dim)).sum();

        let nf = topo.frames.len();
        let ne = topo.elems.len();
        // The tree of elementary joints (step 5).
        let n_bodies = bodies.len();
        let mut el_children = vec![Vec::new(); ne];
        let mut el_bodies = vec![Vec::new(); ne];
        let mut el_parent = vec![None; ne];
        for (e, el) in topo.elems.iter().enumerate() {
            if let Some(&pe) = topo.frames[el.frame].parent.and_then(|pf| paths[pf].last()) {
                assert!(pe < e, "elementary joints in tree order");
                el_children[pe].push(e);
                el_parent[e] = Some(pe);
            }
        }
        for (k, b) in bodies.iter().enumerate() {
            if let Some(&e) = paths[b.frame].last() {
                el_bodies[e].push(k);
            }
        }
        let fixed_identity = topo
            .frames
            .iter()
            .map(|f| matches!(&f.kind, FrameKind::Fixed { rot, .. } if *rot == Matrix3::identity()))
            .collect();
        let z_rotation = |r: &Matrix3<f64>| {
            r[(0, 2)] == 0.0
                && r[(1, 2)] == 0.0
                && r[(2, 0)] == 0.0
                && r[(2, 1)] == 0.0
                && r[(2, 2)] == 1.0
        };
        let planar_frames = dim == Dim::Planar
            && topo.frames.iter().all(|f| match &f.kind {
                FrameKind::Fixed { rot, .. } => z_rotation(rot),
                FrameKind::Elem(_) => true,
            })
            && topo
                .elems
                .iter()
                .all(|e| e.kind == ElemKind::Prismatic || e.axis == Vector3::z());
        let mut rel = Relative {
            dim,
            nr,
            rmap,
            method: scene.solver.inertia,
            gravity: scene.gravity.vec(),
            n_z,
            n_w,
            n_con,
            topo,
            bodies,
            elem_w,
            paths,
            l_rows,
            mass_map: Vec::new(),
            p_buf: vec![0.0; nr + infos.iter().map(|i| i.n_modes).max().unwrap_or(0)],
            elem_rate,
            cons,
            fr_r: vec![Vector3::zeros(); nf],
            fr_a: vec![Matrix3::identity(); nf],
            fr_z: vec![Vector6::zeros(); nf],
            fr_d: vec![Vector6::zeros(); nf],
            body_m: vec![Matrix6::zeros(); n_bodies],
            body_p: vec![Vector6::zeros(); n_bodies],
            el_m: vec![Matrix6::zeros(); ne],
            el_p: vec![Vector6::zeros(); ne],
            el_children,
            el_bodies,
            el_parent,
            ev: vec![Vector6::zeros(); ne],
            m_w: DMatrix::zeros(n_w, n_w),
            q_w: DVector::zeros(n_w),
            phi_w: DMatrix::zeros(n_con, n_w),
            q0: DVector::zeros(n_z),
            qd0: DVector::zeros(n_z),
            held: Vec::new(),
            sensor_names: scene.sensors.iter().map(|s| s.name.clone()).collect(),
            sensors: Vec::new(),
            z_names,
            last_z: DVector::zeros(n_z),
            last_zd: DVector::zeros(n_z),
            pos_ok: false,
            vel_ok: false,
            vel_zd: DVector::zeros(n_z),
            fixed_identity,
            planar_frames,
            jac: true,
            force_elements: ForceElements::default(),
            marker_jacobian: MarkerJacobian::default(),
        };
        if dim == Dim::Planar {
            rel.gravity.z = 0.0;
        }
        // Initial coordinates: joints at their t = 0 placement (z = 0), modes as given.
        for (k, b) in scene.bodies.iter().enumerate() {
            let (o, n) = (rel.bodies[k].y_off, rel.bodies[k].n);
            for m in 0..n {
                rel.q0[o + m] = b.initial_modes.get(m).copied().unwrap_or(0.0);
            }
        }
        rel.mass_map = rel.build_mass_map();
        rel.initial_velocities(scene);
        rel.build_sensors(scene, &infos)?;
        rel.build_force_elements(prepared, &infos)?;
        Ok(rel)
    }

    /// Compile the scene's force elements over this formulation's markers (free lengths left
    /// to the start: the t = 0 distance).
    fn build_force_elements(
        &mut self,
        prepared: &PreparedScene,
        infos: &[BodyInfo],
    ) -> Result<(), ModelError> {
        let scene = prepared.scene();
        let side_at = |id: MarkerId| match id.body {
            None => Side {
                body: None,
                rbar: prepared.marker_position(id),
                node: None,
            },
            Some(b) => infos[b.0].markers[id.index],
        };
        if scene.solver.stiffening == flexmbd_model::Stiffening::Foreshortening {
            for (force, pair) in scene.forces.iter().zip(prepared.force_markers()) {
                let at_fs0_node = [pair.first, pair.second].into_iter().any(|id| {
                    let s = side_at(id);
                    s.node.is_some() && s.body.is_some_and(|b| infos[b].flexible)
                });
                if at_fs0_node {
                    return Err(unsupported(format!(
                        "{}: force `{}`: a spring at a node of a foreshortening (FS0) body is not supported by the relative formulation",
                        scene.origin,
                        force.name()
                    )));
                }
            }
        }
        let (q0, qd0) = (self.q0.clone(), self.qd0.clone());
        self.kinematics(&q0, &qd0);
        self.marker_jacobian = MarkerJacobian::new(self.n_w, self.n_z);
        self.force_elements = ForceElements::new(prepared, side_at, &*self, &q0, &qd0, self.n_z)?;
        Ok(())
    }

    /// The entries of M_w outside its z × z block that [`dynamics`](Self::dynamics) writes
    /// (the others are zero for every state), mapped through L into M.
    fn build_mass_map(&self) -> Vec<(usize, usize, f64)> {
        let (nz, nw) = (self.n_z, self.n_w);
        let mut pattern = vec![false; nw * nw];
        let mut mark = |i: usize, j: usize| {
            pattern[i + j * nw] = true;
            pattern[j + i * nw] = true;
        };
        for (e, el) in self.topo.elems.iter().enumerate() {
            for &a in &self.paths[el.frame] {
                mark(self.elem_w[a], self.elem_w[e]);
            }
        }
        for b in &self.bodies {
            for m in 0..b.n {
                for &a in &self.paths[b.frame] {
                    mark(self.elem_w[a], b.y_off + m);
                }
                for m2 in 0..b.n {
                    mark(b.y_off + m, b.y_off + m2);
                }
            }
        }
        let mut map = Vec::new();
        for j in 0..nw {
            for i in 0..nw {
                if !pattern[i + j * nw] || (i < nz && j < nz) {
                    continue;
                }
                for &(c, a) in &self.l_rows[i] {
                    for &(d, b) in &self.l_rows[j] {
                        map.push((c + d * nz, i + j * nw, a * b));
                    }
                }
            }
        }
        map
    }

    /// ż(0): the kinetic-energy-weighted least-squares fit of the scene's body velocities,
    /// M ż = Σ_k R_kᵀ M̄_k Z*_k (exact when the given velocities are consistent).
    fn initial_velocities(&mut self, scene: &Scene) {
        let n = self.n_z;
        let q0 = self.q0.clone();
        let zero = DVector::zeros(n);
        self.kinematics(&q0, &zero);
        let mut m = DMatrix::zeros(n, n);
        let mut b = DVector::zeros(n);
        // Columns of R: velocity pass with ż = e_c.
        let nb = self.bodies.len();
        let mut cols: Vec<Vec<DVector<f64>>> = vec![Vec::new(); nb];
        for c in 0..n {
            let mut e = DVector::zeros(n);
            e[c] = 1.0;
            self.kinematics(&q0, &e);
            for k in 0..nb {
                let bk = &self.bodies[k];
                let nc = self.nr + bk.n;
                let z = self.fr_z[bk.frame];
                let mut col = DVector::zeros(nc);
                for i in 0..self.nr {
                    col[i] = z[self.rmap[i]];
                }
                for mm in 0..bk.n {
                    col[self.nr + mm] = e[bk.y_off + mm];
                }
                cols[k].push(col);
            }
        }
        self.kinematics(&q0, &zero);
        for k in 0..nb {
            let f = self.bodies[k].frame;
            let (r0, a) = (self.fr_r[f], self.fr_a[f]);
            let bk = &mut self.bodies[k];
            let y: Vec<f64> = q0.as_slice()[bk.y_off..bk.y_off + bk.n].to_vec();
            let yd = vec![0.0; bk.n];
            let state = BodyState {
                r0,
                a,
                omega: Vector3::zeros(),
                s_dot: Vector3::zeros(),
                y: &y,
                y_dot: &yd,
            };
            bk.body
                .inertia(&state, self.method, &mut bk.m_bar, &mut bk.q_bar);
            let v = &scene.bodies[k].velocity;
            let mut w = v.angular.vec();
            let mut lin = v.linear.vec();
            if self.dim == Dim::Planar {
                w = Vector3::new(0.0, 0.0, w.z);
                lin.z = 0.0;
            }
            let s_dot = lin + r0.cross(&w);
            let mut target6 = Vector6::zeros();
            target6.fixed_rows_mut::<3>(0).copy_from(&s_dot);
            target6.fixed_rows_mut::<3>(3).copy_from(&w);
            let nc = self.nr + bk.n;
            let mut target = DVector::zeros(nc);
            for i in 0..self.nr {
                target[i] = target6[self.rmap[i]];
            }
            let mt = &bk.m_bar * &target;
            for c in 0..n {
                let mc = &bk.m_bar * &cols[k][c];
                b[c] += cols[k][c].dot(&mt);
                for d in 0..n {
                    m[(c, d)] += cols[k][d].dot(&mc);
                }
            }
        }
        let svd = m.svd(true, true);
        let max_sv: f64 = svd.singular_values.max();
        if let Ok(x) = svd.solve(&b, 1e-12 * max_sv.max(1e-300)) {
            self.qd0.copy_from(&x);
        }
    }

    fn build_sensors(&mut self, scene: &Scene, infos: &[BodyInfo]) -> Result<(), ModelError> {
        let body_index = |name: &str| scene.bodies.iter().position(|b| b.name == name);
        let axis = |a: flexmbd_model::Axis, name: &str| -> Result<usize, ModelError> {
            let i = a.index();
            if self.dim == Dim::Planar && i == 2 {
                return Err(unsupported(format!(
                    "sensor `{name}`: a planar scene has no z component"
                )));
            }
            Ok(i)
        };
        let mut sensors = Vec::new();
        for s in &scene.sensors {
            let sensor = match &s.kind {
                SensorKind::Position {
                    body,
                    marker,
                    component,
                    frame,
                } => SensorRt::Position {
                    side: side_of(scene, infos, body, marker),
                    axis: axis(*component, &s.name)?,
                    frame: frame.as_deref().and_then(body_index),
                },
                SensorKind::Velocity {
                    body,
                    marker,
                    component,
                    frame,
                } => SensorRt::Velocity {
                    side: side_of(scene, infos, body, marker),
                    axis: axis(*component, &s.name)?,
                    frame: frame.as_deref().and_then(body_index),
                },
                SensorKind::JointCoordinate { joint } => {
                    let ji = scene
                        .joints
                        .iter()
                        .position(|j| &j.name == joint)
                        .expect("validated");
                    let j = &scene.joints[ji];
                    let si = side_of(scene, infos, &j.body1, &j.marker1);
                    let sj = side_of(scene, infos, &j.body2, &j.marker2);
                    let a0 = |s: &Side| s.body.map_or(Matrix3::identity(), |b| infos[b].a0);
                    match (self.dim, &j.kind, &self.topo.tree[ji]) {
                        (Dim::Planar, JointKind::Revolute { .. }, _) => SensorRt::Angle2 {
                            i: si,
                            j: sj,
                            psi0: angle_of(&a0(&sj)) - angle_of(&a0(&si)),
                            last: 0.0,
                            turns: 0.0,
                        },
                        (_, JointKind::Prismatic { axis }, None) => {
                            let nbar = a0(&si).transpose() * axis.vec().normalize();
                            SensorRt::Slide {
                                i: si,
                                nbar,
                                j: sj,
                                d0: 0.0,
                            }
                        }
                        (_, _, Some(tj)) if !tj.coords.is_empty() => SensorRt::Coord {
                            z: tj.coords[0],
                            sign: if tj.reversed { -1.0 } else { 1.0 },
                        },
                        _ => {
                            return Err(unsupported(format!(
                                "sensor `{}`: the coordinate of joint `{joint}` ({:?}) is not available in the relative formulation",
                                s.name, j.kind
                            )));
                        }
                    }
                }
                SensorKind::Modal { body, index } => {
                    let bi = body_index(body).expect("validated");
                    let b = &self.bodies[bi];
                    SensorRt::Modal((*index < b.n).then_some(b.y_off + index))
                }
                SensorKind::Energy => SensorRt::Energy,
            };
            sensors.push(sensor);
        }
        // Reference values of slide sensors.
        let (q0, qd0) = (self.q0.clone(), self.qd0.clone());
        self.last_z.copy_from(&q0);
        self.last_zd.copy_from(&qd0);
        self.kinematics(&q0, &qd0);
        for s in &mut sensors {
            if let SensorRt::Slide { i, nbar, j, d0 } = s {
                let (n, _) = dir_at(self, i, nbar);
                let (pi, _) = point_at(self, i);
                let (pj, _) = point_at(self, j);
                *d0 = n.dot(&(pj - pi));
            }
        }
        self.sensors = sensors;
        Ok(())
    }

    /// §4.5 steps 1–3: positions, velocities Z^r and velocity-product accelerations D of
    /// every frame, root → leaves; twists v_e of the elementary joints. Sets `last_z`,
    /// `last_zd` and the caches of [`update_positions`](Self::update_positions) and
    /// [`update_velocities`](Self::update_velocities).
    pub(crate) fn kinematics(&mut self, z: &DVector<f64>, zd: &DVector<f64>) {
        self.last_z.copy_from(z);
        self.last_zd.copy_from(zd);
        self.positions();
        self.pos_ok = true;
        self.velocities();
        self.vel_zd.copy_from(zd);
        self.vel_ok = true;
    }

    /// Positions (and twists) at z unless they are already those of `last_z`; invalidates
    /// the velocities when z changed.
    fn update_positions(&mut self, z: &DVector<f64>) {
        if self.pos_ok && self.last_z.as_slice() == z.as_slice() {
            return;
        }
        self.last_z.copy_from(z);
        self.positions();
        self.pos_ok = true;
        self.vel_ok = false;
    }

    /// Velocities and D at `last_zd` unless already done at these positions and rates.
    fn update_velocities(&mut self) {
        if self.vel_ok && self.vel_zd.as_slice() == self.last_zd.as_slice() {
            return;
        }
        self.vel_zd.copy_from(&self.last_zd);
        self.velocities();
        self.vel_ok = true;
    }

    /// Steps 1–2 at z = `last_z`: r_F, A_F of every frame and the twists v_e (they depend
    /// on positions only), root → leaves.
    #[inline(never)]
    fn positions(&mut self) {
        let z = self.last_z.as_slice();
        for f in 0..self.topo.frames.len() {
            let (rp, ap) = match self.topo.frames[f].parent {
                None => (Vector3::zeros(), Matrix3::identity()),
                Some(p) => (self.fr_r[p], self.fr_a[p]),
            };
            match &self.topo.frames[f].kind {
                FrameKind::Fixed { offset, rot } => {
                    if self.planar_frames {
                        // ap = [R_p 0; 0 1], rot = [R 0; 0 1]: the products' third terms
                        // are exact zeros.
                        let mut r = rp;
                        r.x += ap[(0, 0)] * offset.x + ap[(0, 1)] * offset.y;
                        r.y += ap[(1, 0)] * offset.x + ap[(1, 1)] * offset.y;
                        r.z += offset.z;
                        self.fr_r[f] = r;
                        if !self.fixed_identity[f] {
                            let mut a = ap;
                            for i in 0..2 {
                                let (p0, p1) = (ap[(i, 0)], ap[(i, 1)]);
                                a[(i, 0)] = p0 * rot[(0, 0)] + p1 * rot[(1, 0)];
                                a[(i, 1)] = p0 * rot[(0, 1)] + p1 * rot[(1, 1)];
                            }
                            self.fr_a[f] = a;
                        } else {
                            self.fr_a[f] = ap;
                        }
                    } else {
                        self.fr_r[f] = rp + ap * offset;
                        self.fr_a[f] = if self.fixed_identity[f] { ap } else { ap * rot };
                    }
                }
                FrameKind::Elem(e) => {
                    let e = *e;
                    let el = &self.topo.elems[e];
                    let mut val = 0.0;
                    for &(c, k) in &self.elem_rate[e] {
                        val += k * z[c];
                    }
                    let a = ap * el.axis;
                    let mut v = Vector6::zeros();
                    match el.kind {
                        ElemKind::Revolute => {
                            // b = {p × a; a}.
                            v.fixed_rows_mut::<3>(0).copy_from(&rp.cross(&a));
                            v.fixed_rows_mut::<3>(3).copy_from(&a);
                            self.fr_r[f] = rp;
                            if el.axis == Vector3::z() {
                                // A_p R_z(val), R_z as `from_axis_angle` forms it for ā = z.
                                let (sn, cs) = val.sin_cos();
                                let mut a_new = ap;
                                for i in 0..3 {
                                    let (c0, c1) = (ap[(i, 0)], ap[(i, 1)]);
                                    a_new[(i, 0)] = c0 * cs + c1 * sn;
                                    a_new[(i, 1)] = c1 * cs - c0 * sn;
                                }
                                self.fr_a[f] = a_new;
                            } else {
                                self.fr_a[f] = ap
                                    * Rotation3::from_axis_angle(
                                        &Unit::new_unchecked(el.axis),
                                        val,
                                    )
                                    .matrix();
                            }
                        }
                        ElemKind::Prismatic => {
                            // b = {a; 0}.
                            v.fixed_rows_mut::<3>(0).copy_from(&a);
                            self.fr_r[f] = rp + a * val;
                            self.fr_a[f] = ap;
                        }
                    }
                    self.ev[e] = v;
                }
            }
        }
    }

    /// Step 3 at ż = `last_zd` (positions current): Z^r_F and D_F, root → leaves.
    #[inline(never)]
    fn velocities(&mut self) {
        let zd = self.last_zd.as_slice();
        // Only the frames of elementary joints (in tree order) and of bodies: a fixed frame
        // has its parent's Z and D.
        for e in 0..self.topo.elems.len() {
            let el = &self.topo.elems[e];
            let f = el.frame;
            let (zp, dp) = match self.el_parent[e] {
                None => (Vector6::zeros(), Vector6::zeros()),
                Some(pe) => {
                    let pf = self.topo.elems[pe].frame;
                    (self.fr_z[pf], self.fr_d[pf])
                }
            };
            let mut rate = 0.0;
            for &(c, k) in &self.elem_rate[e] {
                rate += k * zd[c];
            }
            let v = self.ev[e];
            let w_f = zp.fixed_rows::<3>(3).into_owned();
            let mut d = dp;
            match el.kind {
                ElemKind::Revolute => {
                    // d = {(ṗ × a + p × (ω_f × a)) ė; (ω_f × a) ė}.
                    let a = v.fixed_rows::<3>(3).into_owned();
                    let wxa = w_f.cross(&a);
                    let rp = self.fr_r[f];
                    let s_f = zp.fixed_rows::<3>(0).into_owned();
                    let p_dot = s_f + w_f.cross(&rp);
                    let ds = (p_dot.cross(&a) + rp.cross(&wxa)) * rate;
                    for i in 0..3 {
                        d[i] += ds[i];
                        d[3 + i] += wxa[i] * rate;
                    }
                }
                ElemKind::Prismatic => {
                    // d = {(ω_f × a) ė; 0}.
                    let a = v.fixed_rows::<3>(0).into_owned();
                    let wxa = w_f.cross(&a);
                    for i in 0..3 {
                        d[i] += wxa[i] * rate;
                    }
                }
            }
            self.fr_z[f] = zp + v * rate;
            self.fr_d[f] = d;
        }
        for b in &self.bodies {
            let (z, d) = match self.paths[b.frame].last() {
                None => (Vector6::zeros(), Vector6::zeros()),
                Some(&e) => {
                    let ef = self.topo.elems[e].frame;
                    (self.fr_z[ef], self.fr_d[ef])
                }
            };
            self.fr_z[b.frame] = z;
            self.fr_d[b.frame] = d;
        }
    }

    fn body_state<'a>(&self, k: usize, z: &'a DVector<f64>, zd: &'a DVector<f64>) -> BodyState<'a> {
        let b = &self.bodies[k];
        let f = b.frame;
        let zr = self.fr_z[f];
        BodyState {
            r0: self.fr_r[f],
            a: self.fr_a[f],
            omega: zr.fixed_rows::<3>(3).into_owned(),
            s_dot: zr.fixed_rows::<3>(0).into_owned(),
            y: &z.as_slice()[b.y_off..b.y_off + b.n],
            y_dot: &zd.as_slice()[b.y_off..b.y_off + b.n],
        }
    }

    /// §4.5 step 4: M̄_k and Q̄_k (inertia, gravity, elastic) of every body, at the
    /// state of the last kinematics pass.
    pub(crate) fn evaluate_bodies(&mut self, z: &DVector<f64>, zd: &DVector<f64>) {
        for k in 0..self.bodies.len() {
            let state = self.body_state(k, z, zd);
            let g = self.gravity;
            let method = self.method;
            let b = &mut self.bodies[k];
            b.body.inertia(&state, method, &mut b.m_bar, &mut b.q_bar);
            b.body.gravity_forces(&state, &g, &mut b.grav);
            for (q, gv) in b.q_bar.iter_mut().zip(&b.grav) {
                *q += gv;
            }
            if b.n > 0 {
                b.body.elastic_forces(state.y, state.y_dot, &mut b.elastic);
                for m in 0..b.n {
                    b.q_bar[self.nr + m] += b.elastic[m];
                }
            }
        }
    }

    /// §4.5 steps 4–7: M and Q into `out`.
    #[inline(never)]
    fn dynamics(
        &mut self,
        z: &DVector<f64>,
        zd: &DVector<f64>,
        tangents: bool,
        out: &mut SystemTerms,
    ) {
        let nr = self.nr;
        let rmap = self.rmap;
        self.evaluate_bodies(z, zd);
        // M_w and Q_w need no clearing: every pass writes the same set of their entries
        // (the others stay at their compile-time zeros).
        // M_w[i, j] goes straight into M when both are z indices (L = [I; L_node]), into
        // `m_w` otherwise (mapped below). `out` comes cleared.
        let nz = self.n_z;
        let mass = out.mass.as_mut_slice();
        let put = |mass: &mut [f64], mw: &mut DMatrix<f64>, i: usize, j: usize, v: f64| {
            if i < nz && j < nz {
                mass[i + j * nz] = v;
            } else {
                mw[(i, j)] = v;
            }
        };
        // A planar scene only has the x, y, θz entries (`rmap`) of twists, 𝕄 and ℙ: the
        // others are exact zeros, so the products run on those three.
        let planar = nr == 3;
        let dot = |a: &Vector6<f64>, b: &Vector6<f64>| {
            if planar {
                a[0] * b[0] + a[1] * b[1] + a[5] * b[5]
            } else {
                a.dot(b)
            }
        };
        // Step 4: P_k = Q̄_k − M̄_k {D_k; 0}; own rigid blocks; modal rows of M_w, Q_w.
        for k in 0..self.bodies.len() {
            let b = &self.bodies[k];
            let f = b.frame;
            let d = self.fr_d[f];
            let nc = nr + b.n;
            let (mm, pp) = (&mut self.body_m[k], &mut self.body_p[k]);
            // P = Q̄ − M̄[:, rigid] D, column by column (the same operation order per row).
            let mb = b.m_bar.as_slice();
            let p = &mut self.p_buf[..nc];
            p.copy_from_slice(b.q_bar.as_slice());
            for c in 0..nr {
                let dc = d[rmap[c]];
                for (pr, m) in p.iter_mut().zip(&mb[c * nc..(c + 1) * nc]) {
                    *pr -= m * dc;
                }
                for r in 0..nr {
                    mm[(rmap[r], rmap[c])] = mb[c * nc + r];
                }
            }
            for r in 0..nr {
                pp[rmap[r]] = p[r];
            }
            self.q_w.as_mut_slice()[b.y_off..b.y_off + b.n].copy_from_slice(&p[nr..]);
            for m in 0..b.n {
                let wm = b.y_off + m;
                let col = &mb[(nr + m) * nc..(nr + m + 1) * nc];
                let mut u = Vector6::zeros();
                for r in 0..nr {
                    u[rmap[r]] = col[r];
                }
                for &a in &self.paths[f] {
                    let val = dot(&self.ev[a], &u);
                    let wa = self.elem_w[a];
                    put(mass, &mut self.m_w, wa, wm, val);
                    put(mass, &mut self.m_w, wm, wa, val);
                }
                // M̄_yy (modes are z coordinates): column m of the block, row m2.
                for m2 in 0..b.n {
                    mass[b.y_off + m2 + wm * nz] = col[nr + m2];
                }
            }
        }
        // Step 5: accumulate leaves → root over the tree of elementary joints (a child's
        // index is larger than its parent's).
        for e in (0..self.topo.elems.len()).rev() {
            let (mut m, mut pv) = (Matrix6::zeros(), Vector6::zeros());
            let parts = self.el_bodies[e]
                .iter()
                .map(|&k| (&self.body_m[k], &self.body_p[k]))
                .chain(
                    self.el_children[e]
                        .iter()
                        .map(|&c| (&self.el_m[c], &self.el_p[c])),
                );
            if planar {
                for (bm, bp) in parts {
                    for &c in &rmap[..3] {
                        pv[c] += bp[c];
                        for &r in &rmap[..3] {
                            m[(r, c)] += bm[(r, c)];
                        }
                    }
                }
            } else {
                for (bm, bp) in parts {
                    m += bm;
                    pv += bp;
                }
            }
            self.el_m[e] = m;
            self.el_p[e] = pv;
        }
        // Steps 6–7 for the elementary joints.
        for e in 0..self.topo.elems.len() {
            let f = self.topo.elems[e].frame;
            let (me, ve) = (&self.el_m[e], &self.ev[e]);
            let ke = if planar {
                let mut ke = Vector6::zeros();
                for r in [0, 1, 5] {
                    ke[r] = me[(r, 0)] * ve[0] + me[(r, 1)] * ve[1] + me[(r, 5)] * ve[5];
                }
                ke
            } else {
                me * ve
            };
            let we = self.elem_w[e];
            for &a in &self.paths[f] {
                let val = dot(&self.ev[a], &ke);
                let wa = self.elem_w[a];
                put(mass, &mut self.m_w, wa, we, val);
                put(mass, &mut self.m_w, we, wa, val);
            }
            self.q_w[we] = dot(&self.ev[e], &self.el_p[e]);
        }
        // M = Lᵀ M_w L, Q = Lᵀ Q_w.
        // The z × z block was written into `out` directly; the node-joint rows and columns
        // of M_w (only its structural non-zeros) are added through L.
        let mw = self.m_w.as_slice();
        for &(d, src, k) in &self.mass_map {
            mass[d] += k * mw[src];
        }
        for (w, lw) in self.l_rows.iter().enumerate() {
            let qv = self.q_w[w];
            for &(c, a) in lw {
                out.forces[c] += a * qv;
            }
        }
        if tangents {
            // §4.6: K ≈ blockdiag K_ff, C ≈ blockdiag C_ff on the modal coordinates.
            for b in &self.bodies {
                if b.n == 0 {
                    continue;
                }
                let (o, n) = (b.y_off, b.n);
                let (y, yd) = (&z.as_slice()[o..o + n], &zd.as_slice()[o..o + n]);
                b.body.add_elastic_tangents(
                    y,
                    yd,
                    1.0,
                    0.0,
                    out.stiffness.view_mut((o, o), (n, n)),
                );
                b.body
                    .add_elastic_tangents(y, yd, 0.0, 1.0, out.damping.view_mut((o, o), (n, n)));
            }
        }
        if !self.force_elements.is_empty() {
            let mut force_elements = std::mem::take(&mut self.force_elements);
            force_elements.add_forces(self, z, zd, tangents, out);
            self.force_elements = force_elements;
        }
    }

    /// Add g·Z_k (and the modal coefficients, by the caller) to row `row` of Φ_w; returns g·D_k.
    fn body_row(&mut self, row: usize, body: Option<usize>, g: &Vector6<f64>) -> f64 {
        let Some(k) = body else { return 0.0 };
        let f = self.bodies[k].frame;
        if !self.jac {
            return g.dot(&self.fr_d[f]);
        }
        for &a in &self.paths[f] {
            self.phi_w[(row, self.elem_w[a])] += g.dot(&self.ev[a]);
        }
        g.dot(&self.fr_d[f])
    }

    #[inline(never)]
    fn constraints(&mut self, t: f64, req: Request, out: &mut SystemTerms) {
        self.jac = req.jacobian;
        if req.jacobian {
            self.phi_w.as_mut_slice().fill(0.0);
        }
        let mut row = 0;
        let nt = self.dim.n_trans();
        for ci in 0..self.cons.len() {
            let con = self.cons[ci].clone_light();
            match con {
                ConRef::Point(i, j) => {
                    let (pi, vi) = point_at(self, &i);
                    let (pj, vj) = point_at(self, &j);
                    if req.constraints {
                        for a in 0..nt {
                            out.phi[row + a] = pi[a] - pj[a];
                        }
                    }
                    if req.jacobian || req.accel_term {
                        let bias = self.point_rows(row, &i, &pi, &vi, 1.0)
                            - self.point_rows(row, &j, &pj, &vj, -1.0);
                        if req.accel_term {
                            for a in 0..nt {
                                out.accel_term[row + a] = bias[a];
                            }
                        }
                    }
                }
                ConRef::Angle2(i, j, psi0, law, sign) => {
                    let (th, thd, thdd) = law.eval(t);
                    let (ti, wi) = angle_at(self, &i);
                    let (tj, wj) = angle_at(self, &j);
                    let delta = tj - ti - psi0 - sign * th;
                    let (sd, cd) = delta.sin_cos();
                    if req.constraints {
                        out.phi[row] = sd;
                    }
                    if req.jacobian || req.accel_term {
                        let mut g = Vector6::zeros();
                        g[5] = cd;
                        let mut bias = self.body_row(row, j.body, &g);
                        self.rot_modal(row, &j, cd);
                        g[5] = -cd;
                        bias += self.body_row(row, i.body, &g);
                        self.rot_modal(row, &i, -cd);
                        let rate = wj - wi - sign * thd;
                        if req.jacobian {
                            out.phi_t[row] = -cd * sign * thd;
                        }
                        if req.accel_term {
                            out.accel_term[row] = bias - sd * rate * rate - cd * sign * thdd;
                        }
                    }
                }
                ConRef::Slide(i, nbar, j) => {
                    let (n, nd) = dir_at(self, &i, &nbar);
                    let (pi, vi) = point_at(self, &i);
                    let (pj, vj) = point_at(self, &j);
                    let d = pj - pi;
                    let dd = vj - vi;
                    if req.constraints {
                        out.phi[row] = n.dot(&d);
                    }
                    if req.jacobian || req.accel_term {
                        let mut bias = self.point_row(row, &j, &pj, &vj, &n, 1.0)
                            - self.point_row(row, &i, &pi, &vi, &n, -1.0);
                        bias += self.dir_row(row, &i, &nbar, &n, &nd, &d);
                        bias += 2.0 * nd.dot(&dd);
                        if req.accel_term {
                            out.accel_term[row] = bias;
                        }
                    }
                }
                ConRef::Perp(i, abar, j, bbar) => {
                    let (a, ad) = dir_at(self, &i, &abar);
                    let (b, bd) = dir_at(self, &j, &bbar);
                    if req.constraints {
                        out.phi[row] = a.dot(&b);
                    }
                    if req.jacobian || req.accel_term {
                        let mut bias = self.dir_row(row, &i, &abar, &a, &ad, &b);
                        bias += self.dir_row(row, &j, &bbar, &b, &bd, &a);
                        bias += 2.0 * ad.dot(&bd);
                        if req.accel_term {
                            out.accel_term[row] = bias;
                        }
                    }
                }
                ConRef::Coord(zc, law, sign) => {
                    let (th, thd, thdd) = law.eval(t);
                    if req.constraints {
                        out.phi[row] = self.last_z[zc] - sign * th;
                    }
                    if req.jacobian {
                        self.phi_w[(row, zc)] += 1.0;
                    }
                    if req.jacobian {
                        out.phi_t[row] = -sign * thd;
                    }
                    if req.accel_term {
                        out.accel_term[row] = -sign * thdd;
                    }
                }
            }
            row += self.cons[ci].rows(self.dim);
        }
        if req.jacobian {
            // Φ_z = Φ_w L, L = [I; L_node].
            let nz = self.n_z;
            out.phi_q.copy_from(&self.phi_w.columns(0, nz));
            for w in nz..self.n_w {
                for &(c, a) in &self.l_rows[w] {
                    out.phi_q.column_mut(c).axpy(a, &self.phi_w.column(w), 1.0);
                }
            }
        }
    }

    /// Jacobian rows `row..row + n_trans` of r_P for a point of side `s` (sign `sg` applied
    /// to the rows; one walk of the path for all components), and the Cartesian bias
    /// D_s + D_ω × p + ω × ṙ_P + ω × A X ẏ (returned unsigned).
    fn point_rows(
        &mut self,
        row: usize,
        s: &Side,
        p: &Vector3<f64>,
        v: &Vector3<f64>,
        sg: f64,
    ) -> Vector3<f64> {
        let Some(k) = s.body else {
            return Vector3::zeros();
        };
        let nt = self.dim.n_trans();
        let f = self.bodies[k].frame;
        if self.jac {
            for &a in &self.paths[f] {
                // Velocity of the point per unit rate of elementary joint a.
                let ev = &self.ev[a];
                let u = ev.fixed_rows::<3>(0) + ev.fixed_rows::<3>(3).cross(p);
                let wa = self.elem_w[a];
                for c in 0..nt {
                    self.phi_w[(row + c, wa)] += sg * u[c];
                }
            }
        }
        let d = &self.fr_d[f];
        let w = self.fr_z[f].fixed_rows::<3>(3).into_owned();
        let mut bias = d.fixed_rows::<3>(0) + d.fixed_rows::<3>(3).cross(p) + w.cross(v);
        if let Some(node) = s.node {
            let b = &self.bodies[k];
            let a = self.fr_a[f];
            let mut xy = Vector3::zeros();
            for m in 0..b.n {
                let col = Vector3::new(
                    b.rows.t(node, 0, m),
                    b.rows.t(node, 1, m),
                    b.rows.t(node, 2, m),
                );
                if self.jac {
                    let ac = a * col;
                    for c in 0..nt {
                        self.phi_w[(row + c, b.y_off + m)] += sg * ac[c];
                    }
                }
                xy += col * self.last_zd[b.y_off + m];
            }
            bias += w.cross(&(a * xy));
        }
        bias
    }

    /// Jacobian row of e·r_P for a point of side `s` (sign `sg` applied to the row) and the
    /// Cartesian bias e·(ω × ṙ_P + ω × A X ẏ) + g·D (returned unsigned).
    fn point_row(
        &mut self,
        row: usize,
        s: &Side,
        p: &Vector3<f64>,
        v: &Vector3<f64>,
        e: &Vector3<f64>,
        sg: f64,
    ) -> f64 {
        let Some(k) = s.body else { return 0.0 };
        let mut g = Vector6::zeros();
        g.fixed_rows_mut::<3>(0).copy_from(&(sg * e));
        g.fixed_rows_mut::<3>(3).copy_from(&(sg * p.cross(e)));
        let gd = sg * self.body_row(row, s.body, &g);
        let f = self.bodies[k].frame;
        let a = self.fr_a[f];
        let w = self.fr_z[f].fixed_rows::<3>(3).into_owned();
        let mut bias = gd + e.dot(&w.cross(v));
        if let Some(node) = s.node {
            let b = &self.bodies[k];
            let at_e = a.transpose() * e;
            let mut axy = Vector3::zeros();
            for m in 0..b.n {
                let col = Vector3::new(
                    b.rows.t(node, 0, m),
                    b.rows.t(node, 1, m),
                    b.rows.t(node, 2, m),
                );
                if self.jac {
                    self.phi_w[(row, b.y_off + m)] += sg * at_e.dot(&col);
                }
                axy += col * self.last_zd[b.y_off + m];
            }
            bias += e.dot(&w.cross(&(a * axy)));
        }
        bias
    }

    /// Jacobian row of d·u for a direction d = A (d̄ + θ̄ × d̄) at side `s` (u held fixed),
    /// and its bias terms (D part, ä_bias · u); returned.
    fn dir_row(
        &mut self,
        row: usize,
        s: &Side,
        dbar: &Vector3<f64>,
        d: &Vector3<f64>,
        dd: &Vector3<f64>,
        u: &Vector3<f64>,
    ) -> f64 {
        let Some(k) = s.body else { return 0.0 };
        let mut g = Vector6::zeros();
        g.fixed_rows_mut::<3>(3).copy_from(&d.cross(u));
        let gd = self.body_row(row, s.body, &g);
        let f = self.bodies[k].frame;
        let a = self.fr_a[f];
        let w = self.fr_z[f].fixed_rows::<3>(3).into_owned();
        // ä_bias = ω × ḋ + ω × A (θ̄̇ × d̄).
        let mut extra = Vector3::zeros();
        if let Some(node) = s.node {
            let b = &self.bodies[k];
            let at_u = a.transpose() * u;
            let mut th_d = Vector3::zeros();
            for m in 0..b.n {
                let col = Vector3::new(
                    b.rows.r(node, 0, m),
                    b.rows.r(node, 1, m),
                    b.rows.r(node, 2, m),
                );
                if self.jac {
                    self.phi_w[(row, b.y_off + m)] += at_u.dot(&col.cross(dbar));
                }
                th_d += col * self.last_zd[b.y_off + m];
            }
            extra = a * th_d.cross(dbar);
        }
        gd + (w.cross(dd) + w.cross(&extra)).dot(u)
    }

    /// Modal coefficients of a 2D node rotation, scaled.
    fn rot_modal(&mut self, row: usize, s: &Side, scale: f64) {
        let (Some(k), Some(node)) = (s.body, s.node) else {
            return;
        };
        if !self.jac {
            return;
        }
        let b = &self.bodies[k];
        for m in 0..b.n {
            self.phi_w[(row, b.y_off + m)] += scale * b.rows.r(node, 2, m);
        }
    }

    /// Total mechanical energy: ½ Σ Z_kᵀ M̄_k Z_k + gravity potential + ½ Σ yᵀ K_ff y.
    fn energy(&mut self, z: &DVector<f64>, zd: &DVector<f64>) -> f64 {
        let mut e = 0.0;
        for k in 0..self.bodies.len() {
            let state = self.body_state(k, z, zd);
            let method = self.method;
            let (nr, rmap, g) = (self.nr, self.rmap, self.gravity);
            let zr = self.fr_z[self.bodies[k].frame];
            let b = &mut self.bodies[k];
            b.body.inertia(&state, method, &mut b.m_bar, &mut b.q_bar);
            let nc = nr + b.n;
            let v = |i: usize| {
                if i < nr {
                    zr[rmap[i]]
                } else {
                    state.y_dot[i - nr]
                }
            };
            let mut kin = 0.0;
            for r in 0..nc {
                for c in 0..nc {
                    kin += v(r) * b.m_bar[(r, c)] * v(c);
                }
            }
            e += 0.5 * kin;
            let mb = b.body.first_moment_at(state.y);
            e -= g.dot(&(state.r0 * b.body.mass() + state.a * mb));
            e += b.body.strain_energy(state.y);
        }
        e + self.force_elements.potential_energy(self, z, zd)
    }

    /// Names of the coordinates z (joint coordinates, then `body.y<m>`).
    pub fn coordinate_names(&self) -> &[String] {
        &self.z_names
    }
}

/// A constraint's data, copied out so that `self` can be borrowed mutably.
enum ConRef {
    Point(Side, Side),
    Angle2(Side, Side, f64, MotionLaw, f64),
    Slide(Side, Vector3<f64>, Side),
    Perp(Side, Vector3<f64>, Side, Vector3<f64>),
    Coord(usize, MotionLaw, f64),
}

impl Con {
    fn clone_light(&self) -> ConRef {
        match self {
            Con::Point { i, j } => ConRef::Point(*i, *j),
            Con::Angle2 {
                i,
                j,
                psi0,
                law,
                sign,
            } => ConRef::Angle2(*i, *j, *psi0, law.clone(), *sign),
            Con::Slide { i, nbar, j } => ConRef::Slide(*i, *nbar, *j),
            Con::Perp { i, abar, j, bbar } => ConRef::Perp(*i, *abar, *j, *bbar),
            Con::Coord { z, law, sign } => ConRef::Coord(*z, law.clone(), *sign),
        }
    }
}

/// Global position and velocity of a marker: r = r0 + A (r̄ + X^t y), ṙ = ṡ + ω × r + A X^t ẏ.
pub(crate) fn point_at(rel: &Relative, s: &Side) -> (Vector3<f64>, Vector3<f64>) {
    let Some(k) = s.body else {
        return (s.rbar, Vector3::zeros());
    };
    let b = &rel.bodies[k];
    let f = b.frame;
    let (r0, a, zr) = (rel.fr_r[f], rel.fr_a[f], rel.fr_z[f]);
    let mut pl = s.rbar;
    let mut vl = Vector3::zeros();
    if let Some(node) = s.node {
        for m in 0..b.n {
            let (y, yd) = (rel.last_z[b.y_off + m], rel.last_zd[b.y_off + m]);
            for i in 0..3 {
                pl[i] += b.rows.t(node, i, m) * y;
                vl[i] += b.rows.t(node, i, m) * yd;
            }
        }
        // FS0 (docs/methods.md §6.3): the node's axial shift −½ ē₁ yᵀF y and its rate.
        let ys = b.y_off..b.y_off + b.n;
        let (y, yd) = (
            &rel.last_z.as_slice()[ys.clone()],
            &rel.last_zd.as_slice()[ys],
        );
        if let Some(sh) = b.body.node_foreshortening(node, y, yd) {
            pl += sh.position;
            vl += sh.velocity;
        }
    }
    let p = r0 + a * pl;
    let sd = zr.fixed_rows::<3>(0).into_owned();
    let w = zr.fixed_rows::<3>(3).into_owned();
    (p, sd + w.cross(&p) + a * vl)
}

/// A direction fixed at a marker, d = A (d̄ + θ̄ × d̄) with θ̄ = X^r y, and its rate.
pub(crate) fn dir_at(
    rel: &Relative,
    s: &Side,
    dbar: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let Some(k) = s.body else {
        return (*dbar, Vector3::zeros());
    };
    let b = &rel.bodies[k];
    let f = b.frame;
    let (a, zr) = (rel.fr_a[f], rel.fr_z[f]);
    let w = zr.fixed_rows::<3>(3).into_owned();
    let (mut th, mut thd) = (Vector3::zeros(), Vector3::zeros());
    if let Some(node) = s.node {
        for m in 0..b.n {
            let (y, yd) = (rel.last_z[b.y_off + m], rel.last_zd[b.y_off + m]);
            for i in 0..3 {
                th[i] += b.rows.r(node, i, m) * y;
                thd[i] += b.rows.r(node, i, m) * yd;
            }
        }
    }
    let d = a * (dbar + th.cross(dbar));
    (d, w.cross(&d) + a * thd.cross(dbar))
}

/// 2D: angle of a marker's direction, θ = angle(A) + X^r_z y, and its rate.
pub(crate) fn angle_at(rel: &Relative, s: &Side) -> (f64, f64) {
    let Some(k) = s.body else { return (0.0, 0.0) };
    let b = &rel.bodies[k];
    let f = b.frame;
    let (mut th, mut thd) = (angle_of(&rel.fr_a[f]), rel.fr_z[f][5]);
    if let Some(node) = s.node {
        for m in 0..b.n {
            th += b.rows.r(node, 2, m) * rel.last_z[b.y_off + m];
            thd += b.rows.r(node, 2, m) * rel.last_zd[b.y_off + m];
        }
    }
    (th, thd)
}

impl flexmbd_core::Formulation for Relative {
    fn n_coordinates(&self) -> usize {
        self.n_z
    }
    fn n_constraints(&self) -> usize {
        self.n_con
    }
    fn initial_guess(&self, q: &mut DVector<f64>, qd: &mut DVector<f64>) {
        q.copy_from(&self.q0);
        qd.copy_from(&self.qd0);
    }
    fn specified_coordinates(&self) -> &[usize] {
        &self.held
    }
    fn symmetric_tangent(&self) -> bool {
        self.bodies
            .iter()
            .all(|b| b.body.elastic_model().is_symmetric())
    }
    fn constant_tangents(&self) -> bool {
        // K ≈ blockdiag K_ff, C ≈ blockdiag C_ff (§4.6): constant for rigid bodies and
        // linear elasticity, state-dependent for the stiffening models.
        self.bodies
            .iter()
            .all(|b| b.body.elastic_model().is_linear())
            && self.force_elements.is_empty()
    }
    fn evaluate(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        req: Request,
        out: &mut SystemTerms,
    ) {
        // Only the work the request needs: positions (and twists) when z changed, velocities
        // and D only for M, Q or c, and when z or ż changed.
        self.last_zd.copy_from(qd);
        self.update_positions(q);
        if req.dynamics || req.accel_term {
            self.update_velocities();
        }
        if req.dynamics {
            self.dynamics(q, qd, req.tangents, out);
        }
        if req.constraints || req.jacobian || req.accel_term {
            self.constraints(t, req, out);
        }
    }
    fn sensor_names(&self) -> &[String] {
        &self.sensor_names
    }
    fn sensors(&mut self, _t: f64, q: &DVector<f64>, qd: &DVector<f64>, out: &mut [f64]) {
        self.last_z.copy_from(q);
        self.last_zd.copy_from(qd);
        self.kinematics(q, qd);
        for k in 0..self.sensors.len() {
            let frame_of = |rel: &Relative, fb: Option<usize>| {
                fb.map(|b| {
                    let f = rel.bodies[b].frame;
                    (rel.fr_r[f], rel.fr_a[f])
                })
            };
            out[k] = match &self.sensors[k] {
                SensorRt::Position { side, axis, frame } => {
                    let (p, _) = point_at(self, side);
                    match frame_of(self, *frame) {
                        None => p[*axis],
                        Some((r0, a)) => (a.transpose() * (p - r0))[*axis],
                    }
                }
                SensorRt::Velocity { side, axis, frame } => {
                    let (_, v) = point_at(self, side);
                    match frame_of(self, *frame) {
                        None => v[*axis],
                        Some((_, a)) => (a.transpose() * v)[*axis],
                    }
                }
                SensorRt::Angle2 { i, j, psi0, .. } => {
                    let (ti, _) = angle_at(self, i);
                    let (tj, _) = angle_at(self, j);
                    let raw = tj - ti - psi0;
                    let d = Vector2::new(raw.cos(), raw.sin());
                    let a = d.y.atan2(d.x);
                    let SensorRt::Angle2 { last, turns, .. } = &mut self.sensors[k] else {
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
                SensorRt::Coord { z, sign } => sign * q[*z],
                SensorRt::Slide { i, nbar, j, d0 } => {
                    let (n, _) = dir_at(self, i, nbar);
                    let (pi, _) = point_at(self, i);
                    let (pj, _) = point_at(self, j);
                    n.dot(&(pj - pi)) - d0
                }
                SensorRt::Modal(idx) => idx.map_or(0.0, |i| q[i]),
                SensorRt::Energy => self.energy(q, qd),
            };
        }
    }
}

/// Inspection, for tests and tools (allocates; not on the per-step path).
impl Relative {
    /// Number of bodies.
    pub fn n_bodies(&self) -> usize {
        self.bodies.len()
    }
    /// Rigid velocity entries per body: 3 (2D: ṡx, ṡy, ωz) or 6 (3D: ṡ, ω).
    pub fn rigid_size(&self) -> usize {
        self.nr
    }
    /// First modal coordinate of body k in z, and its number of modes.
    pub fn body_modes(&self, k: usize) -> (usize, usize) {
        (self.bodies[k].y_off, self.bodies[k].n)
    }
    /// Body k's velocity Z_k = {ṡ; ω; ẏ} and its velocity-product acceleration
    /// {D_k; 0} = (Ṙ ż)_k at (z, ż), in the body-term order of `flexmbd-body`.
    pub fn body_velocity(
        &mut self,
        z: &DVector<f64>,
        zd: &DVector<f64>,
        k: usize,
    ) -> (DVector<f64>, DVector<f64>) {
        self.last_z.copy_from(z);
        self.last_zd.copy_from(zd);
        self.kinematics(z, zd);
        let b = &self.bodies[k];
        let (zr, d) = (self.fr_z[b.frame], self.fr_d[b.frame]);
        let nc = self.nr + b.n;
        let mut v = DVector::zeros(nc);
        let mut dv = DVector::zeros(nc);
        for i in 0..self.nr {
            v[i] = zr[self.rmap[i]];
            dv[i] = d[self.rmap[i]];
        }
        for m in 0..b.n {
            v[self.nr + m] = zd[b.y_off + m];
        }
        (v, dv)
    }
    /// Body k's M̄_k and Q̄_k (inertia, gravity, elastic forces) in the s form at (z, ż).
    pub fn body_terms(
        &mut self,
        z: &DVector<f64>,
        zd: &DVector<f64>,
        k: usize,
    ) -> (DMatrix<f64>, DVector<f64>) {
        self.last_z.copy_from(z);
        self.last_zd.copy_from(zd);
        self.kinematics(z, zd);
        self.evaluate_bodies(z, zd);
        (self.bodies[k].m_bar.clone(), self.bodies[k].q_bar.clone())
    }
    /// Total mechanical energy at (z, ż) (the `Energy` sensor).
    pub fn total_energy(&mut self, z: &DVector<f64>, zd: &DVector<f64>) -> f64 {
        self.last_z.copy_from(z);
        self.last_zd.copy_from(zd);
        self.kinematics(z, zd);
        self.energy(z, zd)
    }
}
