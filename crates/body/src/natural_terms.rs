//! Inertia terms kept by their weight in natural coordinates (issue 31): the truncated kinetic
//! energy of `terms.rs` written in the coordinates {r0, u, v, w, y} of docs/methods.md §2.5,
//! docs/design.md "Inertia terms as a model choice".
//!
//! A point is at `r = r0 + A x̄`, `x̄ = r̄_u + X y`, `A = [e_1 e_2 e_3] = [u v w]`. On the
//! constraint manifold (A orthonormal) `v̄0 = Aᵀṙ0` and `ω̃ = AᵀȦ`, so the relative set's truncated
//! T is, term by term, `½ m v̄0² = ½ m ṙ0²`, `v̄0·(ω̄ × m̄) = ṙ0ᵀȦ m̄`, `½ ω̄ᵀĪω̄ = ½ tr(Ȧ P Ȧᵀ)`,
//! `v̄0·S ẏ = ṙ0ᵀA S ẏ` and `ω̄ᵀC ẏ = Σ_ab (ė_a·e_b) K_ab·ẏ` for any rows K_ab whose skew part
//! `K_ab − K_ba` is that of `(L_a)_b = ∫ x̄_a X_b dm` (there `ė_a·e_b` is skew). Constrained motion
//! depends on T on the manifold only, so this extension of T off it is a free choice; we take
//!
//! ```text
//! T = ½ m ṙ0² + ṙ0ᵀȦ m̄(y) + ½ Σ_ab P_ab(y) ė_a·ė_b + ½ ẏᵀM_yy ẏ
//!     + [c] (ṙ0ᵀA S ẏ + Σ_ab (ė_a·e_b) K_ab·ẏ),   K_ab = Sᵃ_b + [k≥1] ½ Σ_c ε_abc G_c y
//! ```
//!
//! with m̄, P truncated at order k as in `terms.rs`, the constant M_yy (the full kernel's
//! `Σ (e_a·e_b) Sᵃᵇ` equals it on the manifold but costs about 13 n² more in M and Q_v) and only the
//! skew half of L's linear part (`Sᵇᵃ − Sᵃᵇ = Σ_c ε_abc G_c`, 3 n² instead of Sᵃᵇ y's 9 n²; C(y)
//! is exact). At order 2 with couplings M differs from the full kernel's Gram matrix by that
//! symmetric half only, which acts on the stretch of A the orthonormality constraints hold.
//! The extension is free for the exact motion, not for the integrator's: with every term kept it
//! drifts 2 to 4 times the full kernel's energy on the free 2D spin-up beam at h = 1 to 0.25 ms
//! (the same order in h; `crates/validation/tests/inertia_terms.rs`).
//! Lagrange's equations of this T give M (its Hessian in q̇) and `Q_v = ∂T/∂q − Ṁ q̇`:
//!
//! ```text
//! M_r0r0 = m I, M_r0ea = m̄_a I, M_eaeb = P_ab I, M_yy,  [c]: M_r0y = A S, M_eay = Σ_b e_b K_abᵀ
//! Q_r0 = −([k≥1] + [c]) Ȧ σ                                     σ = S ẏ, γ_c = C_c·ẏ
//! Q_E  = ([c] − [k≥1]) ṙ0 σᵀ − Ȧ ([c] γ̃ + Ṗ)                   (columns Q_ea)
//! Q_y  = ([k≥1] − [c]) (Sᵀ Ȧᵀṙ0 + Σ_ab (ė_a·ė_b) Sᵃ_b) + [k≥2] Σ_ab (ė_a·ė_b) Sᵃᵇ y
//!        − [c][k≥1][velocity] Σ_c κ_c G_c ẏ,                      κ_c = Σ_ab ε_abc ė_a·e_b
//! ```
//!
//! The last term is the modal gyroscopic force (on the manifold κ = 2 ω̄, i.e. −2 G(ω̄) ẏ): its
//! matrix is skew, so it does no work anywhere and `velocity: false` drops it alone. The
//! planar set {r0, u, y} is the same T with `e_1 = u`, `e_2 = E u`: `I_zz = P_11 + P_22`,
//! `K_11 + K_22 = h₀ = S¹_1 + S²_2`, `K_12 − K_21 = C₃`, κ₃ = 2 u̇·E u, so
//!
//! ```text
//! Q_u = ([c] − [k≥1]) (σ_1 ṙ0 − σ_2 E ṙ0) − 2 [c] γ₃ E u̇ − İ_zz u̇,
//! Q_y = ([k≥1] − [c]) (Sᵀ Ȧᵀṙ0 + |u̇|² h₀) + [k≥2] |u̇|² M_yy y − 2 [c][k≥1][velocity] (u̇·E u) G₃ ẏ.
//! ```

