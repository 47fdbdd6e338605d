//! The constraints Φ, their Jacobian Φ_z and the acceleration term c (docs/methods.md §4.6).
//!
//! Every constraint is written in the Cartesian positions of its two markers (point
//! coincidence r_i − r_j; 2D angle sin(ψ − ψ₀ − s θ(t)); perpendicularity a·b; sliding
//! n·(r_j − r_i), which is also the scene's `PointInPlane`; the scene's `Distance`
//! ½(|r_j − r_i|² − L²)), or in one tree coordinate (z_c − s θ(t)). Its Jacobian row in w walks
//! each body's path to the root, Φ_w = Σ_k Φ_{Z_k} R_k (plus the node's modal columns), and
//! is folded into z by Φ_z = Φ_w L (the z columns are written into Φ_z directly, L = [I;
//! L_node], and only the node-joint columns of Φ_w are folded); c = Σ_k Φ_{Z_k} {D_k; 0} + the Cartesian
//! velocity-product terms + Φ̇_t. Redundant closure equations are kept (ALI3-P tolerates
//! them). The constraints themselves are built in `cut_joints`.

use flexmbd_core::{Dim, Request, SystemTerms};
use flexmbd_model::MotionLaw;
use flexmbd_model::constraint_equations::{Motion, distance};
use nalgebra::{DMatrix, DVector, Vector3, Vector6};

use crate::kinematics::{angle_at, dir_at, point_at};
use crate::system::Relative;
use crate::topology::Side;

/// Where a constraint's rows start, and the runs of its compiled path joints
/// ([`RowPaths`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowAt {
    row: usize,
    runs: [usize; 4],
}

/// The elementary joints each constraint's rows walk, compiled once as flat runs: per
/// constraint, the joints its two sides' paths share from the root (walked once, with
/// g_i + g_j), then side i's own, then side j's own, each with its w index. A side on the
/// ground has no path, and nothing is shared with it.
#[derive(Clone, Debug, Default)]
pub(crate) struct RowPaths {
    /// (elementary joint, its w index), constraint after constraint.
    joints: Vec<(usize, usize)>,
    /// Per constraint: [start, end of the shared run, end of side i's, end of side j's].
    runs: Vec<[usize; 4]>,
}

/// The row outputs of a constraint pass besides the Jacobian: Φ, Φ_t and c, and what the
/// pass asks for.
pub(crate) struct RowTerms<'a> {
    phi: &'a mut DVector<f64>,
    phi_t: &'a mut DVector<f64>,
    accel_term: &'a mut DVector<f64>,
    req: Request,
}

/// A constraint (docs/methods.md §4.6).
#[derive(Clone, Debug)]
pub(crate) enum Constraint {
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
    /// ½(|r_j − r_i|² − L²) = 0 (a scene `Distance` constraint).
    Distance { i: Side, j: Side, length: f64 },
}

impl Constraint {
    pub(crate) fn rows(&self, dim: Dim) -> usize {
        match self {
            Constraint::Point { .. } => dim.n_trans(),
            _ => 1,
        }
    }

    /// Its two sides (none for a driven tree coordinate).
    pub(crate) fn sides(&self) -> Option<(&Side, &Side)> {
        match self {
            Constraint::Point { i, j }
            | Constraint::Angle2 { i, j, .. }
            | Constraint::Slide { i, j, .. }
            | Constraint::Perp { i, j, .. }
            | Constraint::Distance { i, j, .. } => Some((i, j)),
            Constraint::Coord { .. } => None,
        }
    }
}

/// Where a constraint pass writes its Jacobian: the z columns straight into Φ_z (which comes
/// cleared), the node-joint columns of Φ_w (w ≥ n_z) into `node_columns`, folded into Φ_z
/// through L after the rows. Nothing is written when the pass asks for no Jacobian.
pub(crate) struct JacobianSink<'a> {
    phi_z: &'a mut DMatrix<f64>,
    node_columns: &'a mut DMatrix<f64>,
    n_z: usize,
    write: bool,
}

