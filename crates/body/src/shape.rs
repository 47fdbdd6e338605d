//! Route (b): inertia terms from the 13 shape integrals (methods.md §2.3, §2.4 steps 1–3).
//!
//! Body-frame origin form (step 1), with ω̄ = Aᵀω and `(ω̃ω̃)_ab = ω̄_a ω̄_b − |ω̄|² δ_ab`:
//!
//! ```text
//! M̄_body = [ m I    −m̄~    S   ]      Q̄_v,body = −{ ω̄~ω̄~ m̄ + 2 ω̄~ S ẏ
//!          [ m̄~     Ī_O    C   ]                   ω̄~ Ī_O ω̄ + 2 W ẏ
//!          [ Sᵀ     Cᵀ     M_yy]                   Σ_ab (ω̃ω̃)_ab (L_b)_aᵀ + 2 G(ω̄) ẏ }
//! ```
//!
//! Step 2 rotates to global components, step 3 shifts the reference point to s:
//! `M̄ = Dᵀ M̄_0 D`, `Q̄ = Dᵀ(Q̄_0 − M̄_0 {ω × ṙ0; 0; 0})`, `ṙ0 = ṡ − r̃0 ω`.
//! The shift term is applied in body components (`ā = ω̄ × v̄0`) before rotating.
//! The global blocks are formed directly: `M̄_sω = −(m r0 + A m̄)~`,
//! `M̄_ωω = J_O = tr(P_g) I − P_g` with `P_g = ∫ r rᵀ dm` about the global origin,
//! `M̄_ωy = r̃0 A S + A C`.

use crate::{BodyState, FlexibleBody, Workspace, dot, planar_rotation};
use nalgebra::{Dyn, Matrix, Matrix3, StorageMut, U1, Vector2, Vector3};

