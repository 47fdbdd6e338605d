//! One evaluation of the inertia terms M̄ and Q̄_v of a flexible beam by each route
//! (B-matrix projection, shape integrals) against the number of elements, 2D
//! (4 modes) and 3D (8 modes). Target (issue 3): the 3D shape-integral evaluation
//! with 8 modes in ≤ 2 µs, independent of the element count; the B-matrix route
//! linear in the number of cloud points.
//!
//! `inertia_terms_*`: the shape-integral route of one beam (16 elements) with terms dropped
//! (issue 31, `flexmbd_body::InertiaTerms`): the CPU per evaluation should fall with each, in
//! the relative set (`inertia_terms_2d_8modes`, …) and in natural coordinates
//! (`inertia_terms_natural_2d_8modes`, …; the same state on the constraint manifold).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use flexmbd::body::{FlexibleBody, InertiaMethod, InertiaTerms};
use flexmbd::core::Dim;
use flexmbd::fe::reduce;
use flexmbd_test_support::samples::{Probe, cantilever};
use nalgebra::{DMatrix, DVector};

fn inertia(c: &mut Criterion) {
    for (dim, modes, label) in [
        (Dim::Planar, 4, "inertia_2d_4modes"),
        (Dim::Spatial, 8, "inertia_3d_8modes"),
    ] {
        let mut group = c.benchmark_group(label);
        for elements in [4usize, 16, 64, 256] {
            let reduced = reduce(&cantilever(dim, elements, modes)).expect("fixture reduces");
            let mut body = FlexibleBody::new(&reduced).expect("fixture body");
            let nc = body.n_coords();
            let probe = Probe::new(dim, body.n_modes());
            let state = probe.state();
            let (mut m, mut q) = (DMatrix::zeros(nc, nc), DVector::zeros(nc));
            for (method, name) in [
                (InertiaMethod::ShapeIntegrals, "shape_integrals"),
                (InertiaMethod::BMatrix, "b_matrix"),
            ] {
                group.bench_with_input(BenchmarkId::new(name, elements), &elements, |b, _| {
                    b.iter(|| {
                        body.inertia(std::hint::black_box(&state), method, &mut m, &mut q);
                        std::hint::black_box(&m);
                    })
                });
            }
        }
        group.finish();
    }
}

fn inertia_terms(c: &mut Criterion) {
    for (dim, modes, label) in [
        (Dim::Planar, 8, "inertia_terms_2d_8modes"),
        (Dim::Spatial, 8, "inertia_terms_3d_8modes"),
        (Dim::Spatial, 16, "inertia_terms_3d_16modes"),
    ] {
        let mut group = c.benchmark_group(label);
        let reduced = reduce(&cantilever(dim, 16, modes)).expect("fixture reduces");
        for name in CHOICES {
            let terms = InertiaTerms::parse(name).expect("a label");
            let mut body = FlexibleBody::new(&reduced).expect("fixture body");
            body.set_inertia_terms(terms, "bench")
                .expect("a linear body");
            let nc = body.n_coords();
            let probe = Probe::new(dim, body.n_modes());
            let state = probe.state();
            let (mut m, mut q) = (DMatrix::zeros(nc, nc), DVector::zeros(nc));
            group.bench_function(name, |b| {
                b.iter(|| {
                    let method = InertiaMethod::ShapeIntegrals;
                    body.inertia(std::hint::black_box(&state), method, &mut m, &mut q);
                    std::hint::black_box(&m);
                })
            });
        }
        group.finish();
    }
}

/// The choices each `inertia_terms*` group times.
const CHOICES: [&str; 6] = ["full", "o2-nv", "o1", "o1-nc", "o0", "o0-nc"];

fn inertia_terms_natural(c: &mut Criterion) {
    for (dim, modes, label) in [
        (Dim::Planar, 8, "inertia_terms_natural_2d_8modes"),
        (Dim::Spatial, 8, "inertia_terms_natural_3d_8modes"),
        (Dim::Spatial, 16, "inertia_terms_natural_3d_16modes"),
    ] {
        let mut group = c.benchmark_group(label);
        let reduced = reduce(&cantilever(dim, 16, modes)).expect("fixture reduces");
        for name in CHOICES {
            let terms = InertiaTerms::parse(name).expect("a label");
            let mut body = FlexibleBody::new(&reduced).expect("fixture body");
            body.set_inertia_terms(terms, "bench")
                .expect("a linear body");
            let nc = body.n_natural_coords();
            let probe = Probe::new(dim, body.n_modes());
            let state = probe.natural_state(dim);
            let mut ws = body.natural_workspace();
            let (mut m, mut q) = (DMatrix::zeros(nc, nc), DVector::zeros(nc));
            group.bench_function(name, |b| {
                b.iter(|| {
                    let method = InertiaMethod::ShapeIntegrals;
                    let st = std::hint::black_box(&state);
                    body.inertia_natural(st, method, &mut ws, &mut m, &mut q);
                    std::hint::black_box(&m);
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, inertia, inertia_terms, inertia_terms_natural);
criterion_main!(benches);
