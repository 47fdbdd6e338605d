//! Body points, coordinate packing and the gravity potential in natural coordinates
//! (docs/methods.md §2.6, §3.3), beside the inertia terms of `natural.rs`.
//!
//! Coordinate order of one body (as in `natural.rs`):
//!
//! ```text
//! 3D:  q_b = {r0 (3); u (3); v (3); w (3); y (n)}   12 + n,  A = [u v w]
//! 2D:  q_b = {r0 (2); u (2); y (n)}                  4 + n,  A = [u  E u]
//! ```
//!
//! A body point P (a [`BodyPoint`]: undeformed `r̄_P`, mode rows `X_P`, zero for a
//! rigid point) is at `r_P = r0 + A (r̄_P + X_P y)` (§1.1, §3.3). With
//! `r̄' = r̄_P + X_P y`:
//!
//! * Jacobian `∂r_P/∂q_b`: 3D `[I  r̄'_1 I  r̄'_2 I  r̄'_3 I  A X_P]` (3 × (12 + n)),
//!   2D `[I  r̄'_1 I + r̄'_2 E  A X_P]` (2 × (4 + n); the `E u` axis folds into `u`
//!   through `∂(E u)/∂u = E`, §2.6 "2D absolute rows");
//! * velocity `ṙ_P = ṙ0 + Ȧ r̄' + A X_P ẏ` (= Jacobian · q̇);
//! * bias: `r_P` is bilinear in (A, y), so `r̈_P = (∂r_P/∂q) q̈ + 2 Ȧ X_P ẏ` (§3.3);
//! * point force `f` at P: generalized force `(∂r_P/∂q)ᵀ f` (§2.6 point-force rows).
//!
//! Gravity potential: `V = −gᵀ (m r0 + A m̄(y))`, `m̄(y) = m̄_u + S y`, whose `−∂V/∂q`
//! is [`FlexibleBody::gravity_natural`]. The kinetic energy is `½ q̇ᵀ M q̇` with the
//! caller's `M` from [`FlexibleBody::inertia_natural`].
//!
//! Everything here is allocation-free.

use crate::{BodyPoint, FlexibleBody, NaturalState, dot};
use flexmbd_core::Dim;
use nalgebra::{Dyn, Matrix, StorageMut, Vector2, Vector3};

fn natural_rigid(dim: Dim) -> usize {
    match dim {
        Dim::Spatial => 12,
        Dim::Planar => 4,
    }
}

impl<'a> NaturalState<'a> {
    /// Read a state from one body's coordinate and velocity slices in the order of
    /// the module doc (3D `{r0, u, v, w, y}`, 2D `{r0, u, y}`); `y` and `y_dot`
    /// borrow the tails of `q` and `q_dot`.
    ///
    /// # Panics
    /// If `q` and `q_dot` differ in length or are shorter than the rigid part.
    pub fn from_coords(dim: Dim, q: &'a [f64], q_dot: &'a [f64]) -> Self {
        assert_eq!(q.len(), q_dot.len(), "from_coords: q and q_dot lengths");
        match dim {
            Dim::Spatial => {
                assert!(q.len() >= 12, "from_coords: 3D needs 12 + n entries");
                let v = |s: &[f64], i: usize| Vector3::new(s[i], s[i + 1], s[i + 2]);
                let m = |s: &[f64]| nalgebra::Matrix3::from_columns(&[v(s, 3), v(s, 6), v(s, 9)]);
                Self {
                    r0: v(q, 0),
                    a: m(q),
                    r0_dot: v(q_dot, 0),
                    a_dot: m(q_dot),
                    y: &q[12..],
                    y_dot: &q_dot[12..],
                }
            }
            Dim::Planar => {
                assert!(q.len() >= 4, "from_coords: 2D needs 4 + n entries");
                let v = |s: &[f64], i: usize| Vector2::new(s[i], s[i + 1]);
                Self::planar(
                    v(q, 0),
                    v(q, 2),
                    v(q_dot, 0),
                    v(q_dot, 2),
                    &q[4..],
                    &q_dot[4..],
                )
            }
        }
    }

