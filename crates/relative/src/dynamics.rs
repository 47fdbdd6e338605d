//! The dynamic terms M and Q (docs/methods.md §4.5 steps 4–7; the tangents of §4.6).
//!
//! Step 4: the body terms M̄_k, Q̄_k in the s form by each body's kernel (`body_kernels.rs`:
//! a rigid body's in closed form on fixed-size blocks, a flexible body's from `flexmbd-body`,
//! inertia by either [`flexmbd_body::InertiaMethod`], gravity, elastic forces) and
//! P_k = Q̄_k − M̄_k {D_k; 0}.
//! Step 5: 𝕄_F, ℙ_F accumulated leaves → root over the tree of elementary joints. Steps 6–7:
//!
//! ```text
//! M_w[a, e] = v_aᵀ 𝕄_{F(e)} v_e        (a on the path of e)
//! M_w[a, m] = v_aᵀ (M̄^ry_k)_{:,m}       (a moves body k, m a mode of k)
//! M_w[m, m'] = (M̄^yy_k)_{mm'},  Q_w[e] = v_eᵀ ℙ_{F(e)},  Q_w[m] = (P^y_k)_m
//! M = Lᵀ M_w L,  Q = Lᵀ Q_w
//! ```
//!
//! so M = Rᵀ M̄ R and Q = Rᵀ (Q̄ − M̄ Ṙ ż). Tangents (§4.6): K ≈ blockdiag K_ff,
//! C ≈ blockdiag C_ff on the modal coordinates. The spring–dampers add their forces and
//! tangents last (`flexmbd_model::force_elements`).
//!
//! M_w and Q_w need no clearing: every pass writes the same set of their entries (the others
//! stay at their compile-time zeros). M_w[i, j] goes straight into M when both are z indices
//! (L = [I; L_node]), into M_w otherwise, whose structural non-zeros are then added to M
//! through the compile-time mass map. A planar scene only has the x, y, θz entries of twists,
//! 𝕄 and ℙ (the others are exact zeros), so the products run on those three: the pass is
//! generic over the [`Layout`] of its dimension.

use flexmbd_core::{Dim, State, SystemTerms};
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

use crate::body_kernels::{BodyKernel, FrameMotion};
use crate::layout::{Layout, Planar, Spatial};
use crate::system::Relative;

/// Writes M_w[i, j] = v into M (column-major, n_z × n_z) when i and j are z indices, into
/// `m_w` otherwise.
fn put(mass: &mut [f64], m_w: &mut DMatrix<f64>, n_z: usize, i: usize, j: usize, v: f64) {
    if i < n_z && j < n_z {
        mass[i + j * n_z] = v;
    } else {
        m_w[(i, j)] = v;
    }
}

/// out += Lᵀ v for a w-vector v, L given by its rows (z index, coefficient).
pub(crate) fn fold_w_to_z(l_rows: &[Vec<(usize, f64)>], v: &[f64], out: &mut [f64]) {
    for (w, lw) in l_rows.iter().enumerate() {
        let qv = v[w];
        for &(c, a) in lw {
            out[c] += a * qv;
        }
    }
}

impl Relative {
    /// §4.5 step 4 for the flexible bodies: M̄_k and Q̄_k (inertia, gravity, elastic) at the
    /// state of the last kinematics pass (the rigid bodies' terms are formed in
    /// [`body_rows`](Self::body_rows), in closed form).
    pub(crate) fn evaluate_bodies(&mut self, z: &DVector<f64>, zd: &DVector<f64>) {
        if self.tree.dim == Dim::Planar {
            self.evaluate_bodies_in::<Planar>(z, zd);
        } else {
            self.evaluate_bodies_in::<Spatial>(z, zd);
        }
    }

