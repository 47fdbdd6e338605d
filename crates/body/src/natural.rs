//! Inertia terms in natural coordinates (docs/methods.md §2.5), both routes.
//!
//! 3D: `q = {r0; u; v; w; y}` (12 + n), `A = [u v w]` (not necessarily orthonormal),
//! `B_k = [I  r̄_k1 I  r̄_k2 I  r̄_k3 I  A X_k]`, `Ḃ_k q̇ = 2 Ȧ X_k ẏ`:
//!
//! ```text
//! M_r0r0 = m I, M_r0ea = m̄_a(y) I, M_eaeb = P_ab(y) I, M_r0y = A S, M_eay = A L_a(y),
//! M_yy = Σ_ab (e_a·e_b) Sᵃᵇ,
//! Q_v = −2 {Ȧ S ẏ; Ȧ L_1 ẏ; Ȧ L_2 ẏ; Ȧ L_3 ẏ; Σ_ab (e_a·ė_b) Sᵃᵇ ẏ}.
//! ```
//!
//! 2D: `q = {r0; u; y}` (4 + n), `A = [u  E u]`, `B_k = [I₂  r̄_k1 I + r̄_k2 E  A X_k]`:
//! `M_r0u = m̄_1 I + m̄_2 E`, `M_uu = (P_11 + P_22) I`, `M_uy = A L_1 − E A L_2`,
//! `M_yy = |u|² (S¹¹ + S²²)`, `Q_v = −2 {Ȧ S ẏ; (Ȧ L_1 − E Ȧ L_2) ẏ; Σ_ab (AᵀȦ)_ab Sᵃᵇ ẏ}`
//! with `Ȧ = [u̇  E u̇]`, and `Σ_ab (AᵀȦ)_ab Sᵃᵇ = (u·u̇)(S¹¹ + S²²) − (u·E u̇) G_3`.
//!
//! Route (a) accumulates `Σ w_k B_kᵀ B_k` and `−Σ w_k B_kᵀ (2 Ȧ X_k ẏ)` block by block, generic
//! over the cloud-point kinematics (`kinematics.rs`): for FS0 (methods.md §6.3) `X̂_k` replaces
//! `X_k`, `r̄_k` carries the axial shortening and `Ḃ_k q̇` gains `−A ē₁ (ẏᵀF_k ẏ)`.

use crate::bmatrix::{accumulate_modal_mass_2d, accumulate_modal_mass_3d};
use crate::kinematics::PointKinematics;
use crate::shape::{AxialMoments, rows_dot_3};
use crate::{
    FlexibleBody, Workspace, dot, write_modal_block, write_modal_rows, write_natural_rigid_block_3d,
};
use flexmbd_fe::NodeModes;
use nalgebra::{Dyn, Matrix, Matrix2, Matrix3, StorageMut, U1, Vector2, Vector3};

/// The state of one body in natural coordinates (plain data).
///
/// 3D: `a = [u v w]` and `a_dot = [u̇ v̇ ẇ]` (columns, global components; the
/// orthonormality constraints need not hold). 2D: use [`NaturalState::planar`];
/// there `a = [u  E u  e_z]` and only `u`, `u̇` are coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NaturalState<'a> {
    /// Position of the frame origin r0.
    pub r0: Vector3<f64>,
    /// A = [u v w].
    pub a: Matrix3<f64>,
    /// ṙ0.
    pub r0_dot: Vector3<f64>,
    /// Ȧ = [u̇ v̇ ẇ].
    pub a_dot: Matrix3<f64>,
    /// Modal coordinates y.
    pub y: &'a [f64],
    /// Modal rates ẏ.
    pub y_dot: &'a [f64],
}

impl<'a> NaturalState<'a> {
    /// A planar natural state {r0, u, y}: `A = [u  E u]`, `Ȧ = [u̇  E u̇]`.
    pub fn planar(
        r0: Vector2<f64>,
        u: Vector2<f64>,
        r0_dot: Vector2<f64>,
        u_dot: Vector2<f64>,
        y: &'a [f64],
        y_dot: &'a [f64],
    ) -> Self {
        Self {
            r0: Vector3::new(r0.x, r0.y, 0.0),
            a: Matrix3::new(u.x, -u.y, 0.0, u.y, u.x, 0.0, 0.0, 0.0, 1.0),
            r0_dot: Vector3::new(r0_dot.x, r0_dot.y, 0.0),
            a_dot: Matrix3::new(u_dot.x, -u_dot.y, 0.0, u_dot.y, u_dot.x, 0.0, 0.0, 0.0, 0.0),
            y,
            y_dot,
        }
    }
}

