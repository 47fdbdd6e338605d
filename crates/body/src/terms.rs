//! Inertia terms kept by their weight (issue 31): route (b) of the relative set with the
//! kinetic energy truncated, docs/design.md "Inertia terms as a model choice".
//!
//! Terms are dropped from the kinetic energy, never from the kernels' outputs, so that M̄ and
//! Q̄_v still derive from one T and a conservative system still conserves T + V. In body
//! components, with v̄0 = Aᵀṙ0 and ω̄ = Aᵀω (docs/methods.md §2.3–§2.4),
//!
//! ```text
//! T = ½ m v̄0² + v̄0·(ω̄ × m̄(y)) + ½ ω̄ᵀ Ī(y) ω̄ + ½ ẏᵀ M_yy ẏ + [coupling] (v̄0·S ẏ + ω̄ᵀ C(y) ẏ)
//! ```
//!
//! and `order` truncates the invariants in y: m̄ = m̄_u + [k≥1] S y, `P = P̄_u + [k≥1] (Sᵃ_b +
//! Sᵇ_a)·y + [k≥2] yᵀSᵃᵇy` (Ī = tr(P) I − P), `C = C(Sᵃ) + [k≥1] C(Sᵃᵇ y)`. Order 1 drops the
//! quadratic invariant of Ī only, the choice commercial codes call "partial coupling" (MSC
//! Adams/Flex leaves out its invariant 9, the ∫ XᵀX-type term). The equations of motion of a body in its
//! frame's quasi-velocities (Euler–Poincaré / Boltzmann–Hamel: `d/dt ∂T/∂v̄0 + ω̄ × ∂T/∂v̄0`,
//! `d/dt ∂T/∂ω̄ + ω̄ × ∂T/∂ω̄ + v̄0 × ∂T/∂v̄0`, `d/dt ∂T/∂ẏ − ∂T/∂y`) give, besides M̄ ż,
//!
//! ```text
//! Q̄_t = −ω̄ × (ω̄ × m̄) − ω̄ × ([c] S ẏ + ṁ̄) − m ā
//! Q̄_r = −ω̄ × Ī ω̄ − İ ω̄ − [c] ω̄ × C ẏ − ([k≥1] − [c]) (S ẏ × v̄0) − m̄ × ā
//! Q̄_y = −[k≥1] Sᵀ ā − Σ_ab (ω̃ω̃)_ab (Lᴵ_b)_a − [c][k≥1][velocity] 2 G(ω̄) ẏ
//! ```
//!
//! with ā = ω̄ × v̄0 (the s-form shift of §2.4 step 3), ṁ̄ = [k≥1] S ẏ, and `Lᴵ_b = ½ ∂Ī/∂y`'s
//! rows: none at order 0, Sᵇ at order 1, Sᵇ + Sᵇᵃ y at order 2. With every term kept these are
//! the formulas of §2.4 (İ ω̄ + ω̄ × C ẏ = 2 W ẏ, and `Ċ ẏ = ∫ Xẏ × Xẏ = 0`).
//! `velocity: false` drops the modal gyroscopic force −2 G(ω̄) ẏ: G is skew, so it does no
//! work (ẏᵀ G ẏ = 0) and T + V is still conserved; the other ẏ-dependent terms come with M̄'s
//! dependence on y and cannot be dropped alone without breaking conservation.
//!
//! Positive definiteness: order 0 gives the Gram matrix of the undeformed body (positive
//! definite whenever the full M̄ at y = 0 is), `coupling: false` a block-diagonal M̄ of two
//! Gram matrices; order 1 subtracts the positive semidefinite `Ī₂(y) = ∫ (Xy)ᵀ(Xy) I − (Xy)(Xy)ᵀ`
//! from the ω block, which keeps M̄ positive definite only while the deformation is small
//! against the body: the formulations fail the step by name when the factorisation fails.