    /// Write the coordinates and velocities into slices of length 12 + n (3D) or
    /// 4 + n (2D); the inverse of [`NaturalState::from_coords`].
    pub fn to_coords(&self, dim: Dim, q: &mut [f64], q_dot: &mut [f64]) {
        let n = self.y.len();
        let nr = natural_rigid(dim);
        assert_eq!(q.len(), nr + n, "to_coords: q length");
        assert_eq!(q_dot.len(), nr + n, "to_coords: q_dot length");
        let nt = dim.n_trans();
        let na = if dim == Dim::Planar { 1 } else { 3 };
        for i in 0..nt {
            q[i] = self.r0[i];
            q_dot[i] = self.r0_dot[i];
            for a in 0..na {
                q[nt * (1 + a) + i] = self.a[(i, a)];
                q_dot[nt * (1 + a) + i] = self.a_dot[(i, a)];
            }
        }
        q[nr..].copy_from_slice(self.y);
        q_dot[nr..].copy_from_slice(self.y_dot);
    }
}

impl FlexibleBody {
    /// Gravitational potential energy `V = −gᵀ (m r0 + A m̄(y))` (J) in natural
    /// coordinates; `−∂V/∂q` is [`FlexibleBody::gravity_natural`]. 2D uses g.x, g.y.
    pub fn natural_potential_energy(&self, st: &NaturalState<'_>, g: &Vector3<f64>) -> f64 {
        let mb = self.first_moment_at(st.y);
        let lever = self.mass * st.r0 + st.a * mb;
        match self.dim {
            Dim::Spatial => -g.dot(&lever),
            Dim::Planar => -(g.x * lever.x + g.y * lever.y),
        }
    }

    fn point_check(&self, st: &NaturalState<'_>, p: &BodyPoint) {
        assert_eq!(p.n_modes(), self.n, "point: X_P must have n columns");
        assert_eq!(st.y.len(), self.n, "point: y must have n entries");
        assert_eq!(st.y_dot.len(), self.n, "point: y_dot must have n entries");
    }

    /// Global position of a body point, `r_P = r0 + A (r̄_P + X_P y)` (2D: z = 0).
    pub fn point_position(&self, st: &NaturalState<'_>, p: &BodyPoint) -> Vector3<f64> {
        self.point_check(st, p);
        let mut r = st.r0 + st.a * p.local_position(st.y);
        if self.dim == Dim::Planar {
            r.z = 0.0;
        }
        r
    }

    /// Global velocity of a body point, `ṙ_P = ṙ0 + Ȧ (r̄_P + X_P y) + A X_P ẏ`.
    pub fn point_velocity(&self, st: &NaturalState<'_>, p: &BodyPoint) -> Vector3<f64> {
        self.point_check(st, p);
        let mut v =
            st.r0_dot + st.a_dot * p.local_position(st.y) + st.a * p.modal_velocity(st.y_dot);
        if self.dim == Dim::Planar {
            v.z = 0.0;
        }
        v
    }

    /// Acceleration bias of a body point, `2 Ȧ X_P ẏ`:
    /// `r̈_P = (∂r_P/∂q) q̈ + 2 Ȧ X_P ẏ` (2D: z = 0).
    pub fn point_bias(&self, st: &NaturalState<'_>, p: &BodyPoint) -> Vector3<f64> {
        self.point_check(st, p);
        let mut b = 2.0 * st.a_dot * p.modal_velocity(st.y_dot);
        if self.dim == Dim::Planar {
            b.z = 0.0;
        }
        b
    }