    fn evaluate_bodies_in<D: Layout>(&mut self, z: &DVector<f64>, zd: &DVector<f64>) {
        for k in 0..self.bodies.len() {
            if self.bodies[k].n_modes == 0 {
                continue;
            }
            let state = self.body_state(k, z, zd);
            let (g, method) = (self.assembly.gravity, self.assembly.inertia_method);
            if let BodyKernel::Flexible(f) = &mut self.bodies[k].kernel {
                f.evaluate(&state, method, &g, D::ENTRIES);
            }
        }
    }

    /// The motion of body k's frame from the last kinematics pass.
    #[inline(always)]
    pub(crate) fn frame_motion(&self, k: usize) -> FrameMotion {
        let f = self.bodies[k].frame;
        FrameMotion {
            r0: self.frames.position[f],
            a: self.frames.rotation[f],
            velocity: self.frames.velocity[f],
            bias: self.frames.bias[f],
        }
    }

    /// §4.5 steps 4–7: M and Q into `out` (which comes cleared), with the modal tangents
    /// when asked.
    #[inline(never)]
    pub(crate) fn dynamics(&mut self, state: State<'_>, tangents: bool, out: &mut SystemTerms) {
        if self.tree.dim == Dim::Planar {
            self.dynamics_in::<Planar>(state, tangents, out);
        } else {
            self.dynamics_in::<Spatial>(state, tangents, out);
        }
    }

    #[inline(always)]
    fn dynamics_in<D: Layout>(&mut self, state: State<'_>, tangents: bool, out: &mut SystemTerms) {
        let (z, zd) = (state.q, state.qd);
        self.evaluate_bodies_in::<D>(z, zd);
        let mass = out.mass.as_mut_slice();
        self.body_rows::<D>(mass);
        self.accumulate_subtrees::<D>();
        self.elem_rows::<D>(mass);
        // M = Lᵀ M_w L, Q = Lᵀ Q_w. The z × z block was written into `out` directly; the
        // node-joint rows and columns of M_w (only its structural non-zeros) are added
        // through L.
        let mw = self.assembly.m_w.as_slice();
        for &(d, src, k) in &self.tree.mass_map {
            mass[d] += k * mw[src];
        }
        fold_w_to_z(
            &self.tree.l_rows,
            self.assembly.q_w.as_slice(),
            out.forces.as_mut_slice(),
        );
        if tangents {
            self.add_modal_tangents(z, zd, out);
        }
        if !self.forces.elements.is_empty() {
            self.fill_marker_table();
            let mut force_elements = std::mem::take(&mut self.forces.elements);
            force_elements.add_forces(self, z, zd, tangents, out);
            self.forces.elements = force_elements;
        }
    }

    /// Step 4: P_k = Q̄_k − M̄_k {D_k; 0} and the bodies' rigid blocks in the 6-layout, by the
    /// rigid kernels in closed form or from a flexible body's dense terms, with its modal rows
    /// of M_w and Q_w.
    fn body_rows<D: Layout>(&mut self, mass: &mut [f64]) {
        for k in 0..self.bodies.len() {
            // The frame's motion by reference: a planar body reads its entries in place
            // (copying the motion whole would read the kinematic pass's fresh stores back
            // with wider loads, a stall).
            let f = self.bodies[k].frame;
            let motion = (
                &self.frames.position[f],
                &self.frames.rotation[f],
                &self.frames.velocity[f],
                &self.frames.bias[f],
            );
            let (mm, pp) = (
                &mut self.assembly.body_mass[k],
                &mut self.assembly.body_p[k],
            );
            match &self.bodies[k].kernel {
                BodyKernel::RigidSpatial(r) => {
                    let frame = FrameMotion {
                        r0: *motion.0,
                        a: *motion.1,
                        velocity: *motion.2,
                        bias: *motion.3,
                    };
                    r.terms(&frame, &self.assembly.gravity, mm, pp)
                }
                BodyKernel::RigidPlanar(r) => r.terms_at(motion, &self.assembly.gravity, mm, pp),
                BodyKernel::Flexible(_) => {
                    let d = *motion.3;
                    self.flexible_body_rows::<D>(k, &d, mass)
                }
            }
        }
    }

