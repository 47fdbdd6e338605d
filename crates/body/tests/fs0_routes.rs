//! FS0 (docs/methods.md §6.3): the shape-integral route (`fs_shape.rs`) equals the B-matrix
//! projection over the mass cloud (the reference) at random states, in the relative set
//! (2D and 3D) and in natural coordinates (2D and 3D, with a non-orthonormal A), on the
//! spin-up beam and on random clouds with random F's and a skew beam axis (§2.7: both
//! routes sum the same cloud, so they agree to round-off). Also: the shape-integral route
//! allocates nothing per evaluation.

mod common;
use common::*;
use flexmbd_body::{BodyState, Dim, FlexibleBody, InertiaMethod, NaturalState};
use flexmbd_fe::ReducedBody;
use flexmbd_fe::foreshortening::ForeshorteningData;
use nalgebra::{DMatrix, DVector, Matrix3, Vector2, Vector3};
use rand::Rng;

/// Worst relative difference measured (release, x86-64): 2.5e-15 (3D spin-up beam, Q̄_v; see
/// the test output); 1e-12 leaves a margin of 400 for other platforms and compilers.
const TOL: f64 = 1e-12;

/// A random cloud with random symmetric F's (shared by runs of 1–4 consecutive points, as
/// section points share a station's) and a unit axis in general position (in the plane for 2D).
fn random_fs_body<R: Rng>(r: &mut R, dim: Dim, n: usize, np: usize) -> ReducedBody {
    let mut rb = random_body(r, dim, n, np);
    let mut axis = rand_vec(r, 1.0);
    if dim == Dim::Planar {
        axis.z = 0.0;
    }
    let axis = axis.normalize();
    let mut cloud = Vec::with_capacity(np);
    while cloud.len() < np {
        let g = DMatrix::from_fn(n, n, |_, _| uni(r, -0.5, 0.5));
        let f = &g * g.transpose();
        let reps = 1 + (uni(r, 0.0, 3.99) as usize);
        for _ in 0..reps.min(np - cloud.len()) {
            cloud.push(f.clone());
        }
    }
    rb.foreshortening = Some(ForeshorteningData {
        axis,
        cloud,
        nodes: vec![DMatrix::zeros(n, n)],
    });
    rb
}

/// y of order 1 m on the 10 m beam (0.5 on the random cloud), rates of order 2.
fn scaled_state<R: Rng>(r: &mut R, dim: Dim, n: usize, ys: f64) -> OwnedState {
    let mut st = random_state(r, dim, n);
    for v in st.y.iter_mut() {
        *v *= 2.0 * ys;
    }
    st
}

fn relative_worst(rb: &ReducedBody, dim: Dim, seed: u64, ys: f64) -> (f64, f64) {
    let mut r = rng(seed);
    let n = rb.n_modes();
    let mut body = FlexibleBody::new(rb).unwrap();
    assert!(body.has_foreshortening());
    let mut worst = (0.0f64, 0.0f64);
    for _ in 0..20 {
        let st = scaled_state(&mut r, dim, n, ys);
        let (ma, qa) = eval(&mut body, &st.view(), InertiaMethod::BMatrix);
        let (mb, qb) = eval(&mut body, &st.view(), InertiaMethod::ShapeIntegrals);
        let (dm, dq) = (rel_diff_m(&mb, &ma), rel_diff_v(&qb, &qa));
        assert!(dm < TOL && dq < TOL, "{dim} relative: M̄ {dm:e}, Q̄_v {dq:e}");
        assert!(rel_diff_m(&mb, &mb.transpose()) < 1e-15);
        worst = (worst.0.max(dm), worst.1.max(dq));
    }
    worst
}

fn natural_worst(rb: &ReducedBody, dim: Dim, seed: u64, ys: f64) -> (f64, f64) {
    let mut r = rng(seed);
    let n = rb.n_modes();
    let body = FlexibleBody::new(rb).unwrap();
    let mut nws = body.natural_workspace();
    let nc = body.n_natural_coords();
    let mut worst = (0.0f64, 0.0f64);
    for _ in 0..20 {
        let st = scaled_state(&mut r, dim, n, ys);
        // A drifting, non-orthonormal frame (inside Newton iterations) and any Ȧ.
        let nat = match dim {
            Dim::Spatial => NaturalState {
                r0: st.r0,
                a: st.a + Matrix3::from_fn(|_, _| uni(&mut r, -0.05, 0.05)),
                r0_dot: st.s_dot,
                a_dot: Matrix3::from_fn(|_, _| uni(&mut r, -2.0, 2.0)),
                y: &st.y,
                y_dot: &st.y_dot,
            },
            Dim::Planar => NaturalState::planar(
                st.r0.xy(),
                st.a.column(0).xy() * uni(&mut r, 0.95, 1.05),
                st.s_dot.xy(),
                Vector2::new(uni(&mut r, -2.0, 2.0), uni(&mut r, -2.0, 2.0)),
                &st.y,
                &st.y_dot,
            ),
        };
        let mut out = [
            (DMatrix::zeros(nc, nc), DVector::zeros(nc)),
            (DMatrix::zeros(nc, nc), DVector::zeros(nc)),
        ];
        for (method, (m, q)) in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals]
            .into_iter()
            .zip(out.iter_mut())
        {
            m.fill(f64::NAN);
            q.fill(f64::NAN);
            body.inertia_natural(&nat, method, &mut nws, m, q);
            assert!(m.iter().chain(q.iter()).all(|v| v.is_finite()));
        }
        let (dm, dq) = (
            rel_diff_m(&out[1].0, &out[0].0),
            rel_diff_v(&out[1].1, &out[0].1),
        );
        assert!(dm < TOL && dq < TOL, "{dim} natural: M {dm:e}, Q_v {dq:e}");
        worst = (worst.0.max(dm), worst.1.max(dq));
    }
    worst
}