/// Scratch storage for the natural-coordinate terms, sized once for one body
/// ([`FlexibleBody::natural_workspace`]). Keeping it outside the body lets a
/// formulation evaluate a shared `&FlexibleBody`.
#[derive(Clone, Debug)]
pub struct NaturalWorkspace(pub(crate) Workspace);

/// A material point of a body (docs/methods.md §1.1): undeformed position r̄_u and
/// translational mode rows X_P (3 × n, row-major), e.g. an FE node used by a joint.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyPoint {
    /// Undeformed position r̄_u (body components).
    pub position: Vector3<f64>,
    /// Translational mode rows X_P, row-major (3 n).
    pub rows: Vec<f64>,
}

impl BodyPoint {
    /// A point that does not deform (n zero columns).
    pub fn rigid(position: Vector3<f64>, n_modes: usize) -> Self {
        Self {
            position,
            rows: vec![0.0; 3 * n_modes],
        }
    }
    /// The translational rows of an FE node.
    pub fn from_node(node: &NodeModes) -> Self {
        let (r, n) = (&node.translation, node.translation.ncols());
        let mut rows = Vec::with_capacity(3 * n);
        for a in 0..3 {
            for j in 0..n {
                rows.push(r[(a, j)]);
            }
        }
        Self {
            position: node.position,
            rows,
        }
    }
    /// Number of modal columns n.
    pub fn n_modes(&self) -> usize {
        self.rows.len() / 3
    }
    /// Deformed position in body components, r̄_P = r̄_u + X_P y.
    pub fn local_position(&self, y: &[f64]) -> Vector3<f64> {
        let n = self.n_modes();
        Vector3::new(
            self.position.x + dot(&self.rows[..n], y),
            self.position.y + dot(&self.rows[n..2 * n], y),
            self.position.z + dot(&self.rows[2 * n..], y),
        )
    }
    /// Global position r_P = r0 + A r̄_P.
    pub fn global_position(&self, r0: &Vector3<f64>, a: &Matrix3<f64>, y: &[f64]) -> Vector3<f64> {
        r0 + a * self.local_position(y)
    }
    /// X_P ẏ (body components).
    pub fn modal_velocity(&self, y_dot: &[f64]) -> Vector3<f64> {
        self.local_position(y_dot) - self.position
    }
}

/// The frame of a planar natural state: `u`, `u̇`, `A = [u  E u]` and `Ȧ = [u̇  E u̇]`.
#[inline(always)]
pub(crate) fn planar_frame(
    st: &NaturalState<'_>,
) -> (Vector2<f64>, Vector2<f64>, Matrix2<f64>, Matrix2<f64>) {
    let u = st.a.column(0).xy();
    let ud = st.a_dot.column(0).xy();
    let a = Matrix2::new(u.x, -u.y, u.y, u.x);
    let ad = Matrix2::new(ud.x, -ud.y, ud.y, ud.x);
    (u, ud, a, ad)
}

/// The moments the planar natural-set kernel reads (§2.5 2D; FS0: hatted, §6.3).
pub(crate) struct PlanarMoments {
    /// m̄_1, m̄_2.
    pub(crate) mb: Vector2<f64>,
    /// P_11 + P_22.
    pub(crate) trace: f64,
    /// S ẏ (planar rows).
    pub(crate) s_yd: Vector2<f64>,
    /// L_1 ẏ and L_2 ẏ (planar rows).
    pub(crate) l1_yd: Vector2<f64>,
    pub(crate) l2_yd: Vector2<f64>,
    /// Where the rows of L_2 start in `ws.l`, in units of n (linear 2, FS0 3).
    pub(crate) l2_row: usize,
    /// The velocity-product moments of a foreshortened body.
    pub(crate) axial: Option<AxialMoments>,
}