impl JacobianSink<'_> {
    /// Φ_w[row, w] += v.
    #[inline(always)]
    pub(crate) fn add(&mut self, row: usize, w: usize, v: f64) {
        if w < self.n_z {
            self.phi_z[(row, w)] += v;
        } else {
            self.node_columns[(row, w)] += v;
        }
    }
}

impl Relative {
    /// The constraints' [`RowPaths`], from the tree's paths (allocates: for compiling).
    pub(crate) fn compile_row_paths(&self) -> RowPaths {
        let mut paths = RowPaths::default();
        for c in &self.rows.constraints {
            let start = paths.joints.len();
            let (path_i, path_j, shared) = match c.sides() {
                Some((i, j)) => {
                    let (pi, pj) = (self.path_of(i.body), self.path_of(j.body));
                    let shared = pi.iter().zip(pj).take_while(|(a, b)| a == b).count();
                    (pi, pj, shared)
                }
                None => (&[][..], &[][..], 0),
            };
            let with_w = |a: &usize| (*a, self.tree.elem_w[*a]);
            paths.joints.extend(path_i[..shared].iter().map(with_w));
            let end_shared = paths.joints.len();
            paths.joints.extend(path_i[shared..].iter().map(with_w));
            let end_i = paths.joints.len();
            paths.joints.extend(path_j[shared..].iter().map(with_w));
            paths
                .runs
                .push([start, end_shared, end_i, paths.joints.len()]);
        }
        paths
    }

    /// The path of side `body`'s frame (empty for the ground).
    fn path_of(&self, body: Option<usize>) -> &[usize] {
        body.map_or(&[][..], |k| &self.tree.paths[self.bodies[k].frame])
    }

    /// g·D_k of side `body` (0 for the ground).
    #[inline(always)]
    fn bias_of(&self, body: Option<usize>, g: &Vector6<f64>) -> f64 {
        body.map_or(0.0, |k| g.dot(&self.frames.bias[self.bodies[k].frame]))
    }

    /// Add g_i·Z_i + g_j·Z_j of the two sides' bodies to row `row` of Φ_w (the modal
    /// coefficients by the caller) over the constraint's compiled path `runs`, the shared run
    /// once with g_i + g_j; returns g_i·D_i + g_j·D_j.
    pub(crate) fn pair_row(
        &self,
        jac: &mut JacobianSink<'_>,
        row: usize,
        runs: [usize; 4],
        (bi, gi): (Option<usize>, &Vector6<f64>),
        (bj, gj): (Option<usize>, &Vector6<f64>),
    ) -> f64 {
        if jac.write {
            let joints = &self.rows.paths.joints;
            let gs = gi + gj;
            for (run, g) in [(0, &gs), (1, gi), (2, gj)] {
                for &(a, w) in &joints[runs[run]..runs[run + 1]] {
                    jac.add(row, w, g.dot(&self.frames.elem_twist[a]));
                }
            }
        }
        self.bias_of(bi, gi) + self.bias_of(bj, gj)
    }

