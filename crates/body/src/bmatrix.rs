//! Route (a): B-matrix projection on the mass cloud (docs/methods.md §2.2).
//!
//! For each cloud point k, with `r̄_k = r̄_uk + X_k y` and `r_k = r0 + A r̄_k`:
//!
//! ```text
//! B_k = [I  −r̃_k  A X_k],   Ḃ_k Z = ω × ṡ + ω × (ω × r_k) + 2 ω × A X_k ẏ,
//! M̄ = Σ w_k B_kᵀ B_k,       Q̄_v = −Σ w_k B_kᵀ (Ḃ_k Z).
//! ```
//!
//! `Σ w_k B_kᵀ B_k` is accumulated block by block (the identity block of `B_k`
//! is not multiplied out): `Σ w I`, `−Σ w r̃_k`, `Σ w A X_k`, `Σ w (|r_k|² I − r_k r_kᵀ)`,
//! `Σ w r̃_k A X_k`, `Σ w (A X_k)ᵀ (A X_k)` (upper triangle, mirrored); and
//! `Q̄_v = −{Σ w a_k; Σ w r_k × a_k; Σ w (A X_k)ᵀ a_k}` with `a_k = Ḃ_k Z`.
//! Per point: about `3n(n+1)/2 + 30 n + 60` multiply-adds (3D).
//!
//! The spatial kernel is generic over the cloud-point kinematics (`kinematics.rs`): compiled
//! for linear points it is the formula above; for foreshortened points (FS0, docs/methods.md §6.3)
//! `X̂_k` replaces `X_k`, `r̄_k` carries the axial shortening and `Ḃ_k Z` gains
//! `−A ē₁ (ẏᵀF_k ẏ)`. A planar FS0 body runs it too and keeps the x, y, θz rows and columns.
//!
//! 2D: `B_k = [I₂  E r_k  A X_k]` (E = 90° rotation, `e_z × r = E r`),
//! `Ḃ_k Z = ω E ṡ − ω² r_k + 2 ω E A X_k ẏ`.

use crate::blocks::RelativeSink;
use crate::kinematics::PointKinematics;
use crate::{
    BodyState, FlexibleBody, Workspace, planar_rotation, write_modal_block, write_planar_coupling,
    write_planar_rigid,
};
use nalgebra::{Dyn, Matrix, Matrix3, StorageMut, U1, Vector2, Vector3};

impl FlexibleBody {
    /// Route (a) in the spatial relative set for the cloud-point kinematics `points`
    /// (`X̂_k` for `X_k`, `+ A b_k` in `Ḃ_k Z`); a planar body keeps the x, y, θz rows and
    /// columns of the 3D sums.
    pub(crate) fn bmatrix_3d<K: PointKinematics, O: RelativeSink>(
        &self,
        st: &BodyState<'_>,
        mut points: K,
        ws: &mut Workspace,
        out: &mut O,
    ) {
        let n = self.n;
        let (y, yd) = (st.y, st.y_dot);
        let a = &st.a;
        let r0 = st.r0;
        let om = st.omega;
        let w_sd = om.cross(&st.s_dot);
        let axis = points.axis();
        let a_axis = a * axis;
        ws.sy.fill(0.0);
        ws.wy.fill(0.0);
        ws.yy.fill(0.0);
        ws.qy.fill(0.0);
        let mut msum = 0.0;
        let mut gsum = Vector3::zeros();
        let mut psum = Matrix3::zeros();
        let mut asum = Vector3::zeros();
        let mut tq = Vector3::zeros();
        let w3 = 3 * n;
        for k in 0..self.w.len() {
            let wk = self.w[k];
            let x = &self.rows[k * w3..(k + 1) * w3];
            points.at(k, x);
            let (xy, xhyd) = points.relative_products(x, y, yd);
            let mut rb = self.pos[k] + xy;
            if let Some(s) = points.axial() {
                rb -= axis * s.shortening;
            }
            let r = r0 + a * rb;
            let axyd = a * xhyd;
            let mut acc = w_sd + om.cross(&om.cross(&r)) + 2.0 * om.cross(&axyd);
            if let Some(s) = points.axial() {
                acc -= a_axis * s.velocity_product;
            }
            msum += wk;
            gsum += wk * r;
            psum += (wk * r) * r.transpose();
            asum += wk * acc;
            tq += wk * r.cross(&acc);
            let wr = wk * r;
            let wacc = wk * acc;
            accumulate_modal_3d(a, wk, &wr, &wacc, points.velocity_rows(x), ws);
        }
        let jo = Matrix3::identity() * psum.trace() - psum;
        let force = [-asum.x, -asum.y, -asum.z, -tq.x, -tq.y, -tq.z];
        out.rigid(self.dim, msum, &gsum, &jo, &force);
        out.couplings(self.dim, n, &ws.sy, &ws.wy);
        out.modal_block(self.dim, n, &ws.yy, &ws.qy);
    }

