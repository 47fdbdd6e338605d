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

use flexmbd_body::{ElasticTangents, InertiaMethod};
use flexmbd_core::{Coordinates, Dim, Request, State, SystemTerms};
use flexmbd_model::ModelError;
use flexmbd_model::force_elements::ForceElements;
use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Vector3, Vector6};

use crate::body_kernels::BodyKernel;
use crate::constraints::{Constraint, RowPaths};
use crate::marker_kinematics::MarkerJacobian;
use crate::marker_table::MarkerTable;
use crate::sensors::RelativeSensors;
use crate::topology::{Side, Topology};
use flexmbd_body::NodeRows;

/// One body at run time.
pub(crate) struct RunTimeBody {
    /// Its M̄, Q̄ kernel: rigid in closed form, or flexible (`body_kernels.rs`).
    pub(crate) kernel: BodyKernel,
    /// Its frame in the augmented tree.
    pub(crate) frame: usize,
    /// Number of modal coordinates.
    pub(crate) n_modes: usize,
    /// Index of the first modal coordinate in z (and in w).
    pub(crate) first_mode: usize,
    /// Its mode rows at its FE nodes (for markers at nodes).
    pub(crate) node_rows: NodeRows,
}

/// The semi-recursive relative-coordinate formulation of one scene, in the parts a pass
/// reads: the compiled tree and its maps, the bodies, the frames' kinematic state, the
/// dynamics pass's assembly, the constraint rows and the force elements with their markers.
pub struct Relative {
    /// The augmented tree, its elementary joints and the maps between z and w (fixed).
    pub(crate) tree: Tree,
    pub(crate) bodies: Vec<RunTimeBody>,
    /// Per frame and per elementary joint: the kinematics of the last pass.
    pub(crate) frames: FrameStates,
    /// The dynamics pass's body terms, subtree accumulations and w-space M_w, Q_w.
    pub(crate) assembly: Assembly,
    /// The cut-joint and driver constraints, their compiled paths and Φ_w.
    pub(crate) rows: ConstraintRows,
    /// Spring–dampers and the markers they read.
    pub(crate) forces: ForceElementWork,
    // Initial state and outputs.
    /// Number, constraint count, z(0) and ż(0), coordinates the integrator holds (none).
    pub(crate) coordinates: Coordinates,
    pub(crate) sensors: RelativeSensors,
    /// Names of the coordinates.
    pub(crate) coordinate_names: Vec<String>,
}

/// The compiled tree: its frames and elementary joints, the paths, and the maps between
/// the coordinates z and the joint velocities w = L ż. Fixed once the scene is compiled.
pub(crate) struct Tree {
    pub(crate) dim: Dim,
    /// Number of coordinates z (the length of `coordinates.q0`) and of velocity entries w.
    pub(crate) n_z: usize,
    pub(crate) n_w: usize,
    pub(crate) topology: Topology,
    /// w index of each elementary joint.
    pub(crate) elem_w: Vec<usize>,
    /// Elementary joints on the path root → frame (inclusive), per frame.
    pub(crate) paths: Vec<Vec<usize>>,
    /// The rows of L (w = L ż): per w entry, (z index, coefficient).
    pub(crate) l_rows: Vec<Vec<(usize, f64)>>,
    /// M = Lᵀ M_w L over the structural non-zeros of M_w outside its z × z block (which
    /// the pass writes into M directly): (index in M, index in M_w, coefficient),
    /// column-major indices.
    pub(crate) mass_map: Vec<(usize, usize, f64)>,
    /// Per elementary joint: its value (and rate) as a combination of z, (z index, coefficient).
    pub(crate) elem_rate: Vec<Vec<(usize, f64)>>,
    /// Per elementary joint: its children in the tree of elementary joints (fixed frames
    /// only relabel the same global quantities, so the subtree accumulation runs over it),
    /// its nearest elementary joint towards the root, and the bodies whose nearest
    /// elementary joint towards the root it is.
    pub(crate) elem_children: Vec<Vec<usize>>,
    pub(crate) elem_parent: Vec<Option<usize>>,
    pub(crate) elem_bodies: Vec<Vec<usize>>,
    /// Per frame: a `Fixed` frame whose rotation is exactly I.
    pub(crate) fixed_identity: Vec<bool>,
    /// Planar scene whose every rotation is about z (fixed rotations and revolute axes):
    /// frame rotations then have the form [R 0; 0 1] and the fixed-frame products run
    /// on the 2 × 2 blocks (the dropped terms are exact zeros, so the values are the same).
    pub(crate) planar_frames: bool,
}

