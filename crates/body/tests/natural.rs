//! Natural coordinates (docs/methods.md §2.5): routes (a) and (b) agree at random states
//! with a deliberately non-orthonormal A, and Q_v passes the virtual-power check
//! Σ w_k B_kᵀ r̈_k = M q̈ − Q_v with B_k = ∂r_k/∂q and r̈_k, q̈ from differencing.

mod common;
use common::*;
use flexmbd_body::{Dim, FlexibleBody, InertiaMethod, NaturalState};
use flexmbd_fe::ReducedBody;
use nalgebra::{DMatrix, DVector, Matrix3, Vector2, Vector3};

/// Unpack q = {r0; u; v; w; y} (3D) or {r0; u; y} (2D) into (r0, A, y).
fn unpack(dim: Dim, q: &DVector<f64>, n: usize) -> (Vector3<f64>, Matrix3<f64>, Vec<f64>) {
    match dim {
        Dim::Spatial => (
            Vector3::new(q[0], q[1], q[2]),
            Matrix3::from_column_slice(&q.as_slice()[3..12]),
            q.as_slice()[12..12 + n].to_vec(),
        ),
        Dim::Planar => (
            Vector3::new(q[0], q[1], 0.0),
            Matrix3::new(q[2], -q[3], 0.0, q[3], q[2], 0.0, 0.0, 0.0, 1.0),
            q.as_slice()[4..4 + n].to_vec(),
        ),
    }
}

fn state<'a>(
    dim: Dim,
    q: &DVector<f64>,
    qd: &DVector<f64>,
    y: &'a [f64],
    yd: &'a [f64],
) -> NaturalState<'a> {
    match dim {
        Dim::Spatial => NaturalState {
            r0: Vector3::new(q[0], q[1], q[2]),
            a: Matrix3::from_column_slice(&q.as_slice()[3..12]),
            r0_dot: Vector3::new(qd[0], qd[1], qd[2]),
            a_dot: Matrix3::from_column_slice(&qd.as_slice()[3..12]),
            y,
            y_dot: yd,
        },
        Dim::Planar => NaturalState::planar(
            Vector2::new(q[0], q[1]),
            Vector2::new(q[2], q[3]),
            Vector2::new(qd[0], qd[1]),
            Vector2::new(qd[2], qd[3]),
            y,
            yd,
        ),
    }
}

fn positions(rb: &ReducedBody, dim: Dim, q: &DVector<f64>) -> DVector<f64> {
    let n = rb.cloud.n_modes;
    let (r0, a, y) = unpack(dim, q, n);
    let np = rb.cloud.len();
    let mut out = DVector::zeros(3 * np);
    for k in 0..np {
        out.fixed_rows_mut::<3>(3 * k)
            .copy_from(&(r0 + a * cloud_point(rb, k, &y)));
    }
    out
}

fn nq(dim: Dim, n: usize) -> usize {
    if dim == Dim::Spatial { 12 + n } else { 4 + n }
}

/// q(t) = q0 + q1 t + q2 sin(1.3 t + φ), componentwise (A drifts off orthonormality).
fn motion(seed: u64, dim: Dim, n: usize) -> impl Fn(f64) -> DVector<f64> {
    let mut r = rng(seed);
    let m = nq(dim, n);
    let c: Vec<[f64; 4]> = (0..m)
        .map(|_| {
            [
                uni(&mut r, -1.0, 1.0),
                uni(&mut r, -1.0, 1.0),
                uni(&mut r, -0.5, 0.5),
                uni(&mut r, 0.0, 3.0),
            ]
        })
        .collect();
    let nr = m - n;
    move |t: f64| {
        DVector::from_fn(m, |i, _| {
            let s = if i >= nr { 0.3 } else { 1.0 };
            s * (c[i][0] + c[i][1] * t + c[i][2] * (1.3 * t + c[i][3]).sin())
        })
    }
}

