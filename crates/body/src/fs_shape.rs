//! Foreshortening, FS0, by shape integrals (docs/methods.md §6.3 kinematics; §2.3–§2.5 assembly):
//! the FS0 inertia terms without a loop over the mass cloud.
//!
//! **Kinematics** (§6.3). Cloud point k: `p_k = r̄_uk + X_k y` (the linear position),
//! `φ_k = yᵀF_k y`, `f_k = F_k y`, `c_k = ẏᵀF_k ẏ`, and
//!
//! ```text
//! r̄_k = p_k − ½ φ_k e,     X̂_k = X_k − e f_kᵀ,     e = ē₁ (the beam axis, |e| = 1).
//! ```
//!
//! Every sum the B-matrix route forms (`Σ w B_kᵀB_k`, `Σ w B_kᵀḂ_k Z`, relative or natural set)
//! is a sum of the body-frame moments below, products of `1, r̄_k, X̂_k` and `c_k`. Expanding
//! `r̄_k` and `X̂_k` gives sums of `F_k`, `F_k ⊗ r̄_uk`, `F_k ⊗ X_k` and `F_k ⊗ F_k`, which are
//! precomputed once on the cloud (docs/methods.md §6.3 "Why B-projection" names them):
//!
//! ```text
//! 𝔽 = Σ w F_k,   𝔽ᵃ = Σ w r̄_uk,a F_k,   Tᵃ_{lji} = Σ w F_k,lj X_k,ai,   Q_{ijlm} = Σ w F_k,ij F_k,lm
//! ```
//!
//! (n², 3n², 3n³, n⁴ numbers; F_k is shared by the section points of a station). Per evaluation
//! these are contracted with y and ẏ, in O(n⁴) and independent of the cloud:
//!
//! ```text
//! Kᵃ_ij = Σ_l y_l Tᵃ_{lji} = Σ w X_k,ai f_k,j        Kᵈᵃ_ij = Σ_l ẏ_l Tᵃ_{lji}
//! Kᵃ y = Σ w φ_k X_k,aᵀ,   Kᵃᵀ y = Σ w (X_k,a y) f_k,   zᵃ = Kᵈᵃ ẏ = Σ w c_k X_k,aᵀ
//! R = Σ_lm Q_{ijlm} y_l y_m = Σ w φ_k F_k,   N_ij = Σ_lm Q_{iljm} y_l y_m = Σ w f_k f_kᵀ,
//! R y = Σ w φ_k f_k,   yᵀR y = Σ w φ_k²,   ẏᵀR ẏ = Σ w c_k φ_k,   (Σ_lm Q_{lmij} ẏ_l ẏ_m) y = Σ w c_k f_k.
//! ```
//!
//! **The moments** (body components; the linear ones of §2.3 carry no hat):
//!
//! ```text
//! m̄ = m̄_u + S y − ½ (yᵀ𝔽y) e
//! P = P_lin(y) − ½ (e qᵀ + q eᵀ) + ¼ (yᵀR y) e eᵀ,   q_a = Σ w φ_k p_k,a = yᵀ𝔽ᵃy + yᵀKᵃy
//! Ŝ = Σ w X̂_k:          row a  S_a − e_a (𝔽y)ᵀ
//! L̂_b = Σ w r̄_k,b X̂_k:  row a  (L_b)_a − e_a (𝔽ᵇy + Kᵇᵀy)ᵀ − ½ e_b (Kᵃy)ᵀ + ½ e_a e_b (R y)ᵀ
//! Ŝᵃᵇ = Σ w X̂_k,aᵀX̂_k,b = Sᵃᵇ − e_b Kᵃ − e_a Kᵇᵀ + e_a e_b N
//!   so Σ_ab C_ab Ŝᵃᵇ = Σ_ab C_ab Sᵃᵇ − K_{Ce} − K_{Cᵀe}ᵀ + (eᵀCe) N,  K_h = Σ_a h_a Kᵃ
//! c₀ = Σ w c_k = ẏᵀ𝔽ẏ,   c₁ = Σ w c_k r̄_k:  c₁,a = ẏᵀ𝔽ᵃẏ + zᵃ·y − ½ e_a ẏᵀR ẏ
//! Σ w c_k X̂_kᵀ g = Σ_a g_a zᵃ − (e·g) Σ w c_k f_k
//! ```
//!
//! **Relative set** (body-frame origin form of §2.4 step 1, with the velocity-product term
//! `−e c_k` of §6.3 in each point's acceleration; steps 2–3 as in `shape.rs`):
//!
//! ```text
//! M̄_body = [m I, −m̄~, Ŝ; m̄~, Ī_O, Ĉ; Ŝᵀ, Ĉᵀ, M̂_yy],   Ī_O = tr(P) I − P,  Ĉ_a = Σ ε_abc (L̂_b)_c,
//! M̂_yy = Σ_a Ŝᵃᵃ = M_yy − K_e − K_eᵀ + N,
//! Q̄_v,body = −{ ω̄~ω̄~m̄ + 2 ω̄~Ŝẏ − e c₀;
//!               ω̄~Ī_O ω̄ + 2 Ŵẏ − c₁ × e;
//!               Σ_ab (ω̃ω̃)_ab (L̂_b)_aᵀ + 2 Ĝẏ − Σ_a e_a zᵃ + Σ w c_k f_k },
//! Ŵẏ = ω̄ (ĥ·ẏ) − Σ_b ω̄_b L̂_b ẏ,   Ĝẏ = Σ_ab ω̃_ab Ŝᵃᵇ ẏ = G(ω̄) ẏ − K_{ω̄×e} ẏ + K_{ω̄×e}ᵀ ẏ.
//! ```
//!
//! A planar body runs the same 3D algebra and keeps the x, y, θz rows and columns.
//!
//! **Natural set** (§2.5 with X̂, r̄ and `Ḃ_k q̇ = 2 Ȧ X̂_k ẏ − A e c_k`):
//!
//! ```text
//! 3D: M_r0ea = m̄_a I, M_eaeb = P_ab I, M_r0y = A Ŝ, M_eby = A L̂_b, M_yy = Σ_ab (e_a·e_b) Ŝᵃᵇ,
//!     Q_v = { −2 Ȧ Ŝ ẏ + A e c₀;  −2 Ȧ L̂_b ẏ + A e c₁,b;
//!             −2 Σ_ab (e_a·ė_b) Ŝᵃᵇ ẏ + Σ w c_k X̂_kᵀ (AᵀA e) }
//! 2D: M_r0u = m̄_1 I + m̄_2 E, M_uu = (P_11 + P_22) I, M_uy = A L̂_1 − E A L̂_2,
//!     M_yy = |u|² Σ_a Ŝᵃᵃ,  Q_v = { −2 Ȧ Ŝ ẏ + A e c₀;
//!     −2 (Ȧ L̂_1 − E Ȧ L̂_2) ẏ + (c₁,1 I − c₁,2 E) A e;
//!     −2 Σ_ab (AᵀȦ)_ab Ŝᵃᵇ ẏ + |u|² Σ w c_k X̂_kᵀ e }
//! ```
//!
//! The two routes sum the same cloud (§2.7), so they agree to round-off
//! (`tests/fs0_routes.rs`). Cost per evaluation, n modes: ≈ n⁴/2 + 6n³ + 20n² multiply-adds
//! for the FS0 contractions (V = Q·y on i ≤ j only, F being symmetric), plus the linear §2.3
//! terms; nothing depends on the cloud size. The contractions run with n as a compile-time
//! constant for n = 4 and n = 8 (the spin-up beams), generic loops otherwise.
//!
//! This module computes the hatted moments ([`ShapeMoments`] with their axial terms, and the
//! planar rows of the natural set) and the FS0 parts of the modal block. The kernels that read
//! them are the linear ones of `shape.rs` and `natural.rs`, which branch only where FS0 adds a
//! term, so each formula above that FS0 shares with §2.3–§2.5 is written once.