/// The rigid 4 × 4 block of a planar natural-coordinate mass matrix over (r0, u):
/// `[[m I, m̄_1 I + m̄_2 E], [(m̄_1 I + m̄_2 E)ᵀ, (P_11 + P_22) I]]`.
#[inline(always)]
pub(crate) fn write_natural_rigid_block_2d<SM>(
    m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
    m: f64,
    mb: &Vector2<f64>,
    trace: f64,
) where
    SM: StorageMut<f64, Dyn, Dyn>,
{
    m_out[(0, 0)] = m;
    m_out[(1, 1)] = m;
    m_out[(0, 1)] = 0.0;
    m_out[(1, 0)] = 0.0;
    // m̄_1 I + m̄_2 E = [[m̄1, −m̄2], [m̄2, m̄1]].
    let r0u = Matrix2::new(mb.x, -mb.y, mb.y, mb.x);
    for i in 0..2 {
        for j in 0..2 {
            m_out[(i, 2 + j)] = r0u[(i, j)];
            m_out[(2 + j, i)] = r0u[(i, j)];
            m_out[(2 + i, 2 + j)] = if i == j { trace } else { 0.0 };
        }
    }
}

#[inline(always)]
pub(crate) fn e2(v: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-v.y, v.x)
}

impl FlexibleBody {
    /// `Σ_ab G_ab Sᵃᵇ_ij` for the Gram matrix `G_ab = e_a·e_b` (the modal mass of the natural
    /// set, §2.5).
    #[inline(always)]
    pub(crate) fn gram_modal_mass(&self, gram: &Matrix3<f64>, i: usize, j: usize) -> f64 {
        let n = self.n;
        let mut v = 0.0;
        for aa in 0..3 {
            for bb in 0..3 {
                v += gram[(aa, bb)] * self.sab[(3 * aa + bb) * n * n + i * n + j];
            }
        }
        v
    }

    /// Route (b) in spatial natural coordinates (module doc), linear or FS0 (the hatted
    /// moments of `fs_shape.rs` and the velocity-product terms `A e c₀`, `A e c₁,b`).
    pub(crate) fn natural_shape_3d<SM, SQ>(
        &self,
        st: &NaturalState<'_>,
        nws: &mut NaturalWorkspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let n = self.n;
        let (y, yd) = (st.y, st.y_dot);
        let (a, ad) = (&st.a, &st.a_dot);
        let ws = &mut nws.0;
        let moments = self.shape_moments(y, yd, ws);
        let s_rows = self.first_moment_rows(moments.axial.is_some(), &ws.sy);
        let s_yd = self.first_moment_times(s_rows, yd);
        write_natural_rigid_block_3d(m_out, self.mass, &moments.mb, &moments.p);
        let axial = moments.axial.as_ref().map(|ax| (a * ax.axis, ax));
        let mut q0 = -2.0 * (ad * s_yd);
        if let Some((ae, ax)) = &axial {
            q0 += ae * ax.c0;
        }
        for i in 0..3 {
            q_out[i] = q0[i];
        }
        for b in 0..3 {
            // L_b ẏ.
            let lby = if n > 0 {
                rows_dot_3(&ws.l[3 * b * n..], n, yd)
            } else {
                Vector3::zeros()
            };
            let mut qb = -2.0 * (ad * lby);
            if let Some((ae, ax)) = &axial {
                qb += ae * ax.c1[b];
            }
            for i in 0..3 {
                q_out[3 + 3 * b + i] = qb[i];
            }
        }
        if n == 0 {
            return;
        }
        let gram = a.tr_mul(a); // e_a · e_b
        let cdot = a.tr_mul(ad); // e_a · ė_b
        let s_rows = self.live_first_moment(s_rows);
        write_natural_couplings_3d(m_out, a, n, s_rows, &ws.l);
        let o = 12;
        if axial.is_some() {
            self.natural_modal_terms_fs_3d(yd, &gram, &cdot, ws);
            write_modal_rows(m_out, q_out, o, &ws.fs.modal_mass, &ws.qy);
            return;
        }
        // M_yy = Σ_ab (e_a·e_b) Sᵃᵇ (upper triangle, mirrored; Sᵇᵃ = Sᵃᵇᵀ);
        // Q_y = −2 Σ_ab (e_a·ė_b) Sᵃᵇ ẏ.
        let qy = &mut ws.qy;
        qy.fill(0.0);
        for aa in 0..3 {
            for bb in 0..3 {
                let blk = &self.sab[(3 * aa + bb) * n * n..(3 * aa + bb + 1) * n * n];
                let c = cdot[(aa, bb)];
                for (i, row) in blk.chunks_exact(n).enumerate() {
                    qy[i] += c * dot(row, yd);
                }
            }
        }
        for i in 0..n {
            for j in i..n {
                let v = self.gram_modal_mass(&gram, i, j);
                m_out[(o + i, o + j)] = v;
                m_out[(o + j, o + i)] = v;
            }
            q_out[o + i] = -2.0 * qy[i];
        }
    }

