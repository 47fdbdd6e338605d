//! The augmented kinematic tree of a scene (docs/methods.md §4.2–§4.4): the spanning tree
//! of the joints, chosen breadth-first from the ground, and the chain of frames it
//! implies.
//!
//! Every frame of the augmented tree is its parent frame followed by either a
//! constant transform (`Fixed`: r = r_p + A_p ō, A = A_p C) or one **elementary
//! joint** (`Elem`): a revolute about, or a prismatic along, an axis ā fixed in the
//! parent frame. An elementary joint's value is a linear combination of the
//! coordinates z, e = Σ_c L_ec z_c:
//!
//! - a joint coordinate is an elementary joint with one unit coefficient;
//! - the node frame of a flexible parent at node P (§4.3) is a chain of prismatics
//!   along the parent's body axes with values X^t_{P,a} y (exact: node translations are
//!   linear in y), followed, when the joint transmits rotations, by revolutes about the
//!   successive node axes with values X^r_{P,a} y (Cardan form of §4.3 with Ā_P0 = I;
//!   in 2D the single rotation about z is exact). With Craig–Bampton modes and a joint
//!   node in the boundary set, only P's static modes have non-zero rows, and this is
//!   §4.3 verbatim; any other non-zero row (a child hanging from a node outside the
//!   boundary set) is carried the same way;
//! - the frame of a child hung at a node Q that moves with the child's *own* modes (a beam
//!   or an imported body with `reference: Buckens`, whose floating frame is the linearised mean axes and sits
//!   at no node) is placed by the inverse node chain, J = B ∘ node_Q(y) solved for B:
//!   revolutes about the node axes by −X^r_{Q,a} y in reverse order (when the joint
//!   transmits rotations or is driven), the offset −r̄_Q, then prismatics along the child's
//!   axes by −X^t_{Q,a} y (`Topology::inverse_node_elems`). The rotation is the same
//!   Cardan product as a parent node's (exact in 2D), so it agrees with the absolute
//!   formulation's attachment, A (I + θ̃_Q) ā with θ_Q = X^r_Q y, to the first order in y
//!   that the floating frame's model keeps.
//!
//! So the velocity transformation is Z = R_w w with w = L ż, where R_w has one twist
//! per elementary joint and one owner per modal coordinate (§4.4), and L is constant.
//!
//! **Spanning tree.** Bodies are added layer by layer from the ground. A body is
//! reached through one of the joints to bodies already in the tree, preferring (1)
//! joints whose child-side marker can carry the child's frame (for a flexible child:
//! a node where every mode row the joint transmits is zero, i.e. the frame's reference
//! node), (2) joints with degrees of freedom, (3) scene order. A Buckens body, which no
//! marker carries directly, joins through its inverse node chain, in a layer of its own
//! when no body of the layer can join directly. All remaining joints are
//! cut into constraints (§4.6). A body with no joints at all is a floating base
//! (2D: x, y, θ; 3D: x, y, z and three Cardan angles about the ground axes); any other
//! body the tree does not reach is refused.

use flexmbd_body::NodeRows;
use flexmbd_core::Dim;
use flexmbd_model::{JointKind, MarkerId, ModelError, PreparedScene, Scene};
use nalgebra::{Matrix3, Vector3};

/// Elementary joint type (docs/methods.md §4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ElemKind {
    Revolute,
    Prismatic,
}

/// A coordinate while the tree is being built (resolved to an index of z later).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CoordRef {
    /// The k-th joint coordinate.
    Joint(usize),
    /// Mode m of body b.
    Mode(usize, usize),
}

/// One elementary joint of the augmented tree.
#[derive(Clone, Debug)]
pub(crate) struct Elem {
    pub(crate) kind: ElemKind,
    /// Unit axis in the parent frame's components.
    pub(crate) axis: Vector3<f64>,
    /// The frame it creates.
    pub(crate) frame: usize,
    /// Its value as Σ coefficient · coordinate.
    pub(crate) rate: Vec<(CoordRef, f64)>,
}