use crate::foreshortening::{Foreshortening, mat_vec};
use crate::natural::PlanarMoments;
use crate::shape::{AxialMoments, ShapeMoments};
use crate::{FlexibleBody, Workspace, dot};
use flexmbd_core::Dim;
use nalgebra::{Matrix3, Vector2, Vector3};

/// The precomputed FS0 shape integrals of one body (see the module doc).
#[derive(Clone, Debug, Default)]
pub(crate) struct FsIntegrals {
    /// 𝔽ᵃ = Σ w r̄_uk,a F_k, a-major, n² each.
    fa: Vec<f64>,
    /// Tᵃ_{lji} = Σ w F_k,lj X_k,ai, index ((a n + l) n + j) n + i.
    t: Vec<f64>,
    /// Whether Tᵃ has a non-zero entry (a planar centre-line cloud has T¹ = T³ = 0).
    t_live: [bool; 3],
    /// Whether 𝔽ᵃ has a non-zero entry.
    fa_live: [bool; 3],
    /// Q_{ijlm} = Σ w F_k,ij F_k,lm, index ((i n + j) n + l) n + m.
    q: Vec<f64>,
}

impl FsIntegrals {
    /// From the distinct station F's (`cloud`, n² each), the station of every cloud point,
    /// and the cloud's weights, positions and mode rows (3n per point, row-major).
    pub(crate) fn new(
        n: usize,
        cloud: &[f64],
        station: &[usize],
        weights: &[f64],
        positions: &[Vector3<f64>],
        rows: &[f64],
    ) -> Self {
        let n2 = n * n;
        let n_st = cloud.len() / n2.max(1);
        // Station sums: W_s = Σ w, Σ w r̄_u, Σ w X_a.
        let mut ws = vec![0.0; n_st];
        let mut wp = vec![Vector3::zeros(); n_st];
        let mut wx = vec![0.0; n_st * 3 * n];
        for (k, &s) in station.iter().enumerate() {
            if n2 == 0 {
                break;
            }
            let w = weights[k];
            ws[s] += w;
            wp[s] += w * positions[k];
            for (o, x) in wx[s * 3 * n..(s + 1) * 3 * n]
                .iter_mut()
                .zip(&rows[k * 3 * n..(k + 1) * 3 * n])
            {
                *o += w * x;
            }
        }
        let mut fa = vec![0.0; 3 * n2];
        let mut t = vec![0.0; 3 * n * n2];
        let mut q = vec![0.0; n2 * n2];
        for s in 0..n_st {
            let f = &cloud[s * n2..(s + 1) * n2];
            for a in 0..3 {
                let p = wp[s][a];
                for (o, fv) in fa[a * n2..(a + 1) * n2].iter_mut().zip(f) {
                    *o += p * fv;
                }
                let xa = &wx[(s * 3 + a) * n..(s * 3 + a + 1) * n];
                for (lj, fv) in f.iter().enumerate() {
                    let dst = &mut t[(a * n2 + lj) * n..(a * n2 + lj + 1) * n];
                    for (o, x) in dst.iter_mut().zip(xa) {
                        *o += fv * x;
                    }
                }
            }
            let w = ws[s];
            for (ij, fij) in f.iter().enumerate() {
                let c = w * fij;
                for (o, flm) in q[ij * n2..(ij + 1) * n2].iter_mut().zip(f) {
                    *o += c * flm;
                }
            }
        }
        let t_live = [0, 1, 2].map(|a| t[a * n * n2..(a + 1) * n * n2].iter().any(|v| *v != 0.0));
        let fa_live = [0, 1, 2].map(|a| fa[a * n2..(a + 1) * n2].iter().any(|v| *v != 0.0));
        Self {
            fa,
            t,
            t_live,
            fa_live,
            q,
        }
    }
}

