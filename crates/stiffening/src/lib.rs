//! Geometric stiffening of Euler–Bernoulli beam bodies (thesis ch. 4; docs/methods.md §6).
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
//!   correction: FNL2 locks without the complete axial basis). The modal-coordinate count changes;
//!   `Modal` sensors are re-pointed to the same mode (normal modes move behind the added
//!   static modes), or refused when the original basis had axial normal modes.
//!
//!   For `Substructuring(n)` it splits every flexible straight beam into n equal
//!   linear substructures joined by `Rigid` (bracket) joints ([`substructure`], §6.4).
//!
//! - Foreshortening FS0 ([`foreshortening`], docs/methods.md §6.3): no axial modes, F at the
//!   cloud points and nodes attached to the body; both formulations (2D and 3D) and both
//!   inertia routes (the body's FS0 shape integrals or the B-matrix projection).
//!
//! Limits: substructuring runs in the relative formulation only. The formulations'
//! `Energy` sensor adds the model's strain energy U(y) (for FNL1, which is not
//! conservative, the same U as FNL2's first two terms).
//!
//! Measured on the 2D spin-up beam (`models/spin_up_beam_2d.ron`, docs/scenes.md §5, 20 s at
//! h = 1 ms) against the ANCF cable of `flexmbd-ancf` (16 elements), max |Δu_x| / |Δu_y|:
//! FNL1 (4 bending + 2 axial cantilever modes) 18.902 / 8.383 mm; FNL2 (4 bending + 20
//! axial static modes, element-mean H) 0.112 / 1.990 mm; SB5 / SB10 / SB20 1.660 / 47.9,
//! 0.373 / 10.44, 0.090 / 2.478 mm; linear fails at t = 11.5 s (u_y = −72 m at 10 s),
//! i.e. the docs/methods.md §6 prototype figures. Newton iterations per step: 1.0 (relative)
//! and 1.8 (absolute) for FNL1 and FNL2, 1.4–1.5 for SBn.

pub mod foreshortening;

use std::borrow::Cow;

use flexmbd_body::{ElasticModel, FlexibleBody};
use flexmbd_fe::{Dof, NodeDof, ReducedBody, ReferenceFrame};
use flexmbd_model::{
    Body, BodyModel, FormulationKind, Joint, JointKind, Marker, ModelError, PreparedBody, Scene,
    SensorKind, Stiffening, V3,
};
use nalgebra::{DMatrix, DMatrixViewMut, Vector3};

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

/// The elastic model that `stiffening` gives a reduced body (`None`: keep the body's
/// linear model; FS0 keeps it too, its stiffening is in the kinematics).
pub fn elastic_model(
    stiffening: Stiffening,
    body: &ReducedBody,
) -> Result<Option<Box<dyn ElasticModel>>, ModelError> {
    match stiffening {
        Stiffening::Linear => Ok(None),
        Stiffening::Fnl1 => Ok(Some(Box::new(Nonlinear::fnl1(body)))),
        Stiffening::Fnl2 => Ok(Some(Box::new(Nonlinear::fnl2(body)))),
        // FS0: linear elasticity; the stiffening is in the kinematics (`foreshortening`).
        Stiffening::Foreshortening => Ok(None),
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
    if scene.solver.stiffening == Stiffening::Foreshortening {
        foreshortening::install(scene, prep, body)?;
    }
    Ok(())
}

/// The scene to compile for its stiffening choice (see the crate doc): FNL2 completes
/// the axial basis of flexible straight beams; FS0 drops the axial modes.
pub fn prepare_scene(scene: &Scene) -> Result<Cow<'_, Scene>, ModelError> {
    match scene.solver.stiffening {
        Stiffening::Linear | Stiffening::Fnl1 => Ok(Cow::Borrowed(scene)),
        Stiffening::Fnl2 => complete_axial_basis(scene).map(Cow::Owned),
        Stiffening::Foreshortening => foreshortening::prepare(scene).map(Cow::Owned),
        Stiffening::Substructuring(n) => substructure(scene, n).map(Cow::Owned),
    }
}

