//! The kinematic pass (docs/methods.md §4.5 steps 1–3) and the marker kinematics built on it.
//!
//! Root → leaves along the augmented tree, a fixed frame carries its parent's frame by a
//! constant offset and rotation, and an elementary joint e of value e = L_e z moves its frame
//! by its twist v_e (§4.2):
//!
//! ```text
//! Z^r_next = Z^r_f + v_e ė,  D_next = D_f + d_e
//! revolute about a through p:  v = {p × a; a},  d = {(ṗ × a + p × (ω_f × a)) ė; (ω_f × a) ė}
//! prismatic along a:           v = {a; 0},      d = {(ω_f × a) ė; 0}
//! ```
//!
//! Positions and twists depend on z only and are recomputed only when z changed; Z and D
//! only when z or ż changed. A marker's position, velocity and direction follow from its
//! body's frame and, at an FE node, from the node's mode rows X^t, X^r (§4.3):
//! r = r0 + A (r̄ + X^t y), d = A (d̄ + θ̄ × d̄), θ̄ = X^r y.

use flexmbd_body::BodyState;
use nalgebra::{DVector, Matrix3, Rotation3, Unit, Vector3, Vector6};

use crate::system::{Relative, RunTimeBody};
use crate::topology::{ElemKind, FrameKind, Side};

/// The angle of a rotation about z, atan2(A₁₀, A₀₀).
pub(crate) fn angle_of(a: &Matrix3<f64>) -> f64 {
    a[(1, 0)].atan2(a[(0, 0)])
}

impl Relative {
    /// §4.5 steps 1–3: positions, velocities Z^r and velocity-product accelerations D of
    /// every frame, root → leaves; twists v_e of the elementary joints. Sets `last_z`,
    /// `last_zd` and the caches of [`update_positions`](Self::update_positions) and
    /// [`update_velocities`](Self::update_velocities).
    pub(crate) fn kinematics(&mut self, z: &DVector<f64>, zd: &DVector<f64>) {
        self.frames.last_z.copy_from(z);
        self.frames.last_zd.copy_from(zd);
        self.positions();
        self.frames.positions_current = true;
        self.velocities();
        self.frames.velocities_zd.copy_from(zd);
        self.frames.velocities_current = true;
    }

    /// Positions (and twists) at z unless they are already those of `last_z`; invalidates
    /// the velocities when z changed.
    pub(crate) fn update_positions(&mut self, z: &DVector<f64>) {
        if self.frames.positions_current && self.frames.last_z.as_slice() == z.as_slice() {
            return;
        }
        self.frames.last_z.copy_from(z);
        self.positions();
        self.frames.positions_current = true;
        self.frames.velocities_current = false;
    }

    /// Velocities and D at `last_zd` unless already done at these positions and rates.
    pub(crate) fn update_velocities(&mut self) {
        if self.frames.velocities_current
            && self.frames.velocities_zd.as_slice() == self.frames.last_zd.as_slice()
        {
            return;
        }
        self.frames.velocities_zd.copy_from(&self.frames.last_zd);
        self.velocities();
        self.frames.velocities_current = true;
    }

    /// Steps 1–2 at z = `last_z`: r_F, A_F of every frame and the twists v_e (they depend
    /// on positions only), root → leaves.
    #[inline(never)]
    pub(crate) fn positions(&mut self) {
        self.forces.marker_table.invalidate();
        let z = self.frames.last_z.as_slice();
        // The frame just computed, kept in registers: most frames' parent is the frame
        // before them (a chain), and reading it back from the arrays it was just stored to
        // stalls (a wide load over narrower stores cannot be forwarded).
        let (mut r_last, mut a_last) = (Vector3::zeros(), Matrix3::identity());
        for f in 0..self.tree.topology.frames.len() {
            let (rp, ap) = match self.tree.topology.frames[f].parent {
                None => (Vector3::zeros(), Matrix3::identity()),
                Some(p) if p + 1 == f => (r_last, a_last),
                Some(p) => (self.frames.position[p], self.frames.rotation[p]),
            };
            let (r, a) = match &self.tree.topology.frames[f].kind {
                FrameKind::Fixed { offset, rot } => {
                    if self.tree.planar_frames {
                        // ap = [R_p 0; 0 1], rot = [R 0; 0 1]: the products' third terms
                        // are exact zeros.
                        let mut r = rp;
                        r.x += ap[(0, 0)] * offset.x + ap[(0, 1)] * offset.y;
                        r.y += ap[(1, 0)] * offset.x + ap[(1, 1)] * offset.y;
                        r.z += offset.z;
                        let mut a = ap;
                        if !self.tree.fixed_identity[f] {
                            for i in 0..2 {
                                let (p0, p1) = (ap[(i, 0)], ap[(i, 1)]);
                                a[(i, 0)] = p0 * rot[(0, 0)] + p1 * rot[(1, 0)];
                                a[(i, 1)] = p0 * rot[(0, 1)] + p1 * rot[(1, 1)];
                            }
                        }
                        (r, a)
                    } else {
                        let a = if self.tree.fixed_identity[f] {
                            ap
                        } else {
                            ap * rot
                        };
                        (rp + ap * offset, a)
                    }
                }
                FrameKind::Elem(e) => {
                    let e = *e;
                    let el = &self.tree.topology.elems[e];
                    let mut val = 0.0;
                    for &(c, k) in &self.tree.elem_rate[e] {
                        val += k * z[c];
                    }
                    let a = ap * el.axis;
                    let mut v = Vector6::zeros();
                    let moved = match el.kind {
                        ElemKind::Revolute => {
                            // b = {p × a; a}.
                            v.fixed_rows_mut::<3>(0).copy_from(&rp.cross(&a));
                            v.fixed_rows_mut::<3>(3).copy_from(&a);
                            if el.axis == Vector3::z() {
                                // A_p R_z(val), R_z as `from_axis_angle` forms it for ā = z.
                                let (sn, cs) = val.sin_cos();
                                let mut a_new = ap;
                                for i in 0..3 {
                                    let (c0, c1) = (ap[(i, 0)], ap[(i, 1)]);
                                    a_new[(i, 0)] = c0 * cs + c1 * sn;
                                    a_new[(i, 1)] = c1 * cs - c0 * sn;
                                }
                                (rp, a_new)
                            } else {
                                let turn =
                                    Rotation3::from_axis_angle(&Unit::new_unchecked(el.axis), val);
                                (rp, ap * turn.matrix())
                            }
                        }
                        ElemKind::Prismatic => {
                            // b = {a; 0}.
                            v.fixed_rows_mut::<3>(0).copy_from(&a);
                            (rp + a * val, ap)
                        }
                    };
                    self.frames.elem_twist[e] = v;
                    moved
                }
            };
            self.frames.position[f] = r;
            self.frames.rotation[f] = a;
            (r_last, a_last) = (r, a);
        }
    }