/// Scratch of the FS0 shape-integral route (in [`Workspace`]), sized for n modes.
#[derive(Clone, Debug, Default)]
pub(crate) struct FsScratch {
    /// 𝔽 y (n), 𝔽 ẏ (n).
    fy: Vec<f64>,
    fyd: Vec<f64>,
    /// 𝔽ᵃ y (3n).
    fay: Vec<f64>,
    /// Kᵃ as Kt[a][j][i] = Kᵃ_ij (3n²), and Kᵈᵃ likewise.
    kt: Vec<f64>,
    kd: Vec<f64>,
    /// V_{ijl} = Σ_m Q_{ijlm} y_m (n³).
    v: Vec<f64>,
    /// R, N (n² each).
    r: Vec<f64>,
    nm: Vec<f64>,
    /// Kᵃ y, Kᵃᵀ y, zᵃ (3n each).
    ky: Vec<f64>,
    kty: Vec<f64>,
    z: Vec<f64>,
    /// R y, Σ w c_k f_k, and an n-vector scratch.
    ry: Vec<f64>,
    cf: Vec<f64>,
    tmp: Vec<f64>,
    /// M̂_yy of the natural set (n²).
    pub(crate) modal_mass: Vec<f64>,
    /// Sized for a foreshortened body.
    live: bool,
}

