//! Geometric stiffening of Euler–Bernoulli beam bodies (thesis ch. 4; methods.md §6).
//!
//! - [`Nonlinear`]: the FNL1 and FNL2 elastic models of §6.2 as
//!   [`flexmbd_body::ElasticModel`]s, with their tangents:
//!   - FNL1: `Q = −(K_L + K_G(y)) y − C ẏ`, `K_G = Σ_k y_k K_Gk`; tangent
//!     `K_L + K_G + V`, `V = [K_G1 y … K_Gn y]` (not symmetric, not conservative);
//!   - FNL2: `Q = −∂U/∂y − C ẏ` with `U = ½yᵀK_L y + ½Σ_k y_k yᵀK_Gk y +
//!     ⅛ Σ_e w_e (yᵀḠ_e y)²` (H from the element means Ḡ_e, §6.2 correction); tangent
//!     the Hessian `K_L + K_G + V + Vᵀ + K_H + Σ_e w_e (Ḡ_e y)(Ḡ_e y)ᵀ`.
//! - [`install`]: called by the formulations right after they build a
//!   [`FlexibleBody`] from a [`PreparedBody`]; installs the model that
//!   `scene.solver.stiffening` names (nothing for `Linear`).
//! - [`prepare_scene`]: the scene transformation done before compiling. For FNL2 it
//!   completes the axial basis of every flexible straight beam along body x: a static
//!   mode (Craig–Bampton boundary DOF) for the axial DOF `Ux` of every node but the
//!   frame node, appended to the beam's `boundary`, and `axial_modes` set to 0 (§6.2
//!   correction: FNL2 locks without the complete axial basis). The modal-coordinate count changes, and
//!   `Modal` sensor indices of normal modes shift by the number of added modes.
//!
//! Limits: foreshortening (FS0) and substructuring are refused for now. The
//! formulations' `Energy` sensor still uses ½yᵀK_ff y for the elastic energy.

use std::borrow::Cow;

use flexmbd_body::{ElasticModel, FlexibleBody};
use flexmbd_fe::{Dof, NodeDof, ReducedBody, ReferenceFrame};
use flexmbd_model::{BodyModel, ModelError, PreparedBody, Scene, Stiffening};
use nalgebra::{DMatrix, DMatrixViewMut};

/// Which nonlinear force model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// First nonlinear term (K_G only).
    Fnl1,
    /// Full strain energy (K_G, K_H and Q_g).
    Fnl2,
}

