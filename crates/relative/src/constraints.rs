//! The constraints Φ, their Jacobian Φ_z and the acceleration term c (docs/methods.md §4.6).
//!
//! Every constraint is written in the Cartesian positions of its two markers (point
//! coincidence r_i − r_j; 2D angle sin(ψ − ψ₀ − s θ(t)); perpendicularity a·b; sliding
//! n·(r_j − r_i), which is also the scene's `PointInPlane`; the scene's `Distance`
//! ½(|r_j − r_i|² − L²)), or in one tree coordinate (z_c − s θ(t)). Its Jacobian row in w walks
//! each body's path to the root, Φ_w = Σ_k Φ_{Z_k} R_k (plus the node's modal columns), and
//! is folded into z by Φ_z = Φ_w L; c = Σ_k Φ_{Z_k} {D_k; 0} + the Cartesian
//! velocity-product terms + Φ̇_t. Redundant closure equations are kept (ALI3-P tolerates
//! them). The constraints themselves are built in `cut_joints`.

use flexmbd_core::{Dim, Request, SystemTerms};
use flexmbd_model::MotionLaw;
use flexmbd_model::constraint_equations::{Motion, distance};
use nalgebra::{Vector3, Vector6};

use crate::kinematics::{angle_at, dir_at, point_at};
use crate::system::Relative;
use crate::topology::Side;

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
}

impl Relative {
    /// Add g·Z_k (and the modal coefficients, by the caller) to row `row` of Φ_w; returns g·D_k.
    pub(crate) fn body_row(&mut self, row: usize, body: Option<usize>, g: &Vector6<f64>) -> f64 {
        let Some(k) = body else { return 0.0 };
        let f = self.bodies[k].frame;
        if !self.write_jacobian {
            return g.dot(&self.frame_bias[f]);
        }
        for &a in &self.paths[f] {
            self.phi_w[(row, self.elem_w[a])] += g.dot(&self.elem_twist[a]);
        }
        g.dot(&self.frame_bias[f])
    }