#[derive(Clone, Debug)]
pub(crate) enum FrameKind {
    /// r = r_p + A_p offset, A = A_p rot.
    Fixed {
        offset: Vector3<f64>,
        rot: Matrix3<f64>,
    },
    /// The parent frame moved by elementary joint k.
    Elem(usize),
}

#[derive(Clone, Debug)]
pub(crate) struct Frame {
    /// `None`: the ground.
    pub(crate) parent: Option<usize>,
    pub(crate) kind: FrameKind,
}

/// A marker as the relative formulation sees it: a ground point, or a body point (at an FE
/// node on a flexible body).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Side {
    /// `None`: the ground (then `rbar` is in ground components).
    pub(crate) body: Option<usize>,
    /// Undeformed position, body components.
    pub(crate) rbar: Vector3<f64>,
    /// FE node of a flexible body's marker.
    pub(crate) node: Option<usize>,
    /// Its row in the marker table, for a marker the force elements read
    /// (`marker_table.rs`); `None` for the others.
    pub(crate) slot: Option<usize>,
}

/// A joint of the spanning tree.
#[derive(Clone, Debug)]
pub(crate) struct TreeJoint {
    /// Joint coordinates it owns (indices into the joint-coordinate list).
    pub(crate) coords: Vec<usize>,
    /// The tree parent is the joint's body2.
    pub(crate) reversed: bool,
}

/// The mode coefficients of translation (`rotation` false) or rotation component `a` at a
/// node that the tree must carry: those above 1e-12 of the body's largest node-row entry.
pub(crate) fn nonzero_rows(
    rows: &NodeRows,
    node: usize,
    a: usize,
    rotation: bool,
) -> Vec<(usize, f64)> {
    let tiny = 1e-12 * rows.largest_entry().max(1e-300);
    let row = if rotation {
        rows.rotation_row(node, a)
    } else {
        rows.translation_row(node, a)
    };
    row.iter()
        .enumerate()
        .filter_map(|(m, &v)| (v.abs() > tiny).then_some((m, v)))
        .collect()
}

/// The built tree.
pub(crate) struct Topology {
    pub(crate) frames: Vec<Frame>,
    pub(crate) elems: Vec<Elem>,
    /// Frame of each body.
    pub(crate) body_frame: Vec<usize>,
    /// Number of joint coordinates.
    pub(crate) n_joint: usize,
    /// For each scene joint: `Some` if in the tree.
    pub(crate) tree: Vec<Option<TreeJoint>>,
    /// Cut joints (scene indices).
    pub(crate) cuts: Vec<usize>,
    /// Elementary joint of each joint coordinate.
    pub(crate) coord_elem: Vec<usize>,
}

/// The axes of a node chain's rotations, in order: none when it does not turn, z in 2D, the
/// Cardan x, y′, z″ in 3D (docs/methods.md §4.3).
fn node_rotation_axes(dim: Dim, turns: bool) -> &'static [usize] {
    match (turns, dim) {
        (false, _) => &[],
        (true, Dim::Planar) => &[2],
        (true, Dim::Spatial) => &[0, 1, 2],
    }
}

/// Does the joint pass rotations from parent to child (so the node frame must turn)?
pub(crate) fn transmits_rotation(dim: Dim, kind: &JointKind) -> bool {
    match dim {
        Dim::Planar => !matches!(kind, JointKind::Revolute { .. }),
        Dim::Spatial => !matches!(kind, JointKind::Spherical),
    }
}

fn unit(v: Vector3<f64>, what: &str) -> Result<Vector3<f64>, ModelError> {
    let n = v.norm();
    if !(n.is_finite() && n > 1e-12) {
        return Err(ModelError::Unsupported(format!(
            "{what}: the axis {:?} has no direction",
            v.as_slice()
        )));
    }
    Ok(v / n)
}

