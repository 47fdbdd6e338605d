//! Geometric stiffening of Euler–Bernoulli beam bodies (thesis ch. 4; docs/methods.md §6): the
//! nonlinear elastic models, as [`flexmbd_body::ElasticModel`]s with their tangents.
//!
//! - FNL1: `Q = −(K_L + K_G(y)) y − C ẏ`, `K_G = Σ_k y_k K_Gk`; tangent
//!   `K_L + K_G + V`, `V = [K_G1 y … K_Gn y]` (not symmetric, not conservative);
//! - FNL2: `Q = −∂U/∂y − C ẏ` with `U = ½yᵀK_L y + ½Σ_k y_k yᵀK_Gk y +
//!   ⅛ Σ_e w_e (yᵀḠ_e y)²` (H from the element means Ḡ_e, §6.2 correction); tangent
//!   the Hessian `K_L + K_G + V + Vᵀ + K_H + Σ_e w_e (Ḡ_e y)(Ḡ_e y)ᵀ`.
//!
//! The rest of a stiffening method is part of preparing a scene (`flexmbd-model`,
//! `PreparedScene::new`): the scene rewrites (FNL2's complete axial basis, FS0 without axial
//! modes, substructuring SBn into n linear bodies joined by brackets), the installation of
//! these models on the run-time bodies, and FS0's shortening data (§6.3), whose stiffening is
//! in the kinematics rather than in the elastic forces. The formulations' `Energy` sensor
//! adds the model's strain energy U(y) (for FNL1, which is not conservative, the same U as
//! FNL2's first two terms).

use flexmbd_body::ElasticModel;
use flexmbd_fe::ReducedBody;
use nalgebra::{DMatrix, DMatrixViewMut};

/// Which nonlinear force model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// First nonlinear term (K_G only).
    Fnl1,
    /// Full strain energy (K_G, K_H and Q_g).
    Fnl2,
}

/// FNL1 / FNL2 elasticity of one reduced beam body (docs/methods.md §6.2).
#[derive(Clone, Debug)]
pub struct Nonlinear {
    kind: Kind,
    n: usize,
    /// K_L row-major.
    k: Vec<f64>,
    /// C_ff row-major.
    c: Vec<f64>,
    /// Non-zero K_Gk: (k, row-major n × n).
    kg: Vec<(usize, Vec<f64>)>,
    /// Indices on which some Ḡ_e is non-zero (the bending modes).
    hidx: Vec<usize>,
    /// Ḡ_e restricted to `hidx`, row-major nb × nb, one block per element.
    gbar: Vec<f64>,
    /// w_e = EA_e L_e.
    hw: Vec<f64>,
}

fn row_major(m: &DMatrix<f64>) -> Vec<f64> {
    let (r, c) = m.shape();
    let mut v = Vec::with_capacity(r * c);
    for i in 0..r {
        for j in 0..c {
            v.push(m[(i, j)]);
        }
    }
    v
}

impl Nonlinear {
    /// The model of `kind` for a reduced body (its K_ff, C_ff, K_Gk and Ḡ_e).
    pub fn new(kind: Kind, body: &ReducedBody) -> Self {
        let n = body.k_ff.nrows();
        let st = &body.stiffening;
        let scale = body.k_ff.diagonal().amax().max(f64::MIN_POSITIVE);
        let kg = st
            .k_g
            .iter()
            .enumerate()
            .filter(|(_, m)| m.amax() > 1e-14 * scale)
            .map(|(k, m)| (k, row_major(m)))
            .collect();
        let gmax = st.g_mean.iter().map(|g| g.amax()).fold(0.0, f64::max);
        let hidx: Vec<usize> = (0..n)
            .filter(|&i| {
                st.g_mean
                    .iter()
                    .any(|g| g.row(i).amax() > 1e-10 * gmax.max(f64::MIN_POSITIVE))
            })
            .collect();
        let nb = hidx.len();
        let mut gbar = Vec::with_capacity(st.g_mean.len() * nb * nb);
        for g in &st.g_mean {
            for &i in &hidx {
                for &j in &hidx {
                    gbar.push(g[(i, j)]);
                }
            }
        }
        Self {
            kind,
            n,
            k: row_major(&body.k_ff),
            c: row_major(&body.c_ff),
            kg,
            hidx,
            gbar,
            hw: st.h_weight.clone(),
        }
    }

