//! The dynamic terms M and Q (docs/methods.md §4.5 steps 4–7, §4.6 tangents).

use flexmbd_core::SystemTerms;
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

use crate::system::Relative;

impl Relative {
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
    pub(crate) fn dynamics(
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
}
