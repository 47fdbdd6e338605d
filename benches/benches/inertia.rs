//! One evaluation of the inertia terms M̄ and Q̄_v of a flexible beam by each route
//! (B-matrix projection, shape integrals) against the number of elements, 2D
//! (4 modes) and 3D (8 modes). Target (issue 3): the 3D shape-integral evaluation
//! with 8 modes in ≤ 2 µs, independent of the element count; the B-matrix route
//! linear in the number of cloud points.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use flexmbd::body::{FlexibleBody, InertiaMethod};
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

criterion_group!(benches, inertia);
criterion_main!(benches);
