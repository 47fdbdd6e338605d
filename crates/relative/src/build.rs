//! Compiling a prepared scene (docs/methods.md §4.4, §4.5): the bodies and their node rows,
//! the coordinates z and w = L ż, the cut-joint and driver constraints, the tree of elementary
//! joints over which §4.5 step 5 accumulates, the workspace (sized once, so that the pass
//! allocates nothing) and the initial state.

use flexmbd_core::Dim;
use flexmbd_model::force_elements::ForceElements;
use flexmbd_model::{JointKind, MarkerId, ModelError, MotionLaw, PreparedScene};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Rotation3, Vector3, Vector6};

use crate::constraints::Con;
use crate::cut_joints::perpendiculars;
use crate::kinematics::angle_of;
use crate::marker_kinematics::MarkerJacobian;
use crate::system::{BodyRt, Relative, unsupported};
use crate::topology::{BodyInfo, CoordRef, ElemKind, FrameKind, NodeRows, Side, Topology, side_of};

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
    pub(crate) fn build_force_elements(
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
    pub(crate) fn build_mass_map(&self) -> Vec<(usize, usize, f64)> {
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
}