    /// Φ, Φ_z, Φ_t and c as the request asks, every constraint in turn (§4.6), at the
    /// kinematics of the last pass.
    #[inline(never)]
    pub(crate) fn constraint_terms(&mut self, t: f64, req: Request, out: &mut SystemTerms) {
        let (nz, nw) = (self.tree.n_z, self.tree.n_w);
        let mut node_columns = std::mem::replace(&mut self.rows.phi_w, DMatrix::zeros(0, 0));
        if req.jacobian {
            // Only the node-joint columns of Φ_w: the z columns go straight into Φ_z.
            let first = node_columns.nrows() * nz;
            node_columns.as_mut_slice()[first..].fill(0.0);
        }
        let SystemTerms {
            phi,
            phi_q,
            phi_t,
            accel_term,
            ..
        } = out;
        let mut jac = JacobianSink {
            phi_z: phi_q,
            node_columns: &mut node_columns,
            n_z: nz,
            write: req.jacobian,
        };
        let mut rows = RowTerms {
            phi,
            phi_t,
            accel_term,
            req,
        };
        let mut row = 0;
        for (c, &runs) in self.rows.constraints.iter().zip(&self.rows.paths.runs) {
            let rows = &mut rows;
            let jac = &mut jac;
            let row_at = RowAt { row, runs };
            match c {
                Constraint::Point { i, j } => self.point_constraint(row_at, i, j, rows, jac),
                Constraint::Angle2 {
                    i,
                    j,
                    psi0,
                    law,
                    sign,
                } => self.angle_constraint(row_at, (i, j), *psi0, law.eval(t), *sign, rows, jac),
                Constraint::Slide { i, nbar, j } => {
                    self.slide_constraint(row_at, i, nbar, j, rows, jac)
                }
                Constraint::Perp { i, abar, j, bbar } => {
                    self.perp_constraint(row_at, (i, abar), (j, bbar), rows, jac)
                }
                Constraint::Coord { z, law, sign } => {
                    self.coord_constraint(row, *z, law.eval(t), *sign, rows, jac)
                }
                Constraint::Distance { i, j, length } => {
                    self.distance_constraint(row_at, (i, j), *length, rows, jac)
                }
            }
            row += c.rows(self.tree.dim);
        }
        if req.jacobian {
            // Φ_z += Φ_w[:, node joints] L_node (L = [I; L_node]).
            for w in nz..nw {
                for &(c, a) in &self.tree.l_rows[w] {
                    jac.phi_z
                        .column_mut(c)
                        .axpy(a, &jac.node_columns.column(w), 1.0);
                }
            }
        }
        self.rows.phi_w = node_columns;
    }

    /// r_i − r_j = 0: rows `row..row + n_trans`.
    fn point_constraint(
        &self,
        RowAt { row, runs }: RowAt,
        i: &Side,
        j: &Side,
        rows: &mut RowTerms<'_>,
        jac: &mut JacobianSink<'_>,
    ) {
        let nt = self.tree.dim.n_trans();
        let (pi, vi) = point_at(self, i);
        let (pj, vj) = point_at(self, j);
        if rows.req.constraints {
            for a in 0..nt {
                rows.phi[row + a] = pi[a] - pj[a];
            }
        }
        if rows.req.jacobian || rows.req.accel_term {
            if jac.write {
                // The shared joints move both points: their columns are ω_a × (r_i − r_j).
                let joints = &self.rows.paths.joints;
                let rij = pi - pj;
                for &(a, w) in &joints[runs[0]..runs[1]] {
                    let u = self.frames.elem_twist[a].fixed_rows::<3>(3).cross(&rij);
                    self.add_point_column(jac, row, w, &u);
                }
                self.point_columns_from(jac, row, &joints[runs[1]..runs[2]], &pi, 1.0);
                self.point_columns_from(jac, row, &joints[runs[2]..runs[3]], &pj, -1.0);
            }
            // The Cartesian bias is for c only; a side at a node writes its modal columns
            // there too.
            if rows.req.accel_term || i.node.is_some() || j.node.is_some() {
                let bias = self.point_rows(jac, row, i, &pi, &vi, 1.0)
                    - self.point_rows(jac, row, j, &pj, &vj, -1.0);
                if rows.req.accel_term {
                    for a in 0..nt {
                        rows.accel_term[row + a] = bias[a];
                    }
                }
            }
        }
    }

    /// Column w of the point rows `row..row + n_trans`: += u.
    #[inline(always)]
    fn add_point_column(&self, jac: &mut JacobianSink<'_>, row: usize, w: usize, u: &Vector3<f64>) {
        for c in 0..self.tree.dim.n_trans() {
            jac.add(row + c, w, u[c]);
        }
    }

    /// The columns of a point p per unit rate of the elementary joints `joints` ((joint, w)),
    /// u_a = ṡ_a + ω_a × p, signed by `sg`, into rows `row..row + n_trans`.
    fn point_columns_from(
        &self,
        jac: &mut JacobianSink<'_>,
        row: usize,
        joints: &[(usize, usize)],
        p: &Vector3<f64>,
        sg: f64,
    ) {
        for &(a, w) in joints {
            let elem_twist = &self.frames.elem_twist[a];
            let u = elem_twist.fixed_rows::<3>(0) + elem_twist.fixed_rows::<3>(3).cross(p);
            self.add_point_column(jac, row, w, &(sg * u));
        }
    }

