//! Shape integrals that vanish (issue 31 item 3; `vanished.rs`): a mean-axis body (a beam with
//! `reference: Buckens`, a free-free imported part) has S = ∫X dm = 0 and ∫ r̄ × X dm = 0 to
//! round-off; the body stores them as zeros and its kernels skip their products.
//!
//! * detection: the mean-axis bodies take the skip, the interface-fixed ones (every beam of the
//!   existing scenes, a clamped imported part) do not, and the measured ratios are printed;
//! * the skip is the full evaluation: M̄ and Q̄_v (relative set) and M, Q_v (natural set, off
//!   the constraint manifold) with the integrals zeroed and skipped equal those of the same body
//!   built with every integral as reduced (`FlexibleBody::keeping_integrals`) to round-off, for
//!   every choice of inertia terms, and the B-matrix route (the cloud, no shape integral);
//! * an interface-fixed body is the body it was, bit for bit.

mod common;
use common::*;
use flexmbd_body::weights::candidates;
use flexmbd_body::{
    Dim, FlexibleBody, InertiaMethod, InertiaTerms, VANISHING_TOLERANCE, VanishedIntegrals,
    vanishing_ratios,
};
use flexmbd_fe::{ReducedBody, ReferenceCondition, reduce};
use flexmbd_test_support::samples::{cantilever, imported_bar};
use nalgebra::{DVector, Vector3};

const SI: InertiaMethod = InertiaMethod::ShapeIntegrals;

/// The skipped integrals are ≤ 1e-12 of their scales (printed by the first test: the beams'
/// 1e-14, the imported bar's 9e-13): M and Q_v move by that order relative to the full
/// choice's largest entries at the state (a truncated choice's Q_v can vanish, so its own
/// entries are no scale); 1e-10 leaves a hundredfold margin and is 10⁸ times below an
/// interface-fixed body's S (≥ 1e-2 of its scale).
const TOL: f64 = 1e-10;

/// max |a − b| over `scale`.
fn over(a: &[f64], b: &[f64], scale: f64) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

fn beam(dim: Dim, reference: ReferenceCondition) -> ReducedBody {
    let mut spec = cantilever(dim, 16, 6);
    spec.reference = reference;
    reduce(&spec).expect("the fixture reduces")
}

/// The mean-axis bodies: Buckens beams (2D, 3D) and the free-free imported bar.
fn mean_axis_bodies() -> Vec<(&'static str, ReducedBody)> {
    vec![
        (
            "Buckens beam 2D",
            beam(Dim::Planar, ReferenceCondition::Buckens),
        ),
        (
            "Buckens beam 3D",
            beam(Dim::Spatial, ReferenceCondition::Buckens),
        ),
        ("free-free imported bar", imported_bar(true)),
    ]
}

/// The interface-fixed bodies: clamped beams (2D, 3D) and the clamped imported bar.
fn interface_fixed_bodies() -> Vec<(&'static str, ReducedBody)> {
    vec![
        (
            "clamped beam 2D",
            beam(Dim::Planar, ReferenceCondition::InterfaceFixed),
        ),
        (
            "clamped beam 3D",
            beam(Dim::Spatial, ReferenceCondition::InterfaceFixed),
        ),
        ("clamped imported bar", imported_bar(false)),
    ]
}

#[test]
fn mean_axis_bodies_take_the_skip_and_interface_fixed_ones_do_not() {
    let both = VanishedIntegrals {
        first_moment: true,
        skew_first_moments: true,
    };
    for (name, rb) in mean_axis_bodies() {
        let (s, c) = vanishing_ratios(&rb);
        println!("{name}: ‖S‖ / scale {s:.1e}, ‖∫ r̄ × X dm‖ / scale {c:.1e}");
        assert!(s < 1e-11 && c < 1e-11, "{name}: {s:e}, {c:e}");
        let body = FlexibleBody::new(&rb).unwrap();
        assert_eq!(body.vanished_integrals(), both, "{name}");
        // Stored as exact zeros: the first moment does not change with y.
        let y: Vec<f64> = (0..rb.n_modes()).map(|j| 0.1 * (j as f64 + 1.0)).collect();
        assert_eq!(body.first_moment_at(&y), body.first_moment(), "{name}");
        let kept = FlexibleBody::keeping_integrals(&rb).unwrap();
        assert_eq!(kept.vanished_integrals(), VanishedIntegrals::NONE);
        assert_ne!(kept.first_moment_at(&y), kept.first_moment(), "{name}");
    }
    for (name, rb) in interface_fixed_bodies() {
        let (s, c) = vanishing_ratios(&rb);
        println!("{name}: ‖S‖ / scale {s:.1e}, ‖∫ r̄ × X dm‖ / scale {c:.1e}");
        assert!(s > 1e-2 && c > 1e-2, "{name}: {s:e}, {c:e}");
        assert!(s > 1e6 * VANISHING_TOLERANCE);
        let body = FlexibleBody::new(&rb).unwrap();
        assert_eq!(body.vanished_integrals(), VanishedIntegrals::NONE, "{name}");
    }
}

