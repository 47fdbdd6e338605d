//! One evaluation of the inertia terms M̄ and Q̄_v of a flexible beam by each route
//! (B-matrix projection, shape integrals) against the number of elements, 2D
//! (4 modes) and 3D (8 modes). Target (issue 3): the 3D shape-integral evaluation
//! with 8 modes in ≤ 2 µs, independent of the element count; the B-matrix route
//! linear in the number of cloud points.
//!
//! `inertia_terms_*`: the shape-integral route of one beam (16 elements) with terms dropped
//! (issue 31, `flexmbd_body::InertiaTerms`): the CPU per evaluation should fall with each, in
//! the relative set (`inertia_terms_2d_8modes`, …) and in natural coordinates
//! (`inertia_terms_natural_2d_8modes`, …; the same state on the constraint manifold); per body
//! kind (`inertia_terms_buckens_3d_8modes`, `inertia_terms_solid_free_4modes`,
//! `inertia_terms_fnl1_2d_6modes`, …, and their `inertia_terms_natural_*`).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use flexmbd::body::{FlexibleBody, InertiaMethod, InertiaTerms};
use flexmbd::core::Dim;
use flexmbd::fe::{ReferenceCondition, reduce};
use flexmbd::model::PreparedScene;
use flexmbd_test_support::samples::{Probe, cantilever, imported_bar};
use flexmbd_test_support::scenes::model;
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
        let reduced = reduce(&cantilever(dim, 16, modes)).expect("fixture reduces");
        let body = FlexibleBody::new(&reduced).expect("fixture body");
        terms_group(c, label, &body, CoordinateSet::Relative);
    }
}

/// The choices each `inertia_terms*` group times.
const CHOICES: [&str; 6] = ["full", "o2-nv", "o1", "o1-nc", "o0", "o0-nc"];

/// Which kernel a group times.
#[derive(Clone, Copy)]
enum CoordinateSet {
    Relative,
    Natural,
}

/// One group `label`: the shape-integral kernel of `body` in `set` for each of [`CHOICES`], at
/// the probe state (in natural coordinates the same state on the constraint manifold).
fn terms_group(c: &mut Criterion, label: &str, body: &FlexibleBody, set: CoordinateSet) {
    let mut group = c.benchmark_group(label);
    let dim = body.dim();
    for name in CHOICES {
        let terms = InertiaTerms::parse(name).expect("a label");
        let mut body = body.clone();
        body.set_inertia_terms(terms, "bench")
            .expect("a linear body");
        let probe = Probe::new(dim, body.n_modes());
        let method = InertiaMethod::ShapeIntegrals;
        match set {
            CoordinateSet::Relative => {
                let nc = body.n_coords();
                let state = probe.state();
                let (mut m, mut q) = (DMatrix::zeros(nc, nc), DVector::zeros(nc));
                group.bench_function(name, |b| {
                    b.iter(|| {
                        body.inertia(std::hint::black_box(&state), method, &mut m, &mut q);
                        std::hint::black_box(&m);
                    })
                });
            }
            CoordinateSet::Natural => {
                let nc = body.n_natural_coords();
                let state = probe.natural_state(dim);
                let mut ws = body.natural_workspace();
                let (mut m, mut q) = (DMatrix::zeros(nc, nc), DVector::zeros(nc));
                group.bench_function(name, |b| {
                    b.iter(|| {
                        let st = std::hint::black_box(&state);
                        body.inertia_natural(st, method, &mut ws, &mut m, &mut q);
                        std::hint::black_box(&m);
                    })
                });
            }
        }
    }
    group.finish();
}

fn inertia_terms_natural(c: &mut Criterion) {
    for (dim, modes, label) in [
        (Dim::Planar, 8, "inertia_terms_natural_2d_8modes"),
        (Dim::Spatial, 8, "inertia_terms_natural_3d_8modes"),
        (Dim::Spatial, 16, "inertia_terms_natural_3d_16modes"),
    ] {
        let reduced = reduce(&cantilever(dim, 16, modes)).expect("fixture reduces");
        let body = FlexibleBody::new(&reduced).expect("fixture body");
        terms_group(c, label, &body, CoordinateSet::Natural);
    }
}

/// The other body kinds (issue 31, "CPU per step falls with each dropped term, per body kind"),
/// in both sets: the Buckens beam (the cantilever's modes made mean-axis; its S and the skew
/// part of Sᵃ vanish and are skipped), the imported hex8 steel bar clamped at its root (4
/// normal + 6 static modes) and free-free (4 modes, mean-axis), and the FNL1 beam of the 2D
/// spin-up scene (4 bending + 2 axial modes; FNL1 changes the elastic forces only).
fn inertia_terms_kinds(c: &mut Criterion) {
    let mut kinds = Vec::new();
    for (dim, label) in [
        (Dim::Planar, "buckens_2d_8modes"),
        (Dim::Spatial, "buckens_3d_8modes"),
    ] {
        let mut spec = cantilever(dim, 16, 8);
        spec.reference = ReferenceCondition::Buckens;
        let reduced = reduce(&spec).expect("fixture reduces");
        kinds.push((
            label.to_string(),
            FlexibleBody::new(&reduced).expect("fixture body"),
        ));
    }
    for (free_free, what) in [(false, "solid_clamped"), (true, "solid_free")] {
        let body = FlexibleBody::new(&imported_bar(free_free)).expect("fixture body");
        kinds.push((format!("{what}_{}modes", body.n_modes()), body));
    }
    let scene = model("spin_up_beam_2d.ron");
    let prepared = PreparedScene::new(&scene).expect("the scene compiles");
    let beam = prepared
        .bodies()
        .iter()
        .find(|b| b.flexible)
        .expect("the spin-up scene's beam");
    kinds.push((
        format!("fnl1_2d_{}modes", beam.body.n_modes()),
        beam.body.clone(),
    ));
    for (kind, body) in &kinds {
        terms_group(
            c,
            &format!("inertia_terms_{kind}"),
            body,
            CoordinateSet::Relative,
        );
        let natural = format!("inertia_terms_natural_{kind}");
        terms_group(c, &natural, body, CoordinateSet::Natural);
    }
}

criterion_group!(
    benches,
    inertia,
    inertia_terms,
    inertia_terms_natural,
    inertia_terms_kinds
);
criterion_main!(benches);
