//! Inertia terms kept by their weight in natural coordinates (issue 31, `natural_terms.rs`),
//! checked physics against physics:
//!
//! * Lagrange: with T = ½ q̇ᵀ M(q) q̇ and the kernel's own truncated M, `Q_v = −Ṁ q̇ + ∂T/∂q` by
//!   central differences, off the constraint manifold (non-unit u, non-orthonormal A), for every
//!   Lagrangian choice, 2D and 3D; the full Q_v with a truncated M fails that check;
//! * on the manifold each truncation is the relative set's (`terms.rs`, checked there against
//!   its own Lagrange equations and the cloud): with `q̇ = R Z`, `Rᵀ M R = M̄` and
//!   `Rᵀ(Q_v − M Ṙ Z) = Q̄_v`, the velocity term's drop included — so the two formulations
//!   carry the same physics per truncation;
//! * `velocity: false` removes a workless force (q̇ᵀ ΔQ = 0 off the manifold too, ΔQ ≠ 0);
//! * order 0 and `coupling: false` give positive definite M on the manifold's states even at
//!   deformations far beyond small.

mod common;
use common::*;
use flexmbd_body::{Dim, FlexibleBody, InertiaMethod, InertiaTerms, NaturalWorkspace};
use flexmbd_fe::ReducedBody;
use nalgebra::{DMatrix, DVector};

const SI: InertiaMethod = InertiaMethod::ShapeIntegrals;

fn terms(order: u8, velocity: bool, coupling: bool) -> InertiaTerms {
    InertiaTerms {
        order,
        velocity,
        coupling,
    }
}

/// Every truncated choice (the full one runs the kernels of `natural.rs`).
fn truncations() -> Vec<InertiaTerms> {
    let mut v = Vec::new();
    for order in 0..=2 {
        for coupling in [true, false] {
            v.push(terms(order, true, coupling));
        }
    }
    v.retain(|t| !t.is_full());
    v.extend([terms(1, false, true), terms(2, false, true)]);
    v
}

fn truncated(rb: &ReducedBody, t: InertiaTerms) -> FlexibleBody {
    let mut b = FlexibleBody::new(rb).unwrap();
    b.set_inertia_terms(t, "test").unwrap();
    b
}

/// `−Ṁ q̇ + ∂T/∂q` at `s` with T = ½ q̇ᵀ M(q) q̇ and M from `body`, by central differences.
fn lagrange_force(body: &FlexibleBody, ws: &mut NaturalWorkspace, s: &Q) -> DVector<f64> {
    let h = 1e-5;
    let mut m_at = |q: DVector<f64>| eval_natural(body, ws, &s.with_q(q).view(), SI).0;
    let mdot_qd = (m_at(&s.q + h * &s.qd) - m_at(&s.q - h * &s.qd)) / (2.0 * h) * &s.qd;
    let dtdq = DVector::from_fn(s.q.len(), |i, _| {
        let mut t = [0.0; 2];
        for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
            let mut q = s.q.clone();
            q[i] += sign * h;
            t[k] = 0.5 * s.qd.dot(&(m_at(q) * &s.qd));
        }
        (t[0] - t[1]) / (2.0 * h)
    });
    -mdot_qd + dtdq
}

/// max over random off-manifold states of |Q_v − (−Ṁ q̇ + ∂T/∂q)| / max|…|, T and M from
/// `mass`, Q_v from `force`.
fn lagrange(mass: &FlexibleBody, force: &FlexibleBody, dim: Dim, seed: u64) -> f64 {
    let mut r = rng(seed);
    let mut ws = mass.natural_workspace();
    let mut worst = 0.0f64;
    for _ in 0..5 {
        let s = random_q(&mut r, dim, mass.n_modes(), 1.0);
        let q_ref = lagrange_force(mass, &mut ws, &s);
        let (m, qv) = eval_natural(force, &mut ws, &s.view(), SI);
        assert!(
            (&m - m.transpose()).amax() < 1e-14 * m.amax(),
            "M symmetric"
        );
        worst = worst.max(rel_diff_v(&qv, &q_ref));
    }
    worst
}

#[test]
fn velocity_forces_derive_from_the_truncated_kinetic_energy() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut r = rng(11);
        let rb = random_body(&mut r, dim, 5, 25);
        for t in truncations().into_iter().filter(|t| t.velocity) {
            let b = truncated(&rb, t);
            let d = lagrange(&b, &b, dim, 12);
            eprintln!("{dim} {t}: Lagrange residual {d:.1e}");
            // Measured 2e-11 to 2e-10 (M is quadratic in q: central differences leave
            // round-off only); the full Q_v with a truncated M gives 0.1 to 1 (next test).
            assert!(d < 1e-8, "{dim} {t}: Lagrange {d:e}");
        }
    }
}

/// The check can fail: the full model's Q_v with a truncated M is not Lagrangian.
#[test]
fn the_lagrange_check_detects_a_velocity_force_of_another_model() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut r = rng(11);
        let rb = random_body(&mut r, dim, 5, 25);
        let full = FlexibleBody::new(&rb).unwrap();
        for t in [
            terms(1, true, true),
            terms(0, true, true),
            terms(2, true, false),
        ] {
            let d = lagrange(&truncated(&rb, t), &full, dim, 12);
            eprintln!("{dim} {t} with the full Q_v: residual {d:.1e}");
            assert!(d > 1e-2, "{dim} {t}: residual {d:e}");
        }
    }
}

