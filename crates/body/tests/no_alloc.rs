//! One inertia evaluation (both routes, 2D and 3D), the elastic forces and gravity
//! allocate nothing after set-up (counting global allocator).
//!

mod common;
use common::*;
use flexmbd_body::{Dim, FlexibleBody, InertiaMethod};
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
        let nn = body.n_natural_coords();
        let mut mn = DMatrix::zeros(nn, nn);
        let mut qn = DVector::zeros(nn);
        let mut gn = vec![0.0; nn];
        let nat = flexmbd_body::NaturalState {
            r0: view.r0,
            a: view.a,
            r0_dot: view.s_dot,
            a_dot: view.a,
            y: view.y,
            y_dot: view.y_dot,
        };
        let before = flexmbd_test_support::allocations();
        for _ in 0..3 {
            body.inertia(&view, InertiaMethod::BMatrix, &mut m, &mut q);
            body.inertia(&view, InertiaMethod::ShapeIntegrals, &mut m, &mut q);
            body.inertia_origin(&view, InertiaMethod::ShapeIntegrals, &mut m, &mut q);
            body.elastic_forces(view.y, view.y_dot, &mut qel);
            body.gravity_forces(&view, &g, &mut qg);
            body.inertia_natural(&nat, InertiaMethod::BMatrix, &mut nws, &mut mn, &mut qn);
            body.inertia_natural(
                &nat,
                InertiaMethod::ShapeIntegrals,
                &mut nws,
                &mut mn,
                &mut qn,
            );
            body.gravity_natural(&nat, &g, &mut gn);
        }
        let after = flexmbd_test_support::allocations();
        assert_eq!(
            after - before,
            0,
            "{dim} n={n}: allocations in the evaluation path"
        );
    }
}
