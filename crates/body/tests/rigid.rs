//! Zero modes: M̄ is the rigid body's mass, static moment and inertia tensor,
//! computed independently (uniform bar: mL²/12 about its centre, mL²/3 about an end),
//! and Q̄_v the classical rigid-body terms. Bad input to `ReducedBody::rigid` is refused.

mod common;
use common::*;
use flexmbd_body::{BodyState, Dim, FlexibleBody, InertiaMethod};
use flexmbd_fe::{MassCloud, ReducedBody};
use nalgebra::{Matrix3, Vector2, Vector3};

const M: f64 = 3.5;
const L: f64 = 1.2;
const B: f64 = 0.04; // section width (y)
const C: f64 = 0.02; // section height (z)

/// Bar along body x from 0 to L, centre (L/2, 0, 0).
fn bar_rigid(dim: Dim) -> ReducedBody {
    let ic = Matrix3::from_diagonal(&Vector3::new(
        M * (B * B + C * C) / 12.0,
        M * (L * L + C * C) / 12.0,
        M * (L * L + B * B) / 12.0,
    ));
    ReducedBody::rigid(dim, M, Vector3::new(L / 2.0, 0.0, 0.0), ic).unwrap()
}

/// The same bar as a fine cloud of a slender uniform bar (midpoint rule along x,
/// 2 × 2 Gauss points across the section): an independent discretization.
fn bar_cloud(dim: Dim) -> ReducedBody {
    let ns = 2000;
    let g = 1.0 / 3f64.sqrt();
    let mut positions = vec![];
    let mut weights = vec![];
    for i in 0..ns {
        let x = (i as f64 + 0.5) * L / ns as f64;
        if dim == Dim::Planar {
            positions.push(Vector3::new(x, 0.0, 0.0));
            weights.push(M / ns as f64);
            continue;
        }
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                positions.push(Vector3::new(x, sy * g * B / 2.0, sz * g * C / 2.0));
                weights.push(M / ns as f64 / 4.0);
            }
        }
    }
    let cloud = MassCloud {
        n_modes: 0,
        positions,
        weights,
        mode_rows: vec![],
        description: "uniform bar, midpoint rule".into(),
    };
    body_from_cloud(&mut rng(0), dim, cloud)
}

#[test]
fn bar_about_end_and_centre_3d() {
    for rb in [bar_rigid(Dim::Spatial), bar_cloud(Dim::Spatial)] {
        let mut body = FlexibleBody::new(&rb).unwrap();
        let st = OwnedState::rigid_at_rest(Vector3::zeros());
        // The midpoint rule misses m L²/(12 ns²) along x: relative 2.5e-7 at ns = 2000.
        let tol = if rb.cloud.len() > 100 { 1e-6 } else { 1e-12 };
        for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
            let (m, _) = eval(&mut body, &st.view(), method);
            let about_end = M * L * L / 3.0;
            assert!((m[(0, 0)] - M).abs() < 1e-12 * M);
            assert!((m[(4, 4)] - (about_end + M * C * C / 12.0)).abs() < tol * about_end);
            assert!((m[(5, 5)] - (about_end + M * B * B / 12.0)).abs() < tol * about_end);
            // Static moment: M̄_sω = −m g̃ with g = (L/2, 0, 0): entry (1, 5) = −(−g_x)·m... = m g_x.
            assert!((m[(1, 5)] - M * L / 2.0).abs() < 1e-12);
            assert!((m[(2, 4)] + M * L / 2.0).abs() < 1e-12);
            // Shift the frame origin to the centre: r0 = −(L/2) e_x puts the centre at the origin.
            let st_c = OwnedState::rigid_at_rest(Vector3::new(-L / 2.0, 0.0, 0.0));
            let (mc, _) = eval(&mut body, &st_c.view(), method);
            let about_c = M * L * L / 12.0;
            assert!((mc[(5, 5)] - (about_c + M * B * B / 12.0)).abs() < tol * about_c);
            assert!(
                mc.view((0, 3), (3, 3)).amax() < 1e-12,
                "centre at the origin: no static moment"
            );
        }
        assert!(
            (body.inertia_about_origin()[(2, 2)] - (M * L * L / 3.0 + M * B * B / 12.0)).abs()
                < 1e-6
        );
        assert!((body.center_of_mass() - Vector3::new(L / 2.0, 0.0, 0.0)).norm() < 1e-12);
    }
}

#[test]
fn bar_2d() {
    for rb in [bar_rigid(Dim::Planar), bar_cloud(Dim::Planar)] {
        let mut body = FlexibleBody::new(&rb).unwrap();
        let tol = if rb.cloud.len() > 100 { 1e-6 } else { 1e-12 };
        let st = BodyState::planar(Vector2::zeros(), 0.0, Vector2::zeros(), 0.0, &[], &[]);
        for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
            let mut m = nalgebra::DMatrix::zeros(3, 3);
            let mut q = nalgebra::DVector::zeros(3);
            body.inertia(&st, method, &mut m, &mut q);
            let about_end = M * L * L / 3.0;
            // ReducedBody::rigid in 2D uses I_zz only; the cloud bar has no section in 2D.
            let expect = if rb.cloud.len() > 100 {
                about_end
            } else {
                about_end + M * B * B / 12.0
            };
            assert!(
                (m[(2, 2)] - expect).abs() < tol * about_end,
                "{} vs {expect}",
                m[(2, 2)]
            );
            assert!((m[(1, 2)] - M * L / 2.0).abs() < 1e-12);
            assert!((m[(0, 0)] - M).abs() < 1e-12);
        }
    }
}