    /// The planar moments of a linear body (§2.3 in the planar rows), with the rows of L in
    /// `ws.l`: (L_1)_1, (L_1)_2, (L_2)_1, (L_2)_2 at 0, n, 2n, 3n.
    #[inline(always)]
    fn planar_moments(&self, y: &[f64], yd: &[f64], ws: &mut Workspace) -> PlanarMoments {
        let n = self.n;
        let (mb, s_yd) = self.planar_first_moment(y, yd);
        let mut ptr = self.p_u[(0, 0)] + self.p_u[(1, 1)];
        let mut lam = Matrix2::zeros(); // lam[(b, c)] = (L_b)_c · ẏ
        if n > 0 {
            for b in 0..2 {
                for c in 0..2 {
                    let dst = (2 * b + c) * n;
                    let sa = &self.sa[(3 * b + c) * n..(3 * b + c + 1) * n];
                    let blk = &self.sab[(3 * c + b) * n * n..(3 * c + b + 1) * n * n];
                    for (j, row) in blk.chunks_exact(n).enumerate() {
                        ws.l[dst + j] = sa[j] + dot(row, y);
                    }
                    lam[(b, c)] = dot(&ws.l[dst..dst + n], yd);
                }
            }
            for c in 0..2 {
                ptr += dot(&self.sa[(3 * c + c) * n..(3 * c + c + 1) * n], y)
                    + dot(&ws.l[(2 * c + c) * n..(2 * c + c + 1) * n], y);
            }
        }
        PlanarMoments {
            mb,
            trace: ptr,
            s_yd,
            l1_yd: Vector2::new(lam[(0, 0)], lam[(0, 1)]),
            l2_yd: Vector2::new(lam[(1, 0)], lam[(1, 1)]),
            l2_row: 2,
            axial: None,
        }
    }

    /// Route (b) in planar natural coordinates (module doc), linear or FS0 (the hatted
    /// moments of `fs_shape.rs` and the velocity-product terms `A e c₀`, `(c₁,1 I − c₁,2 E) A e`).
    pub(crate) fn natural_shape_2d<SM, SQ>(
        &self,
        st: &NaturalState<'_>,
        nws: &mut NaturalWorkspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let n = self.n;
        let (u, ud, a, ad) = planar_frame(st);
        let ws = &mut nws.0;
        let moments = match self.fs {
            None => self.planar_moments(st.y, st.y_dot, ws),
            Some(_) => self.planar_fs_moments(st.y, st.y_dot, ws),
        };
        write_natural_rigid_block_2d(m_out, self.mass, &moments.mb, moments.trace);
        let mut q0 = -2.0 * (ad * moments.s_yd);
        let mut qu = -2.0 * (ad * moments.l1_yd - e2(ad * moments.l2_yd));
        if let Some(ax) = &moments.axial {
            let ae = a * ax.axis.xy();
            q0 += ae * ax.c0;
            qu += ae * ax.c1.x;
            qu -= e2(ae) * ax.c1.y;
        }
        q_out[0] = q0.x;
        q_out[1] = q0.y;
        q_out[2] = qu.x;
        q_out[3] = qu.y;
        if n == 0 {
            return;
        }
        let o = 4;
        let s_rows = self.first_moment_rows(moments.axial.is_some(), &ws.sy);
        let l2 = moments.l2_row * n;
        let s_rows = self.live_first_moment(s_rows);
        for j in 0..n {
            let asj = match s_rows {
                Some(s) => a * Vector2::new(s[j], s[n + j]),
                None => Vector2::zeros(),
            };
            let l1 = Vector2::new(ws.l[j], ws.l[n + j]);
            let l2 = Vector2::new(ws.l[l2 + j], ws.l[l2 + n + j]);
            let uy = a * l1 - e2(a * l2);
            for i in 0..2 {
                m_out[(i, o + j)] = asj[i];
                m_out[(o + j, i)] = asj[i];
                m_out[(2 + i, o + j)] = uy[i];
                m_out[(o + j, 2 + i)] = uy[i];
            }
        }
        let uu = u.norm_squared();
        if moments.axial.is_some() {
            self.natural_modal_terms_fs_2d(&u, &ud, st.y_dot, ws);
            for i in 0..n {
                for j in 0..n {
                    m_out[(o + i, o + j)] = uu * ws.yy[i * n + j];
                }
                q_out[o + i] = ws.qy[i];
            }
            return;
        }
        // M_yy = |u|² (S¹¹ + S²²), Q_y = −2 ((u·u̇)(S¹¹ + S²²) − (u·E u̇) G_3) ẏ.
        let u_ud = u.dot(&ud);
        let u_eud = u.dot(&e2(ud));
        let g3 = &self.g[2 * n * n..3 * n * n];
        for j in 0..n {
            let row_m = &self.m_yy[j * n..(j + 1) * n];
            let row_g = &g3[j * n..(j + 1) * n];
            q_out[o + j] = -2.0 * (u_ud * dot(row_m, st.y_dot) - u_eud * dot(row_g, st.y_dot));
            for i in j..n {
                let v = uu * self.m_yy[j * n + i];
                m_out[(o + j, o + i)] = v;
                m_out[(o + i, o + j)] = v;
            }
        }
    }