/// The largest of T, RᵀMR and Q differences between the natural and the relative set with
/// `t`, over random states on the manifold.
fn against_relative(rb: &ReducedBody, t: InertiaTerms, seed: u64, y_scale: f64) -> [f64; 3] {
    let mut r = rng(seed);
    let dim = rb.dim;
    let natural = truncated(rb, t);
    let mut relative = truncated(rb, t);
    let mut ws = natural.natural_workspace();
    let n = natural.n_modes();
    let mut worst = [0.0f64; 3];
    for _ in 0..10 {
        let mut st = random_state(&mut r, dim, n);
        for v in st.y.iter_mut() {
            *v *= y_scale;
        }
        let view = st.view();
        let z = z_vec(dim, &view.s_dot, &view.omega, view.y_dot);
        let (mrel, qrel) = eval(&mut relative, &view, SI);
        let (s, rm, rdz) = natural_from_relative(&view, dim, n);
        let (m, qv) = eval_natural(&natural, &mut ws, &s.view(), SI);
        let t_nat = 0.5 * s.qd.dot(&(&m * &s.qd));
        let t_rel = 0.5 * z.dot(&(&mrel * &z));
        let d = [
            (t_nat - t_rel).abs() / t_rel,
            rel_diff_m(&(rm.transpose() * &m * &rm), &mrel),
            rel_diff_v(&(rm.transpose() * (&qv - &m * &rdz)), &qrel),
        ];
        for (w, d) in worst.iter_mut().zip(d) {
            *w = w.max(d);
        }
    }
    worst
}

#[test]
fn on_the_manifold_each_truncation_is_the_relative_sets() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut r = rng(20);
        let rb = random_body(&mut r, dim, 4, 25);
        let beams = beams(dim);
        for t in truncations() {
            let w = against_relative(&rb, t, 21, 1.0);
            eprintln!(
                "{dim} {t} random: T {:.1e}, RᵀMR {:.1e}, Q {:.1e}",
                w[0], w[1], w[2]
            );
            // Measured ≤ 3e-15 / 4e-15 / 2e-14 (round-off).
            assert!(w.iter().all(|d| *d < 1e-12), "{dim} {t}: {w:?}");
            for (i, (name, b)) in beams.iter().enumerate() {
                let w = against_relative(b, t, 22 + i as u64, 0.1);
                assert!(w.iter().all(|d| *d < 1e-12), "{name} {t}: {w:?}");
            }
        }
    }
}

/// The manifold check can fail: the relative set with another truncation differs.
#[test]
fn the_manifold_check_tells_truncations_apart() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut r = rng(20);
        let rb = random_body(&mut r, dim, 4, 25);
        let st = random_state(&mut r, dim, 4);
        let view = st.view();
        let (s, rm, rdz) = natural_from_relative(&view, dim, 4);
        for (a, b) in [
            (terms(1, true, true), terms(2, true, true)),
            (terms(2, false, true), terms(2, true, true)),
            (terms(0, true, false), terms(0, true, true)),
        ] {
            let natural = truncated(&rb, a);
            let mut ws = natural.natural_workspace();
            let (m, qv) = eval_natural(&natural, &mut ws, &s.view(), SI);
            let (_, qrel) = eval(&mut truncated(&rb, b), &view, SI);
            let d = rel_diff_v(&(rm.transpose() * (&qv - &m * &rdz)), &qrel);
            assert!(d > 1e-3, "{dim} {a} vs {b}: {d:e}");
        }
    }
}

/// `velocity: false` differs from the Lagrangian force of its own T by the gyroscopic force
/// alone: on the modal rows, nonzero, and workless (q̇ᵀ ΔQ = 0) off the manifold too.
#[test]
fn dropping_the_velocity_term_removes_a_workless_modal_force() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut r = rng(41);
        let rb = random_body(&mut r, dim, 4, 11);
        for order in [1, 2] {
            let without = truncated(&rb, terms(order, false, true));
            let mut ws = without.natural_workspace();
            for _ in 0..3 {
                let s = random_q(&mut r, dim, 4, 1.0);
                let q_ref = lagrange_force(&without, &mut ws, &s);
                let (_, qv) = eval_natural(&without, &mut ws, &s.view(), SI);
                let dq = &q_ref - &qv;
                let nr = n_rigid(dim);
                let (rigid, modal) = (dq.rows(0, nr).amax(), dq.rows(nr, 4).amax());
                // Measured: rigid rows ≤ 3e-9 of the modal difference (round-off of the
                // differences), modal ≥ 8e-3 of the largest force, power ≤ 5e-10.
                let power = s.qd.dot(&dq).abs() / (s.qd.norm() * dq.norm());
                eprintln!(
                    "{dim} o{order}: rigid {:.1e}, modal {:.1e}, power {power:.1e}",
                    rigid / modal,
                    modal / q_ref.amax()
                );
                assert!(rigid < 1e-8 * modal, "{dim} o{order}: rigid rows {rigid:e}");
                assert!(modal > 1e-3 * q_ref.amax(), "{dim} o{order}: negligible");
                assert!(power < 1e-8, "{dim} o{order}: power {power:e}");
            }
        }
    }
}

#[test]
fn order_zero_and_uncoupled_mass_matrices_are_positive_definite() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut r = rng(31);
        let rb = random_body(&mut r, dim, 5, 11);
        for t in [
            terms(0, true, true),
            terms(0, true, false),
            terms(2, true, false),
        ] {
            let b = truncated(&rb, t);
            let mut ws = b.natural_workspace();
            for _ in 0..10 {
                let mut st = random_state(&mut r, dim, 5);
                st.y.iter_mut().for_each(|v| *v *= 20.0); // far beyond small deformation
                let (s, _, _) = natural_from_relative(&st.view(), dim, 5);
                let (m, _): (DMatrix<f64>, _) = eval_natural(&b, &mut ws, &s.view(), SI);
                assert!(m.cholesky().is_some(), "{dim} {t}: positive definite");
            }
        }
    }
}