    /// [`body_rows`](Self::body_rows) of flexible body k, whose blocks
    /// [`evaluate_bodies`](Self::evaluate_bodies) formed, with its frame's D: the rigid block
    /// into 𝕄's part M̄_k, P_k = Q̄_k − M̄_k[:, rigid] D (per row in the order of the rigid
    /// entries), the coupling columns into M_w's rows of the joints that move body k and
    /// M̄_yy into M.
    fn flexible_body_rows<D: Layout>(&mut self, k: usize, d: &Vector6<f64>, mass: &mut [f64]) {
        let entries = D::ENTRIES;
        let nz = self.tree.n_z;
        let b = &self.bodies[k];
        let BodyKernel::Flexible(flexible) = &b.kernel else {
            return;
        };
        let blocks = &flexible.blocks;
        let (f, n) = (b.frame, b.n_modes);
        let (mm, pp) = (
            &mut self.assembly.body_mass[k],
            &mut self.assembly.body_p[k],
        );
        *mm = blocks.rigid;
        for &r in entries {
            let mut p = blocks.rigid_force[r];
            for &c in entries {
                p -= blocks.rigid[(r, c)] * d[c];
            }
            pp[r] = p;
        }
        let q_w = &mut self.assembly.q_w.as_mut_slice()[b.first_mode..b.first_mode + n];
        for ((q, &force), u) in q_w
            .iter_mut()
            .zip(&blocks.modal_force)
            .zip(&blocks.coupling)
        {
            let mut p = force;
            for &c in entries {
                p -= u[c] * d[c];
            }
            *q = p;
        }
        for (m, u) in blocks.coupling.iter().enumerate() {
            let wm = b.first_mode + m;
            for &a in &self.tree.paths[f] {
                let val = D::dot(&self.frames.elem_twist[a], u);
                let wa = self.tree.elem_w[a];
                put(mass, &mut self.assembly.m_w, nz, wa, wm, val);
                put(mass, &mut self.assembly.m_w, nz, wm, wa, val);
            }
            // M̄_yy (modes are z coordinates): column m of the block, row m2.
            for m2 in 0..n {
                mass[b.first_mode + m2 + wm * nz] = blocks.modal_mass[m2 * n + m];
            }
        }
    }

    /// Step 5: 𝕄 and ℙ of every elementary joint's subtree, leaves → root over the tree of
    /// elementary joints (a child's index is larger than its parent's).
    fn accumulate_subtrees<D: Layout>(&mut self) {
        if D::ENTRIES == Planar::ENTRIES {
            self.accumulate_planar_subtrees();
            return;
        }
        for e in (0..self.tree.topology.elems.len()).rev() {
            let (mut m, mut pv) = (Matrix6::zeros(), Vector6::zeros());
            let parts = self.tree.elem_bodies[e]
                .iter()
                .map(|&k| (&self.assembly.body_mass[k], &self.assembly.body_p[k]))
                .chain(
                    self.tree.elem_children[e]
                        .iter()
                        .map(|&c| (&self.assembly.subtree_mass[c], &self.assembly.subtree_p[c])),
                );
            for (bm, bp) in parts {
                m += bm;
                pv += bp;
            }
            self.assembly.subtree_mass[e] = m;
            self.assembly.subtree_p[e] = pv;
        }
    }

