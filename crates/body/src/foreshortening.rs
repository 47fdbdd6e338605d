//! Foreshortening, FS0 (docs/methods.md §6.3): the data of a straight beam that shortens along
//! its axis ē₁, and the helpers that use it outside the inertia kernels.
//!
//! For each cloud point k, with its own `F_k` (n × n, symmetric):
//!
//! ```text
//! r̄_k = r̄_uk + X_k y − ½ ē₁ yᵀF_k y,        X̂_k = X_k − ē₁ (F_k y)ᵀ,
//! B_k = [I  −r̃_k  A X̂_k],
//! Ḃ_k Z = ω × ṡ + ω × (ω × r_k) + 2 ω × A X̂_k ẏ − A ē₁ (ẏᵀF_k ẏ),
//! M̄ = Σ w_k B_kᵀ B_k,   Q̄_v = −Σ w_k B_kᵀ (Ḃ_k Z).
//! ```
//!
//! The B-matrix route (the reference) is the linear kernel of `bmatrix.rs` (relative set)
//! and `natural.rs` (natural coordinates, `Ḃ_k q̇ = 2 Ȧ X̂_k ẏ − A ē₁ (ẏᵀF_k ẏ)`) compiled
//! for the foreshortened point kinematics of `kinematics.rs`. The 13 shape integrals alone
//! do not suffice, but the integrals of F, r̄_u F, F ⊗ X and F ⊗ F do:
//! [`InertiaMethod::ShapeIntegrals`](crate::InertiaMethod) evaluates FS0 from them without a
//! loop over the cloud (`fs_shape.rs`, which states the algebra), and the two routes agree
//! to round-off (`tests/fs0_routes.rs`).
//!
//! The same kinematics at an FE node give the marker helper
//! [`FlexibleBody::node_foreshortening`] (position shift −½ ē₁ yᵀF_node y, its rate
//! −ē₁ (F_node y)·ẏ, the velocity-product term −ē₁ ẏᵀF_node ẏ and the Jacobian
//! −ē₁ (F_node y)ᵀ), which formulations add to marker and sensor kinematics.

use flexmbd_core::{Dim, InvalidValue};
use flexmbd_fe::ForeshorteningData;
use nalgebra::{DMatrix, Vector3};

use crate::fs_shape::FsIntegrals;
use crate::{FlexibleBody, InertiaMethod, dot};

/// FS0 data of a body at run time (contiguous, row-major F's).
#[derive(Clone, Debug)]
pub(crate) struct Foreshortening {
    pub(crate) axis: Vector3<f64>,
    /// F of every distinct station, row-major, n² each (consecutive cloud points with the
    /// same F, e.g. the 4 section points of a 3D Gauss station, share one).
    pub(crate) cloud: Vec<f64>,
    /// Station of every cloud point (index into `cloud` in units of n²).
    pub(crate) station: Vec<usize>,
    /// F at every FE node, n² per node.
    nodes: Vec<f64>,
    /// Σ_k w_k F_k (n², row-major): the first moment's shortening −½ ē₁ yᵀ(Σ w F) y.
    pub(crate) wf: Vec<f64>,
    /// The FS0 shape integrals of the shape-integral route (`fs_shape.rs`).
    pub(crate) ints: FsIntegrals,
}

/// The foreshortening of one FE node (body components; docs/methods.md §6.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeShift {
    /// Position shift −½ ē₁ yᵀF y, added to r̄_u + X^t y.
    pub position: Vector3<f64>,
    /// Its rate −ē₁ (F y)·ẏ, added to X^t ẏ.
    pub velocity: Vector3<f64>,
    /// The velocity-product part of its second derivative, −ē₁ ẏᵀF ẏ (the rest is
    /// the Jacobian times ÿ).
    pub bias: Vector3<f64>,
}