    /// Route (a) in spatial natural coordinates {r0, u, v, w, y} for the cloud-point
    /// kinematics `points` (module doc, with `X̂_k` for `X_k` and `Ḃ_k q̇ = 2 Ȧ X̂_k ẏ + A b_k`).
    pub(crate) fn natural_bmatrix_3d<K, SM, SQ>(
        &self,
        st: &NaturalState<'_>,
        mut points: K,
        ws: &mut Workspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        K: PointKinematics,
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let n = self.n;
        let (y, yd) = (st.y, st.y_dot);
        let (a, ad) = (&st.a, &st.a_dot);
        let axis = points.axis();
        let a_axis = a * axis;
        // Accumulators: sy (A X̂), l (r̄_b A X̂ for b = 0..3, at 3 n b), yy, qy.
        ws.sy.fill(0.0);
        ws.l.fill(0.0);
        ws.yy.fill(0.0);
        ws.qy.fill(0.0);
        let mut msum = 0.0;
        let mut rsum = Vector3::zeros();
        let mut psum = Matrix3::zeros();
        let mut asum = Vector3::zeros();
        let mut arsum = Matrix3::zeros(); // column b: Σ w r̄_b a_k
        let w3 = 3 * n;
        for k in 0..self.w.len() {
            let wk = self.w[k];
            let x = &self.rows[k * w3..(k + 1) * w3];
            points.at(k, x);
            let xh = points.velocity_rows(x);
            let (x0, x1, x2) = (&x[..n], &x[n..2 * n], &x[2 * n..]);
            let (xh0, xh1, xh2) = (&xh[..n], &xh[n..2 * n], &xh[2 * n..3 * n]);
            let mut rb = self.pos[k] + Vector3::new(dot(x0, y), dot(x1, y), dot(x2, y));
            let mut acc = 2.0 * (ad * Vector3::new(dot(xh0, yd), dot(xh1, yd), dot(xh2, yd)));
            if let Some(s) = points.axial() {
                rb -= axis * s.shortening;
                acc -= a_axis * s.velocity_product;
            }
            msum += wk;
            rsum += wk * rb;
            psum += (wk * rb) * rb.transpose();
            asum += wk * acc;
            arsum += (wk * acc) * rb.transpose();
            if n == 0 {
                continue;
            }
            let (ax0, rest) = ws.ax.split_at_mut(n);
            let (ax1, ax2) = rest.split_at_mut(n);
            for j in 0..n {
                let v = a * Vector3::new(xh0[j], xh1[j], xh2[j]);
                ax0[j] = v.x;
                ax1[j] = v.y;
                ax2[j] = v.z;
                for c in 0..3 {
                    ws.sy[c * n + j] += wk * v[c];
                    for b in 0..3 {
                        ws.l[3 * n * b + c * n + j] += wk * rb[b] * v[c];
                    }
                }
                ws.qy[j] += wk * (acc.x * v.x + acc.y * v.y + acc.z * v.z);
            }
            accumulate_modal_mass_3d(wk, n, &ws.ax, &mut ws.yy);
        }
        let sums = BMatrixSums3 {
            m: msum,
            mr: rsum,
            p: psum,
            a: asum,
            ar: arsum,
        };
        write_bmatrix_natural_3d(m_out, q_out, n, &sums, &ws.sy, &ws.l, &ws.yy, &ws.qy);
    }