    pub(crate) fn bmatrix_2d<SM, SQ>(
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
        let r0 = st.r0.xy();
        let w = st.omega.z;
        let e = |v: Vector2<f64>| Vector2::new(-v.y, v.x);
        let w_sd = w * e(st.s_dot.xy());
        ws.sy.fill(0.0);
        ws.wy.fill(0.0);
        ws.yy.fill(0.0);
        ws.qy.fill(0.0);
        let mut msum = 0.0;
        let mut gsum = Vector2::zeros();
        let mut jsum = 0.0;
        let mut asum = Vector2::zeros();
        let mut tq = 0.0;
        let w3 = 3 * n;
        for k in 0..self.w.len() {
            let wk = self.w[k];
            let x = &self.rows[k * w3..(k + 1) * w3];
            let (x0, x1) = (&x[..n], &x[n..2 * n]);
            let (mut xy, mut xyd) = ([0.0f64; 2], [0.0f64; 2]);
            for ((&u, &v), (&p, &q)) in x0.iter().zip(x1).zip(y.iter().zip(yd)) {
                xy[0] += u * p;
                xy[1] += v * p;
                xyd[0] += u * q;
                xyd[1] += v * q;
            }
            let rb = self.pos[k].xy() + Vector2::from(xy);
            let r = r0 + a * rb;
            let axyd = a * Vector2::from(xyd);
            let acc = w_sd - w * w * r + 2.0 * w * e(axyd);
            msum += wk;
            gsum += wk * r;
            jsum += wk * r.norm_squared();
            asum += wk * acc;
            tq += wk * (r.x * acc.y - r.y * acc.x);
            let wr = wk * r;
            let wacc = wk * acc;
            {
                let (ax0, ax1) = ws.ax.split_at_mut(n);
                for j in 0..n {
                    let axj = a * Vector2::new(x0[j], x1[j]);
                    ax0[j] = axj.x;
                    ax1[j] = axj.y;
                    ws.sy[j] += wk * axj.x;
                    ws.sy[n + j] += wk * axj.y;
                    ws.wy[j] += wr.x * axj.y - wr.y * axj.x;
                    ws.qy[j] += wacc.dot(&axj);
                }
            }
            accumulate_modal_mass_2d(wk, n, &ws.ax, &mut ws.yy);
        }
        write_planar_rigid(m_out, q_out, msum, &gsum, jsum, &[-asum.x, -asum.y, -tq]);
        for j in 0..n {
            write_planar_coupling(m_out, j, ws.sy[j], ws.sy[n + j], ws.wy[j]);
        }
        write_modal_block(m_out, q_out, 3, n, &ws.yy, &ws.qy);
    }
}

