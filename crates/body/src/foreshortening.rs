//! Foreshortening, FS0 (docs/methods.md §6.3): route (a) with the configuration-dependent
//! mode rows of a straight beam that shortens along its axis ē₁.
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
//! This is the reference route. The 13 shape integrals alone do not suffice, but the
//! integrals of F, r̄_u F, F ⊗ X and F ⊗ F do: [`InertiaMethod::ShapeIntegrals`](crate::InertiaMethod)
//! evaluates FS0 from them without a loop over the cloud (`fs_shape.rs`, which states the
//! algebra), and the two routes agree to round-off (`tests/fs0_routes.rs`). In natural
//! coordinates (docs/methods.md §2.5) the same projection uses, in 2D {r0, u, y},
//! `B_k = [I₂  r̄_k1 I + r̄_k2 E  A X̂_k]`, in 3D {r0, u, v, w, y}
//! `B_k = [I  r̄_k1 I  r̄_k2 I  r̄_k3 I  A X̂_k]`, and `Ḃ_k q̇ = 2 Ȧ X̂_k ẏ − A ē₁ (ẏᵀF_k ẏ)`.
//! F_k y, yᵀF_k y and ẏᵀF_k ẏ are formed once per station (the 4 section points of a 3D
//! Gauss station share F_k).
//!
//! The same kinematics at an FE node give the marker helper
//! [`FlexibleBody::node_foreshortening`] (position shift −½ ē₁ yᵀF_node y, its rate
//! −ē₁ (F_node y)·ẏ, the velocity-product term −ē₁ ẏᵀF_node ẏ and the Jacobian
//! −ē₁ (F_node y)ᵀ), which formulations add to marker and sensor kinematics.

use flexmbd_core::{Dim, InvalidValue};
use flexmbd_fe::ForeshorteningData;
use nalgebra::{DMatrix, Dyn, Matrix, Matrix2, Matrix3, StorageMut, U1, Vector2, Vector3};

use crate::fs_shape::FsIntegrals;
use crate::natural::{
    BMatrixSums2, BMatrixSums3, write_bmatrix_natural_2d, write_bmatrix_natural_3d,
};
use crate::{
    BodyState, FlexibleBody, InertiaMethod, NaturalState, NaturalWorkspace, dot, write_modal_block,
};