impl FlexibleBody {
    pub(crate) fn shape_3d<SM, SQ>(
        &self,
        st: &BodyState<'_>,
        ws: &mut Workspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let n = self.n;
        let (y, yd) = (st.y, st.y_dot);
        let a = &st.a;
        let r0 = st.r0;
        let wb = a.tr_mul(&st.omega);
        let v0b = a.tr_mul(&st.r0_dot());
        let ab = wb.cross(&v0b);

        // m̄(y), S ẏ.
        let mut mb = self.m_u;
        let mut s_yd = Vector3::zeros();
        for c in 0..3 {
            let sr = &self.s[c * n..(c + 1) * n];
            mb[c] += dot(sr, y);
            s_yd[c] = dot(sr, yd);
        }
        let mut p = self.p_u;
        let mut lam = Matrix3::zeros(); // lam[(b, c)] = (L_b)_c · ẏ
        let mut h_yd = 0.0;
        if n > 0 {
            // u^{ab} = S^{ab} y (9 n-vectors), G_c ẏ (3 n-vectors).
            for (row, u) in self.sab.chunks_exact(n).zip(ws.u.iter_mut()) {
                *u = dot(row, y);
            }
            for (row, g) in self.g.chunks_exact(n).zip(ws.gy.iter_mut()) {
                *g = dot(row, yd);
            }
            // (L_b)_a = S^b_a + u^{ab}, stored at (3b + a) n.
            for b in 0..3 {
                for c in 0..3 {
                    let dst = (3 * b + c) * n;
                    let src = (3 * c + b) * n;
                    let (l, sa, u) = (
                        &mut ws.l[dst..dst + n],
                        &self.sa[dst..dst + n],
                        &ws.u[src..src + n],
                    );
                    for j in 0..n {
                        l[j] = sa[j] + u[j];
                    }
                    lam[(b, c)] = dot(l, yd);
                }
            }
            // P_ab = P̄_ab + S^a_b · y + (L_b)_a · y.
            for c in 0..3 {
                for b in c..3 {
                    let v = self.p_u[(c, b)]
                        + dot(&self.sa[(3 * c + b) * n..(3 * c + b + 1) * n], y)
                        + dot(&ws.l[(3 * b + c) * n..(3 * b + c + 1) * n], y);
                    p[(c, b)] = v;
                    p[(b, c)] = v;
                }
            }
            h_yd = lam[(0, 0)] + lam[(1, 1)] + lam[(2, 2)];
        }
        let io = Matrix3::identity() * p.trace() - p;

        // Body-frame inertia forces including the D-shift term −M̄_body {ā; 0; 0}.
        let qt = -(wb.cross(&wb.cross(&mb)) + 2.0 * wb.cross(&s_yd)) - self.mass * ab;
        // W ẏ = ω̄ (h·ẏ) − Σ_b ω̄_b (L_b ẏ).
        let w_yd = wb * h_yd - lam.tr_mul(&wb);
        let qr = -(wb.cross(&(io * wb)) + 2.0 * w_yd) - mb.cross(&ab);

        // Global blocks.
        let am = a * mb;
        let lever = self.mass * r0 + am;
        let pg = a * p * a.transpose()
            + self.mass * r0 * r0.transpose()
            + r0 * am.transpose()
            + am * r0.transpose();
        let jo = Matrix3::identity() * pg.trace() - pg;
        let qtg = a * qt;
        let qrg = r0.cross(&qtg) + a * qr;

        // Fill M̄: rigid 6×6 part.
        for i in 0..3 {
            for j in 0..3 {
                m_out[(i, j)] = if i == j { self.mass } else { 0.0 };
                m_out[(i + 3, j + 3)] = jo[(i, j)];
            }
        }
        let lt = flexmbd_core::skew(&lever);
        for i in 0..3 {
            for j in 0..3 {
                m_out[(i, j + 3)] = -lt[(i, j)];
                m_out[(i + 3, j)] = lt[(i, j)];
            }
        }
        for i in 0..3 {
            q_out[i] = qtg[i];
            q_out[i + 3] = qrg[i];
        }
        if n == 0 {
            return;
        }

        // C rows: C_1 = (L_2)_3 − (L_3)_2, C_2 = (L_3)_1 − (L_1)_3, C_3 = (L_1)_2 − (L_2)_1;
        // h = Σ_a (L_a)_a; q_y.
        let l = &ws.l;
        let lrow = |b: usize, c: usize| &l[(3 * b + c) * n..(3 * b + c + 1) * n];
        let ww = wb.norm_squared();
        let om = wb * wb.transpose() - Matrix3::identity() * ww; // (ω̃ω̃)_ab
        let gsum = &mut ws.qy; // G(ω̄) ẏ, then q_y
        for j in 0..n {
            gsum[j] = wb.x * ws.gy[j] + wb.y * ws.gy[n + j] + wb.z * ws.gy[2 * n + j];
        }
        let cc = &mut ws.c;
        for j in 0..n {
            cc[j] = lrow(1, 2)[j] - lrow(2, 1)[j];
            cc[n + j] = lrow(2, 0)[j] - lrow(0, 2)[j];
            cc[2 * n + j] = lrow(0, 1)[j] - lrow(1, 0)[j];
        }
        for j in 0..n {
            // Σ_ab (ω̃ω̃)_ab (L_b)_a
            let mut t = 0.0;
            for c in 0..3 {
                for b in 0..3 {
                    t += om[(c, b)] * l[(3 * b + c) * n + j];
                }
            }
            let sta = self.s[j] * ab.x + self.s[n + j] * ab.y + self.s[2 * n + j] * ab.z;
            gsum[j] = -(t + 2.0 * gsum[j]) - sta;
        }
        // A S and A C columns; M̄_sy = A S, M̄_ωy = r0 × (A S) + A C.
        for j in 0..n {
            let sj = Vector3::new(self.s[j], self.s[n + j], self.s[2 * n + j]);
            let cj = Vector3::new(cc[j], cc[n + j], cc[2 * n + j]);
            let asj = a * sj;
            let wyj = r0.cross(&asj) + a * cj;
            for i in 0..3 {
                m_out[(i, 6 + j)] = asj[i];
                m_out[(6 + j, i)] = asj[i];
                m_out[(3 + i, 6 + j)] = wyj[i];
                m_out[(6 + j, 3 + i)] = wyj[i];
            }
            q_out[6 + j] = gsum[j];
        }
        for i in 0..n {
            for j in 0..n {
                m_out[(6 + i, 6 + j)] = self.m_yy[i * n + j];
            }
        }
    }