use crate::blocks::RelativeSink;
use crate::shape::{body_frame_motion, c_rows, planar_frame_motion};
use crate::{BodyState, FlexibleBody, Workspace, dot};
use crate::{write_planar_coupling, write_planar_rigid};
use flexmbd_core::InvalidValue;
use nalgebra::{Dyn, Matrix, Matrix3, StorageMut, U1, Vector2, Vector3};
use serde::{Deserialize, Serialize};

/// Which inertia terms of a flexible body are kept (issue 31; module doc of `terms.rs`).
/// The default keeps every term and runs the full kernels unchanged.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InertiaTerms {
    /// Order in y of the kinetic energy's invariants m̄(y), Ī(y), C(y): 0 (the undeformed
    /// body's), 1 (linear: drops Ī's quadratic part), 2 (all).
    #[serde(default = "full_order")]
    pub order: u8,
    /// Keep the workless modal gyroscopic force −2 G(ω̄) ẏ.
    #[serde(default = "keep")]
    pub velocity: bool,
    /// Keep the rigid–elastic couplings v̄0·S ẏ + ω̄ᵀ C(y) ẏ of T (false: block-diagonal M̄).
    #[serde(default = "keep")]
    pub coupling: bool,
}

fn full_order() -> u8 {
    2
}
fn keep() -> bool {
    true
}

impl Default for InertiaTerms {
    fn default() -> Self {
        Self::FULL
    }
}

impl InertiaTerms {
    /// Every term kept.
    pub const FULL: Self = Self {
        order: 2,
        velocity: true,
        coupling: true,
    };

    /// Every term kept (the kernels of §2.4 unchanged).
    pub fn is_full(&self) -> bool {
        *self == Self::FULL
    }

    /// Every term but the workless modal gyroscopic force (`o2-nv`): the relative set's full
    /// kernels run it with that force switched off, cheaper than the truncated path there
    /// (bench `inertia_terms_*`); the natural set's truncated kernels are the cheaper ones.
    pub fn is_full_but_gyroscopic(&self) -> bool {
        *self
            == Self {
                velocity: false,
                ..Self::FULL
            }
    }

    /// Run by the relative set's full kernels: every term, or every term but the gyroscopic.
    pub(crate) fn is_full_or_o2_nv(&self) -> bool {
        self.is_full() || self.is_full_but_gyroscopic()
    }

    /// Refuse an order above 2, naming `field`.
    pub fn check(&self, field: &str) -> Result<(), InvalidValue> {
        if self.order > 2 {
            return Err(InvalidValue::new(
                format!("{field}.order"),
                self.order,
                "must be 0 (undeformed invariants), 1 (linear in y) or 2 (all)",
            ));
        }
        Ok(())
    }

    /// A short label, `full` or e.g. `o1`, `o2-nv`, `o0-nc` (order, `-nv` without the
    /// velocity term, `-nc` without the couplings); [`parse`](Self::parse) reads it back.
    pub fn label(&self) -> String {
        if self.is_full() {
            return "full".into();
        }
        let mut s = format!("o{}", self.order);
        if !self.velocity {
            s.push_str("-nv");
        }
        if !self.coupling {
            s.push_str("-nc");
        }
        s
    }

    /// Read a [`label`](Self::label); `None` for anything else.
    pub fn parse(s: &str) -> Option<Self> {
        if s == "full" {
            return Some(Self::FULL);
        }
        let mut parts = s.split('-');
        let order = parts.next()?.strip_prefix('o')?.parse::<u8>().ok()?;
        let mut t = Self {
            order,
            ..Self::FULL
        };
        for p in parts {
            match p {
                "nv" if t.velocity && t.coupling => t.velocity = false,
                "nc" if t.coupling => t.coupling = false,
                _ => return None,
            }
        }
        (order <= 2).then_some(t)
    }
}

impl std::fmt::Display for InertiaTerms {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.label())
    }
}