/// A mean-axis body with and without the skip, every choice of terms; returns the largest
/// relative differences of M̄ and Q̄_v.
fn relative_set_differences(rb: &ReducedBody, seed: u64) -> (f64, f64) {
    let (mut skip, mut full) = (
        FlexibleBody::new(rb).unwrap(),
        FlexibleBody::keeping_integrals(rb).unwrap(),
    );
    let mut r = rng(seed);
    let (mut dm, mut dq) = (0.0_f64, 0.0_f64);
    for _ in 0..10 {
        let st = random_state(&mut r, rb.dim, rb.n_modes());
        full.set_inertia_terms(InertiaTerms::FULL, "t").unwrap();
        let (m0, q0) = eval(&mut full, &st.view(), SI);
        for terms in candidates() {
            skip.set_inertia_terms(terms, "t").unwrap();
            full.set_inertia_terms(terms, "t").unwrap();
            let (ms, qs) = eval(&mut skip, &st.view(), SI);
            let (mf, qf) = eval(&mut full, &st.view(), SI);
            dm = dm.max(over(ms.as_slice(), mf.as_slice(), m0.amax()));
            dq = dq.max(over(qs.as_slice(), qf.as_slice(), q0.amax()));
        }
        // Every term kept: the cloud's route, which reads no shape integral.
        skip.set_inertia_terms(InertiaTerms::FULL, "t").unwrap();
        let (ms, qs) = eval(&mut skip, &st.view(), SI);
        let (mb, qb) = eval(&mut skip, &st.view(), InertiaMethod::BMatrix);
        assert!(rel_diff_m(&ms, &mb) < 1e-10, "{:e}", rel_diff_m(&ms, &mb));
        assert!(rel_diff_v(&qs, &qb) < 1e-10, "{:e}", rel_diff_v(&qs, &qb));
        // Gravity's modal rows Sᵀ Aᵀ g.
        let g = Vector3::new(0.3, -9.81, 1.2);
        let nc = skip.n_coords();
        let (mut gs, mut gf) = (vec![0.0; nc], vec![0.0; nc]);
        skip.gravity_forces(&st.view(), &g, &mut gs);
        full.gravity_forces(&st.view(), &g, &mut gf);
        let d = rel_diff_v(&DVector::from_vec(gs), &DVector::from_vec(gf));
        assert!(d < TOL, "gravity {d:e}");
    }
    (dm, dq)
}

#[test]
fn the_skip_is_the_full_evaluation_in_the_relative_set() {
    for (k, (name, rb)) in mean_axis_bodies().into_iter().enumerate() {
        let (dm, dq) = relative_set_differences(&rb, 3100 + k as u64);
        println!("{name}: relative set, max ΔM̄ {dm:.1e}, ΔQ̄_v {dq:.1e}");
        assert!(dm < TOL && dq < TOL, "{name}: {dm:e}, {dq:e}");
    }
}