fn flatten(field: &str, ms: &[DMatrix<f64>], n: usize) -> Result<Vec<f64>, InvalidValue> {
    let mut v = Vec::with_capacity(ms.len() * n * n);
    for (k, m) in ms.iter().enumerate() {
        if m.shape() != (n, n) {
            return Err(InvalidValue::new(
                format!("{field}[{k}]"),
                format!("{}x{}", m.nrows(), m.ncols()),
                format!("must be {n}x{n}"),
            ));
        }
        if !m.iter().all(|x| x.is_finite()) {
            return Err(InvalidValue::new(
                format!("{field}[{k}]"),
                "non-finite entry",
                "must be finite",
            ));
        }
        for i in 0..n {
            for j in 0..n {
                v.push(0.5 * (m[(i, j)] + m[(j, i)]));
            }
        }
    }
    Ok(v)
}

impl Foreshortening {
    pub(crate) fn new(
        data: &ForeshorteningData,
        dim: Dim,
        n: usize,
        weights: &[f64],
        positions: &[Vector3<f64>],
        rows: &[f64],
    ) -> Result<Self, InvalidValue> {
        let n_cloud = weights.len();
        let norm = data.axis.norm();
        if !(norm.is_finite() && (norm - 1.0).abs() < 1e-9) {
            return Err(InvalidValue::new(
                "foreshortening.axis",
                format!("{:?}", data.axis.as_slice()),
                "must be a unit vector",
            ));
        }
        if dim == Dim::Planar && data.axis.z != 0.0 {
            return Err(InvalidValue::new(
                "foreshortening.axis.z",
                data.axis.z,
                "a planar body's beam axis lies in z = 0",
            ));
        }
        if data.cloud.len() != n_cloud {
            return Err(InvalidValue::new(
                "foreshortening.cloud",
                data.cloud.len(),
                format!("must have one F per cloud point ({n_cloud})"),
            ));
        }
        let all = flatten("foreshortening.cloud", &data.cloud, n)?;
        let n2 = n * n;
        // Distinct stations: a cloud point whose F equals its predecessor's shares it.
        let mut cloud: Vec<f64> = Vec::with_capacity(all.len());
        let mut station = Vec::with_capacity(n_cloud);
        for k in 0..n_cloud {
            let f = &all[k * n2..(k + 1) * n2];
            let same = k > 0 && cloud.len() >= n2 && cloud[cloud.len() - n2..] == *f;
            if !same {
                cloud.extend_from_slice(f);
            }
            station.push((cloud.len() / n2.max(1)).saturating_sub(1));
        }
        let mut wf = vec![0.0; n2];
        for (k, w) in weights.iter().enumerate() {
            for (o, f) in wf.iter_mut().zip(&all[k * n2..(k + 1) * n2]) {
                *o += w * f;
            }
        }
        let ints = FsIntegrals::new(n, &cloud, &station, weights, positions, rows);
        Ok(Self {
            wf,
            ints,
            axis: data.axis,
            cloud,
            station,
            nodes: flatten("foreshortening.nodes", &data.nodes, n)?,
        })
    }
}

/// u = F v for a row-major n × n F.
pub(crate) fn mat_vec(f: &[f64], v: &[f64], out: &mut [f64]) {
    let n = v.len();
    for (i, o) in out.iter_mut().enumerate() {
        *o = dot(&f[i * n..(i + 1) * n], v);
    }
}

impl FlexibleBody {
    /// Attach FS0 data (docs/methods.md §6.3) to this body: from then on both inertia routes use
    /// the foreshortened kinematics, and [`node_foreshortening`](Self::node_foreshortening)
    /// reports node shifts. Refuses data of the wrong sizes. Make natural-coordinate
    /// workspaces ([`natural_workspace`](Self::natural_workspace)) after this call.
    pub fn set_foreshortening(&mut self, data: &ForeshorteningData) -> Result<(), InvalidValue> {
        self.fs = Some(Foreshortening::new(
            data, self.dim, self.n, &self.w, &self.pos, &self.rows,
        )?);
        self.workspace = Some(Box::new(crate::Workspace::for_body(self.n, true)));
        Ok(())
    }

    /// True when the body carries FS0 data.
    pub fn has_foreshortening(&self) -> bool {
        self.fs.is_some()
    }