/// FS0 data of a body at run time (contiguous, row-major F's) and its scratch.
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
    /// Scratch: X̂_k (3n), F_k y (n).
    xhat: Vec<f64>,
    fy: Vec<f64>,
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
            xhat: vec![0.0; 3 * n],
            fy: vec![0.0; n],
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
        self.ws.fs = crate::fs_shape::FsScratch::new(self.n);
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

    /// Route (a) with FS0 kinematics, both dimensions (3D accumulators; a planar body
    /// keeps the x, y, θz rows and columns).
    pub(crate) fn bmatrix_fs<SM, SQ>(
        &mut self,
        st: &BodyState<'_>,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        q_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let n = self.n;
        let dim = self.dim;
        let FlexibleBody {
            pos,
            w,
            rows,
            ws,
            fs,
            ..
        } = self;
        let fs = fs.as_mut().expect("bmatrix_fs without FS0 data");
        let (y, yd) = (st.y, st.y_dot);
        let a = &st.a;
        let r0 = st.r0;
        let om = st.omega;
        let w_sd = om.cross(&st.s_dot);
        let axis = fs.axis;
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
        let (n2, w3) = (n * n, 3 * n);
        // F_k y, yᵀF_k y and ẏᵀF_k ẏ once per station (the 3D section points share F).
        let (mut last, mut yfy, mut c) = (usize::MAX, 0.0, 0.0);
        for k in 0..w.len() {
            let wk = w[k];
            let x = &rows[k * w3..(k + 1) * w3];
            let st_k = fs.station[k];
            if st_k != last {
                let f = &fs.cloud[st_k * n2..(st_k + 1) * n2];
                mat_vec(f, y, &mut fs.fy);
                yfy = dot(y, &fs.fy);
                c = 0.0;
                for i in 0..n {
                    c += yd[i] * dot(&f[i * n..(i + 1) * n], yd);
                }
                last = st_k;
            }
            for r in 0..3 {
                for j in 0..n {
                    fs.xhat[r * n + j] = x[r * n + j] - axis[r] * fs.fy[j];
                }
            }
            let mut xy = Vector3::zeros();
            let mut xhyd = Vector3::zeros();
            for r in 0..3 {
                xy[r] = dot(&x[r * n..(r + 1) * n], y);
                xhyd[r] = dot(&fs.xhat[r * n..(r + 1) * n], yd);
            }
            let rb = pos[k] + xy - axis * (0.5 * yfy);
            let r = r0 + a * rb;
            let axyd = a * xhyd;
            let acc = w_sd + om.cross(&om.cross(&r)) + 2.0 * om.cross(&axyd) - a_axis * c;
            msum += wk;
            gsum += wk * r;
            psum += (wk * r) * r.transpose();
            asum += wk * acc;
            tq += wk * r.cross(&acc);
            let wr = wk * r;
            let wacc = wk * acc;
            for j in 0..n {
                let v = a * Vector3::new(fs.xhat[j], fs.xhat[n + j], fs.xhat[2 * n + j]);
                for i in 0..3 {
                    ws.ax[i * n + j] = v[i];
                    ws.sy[i * n + j] += wk * v[i];
                }
                let rv = wr.cross(&v);
                for i in 0..3 {
                    ws.wy[i * n + j] += rv[i];
                }
                ws.qy[j] += wacc.dot(&v);
            }
            for i in 0..n {
                let p = [wk * ws.ax[i], wk * ws.ax[n + i], wk * ws.ax[2 * n + i]];
                for j in i..n {
                    ws.yy[i * n + j] +=
                        p[0] * ws.ax[j] + p[1] * ws.ax[n + j] + p[2] * ws.ax[2 * n + j];
                }
            }
        }
        // Full 3D layout {ṡ; ω; ẏ}; a planar body keeps x, y, θz.
        let (map, nr): ([Option<usize>; 6], usize) = match dim {
            Dim::Spatial => ([Some(0), Some(1), Some(2), Some(3), Some(4), Some(5)], 6),
            Dim::Planar => ([Some(0), Some(1), None, None, None, Some(2)], 3),
        };
        let jo = Matrix3::identity() * psum.trace() - psum;
        let gt = flexmbd_core::skew(&gsum);
        let mut rig = [[0.0; 6]; 6];
        for i in 0..3 {
            for j in 0..3 {
                rig[i][j] = if i == j { msum } else { 0.0 };
                rig[i][j + 3] = -gt[(i, j)];
                rig[i + 3][j] = gt[(i, j)];
                rig[i + 3][j + 3] = jo[(i, j)];
            }
        }
        let qr = [-asum.x, -asum.y, -asum.z, -tq.x, -tq.y, -tq.z];
        for (i, mi) in map.iter().enumerate() {
            let Some(oi) = *mi else { continue };
            for (j, mj) in map.iter().enumerate() {
                if let Some(oj) = *mj {
                    m_out[(oi, oj)] = rig[i][j];
                }
            }
            q_out[oi] = qr[i];
            for jm in 0..n {
                let v = if i < 3 {
                    ws.sy[i * n + jm]
                } else {
                    ws.wy[(i - 3) * n + jm]
                };
                m_out[(oi, nr + jm)] = v;
                m_out[(nr + jm, oi)] = v;
            }
        }
        write_modal_block(m_out, q_out, nr, n, &ws.yy, &ws.qy);
    }

    /// Planar natural coordinates {r0, u, y} (docs/methods.md §2.5) with FS0 kinematics, route
    /// (a): `B_k = [I₂  r̄_k1 I + r̄_k2 E  A X̂_k]`, `Ḃ_k q̇ = 2 Ȧ X̂_k ẏ − A ē₁ (ẏᵀF_k ẏ)`,
    /// with `A = [u  E u]` (not necessarily orthonormal) and the deformed r̄_k.
    pub(crate) fn natural_bmatrix_fs_2d<SM, SQ>(
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
        let fs = self
            .fs
            .as_ref()
            .expect("natural_bmatrix_fs_2d without FS0 data");
        let (y, yd) = (st.y, st.y_dot);
        let u = st.a.column(0).xy();
        let ud = st.a_dot.column(0).xy();
        let a = Matrix2::new(u.x, -u.y, u.y, u.x);
        let ad = Matrix2::new(ud.x, -ud.y, ud.y, ud.x);
        let e2 = |v: Vector2<f64>| Vector2::new(-v.y, v.x);
        let axis = fs.axis.xy();
        let a_axis = a * axis;
        let crate::Workspace {
            u: xh,
            gy: fy,
            ax,
            sy,
            wy,
            yy,
            qy,
            ..
        } = &mut nws.0;
        sy.fill(0.0);
        wy.fill(0.0);
        yy.fill(0.0);
        qy.fill(0.0);
        let mut msum = 0.0;
        let mut rsum = Vector2::zeros();
        let mut psum = 0.0;
        let mut asum = Vector2::zeros();
        let mut qu = Vector2::zeros();
        let (n2, w3) = (n * n, 3 * n);
        let (mut last, mut yfy, mut c) = (usize::MAX, 0.0, 0.0);
        for k in 0..self.w.len() {
            let wk = self.w[k];
            let x = &self.rows[k * w3..(k + 1) * w3];
            let (x0, x1) = (&x[..n], &x[n..2 * n]);
            let st_k = fs.station[k];
            if st_k != last {
                let f = &fs.cloud[st_k * n2..(st_k + 1) * n2];
                mat_vec(f, y, &mut fy[..n]);
                yfy = dot(y, &fy[..n]);
                c = 0.0;
                for i in 0..n {
                    c += yd[i] * dot(&f[i * n..(i + 1) * n], yd);
                }
                last = st_k;
            }
            for j in 0..n {
                xh[j] = x0[j] - axis.x * fy[j];
                xh[n + j] = x1[j] - axis.y * fy[j];
            }
            let (xh0, xh1) = (&xh[..n], &xh[n..2 * n]);
            let rb = self.pos[k].xy() + Vector2::new(dot(x0, y), dot(x1, y)) - axis * (0.5 * yfy);
            let acc = 2.0 * (ad * Vector2::new(dot(xh0, yd), dot(xh1, yd))) - a_axis * c;
            msum += wk;
            rsum += wk * rb;
            psum += wk * rb.norm_squared();
            asum += wk * acc;
            // (r̄1 I + r̄2 E)ᵀ a = r̄1 a − r̄2 E a.
            qu += wk * (rb.x * acc - rb.y * e2(acc));
            for j in 0..n {
                let v = a * Vector2::new(xh0[j], xh1[j]);
                ax[j] = v.x;
                ax[n + j] = v.y;
                sy[j] += wk * v.x;
                sy[n + j] += wk * v.y;
                let uy = rb.x * v - rb.y * e2(v);
                wy[j] += wk * uy.x;
                wy[n + j] += wk * uy.y;
                qy[j] += wk * acc.dot(&v);
            }
            for i in 0..n {
                let (p0, p1) = (wk * ax[i], wk * ax[n + i]);
                for j in i..n {
                    yy[i * n + j] += p0 * ax[j] + p1 * ax[n + j];
                }
            }
        }
        let sums = BMatrixSums2 {
            m: msum,
            mr: rsum,
            p: psum,
            a: asum,
            qu,
        };
        write_bmatrix_natural_2d(m_out, q_out, n, &sums, sy, wy, yy, qy);
    }

    /// Spatial natural coordinates {r0, u, v, w, y} (docs/methods.md §2.5) with FS0 kinematics,
    /// route (a): `B_k = [I  r̄_k1 I  r̄_k2 I  r̄_k3 I  A X̂_k]`,
    /// `Ḃ_k q̇ = 2 Ȧ X̂_k ẏ − A ē₁ (ẏᵀF_k ẏ)`, with `A = [u v w]` (not necessarily
    /// orthonormal) and the deformed r̄_k. The reference for the shape-integral route.
    pub(crate) fn natural_bmatrix_fs_3d<SM, SQ>(
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
        let fs = self
            .fs
            .as_ref()
            .expect("natural_bmatrix_fs_3d without FS0 data");
        let (y, yd) = (st.y, st.y_dot);
        let (a, ad) = (&st.a, &st.a_dot);
        let axis = fs.axis;
        let a_axis = a * axis;
        let crate::Workspace {
            u: xh,
            gy: fy,
            ax,
            sy,
            l,
            yy,
            qy,
            ..
        } = &mut nws.0;
        sy.fill(0.0);
        l.fill(0.0);
        yy.fill(0.0);
        qy.fill(0.0);
        let mut msum = 0.0;
        let mut rsum = Vector3::zeros();
        let mut psum = Matrix3::zeros();
        let mut asum = Vector3::zeros();
        let mut arsum = Matrix3::zeros(); // column b: Σ w r̄_b a_k
        let (n2, w3) = (n * n, 3 * n);
        let (mut last, mut yfy, mut c) = (usize::MAX, 0.0, 0.0);
        for k in 0..self.w.len() {
            let wk = self.w[k];
            let x = &self.rows[k * w3..(k + 1) * w3];
            let st_k = fs.station[k];
            if st_k != last {
                let f = &fs.cloud[st_k * n2..(st_k + 1) * n2];
                mat_vec(f, y, &mut fy[..n]);
                yfy = dot(y, &fy[..n]);
                c = 0.0;
                for i in 0..n {
                    c += yd[i] * dot(&f[i * n..(i + 1) * n], yd);
                }
                last = st_k;
            }
            for r in 0..3 {
                for j in 0..n {
                    xh[r * n + j] = x[r * n + j] - axis[r] * fy[j];
                }
            }
            let (x0, x1, x2) = (&x[..n], &x[n..2 * n], &x[2 * n..]);
            let rb =
                self.pos[k] + Vector3::new(dot(x0, y), dot(x1, y), dot(x2, y)) - axis * (0.5 * yfy);
            let xhyd = Vector3::new(
                dot(&xh[..n], yd),
                dot(&xh[n..2 * n], yd),
                dot(&xh[2 * n..3 * n], yd),
            );
            let acc = 2.0 * (ad * xhyd) - a_axis * c;
            msum += wk;
            rsum += wk * rb;
            psum += (wk * rb) * rb.transpose();
            asum += wk * acc;
            arsum += (wk * acc) * rb.transpose();
            let (ax0, rest) = ax.split_at_mut(n);
            let (ax1, ax2) = rest.split_at_mut(n);
            for j in 0..n {
                let v = a * Vector3::new(xh[j], xh[n + j], xh[2 * n + j]);
                ax0[j] = v.x;
                ax1[j] = v.y;
                ax2[j] = v.z;
                for cc in 0..3 {
                    sy[cc * n + j] += wk * v[cc];
                    for b in 0..3 {
                        l[3 * n * b + cc * n + j] += wk * rb[b] * v[cc];
                    }
                }
                qy[j] += wk * acc.dot(&v);
            }
            for (i, row) in yy.chunks_exact_mut(n).enumerate() {
                let (p0, p1, p2) = (wk * ax0[i], wk * ax1[i], wk * ax2[i]);
                for (((o, b0), b1), b2) in row.iter_mut().zip(&*ax0).zip(&*ax1).zip(&*ax2) {
                    *o += p0 * b0 + p1 * b1 + p2 * b2;
                }
            }
        }
        let sums = BMatrixSums3 {
            m: msum,
            mr: rsum,
            p: psum,
            a: asum,
            ar: arsum,
        };
        write_bmatrix_natural_3d(m_out, q_out, n, &sums, sy, l, yy, qy);
    }
}