    /// Route (a) in planar natural coordinates {r0, u, y} for the cloud-point kinematics
    /// `points` (module doc, with `X̂_k` for `X_k` and `Ḃ_k q̇ = 2 Ȧ X̂_k ẏ + A b_k`).
    pub(crate) fn natural_bmatrix_2d<K, SM, SQ>(
        &self,
        st: &NaturalState<'_>,
        mut points: K,
        ws: &mut Workspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        K: PointKinematics,
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let n = self.n;
        let (y, yd) = (st.y, st.y_dot);
        let (_, _, a, ad) = planar_frame(st);
        let axis = points.axis().xy();
        let a_axis = a * axis;
        ws.sy.fill(0.0);
        ws.wy.fill(0.0);
        ws.yy.fill(0.0);
        ws.qy.fill(0.0);
        let mut msum = 0.0;
        let mut rsum = Vector2::zeros();
        let mut psum = 0.0;
        let mut asum = Vector2::zeros();
        let mut qu = Vector2::zeros();
        let w3 = 3 * n;
        for k in 0..self.w.len() {
            let wk = self.w[k];
            let x = &self.rows[k * w3..(k + 1) * w3];
            points.at(k, x);
            let xh = points.velocity_rows(x);
            let (x0, x1) = (&x[..n], &x[n..2 * n]);
            let (xh0, xh1) = (&xh[..n], &xh[n..2 * n]);
            let mut rb = self.pos[k].xy() + Vector2::new(dot(x0, y), dot(x1, y));
            let mut acc = 2.0 * (ad * Vector2::new(dot(xh0, yd), dot(xh1, yd)));
            if let Some(s) = points.axial() {
                rb -= axis * s.shortening;
                acc -= a_axis * s.velocity_product;
            }
            msum += wk;
            rsum += wk * rb;
            psum += wk * rb.norm_squared();
            asum += wk * acc;
            // (r̄1 I + r̄2 E)ᵀ a = r̄1 a − r̄2 E a.
            qu += wk * (rb.x * acc - rb.y * e2(acc));
            let (ax0, ax1) = ws.ax.split_at_mut(n);
            for j in 0..n {
                let v = a * Vector2::new(xh0[j], xh1[j]);
                ax0[j] = v.x;
                ax1[j] = v.y;
                ws.sy[j] += wk * v.x;
                ws.sy[n + j] += wk * v.y;
                let uy = rb.x * v - rb.y * e2(v);
                ws.wy[j] += wk * uy.x;
                ws.wy[n + j] += wk * uy.y;
                ws.qy[j] += wk * acc.dot(&v);
            }
            accumulate_modal_mass_2d(wk, n, &ws.ax, &mut ws.yy);
        }
        let sums = BMatrixSums2 {
            m: msum,
            mr: rsum,
            p: psum,
            a: asum,
            qu,
        };
        write_bmatrix_natural_2d(m_out, q_out, n, &sums, &ws.sy, &ws.wy, &ws.yy, &ws.qy);
    }
}

/// The rigid–modal couplings of a spatial natural-coordinate M, symmetric: `M_r0y = A S` and
/// `M_eby = A L_b` from the body-frame rows of S (3 × n; `None` when S vanished, `vanished.rs`:
/// zero without the products) and L ((L_b)_a at (3b + a) n).
#[inline(always)]
pub(crate) fn write_natural_couplings_3d<SM>(
    m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
    a: &Matrix3<f64>,
    n: usize,
    s: Option<&[f64]>,
    l: &[f64],
) where
    SM: StorageMut<f64, Dyn, Dyn>,
{
    let o = 12;
    for j in 0..n {
        let asj = match s {
            Some(s) => a * Vector3::new(s[j], s[n + j], s[2 * n + j]),
            None => Vector3::zeros(),
        };
        for i in 0..3 {
            m_out[(i, o + j)] = asj[i];
            m_out[(o + j, i)] = asj[i];
        }
        for b in 0..3 {
            let lbj = Vector3::new(
                l[(3 * b) * n + j],
                l[(3 * b + 1) * n + j],
                l[(3 * b + 2) * n + j],
            );
            let alj = a * lbj;
            for i in 0..3 {
                m_out[(3 + 3 * b + i, o + j)] = alj[i];
                m_out[(o + j, 3 + 3 * b + i)] = alj[i];
            }
        }
    }
}