impl FsScratch {
    /// True for the placeholder of a body without FS0 data.
    pub(crate) fn is_empty(&self) -> bool {
        !self.live
    }

    pub(crate) fn new(n: usize) -> Self {
        Self {
            fy: vec![0.0; n],
            fyd: vec![0.0; n],
            fay: vec![0.0; 3 * n],
            kt: vec![0.0; 3 * n * n],
            kd: vec![0.0; 3 * n * n],
            v: vec![0.0; n * n * n],
            r: vec![0.0; n * n],
            nm: vec![0.0; n * n],
            ky: vec![0.0; 3 * n],
            kty: vec![0.0; 3 * n],
            z: vec![0.0; 3 * n],
            ry: vec![0.0; n],
            cf: vec![0.0; n],
            tmp: vec![0.0; n],
            modal_mass: vec![0.0; n * n],
            live: true,
        }
    }

    /// 𝔽 and 𝔽ᵃ contracted (zero 𝔽ᵃ skipped: a centre-line cloud has 𝔽² = 𝔽³ = 0): leaves 𝔽y,
    /// 𝔽ẏ, 𝔽ᵃy here and returns `yᵀ𝔽y`, `c₀ = ẏᵀ𝔽ẏ`, `yᵀ𝔽ᵃy` and `ẏᵀ𝔽ᵃẏ`.
    #[inline(always)]
    fn contract_f<const N: usize>(
        &mut self,
        fs: &Foreshortening,
        y: &[f64],
        yd: &[f64],
    ) -> (f64, f64, Vector3<f64>, Vector3<f64>) {
        let n = if N == 0 { y.len() } else { N };
        let n2 = n * n;
        let ints = &fs.ints;
        mat_vec(&fs.wf, y, &mut self.fy);
        mat_vec(&fs.wf, yd, &mut self.fyd);
        let phibar = dot(y, &self.fy);
        let c0 = dot(yd, &self.fyd);
        let mut q = Vector3::zeros();
        let mut c1 = Vector3::zeros();
        for a in 0..3 {
            let fay = &mut self.fay[a * n..(a + 1) * n];
            if !ints.fa_live[a] {
                fay.fill(0.0);
                continue;
            }
            let fa = &ints.fa[a * n2..(a + 1) * n2];
            mat_vec(fa, y, fay);
            q[a] = dot(y, fay);
            mat_vec(fa, yd, &mut self.tmp);
            c1[a] = dot(yd, &self.tmp);
        }
        (phibar, c0, q, c1)
    }

    /// Tᵃ contracted: Kᵃ, Kᵈᵃ, Kᵃ y, Kᵃᵀ y, zᵃ here; adds `yᵀKᵃy` to `q` and `zᵃ·y` to `c1`.
    #[inline(always)]
    fn contract_t<const N: usize>(
        &mut self,
        ints: &FsIntegrals,
        y: &[f64],
        yd: &[f64],
        q: &mut Vector3<f64>,
        c1: &mut Vector3<f64>,
    ) {
        let n = if N == 0 { y.len() } else { N };
        let n2 = n * n;
        for a in 0..3 {
            let (kt, kd) = (
                &mut self.kt[a * n2..(a + 1) * n2],
                &mut self.kd[a * n2..(a + 1) * n2],
            );
            let (ky, kty, z) = (
                &mut self.ky[a * n..(a + 1) * n],
                &mut self.kty[a * n..(a + 1) * n],
                &mut self.z[a * n..(a + 1) * n],
            );
            kt.fill(0.0);
            kd.fill(0.0);
            ky.fill(0.0);
            z.fill(0.0);
            if !ints.t_live[a] {
                kty.fill(0.0);
                continue;
            }
            let ta = &ints.t[a * n * n2..(a + 1) * n * n2];
            for (lidx, blk) in ta.chunks_exact(n2).enumerate() {
                let (yl, ydl) = (y[lidx], yd[lidx]);
                let (kt, kd, blk) = (&mut kt[..n2], &mut kd[..n2], &blk[..n2]);
                for q in 0..n2 {
                    kt[q] += yl * blk[q];
                    kd[q] += ydl * blk[q];
                }
            }
            // kt[j][i] = Kᵃ_ij: (Kᵃ y)_i = Σ_j kt[j][i] y_j, (Kᵃᵀ y)_j = kt[j]·y.
            for j in 0..n {
                let (row, rowd) = (&kt[j * n..(j + 1) * n], &kd[j * n..(j + 1) * n]);
                kty[j] = dot(row, y);
                let (yj, ydj) = (y[j], yd[j]);
                for i in 0..n {
                    ky[i] += yj * row[i];
                    z[i] += ydj * rowd[i];
                }
            }
            q[a] += dot(y, ky);
            c1[a] += dot(y, z);
        }
    }