    /// FNL1 of a reduced body.
    pub fn fnl1(body: &ReducedBody) -> Self {
        Self::new(Kind::Fnl1, body)
    }

    /// FNL2 of a reduced body.
    pub fn fnl2(body: &ReducedBody) -> Self {
        Self::new(Kind::Fnl2, body)
    }

    /// The model kind.
    pub fn kind(&self) -> Kind {
        self.kind
    }

    /// Strain energy U(y) of FNL2 (docs/methods.md §6.1 with the element-averaged H).
    /// For FNL1 (not conservative) this is the same function, which FNL1's force is not
    /// the gradient of.
    pub fn strain_energy(&self, y: &[f64]) -> f64 {
        let n = self.n;
        let mut u = 0.0;
        for i in 0..n {
            for j in 0..n {
                u += 0.5 * y[i] * self.k[i * n + j] * y[j];
            }
        }
        for (k, m) in &self.kg {
            u += 0.5 * y[*k] * quad(m, n, y);
        }
        for (e, w) in self.hw.iter().enumerate() {
            let s = self.s_e(e, y);
            u += 0.125 * w * s * s;
        }
        u
    }

    fn block(&self, e: usize) -> &[f64] {
        let nb = self.hidx.len();
        &self.gbar[e * nb * nb..(e + 1) * nb * nb]
    }

    /// s_e = yᵀ Ḡ_e y.
    fn s_e(&self, e: usize, y: &[f64]) -> f64 {
        let nb = self.hidx.len();
        let g = self.block(e);
        let mut s = 0.0;
        for a in 0..nb {
            let ya = y[self.hidx[a]];
            if ya == 0.0 {
                continue;
            }
            let mut r = 0.0;
            for b in 0..nb {
                r += g[a * nb + b] * y[self.hidx[b]];
            }
            s += ya * r;
        }
        s
    }

    /// (Ḡ_e y)_a on the compact index a.
    fn gy(&self, e: usize, a: usize, y: &[f64]) -> f64 {
        let nb = self.hidx.len();
        let g = &self.block(e)[a * nb..(a + 1) * nb];
        let mut r = 0.0;
        for b in 0..nb {
            r += g[b] * y[self.hidx[b]];
        }
        r
    }
}

/// yᵀ M y for a row-major n × n M.
fn quad(m: &[f64], n: usize, y: &[f64]) -> f64 {
    let mut s = 0.0;
    for i in 0..n {
        if y[i] == 0.0 {
            continue;
        }
        let mut r = 0.0;
        for j in 0..n {
            r += m[i * n + j] * y[j];
        }
        s += y[i] * r;
    }
    s
}

impl ElasticModel for Nonlinear {
    fn name(&self) -> &str {
        match self.kind {
            Kind::Fnl1 => "FNL1",
            Kind::Fnl2 => "FNL2",
        }
    }

    fn strain_energy(&self, y: &[f64]) -> f64 {
        Nonlinear::strain_energy(self, y)
    }