/// The mass-weighted sums a route-(a) kernel in planar natural coordinates {r0, u, y}
/// accumulates over the cloud: Σw, Σw r̄, Σw|r̄|², Σw Ḃ-acceleration and its u-moment.
pub(crate) struct BMatrixSums2 {
    pub(crate) m: f64,
    pub(crate) mr: Vector2<f64>,
    pub(crate) p: f64,
    pub(crate) a: Vector2<f64>,
    pub(crate) qu: Vector2<f64>,
}

/// The same sums in spatial natural coordinates {r0, u, v, w, y}: Σw, Σw r̄, Σw r̄ r̄ᵀ,
/// Σw Ḃ-acceleration and its moments with r̄.
pub(crate) struct BMatrixSums3 {
    pub(crate) m: f64,
    pub(crate) mr: Vector3<f64>,
    pub(crate) p: Matrix3<f64>,
    pub(crate) a: Vector3<f64>,
    pub(crate) ar: Matrix3<f64>,
}

/// Write a planar route-(a) result: the rigid 4 × 4 block [[m I, R(m̄)], [R(m̄)ᵀ, P I]] with
/// R(m̄) = [m̄  e₂(m̄)], Q = −(Σa, q_u, q_y), the couplings `sy` (r0–y) and `wy` (u–y, both
/// 2 × n row-major) and the modal block from the upper triangle of `yy`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn write_bmatrix_natural_2d<SM, SQ>(
    m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
    q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    n: usize,
    s: &BMatrixSums2,
    sy: &[f64],
    wy: &[f64],
    yy: &[f64],
    qy: &[f64],
) where
    SM: StorageMut<f64, Dyn, Dyn>,
    SQ: StorageMut<f64, Dyn, U1>,
{
    m_out[(0, 0)] = s.m;
    m_out[(1, 1)] = s.m;
    m_out[(0, 1)] = 0.0;
    m_out[(1, 0)] = 0.0;
    let r0u = Matrix2::new(s.mr.x, -s.mr.y, s.mr.y, s.mr.x);
    for i in 0..2 {
        for j in 0..2 {
            m_out[(i, 2 + j)] = r0u[(i, j)];
            m_out[(2 + j, i)] = r0u[(i, j)];
            m_out[(2 + i, 2 + j)] = if i == j { s.p } else { 0.0 };
        }
    }
    q_out[0] = -s.a.x;
    q_out[1] = -s.a.y;
    q_out[2] = -s.qu.x;
    q_out[3] = -s.qu.y;
    let o = 4;
    for j in 0..n {
        for c in 0..2 {
            m_out[(c, o + j)] = sy[c * n + j];
            m_out[(o + j, c)] = sy[c * n + j];
            m_out[(2 + c, o + j)] = wy[c * n + j];
            m_out[(o + j, 2 + c)] = wy[c * n + j];
        }
    }
    write_modal_block(m_out, q_out, o, n, yy, qy);
}

/// Write a spatial route-(a) result: the rigid 12 × 12 block, Q = −(Σa, Σa r̄ᵀ, q_y), the
/// couplings `sy` (r0–y, 3 × n) and `l` (u, v, w–y, 3 × 3 × n) and the modal block.
#[allow(clippy::too_many_arguments)]
pub(crate) fn write_bmatrix_natural_3d<SM, SQ>(
    m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
    q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    n: usize,
    s: &BMatrixSums3,
    sy: &[f64],
    l: &[f64],
    yy: &[f64],
    qy: &[f64],
) where
    SM: StorageMut<f64, Dyn, Dyn>,
    SQ: StorageMut<f64, Dyn, U1>,
{
    write_natural_rigid_block_3d(m_out, s.m, &s.mr, &s.p);
    for i in 0..3 {
        q_out[i] = -s.a[i];
        for b in 0..3 {
            q_out[3 + 3 * b + i] = -s.ar[(i, b)];
        }
    }
    let o = 12;
    for j in 0..n {
        for c in 0..3 {
            let v = sy[c * n + j];
            m_out[(c, o + j)] = v;
            m_out[(o + j, c)] = v;
            for b in 0..3 {
                let v = l[3 * n * b + c * n + j];
                m_out[(3 + 3 * b + c, o + j)] = v;
                m_out[(o + j, 3 + 3 * b + c)] = v;
            }
        }
    }
    write_modal_block(m_out, q_out, o, n, yy, qy);
}
