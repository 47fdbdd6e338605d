//! Independent checks of the inertia formulas, not using B_k or Ḃ_k:
//!
//! * kinetic energy: ½ Zᵀ M̄ Z = ½ Σ w_k |ṙ_k|² with ṙ_k from differencing the point
//!   positions along a motion (docs/methods.md §8 item 4);
//! * virtual power / Jourdain: along a smooth prescribed motion,
//!   Σ w_k B_kᵀ r̈_k (r̈_k from differencing positions) = M̄ Ż − Q̄_v (§8 item 5),
//!   with Ż = {s̈; ω̇; ÿ} also from differencing. This catches a sign error common to
//!   both routes. The B_kᵀ used to project is the velocity Jacobian ∂ṙ_k/∂Z written
//!   afresh from the velocity law; Ḃ_k is never used.

mod common;
use common::*;
use flexmbd_body::{Dim, FlexibleBody, InertiaMethod};
use flexmbd_fe::ReducedBody;
use nalgebra::{DVector, Matrix3, Vector3};

/// A smooth motion: r0(t), A(t) = Rz(α) Ry(β) Rx(γ) (3D) or Rz(α) (2D), y(t).
struct Motion {
    dim: Dim,
    c: [[f64; 3]; 12],
    n: usize,
    yc: Vec<[f64; 3]>,
}

fn f(c: &[f64; 3], t: f64) -> f64 {
    c[0] + c[1] * t + c[2] * (1.3 * t + 0.4 * c[0]).sin()
}

impl Motion {
    fn new(seed: u64, dim: Dim, n: usize) -> Self {
        let mut r = rng(seed);
        let mut c = [[0.0; 3]; 12];
        for row in c.iter_mut() {
            for v in row.iter_mut() {
                *v = uni(&mut r, -1.0, 1.0);
            }
        }
        let yc = (0..n)
            .map(|_| {
                [
                    uni(&mut r, -0.3, 0.3),
                    uni(&mut r, -0.5, 0.5),
                    uni(&mut r, -0.5, 0.5),
                ]
            })
            .collect();
        Self { dim, c, n, yc }
    }
}

impl PrescribedMotion for Motion {
    fn r0(&self, t: f64) -> Vector3<f64> {
        let z = if self.dim == Dim::Planar {
            0.0
        } else {
            f(&self.c[2], t)
        };
        Vector3::new(f(&self.c[0], t), f(&self.c[1], t), z)
    }
    fn a(&self, t: f64) -> Matrix3<f64> {
        let alpha = f(&self.c[3], t);
        if self.dim == Dim::Planar {
            return rot_z(alpha);
        }
        rz_ry_rx(alpha, f(&self.c[4], t), f(&self.c[5], t))
    }
    fn y(&self, t: f64) -> Vec<f64> {
        (0..self.n).map(|j| f(&self.yc[j], t)).collect()
    }
}

fn positions(rb: &ReducedBody, m: &Motion, t: f64) -> DVector<f64> {
    let (r0, a, y) = (m.r0(t), m.a(t), m.y(t));
    let np = rb.cloud.len();
    let mut out = DVector::zeros(3 * np);
    for k in 0..np {
        let r = r0 + a * cloud_point(rb, k, &y);
        out.fixed_rows_mut::<3>(3 * k).copy_from(&r);
    }
    out
}