use crate::natural::{NaturalState, e2, planar_frame};
use crate::natural::{write_natural_couplings_3d, write_natural_rigid_block_2d};
use crate::shape::{c_rows, rows_dot_3};
use crate::terms::rows_dot_9;
use crate::write_natural_rigid_block_3d;
use crate::{FlexibleBody, InertiaTerms, Workspace, dot, write_modal_rows};
use nalgebra::{Dyn, Matrix, Matrix3, StorageMut, U1, Vector2, Vector3};

/// `[cond]` as 0 or 1.
#[inline(always)]
fn ind(cond: bool) -> f64 {
    if cond { 1.0 } else { 0.0 }
}

impl FlexibleBody {
    /// Route (b) in spatial natural coordinates with the kinetic energy truncated by `terms`
    /// (module doc). Work skipped: Sᵃᵇ y (9 n²) below order 2, G y (3 n²) without couplings or
    /// at order 0, G ẏ (3 n²) without the velocity term; the modal mass is never re-formed.
    pub(crate) fn natural_shape_3d_terms<SM, SQ>(
        &self,
        st: &NaturalState<'_>,
        terms: InertiaTerms,
        ws: &mut Workspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let n = self.n;
        let (k, cpl) = (terms.order, terms.coupling);
        let (y, yd) = (st.y, st.y_dot);
        let (a, ad) = (&st.a, &st.a_dot);
        let (mb, p) = self.truncated_moments(y, k, ws);
        write_natural_rigid_block_3d(m_out, self.mass, &mb, &p);
        // Ṗ = Λ + Λᵀ with Λ_ab = (L_a)_b·ẏ (order 1: L at y = 0).
        let lam = match k {
            0 => Matrix3::zeros(),
            1 => rows_dot_9(&self.sa, n, yd),
            _ => rows_dot_9(&ws.l, n, yd),
        };
        let pdot = lam + lam.transpose();
        let sigma = self.first_moment_times(&self.s, yd);
        let s_live = self.live_first_moment(&self.s);
        // C = C(Sᵃ) = 0 at order 0 when the skew part of Sᵃ vanished (`vanished.rs`).
        let c_vanished = k == 0 && self.vanished.skew_first_moments;
        let linear = k >= 1 && n > 0;
        // C rows (3 × n) into ws.c, G_c y into ws.gy, K rows ((K_a)_b at (3a + b) n) into ws.l.
        let mut gamma = Vector3::zeros();
        if cpl && n > 0 {
            if !c_vanished {
                c_rows(n, &self.sa, &mut ws.c);
            }
            if linear {
                for (gy, row) in ws.gy.iter_mut().zip(self.g.chunks_exact(n)) {
                    *gy = dot(row, y);
                }
                for (cj, gy) in ws.c.iter_mut().zip(&ws.gy) {
                    *cj += gy;
                }
            } else {
                ws.gy.fill(0.0);
            }
            if !c_vanished {
                gamma = rows_dot_3(&ws.c, n, yd);
            }
            for aa in 0..3 {
                for b in 0..3 {
                    let dst = (3 * aa + b) * n;
                    // ½ Σ_c ε_abc G_c y: nonzero for a ≠ b, c the third axis.
                    let (c, sign) = match (aa, b) {
                        (0, 1) => (2, 0.5),
                        (1, 0) => (2, -0.5),
                        (1, 2) => (0, 0.5),
                        (2, 1) => (0, -0.5),
                        (2, 0) => (1, 0.5),
                        (0, 2) => (1, -0.5),
                        _ => (0, 0.0),
                    };
                    for j in 0..n {
                        ws.l[dst + j] = self.sa[dst + j] + sign * ws.gy[c * n + j];
                    }
                }
            }
            write_natural_couplings_3d(m_out, a, n, s_live, &ws.l);
        } else if n > 0 {
            ws.sy.fill(0.0);
            ws.l.fill(0.0);
            write_natural_couplings_3d(m_out, a, n, Some(&ws.sy), &ws.l);
        }
        let (ck, cc) = (ind(k >= 1), ind(cpl));
        let q0 = -(ck + cc) * (ad * sigma);
        let gt = Matrix3::new(
            0.0, -gamma.z, gamma.y, gamma.z, 0.0, -gamma.x, -gamma.y, gamma.x, 0.0,
        );
        let qe = (cc - ck) * (st.r0_dot * sigma.transpose()) - ad * (cc * gt + pdot);
        for i in 0..3 {
            q_out[i] = q0[i];
            for b in 0..3 {
                q_out[3 + 3 * b + i] = qe[(i, b)];
            }
        }
        if n == 0 {
            return;
        }
        let gdd = ad.tr_mul(ad); // ė_a·ė_b
        let adr = ad.tr_mul(&st.r0_dot); // ė_a·ṙ0
        let cdot = ad.tr_mul(a); // ė_a·e_b
        let kappa = Vector3::new(
            cdot[(1, 2)] - cdot[(2, 1)],
            cdot[(2, 0)] - cdot[(0, 2)],
            cdot[(0, 1)] - cdot[(1, 0)],
        );
        let gyro = cpl && linear && terms.velocity;
        if gyro {
            for (g, row) in ws.ax.iter_mut().zip(self.g.chunks_exact(n)) {
                *g = dot(row, yd);
            }
        }
        let d = ck - cc;
        let mut qy = std::mem::take(&mut ws.qy);
        for (j, q) in qy.iter_mut().enumerate() {
            let mut v = 0.0;
            if d != 0.0 {
                let mut t = 0.0;
                for aa in 0..3 {
                    if let Some(s) = s_live {
                        t += s[aa * n + j] * adr[aa];
                    }
                    for b in 0..3 {
                        t += gdd[(aa, b)] * self.sa[(3 * aa + b) * n + j];
                    }
                }
                v += d * t;
            }
            if k >= 2 {
                for aa in 0..3 {
                    for b in 0..3 {
                        v += gdd[(aa, b)] * ws.u[(3 * aa + b) * n + j];
                    }
                }
            }
            if gyro {
                v -= kappa.x * ws.ax[j] + kappa.y * ws.ax[n + j] + kappa.z * ws.ax[2 * n + j];
            }
            *q = v;
        }
        write_modal_rows(m_out, q_out, 12, &self.m_yy, &qy);
        ws.qy = qy;
    }