/// Inputs of the tree builder.
pub(crate) struct BodyInfo {
    pub(crate) name: String,
    pub(crate) flexible: bool,
    pub(crate) n_modes: usize,
    pub(crate) r0: Vector3<f64>,
    pub(crate) a0: Matrix3<f64>,
    pub(crate) center_of_mass: Vector3<f64>,
    /// Initial angular velocity guess (ground components).
    pub(crate) omega0: Vector3<f64>,
    pub(crate) markers: Vec<Side>,
    pub(crate) node_rows: NodeRows,
}

impl Side {
    /// A marker of the prepared scene as this formulation sees it: a ground point, or the
    /// body's compiled marker (`bodies` in the scene's body order).
    pub(crate) fn at(prepared: &PreparedScene, bodies: &[BodyInfo], marker: MarkerId) -> Side {
        match marker.body {
            None => Side {
                body: None,
                rbar: prepared.marker_position(marker),
                node: None,
                slot: None,
            },
            Some(b) => bodies[b.0].markers[marker.index],
        }
    }
}

impl Topology {
    /// Choose the spanning tree and build the augmented frames.
    pub(crate) fn build(
        prepared: &PreparedScene,
        bodies: &[BodyInfo],
    ) -> Result<Topology, ModelError> {
        let scene = prepared.scene();
        let dim = scene.dim;
        let nb = bodies.len();
        let SpanningTree {
            order,
            used,
            floating,
        } = spanning_tree(prepared, bodies)?;
        let mut t = Topology {
            frames: Vec::new(),
            elems: Vec::new(),
            body_frame: vec![usize::MAX; nb],
            n_joint: 0,
            tree: vec![None; scene.joints.len()],
            cuts: (0..scene.joints.len()).filter(|&j| !used[j]).collect(),
            coord_elem: Vec::new(),
        };
        for &b in &floating {
            t.add_floating(dim, b, &bodies[b]);
        }
        for &(ji, reversed) in &order {
            t.add_tree_joint(prepared, bodies, ji, reversed)?;
        }
        Ok(t)
    }

    fn push_frame(&mut self, parent: Option<usize>, kind: FrameKind) -> usize {
        self.frames.push(Frame { parent, kind });
        self.frames.len() - 1
    }

    fn push_elem(
        &mut self,
        parent: Option<usize>,
        kind: ElemKind,
        axis: Vector3<f64>,
        rate: Vec<(CoordRef, f64)>,
    ) -> usize {
        let e = self.elems.len();
        let f = self.push_frame(parent, FrameKind::Elem(e));
        self.elems.push(Elem {
            kind,
            axis,
            frame: f,
            rate,
        });
        f
    }

    fn joint_elem(
        &mut self,
        parent: Option<usize>,
        kind: ElemKind,
        axis: Vector3<f64>,
        coords: &mut Vec<usize>,
    ) -> usize {
        let k = self.n_joint;
        self.n_joint += 1;
        coords.push(k);
        let f = self.push_elem(parent, kind, axis, vec![(CoordRef::Joint(k), 1.0)]);
        self.coord_elem.push(self.elems.len() - 1);
        f
    }

    /// The elementary joints of a floating base after frame `f`: translations along, then
    /// intrinsic rotations about (x, y′, z″; 2D: z), the axes of `f`. Returns the last frame.
    fn free_elems(&mut self, dim: Dim, mut f: usize, coords: &mut Vec<usize>) -> usize {
        for a in 0..dim.n_trans() {
            f = self.joint_elem(Some(f), ElemKind::Prismatic, Vector3::ith(a, 1.0), coords);
        }
        let axes: &[usize] = match dim {
            Dim::Planar => &[2],
            Dim::Spatial => &[0, 1, 2],
        };
        for &a in axes {
            f = self.joint_elem(Some(f), ElemKind::Revolute, Vector3::ith(a, 1.0), coords);
        }
        f
    }

    fn add_floating(&mut self, dim: Dim, b: usize, info: &BodyInfo) {
        let mut coords = Vec::new();
        let mut f = self.push_frame(
            None,
            FrameKind::Fixed {
                offset: info.r0,
                rot: Matrix3::identity(),
            },
        );
        f = self.free_elems(dim, f, &mut coords);
        let bf = self.push_frame(
            Some(f),
            FrameKind::Fixed {
                offset: Vector3::zeros(),
                rot: info.a0,
            },
        );
        self.body_frame[b] = bf;
    }

