//! Route (a) (B-matrix projection) and route (b) (shape integrals) agree to round-off
//! on the same cloud at random states (docs/methods.md §2.7, §8 item 3).

mod common;
use common::*;
use flexmbd_body::{BodyState, Dim, FlexibleBody, InertiaMethod};
use nalgebra::{DMatrix, DVector};
use std::ops::AddAssign;

const TOL: f64 = 1e-10;

fn check_body(seed: u64, dim: Dim, n: usize, np: usize, states: usize) -> (f64, f64) {
    let mut r = rng(seed);
    let rb = random_body(&mut r, dim, n, np);
    let mut body = FlexibleBody::new(&rb).unwrap();
    let mut worst = (0.0f64, 0.0f64);
    for _ in 0..states {
        let st = random_state(&mut r, dim, n);
        let (ma, qa) = eval(&mut body, &st.view(), InertiaMethod::BMatrix);
        let (mb, qb) = eval(&mut body, &st.view(), InertiaMethod::ShapeIntegrals);
        let dm = rel_diff_m(&ma, &mb);
        let dq = rel_diff_v(&qa, &qb);
        assert!(dm < TOL, "{dim} n={n}: M̄ routes differ by {dm:e}");
        assert!(dq < TOL, "{dim} n={n}: Q̄_v routes differ by {dq:e}");
        // Symmetry of M̄.
        assert!(rel_diff_m(&ma, &ma.transpose()) < 1e-15);
        assert!(rel_diff_m(&mb, &mb.transpose()) < 1e-15);
        worst = (worst.0.max(dm), worst.1.max(dq));
    }
    worst
}

#[test]
fn routes_agree_3d_with_modes() {
    for (seed, n) in [(1, 1), (2, 3), (3, 8), (4, 12)] {
        let w = check_body(seed, Dim::Spatial, n, 37, 25);
        eprintln!("3D n={n}: max rel diff M̄ {:.1e}, Q̄_v {:.1e}", w.0, w.1);
    }
}

#[test]
fn routes_agree_3d_rigid() {
    let w = check_body(11, Dim::Spatial, 0, 9, 25);
    eprintln!("3D n=0: {:.1e} {:.1e}", w.0, w.1);
}

#[test]
fn routes_agree_2d_with_modes() {
    for (seed, n) in [(5, 1), (6, 4), (7, 8)] {
        let w = check_body(seed, Dim::Planar, n, 29, 25);
        eprintln!("2D n={n}: max rel diff M̄ {:.1e}, Q̄_v {:.1e}", w.0, w.1);
    }
}

#[test]
fn routes_agree_2d_rigid() {
    check_body(12, Dim::Planar, 0, 7, 25);
}

/// The lean 2D path equals the 3D formulas with third components zero, keeping the
/// x, y, θz rows and columns (docs/methods.md §0 reduction rule), for both routes.
#[test]
fn planar_path_equals_3d_extraction() {
    let keep = |n: usize| -> Vec<usize> {
        let mut v = vec![0, 1, 5];
        v.extend(6..6 + n);
        v
    };
    for (seed, n) in [(21, 0), (22, 2), (23, 6)] {
        let mut r = rng(seed);
        let rb2 = random_body(&mut r, Dim::Planar, n, 17);
        let mut rb3 = rb2.clone();
        rb3.dim = Dim::Spatial;
        let mut b2 = FlexibleBody::new(&rb2).unwrap();
        let mut b3 = FlexibleBody::new(&rb3).unwrap();
        let idx = keep(n);
        for _ in 0..10 {
            let st = random_state(&mut r, Dim::Planar, n);
            for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
                let (m2, q2) = eval(&mut b2, &st.view(), method);
                let (m3, q3) = eval(&mut b3, &st.view(), method);
                let m3r = DMatrix::from_fn(3 + n, 3 + n, |i, j| m3[(idx[i], idx[j])]);
                let q3r = DVector::from_fn(3 + n, |i, _| q3[idx[i]]);
                assert!(rel_diff_m(&m2, &m3r) < TOL, "{method:?} M̄ 2D vs 3D");
                assert!(rel_diff_v(&q2, &q3r) < TOL, "{method:?} Q̄ 2D vs 3D");
                // No out-of-plane inertia force (the θx, θy rows may carry moments,
                // which the plane's constraint balances).
                assert!(q3[2].abs() < 1e-12 * q3.amax().max(1.0), "Q̄_z = {}", q3[2]);
            }
        }
    }
}