    /// Q contracted: V, R, N and Σ w c_k f_k here; returns `yᵀR y` and `ẏᵀR ẏ`.
    #[inline(always)]
    fn contract_q<const N: usize>(
        &mut self,
        ints: &FsIntegrals,
        y: &[f64],
        yd: &[f64],
    ) -> (f64, f64) {
        let n = if N == 0 { y.len() } else { N };
        let n2 = n * n;
        let n3 = n2 * n;
        // V_{ijl} = V_{jil} (F_k symmetric): form i ≤ j, copy the other half.
        for i in 0..n {
            for j in i..n {
                let ij = (i * n + j) * n;
                for lidx in 0..n {
                    let o = ij + lidx;
                    self.v[o] = dot(&ints.q[o * n..(o + 1) * n], y);
                }
                if j > i {
                    let ji = (j * n + i) * n;
                    self.v.copy_within(ij..ij + n, ji);
                }
            }
        }
        for ij in 0..n2 {
            self.r[ij] = dot(&self.v[ij * n..(ij + 1) * n], y);
        }
        self.nm.fill(0.0);
        self.cf.fill(0.0);
        for i in 0..n {
            for (lidx, &yl) in y.iter().enumerate() {
                // N_ij += V[i][l][j] y_l
                let src = &self.v[(i * n + lidx) * n..(i * n + lidx + 1) * n];
                let dst = &mut self.nm[i * n..(i + 1) * n];
                for (o, vv) in dst.iter_mut().zip(src) {
                    *o += yl * vv;
                }
            }
        }
        for (lidx, &ydl) in yd.iter().enumerate() {
            for (m, &ydm) in yd.iter().enumerate() {
                // Σ w c f: cf_i += V[l][m][i] ẏ_l ẏ_m
                let c = ydl * ydm;
                let lm = lidx * n + m;
                for (o, vv) in self.cf.iter_mut().zip(&self.v[lm * n..(lm + 1) * n]) {
                    *o += c * vv;
                }
            }
        }
        debug_assert_eq!(self.v.len(), n3);
        mat_vec(&self.r, y, &mut self.ry);
        let psi = dot(y, &self.ry);
        mat_vec(&self.r, yd, &mut self.tmp);
        let cphi = dot(yd, &self.tmp);

        (psi, cphi)
    }

    /// The hatted rows: Ŝ (rows a at a n) into `sy` from S, and the FS0 part of L̂ added to
    /// `l` ((L̂_b)_a at (3b + a) n), along the axis `e`.
    #[inline(always)]
    fn hat_rows<const N: usize>(&self, e: &Vector3<f64>, s: &[f64], sy: &mut [f64], l: &mut [f64]) {
        let n = if N == 0 { self.fy.len() } else { N };
        for a in 0..3 {
            for j in 0..n {
                sy[a * n + j] = s[a * n + j] - e[a] * self.fy[j];
            }
        }
        for b in 0..3 {
            for a in 0..3 {
                let (ea, eb) = (e[a], e[b]);
                if ea == 0.0 && eb == 0.0 {
                    continue;
                }
                let dst = &mut l[(3 * b + a) * n..(3 * b + a + 1) * n];
                for j in 0..n {
                    dst[j] += -ea * (self.fay[b * n + j] + self.kty[b * n + j])
                        - 0.5 * eb * self.ky[a * n + j]
                        + 0.5 * ea * eb * self.ry[j];
                }
            }
        }
    }
}