/// The `ω̃ω̃`-weighted sum `Σ_ab (ω̃ω̃)_ab (L_b)_a,j` of rows L ((L_b)_a at (3b + a) n).
#[inline(always)]
fn centrifugal(om: &Matrix3<f64>, l: &[f64], n: usize, j: usize) -> f64 {
    let mut t = 0.0;
    for c in 0..3 {
        for b in 0..3 {
            t += om[(c, b)] * l[(3 * b + c) * n + j];
        }
    }
    t
}

/// `lam[(b, c)] = (L_b)_c · ẏ` for rows L at (3b + c) n.
#[inline(always)]
pub(crate) fn rows_dot_9(l: &[f64], n: usize, yd: &[f64]) -> Matrix3<f64> {
    Matrix3::from_fn(|b, c| dot(&l[(3 * b + c) * n..(3 * b + c + 1) * n], yd))
}

impl FlexibleBody {
    /// m̄(y) and P(y) truncated at `order` (module doc): the undeformed body's at 0, `m̄_u + S y`
    /// and `P₁ = P̄_u + Sᵃ_b·y + Sᵇ_a·y` at 1, all at 2, where `u^{ab} = Sᵃᵇ y` (9 n²) and the
    /// full L rows `(L_b)_a = Sᵇ_a + u^{ab}` are left in `ws.u`, `ws.l` (order 2 only).
    #[inline(always)]
    pub(crate) fn truncated_moments(
        &self,
        y: &[f64],
        order: u8,
        ws: &mut Workspace,
    ) -> (Vector3<f64>, Matrix3<f64>) {
        let n = self.n;
        if n > 0 && order >= 2 {
            return self.linear_moments::<0>(y, 3, &mut ws.u, &mut ws.l);
        }
        let (mut mb, mut p) = (self.m_u, self.p_u);
        if order >= 1 && !self.first_moment_vanished() {
            for c in 0..3 {
                mb[c] += dot(&self.s[c * n..(c + 1) * n], y);
            }
        }
        if order == 1 && n > 0 {
            // P₁ = P̄ + Sᵃ_b·y + Sᵇ_a·y (sa: Sᵇ row a at (3b + a) n).
            for c in 0..3 {
                for b in c..3 {
                    let v = self.p_u[(c, b)]
                        + dot(&self.sa[(3 * c + b) * n..(3 * c + b + 1) * n], y)
                        + dot(&self.sa[(3 * b + c) * n..(3 * b + c + 1) * n], y);
                    p[(c, b)] = v;
                    p[(b, c)] = v;
                }
            }
        }
        (mb, p)
    }