fn check(seed: u64, dim: Dim, n: usize) {
    let mut r = rng(seed);
    let rb = random_body(&mut r, dim, n, 13);
    let mut body = FlexibleBody::new(&rb).unwrap();
    let m = Motion::new(seed + 100, dim, n);
    let h = 1e-3;
    for &t in &[0.0, 0.37, 1.1] {
        // Ż by differencing Z(t) (itself from differences of an analytic motion).
        let sample = MotionSample::new(&m, dim, t, h);
        let (st, z, zd) = (sample.state.view(), &sample.z, &sample.z_dot);
        let rdot = d1(|t| positions(&rb, &m, t), t, h);
        let rddot = d2(|t| positions(&rb, &m, t), t, h);
        // Velocity Jacobian column i = ṙ_k at the unit velocity Z = e_i, straight from the
        // velocity law ṙ = ṡ + ω × r + A X ẏ (§1.1, §4.1), not from the crate's B_k code.
        let nc = body.n_coords();
        let pos_now = positions(&rb, &m, t);
        let np = rb.cloud.len();
        let a = m.a(t);
        let jac = |i: usize| -> DVector<f64> {
            let mut ev = DVector::zeros(nc);
            ev[i] = 1.0;
            let (sd, w, ydv) = match dim {
                Dim::Spatial => (
                    Vector3::new(ev[0], ev[1], ev[2]),
                    Vector3::new(ev[3], ev[4], ev[5]),
                    ev.rows(6, n).iter().copied().collect::<Vec<_>>(),
                ),
                Dim::Planar => (
                    Vector3::new(ev[0], ev[1], 0.0),
                    Vector3::new(0.0, 0.0, ev[2]),
                    ev.rows(3, n).iter().copied().collect::<Vec<_>>(),
                ),
            };
            let mut out = DVector::zeros(3 * np);
            for k in 0..np {
                let x = rb.cloud.rows(k);
                let rk = pos_now.fixed_rows::<3>(3 * k).into_owned();
                let mut dxy = Vector3::zeros();
                for c in 0..3 {
                    for j in 0..n {
                        dxy[c] += x[c * n + j] * ydv[j];
                    }
                }
                let v = sd + w.cross(&rk) + a * dxy;
                out.fixed_rows_mut::<3>(3 * k).copy_from(&v);
            }
            out
        };
        let bt: Vec<DVector<f64>> = (0..nc).map(jac).collect();
        let mut lhs = DVector::zeros(nc);
        let mut ke = 0.0;
        for k in 0..np {
            let w = rb.cloud.weights[k];
            let acc = rddot.fixed_rows::<3>(3 * k);
            for i in 0..nc {
                lhs[i] += w * bt[i].fixed_rows::<3>(3 * k).dot(&acc);
            }
            ke += 0.5 * w * rdot.fixed_rows::<3>(3 * k).norm_squared();
        }
        for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
            let (mm, qv) = eval(&mut body, &st, method);
            let rhs = &mm * zd - &qv;
            let d = rel_diff_v(&rhs, &lhs);
            eprintln!(
                "{dim} n={n} {method:?} t={t}: virtual power rel diff {d:.1e}, |Q_v|/|lhs| = {:.2}",
                qv.amax() / lhs.amax()
            );
            assert!(
                d < 1e-7,
                "{dim} n={n} {method:?}: Σ w Bᵀ r̈ vs M̄Ż − Q̄_v: {d:e}"
            );
            let ke_m = 0.5 * z.dot(&(&mm * z));
            assert!(
                (ke_m - ke).abs() < 1e-8 * ke,
                "{dim} {method:?}: T {ke_m} vs {ke}"
            );
            // The sign check is meaningful only if Q̄_v is not negligible.
            assert!(qv.amax() > 1e-3 * lhs.amax());
        }
    }
}

#[test]
fn virtual_power_and_energy_3d() {
    check(1, Dim::Spatial, 0);
    check(2, Dim::Spatial, 4);
}

#[test]
fn virtual_power_and_energy_2d() {
    check(3, Dim::Planar, 0);
    check(4, Dim::Planar, 3);
}

/// The origin form {ṙ0, ω, ẏ} against its own B-matrix written out here:
/// B_k = [I  −(A r̄_k)~  A X_k], Ḃ_k Z_0 = ω × (ω × A r̄_k) + 2 ω × A X_k ẏ.
#[test]
fn origin_form_against_direct_projection() {
    for (dim, n, seed) in [
        (Dim::Spatial, 4, 41),
        (Dim::Spatial, 0, 42),
        (Dim::Planar, 3, 43),
    ] {
        let mut r = rng(seed);
        let rb = random_body(&mut r, dim, n, 11);
        let mut body = FlexibleBody::new(&rb).unwrap();
        for _ in 0..5 {
            let st = random_state(&mut r, dim, n);
            let v = st.view();
            let r0d = v.r0_dot();
            let full = 6 + n;
            let mut mref = nalgebra::DMatrix::zeros(full, full);
            let mut qref = DVector::zeros(full);
            for k in 0..rb.cloud.len() {
                let x = rb.cloud.rows(k);
                let mut rbk = rb.cloud.positions[k];
                let mut xyd = Vector3::zeros();
                for c in 0..3 {
                    for j in 0..n {
                        rbk[c] += x[c * n + j] * v.y[j];
                        xyd[c] += x[c * n + j] * v.y_dot[j];
                    }
                }
                let rho = v.a * rbk;
                let mut b = nalgebra::DMatrix::zeros(3, full);
                b.view_mut((0, 0), (3, 3)).copy_from(&Matrix3::identity());
                b.view_mut((0, 3), (3, 3))
                    .copy_from(&(-flexmbd_core::skew(&rho)));
                for j in 0..n {
                    let mut col = Vector3::zeros();
                    for c in 0..3 {
                        col[c] = x[c * n + j];
                    }
                    b.view_mut((0, 6 + j), (3, 1)).copy_from(&(v.a * col));
                }
                let w = v.omega;
                let bd = w.cross(&w.cross(&rho)) + 2.0 * w.cross(&(v.a * xyd));
                let wk = rb.cloud.weights[k];
                mref += wk * b.transpose() * &b;
                qref -= wk * b.transpose() * bd;
            }
            let _ = r0d;
            let keep = kept_rows(dim, n);
            let nc = keep.len();
            let mref = nalgebra::DMatrix::from_fn(nc, nc, |i, j| mref[(keep[i], keep[j])]);
            let qref = DVector::from_fn(nc, |i, _| qref[keep[i]]);
            for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
                let mut m = nalgebra::DMatrix::zeros(nc, nc);
                let mut q = DVector::zeros(nc);
                body.inertia_origin(&v, method, &mut m, &mut q);
                assert!(rel_diff_m(&m, &mref) < 1e-12, "{dim} {method:?} M̄_0");
                assert!(rel_diff_v(&q, &qref) < 1e-12, "{dim} {method:?} Q̄_v0");
            }
        }
    }
}