impl FlexibleBody {
    /// The FS0 moments (module doc): returns m̄, P, c₀, c₁ and leaves Ŝ (rows a at a n) in
    /// `ws.sy`, L̂ ((L̂_b)_a at (3b + a) n) in `ws.l`, and Kᵃ, N, zᵃ, Σ w c_k f_k in `ws.fs`.
    pub(crate) fn fs_moments(&self, y: &[f64], yd: &[f64], ws: &mut Workspace) -> ShapeMoments {
        // The loops run over rows of n entries; with n a compile-time constant for the common
        // mode counts the compiler unrolls them and drops the bounds checks.
        match self.n {
            4 => self.fs_moments_n::<4>(y, yd, ws),
            8 => self.fs_moments_n::<8>(y, yd, ws),
            _ => self.fs_moments_n::<0>(y, yd, ws),
        }
    }

    /// [`fs_moments`](Self::fs_moments) for `N = n` modes (`N = 0`: any n).
    fn fs_moments_n<const N: usize>(
        &self,
        y: &[f64],
        yd: &[f64],
        ws: &mut Workspace,
    ) -> ShapeMoments {
        let n = if N == 0 { self.n } else { N };
        debug_assert_eq!(n, self.n);
        let (y, yd) = (&y[..n], &yd[..n]);
        let fs = self.fs.as_ref().expect("fs_moments without FS0 data");
        let e = fs.axis;
        let Workspace {
            u, l, sy, fs: sc, ..
        } = ws;
        // Linear part (§2.3): u^{ab} = Sᵃᵇ y, (L_b)_a = Sᵇ_a + u^{ab}, m̄, P. A planar body
        // has no z rows: only a, b < 2 are formed, the z entries of L are zero.
        let na = if self.dim == Dim::Planar { 2 } else { 3 };
        let (mb, p) = self.linear_moments::<N>(y, na, u, l);
        let (phibar, c0, mut q, mut c1) = sc.contract_f::<N>(fs, y, yd);
        sc.contract_t::<N>(&fs.ints, y, yd, &mut q, &mut c1);
        let (psi, cphi) = sc.contract_q::<N>(&fs.ints, y, yd);

        // Moments.
        let mbh = mb - e * (0.5 * phibar);
        let ph =
            p - 0.5 * (e * q.transpose() + q * e.transpose()) + (0.25 * psi) * (e * e.transpose());
        let c1 = c1 - e * (0.5 * cphi);
        sc.hat_rows::<N>(&e, &self.s, sy, l);
        ShapeMoments {
            mb: mbh,
            p: ph,
            axial: Some(AxialMoments { axis: e, c0, c1 }),
        }
    }

    /// `out[i][j] = base[i][j] − (K_g + K_gᵀ)_ij + s N_ij` with `K_g = Σ_a g_a Kᵃ`
    /// (i.e. Σ_ab C_ab Ŝᵃᵇ for a symmetric C, g = C e, s = eᵀC e; upper triangle mirrored).
    pub(crate) fn fs_yy(
        &self,
        ws: &Workspace,
        g: &Vector3<f64>,
        s: f64,
        base: &[f64],
        out: &mut [f64],
    ) {
        let n = self.n;
        let n2 = n * n;
        let sc = &ws.fs;
        let live = self.fs.as_ref().map_or([false; 3], |f| f.ints.t_live);
        for i in 0..n {
            for j in i..n {
                let mut kg = 0.0;
                for a in 0..3 {
                    if g[a] == 0.0 || !live[a] {
                        continue;
                    }
                    let kt = &sc.kt[a * n2..(a + 1) * n2];
                    kg += g[a] * (kt[j * n + i] + kt[i * n + j]);
                }
                let v = base[i * n + j] - kg + s * sc.nm[i * n + j];
                out[i * n + j] = v;
                out[j * n + i] = v;
            }
        }
    }