    /// Step 3 at ż = `last_zd` (positions current): Z^r_F and D_F, root → leaves.
    #[inline(never)]
    pub(crate) fn velocities(&mut self) {
        self.forces.marker_table.invalidate();
        let zd = self.frames.last_zd.as_slice();
        // Only the frames of elementary joints (in tree order) and of bodies: a fixed frame
        // has its parent's Z and D.
        // The last joint's Z and D kept in registers, as in `positions` (most joints' parent
        // is the joint before them).
        let (mut z_last, mut d_last) = (Vector6::zeros(), Vector6::zeros());
        for e in 0..self.tree.topology.elems.len() {
            let el = &self.tree.topology.elems[e];
            let f = el.frame;
            let (zp, dp) = match self.tree.elem_parent[e] {
                None => (Vector6::zeros(), Vector6::zeros()),
                Some(pe) if pe + 1 == e => (z_last, d_last),
                Some(pe) => {
                    let pf = self.tree.topology.elems[pe].frame;
                    (self.frames.velocity[pf], self.frames.bias[pf])
                }
            };
            let mut rate = 0.0;
            for &(c, k) in &self.tree.elem_rate[e] {
                rate += k * zd[c];
            }
            let v = self.frames.elem_twist[e];
            let w_f = zp.fixed_rows::<3>(3).into_owned();
            let mut d = dp;
            match el.kind {
                ElemKind::Revolute => {
                    // d = {(ṗ × a + p × (ω_f × a)) ė; (ω_f × a) ė}.
                    let a = v.fixed_rows::<3>(3).into_owned();
                    let wxa = w_f.cross(&a);
                    let rp = self.frames.position[f];
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
            let z_f = zp + v * rate;
            self.frames.velocity[f] = z_f;
            self.frames.bias[f] = d;
            // The bodies whose nearest elementary joint this is have its Z and D, written
            // from registers (copying them from the arrays just written would stall, as above).
            for &k in &self.tree.elem_bodies[e] {
                let bf = self.bodies[k].frame;
                self.frames.velocity[bf] = z_f;
                self.frames.bias[bf] = d;
            }
            (z_last, d_last) = (z_f, d);
        }
        // A body with no elementary joint towards the root is fixed to the ground.
        for b in &self.bodies {
            if self.tree.paths[b.frame].is_empty() {
                self.frames.velocity[b.frame] = Vector6::zeros();
                self.frames.bias[b.frame] = Vector6::zeros();
            }
        }
    }

    pub(crate) fn body_state<'a>(
        &self,
        k: usize,
        z: &'a DVector<f64>,
        zd: &'a DVector<f64>,
    ) -> BodyState<'a> {
        let b = &self.bodies[k];
        let f = b.frame;
        let zr = self.frames.velocity[f];
        BodyState {
            r0: self.frames.position[f],
            a: self.frames.rotation[f],
            omega: zr.fixed_rows::<3>(3).into_owned(),
            s_dot: zr.fixed_rows::<3>(0).into_owned(),
            y: &z.as_slice()[b.first_mode..b.first_mode + b.n_modes],
            y_dot: &zd.as_slice()[b.first_mode..b.first_mode + b.n_modes],
        }
    }
}