    /// The node frame of a flexible parent at the parent marker's node (§4.3): prismatics
    /// along the parent's body axes with values X^t_{P,a} y, then, when the joint turns the
    /// node frame (`turns`), revolutes about the node axes with values X^r_{P,a} y; only the
    /// non-zero rows. Returns the last frame (`f` for a rigid parent).
    fn node_elems(
        &mut self,
        dim: Dim,
        bodies: &[BodyInfo],
        ps: &Side,
        mut f: usize,
        turns: bool,
    ) -> usize {
        if let (Some(pb), Some(node)) = (ps.body, ps.node)
            && bodies[pb].flexible
        {
            let rows = &bodies[pb].node_rows;
            let translations = (0..dim.n_trans()).map(|a| (a, false, ElemKind::Prismatic));
            let rotations = node_rotation_axes(dim, turns)
                .iter()
                .map(|&a| (a, true, ElemKind::Revolute));
            for (a, rotation, kind) in translations.chain(rotations) {
                let nz = nonzero_rows(rows, node, a, rotation);
                if !nz.is_empty() {
                    let rate = nz
                        .iter()
                        .map(|&(m, v)| (CoordRef::Mode(pb, m), v))
                        .collect();
                    f = self.push_elem(Some(f), kind, Vector3::ith(a, 1.0), rate);
                }
            }
        }
        f
    }

    /// The frame of a child whose marker Q (at FE node `cs.node`) moves with the child's own
    /// modes (a Buckens body), after the joint frame J at Q: the inverse of the node chain
    /// J = B ∘ node_Q(y) of [`node_elems`](Self::node_elems). With C = A_J0ᵀ A_B0 the
    /// t = 0 turn from J's axes to the child's,
    ///
    /// ```text
    /// A_B = A_J C R_Q(y)⁻¹,  r_B = r_J − A_B (r̄_Q + X^t_Q y)
    /// R_Q(y) = R_x(X^r_x y) R_y(X^r_y y) R_z(X^r_z y)   (3D; 2D: R_z(X^r_z y), exact)
    /// ```
    ///
    /// as elementary joints of rates linear in the child's ẏ: revolutes about z, y, x of
    /// the node frame by −X^r_a y (when the joint transmits rotations or is driven, as
    /// for a parent node; otherwise the joint's own coordinates carry the child's
    /// orientation and C alone turns it), the fixed offset −r̄_Q, and prismatics along the
    /// child's axes by −X^t_a y. So ω_B = ω_J − A_B X^r_Q ẏ to first order (exactly in 2D)
    /// and ṙ_B = ṙ_J − ω_B × A_B (r̄_Q + X^t_Q y) − A_B X^t_Q ẏ. Returns the child's frame.
    fn inverse_node_elems(
        &mut self,
        dim: Dim,
        bodies: &[BodyInfo],
        cs: &Side,
        mut f: usize,
        (c, turns): (Matrix3<f64>, bool),
    ) -> usize {
        let (Some(b), Some(node)) = (cs.body, cs.node) else {
            unreachable!("an inverse node chain is built for a marker at a node");
        };
        let rows = &bodies[b].node_rows;
        // The node's axes: J's turned by C.
        f = self.push_frame(
            Some(f),
            FrameKind::Fixed {
                offset: Vector3::zeros(),
                rot: c,
            },
        );
        let rotations = node_rotation_axes(dim, turns)
            .iter()
            .rev()
            .map(|&a| (a, true, ElemKind::Revolute));
        for (a, rotation, kind) in rotations {
            f = self.elem_against_modes(f, kind, (b, rows), (node, a, rotation));
        }
        f = self.push_frame(
            Some(f),
            FrameKind::Fixed {
                offset: -cs.rbar,
                rot: Matrix3::identity(),
            },
        );
        for a in 0..dim.n_trans() {
            f = self.elem_against_modes(f, ElemKind::Prismatic, (b, rows), (node, a, false));
        }
        f
    }

