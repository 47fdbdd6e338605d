//! Compiling a prepared scene (docs/methods.md §4.4, §4.5) in named steps: the bodies and
//! their node rows ([`body_infos`]), the topology, the coordinates z and w with the rows of
//! L ([`Coordinates`]), the cut-joint and driver constraints (`cut_joints`), the tree of
//! elementary joints over which §4.5 step 5 accumulates ([`ElemTree`]), the workspace (sized
//! once, so that the pass allocates nothing), the initial state (`initial_state`), the mass
//! map, the sensors and the force elements.

use flexmbd_body::FlexibleBody;
use flexmbd_core::Dim;
use flexmbd_model::force_elements::ForceElements;
use flexmbd_model::{MarkerId, ModelError, PreparedScene, Scene};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Rotation3, Vector3, Vector6};

use crate::body_kernels::BodyKernel;
use crate::constraints::Constraint;
use crate::cut_joints::{cut_joint_constraints, driver_constraints, marker_constraints};
use crate::kinematics::angle_of;
use crate::marker_kinematics::MarkerJacobian;
use crate::marker_table::MarkerTable;
use crate::system::{
    Assembly, ConstraintRows, ForceElementWork, FrameStates, Relative, RunTimeBody, Tree,
    unsupported,
};
use crate::topology::{BodyInfo, CoordRef, ElemKind, Frame, FrameKind, Side, Topology};
use flexmbd_body::NodeRows;

impl Relative {
    /// Compile a scene (planar or spatial) for the relative formulation.
    pub fn compile(prepared: &PreparedScene) -> Result<Relative, ModelError> {
        let scene = prepared.scene();
        let (infos, flex) = body_infos(prepared)?;
        let topology = Topology::build(prepared, &infos)?;
        let coordinates = Coordinates::new(&topology, &infos);
        let mut constraints = cut_joint_constraints(prepared, &infos, &topology)?;
        driver_constraints(prepared, &topology, &mut constraints)?;
        marker_constraints(prepared, &infos, &mut constraints);
        let mut rel =
            Relative::with_workspace(scene, &infos, flex, topology, coordinates, constraints);
        rel.rows.paths = rel.compile_row_paths();
        rel.initial_coordinates(scene);
        rel.tree.mass_map = rel.build_mass_map();
        rel.initial_velocities(scene)?;
        rel.sensors = rel.build_sensors(prepared, &infos)?;
        rel.build_force_elements(prepared, &infos)?;
        Ok(rel)
    }