    /// 2D: sin(θ_j − θ_i − ψ₀ − s θ(t)) = 0, the sides given as (i, j), the law's
    /// (θ, θ̇, θ̈) at t as `drive`.
    #[allow(clippy::too_many_arguments)]
    fn angle_constraint(
        &self,
        RowAt { row, runs }: RowAt,
        (i, j): (&Side, &Side),
        psi0: f64,
        drive: (f64, f64, f64),
        sign: f64,
        rows: &mut RowTerms<'_>,
        jac: &mut JacobianSink<'_>,
    ) {
        let (th, thd, thdd) = drive;
        let (ti, wi) = angle_at(self, i);
        let (tj, wj) = angle_at(self, j);
        let delta = tj - ti - psi0 - sign * th;
        let (sd, cd) = delta.sin_cos();
        if rows.req.constraints {
            rows.phi[row] = sd;
        }
        if rows.req.jacobian || rows.req.accel_term {
            let (mut gi, mut gj) = (Vector6::zeros(), Vector6::zeros());
            gj[5] = cd;
            gi[5] = -cd;
            let bias = self.pair_row(jac, row, runs, (i.body, &gi), (j.body, &gj));
            self.rot_modal(jac, row, j, cd);
            self.rot_modal(jac, row, i, -cd);
            let rate = wj - wi - sign * thd;
            if rows.req.jacobian {
                rows.phi_t[row] = -cd * sign * thd;
            }
            if rows.req.accel_term {
                rows.accel_term[row] = bias - sd * rate * rate - cd * sign * thdd;
            }
        }
    }

    /// n · (r_j − r_i) = 0 with n = A_i n̄ fixed at side i.
    fn slide_constraint(
        &self,
        RowAt { row, runs }: RowAt,
        i: &Side,
        nbar: &Vector3<f64>,
        j: &Side,
        rows: &mut RowTerms<'_>,
        jac: &mut JacobianSink<'_>,
    ) {
        let (n, nd) = dir_at(self, i, nbar);
        let (pi, vi) = point_at(self, i);
        let (pj, vj) = point_at(self, j);
        let d = pj - pi;
        let dd = vj - vi;
        if rows.req.constraints {
            rows.phi[row] = n.dot(&d);
        }
        if rows.req.jacobian || rows.req.accel_term {
            let (gj, rest_j) = self.point_side(jac, row, j, &pj, &vj, &n, 1.0);
            let (gi_point, rest_i) = self.point_side(jac, row, i, &pi, &vi, &n, -1.0);
            let (gi_dir, rest_dir) = self.dir_side(jac, row, i, nbar, &n, &nd, &d);
            let gi = gi_point + gi_dir;
            let mut bias = self.pair_row(jac, row, runs, (i.body, &gi), (j.body, &gj));
            bias += rest_j - rest_i + rest_dir;
            bias += 2.0 * nd.dot(&dd);
            if rows.req.accel_term {
                rows.accel_term[row] = bias;
            }
        }
    }

    /// a · b = 0, a = A_i ā fixed at side i, b = A_j b̄ at side j.
    fn perp_constraint(
        &self,
        RowAt { row, runs }: RowAt,
        (i, abar): (&Side, &Vector3<f64>),
        (j, bbar): (&Side, &Vector3<f64>),
        rows: &mut RowTerms<'_>,
        jac: &mut JacobianSink<'_>,
    ) {
        let (a, ad) = dir_at(self, i, abar);
        let (b, bd) = dir_at(self, j, bbar);
        if rows.req.constraints {
            rows.phi[row] = a.dot(&b);
        }
        if rows.req.jacobian || rows.req.accel_term {
            let (gi, rest_i) = self.dir_side(jac, row, i, abar, &a, &ad, &b);
            let (gj, rest_j) = self.dir_side(jac, row, j, bbar, &b, &bd, &a);
            let mut bias = self.pair_row(jac, row, runs, (i.body, &gi), (j.body, &gj));
            bias += rest_i + rest_j;
            bias += 2.0 * ad.dot(&bd);
            if rows.req.accel_term {
                rows.accel_term[row] = bias;
            }
        }
    }