    /// After frame `f`, an elementary joint along (or about) axis `a` of value −X_a y, X_a
    /// the translation (or rotation) row `a` of body `b` at `node`; none when the row is
    /// zero. Returns the last frame.
    fn elem_against_modes(
        &mut self,
        f: usize,
        kind: ElemKind,
        (b, rows): (usize, &NodeRows),
        (node, a, rotation): (usize, usize, bool),
    ) -> usize {
        let nz = nonzero_rows(rows, node, a, rotation);
        if nz.is_empty() {
            return f;
        }
        let rate = nz
            .iter()
            .map(|&(m, v)| (CoordRef::Mode(b, m), -v))
            .collect();
        self.push_elem(Some(f), kind, Vector3::ith(a, 1.0), rate)
    }

    /// The elementary joints of tree joint `ji` (run from `ps` to `cs`, `reversed` when
    /// that is body2 → body1) after frame `f`, their coordinates pushed to `coords`.
    /// Returns the last frame.
    fn joint_elems(
        &mut self,
        scene: &Scene,
        bodies: &[BodyInfo],
        (ji, reversed): (usize, bool),
        (ps, cs): (&Side, &Side),
        mut f: usize,
        coords: &mut Vec<usize>,
    ) -> Result<usize, ModelError> {
        let dim = scene.dim;
        let j = &scene.joints[ji];
        let child = cs.body.expect("a tree child is a body");
        let a_parent0 = ps.body.map_or(Matrix3::identity(), |b| bodies[b].a0);
        let local = |v: Vector3<f64>| a_parent0.transpose() * v;
        let what = format!("joint `{}`", j.name);
        match (&j.kind, dim) {
            (JointKind::Revolute { .. }, Dim::Planar) => {
                f = self.joint_elem(Some(f), ElemKind::Revolute, Vector3::z(), coords);
            }
            (JointKind::Revolute { axis }, Dim::Spatial) => {
                let axis = axis.ok_or_else(|| {
                    ModelError::Unsupported(format!("{what}: a 3D revolute joint needs an axis"))
                })?;
                let a = unit(local(axis.vec()), &what)?;
                f = self.joint_elem(Some(f), ElemKind::Revolute, a, coords);
            }
            (JointKind::Prismatic { axis }, _) => {
                let mut v = axis.vec();
                if dim == Dim::Planar {
                    v.z = 0.0;
                }
                let a = unit(local(v), &what)?;
                f = self.joint_elem(Some(f), ElemKind::Prismatic, a, coords);
            }
            (JointKind::Cylindrical { axis }, Dim::Spatial) => {
                let a = unit(local(axis.vec()), &what)?;
                f = self.joint_elem(Some(f), ElemKind::Prismatic, a, coords);
                f = self.joint_elem(Some(f), ElemKind::Revolute, a, coords);
            }
            (JointKind::Universal { axis1, axis2 }, Dim::Spatial) => {
                // The first rotation is about the arm fixed in the tree parent.
                let (p_arm, c_arm) = if reversed {
                    (axis2, axis1)
                } else {
                    (axis1, axis2)
                };
                let a1 = unit(local(p_arm.vec()), &what)?;
                let a2 = unit(local(c_arm.vec()), &what)?;
                if a1.dot(&a2).abs() > 1e-6 {
                    return Err(ModelError::Unsupported(format!(
                        "{what}: the universal joint's arms must be perpendicular"
                    )));
                }
                f = self.joint_elem(Some(f), ElemKind::Revolute, a1, coords);
                f = self.joint_elem(Some(f), ElemKind::Revolute, a2, coords);
            }
            (JointKind::Spherical, Dim::Spatial) => {
                // Three intrinsic rotations (§4.2); the middle angle is singular at ±π/2, so
                // the middle axis is the P0 axis about which the child turns slowest at
                // t = 0 (relative angular velocity of the scene's guess), ties going to the
                // axis best aligned with the line from the joint to the child's centre of
                // mass (a bar's twist, small in practice; the prototype's y, x′, z″).
                let info = &bodies[child];
                let joint_point = info.r0 + info.a0 * cs.rbar;
                let lever = local(info.r0 + info.a0 * info.center_of_mass - joint_point);
                let lever = lever / lever.norm().max(1e-300);
                let w_parent = ps.body.map_or(Vector3::zeros(), |b| bodies[b].omega0);
                let w_rel = local(info.omega0 - w_parent);
                let w_scale = w_rel.norm().max(1e-300);
                let score = |a: usize| w_rel[a].abs() / w_scale + 1e-3 * (1.0 - lever[a].abs());
                let mid = (0..3)
                    .min_by(|&a, &b| score(a).total_cmp(&score(b)))
                    .expect("three axes");
                for a in [(mid + 1) % 3, mid, (mid + 2) % 3] {
                    f = self.joint_elem(Some(f), ElemKind::Revolute, Vector3::ith(a, 1.0), coords);
                }
            }
            (JointKind::Rigid, _) => {}
            // A floating base, in the ground marker's axes (as a body without joints).
            (JointKind::Free, _) => f = self.free_elems(dim, f, coords),
            (k, d) => {
                return Err(ModelError::Unsupported(format!(
                    "{what}: {k:?} is not a {d} joint"
                )));
            }
        }
        Ok(f)
    }