    /// The compiled scene with its workspace sized once: per frame, per body, per elementary
    /// joint and in w (the pass allocates nothing).
    fn with_workspace(
        scene: &Scene,
        infos: &[BodyInfo],
        flex: Vec<FlexibleBody>,
        topology: Topology,
        coordinates: Coordinates,
        constraints: Vec<Constraint>,
    ) -> Relative {
        let dim = scene.dim;
        let Coordinates {
            first_mode,
            n_z,
            n_w,
            elem_rate,
            elem_w,
            l_rows,
            paths,
        } = coordinates;
        let rigid_size = dim.n_trans() + dim.n_rot();
        let bodies = run_time_bodies(infos, flex, &topology.body_frame, &first_mode, rigid_size);
        let coordinate_names = names_of_coordinates(topology.n_joint, infos);
        let n_constraints = constraints.iter().map(|c| c.rows(dim)).sum();
        let nf = topology.frames.len();
        let ne = topology.elems.len();
        let n_bodies = bodies.len();
        let body_frames: Vec<usize> = bodies.iter().map(|b| b.frame).collect();
        let tree = ElemTree::new(&topology, &paths, &body_frames);
        let fixed_identity = fixed_identity(&topology);
        let planar_frames = dim == Dim::Planar && planar_frames(&topology);
        let mut gravity = scene.gravity.vec();
        if dim == Dim::Planar {
            gravity.z = 0.0;
        }
        Relative {
            tree: Tree {
                dim,
                n_z,
                n_w,
                topology,
                elem_w,
                paths,
                l_rows,
                mass_map: Vec::new(),
                elem_rate,
                elem_children: tree.children,
                elem_parent: tree.parent,
                elem_bodies: tree.bodies,
                fixed_identity,
                planar_frames,
            },
            bodies,
            frames: FrameStates {
                position: vec![Vector3::zeros(); nf],
                rotation: vec![Matrix3::identity(); nf],
                velocity: vec![Vector6::zeros(); nf],
                bias: vec![Vector6::zeros(); nf],
                elem_twist: vec![Vector6::zeros(); ne],
                last_z: DVector::zeros(n_z),
                last_zd: DVector::zeros(n_z),
                positions_current: false,
                velocities_current: false,
                velocities_zd: DVector::zeros(n_z),
            },
            assembly: Assembly {
                inertia_method: scene.solver.inertia,
                gravity,
                body_mass: vec![Matrix6::zeros(); n_bodies],
                body_p: vec![Vector6::zeros(); n_bodies],
                subtree_mass: vec![Matrix6::zeros(); ne],
                subtree_p: vec![Vector6::zeros(); ne],
                m_w: DMatrix::zeros(n_w, n_w),
                q_w: DVector::zeros(n_w),
            },
            rows: ConstraintRows {
                constraints,
                paths: Default::default(),
                phi_w: DMatrix::zeros(n_constraints, n_w),
            },
            forces: ForceElementWork {
                elements: ForceElements::default(),
                marker_jacobian: MarkerJacobian::default(),
                marker_table: MarkerTable::default(),
            },
            coordinates: flexmbd_core::Coordinates::zeros(n_z, n_constraints),
            sensors: Default::default(),
            coordinate_names,
        }
    }

    /// Compile the scene's force elements over this formulation's markers (free lengths left
    /// to the start: the t = 0 distance).
    pub(crate) fn build_force_elements(
        &mut self,
        prepared: &PreparedScene,
        infos: &[BodyInfo],
    ) -> Result<(), ModelError> {
        let scene = prepared.scene();
        let side_at = |id: MarkerId| Side::at(prepared, infos, id);
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
        let (q0, qd0) = (self.coordinates.q0.clone(), self.coordinates.qd0.clone());
        self.kinematics(&q0, &qd0);
        self.forces.marker_jacobian = MarkerJacobian::new(self.tree.n_w, self.tree.n_z);
        self.forces.elements =
            ForceElements::new(prepared, side_at, &*self, &q0, &qd0, self.tree.n_z)?;
        let mut table = MarkerTable::default();
        for side in self.forces.elements.markers_mut() {
            side.slot = Some(table.row_of(side));
        }
        table.plan(self);
        self.forces.marker_table = table;
        self.fill_marker_table();
        Ok(())
    }

    /// The entries of M_w outside its z × z block that [`dynamics`](Self::dynamics) writes
    /// (the others are zero for every state), mapped through L into M.
    pub(crate) fn build_mass_map(&self) -> Vec<(usize, usize, f64)> {
        let (nz, nw) = (self.tree.n_z, self.tree.n_w);
        let mut pattern = vec![false; nw * nw];
        let mut mark = |i: usize, j: usize| {
            pattern[i + j * nw] = true;
            pattern[j + i * nw] = true;
        };
        for (e, el) in self.tree.topology.elems.iter().enumerate() {
            for &a in &self.tree.paths[el.frame] {
                mark(self.tree.elem_w[a], self.tree.elem_w[e]);
            }
        }
        for b in &self.bodies {
            for m in 0..b.n_modes {
                for &a in &self.tree.paths[b.frame] {
                    mark(self.tree.elem_w[a], b.first_mode + m);
                }
                for m2 in 0..b.n_modes {
                    mark(b.first_mode + m, b.first_mode + m2);
                }
            }
        }
        let mut map = Vec::new();
        for j in 0..nw {
            for i in 0..nw {
                if !pattern[i + j * nw] || (i < nz && j < nz) {
                    continue;
                }
                for &(c, a) in &self.tree.l_rows[i] {
                    for &(d, b) in &self.tree.l_rows[j] {
                        map.push((c + d * nz, i + j * nw, a * b));
                    }
                }
            }
        }
        map
    }
}