    /// Φ, Φ_z, Φ_t and c as the request asks, every constraint in turn (§4.6), at the
    /// kinematics of the last pass.
    #[inline(never)]
    pub(crate) fn constraint_terms(&mut self, t: f64, req: Request, out: &mut SystemTerms) {
        self.write_jacobian = req.jacobian;
        if req.jacobian {
            self.phi_w.as_mut_slice().fill(0.0);
        }
        // Lent out for the pass, so that the rows can borrow `self` mutably.
        let constraints = std::mem::take(&mut self.constraints);
        let mut row = 0;
        for c in &constraints {
            match c {
                Constraint::Point { i, j } => self.point_constraint(row, i, j, req, out),
                Constraint::Angle2 {
                    i,
                    j,
                    psi0,
                    law,
                    sign,
                } => self.angle_constraint(row, (i, j), *psi0, law.eval(t), *sign, req, out),
                Constraint::Slide { i, nbar, j } => {
                    self.slide_constraint(row, i, nbar, j, req, out)
                }
                Constraint::Perp { i, abar, j, bbar } => {
                    self.perp_constraint(row, (i, abar), (j, bbar), req, out)
                }
                Constraint::Coord { z, law, sign } => {
                    self.coord_constraint(row, *z, law.eval(t), *sign, req, out)
                }
                Constraint::Distance { i, j, length } => {
                    self.distance_constraint(row, (i, j), *length, req, out)
                }
            }
            row += c.rows(self.dim);
        }
        self.constraints = constraints;
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

    /// r_i − r_j = 0: rows `row..row + n_trans`.
    fn point_constraint(
        &mut self,
        row: usize,
        i: &Side,
        j: &Side,
        req: Request,
        out: &mut SystemTerms,
    ) {
        let nt = self.dim.n_trans();
        let (pi, vi) = point_at(self, i);
        let (pj, vj) = point_at(self, j);
        if req.constraints {
            for a in 0..nt {
                out.phi[row + a] = pi[a] - pj[a];
            }
        }
        if req.jacobian || req.accel_term {
            let bias =
                self.point_rows(row, i, &pi, &vi, 1.0) - self.point_rows(row, j, &pj, &vj, -1.0);
            if req.accel_term {
                for a in 0..nt {
                    out.accel_term[row + a] = bias[a];
                }
            }
        }
    }

    /// 2D: sin(θ_j − θ_i − ψ₀ − s θ(t)) = 0, the sides given as (i, j), the law's
    /// (θ, θ̇, θ̈) at t as `drive`.
    fn angle_constraint(
        &mut self,
        row: usize,
        (i, j): (&Side, &Side),
        psi0: f64,
        drive: (f64, f64, f64),
        sign: f64,
        req: Request,
        out: &mut SystemTerms,
    ) {
        let (th, thd, thdd) = drive;
        let (ti, wi) = angle_at(self, i);
        let (tj, wj) = angle_at(self, j);
        let delta = tj - ti - psi0 - sign * th;
        let (sd, cd) = delta.sin_cos();
        if req.constraints {
            out.phi[row] = sd;
        }
        if req.jacobian || req.accel_term {
            let mut g = Vector6::zeros();
            g[5] = cd;
            let mut bias = self.body_row(row, j.body, &g);
            self.rot_modal(row, j, cd);
            g[5] = -cd;
            bias += self.body_row(row, i.body, &g);
            self.rot_modal(row, i, -cd);
            let rate = wj - wi - sign * thd;
            if req.jacobian {
                out.phi_t[row] = -cd * sign * thd;
            }
            if req.accel_term {
                out.accel_term[row] = bias - sd * rate * rate - cd * sign * thdd;
            }
        }
    }

    /// n · (r_j − r_i) = 0 with n = A_i n̄ fixed at side i.
    fn slide_constraint(
        &mut self,
        row: usize,
        i: &Side,
        nbar: &Vector3<f64>,
        j: &Side,
        req: Request,
        out: &mut SystemTerms,
    ) {
        let (n, nd) = dir_at(self, i, nbar);
        let (pi, vi) = point_at(self, i);
        let (pj, vj) = point_at(self, j);
        let d = pj - pi;
        let dd = vj - vi;
        if req.constraints {
            out.phi[row] = n.dot(&d);
        }
        if req.jacobian || req.accel_term {
            let mut bias = self.point_row(row, j, &pj, &vj, &n, 1.0)
                - self.point_row(row, i, &pi, &vi, &n, -1.0);
            bias += self.dir_row(row, i, nbar, &n, &nd, &d);
            bias += 2.0 * nd.dot(&dd);
            if req.accel_term {
                out.accel_term[row] = bias;
            }
        }
    }

    /// a · b = 0, a = A_i ā fixed at side i, b = A_j b̄ at side j.
    fn perp_constraint(
        &mut self,
        row: usize,
        (i, abar): (&Side, &Vector3<f64>),
        (j, bbar): (&Side, &Vector3<f64>),
        req: Request,
        out: &mut SystemTerms,
    ) {
        let (a, ad) = dir_at(self, i, abar);
        let (b, bd) = dir_at(self, j, bbar);
        if req.constraints {
            out.phi[row] = a.dot(&b);
        }
        if req.jacobian || req.accel_term {
            let mut bias = self.dir_row(row, i, abar, &a, &ad, &b);
            bias += self.dir_row(row, j, bbar, &b, &bd, &a);
            bias += 2.0 * ad.dot(&bd);
            if req.accel_term {
                out.accel_term[row] = bias;
            }
        }
    }

    /// ½(|r_j − r_i|² − L²) = 0 (`flexmbd_model::constraint_equations::distance`): its
    /// gradient d = r_j − r_i weights the points' Jacobian rows, and the points' biases come
    /// from the same walk as d·(bias_j − bias_i).
    fn distance_constraint(
        &mut self,
        row: usize,
        (i, j): (&Side, &Side),
        length: f64,
        req: Request,
        out: &mut SystemTerms,
    ) {
        let (pi, vi) = point_at(self, i);
        let (pj, vj) = point_at(self, j);
        let d = Motion {
            value: pj - pi,
            rate: vj - vi,
            bias: Vector3::zeros(), // added below, as d·bias
        };
        let equation = distance(&d, length);
        if req.constraints {
            out.phi[row] = equation.phi;
        }
        if req.jacobian || req.accel_term {
            let d_bias = self.point_row(row, j, &pj, &vj, &d.value, 1.0)
                - self.point_row(row, i, &pi, &vi, &d.value, -1.0);
            if req.accel_term {
                out.accel_term[row] = equation.accel_term + d_bias;
            }
        }
    }

    /// z_c − s θ(t) = 0 (a driven joint of the tree), the law's (θ, θ̇, θ̈) at t as `drive`.
    fn coord_constraint(
        &mut self,
        row: usize,
        zc: usize,
        drive: (f64, f64, f64),
        sign: f64,
        req: Request,
        out: &mut SystemTerms,
    ) {
        let (th, thd, thdd) = drive;
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

    /// Jacobian rows `row..row + n_trans` of r_P for a point of side `s` (sign `sg` applied
    /// to the rows; one walk of the path for all components), and the Cartesian bias
    /// D_s + D_ω × p + ω × ṙ_P + ω × A X ẏ (returned unsigned).
    pub(crate) fn point_rows(
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
        if self.write_jacobian {
            for &a in &self.paths[f] {
                // Velocity of the point per unit rate of elementary joint a.
                let elem_twist = &self.elem_twist[a];
                let u = elem_twist.fixed_rows::<3>(0) + elem_twist.fixed_rows::<3>(3).cross(p);
                let wa = self.elem_w[a];
                for c in 0..nt {
                    self.phi_w[(row + c, wa)] += sg * u[c];
                }
            }
        }
        let d = &self.frame_bias[f];
        let w = self.frame_velocity[f].fixed_rows::<3>(3).into_owned();
        let mut bias = d.fixed_rows::<3>(0) + d.fixed_rows::<3>(3).cross(p) + w.cross(v);
        if let Some(node) = s.node {
            let b = &self.bodies[k];
            let a = self.frame_rotation[f];
            let mut xy = Vector3::zeros();
            for m in 0..b.n_modes {
                let col = Vector3::new(
                    b.node_rows.translation_entry(node, 0, m),
                    b.node_rows.translation_entry(node, 1, m),
                    b.node_rows.translation_entry(node, 2, m),
                );
                if self.write_jacobian {
                    let ac = a * col;
                    for c in 0..nt {
                        self.phi_w[(row + c, b.first_mode + m)] += sg * ac[c];
                    }
                }
                xy += col * self.last_zd[b.first_mode + m];
            }
            bias += w.cross(&(a * xy));
        }
        bias
    }

    /// Jacobian row of e·r_P for a point of side `s` (sign `sg` applied to the row) and the
    /// Cartesian bias e·(ω × ṙ_P + ω × A X ẏ) + g·D (returned unsigned).
    pub(crate) fn point_row(
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
        let a = self.frame_rotation[f];
        let w = self.frame_velocity[f].fixed_rows::<3>(3).into_owned();
        let mut bias = gd + e.dot(&w.cross(v));
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
                if self.write_jacobian {
                    self.phi_w[(row, b.first_mode + m)] += sg * at_e.dot(&col);
                }
                axy += col * self.last_zd[b.first_mode + m];
            }
            bias += e.dot(&w.cross(&(a * axy)));
        }
        bias
    }

    /// Jacobian row of d·u for a direction d = A (d̄ + θ̄ × d̄) at side `s` (u specified fixed),
    /// and its bias terms (D part, ä_bias · u); returned.
    pub(crate) fn dir_row(
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
        let a = self.frame_rotation[f];
        let w = self.frame_velocity[f].fixed_rows::<3>(3).into_owned();
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
                if self.write_jacobian {
                    self.phi_w[(row, b.first_mode + m)] += at_u.dot(&col.cross(dbar));
                }
                th_d += col * self.last_zd[b.first_mode + m];
            }
            extra = a * th_d.cross(dbar);
        }
        gd + (w.cross(dd) + w.cross(&extra)).dot(u)
    }

    /// Modal coefficients of a 2D node rotation, scaled.
    pub(crate) fn rot_modal(&mut self, row: usize, s: &Side, scale: f64) {
        let (Some(k), Some(node)) = (s.body, s.node) else {
            return;
        };
        if !self.write_jacobian {
            return;
        }
        let b = &self.bodies[k];
        for m in 0..b.n_modes {
            self.phi_w[(row, b.first_mode + m)] += scale * b.node_rows.rotation_entry(node, 2, m);
        }
    }
}