    /// ½(|r_j − r_i|² − L²) = 0 (`flexmbd_model::constraint_equations::distance`): its
    /// gradient d = r_j − r_i weights the points' Jacobian rows, and the points' biases come
    /// from the same walk as d·(bias_j − bias_i).
    fn distance_constraint(
        &self,
        RowAt { row, runs }: RowAt,
        (i, j): (&Side, &Side),
        length: f64,
        rows: &mut RowTerms<'_>,
        jac: &mut JacobianSink<'_>,
    ) {
        let (pi, vi) = point_at(self, i);
        let (pj, vj) = point_at(self, j);
        let d = Motion {
            value: pj - pi,
            rate: vj - vi,
            bias: Vector3::zeros(), // added below, as d·bias
        };
        let equation = distance(&d, length);
        if rows.req.constraints {
            rows.phi[row] = equation.phi;
        }
        if rows.req.jacobian || rows.req.accel_term {
            let (gj, rest_j) = self.point_side(jac, row, j, &pj, &vj, &d.value, 1.0);
            let (gi, rest_i) = self.point_side(jac, row, i, &pi, &vi, &d.value, -1.0);
            let d_bias =
                self.pair_row(jac, row, runs, (i.body, &gi), (j.body, &gj)) + rest_j - rest_i;
            if rows.req.accel_term {
                rows.accel_term[row] = equation.accel_term + d_bias;
            }
        }
    }

    /// z_c − s θ(t) = 0 (a driven joint of the tree), the law's (θ, θ̇, θ̈) at t as `drive`.
    fn coord_constraint(
        &self,
        row: usize,
        zc: usize,
        drive: (f64, f64, f64),
        sign: f64,
        rows: &mut RowTerms<'_>,
        jac: &mut JacobianSink<'_>,
    ) {
        let (th, thd, thdd) = drive;
        if rows.req.constraints {
            rows.phi[row] = self.frames.last_z[zc] - sign * th;
        }
        if rows.req.jacobian {
            jac.add(row, zc, 1.0);
        }
        if rows.req.jacobian {
            rows.phi_t[row] = -sign * thd;
        }
        if rows.req.accel_term {
            rows.accel_term[row] = -sign * thdd;
        }
    }

    /// The modal columns of rows `row..row + n_trans` of r_P for a point of side `s` (sign
    /// `sg` applied; its path's columns are written by `point_constraint`), and the Cartesian
    /// bias D_s + D_ω × p + ω × ṙ_P + ω × A X ẏ (returned unsigned).
    pub(crate) fn point_rows(
        &self,
        jac: &mut JacobianSink<'_>,
        row: usize,
        s: &Side,
        p: &Vector3<f64>,
        v: &Vector3<f64>,
        sg: f64,
    ) -> Vector3<f64> {
        let Some(k) = s.body else {
            return Vector3::zeros();
        };
        let nt = self.tree.dim.n_trans();
        let f = self.bodies[k].frame;
        let d = &self.frames.bias[f];
        let w = self.frames.velocity[f].fixed_rows::<3>(3).into_owned();
        let mut bias = d.fixed_rows::<3>(0) + d.fixed_rows::<3>(3).cross(p) + w.cross(v);
        if let Some(node) = s.node {
            let b = &self.bodies[k];
            let a = self.frames.rotation[f];
            let mut xy = Vector3::zeros();
            for m in 0..b.n_modes {
                let col = Vector3::new(
                    b.node_rows.translation_entry(node, 0, m),
                    b.node_rows.translation_entry(node, 1, m),
                    b.node_rows.translation_entry(node, 2, m),
                );
                if jac.write {
                    let ac = a * col;
                    for c in 0..nt {
                        jac.add(row + c, b.first_mode + m, sg * ac[c]);
                    }
                }
                xy += col * self.frames.last_zd[b.first_mode + m];
            }
            bias += w.cross(&(a * xy));
        }
        bias
    }