/// The kinematics of the last pass (§4.5 steps 1–3), and what it was computed for.
pub(crate) struct FrameStates {
    /// Per frame: position r_F, rotation A_F, velocity Z^r_F = {ṡ; ω} and velocity-product
    /// acceleration D_F.
    pub(crate) position: Vec<Vector3<f64>>,
    pub(crate) rotation: Vec<Matrix3<f64>>,
    pub(crate) velocity: Vec<Vector6<f64>>,
    pub(crate) bias: Vec<Vector6<f64>>,
    /// Per elementary joint: its twist v_e (depends on positions only).
    pub(crate) elem_twist: Vec<Vector6<f64>>,
    /// z and ż of the last kinematics pass.
    pub(crate) last_z: DVector<f64>,
    pub(crate) last_zd: DVector<f64>,
    /// The frame positions and elementary-joint twists are those of `last_z`.
    pub(crate) positions_current: bool,
    /// The frame velocities and D are those of `last_z` and `velocities_zd`.
    pub(crate) velocities_current: bool,
    pub(crate) velocities_zd: DVector<f64>,
}

/// What the dynamics pass assembles (§4.5 steps 4–7).
pub(crate) struct Assembly {
    pub(crate) inertia_method: InertiaMethod,
    /// Gravity (m/s², ground components; z = 0 in 2D).
    pub(crate) gravity: Vector3<f64>,
    /// Per body: its rigid block of M̄_k and its P_k in the 6-layout (step 4).
    pub(crate) body_mass: Vec<Matrix6<f64>>,
    pub(crate) body_p: Vec<Vector6<f64>>,
    /// Per elementary joint: 𝕄 and ℙ of the subtree its frame carries (step 5).
    pub(crate) subtree_mass: Vec<Matrix6<f64>>,
    pub(crate) subtree_p: Vec<Vector6<f64>>,
    pub(crate) m_w: DMatrix<f64>,
    pub(crate) q_w: DVector<f64>,
}

impl Tree {
    /// The rigid velocity entries of a body in the 6-layout: x, y, θz in 2D, all six in 3D
    /// (the dynamics pass's [`Layout`](crate::layout::Layout)).
    pub(crate) fn rigid_entries(&self) -> &'static [usize] {
        use crate::layout::{Layout, Planar, Spatial};
        match self.dim {
            Dim::Planar => Planar::ENTRIES,
            Dim::Spatial => Spatial::ENTRIES,
        }
    }

    /// Their number (3 or 6).
    pub(crate) fn rigid_size(&self) -> usize {
        self.rigid_entries().len()
    }
}

/// The cut-joint and driver constraints, in the order of their rows in Φ.
pub(crate) struct ConstraintRows {
    pub(crate) constraints: Vec<Constraint>,
    /// The elementary joints each constraint's rows walk, compiled as flat runs (the two
    /// sides' shared path once, then each side's own; `constraints.rs`).
    pub(crate) paths: RowPaths,
    /// Φ_w, of which a pass writes only the node-joint columns (w ≥ n_z): the z columns go
    /// straight into Φ_z.
    pub(crate) phi_w: DMatrix<f64>,
}

/// Spring–dampers and the scratch of their markers' Jacobians.
pub(crate) struct ForceElementWork {
    pub(crate) elements: ForceElements<Side>,
    /// Scratch of one marker's Jacobian (the force elements' query).
    pub(crate) marker_jacobian: MarkerJacobian,
    /// The force elements' markers, evaluated once per dynamics pass.
    pub(crate) marker_table: MarkerTable,
}

impl Relative {
    /// The flexible bodies' run-time bodies (rigid bodies have no elastic model to ask).
    fn flexible_bodies(&self) -> impl Iterator<Item = &flexmbd_body::FlexibleBody> {
        self.bodies
            .iter()
            .filter_map(|b| b.kernel.flexible().map(|f| &f.body))
    }
}

/// A scene this formulation cannot run.
pub(crate) fn unsupported(s: String) -> ModelError {
    ModelError::Unsupported(s)
}