    /// `∂r_P/∂q_b` written into `out` (3 × (12 + n) in 3D, 2 × (4 + n) in 2D; every
    /// entry overwritten). See the module doc for the blocks.
    pub fn point_jacobian<S>(
        &self,
        st: &NaturalState<'_>,
        p: &BodyPoint,
        out: &mut Matrix<f64, Dyn, Dyn, S>,
    ) where
        S: StorageMut<f64, Dyn, Dyn>,
    {
        self.point_check(st, p);
        let n = self.n;
        let rb = p.local_position(st.y);
        let x = &p.rows;
        match self.dim {
            Dim::Spatial => {
                assert_eq!(
                    out.shape(),
                    (3, 12 + n),
                    "point_jacobian: out must be 3x(12+n)"
                );
                for i in 0..3 {
                    for j in 0..3 {
                        let d = if i == j { 1.0 } else { 0.0 };
                        out[(i, j)] = d;
                        for ax in 0..3 {
                            out[(i, 3 + 3 * ax + j)] = d * rb[ax];
                        }
                    }
                }
                for j in 0..n {
                    let axj = st.a * Vector3::new(x[j], x[n + j], x[2 * n + j]);
                    for i in 0..3 {
                        out[(i, 12 + j)] = axj[i];
                    }
                }
            }
            Dim::Planar => {
                assert_eq!(
                    out.shape(),
                    (2, 4 + n),
                    "point_jacobian: out must be 2x(4+n)"
                );
                out[(0, 0)] = 1.0;
                out[(0, 1)] = 0.0;
                out[(1, 0)] = 0.0;
                out[(1, 1)] = 1.0;
                // r̄'_1 I + r̄'_2 E = [r̄'_1 −r̄'_2; r̄'_2 r̄'_1].
                out[(0, 2)] = rb.x;
                out[(0, 3)] = -rb.y;
                out[(1, 2)] = rb.y;
                out[(1, 3)] = rb.x;
                let a2 = st.a.fixed_view::<2, 2>(0, 0);
                for j in 0..n {
                    let axj = a2 * Vector2::new(x[j], x[n + j]);
                    out[(0, 4 + j)] = axj.x;
                    out[(1, 4 + j)] = axj.y;
                }
            }
        }
    }

    /// Add the generalized force of a global force `f` applied at a body point,
    /// `(∂r_P/∂q)ᵀ f` (docs/methods.md §2.6: 3D `{f; r̄'_1 f; r̄'_2 f; r̄'_3 f; X_Pᵀ Aᵀ f}`,
    /// 2D `{f; (r̄'_1 I − r̄'_2 E) f; X_Pᵀ Aᵀ f}`), to `out` (length 12 + n or 4 + n).
    pub fn add_point_force(
        &self,
        st: &NaturalState<'_>,
        p: &BodyPoint,
        f: &Vector3<f64>,
        out: &mut [f64],
    ) {
        self.point_check(st, p);
        let n = self.n;
        let nr = natural_rigid(self.dim);
        assert_eq!(
            out.len(),
            nr + n,
            "add_point_force: out must have {} entries",
            nr + n
        );
        let rb = p.local_position(st.y);
        let x = &p.rows;
        match self.dim {
            Dim::Spatial => {
                for c in 0..3 {
                    out[c] += f[c];
                    for ax in 0..3 {
                        out[3 + 3 * ax + c] += rb[ax] * f[c];
                    }
                }
                let fb = st.a.tr_mul(f);
                for j in 0..n {
                    let xj = [x[j], x[n + j], x[2 * n + j]];
                    out[12 + j] += dot(&xj, fb.as_slice());
                }
            }
            Dim::Planar => {
                // (r̄'_1 I − r̄'_2 E) f = (r̄'_1 f_x + r̄'_2 f_y, r̄'_1 f_y − r̄'_2 f_x).
                out[0] += f.x;
                out[1] += f.y;
                out[2] += rb.x * f.x + rb.y * f.y;
                out[3] += rb.x * f.y - rb.y * f.x;
                let a2 = st.a.fixed_view::<2, 2>(0, 0);
                let fb = a2.tr_mul(&f.xy());
                for j in 0..n {
                    out[4 + j] += x[j] * fb.x + x[n + j] * fb.y;
                }
            }
        }
    }
}