/// Add one cloud point's modal terms to the spatial route-(a) sums: with the global rows
/// `A X̂_k` (into `ws.ax`), `Σ w A X̂_k` (`ws.sy`), `Σ w r̃_k A X̂_k` (`ws.wy`, with `wr = w r_k`),
/// `Σ w (A X̂_k)ᵀ a_k` (`ws.qy`, with `wacc = w a_k`) and `Σ w (A X̂_k)ᵀ (A X̂_k)` (`ws.yy`, the
/// upper triangle is what is read).
#[inline(always)]
fn accumulate_modal_3d(
    a: &Matrix3<f64>,
    wk: f64,
    wr: &Vector3<f64>,
    wacc: &Vector3<f64>,
    xh: &[f64],
    ws: &mut Workspace,
) {
    let n = ws.qy.len();
    {
        let (ax0, rest) = ws.ax.split_at_mut(n);
        let (ax1, ax2) = rest.split_at_mut(n);
        let (sy0, rest) = ws.sy.split_at_mut(n);
        let (sy1, sy2) = rest.split_at_mut(n);
        let (wy0, rest) = ws.wy.split_at_mut(n);
        let (wy1, wy2) = rest.split_at_mut(n);
        let qy = &mut ws.qy[..n];
        let (ax2, sy2, wy2) = (&mut ax2[..n], &mut sy2[..n], &mut wy2[..n]);
        let (x0, x1, x2) = (&xh[..n], &xh[n..2 * n], &xh[2 * n..3 * n]);
        // Row-wise (vectorizable over j): A X̂_k, then the accumulators.
        let (a00, a01, a02) = (a[(0, 0)], a[(0, 1)], a[(0, 2)]);
        let (a10, a11, a12) = (a[(1, 0)], a[(1, 1)], a[(1, 2)]);
        let (a20, a21, a22) = (a[(2, 0)], a[(2, 1)], a[(2, 2)]);
        for j in 0..n {
            let (u, v, w) = (x0[j], x1[j], x2[j]);
            ax0[j] = a00 * u + a01 * v + a02 * w;
            ax1[j] = a10 * u + a11 * v + a12 * w;
            ax2[j] = a20 * u + a21 * v + a22 * w;
        }
        for j in 0..n {
            let (p, q, r) = (ax0[j], ax1[j], ax2[j]);
            sy0[j] += wk * p;
            sy1[j] += wk * q;
            sy2[j] += wk * r;
            wy0[j] += wr.y * r - wr.z * q;
            wy1[j] += wr.z * p - wr.x * r;
            wy2[j] += wr.x * q - wr.y * p;
            qy[j] += wacc.x * p + wacc.y * q + wacc.z * r;
        }
    }
    if n == 0 {
        return;
    }
    accumulate_modal_mass_3d(wk, n, &ws.ax, &mut ws.yy);
}

/// Add one cloud point's `w (A X̂_k)ᵀ (A X̂_k)` to the n × n row-major `yy` (n > 0), from the
/// three global rows of `A X̂_k` at 0, n, 2n in `ax`.
#[inline(always)]
pub(crate) fn accumulate_modal_mass_3d(wk: f64, n: usize, ax: &[f64], yy: &mut [f64]) {
    let (ax0, ax1, ax2) = (&ax[..n], &ax[n..2 * n], &ax[2 * n..3 * n]);
    for (i, row) in yy.chunks_exact_mut(n).enumerate() {
        let (p0, p1, p2) = (wk * ax0[i], wk * ax1[i], wk * ax2[i]);
        for (((o, b0), b1), b2) in row.iter_mut().zip(ax0).zip(ax1).zip(ax2) {
            *o += p0 * b0 + p1 * b1 + p2 * b2;
        }
    }
}

/// Add one cloud point's `w (A X̂_k)ᵀ (A X̂_k)` to the upper triangle of the n × n row-major
/// `yy`, from the two in-plane rows of `A X̂_k` at 0, n in `ax`.
#[inline(always)]
pub(crate) fn accumulate_modal_mass_2d(wk: f64, n: usize, ax: &[f64], yy: &mut [f64]) {
    let (ax0, ax1) = (&ax[..n], &ax[n..2 * n]);
    for i in 0..n {
        let (p0, p1) = (wk * ax0[i], wk * ax1[i]);
        let row = &mut yy[i * n + i..(i + 1) * n];
        let (b0, b1) = (&ax0[i..], &ax1[i..]);
        for j in 0..row.len() {
            row[j] += p0 * b0[j] + p1 * b1[j];
        }
    }
}