    /// Route (b) in planar natural coordinates {r0, u, y} with the kinetic energy truncated by
    /// `terms` (module doc): M_yy y (n²) only at order 2, G₃ y (n²) only with couplings at
    /// order ≥ 1, G₃ ẏ (n²) only with the velocity term.
    pub(crate) fn natural_shape_2d_terms<SM, SQ>(
        &self,
        st: &NaturalState<'_>,
        terms: InertiaTerms,
        ws: &mut Workspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let n = self.n;
        let (k, cpl) = (terms.order, terms.coupling);
        let (y, yd) = (st.y, st.y_dot);
        let (u, ud, a, ad) = planar_frame(st);
        let r0d = st.r0_dot.xy();
        let (full_mb, sigma) = self.planar_first_moment(y, yd);
        let mb = if k >= 1 { full_mb } else { self.m_u.xy() };
        let g3 = &self.g[2 * n * n..3 * n * n];
        let (s11, s22) = (&self.sa[..n], &self.sa[4 * n..5 * n]);
        let mut izz = self.p_u[(0, 0)] + self.p_u[(1, 1)];
        let mut izz_dot = 0.0;
        // ws.u: [M_yy y; h₀; G₃ ẏ], ws.c: C₃.
        let (t, rest) = ws.u.split_at_mut(n);
        let (h, g3yd) = rest.split_at_mut(n);
        for j in 0..n {
            h[j] = s11[j] + s22[j];
        }
        if k >= 1 && n > 0 {
            izz += 2.0 * dot(h, y);
            izz_dot += 2.0 * dot(h, yd);
        }
        if k >= 2 && n > 0 {
            for (i, ti) in t.iter_mut().enumerate() {
                *ti = dot(&self.m_yy[i * n..(i + 1) * n], y);
            }
            izz += dot(t, y);
            izz_dot += 2.0 * dot(t, yd);
        }
        write_natural_rigid_block_2d(m_out, self.mass, &mb, izz);
        let gyro = cpl && k >= 1 && terms.velocity;
        let mut gamma = 0.0;
        if cpl && n > 0 {
            let (s12, s21) = (&self.sa[n..2 * n], &self.sa[3 * n..4 * n]);
            for j in 0..n {
                let gr = &g3[j * n..(j + 1) * n];
                ws.c[j] = s12[j] - s21[j] + if k >= 1 { dot(gr, y) } else { 0.0 };
                g3yd[j] = if gyro { dot(gr, yd) } else { 0.0 };
            }
            gamma = dot(&ws.c[..n], yd);
        }
        let (ck, cc) = (ind(k >= 1), ind(cpl));
        let q0 = -(ck + cc) * (ad * sigma);
        let qu = (cc - ck) * (sigma.x * r0d - sigma.y * e2(r0d))
            - 2.0 * cc * gamma * e2(ud)
            - izz_dot * ud;
        q_out[0] = q0.x;
        q_out[1] = q0.y;
        q_out[2] = qu.x;
        q_out[3] = qu.y;
        if n == 0 {
            return;
        }
        let o = 4;
        let (eu, uu) = (e2(u), ud.norm_squared());
        let adr = ad.tr_mul(&r0d); // (u̇·ṙ0, E u̇·ṙ0)
        let d = ck - cc;
        let u_eu = 2.0 * ud.dot(&eu);
        let s_live = self.live_first_moment(&self.s);
        for j in 0..n {
            let (asj, uyj) = if cpl {
                let asj = match s_live {
                    Some(s) => a * Vector2::new(s[j], s[n + j]),
                    None => Vector2::zeros(),
                };
                (asj, u * h[j] + eu * ws.c[j])
            } else {
                (Vector2::zeros(), Vector2::zeros())
            };
            for i in 0..2 {
                m_out[(i, o + j)] = asj[i];
                m_out[(o + j, i)] = asj[i];
                m_out[(2 + i, o + j)] = uyj[i];
                m_out[(o + j, 2 + i)] = uyj[i];
            }
            let mut v = match s_live {
                Some(s) => d * (s[j] * adr.x + s[n + j] * adr.y + uu * h[j]),
                None => d * (uu * h[j]),
            };
            if k >= 2 {
                v += uu * t[j];
            }
            if gyro {
                v -= u_eu * g3yd[j];
            }
            q_out[o + j] = v;
            for i in 0..n {
                m_out[(o + j, o + i)] = self.m_yy[j * n + i];
            }
        }
    }
}