/// Views work as outputs: writing into a block of a larger matrix.
#[test]
fn writes_into_views() {
    let mut r = rng(31);
    let rb = random_body(&mut r, Dim::Spatial, 3, 10);
    let mut body = FlexibleBody::new(&rb).unwrap();
    let st = random_state(&mut r, Dim::Spatial, 3);
    let (m, q) = eval(&mut body, &st.view(), InertiaMethod::ShapeIntegrals);
    let mut big = DMatrix::zeros(12, 12);
    let mut bq = DVector::zeros(12);
    body.inertia(
        &st.view(),
        InertiaMethod::ShapeIntegrals,
        &mut big.view_mut((2, 2), (9, 9)),
        &mut bq.rows_mut(3, 9),
    );
    assert_eq!(big.view((2, 2), (9, 9)).into_owned(), m);
    assert_eq!(bq.rows(3, 9).into_owned(), q);
    let _ = BodyState::planar;
}

/// Gravity in the s form equals Σ w_k B_kᵀ g, and the elastic force is −K y − C ẏ
/// with tangents K and C.
#[test]
fn gravity_and_elastic_rows() {
    for (dim, n, seed) in [
        (Dim::Spatial, 3, 51),
        (Dim::Spatial, 0, 52),
        (Dim::Planar, 4, 53),
    ] {
        let mut r = rng(seed);
        let rb = random_body(&mut r, dim, n, 9);
        let body = FlexibleBody::new(&rb).unwrap();
        let st = random_state(&mut r, dim, n);
        let v = st.view();
        let g = if dim == Dim::Planar {
            nalgebra::Vector3::new(0.4, -9.81, 0.0)
        } else {
            nalgebra::Vector3::new(0.4, -9.81, 2.0)
        };
        let mut refv = DVector::zeros(6 + n);
        for k in 0..rb.cloud.len() {
            let x = rb.cloud.rows(k);
            let rk = v.r0 + v.a * cloud_point(&rb, k, v.y);
            let w = rb.cloud.weights[k];
            refv.rows_mut(0, 3).add_assign(&(w * g));
            refv.rows_mut(3, 3).add_assign(&(w * rk.cross(&g)));
            for j in 0..n {
                let col = nalgebra::Vector3::new(x[j], x[n + j], x[2 * n + j]);
                refv[6 + j] += w * (v.a * col).dot(&g);
            }
        }
        let keep = kept_rows(dim, n);
        let refv = DVector::from_fn(keep.len(), |i, _| refv[keep[i]]);
        let mut out = vec![0.0; body.n_coords()];
        body.gravity_forces(&v, &g, &mut out);
        assert!(
            rel_diff_v(&DVector::from_vec(out), &refv) < 1e-12,
            "{dim} gravity"
        );

        let mut qel = vec![0.0; n];
        body.elastic_forces(v.y, v.y_dot, &mut qel);
        let yv = DVector::from_column_slice(v.y);
        let ydv = DVector::from_column_slice(v.y_dot);
        let expect = -(&rb.k_ff * &yv) - &rb.c_ff * &ydv;
        if n > 0 {
            assert!(rel_diff_v(&DVector::from_vec(qel), &expect) < 1e-14);
        }
        let mut kt = DMatrix::zeros(n, n);
        body.add_elastic_tangents(v.y, v.y_dot, 2.0, 0.5, kt.view_mut((0, 0), (n, n)));
        assert!((kt - (2.0 * &rb.k_ff + 0.5 * &rb.c_ff)).amax() < 1e-12);
        assert_eq!(body.elastic_model().name(), "linear");
    }
}

/// An imported solid (the CalculiX export of a steel bar of hex8 bricks, clamped at one end
/// with static modes of the other): its cloud rewrites the consistent mass matrix exactly,
/// with negative node weights, and both routes agree on it as on any cloud.
#[test]
fn routes_agree_on_an_imported_solid() {
    let rb = flexmbd_test_support::samples::imported_bar(false);
    assert!(rb.cloud.weights.iter().any(|w| *w < 0.0));
    let n = rb.n_modes();
    let mut body = FlexibleBody::new(&rb).unwrap();
    let mut r = rng(31);
    for _ in 0..10 {
        let mut st = random_state(&mut r, Dim::Spatial, n);
        // Deformations of the size of the bar's (1 mm at the tip).
        st.y.iter_mut().for_each(|y| *y *= 1e-3);
        let (ma, qa) = eval(&mut body, &st.view(), InertiaMethod::BMatrix);
        let (mb, qb) = eval(&mut body, &st.view(), InertiaMethod::ShapeIntegrals);
        assert!(rel_diff_m(&ma, &mb) < TOL, "M̄ {:e}", rel_diff_m(&ma, &mb));
        assert!(rel_diff_v(&qa, &qb) < TOL, "Q̄_v {:e}", rel_diff_v(&qa, &qb));
    }
}
