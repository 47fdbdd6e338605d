//! Route (b): inertia terms from the 13 shape integrals (docs/methods.md §2.3, §2.4 steps 1–3).
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

use crate::blocks::RelativeSink;
use crate::{
    BodyState, FlexibleBody, Workspace, dot, planar_rotation, write_planar_coupling,
    write_planar_rigid,
};
use nalgebra::{Dyn, Matrix, Matrix2, Matrix3, StorageMut, U1, Vector2, Vector3};

/// `(R_c · ẏ)_c` for the three rows R_c of length n at c n in `rows` (S ẏ, or L_b ẏ from the
/// rows of L_b).
#[inline(always)]
pub(crate) fn rows_dot_3(rows: &[f64], n: usize, yd: &[f64]) -> Vector3<f64> {
    let mut v = Vector3::zeros();
    for c in 0..3 {
        v[c] = dot(&rows[c * n..(c + 1) * n], yd);
    }
    v
}

/// The rigid blocks of the s form in global components (§2.4 steps 2–3), from the body-frame
/// moments and forces: `M̄_sω = −g̃` with the first moment `g = m r0 + A m̄` about the global
/// origin, `M̄_ωω = J_O = tr(P_g) I − P_g`, and `Q̄ = {A q_t; r0 × A q_t + A q_r}`.
pub(crate) struct GlobalRigid {
    pub(crate) moment: Vector3<f64>,
    pub(crate) inertia: Matrix3<f64>,
    pub(crate) force: [f64; 6],
}

/// The configuration-dependent moments of a body at (y, ẏ) in body components (§2.3; FS0:
/// the hatted moments of §6.3), beside the S and L rows the kernels read from the workspace.
pub(crate) struct ShapeMoments {
    /// m̄(y).
    pub(crate) mb: Vector3<f64>,
    /// P(y) = Σ w r̄ r̄ᵀ.
    pub(crate) p: Matrix3<f64>,
    /// The velocity-product moments of a foreshortened body, `None` for a linear one.
    pub(crate) axial: Option<AxialMoments>,
}

/// The velocity-product moments of FS0 (§6.3): `c₀ = Σ w c_k`, `c₁ = Σ w c_k r̄_k` with
/// `c_k = ẏᵀF_k ẏ`, along the beam axis ē₁.
pub(crate) struct AxialMoments {
    pub(crate) axis: Vector3<f64>,
    pub(crate) c0: f64,
    pub(crate) c1: Vector3<f64>,
}

/// The motion of the body frame in body components: ω̄ = Aᵀω and the shift term
/// `ā = ω̄ × v̄0` (`v̄0 = Aᵀṙ0`) of step 3.
#[inline(always)]
pub(crate) fn body_frame_motion(st: &BodyState<'_>) -> (Vector3<f64>, Vector3<f64>) {
    let wb = st.a.tr_mul(&st.omega);
    let v0b = st.a.tr_mul(&st.r0_dot());
    (wb, wb.cross(&v0b))
}

/// The planar body frame's motion (§2.4 step 3 in the x, y, θz rows): the rotation a,
/// ω, r0, v̄0 = aᵀṙ0 with ṙ0 = ṡ + ω E r0, and the shift term ā = ω E v̄0 (body components
/// of ω × ṙ0), E the rotation by +90°.
#[inline(always)]
pub(crate) fn planar_frame_motion(
    st: &BodyState<'_>,
) -> (Matrix2<f64>, f64, Vector2<f64>, Vector2<f64>, Vector2<f64>) {
    let a = planar_rotation(&st.a);
    let w = st.omega.z;
    let r0 = st.r0.xy();
    let r0_dot = st.s_dot.xy() + w * Vector2::new(-r0.y, r0.x);
    let v0b = a.tr_mul(&r0_dot);
    let ab = w * Vector2::new(-v0b.y, v0b.x);
    (a, w, r0, v0b, ab)
}

/// The rows of `C_a = Σ_bc ε_abc (L_b)_c` (3 × n into `c`) from L ((L_b)_a at (3b + a) n):
/// `C_1 = (L_2)_3 − (L_3)_2`, `C_2 = (L_3)_1 − (L_1)_3`, `C_3 = (L_1)_2 − (L_2)_1`.
#[inline(always)]
pub(crate) fn c_rows(n: usize, l: &[f64], c: &mut [f64]) {
    let lrow = |b: usize, a: usize| &l[(3 * b + a) * n..(3 * b + a + 1) * n];
    for j in 0..n {
        c[j] = lrow(1, 2)[j] - lrow(2, 1)[j];
        c[n + j] = lrow(2, 0)[j] - lrow(0, 2)[j];
        c[2 * n + j] = lrow(0, 1)[j] - lrow(1, 0)[j];
    }
}