    /// `out += −K_h x − K_kᵀ x + s N x` (the FS0 part of Σ_ab D_ab Ŝᵃᵇ x with h = D e,
    /// k = Dᵀe, s = eᵀD e).
    fn fs_sab_vec(
        &self,
        ws: &Workspace,
        h: &Vector3<f64>,
        k: &Vector3<f64>,
        s: f64,
        x: &[f64],
        out: &mut [f64],
    ) {
        let n = self.n;
        let n2 = n * n;
        let sc = &ws.fs;
        let live = self.fs.as_ref().map_or([false; 3], |f| f.ints.t_live);
        for a in 0..3 {
            if h[a] == 0.0 && k[a] == 0.0 || !live[a] {
                continue;
            }
            let kt = &sc.kt[a * n2..(a + 1) * n2];
            for j in 0..n {
                let row = &kt[j * n..(j + 1) * n];
                // (Kᵃ x)_i = Σ_j kt[j][i] x_j ; (Kᵃᵀ x)_j = kt[j]·x.
                let xj = h[a] * x[j];
                for i in 0..n {
                    out[i] -= xj * row[i];
                }
                out[j] -= k[a] * dot(row, x);
            }
        }
        if s != 0.0 {
            for (i, o) in out.iter_mut().enumerate() {
                *o += s * dot(&sc.nm[i * n..(i + 1) * n], x);
            }
        }
    }

    /// `Σ w c_k X̂_kᵀ g = Σ_a g_a zᵃ − (e·g) Σ w c_k f_k`, added to `out`.
    pub(crate) fn fs_add_c_term(&self, ws: &Workspace, g: &Vector3<f64>, out: &mut [f64]) {
        let n = self.n;
        let e = self.fs.as_ref().map_or(Vector3::zeros(), |f| f.axis);
        let sc = &ws.fs;
        let eg = e.dot(g);
        for (j, o) in out.iter_mut().enumerate() {
            *o += g.x * sc.z[j] + g.y * sc.z[n + j] + g.z * sc.z[2 * n + j] - eg * sc.cf[j];
        }
    }

    /// `G̑ ẏ = Σ_ab ω̃_ab Ŝᵃᵇ ẏ = G(ω̄) ẏ − K_{ω̄×e} ẏ + K_{ω̄×e}ᵀ ẏ` into `out` (n; a planar body:
    /// G_3 only).
    pub(crate) fn fs_gyroscopic(
        &self,
        wb: &Vector3<f64>,
        e: &Vector3<f64>,
        yd: &[f64],
        ws: &Workspace,
        out: &mut [f64],
    ) {
        let n = self.n;
        out.fill(0.0);
        for c in 0..3 {
            if wb[c] == 0.0 {
                continue;
            }
            let gc = &self.g[c * n * n..(c + 1) * n * n];
            for (o, row) in out.iter_mut().zip(gc.chunks_exact(n)) {
                *o += wb[c] * dot(row, yd);
            }
        }
        let h = wb.cross(e);
        self.fs_sab_vec(ws, &h, &(-h), 0.0, yd, out);
    }

    /// Σ_ab D_ab Sᵃᵇ x (the linear part), skipping zero D entries, into `out`.
    fn sab_vec(&self, d: &Matrix3<f64>, x: &[f64], out: &mut [f64]) {
        let n = self.n;
        out.fill(0.0);
        for a in 0..3 {
            for b in 0..3 {
                let c = d[(a, b)];
                if c == 0.0 {
                    continue;
                }
                let blk = &self.sab[(3 * a + b) * n * n..(3 * a + b + 1) * n * n];
                for (o, row) in out.iter_mut().zip(blk.chunks_exact(n)) {
                    *o += c * dot(row, x);
                }
            }
        }
    }