    fn add_tree_joint(
        &mut self,
        prepared: &PreparedScene,
        bodies: &[BodyInfo],
        ji: usize,
        reversed: bool,
    ) -> Result<(), ModelError> {
        let scene = prepared.scene();
        let dim = scene.dim;
        let j = &scene.joints[ji];
        let ends = prepared.joint_markers()[ji];
        let (s1, s2) = (
            Side::at(prepared, bodies, ends.first),
            Side::at(prepared, bodies, ends.second),
        );
        let (ps, cs) = if reversed { (s2, s1) } else { (s1, s2) };
        let child = cs.body.expect("a tree child is a body");
        let parent_frame = ps.body.map(|b| self.body_frame[b]);
        let a_parent0 = ps.body.map_or(Matrix3::identity(), |b| bodies[b].a0);
        // Node frame P0 at the parent marker.
        let mut f = self.push_frame(
            parent_frame,
            FrameKind::Fixed {
                offset: ps.rbar,
                rot: Matrix3::identity(),
            },
        );
        // Static modes (and any other non-zero node rows) of a flexible parent, §4.3.
        let driven = scene.drivers.iter().any(|d| d.joint == j.name);
        let turns = transmits_rotation(dim, &j.kind) || driven;
        f = self.node_elems(dim, bodies, &ps, f, turns);
        // The joint's elementary joints, axes in P0 components at t = 0.
        let mut coords = Vec::new();
        f = self.joint_elems(scene, bodies, (ji, reversed), (&ps, &cs), f, &mut coords)?;
        // The child's frame: A_j = A_J C, r_j = r_J − A_j r̄_Q, or through the inverse node
        // chain of its own modes.
        let info = &bodies[child];
        let c = a_parent0.transpose() * info.a0;
        let bf = match carriage(prepared, bodies, ji, !reversed) {
            Carriage::InverseChain => {
                if scene.solver.stiffening == flexmbd_model::Stiffening::Foreshortening {
                    return Err(ModelError::Unsupported(format!(
                        "{}: flexible body `{}` has `reference: Buckens` and hangs from joint `{}` at a node that moves with its modes; with `stiffening: Foreshortening` (FS0) that node also moves by its axial shift, quadratic in the modes, which the relative formulation's inverse node chain (linear in the modes) does not carry: use `--formulation absolute`, `reference: InterfaceFixed` or another stiffening method",
                        scene.origin, info.name, j.name
                    )));
                }
                self.inverse_node_elems(dim, bodies, &cs, f, (c, turns))
            }
            _ => self.push_frame(
                Some(f),
                FrameKind::Fixed {
                    offset: -(c * cs.rbar),
                    rot: c,
                },
            ),
        };
        self.body_frame[child] = bf;
        self.tree[ji] = Some(TreeJoint { coords, reversed });
        Ok(())
    }
}