impl flexmbd_core::Formulation for Relative {
    fn coordinates(&self) -> &Coordinates {
        &self.coordinates
    }
    fn symmetric_tangent(&self) -> bool {
        ElasticTangents::of(self.flexible_bodies()).symmetric
    }
    fn constant_tangents(&self) -> bool {
        // K ≈ blockdiag K_ff, C ≈ blockdiag C_ff (§4.6): constant for rigid bodies and
        // linear elasticity, state-dependent for the stiffening models.
        ElasticTangents::of(self.flexible_bodies()).linear && self.forces.elements.is_empty()
    }
    fn declared_pattern(&self) -> Option<flexmbd_core::DeclaredPattern> {
        Some(self.pattern())
    }
    /// The tree joints a law drives, z_c = s θ(t), each with its row z_c − s θ(t) = 0
    /// (none when a coordinate is driven twice: its rows then stay constraints).
    fn driven_coordinates(&self) -> Option<flexmbd_core::DrivenCoordinates> {
        let mut driven = flexmbd_core::DrivenCoordinates::default();
        let mut row = 0;
        for c in &self.rows.constraints {
            if let Constraint::Coord { z, .. } = c {
                driven.coordinates.push(*z);
                driven.rows.push(row);
            }
            row += c.rows(self.tree.dim);
        }
        let mut distinct = driven.coordinates.clone();
        distinct.sort_unstable();
        distinct.dedup();
        let k = driven.coordinates.len();
        (k > 0 && distinct.len() == k).then_some(driven)
    }
    /// In the order of the driver rows, as declared.
    fn driven_motion(&self, t: f64, out: &mut [[f64; 3]]) {
        let drivers = self.rows.constraints.iter().filter_map(|c| match c {
            Constraint::Coord { law, sign, .. } => Some((law, *sign)),
            _ => None,
        });
        for ((law, sign), out) in drivers.zip(out) {
            let (th, thd, thdd) = law.eval(t);
            *out = [sign * th, sign * thd, sign * thdd];
        }
    }
    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        // Only the work the request needs: positions (and twists) when z changed, velocities
        // and D only for M, Q or c, and when z or ż changed.
        self.frames.last_zd.copy_from(state.qd);
        self.update_positions(state.q);
        if req.dynamics || req.accel_term {
            self.update_velocities();
        }
        if req.dynamics {
            self.dynamics(state, req.tangents, out);
        }
        if req.constraints || req.jacobian || req.accel_term {
            self.constraint_terms(state.t, req, out);
        }
    }
}

impl flexmbd_core::Observe for Relative {
    fn sensor_names(&self) -> &[String] {
        self.sensors.names()
    }
    fn sensors(&mut self, state: State<'_>, out: &mut [f64]) {
        self.read_sensors(state.q, state.qd, state.qdd, out);
    }
    /// From one kinematics pass at (z, ż), as the sensors.
    fn body_poses(&mut self, state: State<'_>, out: &mut [flexmbd_core::BodyPose]) {
        self.kinematics(state.q, state.qd);
        for (b, pose) in out.iter_mut().enumerate() {
            (pose.origin, pose.rotation) = flexmbd_core::SensorQuery::body_frame(self, b, state.q);
            let first = self.bodies[b].first_mode;
            pose.modes.clear();
            pose.modes
                .extend_from_slice(&state.q.as_slice()[first..first + self.bodies[b].n_modes]);
        }
    }
    /// From one kinematics pass at (z, ż), as the sensors; ż̇ = 0 when the state has none.
    fn body_motions(&mut self, state: State<'_>, out: &mut [flexmbd_core::BodyMotion]) -> bool {
        self.kinematics(state.q, state.qd);
        let at_rest;
        let qdd = match state.qdd {
            Some(qdd) => qdd,
            None => {
                at_rest = DVector::zeros(state.q.len());
                &at_rest
            }
        };
        for (b, motion) in out.iter_mut().enumerate() {
            motion.frame = flexmbd_core::SensorQuery::frame_motion(self, b, state.q, state.qd, qdd);
            let modes =
                self.bodies[b].first_mode..self.bodies[b].first_mode + self.bodies[b].n_modes;
            let copy = |to: &mut Vec<f64>, from: &DVector<f64>| {
                to.clear();
                to.extend_from_slice(&from.as_slice()[modes.clone()]);
            };
            copy(&mut motion.modes, state.q);
            copy(&mut motion.mode_rates, state.qd);
            copy(&mut motion.mode_accelerations, qdd);
        }
        true
    }
}