    /// The modal terms of the spatial natural set for FS0 (module doc), `M_yy = Σ_ab (e_a·e_b)
    /// Ŝᵃᵇ` into `ws.fs.modal_mass` and `Q_y = −2 Σ_ab (e_a·ė_b) Ŝᵃᵇ ẏ + Σ w c_k X̂_kᵀ (AᵀA e)` into
    /// `ws.qy`, from `gram = AᵀA` and `cdot = AᵀȦ`.
    pub(crate) fn natural_modal_terms_fs_3d(
        &self,
        yd: &[f64],
        gram: &Matrix3<f64>,
        cdot: &Matrix3<f64>,
        ws: &mut Workspace,
    ) {
        let n = self.n;
        let e = self
            .fs
            .as_ref()
            .expect("FS0 modal terms without FS0 data")
            .axis;
        // M_yy = Σ gram_ab Ŝᵃᵇ: linear part into ws.yy, then FS0 terms.
        let mut base = std::mem::take(&mut ws.yy);
        for i in 0..n {
            for j in i..n {
                let v = self.gram_modal_mass(gram, i, j);
                base[i * n + j] = v;
                base[j * n + i] = v;
            }
        }
        let g = gram * e;
        let mut yy = std::mem::take(&mut ws.fs.modal_mass);
        self.fs_yy(ws, &g, e.dot(&g), &base, &mut yy);
        // Q_y = −2 Σ cdot_ab Ŝᵃᵇ ẏ + Σ w c X̂ᵀ (gram e).
        let mut qy = std::mem::take(&mut ws.qy);
        self.sab_vec(cdot, yd, &mut qy);
        let (h, k) = (cdot * e, cdot.transpose() * e);
        self.fs_sab_vec(ws, &h, &k, e.dot(&h), yd, &mut qy);
        for v in qy.iter_mut() {
            *v *= -2.0;
        }
        self.fs_add_c_term(ws, &g, &mut qy);
        ws.fs.modal_mass = yy;
        ws.yy = base;
        ws.qy = qy;
    }

    /// The planar natural-set moments of an FS0 body (the 3D algebra's planar rows; Ŝ in
    /// `ws.sy`, L̂ at (3b + a) n in `ws.l`).
    pub(crate) fn planar_fs_moments(
        &self,
        y: &[f64],
        yd: &[f64],
        ws: &mut Workspace,
    ) -> PlanarMoments {
        let n = self.n;
        let mo = self.fs_moments(y, yd, ws);
        let lb = |b: usize, c: usize| &ws.l[(3 * b + c) * n..(3 * b + c + 1) * n];
        PlanarMoments {
            mb: mo.mb.xy(),
            trace: mo.p[(0, 0)] + mo.p[(1, 1)],
            s_yd: Vector2::new(dot(&ws.sy[..n], yd), dot(&ws.sy[n..2 * n], yd)),
            l1_yd: Vector2::new(dot(lb(0, 0), yd), dot(lb(0, 1), yd)),
            l2_yd: Vector2::new(dot(lb(1, 0), yd), dot(lb(1, 1), yd)),
            l2_row: 3,
            axial: mo.axial,
        }
    }

    /// The modal terms of the planar natural set for FS0 (module doc): `Σ_a Ŝᵃᵃ` into `ws.yy`
    /// (the caller scales it by |u|²) and `Q_y = −2 Σ_ab (AᵀȦ)_ab Ŝᵃᵇ ẏ + |u|² Σ w c_k X̂_kᵀ e`
    /// into `ws.qy`.
    pub(crate) fn natural_modal_terms_fs_2d(
        &self,
        u: &Vector2<f64>,
        ud: &Vector2<f64>,
        yd: &[f64],
        ws: &mut Workspace,
    ) {
        let e3 = self
            .fs
            .as_ref()
            .expect("FS0 modal terms without FS0 data")
            .axis;
        let rot = |v: Vector2<f64>| Vector2::new(-v.y, v.x);
        let uu = u.norm_squared();
        let mut yy = std::mem::take(&mut ws.yy);
        self.fs_yy(ws, &e3, 1.0, &self.m_yy, &mut yy);
        ws.yy = yy;
        // (AᵀȦ) in 3D indices: [[u·u̇, u·E u̇, 0], [−u·E u̇, u·u̇, 0], [0, 0, 0]].
        let (c11, c12) = (u.dot(ud), u.dot(&rot(*ud)));
        let d = Matrix3::new(c11, c12, 0.0, -c12, c11, 0.0, 0.0, 0.0, 0.0);
        let mut qy = std::mem::take(&mut ws.qy);
        self.sab_vec(&d, yd, &mut qy);
        let (h, k) = (d * e3, d.transpose() * e3);
        self.fs_sab_vec(ws, &h, &k, e3.dot(&h), yd, &mut qy);
        for v in qy.iter_mut() {
            *v *= -2.0;
        }
        self.fs_add_c_term(ws, &(e3 * uu), &mut qy);
        ws.qy = qy;
    }
}