/// The modal inertia force of the body-frame origin form with the shift term,
/// `q_y = −(Σ_ab (ω̃ω̃)_ab (L_b)_aᵀ + 2 G ẏ) − Sᵀ ā`, over `q` (n) which holds `G ẏ` on entry;
/// `s` and `l` are the rows of S and L (3n, 9n); `s` is `None` when S vanished (`vanished.rs`).
#[inline(always)]
pub(crate) fn modal_inertia_forces(
    wb: &Vector3<f64>,
    ab: &Vector3<f64>,
    s: Option<&[f64]>,
    l: &[f64],
    q: &mut [f64],
) {
    let n = q.len();
    let ww = wb.norm_squared();
    let om = wb * wb.transpose() - Matrix3::identity() * ww; // (ω̃ω̃)_ab
    let centrifugal = |j: usize| {
        let mut t = 0.0;
        for c in 0..3 {
            for b in 0..3 {
                t += om[(c, b)] * l[(3 * b + c) * n + j];
            }
        }
        t
    };
    match s {
        Some(s) => {
            for j in 0..n {
                let t = centrifugal(j);
                let sta = s[j] * ab.x + s[n + j] * ab.y + s[2 * n + j] * ab.z;
                q[j] = -(t + 2.0 * q[j]) - sta;
            }
        }
        None => {
            for j in 0..n {
                q[j] = -(centrifugal(j) + 2.0 * q[j]);
            }
        }
    }
}

impl FlexibleBody {
    /// The linear configuration-dependent moments of §2.3 over the first `axes` body axes
    /// (3, or 2 for the planar rows): `u^{ab} = Sᵃᵇ y` into `u` and `(L_b)_a = Sᵇ_a + u^{ab}`
    /// into `l` (at (3b + a) n; the z entries zero when `axes` = 2); returns `m̄(y) = m̄_u + S y`
    /// and `P_ab = P̄_ab + Sᵃ_b·y + (L_b)_a·y`. `N` = n as a compile-time constant, or 0.
    #[inline(always)]
    pub(crate) fn linear_moments<const N: usize>(
        &self,
        y: &[f64],
        axes: usize,
        u: &mut [f64],
        l: &mut [f64],
    ) -> (Vector3<f64>, Matrix3<f64>) {
        let n = if N == 0 { self.n } else { N };
        let n2 = n * n;
        let mut mb = self.m_u;
        if !self.first_moment_vanished() {
            for c in 0..axes {
                mb[c] += dot(&self.s[c * n..(c + 1) * n], y);
            }
        }
        let mut p = self.p_u;
        if n == 0 {
            return (mb, p);
        }
        for c in 0..axes {
            for b in 0..axes {
                let block = &self.sab[(3 * c + b) * n2..(3 * c + b + 1) * n2];
                let dst = &mut u[(3 * c + b) * n..(3 * c + b + 1) * n];
                for (uu, row) in dst.iter_mut().zip(block.chunks_exact(n)) {
                    *uu = dot(row, y);
                }
            }
        }
        if axes == 2 {
            l[2 * n..3 * n].fill(0.0);
            l[5 * n..9 * n].fill(0.0);
        }
        for b in 0..axes {
            for c in 0..axes {
                let dst = (3 * b + c) * n;
                let src = (3 * c + b) * n;
                for j in 0..n {
                    l[dst + j] = self.sa[dst + j] + u[src + j];
                }
            }
        }
        for c in 0..axes {
            for b in c..axes {
                let v = self.p_u[(c, b)]
                    + dot(&self.sa[(3 * c + b) * n..(3 * c + b + 1) * n], y)
                    + dot(&l[(3 * b + c) * n..(3 * b + c + 1) * n], y);
                p[(c, b)] = v;
                p[(b, c)] = v;
            }
        }
        (mb, p)
    }

    /// [`GlobalRigid`] from m̄, P and the body-frame forces q_t, q_r at orientation `a` and
    /// origin `r0`.
    #[inline(always)]
    pub(crate) fn global_rigid(
        &self,
        a: &Matrix3<f64>,
        r0: &Vector3<f64>,
        mb: &Vector3<f64>,
        p: &Matrix3<f64>,
        qt: &Vector3<f64>,
        qr: &Vector3<f64>,
    ) -> GlobalRigid {
        let am = a * mb;
        let lever = self.mass * r0 + am;
        let pg = a * p * a.transpose()
            + self.mass * r0 * r0.transpose()
            + r0 * am.transpose()
            + am * r0.transpose();
        let jo = Matrix3::identity() * pg.trace() - pg;
        let qtg = a * qt;
        let qrg = r0.cross(&qtg) + a * qr;
        GlobalRigid {
            moment: lever,
            inertia: jo,
            force: [qtg.x, qtg.y, qtg.z, qrg.x, qrg.y, qrg.z],
        }
    }