    /// Whether `method` can evaluate this body's inertia. Both routes evaluate every body,
    /// a foreshortened one included (FS0 by shape integrals: `fs_shape.rs`), so this is
    /// always `Ok`; it is kept for formulations that check at set-up.
    pub fn check_inertia_method(&self, method: InertiaMethod) -> Result<(), InvalidValue> {
        let _ = method;
        Ok(())
    }

    /// The foreshortening of FE node `node` at (y, ẏ), in body components, or `None`
    /// for a body without FS0 data. Add `position` to r̄_u + X^t y, `velocity` to
    /// X^t ẏ and `bias` to the velocity-product acceleration of the node.
    ///
    /// # Panics
    /// If `node` is out of range or `y`, `y_dot` do not have n entries.
    pub fn node_foreshortening(&self, node: usize, y: &[f64], y_dot: &[f64]) -> Option<NodeShift> {
        let fs = self.fs.as_ref()?;
        let n = self.n;
        assert!(
            y.len() == n && y_dot.len() == n,
            "node_foreshortening: y, ẏ need n entries"
        );
        let f = &fs.nodes[node * n * n..(node + 1) * n * n];
        let (mut yfy, mut yfyd, mut ydfyd) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let row = &f[i * n..(i + 1) * n];
            let (fy, fyd) = (dot(row, y), dot(row, y_dot));
            yfy += y[i] * fy;
            yfyd += y_dot[i] * fy;
            ydfyd += y_dot[i] * fyd;
        }
        Some(NodeShift {
            position: fs.axis * (-0.5 * yfy),
            velocity: fs.axis * (-yfyd),
            bias: fs.axis * (-ydfyd),
        })
    }

    /// Add the foreshortening Jacobian of FE node `node`, −ē₁ (F y)ᵀ (3 × n, body
    /// components), to `out` (the node's translation rows X^t). No-op without FS0 data.
    pub fn add_node_foreshortening_jacobian(&self, node: usize, y: &[f64], out: &mut DMatrix<f64>) {
        let Some(fs) = self.fs.as_ref() else { return };
        let n = self.n;
        assert_eq!(out.shape(), (3, n), "node Jacobian must be 3 x n");
        let f = &fs.nodes[node * n * n..(node + 1) * n * n];
        for j in 0..n {
            let fy = dot(&f[j * n..(j + 1) * n], y);
            for a in 0..3 {
                out[(a, j)] -= fs.axis[a] * fy;
            }
        }
    }

    /// Column j of the foreshortening Jacobian of FE node `node`, −ē₁ (F y)_j (body
    /// components; zero without FS0 data).
    pub fn node_foreshortening_column(&self, node: usize, y: &[f64], j: usize) -> Vector3<f64> {
        let Some(fs) = self.fs.as_ref() else {
            return Vector3::zeros();
        };
        let n = self.n;
        let f = &fs.nodes[node * n * n..(node + 1) * n * n];
        fs.axis * (-dot(&f[j * n..(j + 1) * n], y))
    }

    /// The first moment's foreshortening −½ ē₁ yᵀ(Σ_k w_k F_k) y (body components), or
    /// zero without FS0 data.
    pub(crate) fn fs_first_moment(&self, y: &[f64]) -> Vector3<f64> {
        let Some(fs) = self.fs.as_ref() else {
            return Vector3::zeros();
        };
        let n = self.n;
        let mut q = 0.0;
        for i in 0..n {
            q += y[i] * dot(&fs.wf[i * n..(i + 1) * n], y);
        }
        fs.axis * (-0.5 * q)
    }

    /// Add the FS0 part of the modal gravity force, −(Σ w F_k) y (ē₁ · Aᵀg), to `out` (n).
    pub(crate) fn add_fs_gravity(&self, y: &[f64], gb: &Vector3<f64>, out: &mut [f64]) {
        let Some(fs) = self.fs.as_ref() else { return };
        let n = self.n;
        let s = fs.axis.dot(gb);
        if s == 0.0 {
            return;
        }
        for (j, o) in out.iter_mut().enumerate() {
            *o -= s * dot(&fs.wf[j * n..(j + 1) * n], y);
        }
    }
}