/// FNL2's axial basis (docs/methods.md §6.2 correction): every node's `Ux` but the frame
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
        let (n_static, had_axial) = (spec.boundary.len(), spec.axial_modes > 0);
        spec.axial_modes = 0;
        for node in 0..spec.n_nodes() {
            let nd = NodeDof { node, dof: Dof::Ux };
            if node != frame && !spec.boundary.contains(&nd) {
                spec.boundary.push(nd);
            }
        }
        let added = spec.boundary.len() - n_static;
        // Modal sensors keep naming the same mode: static modes keep their index, normal
        // modes move behind the added static modes. With axial normal modes in the original
        // basis (interleaved with the bending ones by frequency) the map needs the
        // eigen-solution, so such sensors are refused rather than silently re-pointed.
        for sensor in out.sensors.iter_mut() {
            let SensorKind::Modal { body, index } = &mut sensor.kind else {
                continue;
            };
            if *body != b.name || *index < n_static {
                continue;
            }
            if had_axial {
                return Err(ModelError::Unsupported(format!(
                    "{}: sensor `{}`: modal index {} of body `{}` names a normal mode, and FNL2 \
                     replaces that body's axial modes (axial_modes > 0) by static modes, so the \
                     normal modes are renumbered; use a Position sensor or run without axial_modes",
                    scene.origin, sensor.name, index, b.name
                )));
            }
            *index += added;
        }
    }
    Ok(out)
}