    /// Route (b) of the spatial relative set with the kinetic energy truncated by `terms`
    /// (module doc). Skips the work of what is dropped: Sᵃᵇ y (9 n²) unless order 2 (order 1's
    /// couplings read `C(y) = C(Sᵃ) + [G_a y]`, 3 n²), G(ω̄) ẏ (3 n²) unless kept.
    pub(crate) fn shape_3d_terms<O: RelativeSink>(
        &self,
        st: &BodyState<'_>,
        terms: InertiaTerms,
        ws: &mut Workspace,
        out: &mut O,
    ) {
        let n = self.n;
        let (k, cpl) = (terms.order, terms.coupling);
        let (y, yd) = (st.y, st.y_dot);
        let (wb, ab) = body_frame_motion(st);
        let v0b = st.a.tr_mul(&st.r0_dot());
        // Sᵃᵇ y (9 n²) only at order 2; order 1's C(y) = C(Sᵃ) + [G_1 y; G_2 y; G_3 y] (3 n²).
        let need_u = n > 0 && k >= 2;
        let (mb, p) = self.truncated_moments(y, k, ws);
        let s_yd = if n > 0 && (k >= 1 || cpl) {
            self.first_moment_times(&self.s, yd)
        } else {
            Vector3::zeros()
        };
        let lam0 = if n > 0 && k == 1 {
            rows_dot_9(&self.sa, n, yd)
        } else {
            Matrix3::zeros()
        };
        let laml = if need_u {
            rows_dot_9(&ws.l, n, yd)
        } else {
            Matrix3::zeros()
        };
        let pdot = match k {
            0 => Matrix3::zeros(),
            1 => lam0 + lam0.transpose(),
            _ => laml + laml.transpose(),
        };
        let io = Matrix3::identity() * p.trace() - p;
        let io_dot = Matrix3::identity() * pdot.trace() - pdot;
        let mb_dot = if k >= 1 { s_yd } else { Vector3::zeros() };
        let s_kept = if cpl { s_yd } else { Vector3::zeros() };
        let qt = -wb.cross(&wb.cross(&mb)) - wb.cross(&(s_kept + mb_dot)) - self.mass * ab;
        let mut qr = -wb.cross(&(io * wb)) - io_dot * wb - mb.cross(&ab);
        // C(y) = C(Sᵃ) = 0 at order 0 when the skew part of Sᵃ vanished (`vanished.rs`).
        let c_vanished = k == 0 && self.vanished.skew_first_moments;
        if cpl && n > 0 && !c_vanished {
            // C(y) rows into ws.c, then C ẏ.
            c_rows(n, if k >= 2 { &ws.l } else { &self.sa }, &mut ws.c);
            if k == 1 {
                for (cj, row) in ws.c.iter_mut().zip(self.g.chunks_exact(n)) {
                    *cj += dot(row, y);
                }
            }
            qr -= wb.cross(&crate::shape::rows_dot_3(&ws.c, n, yd));
        }
        if (k >= 1) != cpl {
            let sign = if k >= 1 { 1.0 } else { -1.0 };
            qr -= sign * s_yd.cross(&v0b);
        }
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
        // Modal force: −[k≥1] Sᵀā − Σ (ω̃ω̃)_ab (Lᴵ_b)_a − [gyro] 2 G(ω̄) ẏ.
        let gyro = cpl && k >= 1 && terms.velocity;
        if gyro {
            for (row, g) in self.g.chunks_exact(n).zip(ws.gy.iter_mut()) {
                *g = dot(row, yd);
            }
        }
        let om = wb * wb.transpose() - Matrix3::identity() * wb.norm_squared();
        let li: Option<&[f64]> = match k {
            0 => None,
            1 => Some(&self.sa),
            _ => Some(&ws.l),
        };
        let mut qy = std::mem::take(&mut ws.qy);
        let s_live = self.live_first_moment(&self.s);
        for j in 0..n {
            let mut v = 0.0;
            if let Some(l) = li {
                v -= centrifugal(&om, l, n, j);
                if let Some(s) = s_live {
                    v -= s[j] * ab.x + s[n + j] * ab.y + s[2 * n + j] * ab.z;
                }
            }
            if gyro {
                v -= 2.0 * (wb.x * ws.gy[j] + wb.y * ws.gy[n + j] + wb.z * ws.gy[2 * n + j]);
            }
            qy[j] = v;
        }
        if cpl {
            let c = (!c_vanished).then_some(&ws.c[..]);
            self.write_shape_couplings(&st.a, &st.r0, s_live, c, &mut ws.ax, &mut ws.wy, out);
        } else {
            ws.ax.fill(0.0);
            ws.wy.fill(0.0);
            out.couplings(self.dim, n, &ws.ax, &ws.wy);
        }
        out.modal_rows(self.dim, &self.m_yy, &qy);
        ws.qy = qy;
    }