/// Global position and velocity of a marker: r = r0 + A (r̄ + X^t y), ṙ = ṡ + ω × r + A X^t ẏ.
/// Inlined for a rigid marker (its two vectors come back in registers, not through memory
/// read back at once); a marker at a node is evaluated out of line.
#[inline(always)]
pub(crate) fn point_at(rel: &Relative, s: &Side) -> (Vector3<f64>, Vector3<f64>) {
    let Some(k) = s.body else {
        return (s.rbar, Vector3::zeros());
    };
    if s.node.is_some() {
        return node_point_at(rel, k, s);
    }
    let f = rel.bodies[k].frame;
    let (r0, a, zr) = (
        &rel.frames.position[f],
        &rel.frames.rotation[f],
        &rel.frames.velocity[f],
    );
    let p = r0 + a * s.rbar;
    let sd = zr.fixed_rows::<3>(0).into_owned();
    let w = zr.fixed_rows::<3>(3).into_owned();
    (p, sd + w.cross(&p) + a * Vector3::zeros())
}

/// [`point_at`] for a marker at a node of body k: r̄ + X^t y with FS0's axial shift, and
/// its rate X^t ẏ, at the last (z, ż).
#[inline(never)]
fn node_point_at(rel: &Relative, k: usize, s: &Side) -> (Vector3<f64>, Vector3<f64>) {
    let b = &rel.bodies[k];
    let f = b.frame;
    let (r0, a, zr) = (
        rel.frames.position[f],
        rel.frames.rotation[f],
        rel.frames.velocity[f],
    );
    let mut pl = s.rbar;
    let mut vl = Vector3::zeros();
    if let Some(node) = s.node {
        add_node_modes(rel, b, &mut pl, &mut vl, |i, m| {
            b.node_rows.translation_entry(node, i, m)
        });
        // FS0 (docs/methods.md §6.3): the node's axial shift −½ ē₁ yᵀF y and its rate.
        let ys = b.first_mode..b.first_mode + b.n_modes;
        let (y, yd) = (
            &rel.frames.last_z.as_slice()[ys.clone()],
            &rel.frames.last_zd.as_slice()[ys],
        );
        let shift = b
            .kernel
            .flexible()
            .and_then(|f| f.body.node_foreshortening(node, y, yd));
        if let Some(sh) = shift {
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
    let (a, zr) = (rel.frames.rotation[f], rel.frames.velocity[f]);
    let w = zr.fixed_rows::<3>(3).into_owned();
    let (mut th, mut thd) = (Vector3::zeros(), Vector3::zeros());
    if let Some(node) = s.node {
        add_node_modes(rel, b, &mut th, &mut thd, |i, m| {
            b.node_rows.rotation_entry(node, i, m)
        });
    }
    let d = a * (dbar + th.cross(dbar));
    (d, w.cross(&d) + a * thd.cross(dbar))
}

/// Add Σ_m X_m y_m to `x` and Σ_m X_m ẏ_m to `xd`, over the modes m of body `b` in order, at
/// the last (z, ż); `rows(i, m)` is component i of X_m, a node's translation or rotation rows.
fn add_node_modes(
    rel: &Relative,
    b: &RunTimeBody,
    x: &mut Vector3<f64>,
    xd: &mut Vector3<f64>,
    rows: impl Fn(usize, usize) -> f64,
) {
    for m in 0..b.n_modes {
        let (y, yd) = (
            rel.frames.last_z[b.first_mode + m],
            rel.frames.last_zd[b.first_mode + m],
        );
        for i in 0..3 {
            x[i] += rows(i, m) * y;
            xd[i] += rows(i, m) * yd;
        }
    }
}

/// 2D: angle of a marker's direction, θ = angle(A) + X^r_z y, and its rate.
pub(crate) fn angle_at(rel: &Relative, s: &Side) -> (f64, f64) {
    let Some(k) = s.body else { return (0.0, 0.0) };
    let b = &rel.bodies[k];
    let f = b.frame;
    let (mut th, mut thd) = (angle_of(&rel.frames.rotation[f]), rel.frames.velocity[f][5]);
    if let Some(node) = s.node {
        for m in 0..b.n_modes {
            th += b.node_rows.rotation_entry(node, 2, m) * rel.frames.last_z[b.first_mode + m];
            thd += b.node_rows.rotation_entry(node, 2, m) * rel.frames.last_zd[b.first_mode + m];
        }
    }
    (th, thd)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_of_recovers_the_angle_of_a_rotation_about_z() {
        for th in [0.0, 0.3, -1.2, 2.5, -3.0, std::f64::consts::FRAC_PI_2] {
            let a = *Rotation3::from_axis_angle(&Vector3::z_axis(), th).matrix();
            let got = angle_of(&a);
            assert!((got - th).abs() < 1e-15, "θ = {th}: angle_of gives {got}");
        }
    }

    #[test]
    fn angle_of_wraps_to_minus_pi_pi() {
        let a = *Rotation3::from_axis_angle(&Vector3::z_axis(), 4.0).matrix();
        let got = angle_of(&a);
        let expected = 4.0 - std::f64::consts::TAU;
        assert!(
            (got - expected).abs() < 1e-14,
            "angle_of(R_z(4)) = {got}, expected {expected}"
        );
    }
}
