//! One inertia evaluation (both routes, 2D and 3D, relative and natural sets, full and with
//! inertia terms dropped), the elastic
//! forces, gravity, the potential energy and the body-point queries allocate nothing after
//! set-up (counting global allocator, counting per thread).
//!

mod common;
use common::*;
use flexmbd_body::{BodyPoint, Dim, FlexibleBody, InertiaMethod, InertiaTerms, NaturalState};
use nalgebra::{DMatrix, DVector, Vector3};

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn evaluation_allocates_nothing() {
    for (dim, n) in [
        (Dim::Spatial, 8),
        (Dim::Spatial, 0),
        (Dim::Planar, 5),
        (Dim::Planar, 0),
    ] {
        let mut r = rng(3);
        let rb = random_body(&mut r, dim, n, 40);
        let mut body = FlexibleBody::new(&rb).unwrap();
        let st = random_state(&mut r, dim, n);
        let view = st.view();
        let nc = body.n_coords();
        let mut m = DMatrix::zeros(nc, nc);
        let mut q = DVector::zeros(nc);
        let mut qel = vec![0.0; n];
        let mut qg = vec![0.0; nc];
        let g = Vector3::new(0.0, -9.81, 0.0);
        let mut nws = body.natural_workspace();
        let nat = random_q(&mut r, dim, n, 1.0);
        let nn = body.n_natural_coords();
        let (mut mn, mut qn) = (DMatrix::zeros(nn, nn), DVector::zeros(nn));
        let mut gn = vec![0.0; nn];
        let p = BodyPoint::rigid(Vector3::new(0.5, 0.1, 0.0), n);
        let mut jac = DMatrix::zeros(dim.n_trans(), nn);
        let mut sink = 0.0;
        // Truncated inertia terms (issue 31) in both sets.
        let mut truncated: Vec<FlexibleBody> = ["o2-nv", "o1", "o0-nc"]
            .iter()
            .map(|l| {
                let mut b = body.clone();
                let t = InertiaTerms::parse(l).unwrap();
                b.set_inertia_terms(t, "test").unwrap();
                b
            })
            .collect();
        let before = flexmbd_test_support::allocations();
        for _ in 0..3 {
            body.inertia(&view, InertiaMethod::BMatrix, &mut m, &mut q);
            body.inertia(&view, InertiaMethod::ShapeIntegrals, &mut m, &mut q);
            body.inertia_origin(&view, InertiaMethod::ShapeIntegrals, &mut m, &mut q);
            body.elastic_forces(view.y, view.y_dot, &mut qel);
            body.gravity_forces(&view, &g, &mut qg);
            let st = NaturalState::from_coords(dim, nat.q.as_slice(), nat.qd.as_slice());
            for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
                body.inertia_natural(&st, method, &mut nws, &mut mn, &mut qn);
            }
            for b in truncated.iter_mut() {
                b.inertia(&view, InertiaMethod::ShapeIntegrals, &mut m, &mut q);
                b.inertia_natural(
                    &st,
                    InertiaMethod::ShapeIntegrals,
                    &mut nws,
                    &mut mn,
                    &mut qn,
                );
            }
            body.gravity_natural(&st, &g, &mut gn);
            sink += body.natural_potential_energy(&st, &g);
            body.point_jacobian(&st, &p, &mut jac);
            sink += body.point_position(&st, &p).x
                + body.point_velocity(&st, &p).x
                + body.point_bias(&st, &p).x;
            body.add_point_force(&st, &p, &g, &mut gn);
        }
        let after = flexmbd_test_support::allocations();
        assert!(sink.is_finite());
        assert_eq!(
            after - before,
            0,
            "{dim} n={n}: allocations in the evaluation path"
        );
    }
}
