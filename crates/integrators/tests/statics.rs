//! The static-equilibrium solver (docs/methods.md §5.4 item 4) on small formulations with
//! closed-form answers: a hanging pendulum in natural coordinates (constraint curvature is
//! the only tangent; redundant copies of the constraint), a hardening spring chain with a
//! held coordinate, the load stepping of a snap-free but strongly non-linear spring, and
//! the error paths (no equilibrium; a free rigid-body motion).

mod common;
use common::*;
use flexmbd_core::{Coordinates, Formulation, Request, State, SystemTerms};
use flexmbd_integrators::{
    Ali3p, Ali3pSettings, StartFrom, StaticError, StaticSettings, solve_static,
};
use nalgebra::DVector;

#[test]
fn pendulum_hangs_down_with_the_weight_in_the_rod() {
    for copies in [1, 2] {
        // 60° off the vertical: the tangent is the constraint curvature alone.
        let mut p = pendulum(1.0).with_copies(copies);
        let sol = solve_static(&mut p, 0.0, &StaticSettings::default()).unwrap();
        eprintln!(
            "copies {copies}: q = {:?}, λ = {:?}, {} iterations, {} load steps",
            sol.q.as_slice(),
            sol.lambda.as_slice(),
            sol.counters.iterations,
            sol.counters.load_steps
        );
        assert!(sol.q[0].abs() < 1e-10, "{}", sol.q[0]);
        assert!((sol.q[1] + LENGTH).abs() < 1e-10, "{}", sol.q[1]);
        // Q − Φ_qᵀλ = 0: (0, −mg) − Σλ (0, −2L) = 0, Σλ = mg / (2L) (the rod tension mg).
        let sum: f64 = sol.lambda.iter().sum();
        assert!(
            (sum - MASS * G / (2.0 * LENGTH)).abs() < 1e-8 * MASS * G,
            "{sum}"
        );
        assert!(sol.counters.residual.is_finite() && sol.counters.phi < 1e-10);
    }
    // With the formulation's K (zero here) the tangent Φ_qᵀαΦ_q is singular along the circle:
    // the error says so instead of returning garbage.
    let mut p = pendulum(1.0);
    let e = solve_static(
        &mut p,
        0.0,
        &StaticSettings {
            fd_tangent: false,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(matches!(e, StaticError::Singular { .. }), "{e}");
}

/// Unit masses on springs, unconstrained: `load` writes the forces (and, when asked, the
/// tangents) at q; the coordinates hold the start and the specified coordinates.
struct Unconstrained<L: FnMut(&DVector<f64>, Request, &mut SystemTerms)> {
    coordinates: Coordinates,
    load: L,
}

impl<L: FnMut(&DVector<f64>, Request, &mut SystemTerms)> Unconstrained<L> {
    /// Starting at rest at `q0`, `hold` held.
    fn new(hold: Vec<usize>, q0: &[f64], load: L) -> Self {
        let n = q0.len();
        let coordinates = Coordinates {
            specified: hold,
            ..Coordinates::new(DVector::from_column_slice(q0), DVector::zeros(n), 0)
        };
        Unconstrained { coordinates, load }
    }
}

impl<L: FnMut(&DVector<f64>, Request, &mut SystemTerms)> Formulation for Unconstrained<L> {
    fn coordinates(&self) -> &Coordinates {
        &self.coordinates
    }
    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        if req.dynamics {
            for i in 0..self.coordinates.len() {
                out.mass[(i, i)] = 1.0;
            }
            (self.load)(state.q, req, out);
        }
    }
}

/// Two masses on hardening springs in series along x: ground —k₁— x₀ —k₂— x₁, spring force
/// k s (1 + c s²), load P on each; x₀ held at a given value when `hold` is set.
fn chain(
    hold: Vec<usize>,
    q0: [f64; 2],
    p: f64,
    c: f64,
) -> Unconstrained<impl FnMut(&DVector<f64>, Request, &mut SystemTerms)> {
    Unconstrained::new(hold, &q0, move |q, req, out| {
        let (f1, k1) = spring(K1, c, q[0]);
        let (f2, k2) = spring(K2, c, q[1] - q[0]);
        out.forces[0] = p - f1 + f2;
        out.forces[1] = p - f2;
        if req.tangents {
            out.stiffness[(0, 0)] = k1 + k2;
            out.stiffness[(0, 1)] = -k2;
            out.stiffness[(1, 0)] = -k2;
            out.stiffness[(1, 1)] = k2;
        }
    })
}
const K1: f64 = 1e3;
const K2: f64 = 4e2;

fn spring(k: f64, c: f64, s: f64) -> (f64, f64) {
    (k * s * (1.0 + c * s * s), k * (1.0 + 3.0 * c * s * s))
}

/// Solve k s (1 + c s²) = f for s by bisection (monotone).
fn invert(k: f64, c: f64, f: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, f / k);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if spring(k, c, mid).0 < f {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn hardening_chain_with_both_tangents_and_a_held_coordinate() {
    // Strongly non-linear: the linear guess P/k overshoots the hardened answer many times.
    let (p, c) = (50.0, 400.0);
    let s2 = invert(K2, c, p);
    let s1 = invert(K1, c, 2.0 * p);
    for fd in [true, false] {
        let mut ch = chain(vec![], [0.0, 0.0], p, c);
        let settings = StaticSettings {
            fd_tangent: fd,
            ..Default::default()
        };
        let sol = solve_static(&mut ch, 0.0, &settings).unwrap();
        eprintln!(
            "fd {fd}: q = {:?} ({} iterations, {} load steps), exact ({s1}, {})",
            sol.q.as_slice(),
            sol.counters.iterations,
            sol.counters.load_steps,
            s1 + s2
        );
        assert!((sol.q[0] - s1).abs() < 1e-10 && (sol.q[1] - s1 - s2).abs() < 1e-10);
    }
    // x₀ held at 0.01: only the second spring carries its load.
    let mut ch = chain(vec![0], [0.01, 0.0], p, c);
    let sol = solve_static(&mut ch, 0.0, &StaticSettings::default()).unwrap();
    assert_eq!(sol.q[0], 0.01);
    assert!((sol.q[1] - 0.01 - s2).abs() < 1e-10, "{}", sol.q[1]);
}

/// A softening spring k s / (1 + s²) carries at most k/2: above that load there is no
/// equilibrium, and below it the spring is strongly non-linear.
fn softening(p: f64) -> Unconstrained<impl FnMut(&DVector<f64>, Request, &mut SystemTerms)> {
    Unconstrained::new(vec![], &[0.0], move |q, req, out| {
        let s = q[0];
        out.forces[0] = p - s / (1.0 + s * s);
        if req.tangents {
            out.stiffness[(0, 0)] = (1.0 - s * s) / (1.0 + s * s).powi(2);
        }
    })
}

#[test]
fn no_equilibrium_is_an_error_with_data_and_a_near_limit_load_converges() {
    // Near the limit load 0.5: s/(1 + s²) = 0.49 at s = 0.8174 (the stable root).
    let mut near = softening(0.49);
    let sol = solve_static(&mut near, 0.0, &StaticSettings::default()).unwrap();
    let s = sol.q[0];
    assert!((s / (1.0 + s * s) - 0.49).abs() < 1e-12 && s < 1.0, "{s}");

    let mut over = softening(0.6);
    let e = solve_static(&mut over, 0.0, &StaticSettings::default()).unwrap_err();
    eprintln!("{e}");
    let StaticError::NoConvergence {
        iterations,
        residual,
        load_factor,
        ..
    } = e
    else {
        panic!("{e}")
    };
    assert!(iterations > 0 && residual.is_finite() && residual > 0.0);
    // The loads up to 0.5/0.6 of the full load have equilibria; the last one solved is below.
    assert!(
        load_factor < 0.5 / 0.6 && load_factor > 0.5,
        "{load_factor}"
    );
    assert!(e.to_string().contains("load factor"));
}

/// A free mass under gravity has no equilibrium and no stiffness: the tangent is singular.
fn free() -> Unconstrained<impl FnMut(&DVector<f64>, Request, &mut SystemTerms)> {
    Unconstrained::new(vec![], &[0.0], |_, _, out| out.forces[0] = -G)
}

#[test]
fn a_free_body_is_refused_as_singular() {
    let e = solve_static(&mut free(), 0.0, &StaticSettings::default()).unwrap_err();
    assert!(matches!(e, StaticError::Singular { .. }), "{e}");
}

/// Started at the static solution, ALI3-P stays there: the multipliers of the consistent
/// start carry the weight and nothing moves.
#[test]
fn alip3_started_at_the_equilibrium_stays_put() {
    let mut p = pendulum(0.3);
    let sol = solve_static(&mut p, 0.0, &StaticSettings::default()).unwrap();
    let settings = Ali3pSettings::default();
    let mut s = Ali3p::new(&mut StartFrom::at_rest(&mut p, &sol), 0.0, settings).unwrap();
    for _ in 0..1000 {
        s.step(&mut p).unwrap();
    }
    assert!(
        s.q[0].abs() < 1e-9 && (s.q[1] + LENGTH).abs() < 1e-9,
        "{:?}",
        s.q
    );
    assert!(s.qd.amax() < 1e-9, "{:?}", s.qd);
}

#[test]
fn start_from_replaces_the_initial_guess_and_keeps_constraints_and_specified_coordinates() {
    let mut p = pendulum(0.3).with_copies(2);
    p.coordinates.specified = vec![0];
    let q = DVector::from_column_slice(&[0.0, -LENGTH]);
    let qd = DVector::from_column_slice(&[0.1, 0.0]);
    let start = StartFrom::new(&mut p, q.clone(), qd.clone());
    assert_eq!((start.n_coordinates(), start.n_constraints()), (2, 2));
    assert_eq!(start.specified_coordinates(), &[0]);
    let (mut q_start, mut qd_start) = (DVector::zeros(2), DVector::zeros(2));
    start.initial_guess(&mut q_start, &mut qd_start);
    assert_eq!((q_start, qd_start), (q, qd));
}