    /// Side `s`'s share of a row e·r_P (sign `sg`): its coefficient g = sg {e; p × e} on
    /// the body's Z_k (walked by [`pair_row`](Self::pair_row)), its node's modal columns, and
    /// the Cartesian bias e·(ω × ṙ_P + ω × A X ẏ) without g·D (returned unsigned).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn point_side(
        &self,
        jac: &mut JacobianSink<'_>,
        row: usize,
        s: &Side,
        p: &Vector3<f64>,
        v: &Vector3<f64>,
        e: &Vector3<f64>,
        sg: f64,
    ) -> (Vector6<f64>, f64) {
        let mut g = Vector6::zeros();
        let Some(k) = s.body else { return (g, 0.0) };
        g.fixed_rows_mut::<3>(0).copy_from(&(sg * e));
        g.fixed_rows_mut::<3>(3).copy_from(&(sg * p.cross(e)));
        let f = self.bodies[k].frame;
        let a = self.frames.rotation[f];
        let w = self.frames.velocity[f].fixed_rows::<3>(3).into_owned();
        let mut bias = e.dot(&w.cross(v));
        if let Some(node) = s.node {
            let b = &self.bodies[k];
            let at_e = a.transpose() * e;
            let mut axy = Vector3::zeros();
            for m in 0..b.n_modes {
                let col = Vector3::new(
                    b.node_rows.translation_entry(node, 0, m),
                    b.node_rows.translation_entry(node, 1, m),
                    b.node_rows.translation_entry(node, 2, m),
                );
                if jac.write {
                    jac.add(row, b.first_mode + m, sg * at_e.dot(&col));
                }
                axy += col * self.frames.last_zd[b.first_mode + m];
            }
            bias += e.dot(&w.cross(&(a * axy)));
        }
        (g, bias)
    }

    /// Side `s`'s share of a row d·u for a direction d = A (d̄ + θ̄ × d̄) there (u held
    /// fixed): its coefficient g = {0; d × u} on the body's Z_k, its node's modal columns, and
    /// the bias (ω × ḋ + ω × A (θ̄̇ × d̄))·u without g·D.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn dir_side(
        &self,
        jac: &mut JacobianSink<'_>,
        row: usize,
        s: &Side,
        dbar: &Vector3<f64>,
        d: &Vector3<f64>,
        dd: &Vector3<f64>,
        u: &Vector3<f64>,
    ) -> (Vector6<f64>, f64) {
        let mut g = Vector6::zeros();
        let Some(k) = s.body else { return (g, 0.0) };
        g.fixed_rows_mut::<3>(3).copy_from(&d.cross(u));
        let f = self.bodies[k].frame;
        let a = self.frames.rotation[f];
        let w = self.frames.velocity[f].fixed_rows::<3>(3).into_owned();
        // ä_bias = ω × ḋ + ω × A (θ̄̇ × d̄).
        let mut extra = Vector3::zeros();
        if let Some(node) = s.node {
            let b = &self.bodies[k];
            let at_u = a.transpose() * u;
            let mut th_d = Vector3::zeros();
            for m in 0..b.n_modes {
                let col = Vector3::new(
                    b.node_rows.rotation_entry(node, 0, m),
                    b.node_rows.rotation_entry(node, 1, m),
                    b.node_rows.rotation_entry(node, 2, m),
                );
                if jac.write {
                    jac.add(row, b.first_mode + m, at_u.dot(&col.cross(dbar)));
                }
                th_d += col * self.frames.last_zd[b.first_mode + m];
            }
            extra = a * th_d.cross(dbar);
        }
        (g, (w.cross(dd) + w.cross(&extra)).dot(u))
    }

    /// Modal coefficients of a 2D node rotation, scaled.
    pub(crate) fn rot_modal(&self, jac: &mut JacobianSink<'_>, row: usize, s: &Side, scale: f64) {
        let (Some(k), Some(node)) = (s.body, s.node) else {
            return;
        };
        if !jac.write {
            return;
        }
        let b = &self.bodies[k];
        for m in 0..b.n_modes {
            jac.add(
                row,
                b.first_mode + m,
                scale * b.node_rows.rotation_entry(node, 2, m),
            );
        }
    }
}