/// Substructuring SBn (methods.md §6.4, scenes.md §5): every flexible beam (straight along
/// body x, frame clamped at node 0, one segment) becomes n bodies `{name}_1` …
/// `{name}_n`, each a 2-element beam (whatever the original mesh; markers must sit on
/// the new nodes), frame clamped at its inner node, static modes of
/// every DOF of its outer node (2D: u, v, θ; 3D: 6) and one fixed-interface mode per
/// bending plane (3D: 2), linear elasticity; consecutive bodies are joined by `Rigid`
/// joints `{name}_bracket_k` between `outer` and `inner` markers. Markers, joints and
/// sensors naming the beam move to the substructure that holds the point (the root to
/// the first, a point on an interface to the inner end of the outer body, the tip to the
/// last); a sensor frame naming the beam becomes the first substructure's frame, which is
/// the beam's floating frame. `Modal` sensors and initial modes of a split beam are refused.
pub fn substructure(scene: &Scene, n: usize) -> Result<Scene, ModelError> {
    let refuse = |what: String| Err(ModelError::Unsupported(format!("{}: {what}", scene.origin)));
    if n == 0 {
        return refuse("substructuring needs n ≥ 1 substructures".into());
    }
    if scene.solver.formulation != FormulationKind::Relative {
        return refuse(format!(
            "substructuring SB{n} runs in the relative formulation only (methods.md §6.4); \
             use --formulation relative"
        ));
    }
    let mut out = scene.clone();
    out.solver.stiffening = Stiffening::Linear;
    out.bodies.clear();
    out.joints = scene.joints.clone();
    // (old body, old marker) → (new body, new marker name)
    let mut moved: Vec<(String, String, String, String)> = Vec::new();
    let mut first_of: Vec<(String, String)> = Vec::new();
    for b in &scene.bodies {
        let BodyModel::Beam(spec) = &b.model else {
            out.bodies.push(b.clone());
            continue;
        };
        if !b.flexible {
            out.bodies.push(b.clone());
            continue;
        }
        let pts = &spec.geometry.points;
        let straight = pts.len() == 2
            && pts[0].iter().all(|c| *c == 0.0)
            && pts[1].iter().skip(1).all(|c| *c == 0.0)
            && pts[1][0] > 0.0;
        if !straight || spec.frame != (ReferenceFrame::Clamped { node: 0 }) {
            return refuse(format!(
                "body `{}`: substructuring needs a straight beam from the origin along body x \
                 with its frame clamped at node 0",
                b.name
            ));
        }
        if !b.initial_modes.is_empty() {
            return refuse(format!(
                "body `{}`: initial modes of a split beam are not supported",
                b.name
            ));
        }
        // Each substructure: 2 elements (docs/methods.md §6.4 prototype, docs/scenes.md §5).
        let (length, per) = (pts[1][0], 2);
        let ls = length / n as f64;
        let a0 = b.orientation.matrix();
        let planar = spec.dim == flexmbd_core::Dim::Planar;
        let dofs: &[Dof] = if planar {
            &[Dof::Ux, Dof::Uy, Dof::Rz]
        } else {
            &[Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz]
        };
        let v3 = |x: f64| V3([x, 0.0, 0.0]);
        let point = |x: f64| -> Vec<f64> {
            if planar {
                vec![x, 0.0]
            } else {
                vec![x, 0.0, 0.0]
            }
        };
        let name = |k: usize| format!("{}_{}", b.name, k + 1);
        first_of.push((b.name.clone(), name(0)));
        for k in 0..n {
            let mut sub = spec.clone();
            sub.geometry.points = vec![point(0.0), point(ls)];
            sub.geometry.elements_per_segment = per;
            sub.boundary = dofs.iter().map(|&dof| NodeDof { node: per, dof }).collect();
            sub.normal_modes = if planar { 1 } else { 2 };
            sub.axial_modes = 0;
            let offset = a0 * Vector3::new(k as f64 * ls, 0.0, 0.0);
            let w = b.velocity.angular.vec();
            let mut velocity = b.velocity.clone();
            velocity.linear = V3((b.velocity.linear.vec() + w.cross(&offset)).into());
            let mut markers = vec![
                Marker {
                    name: "inner".into(),
                    position: v3(0.0),
                },
                Marker {
                    name: "outer".into(),
                    position: v3(ls),
                },
            ];
            for m in &b.markers {
                let x = m.position.0[0];
                let kk = ((x / ls + 1e-9).floor() as usize).min(n - 1);
                if kk == k {
                    markers.push(Marker {
                        name: m.name.clone(),
                        position: v3(x - k as f64 * ls),
                    });
                    moved.push((b.name.clone(), m.name.clone(), name(k), m.name.clone()));
                }
            }
            out.bodies.push(Body {
                name: name(k),
                origin: V3((b.origin.vec() + offset).into()),
                orientation: b.orientation.clone(),
                model: BodyModel::Beam(sub),
                flexible: true,
                markers,
                velocity,
                initial_modes: Vec::new(),
            });
            if k > 0 {
                out.joints.push(Joint {
                    name: format!("{}_bracket_{k}", b.name),
                    kind: JointKind::Rigid,
                    body1: name(k - 1),
                    marker1: "outer".into(),
                    body2: name(k),
                    marker2: "inner".into(),
                });
            }
        }
    }
    let remap = |body: &mut String, marker: &mut String| {
        if let Some((_, _, nb, nm)) = moved
            .iter()
            .find(|(ob, om, _, _)| ob == body && om == marker)
        {
            *body = nb.clone();
            *marker = nm.clone();
        }
    };
    for j in out.joints.iter_mut() {
        remap(&mut j.body1, &mut j.marker1);
        remap(&mut j.body2, &mut j.marker2);
    }
    for f in out.forces.iter_mut() {
        let flexmbd_model::Force::SpringDamper {
            body1,
            marker1,
            body2,
            marker2,
            ..
        } = f;
        remap(body1, marker1);
        remap(body2, marker2);
    }
    let frame_of = |f: &mut Option<String>| {
        if let Some(name) = f
            && let Some((_, first)) = first_of.iter().find(|(o, _)| o == name)
        {
            *name = first.clone();
        }
    };
    for s in out.sensors.iter_mut() {
        match &mut s.kind {
            SensorKind::Position {
                body,
                marker,
                frame,
                ..
            }
            | SensorKind::Velocity {
                body,
                marker,
                frame,
                ..
            } => {
                remap(body, marker);
                frame_of(frame);
            }
            SensorKind::Modal { body, .. } if first_of.iter().any(|(o, _)| o == body) => {
                return refuse(format!(
                    "sensor `{}`: modal coordinates of a split beam do not exist under substructuring",
                    s.name
                ));
            }
            _ => {}
        }
    }
    Ok(out)
}