    /// [`accumulate_subtrees`](Self::accumulate_subtrees) of a planar scene: the sums on the
    /// x, y, θz entries, entry by entry, stored as scalars (the other entries of 𝕄 and ℙ
    /// stay at their zeros). Accumulating into a whole zeroed 6 × 6 and storing it would
    /// read narrow stores back with wide loads (a stall per joint).
    fn accumulate_planar_subtrees(&mut self) {
        let entries = Planar::ENTRIES;
        for e in (0..self.tree.topology.elems.len()).rev() {
            let (mut m, mut pv) = ([[0.0; 3]; 3], [0.0; 3]);
            let parts = self.tree.elem_bodies[e]
                .iter()
                .map(|&k| (&self.assembly.body_mass[k], &self.assembly.body_p[k]))
                .chain(
                    self.tree.elem_children[e]
                        .iter()
                        .map(|&c| (&self.assembly.subtree_mass[c], &self.assembly.subtree_p[c])),
                );
            for (bm, bp) in parts {
                for (j, &c) in entries.iter().enumerate() {
                    pv[j] += bp[c];
                    for (i, &r) in entries.iter().enumerate() {
                        m[j][i] += bm[(r, c)];
                    }
                }
            }
            let (sm, sp) = (
                &mut self.assembly.subtree_mass[e],
                &mut self.assembly.subtree_p[e],
            );
            for (j, &c) in entries.iter().enumerate() {
                sp[c] = pv[j];
                for (i, &r) in entries.iter().enumerate() {
                    sm[(r, c)] = m[j][i];
                }
            }
        }
    }

    /// Steps 6–7 for the elementary joints: `M_w[a, e] = v_aᵀ 𝕄_{F(e)} v_e` for a on the path
    /// of e, and `Q_w[e] = v_eᵀ ℙ_{F(e)}`.
    fn elem_rows<D: Layout>(&mut self, mass: &mut [f64]) {
        let nz = self.tree.n_z;
        for e in 0..self.tree.topology.elems.len() {
            let f = self.tree.topology.elems[e].frame;
            let (me, ve) = (&self.assembly.subtree_mass[e], &self.frames.elem_twist[e]);
            let ke = D::inertia_times(me, ve);
            let we = self.tree.elem_w[e];
            for &a in &self.tree.paths[f] {
                let val = D::dot(&self.frames.elem_twist[a], &ke);
                let wa = self.tree.elem_w[a];
                put(mass, &mut self.assembly.m_w, nz, wa, we, val);
                put(mass, &mut self.assembly.m_w, nz, we, wa, val);
            }
            self.assembly.q_w[we] = D::dot(&self.frames.elem_twist[e], &self.assembly.subtree_p[e]);
        }
    }

    /// §4.6: K ≈ blockdiag K_ff, C ≈ blockdiag C_ff on the modal coordinates.
    fn add_modal_tangents(&self, z: &DVector<f64>, zd: &DVector<f64>, out: &mut SystemTerms) {
        for b in &self.bodies {
            if b.n_modes == 0 {
                continue;
            }
            let (o, n) = (b.first_mode, b.n_modes);
            let (y, yd) = (&z.as_slice()[o..o + n], &zd.as_slice()[o..o + n]);
            let Some(flexible) = b.kernel.flexible() else {
                continue;
            };
            let body = &flexible.body;
            body.add_elastic_tangents(y, yd, 1.0, 0.0, out.stiffness.view_mut((o, o), (n, n)));
            body.add_elastic_tangents(y, yd, 0.0, 1.0, out.damping.view_mut((o, o), (n, n)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fold_w_to_z_adds_l_transpose_times_v() {
        // z = (z0, z1); w = (z0, z1, node joint e = 2 z0 − 0.5 z1).
        let l_rows = vec![vec![(0, 1.0)], vec![(1, 1.0)], vec![(0, 2.0), (1, -0.5)]];
        let v = [1.0, 10.0, 100.0];
        let mut out = [0.25, -0.25];
        fold_w_to_z(&l_rows, &v, &mut out);
        assert_eq!(out, [0.25 + 1.0 + 200.0, -0.25 + 10.0 - 50.0]);
    }

    #[test]
    fn put_writes_the_z_block_into_m_and_the_rest_into_m_w() {
        let mut mass = vec![0.0; 4];
        let mut m_w = DMatrix::zeros(3, 3);
        put(&mut mass, &mut m_w, 2, 1, 0, 5.0);
        put(&mut mass, &mut m_w, 2, 2, 1, 7.0);
        assert_eq!(mass, [0.0, 5.0, 0.0, 0.0]);
        assert_eq!(m_w[(2, 1)], 7.0);
        assert_eq!(m_w[(1, 0)], 0.0);
    }
}