/// How a tree joint carries its child's frame at the child's marker; the spanning tree
/// prefers `Directly` to `InverseChain` (ordered so).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Carriage {
    /// It cannot: a flexible child whose marker moves with its modes, not a Buckens body.
    No,
    /// Through the inverse node chain of the child's own modes
    /// (`Topology::inverse_node_elems`): a Buckens body, whose every node moves with its
    /// modes.
    InverseChain,
    /// At the marker: a rigid child, or a node where every mode row the joint transmits is
    /// zero (the frame's reference node).
    Directly,
}

/// How joint `ji` can carry its child's frame at the child's marker (`child_is_body2`: the
/// child is the joint's body2): see [`Carriage`].
fn carriage(
    prepared: &PreparedScene,
    bodies: &[BodyInfo],
    ji: usize,
    child_is_body2: bool,
) -> Carriage {
    let scene = prepared.scene();
    let dim = scene.dim;
    let j = &scene.joints[ji];
    let ends = prepared.joint_markers()[ji];
    let child = if child_is_body2 {
        ends.second
    } else {
        ends.first
    };
    let side = Side::at(prepared, bodies, child);
    let Some(b) = side.body else {
        return Carriage::No;
    };
    let info = &bodies[b];
    if !info.flexible {
        return Carriage::Directly;
    }
    let Some(node) = side.node else {
        return Carriage::No;
    };
    let nt = dim.n_trans();
    let rot = transmits_rotation(dim, &j.kind);
    let zero_rows = (0..nt).all(|a| nonzero_rows(&info.node_rows, node, a, false).is_empty())
        && (!rot
            || match dim {
                Dim::Planar => nonzero_rows(&info.node_rows, node, 2, true).is_empty(),
                Dim::Spatial => {
                    (0..3).all(|a| nonzero_rows(&info.node_rows, node, a, true).is_empty())
                }
            });
    if zero_rows {
        Carriage::Directly
    } else if is_buckens(scene, b) {
        Carriage::InverseChain
    } else {
        Carriage::No
    }
}

/// Are body `b`'s modes mean-axis ones, so that its frame sits at no node: a beam or an
/// imported body with `reference: Buckens`, or an imported body with `frame: FreeFree`, whose
/// modes satisfy the conditions whatever its `reference` says.
fn is_buckens(scene: &Scene, b: usize) -> bool {
    use flexmbd_model::{BodyModel, ImportedFrame, ReferenceCondition::Buckens};
    match &scene.bodies[b].model {
        BodyModel::Beam(spec) => spec.reference == Buckens,
        BodyModel::Imported(spec) => {
            spec.reference == Buckens || matches!(spec.frame, ImportedFrame::FreeFree)
        }
        _ => false,
    }
}

/// The spanning tree chosen breadth-first from the ground (see the module doc).
struct SpanningTree {
    /// (joint, reversed) in the order bodies join the tree.
    order: Vec<(usize, bool)>,
    /// Per joint: in the tree (the others are cut).
    used: Vec<bool>,
    /// Bodies without joints (floating bases).
    floating: Vec<usize>,
}