/// FNL1 / FNL2 elasticity of one reduced beam body (methods.md §6.2).
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

    /// Strain energy U(y) of FNL2 (methods.md §6.1 with the element-averaged H).
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
        for i in 0..n {
            for j in 0..n {
                out[(i, j)] += k_scale * self.k[i * n + j] + c_scale * self.c[i * n + j];
            }
        }
        if k_scale == 0.0 {
            return;
        }
        for (k, m) in &self.kg {
            let yk = y[*k];
            // K_G = Σ y_k K_Gk
            if yk != 0.0 {
                for i in 0..n {
                    for j in 0..n {
                        out[(i, j)] += k_scale * yk * m[i * n + j];
                    }
                }
            }
            // V: column k = K_Gk y; FNL2 adds Vᵀ (row k).
            for i in 0..n {
                let mut r = 0.0;
                for j in 0..n {
                    r += m[i * n + j] * y[j];
                }
                out[(i, *k)] += k_scale * r;
                if self.kind == Kind::Fnl2 {
                    out[(*k, i)] += k_scale * r;
                }
            }
        }
        if self.kind == Kind::Fnl2 {
            let nb = self.hidx.len();
            for (e, w) in self.hw.iter().enumerate() {
                let half_s = 0.5 * w * self.s_e(e, y) * k_scale;
                let g = self.block(e);
                for a in 0..nb {
                    let ga = w * k_scale * self.gy(e, a, y);
                    let ia = self.hidx[a];
                    for b in 0..nb {
                        let ib = self.hidx[b];
                        // K_H + w (Ḡy)(Ḡy)ᵀ
                        out[(ia, ib)] += half_s * g[a * nb + b] + ga * self.gy(e, b, y);
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

/// The elastic model that `stiffening` gives a reduced body (`None`: keep the body's
/// linear model). Errors for methods that are not elastic models (FS0, substructuring).
pub fn elastic_model(
    stiffening: Stiffening,
    body: &ReducedBody,
) -> Result<Option<Box<dyn ElasticModel>>, ModelError> {
    match stiffening {
        Stiffening::Linear => Ok(None),
        Stiffening::Fnl1 => Ok(Some(Box::new(Nonlinear::fnl1(body)))),
        Stiffening::Fnl2 => Ok(Some(Box::new(Nonlinear::fnl2(body)))),
        Stiffening::Foreshortening => Err(ModelError::Unsupported(
            "stiffening Foreshortening (FS0) is not available yet".into(),
        )),
        // The scene was transformed by `prepare_scene`: its bodies are linear.
        Stiffening::Substructuring(_) => Ok(None),
    }
}

/// Install the elastic model of `scene.solver.stiffening` on a body the formulation
/// just built from `prep` (a no-op for rigid bodies and for `Linear`).
pub fn install(
    scene: &Scene,
    prep: &PreparedBody,
    body: &mut FlexibleBody,
) -> Result<(), ModelError> {
    if !prep.flexible || body.n_modes() == 0 {
        return Ok(());
    }
    if let Some(m) = elastic_model(scene.solver.stiffening, &prep.reduced)? {
        body.set_elastic_model(m);
    }
    Ok(())
}

/// The scene to compile for its stiffening choice (see the crate doc): FNL2 completes
/// the axial basis of flexible straight beams; FS0 and substructuring are refused.
pub fn prepare_scene(scene: &Scene) -> Result<Cow<'_, Scene>, ModelError> {
    match scene.solver.stiffening {
        Stiffening::Linear | Stiffening::Fnl1 => Ok(Cow::Borrowed(scene)),
        Stiffening::Fnl2 => complete_axial_basis(scene).map(Cow::Owned),
        Stiffening::Foreshortening => Err(ModelError::Unsupported(
            "stiffening Foreshortening (FS0) is not available yet".into(),
        )),
        Stiffening::Substructuring(n) => Err(ModelError::Unsupported(format!(
            "stiffening Substructuring({n}) is not available yet"
        ))),
    }
}

/// FNL2's axial basis (methods.md §6.2 correction): every node's `Ux` but the frame
/// node's becomes a static mode of every flexible beam (straight, along body x,
/// clamped frame).
pub fn complete_axial_basis(scene: &Scene) -> Result<Scene, ModelError> {
    let mut out = scene.clone();
    for b in out.bodies.iter_mut() {
        let BodyModel::Beam(spec) = &mut b.model else {
            continue;
        };
        if !b.flexible {
            continue;
        }
        let straight = spec
            .geometry
            .points
            .iter()
            .all(|p| p.iter().skip(1).all(|c| *c == 0.0));
        let ReferenceFrame::Clamped { node: frame } = spec.frame else {
            return Err(ModelError::Unsupported(format!(
                "{}: body `{}`: FNL2 needs a clamped frame (methods.md §6)",
                scene.origin, b.name
            )));
        };
        if !straight {
            return Err(ModelError::Unsupported(format!(
                "{}: body `{}`: FNL2 needs a straight beam along body x (methods.md §6)",
                scene.origin, b.name
            )));
        }
        // The axial normal modes are replaced by the complete static basis.
        spec.axial_modes = 0;
        for node in 0..spec.n_nodes() {
            let nd = NodeDof { node, dof: Dof::Ux };
            if node != frame && !spec.boundary.contains(&nd) {
                spec.boundary.push(nd);
            }
        }
    }
    Ok(out)
}