/// The run-time bodies, each with its kernel (rigid in closed form, or flexible with its
/// body terms sized rigid_size + n_modes).
fn run_time_bodies(
    infos: &[BodyInfo],
    flex: Vec<FlexibleBody>,
    body_frame: &[usize],
    first_mode: &[usize],
    rigid_size: usize,
) -> Vec<RunTimeBody> {
    let mut bodies = Vec::new();
    for (k, (info, body)) in infos.iter().zip(flex).enumerate() {
        bodies.push(RunTimeBody {
            kernel: BodyKernel::new(body, info.n_modes, rigid_size),
            frame: body_frame[k],
            n_modes: info.n_modes,
            first_mode: first_mode[k],
            node_rows: info.node_rows.clone(),
        });
    }
    bodies
}

/// Every body's compile-time data (placement at t = 0, markers, node rows) and its run-time
/// body, in scene order.
fn body_infos(prepared: &PreparedScene) -> Result<(Vec<BodyInfo>, Vec<FlexibleBody>), ModelError> {
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
        let node_rows = if n > 0 {
            prep.nodes.clone()
        } else {
            NodeRows::default()
        };
        let markers = b
            .markers
            .iter()
            .enumerate()
            .map(|(k, m)| Side {
                body: Some(infos.len()),
                rbar: m.position.vec(),
                node: if n > 0 { prep.marker_nodes[k] } else { None },
                slot: None,
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
            node_rows,
        });
        flex.push(body);
    }
    Ok((infos, flex))
}

/// The coordinates (docs/methods.md §4.4): z = the joint coordinates, then every body's
/// modes; w = the joint elementary joints (= the joint coordinates), the modes, then the
/// node elementary joints, with w = L ż row by row.
struct Coordinates {
    /// Per body: the index of its first modal coordinate in z (and in w).
    first_mode: Vec<usize>,
    n_z: usize,
    n_w: usize,
    /// Per elementary joint: its rate ė = L_e ż as (z index, coefficient).
    elem_rate: Vec<Vec<(usize, f64)>>,
    /// Per elementary joint: its index in w.
    elem_w: Vec<usize>,
    /// Per w entry: its row of L, (z index, coefficient).
    l_rows: Vec<Vec<(usize, f64)>>,
    /// Per frame: the elementary joints on the path root → frame (inclusive).
    paths: Vec<Vec<usize>>,
}

impl Coordinates {
    fn new(topology: &Topology, infos: &[BodyInfo]) -> Coordinates {
        let mut first_mode = Vec::new();
        let mut n_z = topology.n_joint;
        for info in infos {
            first_mode.push(n_z);
            n_z += info.n_modes;
        }
        let resolve = |c: CoordRef| match c {
            CoordRef::Joint(k) => k,
            CoordRef::Mode(b, m) => first_mode[b] + m,
        };
        let elem_rate: Vec<Vec<(usize, f64)>> = topology
            .elems
            .iter()
            .map(|e| e.rate.iter().map(|&(c, v)| (resolve(c), v)).collect())
            .collect();
        let (elem_w, l_rows) = w_layout(&topology.coord_elem, &elem_rate, n_z);
        Coordinates {
            first_mode,
            n_z,
            n_w: l_rows.len(),
            elem_rate,
            elem_w,
            l_rows,
            paths: frame_paths(&topology.frames),
        }
    }
}