#[test]
fn natural_routes_agree() {
    for (dim, n, seed) in [
        (Dim::Spatial, 0, 1),
        (Dim::Spatial, 5, 2),
        (Dim::Planar, 0, 3),
        (Dim::Planar, 4, 4),
    ] {
        let mut r = rng(seed);
        let rb = random_body(&mut r, dim, n, 23);
        let body = FlexibleBody::new(&rb).unwrap();
        let mut ws = body.natural_workspace();
        let qf = motion(seed + 10, dim, n);
        for i in 0..10 {
            let t = 0.3 * i as f64;
            let q = qf(t);
            let qd = (qf(t + 1e-3) - qf(t - 1e-3)) / 2e-3;
            let (_, _, y) = unpack(dim, &q, n);
            let yd = qd.as_slice()[qd.len() - n..].to_vec();
            let st = state(dim, &q, &qd, &y, &yd);
            let (ma, qa) = eval_natural(&body, &mut ws, &st, InertiaMethod::BMatrix);
            let (mb, qb) = eval_natural(&body, &mut ws, &st, InertiaMethod::ShapeIntegrals);
            let (dm, dq) = (rel_diff_m(&ma, &mb), rel_diff_v(&qa, &qb));
            assert!(dm < 1e-10 && dq < 1e-10, "{dim} n={n}: M {dm:e}, Q {dq:e}");
            assert!(rel_diff_m(&ma, &ma.transpose()) < 1e-15);
        }
    }
}

#[test]
fn natural_virtual_power_and_gravity() {
    for (dim, n, seed) in [
        (Dim::Spatial, 0, 5),
        (Dim::Spatial, 4, 6),
        (Dim::Planar, 0, 7),
        (Dim::Planar, 3, 8),
    ] {
        let mut r = rng(seed);
        let rb = random_body(&mut r, dim, n, 13);
        let body = FlexibleBody::new(&rb).unwrap();
        let mut ws = body.natural_workspace();
        let qf = motion(seed + 20, dim, n);
        let m = nq(dim, n);
        let h = 1e-3;
        for &t in &[0.1, 0.8] {
            let q = qf(t);
            let qd = d1(&qf, t, h);
            let qdd = d2(&qf, t, h);
            let rdd = d2(|t: f64| positions(&rb, dim, &qf(t)), t, h);
            // B = ∂r/∂q by central differences (r is linear in r0, A, and in y: exact).
            let mut bmat = DMatrix::zeros(3 * rb.cloud.len(), m);
            for i in 0..m {
                let mut qp = q.clone();
                let mut qm = q.clone();
                qp[i] += 1e-4;
                qm[i] -= 1e-4;
                bmat.set_column(
                    i,
                    &((positions(&rb, dim, &qp) - positions(&rb, dim, &qm)) / 2e-4),
                );
            }
            let wdiag = DVector::from_fn(3 * rb.cloud.len(), |i, _| rb.cloud.weights[i / 3]);
            let lhs = bmat.transpose() * rdd.component_mul(&wdiag);
            let (_, _, y) = unpack(dim, &q, n);
            let yd = qd.as_slice()[m - n..].to_vec();
            let st = state(dim, &q, &qd, &y, &yd);
            let g = if dim == Dim::Planar {
                Vector3::new(0.3, -9.81, 0.0)
            } else {
                Vector3::new(0.3, -9.81, 1.2)
            };
            let g_ref =
                bmat.transpose() * DVector::from_fn(3 * rb.cloud.len(), |i, _| wdiag[i] * g[i % 3]);
            for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
                let (mm, qv) = eval_natural(&body, &mut ws, &st, method);
                let d = rel_diff_v(&(&mm * &qdd - &qv), &lhs);
                assert!(d < 1e-7, "{dim} n={n} {method:?}: virtual power {d:e}");
                // M = Σ w B_kᵀ B_k with the differenced B.
                let mref = bmat.transpose() * DMatrix::from_diagonal(&wdiag) * &bmat;
                assert!(
                    rel_diff_m(&mm, &mref) < 1e-8,
                    "{dim} {method:?} M vs Σ w BᵀB"
                );
                if n > 0 {
                    assert!(qv.amax() > 1e-3 * lhs.amax());
                }
            }
            let mut gq = vec![0.0; m];
            body.gravity_natural(&st, &g, &mut gq);
            let dg = rel_diff_v(&DVector::from_vec(gq), &g_ref);
            assert!(dg < 1e-8, "{dim} gravity rows {dg:e}");
        }
    }
}