/// Choose the spanning tree: layer by layer from the ground, each body through its best
/// joint to the bodies already in the tree.
fn spanning_tree(
    prepared: &PreparedScene,
    bodies: &[BodyInfo],
) -> Result<SpanningTree, ModelError> {
    let scene = prepared.scene();
    let nb = bodies.len();
    let ends: Vec<(Option<usize>, Option<usize>)> = prepared
        .joint_markers()
        .iter()
        .map(|p| (p.first.body.map(|b| b.0), p.second.body.map(|b| b.0)))
        .collect();
    let mut in_tree = vec![false; nb];
    let mut used = vec![false; scene.joints.len()];
    // (joint, reversed) in the order bodies join the tree.
    let mut order: Vec<(usize, bool)> = Vec::new();
    loop {
        // Candidate joints: one end in the tree (or ground), the other not.
        let mut best: Vec<Option<(Carriage, bool, usize, bool)>> = vec![None; nb];
        for (ji, &(b1, b2)) in ends.iter().enumerate() {
            if used[ji] {
                continue;
            }
            let reached = |b: Option<usize>| b.is_none_or(|b| in_tree[b]);
            let (child, reversed) = match (reached(b1), reached(b2)) {
                (true, false) => (b2.expect("not ground"), false),
                (false, true) => (b1.expect("not ground"), true),
                _ => continue,
            };
            let carried = carriage(prepared, bodies, ji, !reversed);
            let has_dof = !matches!(scene.joints[ji].kind, JointKind::Rigid);
            let key = (carried, has_dof, ji, reversed);
            let better = match best[child] {
                None => true,
                Some((v, d, _, _)) => (carried, has_dof) > (v, d),
            };
            if better {
                best[child] = Some(key);
            }
        }
        // The bodies carried directly join first; only when none can (so never in a scene
        // that ran before the inverse chain), those carried by an inverse node chain.
        let mut added = false;
        for level in [Carriage::Directly, Carriage::InverseChain] {
            for (child, b) in best.iter().enumerate() {
                let Some((carried, _, ji, reversed)) = *b else {
                    continue;
                };
                if carried != level {
                    continue;
                }
                in_tree[child] = true;
                used[ji] = true;
                order.push((ji, reversed));
                added = true;
            }
            if added {
                break;
            }
        }
        if !added {
            // Flexible bodies reachable only through markers that cannot carry their frame.
            if let Some((child, Some((_, _, ji, _)))) =
                best.iter().enumerate().find(|(_, b)| b.is_some())
            {
                return Err(ModelError::Unsupported(format!(
                    "{}: flexible body `{}` can only join the kinematic tree through joint `{}`, whose marker on it is not where its frame is attached; the relative formulation needs the joint to its parent where the frame is attached: a beam's `frame: Clamped(node: ..)` at that marker's node, an imported body's `frame: Interface(NAME)` with the marker on that interface, or a body whose frame sits at no node (`reference: Buckens`, an imported `frame: FreeFree`), hung through its own modes; otherwise give it no joint to a parent (a body without joints floats), or use the absolute formulation",
                    scene.origin, bodies[child].name, scene.joints[*ji].name
                )));
            }
            break;
        }
    }
    let mut floating = Vec::new();
    for b in 0..nb {
        if in_tree[b] {
            continue;
        }
        let has_joint = ends.iter().any(|&(b1, b2)| b1 == Some(b) || b2 == Some(b));
        if has_joint {
            let lonely: Vec<&str> = (0..nb)
                .filter(|&k| !in_tree[k])
                .map(|k| bodies[k].name.as_str())
                .collect();
            return Err(ModelError::Unsupported(format!(
                "{}: bodies {lonely:?} do not reach the ground through joints; the relative formulation needs every jointed body connected to the ground: join the group's base body to the ground with a `Free` joint to make it a floating base (a body with no joints at all is one already)",
                scene.origin
            )));
        }
        floating.push(b);
    }
    Ok(SpanningTree {
        order,
        used,
        floating,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nonzero_rows_drop_entries_below_the_relative_threshold() {
        // One node, two modes: X^t rows then X^r rows, row-major.
        let rows = [
            [1.0, 1e-14],
            [0.0, 2.0],
            [0.0, 0.0],
            [0.0, 0.0],
            [0.0, 0.0],
            [-3.0, 1e-13],
        ];
        let rows = NodeRows::new(2, vec![Vector3::zeros()], rows.concat()).unwrap();
        assert_eq!(nonzero_rows(&rows, 0, 0, false), [(0, 1.0)]);
        assert_eq!(nonzero_rows(&rows, 0, 1, false), [(1, 2.0)]);
        assert_eq!(nonzero_rows(&rows, 0, 2, false), []);
        assert_eq!(nonzero_rows(&rows, 0, 2, true), [(0, -3.0)]);
    }
}