    pub(crate) fn shape_2d<SM, SQ>(
        &self,
        st: &BodyState<'_>,
        ws: &mut Workspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let n = self.n;
        let (y, yd) = (st.y, st.y_dot);
        let a = planar_rotation(&st.a);
        let w = st.omega.z;
        let r0 = st.r0.xy();
        let m = self.mass;
        // ṙ0 = ṡ + ω E r0 ; ā = ω E v̄0 (body components of ω × ṙ0).
        let r0_dot = st.s_dot.xy() + w * Vector2::new(-r0.y, r0.x);
        let v0b = a.tr_mul(&r0_dot);
        let ab = w * Vector2::new(-v0b.y, v0b.x);

        let mut mb = self.m_u.xy();
        let mut s_yd = Vector2::zeros();
        for c in 0..2 {
            let sr = &self.s[c * n..(c + 1) * n];
            mb[c] += dot(sr, y);
            s_yd[c] = dot(sr, yd);
        }
        // I_zz(y) = P̄11 + P̄22 + 2 (S¹_1 + S²_2)·y + y·M_yy y ; h = S¹_1 + S²_2 + M_yy y ;
        // C_3 = S¹_2 − S²_1 + G_3 y ; all in O(n²) with three mat-vecs.
        let mut izz = self.p_u[(0, 0)] + self.p_u[(1, 1)];
        let mut h_yd = 0.0;
        let g3 = &self.g[2 * n * n..3 * n * n];
        if n > 0 {
            let (t, rest) = ws.u.split_at_mut(n);
            let (g3y, rest) = rest.split_at_mut(n);
            let g3yd = &mut rest[..n];
            for i in 0..n {
                let mr = &self.m_yy[i * n..(i + 1) * n];
                let gr = &g3[i * n..(i + 1) * n];
                t[i] = dot(mr, y);
                g3y[i] = dot(gr, y);
                g3yd[i] = dot(gr, yd);
            }
            let s11 = &self.sa[0..n]; // S¹ row 1: (3·0 + 0) n
            let s22 = &self.sa[4 * n..5 * n]; // S² row 2: (3·1 + 1) n
            let s12 = &self.sa[n..2 * n]; // S¹ row 2
            let s21 = &self.sa[3 * n..4 * n]; // S² row 1
            let h = &mut ws.l[..n];
            let c3 = &mut ws.c[..n];
            for j in 0..n {
                h[j] = s11[j] + s22[j] + t[j];
                c3[j] = s12[j] - s21[j] + g3y[j];
            }
            izz += dot(s11, y) + dot(s22, y) + dot(h, y);
            h_yd = dot(h, yd);
        }

        let e = |v: Vector2<f64>| Vector2::new(-v.y, v.x);
        let qt = w * w * mb - 2.0 * w * e(s_yd) - m * ab;
        let qr = -2.0 * w * h_yd - (mb.x * ab.y - mb.y * ab.x);
        let am = a * mb;
        let lever = m * r0 + am;
        let jzz = izz + m * r0.norm_squared() + 2.0 * r0.dot(&am);
        let qtg = a * qt;
        let qrg = r0.x * qtg.y - r0.y * qtg.x + qr;

        m_out[(0, 0)] = m;
        m_out[(1, 1)] = m;
        m_out[(0, 1)] = 0.0;
        m_out[(1, 0)] = 0.0;
        m_out[(0, 2)] = -lever.y;
        m_out[(2, 0)] = -lever.y;
        m_out[(1, 2)] = lever.x;
        m_out[(2, 1)] = lever.x;
        m_out[(2, 2)] = jzz;
        q_out[0] = qtg.x;
        q_out[1] = qtg.y;
        q_out[2] = qrg;
        if n == 0 {
            return;
        }
        let h = &ws.l[..n];
        let c3 = &ws.c[..n];
        let g3yd = &ws.u[2 * n..3 * n];
        for j in 0..n {
            let asj = a * Vector2::new(self.s[j], self.s[n + j]);
            let wyj = r0.x * asj.y - r0.y * asj.x + c3[j];
            m_out[(0, 3 + j)] = asj.x;
            m_out[(3 + j, 0)] = asj.x;
            m_out[(1, 3 + j)] = asj.y;
            m_out[(3 + j, 1)] = asj.y;
            m_out[(2, 3 + j)] = wyj;
            m_out[(3 + j, 2)] = wyj;
            let sta = self.s[j] * ab.x + self.s[n + j] * ab.y;
            q_out[3 + j] = w * w * h[j] - 2.0 * w * g3yd[j] - sta;
        }
        for i in 0..n {
            for j in 0..n {
                m_out[(3 + i, 3 + j)] = self.m_yy[i * n + j];
            }
        }
    }
}