/// At a random state, M̄ = [m I, −m g̃; m g̃, J_O] with J_O = A I_c Aᵀ + m(|g|² I − g gᵀ)
/// (parallel axes), and Q̄_v = −{m(ω × ṡ + ω × (ω × g)); m g × (ω × ṡ) + ω × J_O ω}.
#[test]
fn rigid_random_states_closed_form() {
    let mut r = rng(5);
    let c = Vector3::new(0.3, -0.1, 0.2);
    let ic = Matrix3::new(2.0, 0.1, -0.2, 0.1, 3.0, 0.05, -0.2, 0.05, 4.0);
    let m = 7.0;
    let rb = ReducedBody::rigid(Dim::Spatial, m, c, ic).unwrap();
    let mut body = FlexibleBody::new(&rb).unwrap();
    for _ in 0..20 {
        let st = random_state(&mut r, Dim::Spatial, 0);
        let g = st.r0 + st.a * c;
        let jo = st.a * ic * st.a.transpose()
            + m * (Matrix3::identity() * g.norm_squared() - g * g.transpose());
        let w = st.omega;
        let qs = -m * (w.cross(&st.s_dot) + w.cross(&w.cross(&g)));
        let qw = -(m * g.cross(&w.cross(&st.s_dot)) + w.cross(&(jo * w)));
        for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
            let (mm, q) = eval(&mut body, &st.view(), method);
            let gt = flexmbd_core::skew(&g);
            let scale = jo.amax().max(m);
            assert!((mm.view((0, 0), (3, 3)) - Matrix3::identity() * m).amax() < 1e-13 * scale);
            assert!((mm.view((0, 3), (3, 3)) + m * gt).amax() < 1e-13 * scale);
            assert!((mm.view((3, 3), (3, 3)) - jo).amax() < 1e-12 * scale);
            let qscale = qs.amax().max(qw.amax());
            assert!((q.rows(0, 3) - qs).amax() < 1e-12 * qscale);
            assert!((q.rows(3, 3) - qw).amax() < 1e-12 * qscale);
        }
    }
}

#[test]
fn rigid_refuses_bad_input() {
    let z = Vector3::zeros();
    let i = Matrix3::identity();
    let e = ReducedBody::rigid(Dim::Spatial, -2.0, z, i).unwrap_err();
    assert_eq!(e.field, "mass");
    assert!(e.value.contains("-2"), "{e}");
    let e = ReducedBody::rigid(Dim::Spatial, 0.0, z, i).unwrap_err();
    assert_eq!(e.field, "mass");
    let e = ReducedBody::rigid(Dim::Spatial, f64::NAN, z, i).unwrap_err();
    assert_eq!(e.field, "mass");
    // Not positive definite.
    let e = ReducedBody::rigid(Dim::Spatial, 1.0, z, -i).unwrap_err();
    assert_eq!(e.field, "inertia_about_com");
    assert!(e.value.contains("-1"), "{e}");
    // Not symmetric.
    let ns = Matrix3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    let e = ReducedBody::rigid(Dim::Spatial, 1.0, z, ns).unwrap_err();
    assert!(e.reason.contains("symmetric"), "{e}");
    // Triangle inequality: 1 + 1 < 3.
    let tri = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 3.0));
    let e = ReducedBody::rigid(Dim::Spatial, 1.0, z, tri).unwrap_err();
    assert_eq!(e.field, "inertia_about_com");
    assert!(e.reason.contains("triangle"), "{e}");
    // Non-finite centre of mass.
    let e = ReducedBody::rigid(Dim::Spatial, 1.0, Vector3::new(f64::INFINITY, 0.0, 0.0), i)
        .unwrap_err();
    assert_eq!(e.field, "center_of_mass");
    // 2D: only I_zz > 0 needed, the body in z = 0.
    let only_zz = Matrix3::from_diagonal(&Vector3::new(0.0, 0.0, 2.0));
    assert!(ReducedBody::rigid(Dim::Planar, 1.0, z, only_zz).is_ok());
    let e = ReducedBody::rigid(Dim::Planar, 1.0, z, Matrix3::zeros()).unwrap_err();
    assert_eq!(e.field, "inertia_about_com.zz");
    let e = ReducedBody::rigid(Dim::Planar, 1.0, Vector3::new(0.0, 0.0, 0.1), i).unwrap_err();
    assert_eq!(e.field, "center_of_mass.z");
    // A rigid 3D body with a flat (triangle-equality) inertia is accepted.
    let flat = Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0));
    assert!(ReducedBody::rigid(Dim::Spatial, 1.0, z, flat).is_ok());
}

#[test]
fn flexible_body_refuses_inconsistent_data() {
    let mut r = rng(9);
    let mut rb = random_body(&mut r, Dim::Spatial, 2, 5);
    // A negative weight is accepted (an exact rewriting of a consistent mass has them, see
    // flexmbd_fe::imported::inertia); a non-finite one is not.
    rb.cloud.weights[3] = f64::NAN;
    let e = FlexibleBody::new(&rb).unwrap_err();
    assert_eq!(e.field, "cloud.weights[3]");
    let mut rb = random_body(&mut r, Dim::Planar, 2, 5);
    rb.cloud.positions[1].z = 0.5;
    let e = FlexibleBody::new(&rb).unwrap_err();
    assert_eq!(e.field, "cloud.positions[1].z");
    let mut rb = random_body(&mut r, Dim::Spatial, 2, 5);
    rb.k_ff = nalgebra::DMatrix::zeros(3, 3);
    assert_eq!(FlexibleBody::new(&rb).unwrap_err().field, "k_ff");
    let _ = MassCloud::len;
}