    /// The planar lean path (`shape_2d`) with the kinetic energy truncated by `terms` (module
    /// doc, in the x, y, θz rows: `I_zz = P̄₁₁ + P̄₂₂ + [k≥1] 2 h₀·y + [k≥2] yᵀM_yy y`,
    /// `h₀ = S¹_1 + S²_2`, `C₃ = S¹_2 − S²_1 + [k≥1] G₃ y`).
    pub(crate) fn shape_2d_terms<SM, SQ>(
        &self,
        st: &BodyState<'_>,
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
        let (a, w, r0, v0b, ab) = planar_frame_motion(st);
        let m = self.mass;
        let e = |v: Vector2<f64>| Vector2::new(-v.y, v.x);
        let cross = |p: Vector2<f64>, q: Vector2<f64>| p.x * q.y - p.y * q.x;

        let (full_mb, s_yd) = self.planar_first_moment(y, yd);
        let mb = if k >= 1 { full_mb } else { self.m_u.xy() };
        let mut izz = self.p_u[(0, 0)] + self.p_u[(1, 1)];
        let mut half_izz_dot = 0.0;
        // h^I = ½ ∂I_zz/∂y into ws.l[..n] (k ≥ 1); C₃ into ws.c[..n] (coupling).
        if n > 0 {
            let s11 = &self.sa[0..n];
            let s22 = &self.sa[4 * n..5 * n];
            let (t, rest) = ws.u.split_at_mut(n);
            let g3yd = &mut rest[n..2 * n];
            if k >= 2 {
                for (i, ti) in t.iter_mut().enumerate() {
                    *ti = dot(&self.m_yy[i * n..(i + 1) * n], y);
                }
            }
            if k >= 1 {
                let h = &mut ws.l[..n];
                for j in 0..n {
                    h[j] = s11[j] + s22[j] + if k >= 2 { t[j] } else { 0.0 };
                }
                izz += 2.0 * (dot(s11, y) + dot(s22, y));
                if k >= 2 {
                    izz += dot(t, y);
                }
                half_izz_dot = dot(h, yd);
            }
            if cpl {
                let g3 = &self.g[2 * n * n..3 * n * n];
                let (s12, s21) = (&self.sa[n..2 * n], &self.sa[3 * n..4 * n]);
                let gyro = k >= 1 && terms.velocity;
                for j in 0..n {
                    let gr = &g3[j * n..(j + 1) * n];
                    ws.c[j] = s12[j] - s21[j] + if k >= 1 { dot(gr, y) } else { 0.0 };
                    g3yd[j] = if gyro { dot(gr, yd) } else { 0.0 };
                }
            } else {
                g3yd.fill(0.0);
            }
        }
        let s_kept = if cpl { s_yd } else { Vector2::zeros() };
        let mb_dot = if k >= 1 { s_yd } else { Vector2::zeros() };
        let qt = w * w * mb - w * e(s_kept + mb_dot) - m * ab;
        let mut qr = -2.0 * w * half_izz_dot - cross(mb, ab);
        if (k >= 1) != cpl {
            let sign = if k >= 1 { 1.0 } else { -1.0 };
            qr -= sign * cross(s_yd, v0b);
        }
        let am = a * mb;
        let lever = m * r0 + am;
        let jzz = izz + m * r0.norm_squared() + 2.0 * r0.dot(&am);
        let qtg = a * qt;
        let qrg = r0.x * qtg.y - r0.y * qtg.x + qr;
        write_planar_rigid(m_out, q_out, m, &lever, jzz, &[qtg.x, qtg.y, qrg]);
        if n == 0 {
            return;
        }
        let g3yd = &ws.u[2 * n..3 * n];
        let s_live = self.live_first_moment(&self.s);
        for j in 0..n {
            match (cpl, s_live) {
                (true, Some(s)) => {
                    let asj = a * Vector2::new(s[j], s[n + j]);
                    let wyj = r0.x * asj.y - r0.y * asj.x + ws.c[j];
                    write_planar_coupling(m_out, j, asj.x, asj.y, wyj);
                }
                (true, None) => write_planar_coupling(m_out, j, 0.0, 0.0, ws.c[j]),
                (false, _) => write_planar_coupling(m_out, j, 0.0, 0.0, 0.0),
            }
            q_out[3 + j] = if k >= 1 {
                match s_live {
                    Some(s) => w * w * ws.l[j] - (s[j] * ab.x + s[n + j] * ab.y),
                    None => w * w * ws.l[j],
                }
            } else {
                0.0
            } - 2.0 * w * g3yd[j];
        }
        for i in 0..n {
            for j in 0..n {
                m_out[(3 + i, 3 + j)] = self.m_yy[i * n + j];
            }
        }
    }
}