/// The w index of every elementary joint and the rows of L: the elementary joint of joint
/// coordinate k is w_k = z_k (its L row e_k), the modes are w = z too, and every other
/// (node) elementary joint e is appended with its rate ė = L_e ż as its row.
fn w_layout(
    coord_elem: &[usize],
    elem_rate: &[Vec<(usize, f64)>],
    n_z: usize,
) -> (Vec<usize>, Vec<Vec<(usize, f64)>>) {
    let mut elem_w = vec![usize::MAX; elem_rate.len()];
    for (k, &e) in coord_elem.iter().enumerate() {
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
    (elem_w, l_rows)
}

/// Per frame (parents before children): the elementary joints on its path from the root.
fn frame_paths(frames: &[Frame]) -> Vec<Vec<usize>> {
    let mut paths: Vec<Vec<usize>> = Vec::with_capacity(frames.len());
    for fr in frames {
        let mut p = fr.parent.map_or_else(Vec::new, |pf| paths[pf].clone());
        if let FrameKind::Elem(e) = fr.kind {
            p.push(e);
        }
        paths.push(p);
    }
    paths
}

/// The names of z: `joint coordinate <k>`, then `<body>.y<m>`.
fn names_of_coordinates(n_joint: usize, infos: &[BodyInfo]) -> Vec<String> {
    let mut coordinate_names: Vec<String> = (0..n_joint)
        .map(|k| format!("joint coordinate {k}"))
        .collect();
    for info in infos {
        coordinate_names.extend((0..info.n_modes).map(|m| format!("{}.y{m}", info.name)));
    }
    coordinate_names
}

/// The tree of elementary joints over which §4.5 step 5 accumulates 𝕄 and ℙ: fixed frames
/// only relabel the same global quantities, so an elementary joint's subtree is its child
/// elementary joints and the bodies whose nearest elementary joint towards the root it is.
struct ElemTree {
    children: Vec<Vec<usize>>,
    bodies: Vec<Vec<usize>>,
    parent: Vec<Option<usize>>,
}

impl ElemTree {
    fn new(topology: &Topology, paths: &[Vec<usize>], body_frames: &[usize]) -> ElemTree {
        let ne = topology.elems.len();
        let mut children = vec![Vec::new(); ne];
        let mut bodies = vec![Vec::new(); ne];
        let mut parent = vec![None; ne];
        for (e, el) in topology.elems.iter().enumerate() {
            if let Some(&pe) = topology.frames[el.frame]
                .parent
                .and_then(|pf| paths[pf].last())
            {
                assert!(pe < e, "elementary joints in tree order");
                children[pe].push(e);
                parent[e] = Some(pe);
            }
        }
        for (k, &frame) in body_frames.iter().enumerate() {
            if let Some(&e) = paths[frame].last() {
                bodies[e].push(k);
            }
        }
        ElemTree {
            children,
            bodies,
            parent,
        }
    }
}

/// Per frame: a `Fixed` frame whose rotation is exactly I.
fn fixed_identity(topology: &Topology) -> Vec<bool> {
    topology
        .frames
        .iter()
        .map(|f| matches!(&f.kind, FrameKind::Fixed { rot, .. } if *rot == Matrix3::identity()))
        .collect()
}

/// Every rotation of the tree (fixed rotations and revolute axes) is about z (for a planar
/// scene: the frame rotations then have the form [R 0; 0 1]).
fn planar_frames(topology: &Topology) -> bool {
    let z_rotation = |r: &Matrix3<f64>| {
        r[(0, 2)] == 0.0
            && r[(1, 2)] == 0.0
            && r[(2, 0)] == 0.0
            && r[(2, 1)] == 0.0
            && r[(2, 2)] == 1.0
    };
    topology.frames.iter().all(|f| match &f.kind {
        FrameKind::Fixed { rot, .. } => z_rotation(rot),
        FrameKind::Elem(_) => true,
    }) && topology
        .elems
        .iter()
        .all(|e| e.kind == ElemKind::Prismatic || e.axis == Vector3::z())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn w_layout_puts_joint_coordinates_and_modes_first_then_node_joints() {
        // Elementary joints: 0 = node joint (rate 0.5 y), 1 = joint coordinate 0,
        // 2 = node joint (rate −y), 3 = joint coordinate 1; z = (q0, q1, y).
        let elem_rate = vec![
            vec![(2, 0.5)],
            vec![(0, 1.0)],
            vec![(2, -1.0)],
            vec![(1, 1.0)],
        ];
        let (elem_w, l_rows) = w_layout(&[1, 3], &elem_rate, 3);
        assert_eq!(elem_w, [3, 0, 4, 1]);
        assert_eq!(
            l_rows,
            [
                vec![(0, 1.0)],
                vec![(1, 1.0)],
                vec![(2, 1.0)],
                vec![(2, 0.5)],
                vec![(2, -1.0)],
            ]
        );
    }

    /// A body (frame 2) on a revolute (elementary joint 0, frame 1) from the ground, with a
    /// node joint (elementary joint 1, frame 3) carrying a second body (frame 4) through a
    /// fixed frame (5 is its body frame).
    fn two_body_topology() -> Topology {
        let fixed = |parent| Frame {
            parent,
            kind: FrameKind::Fixed {
                offset: Vector3::new(1.0, 0.0, 0.0),
                rot: Matrix3::identity(),
            },
        };
        let elem = |parent, e| Frame {
            parent,
            kind: FrameKind::Elem(e),
        };
        let revolute = |frame, axis| crate::topology::Elem {
            kind: ElemKind::Revolute,
            axis,
            frame,
            rate: Vec::new(),
        };
        Topology {
            frames: vec![
                fixed(None),
                elem(Some(0), 0),
                fixed(Some(1)),
                elem(Some(2), 1),
                fixed(Some(3)),
                fixed(Some(4)),
            ],
            elems: vec![revolute(1, Vector3::z()), revolute(3, Vector3::z())],
            body_frame: vec![2, 5],
            n_joint: 1,
            tree: Vec::new(),
            cuts: Vec::new(),
            coord_elem: vec![0],
        }
    }

    #[test]
    fn elem_tree_links_elementary_joints_across_fixed_frames() {
        let topology = two_body_topology();
        let paths = frame_paths(&topology.frames);
        let tree = ElemTree::new(&topology, &paths, &topology.body_frame);
        assert_eq!(tree.parent, [None, Some(0)]);
        assert_eq!(tree.children, [vec![1], vec![]]);
        assert_eq!(tree.bodies, [vec![0], vec![1]]);
    }

    #[test]
    fn planar_frames_needs_every_rotation_about_z() {
        let mut topology = two_body_topology();
        assert!(planar_frames(&topology));
        assert_eq!(
            fixed_identity(&topology),
            [true, false, true, false, true, true]
        );
        topology.elems[1].axis = Vector3::x();
        assert!(!planar_frames(&topology));
        let mut topology = two_body_topology();
        topology.frames[4].kind = FrameKind::Fixed {
            offset: Vector3::zeros(),
            rot: *nalgebra::Rotation3::from_axis_angle(&Vector3::y_axis(), 0.1).matrix(),
        };
        assert!(!planar_frames(&topology));
        assert!(!fixed_identity(&topology)[4]);
    }

    #[test]
    fn frame_paths_collect_the_elementary_joints_from_the_root() {
        let fixed = |parent| Frame {
            parent,
            kind: FrameKind::Fixed {
                offset: Vector3::zeros(),
                rot: Matrix3::identity(),
            },
        };
        let elem = |parent, e| Frame {
            parent,
            kind: FrameKind::Elem(e),
        };
        let frames = [
            fixed(None),
            elem(Some(0), 0),
            fixed(Some(1)),
            elem(Some(2), 1),
            elem(Some(1), 2),
        ];
        let paths = frame_paths(&frames);
        assert_eq!(paths, [vec![], vec![0], vec![0], vec![0, 1], vec![0, 2]]);
    }
}