#[test]
fn the_skip_is_the_full_evaluation_in_natural_coordinates() {
    for (k, (name, rb)) in mean_axis_bodies().into_iter().enumerate() {
        let (mut skip, mut full) = (
            FlexibleBody::new(&rb).unwrap(),
            FlexibleBody::keeping_integrals(&rb).unwrap(),
        );
        let (mut ws, mut wf) = (skip.natural_workspace(), full.natural_workspace());
        let mut r = rng(3200 + k as u64);
        let (mut dm, mut dq) = (0.0_f64, 0.0_f64);
        for _ in 0..10 {
            let q = random_q(&mut r, rb.dim, rb.n_modes(), 1.0);
            full.set_inertia_terms(InertiaTerms::FULL, "t").unwrap();
            let (m0, q0) = eval_natural(&full, &mut wf, &q.view(), SI);
            for terms in candidates() {
                skip.set_inertia_terms(terms, "t").unwrap();
                full.set_inertia_terms(terms, "t").unwrap();
                let (ms, qs) = eval_natural(&skip, &mut ws, &q.view(), SI);
                let (mf, qf) = eval_natural(&full, &mut wf, &q.view(), SI);
                dm = dm.max(over(ms.as_slice(), mf.as_slice(), m0.amax()));
                dq = dq.max(over(qs.as_slice(), qf.as_slice(), q0.amax()));
            }
            skip.set_inertia_terms(InertiaTerms::FULL, "t").unwrap();
            let (ms, qs) = eval_natural(&skip, &mut ws, &q.view(), SI);
            let (mb, qb) = eval_natural(&skip, &mut ws, &q.view(), InertiaMethod::BMatrix);
            assert!(rel_diff_m(&ms, &mb) < 1e-10, "{:e}", rel_diff_m(&ms, &mb));
            assert!(rel_diff_v(&qs, &qb) < 1e-10, "{:e}", rel_diff_v(&qs, &qb));
            let g = Vector3::new(0.3, -9.81, 1.2);
            let nc = skip.n_natural_coords();
            let (mut gs, mut gf) = (vec![0.0; nc], vec![0.0; nc]);
            skip.gravity_natural(&q.view(), &g, &mut gs);
            full.gravity_natural(&q.view(), &g, &mut gf);
            let d = rel_diff_v(&DVector::from_vec(gs), &DVector::from_vec(gf));
            assert!(d < TOL, "gravity {d:e}");
        }
        println!("{name}: natural set, max ΔM {dm:.1e}, ΔQ_v {dq:.1e}");
        assert!(dm < TOL && dq < TOL, "{name}: {dm:e}, {dq:e}");
    }
}

#[test]
fn an_interface_fixed_body_is_unchanged_bit_for_bit() {
    for (k, (name, rb)) in interface_fixed_bodies().into_iter().enumerate() {
        let (mut new, mut kept) = (
            FlexibleBody::new(&rb).unwrap(),
            FlexibleBody::keeping_integrals(&rb).unwrap(),
        );
        let (mut wn, mut wk) = (new.natural_workspace(), kept.natural_workspace());
        let mut r = rng(3300 + k as u64);
        for _ in 0..5 {
            let st = random_state(&mut r, rb.dim, rb.n_modes());
            let q = random_q(&mut r, rb.dim, rb.n_modes(), 1.0);
            for terms in candidates() {
                new.set_inertia_terms(terms, "t").unwrap();
                kept.set_inertia_terms(terms, "t").unwrap();
                assert_eq!(
                    eval(&mut new, &st.view(), SI),
                    eval(&mut kept, &st.view(), SI)
                );
                assert_eq!(
                    eval_natural(&new, &mut wn, &q.view(), SI),
                    eval_natural(&kept, &mut wk, &q.view(), SI),
                    "{name} {terms}"
                );
            }
        }
    }
}

/// The structural count (`flexmbd_body::operations`) against the terms' own n² measure
/// (`weights::kernel_work`, written apart for the automatic choice): the n² coefficient of the
/// relative spatial count, `(ops(2n) − 2 ops(n)) / 2n²`, is `kernel_work` for every choice;
/// what the vanished integrals save is linear in n and never negative.
#[test]
fn the_operation_count_has_the_terms_n2_work_and_the_skip_saves_o_n() {
    use flexmbd_body::operations::{CoordinateSet, kernel_operations};
    use flexmbd_body::weights::kernel_work;
    let both = VanishedIntegrals {
        first_moment: true,
        skew_first_moments: true,
    };
    for terms in candidates() {
        let ops =
            |n: usize, v| kernel_operations(Dim::Spatial, n, terms, v, CoordinateSet::Relative);
        let n = 10;
        let none = VanishedIntegrals::NONE;
        let c = (ops(2 * n, none) - 2 * ops(n, none)) / (2 * n * n) as u64;
        assert_eq!(c, u64::from(kernel_work(terms)), "{terms}");
        for dim in [Dim::Planar, Dim::Spatial] {
            for set in [CoordinateSet::Relative, CoordinateSet::Natural] {
                let saved = |n| {
                    kernel_operations(dim, n, terms, none, set)
                        - kernel_operations(dim, n, terms, both, set)
                };
                assert_eq!(saved(2 * n), 2 * saved(n), "{terms} {dim:?} {set:?}");
            }
        }
    }
    // Every term kept, spatial relative set: S y, S ẏ, Sᵀā 3n each, A S 9n, r0 × A S 6n.
    let full = |v| {
        kernel_operations(
            Dim::Spatial,
            8,
            InertiaTerms::FULL,
            v,
            CoordinateSet::Relative,
        )
    };
    assert_eq!(full(VanishedIntegrals::NONE) - full(both), 24 * 8);
}