#[test]
fn routes_agree_on_the_spin_up_beam() {
    for (dim, modes) in [(Dim::Planar, 4), (Dim::Planar, 8), (Dim::Spatial, 8)] {
        let rb = spin_up_body(dim, 20, modes).0;
        let wr = relative_worst(&rb, dim, 7, 1.0);
        let wn = natural_worst(&rb, dim, 8, 1.0);
        eprintln!(
            "FS0 spin-up beam {dim} n={modes}: relative M̄ {:.1e} Q̄_v {:.1e}; natural M {:.1e} Q_v {:.1e}",
            wr.0, wr.1, wn.0, wn.1
        );
    }
}

#[test]
fn routes_agree_on_random_clouds() {
    for (seed, dim, n, np) in [
        (1, Dim::Spatial, 1, 13),
        (2, Dim::Spatial, 3, 37),
        (3, Dim::Spatial, 6, 41),
        (4, Dim::Planar, 2, 17),
        (5, Dim::Planar, 5, 29),
    ] {
        let mut r = rng(seed);
        let rb = random_fs_body(&mut r, dim, n, np);
        let wr = relative_worst(&rb, dim, seed + 100, 0.5);
        let wn = natural_worst(&rb, dim, seed + 200, 0.5);
        eprintln!(
            "FS0 random cloud {dim} n={n} N_p={np}: relative M̄ {:.1e} Q̄_v {:.1e}; natural M {:.1e} Q_v {:.1e}",
            wr.0, wr.1, wn.0, wn.1
        );
    }
}

/// The shape route's FS0 terms are not zero here: at y ≠ 0 they differ from the plain
/// (linear) shape route, so the agreement above is not the linear route agreeing with itself.
#[test]
fn fs0_terms_are_exercised() {
    let rb = spin_up_body(Dim::Spatial, 20, 8).0;
    let mut plain = rb.clone();
    plain.foreshortening = None;
    let mut r = rng(3);
    let st = scaled_state(&mut r, Dim::Spatial, 8, 1.0);
    let mut b = FlexibleBody::new(&rb).unwrap();
    let mut p = FlexibleBody::new(&plain).unwrap();
    let (m1, q1) = eval(&mut b, &st.view(), InertiaMethod::ShapeIntegrals);
    let (m2, q2) = eval(&mut p, &st.view(), InertiaMethod::ShapeIntegrals);
    let (dm, dq) = (rel_diff_m(&m1, &m2), rel_diff_v(&q1, &q2));
    eprintln!("FS0 vs linear at a deformed state: M̄ {dm:.1e}, Q̄_v {dq:.1e}");
    assert!(dm > 1e-3 && dq > 1e-3);
}

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn shape_route_allocates_nothing() {
    for (dim, modes) in [(Dim::Planar, 4), (Dim::Spatial, 8)] {
        let rb = spin_up_body(dim, 8, modes).0;
        let mut body = FlexibleBody::new(&rb).unwrap();
        let mut r = rng(9);
        let st = scaled_state(&mut r, dim, modes, 1.0);
        let nc = body.n_coords();
        let (mut m, mut q) = (DMatrix::zeros(nc, nc), DVector::zeros(nc));
        let mut nws = body.natural_workspace();
        let nn = body.n_natural_coords();
        let (mut mn, mut qn) = (DMatrix::zeros(nn, nn), DVector::zeros(nn));
        let nat = match dim {
            Dim::Spatial => NaturalState {
                r0: st.r0,
                a: st.a,
                r0_dot: st.s_dot,
                a_dot: st.a,
                y: &st.y,
                y_dot: &st.y_dot,
            },
            Dim::Planar => NaturalState::planar(
                st.r0.xy(),
                st.a.column(0).xy(),
                st.s_dot.xy(),
                Vector2::new(0.3, -0.2),
                &st.y,
                &st.y_dot,
            ),
        };
        let view: BodyState<'_> = st.view();
        let before = flexmbd_test_support::allocations();
        for _ in 0..3 {
            for method in [InertiaMethod::ShapeIntegrals, InertiaMethod::BMatrix] {
                body.inertia(&view, method, &mut m, &mut q);
                body.inertia_origin(&view, method, &mut m, &mut q);
                body.inertia_natural(&nat, method, &mut nws, &mut mn, &mut qn);
            }
        }
        assert_eq!(flexmbd_test_support::allocations(), before, "{dim}");
        let _ = Vector3::<f64>::zeros();
    }
}