    fn forces(&self, y: &[f64], y_dot: &[f64], out: &mut [f64]) {
        let n = self.n;
        assert!(y.len() == n && y_dot.len() == n && out.len() == n);
        // −K_L y − C ẏ
        for i in 0..n {
            let kr = &self.k[i * n..(i + 1) * n];
            let cr = &self.c[i * n..(i + 1) * n];
            let mut s = 0.0;
            for j in 0..n {
                s += kr[j] * y[j] + cr[j] * y_dot[j];
            }
            out[i] = -s;
        }
        // −K_G(y) y = −Σ_k y_k K_Gk y
        for (k, m) in &self.kg {
            let yk = y[*k];
            if yk != 0.0 {
                for i in 0..n {
                    let mut r = 0.0;
                    for j in 0..n {
                        r += m[i * n + j] * y[j];
                    }
                    out[i] -= yk * r;
                }
            }
            if self.kind == Kind::Fnl2 {
                // Q_g,k = −½ yᵀ K_Gk y
                out[*k] -= 0.5 * quad(m, n, y);
            }
        }
        if self.kind == Kind::Fnl2 {
            // −K_H y = −½ Σ_e w_e s_e Ḡ_e y
            for (e, w) in self.hw.iter().enumerate() {
                let f = 0.5 * w * self.s_e(e, y);
                if f == 0.0 {
                    continue;
                }
                for a in 0..self.hidx.len() {
                    out[self.hidx[a]] -= f * self.gy(e, a, y);
                }
            }
        }
    }

    fn add_tangents(
        &self,
        y: &[f64],
        _y_dot: &[f64],
        k_scale: f64,
        c_scale: f64,
        mut out: DMatrixViewMut<'_, f64>,
    ) {
        let n = self.n;
        assert_eq!(out.shape(), (n, n));
        // Column by column on contiguous column slices (indexing the strided view entry by
        // entry cost about 20 instructions per entry); every entry receives its terms in
        // the same order as a plain (i, j) loop would add them.
        for j in 0..n {
            let mut col = out.column_mut(j);
            let col = col.as_mut_slice();
            for i in 0..n {
                col[i] += k_scale * self.k[i * n + j] + c_scale * self.c[i * n + j];
            }
        }
        if k_scale == 0.0 {
            return;
        }
        for (k, m) in &self.kg {
            let k = *k;
            let yk = y[k];
            // K_G = Σ y_k K_Gk
            if yk != 0.0 {
                let s = k_scale * yk;
                for j in 0..n {
                    let mut col = out.column_mut(j);
                    let col = col.as_mut_slice();
                    for i in 0..n {
                        col[i] += s * m[i * n + j];
                    }
                }
            }
            // V: column k = K_Gk y; FNL2 adds Vᵀ (row k).
            for i in 0..n {
                let mut r = 0.0;
                for (mij, yj) in m[i * n..(i + 1) * n].iter().zip(y) {
                    r += mij * yj;
                }
                out[(i, k)] += k_scale * r;
                if self.kind == Kind::Fnl2 {
                    out[(k, i)] += k_scale * r;
                }
            }
        }
        if self.kind == Kind::Fnl2 {
            let nb = self.hidx.len();
            // (Ḡ_e y)_b once per element (the same value the pair loop would recompute).
            const MAX_NB: usize = 64;
            let mut gyb = [0.0; MAX_NB];
            for (e, w) in self.hw.iter().enumerate() {
                let half_s = 0.5 * w * self.s_e(e, y) * k_scale;
                let g = self.block(e);
                if nb <= MAX_NB {
                    for (b, v) in gyb[..nb].iter_mut().enumerate() {
                        *v = self.gy(e, b, y);
                    }
                }
                for a in 0..nb {
                    let ga = w * k_scale * self.gy(e, a, y);
                    let ia = self.hidx[a];
                    for b in 0..nb {
                        let ib = self.hidx[b];
                        let gb = if nb <= MAX_NB {
                            gyb[b]
                        } else {
                            self.gy(e, b, y)
                        };
                        // K_H + w (Ḡy)(Ḡy)ᵀ
                        out[(ia, ib)] += half_s * g[a * nb + b] + ga * gb;
                    }
                }
            }
        }
    }

    fn clone_box(&self) -> Box<dyn ElasticModel> {
        Box::new(self.clone())
    }

    fn is_linear(&self) -> bool {
        false
    }

    fn is_symmetric(&self) -> bool {
        self.kind == Kind::Fnl2 || self.kg.is_empty()
    }
}