    /// The rigid–modal couplings `M̄_sy = A S`, `M̄_ωy = r0 × (A S) + A C` from the body-frame
    /// rows of S and C (3 × n each), written in the layout of the body's dimension through the
    /// global rows `translation` and `rotation` (3n each). `None` for S (vanished,
    /// `vanished.rs`) or C (vanished at order 0) skips its products: its rows are zero.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn write_shape_couplings<O: RelativeSink>(
        &self,
        a: &Matrix3<f64>,
        r0: &Vector3<f64>,
        s: Option<&[f64]>,
        c: Option<&[f64]>,
        translation: &mut [f64],
        rotation: &mut [f64],
        out: &mut O,
    ) {
        let n = self.n;
        let row = |v: &[f64], j: usize| Vector3::new(v[j], v[n + j], v[2 * n + j]);
        match (s, c) {
            (Some(s), Some(c)) => {
                for j in 0..n {
                    let asj = a * row(s, j);
                    let wyj = r0.cross(&asj) + a * row(c, j);
                    for i in 0..3 {
                        translation[i * n + j] = asj[i];
                        rotation[i * n + j] = wyj[i];
                    }
                }
            }
            (None, Some(c)) => {
                translation.fill(0.0);
                for j in 0..n {
                    let wyj = a * row(c, j);
                    for i in 0..3 {
                        rotation[i * n + j] = wyj[i];
                    }
                }
            }
            (Some(s), None) => {
                for j in 0..n {
                    let asj = a * row(s, j);
                    let wyj = r0.cross(&asj);
                    for i in 0..3 {
                        translation[i * n + j] = asj[i];
                        rotation[i * n + j] = wyj[i];
                    }
                }
            }
            (None, None) => {
                translation.fill(0.0);
                rotation.fill(0.0);
            }
        }
        out.couplings(self.dim, n, translation, rotation);
    }

    /// The rows of S for a kernel to multiply, `None` when S vanished (`vanished.rs`).
    #[inline(always)]
    pub(crate) fn live_first_moment<'a>(&self, rows: &'a [f64]) -> Option<&'a [f64]> {
        (!self.first_moment_vanished()).then_some(rows)
    }

    /// `S ẏ` from the rows of S (3n), zero without the products when S vanished.
    #[inline(always)]
    pub(crate) fn first_moment_times(&self, rows: &[f64], v: &[f64]) -> Vector3<f64> {
        match self.live_first_moment(rows) {
            Some(rows) => rows_dot_3(rows, self.n, v),
            None => Vector3::zeros(),
        }
    }

    /// The S rows (3 × n) of the moments just formed: the body's own for a linear body, FS0's
    /// hatted Ŝ (written into `sy` by [`fs_moments`](Self::fs_moments)) for a foreshortened one.
    #[inline(always)]
    pub(crate) fn first_moment_rows<'a>(&'a self, foreshortened: bool, sy: &'a [f64]) -> &'a [f64] {
        if foreshortened { sy } else { &self.s }
    }

    /// The in-plane first moment `m̄(y)` and `S ẏ` of a linear body (x, y rows of S).
    #[inline(always)]
    pub(crate) fn planar_first_moment(
        &self,
        y: &[f64],
        yd: &[f64],
    ) -> (Vector2<f64>, Vector2<f64>) {
        let n = self.n;
        let mut mb = self.m_u.xy();
        let mut s_yd = Vector2::zeros();
        if self.first_moment_vanished() {
            return (mb, s_yd);
        }
        for c in 0..2 {
            let sr = &self.s[c * n..(c + 1) * n];
            mb[c] += dot(sr, y);
            s_yd[c] = dot(sr, yd);
        }
        (mb, s_yd)
    }

    /// The moments of this body at (y, ẏ): linear (§2.3, S and L rows in `self.s`, `ws.l`) or
    /// foreshortened (§6.3, Ŝ and L̂ rows in `ws.sy`, `ws.l`, contractions in `ws.fs`).
    #[inline(always)]
    pub(crate) fn shape_moments(&self, y: &[f64], yd: &[f64], ws: &mut Workspace) -> ShapeMoments {
        match self.fs {
            None => {
                let (mb, p) = self.linear_moments::<0>(y, 3, &mut ws.u, &mut ws.l);
                ShapeMoments { mb, p, axial: None }
            }
            Some(_) => self.fs_moments(y, yd, ws),
        }
    }

    /// Route (b) in the spatial relative set (§2.4 steps 1–3), linear or FS0 (the hatted
    /// moments of `fs_shape.rs`, and the velocity-product terms `e c₀`, `c₁ × e`,
    /// `Σ w c_k X̂_kᵀ e`); a planar FS0 body runs it too and keeps x, y, θz.
    pub(crate) fn shape_3d<O: RelativeSink>(
        &self,
        st: &BodyState<'_>,
        gyroscopic: bool,
        ws: &mut Workspace,
        out: &mut O,
    ) {
        let n = self.n;
        let (y, yd) = (st.y, st.y_dot);
        let (wb, ab) = body_frame_motion(st);
        let moments = self.shape_moments(y, yd, ws);
        let (mb, p) = (moments.mb, moments.p);
        let s_yd =
            self.first_moment_times(self.first_moment_rows(moments.axial.is_some(), &ws.sy), yd);
        let mut lam = Matrix3::zeros(); // lam[(b, c)] = (L_b)_c · ẏ
        let mut h_yd = 0.0;
        if n > 0 {
            for b in 0..3 {
                lam.set_row(b, &rows_dot_3(&ws.l[3 * b * n..], n, yd).transpose());
            }
            h_yd = lam[(0, 0)] + lam[(1, 1)] + lam[(2, 2)];
        }
        let io = Matrix3::identity() * p.trace() - p;

        // Body-frame inertia forces including the D-shift term −M̄_body {ā; 0; 0}, with
        // W ẏ = ω̄ (h·ẏ) − Σ_b ω̄_b (L_b ẏ).
        let translation = wb.cross(&wb.cross(&mb)) + 2.0 * wb.cross(&s_yd);
        let w_yd = wb * h_yd - lam.tr_mul(&wb);
        let rotation = wb.cross(&(io * wb)) + 2.0 * w_yd;
        let (qt, qr) = match &moments.axial {
            None => (-translation - self.mass * ab, -rotation - mb.cross(&ab)),
            Some(ax) => (
                -(translation - ax.axis * ax.c0) - self.mass * ab,
                -(rotation - ax.c1.cross(&ax.axis)) - mb.cross(&ab),
            ),
        };
        let rigid = self.global_rigid(&st.a, &st.r0, &mb, &p, &qt, &qr);
        out.rigid(
            self.dim,
            self.mass,
            &rigid.moment,
            &rigid.inertia,
            &rigid.force,
        );
        if n == 0 {
            return;
        }
        let mut qy = std::mem::take(&mut ws.qy);
        let mut yy = std::mem::take(&mut ws.yy);
        let modal_mass =
            self.shape_modal_terms(&wb, &ab, yd, gyroscopic, &moments, ws, &mut qy, &mut yy);
        c_rows(n, &ws.l, &mut ws.c);
        let s_rows = self.first_moment_rows(moments.axial.is_some(), &ws.sy);
        let s_rows = self.live_first_moment(s_rows);
        self.write_shape_couplings(
            &st.a,
            &st.r0,
            s_rows,
            Some(&ws.c),
            &mut ws.ax,
            &mut ws.wy,
            out,
        );
        out.modal_rows(self.dim, modal_mass.unwrap_or(&yy), &qy);
        ws.qy = qy;
        ws.yy = yy;
    }

    /// The modal rows of the relative set: `q_y = −(Σ_ab (ω̃ω̃)_ab (L_b)_a + 2 G ẏ) − Sᵀā` into
    /// `qy` (FS0: hatted, `+ Σ w c_k X̂_kᵀ e`), and the modal mass: `None` for the body's
    /// `M_yy`, or FS0's `M̂_yy` written into `yy`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn shape_modal_terms<'m>(
        &'m self,
        wb: &Vector3<f64>,
        ab: &Vector3<f64>,
        yd: &[f64],
        gyroscopic: bool,
        moments: &ShapeMoments,
        ws: &mut Workspace,
        qy: &mut [f64],
        yy: &mut [f64],
    ) -> Option<&'m [f64]> {
        let n = self.n;
        match &moments.axial {
            None => {
                // G(ω̄) ẏ = Σ_c ω̄_c G_c ẏ, unless dropped (`o2-nv`, terms.rs).
                if gyroscopic {
                    for (row, g) in self.g.chunks_exact(n).zip(ws.gy.iter_mut()) {
                        *g = dot(row, yd);
                    }
                    for j in 0..n {
                        qy[j] = wb.x * ws.gy[j] + wb.y * ws.gy[n + j] + wb.z * ws.gy[2 * n + j];
                    }
                } else {
                    qy[..n].fill(0.0);
                }
                modal_inertia_forces(wb, ab, self.live_first_moment(&self.s), &ws.l, qy);
                Some(&self.m_yy)
            }
            Some(ax) => {
                self.fs_gyroscopic(wb, &ax.axis, yd, ws, qy);
                modal_inertia_forces(wb, ab, Some(&ws.sy), &ws.l, qy);
                self.fs_add_c_term(ws, &ax.axis, qy);
                self.fs_yy(ws, &ax.axis, 1.0, &self.m_yy, yy);
                None
            }
        }
    }

    pub(crate) fn shape_2d<SM, SQ>(
        &self,
        st: &BodyState<'_>,
        gyroscopic: bool,
        ws: &mut Workspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let n = self.n;
        let (y, yd) = (st.y, st.y_dot);
        let (a, w, r0, _, ab) = planar_frame_motion(st);
        let m = self.mass;

        let (mb, s_yd) = self.planar_first_moment(y, yd);
        // I_zz(y) = P̄11 + P̄22 + 2 (S¹_1 + S²_2)·y + y·M_yy y ; h = S¹_1 + S²_2 + M_yy y ;
        // C_3 = S¹_2 − S²_1 + G_3 y ; all in O(n²) with three mat-vecs.
        let mut izz = self.p_u[(0, 0)] + self.p_u[(1, 1)];
        let mut h_yd = 0.0;
        let g3 = &self.g[2 * n * n..3 * n * n];
        if n > 0 {
            let (t, rest) = ws.u.split_at_mut(n);
            let (g3y, rest) = rest.split_at_mut(n);
            let g3yd = &mut rest[..n];
            if gyroscopic {
                for i in 0..n {
                    let mr = &self.m_yy[i * n..(i + 1) * n];
                    let gr = &g3[i * n..(i + 1) * n];
                    t[i] = dot(mr, y);
                    g3y[i] = dot(gr, y);
                    g3yd[i] = dot(gr, yd);
                }
            } else {
                // `o2-nv` (terms.rs): no −2ω G_3 ẏ in q_y.
                for i in 0..n {
                    t[i] = dot(&self.m_yy[i * n..(i + 1) * n], y);
                    g3y[i] = dot(&g3[i * n..(i + 1) * n], y);
                }
                g3yd.fill(0.0);
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

        write_planar_rigid(m_out, q_out, m, &lever, jzz, &[qtg.x, qtg.y, qrg]);
        if n == 0 {
            return;
        }
        self.write_planar_modal_terms(&a, &r0, w, &ab, ws, m_out, q_out);
    }

    /// The modal rows and columns of the planar lean path: `M̄_sy = A S`, `M̄_θy = r0 × (A S) + C_3`,
    /// `M_yy`, and `q_y = ω² h − 2ω G_3 ẏ − Sᵀā`, from h, C_3 and G_3 ẏ in the workspace.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn write_planar_modal_terms<SM, SQ>(
        &self,
        a: &Matrix2<f64>,
        r0: &Vector2<f64>,
        w: f64,
        ab: &Vector2<f64>,
        ws: &Workspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let n = self.n;
        let h = &ws.l[..n];
        let c3 = &ws.c[..n];
        let g3yd = &ws.u[2 * n..3 * n];
        if self.first_moment_vanished() {
            for j in 0..n {
                write_planar_coupling(m_out, j, 0.0, 0.0, c3[j]);
                q_out[3 + j] = w * w * h[j] - 2.0 * w * g3yd[j];
            }
        } else {
            for j in 0..n {
                let asj = a * Vector2::new(self.s[j], self.s[n + j]);
                let wyj = r0.x * asj.y - r0.y * asj.x + c3[j];
                write_planar_coupling(m_out, j, asj.x, asj.y, wyj);
                let sta = self.s[j] * ab.x + self.s[n + j] * ab.y;
                q_out[3 + j] = w * w * h[j] - 2.0 * w * g3yd[j] - sta;
            }
        }
        // M_yy is row-major: the column-major view of it is its transpose.
        let m_yy = nalgebra::DMatrixView::from_slice(&self.m_yy, n, n);
        m_out.view_mut((3, 3), (n, n)).tr_copy_from(&m_yy);
    }
}
