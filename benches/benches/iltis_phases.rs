//! What one ALI3-P step of the Iltis runs is made of, piece by piece, in the relative
//! formulation with shape integrals (the faster pairing): the three formulation passes a
//! step makes (docs/methods.md §5.2) and the factorisation and solve of its leading matrix
//! f_q = M + h/2 C + h²/4 (K + α Φ_qᵀ Φ_q). These are what bound issue 13's and 14's speed
//! targets. A step that converges in one Newton iteration makes, at least,
//!
//! ```text
//! dynamics_tangents + 2 constraints + accel_term   (the correction's pass, which also takes
//!                                                   Φ and Φ_q at the predictor; the
//!                                                   multiplier update's at the corrected q;
//!                                                   the acceleration projection's)
//! + 2 factorise + 3 solve                          (Newton's f_q, and the projections' f_q
//!                                                   refactorised at the converged q)
//! ```
//!
//! plus forming f_q twice and the vector work; each further iteration adds one
//! dynamics_tangents, constraints, factorise and solve.
//!
//! Cases: the rigid benchmark vehicle on the bump (22 coordinates), the rigid thesis vehicle
//! (42) and with its 12 beam bodies flexible (118), each at the state reached after 1 s of
//! its own run. The passes alternate between q and q with its first coordinate moved by
//! 1e-9, so that every call recomputes the positions as a step's passes do. The
//! factorisation is the one the integrator picks for that f_q (the arrow form for the
//! vehicle, dense below 32 coordinates); `work` in the output line is its flop count.

use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use flexmbd::Simulation;
use flexmbd::core::{Request, State, SystemTerms};
use flexmbd::integrators::arrow_llt::ArrowLlt;
use flexmbd::integrators::lu::DenseLlt;
use flexmbd::model::{FormulationKind, Scene};
use flexmbd::simulation::compile;
use flexmbd_test_support::iltis::vehicle_flexible;
use flexmbd_test_support::scenes::model_with;
use nalgebra::{DMatrix, DVector};

/// The relative, shape-integral scene of each case.
fn cases() -> Vec<(&'static str, Scene)> {
    let relative = |file, k| model_with(file, FormulationKind::Relative, &vehicle_flexible(k));
    let mut cases = vec![
        ("bump", relative("iltis_bump.ron", 0)),
        ("vehicle_rigid", relative("iltis_vehicle.ron", 0)),
        ("vehicle_12_flexible", relative("iltis_vehicle.ron", 12)),
    ];
    for (_, scene) in &mut cases {
        scene.solver.inertia = flexmbd::body::InertiaMethod::ShapeIntegrals;
    }
    cases
}

/// The leading matrix's factorisation as the integrator chooses it for this f_q.
enum Factorisation {
    Arrow(Box<ArrowLlt>),
    Dense(DenseLlt),
}

impl Factorisation {
    fn choose(lead: &DMatrix<f64>) -> (Self, f64) {
        match ArrowLlt::detect(lead) {
            Some(arrow) => {
                let work = arrow.work();
                (Factorisation::Arrow(Box::new(arrow)), work)
            }
            None => {
                let n = lead.nrows() as f64;
                (
                    Factorisation::Dense(DenseLlt::new(lead.nrows())),
                    n * n * n / 3.0,
                )
            }
        }
    }

    fn factor(&mut self, lead: &DMatrix<f64>) {
        match self {
            Factorisation::Arrow(arrow) => arrow.factor(lead).expect("f_q is SPD"),
            Factorisation::Dense(dense) => dense.factor(lead).expect("f_q is SPD"),
        }
    }

    fn solve(&mut self, b: &mut DVector<f64>) {
        match self {
            Factorisation::Arrow(arrow) => arrow.solve_in_place(b),
            Factorisation::Dense(dense) => dense.solve_in_place(b),
        }
    }
}

fn phases(c: &mut Criterion) {
    let mut group = c.benchmark_group("iltis_phases");
    group
        .sample_size(30)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for (name, scene) in cases() {
        let mut simulation = Simulation::new(&scene).expect("the vehicle starts");
        simulation.advance_to(1.0).expect("the first second runs");
        let (h, alpha) = (simulation.step_size(), simulation.integrator().penalty());
        let state = simulation.integrator().state();
        let (t, q, qd) = (state.t, state.q.clone(), state.qd.clone());
        let mut moved = q.clone();
        moved[0] += 1e-9;
        let mut formulation = compile(&scene).expect("the scene compiles");
        let (n, m) = (q.len(), simulation.n_constraints());
        let mut terms = SystemTerms::new(n, m);

        let passes = [
            (
                "dynamics_tangents",
                Request {
                    dynamics: true,
                    tangents: true,
                    ..Request::default()
                },
            ),
            (
                "dynamics",
                Request {
                    dynamics: true,
                    ..Request::default()
                },
            ),
            (
                "constraints",
                Request {
                    constraints: true,
                    jacobian: true,
                    ..Request::default()
                },
            ),
            (
                "accel_term",
                Request {
                    accel_term: true,
                    ..Request::default()
                },
            ),
        ];
        for (pass, request) in passes {
            let mut flip = false;
            group.bench_function(BenchmarkId::new(pass, name), |b| {
                b.iter(|| {
                    flip = !flip;
                    let at = if flip { &moved } else { &q };
                    terms.clear(request);
                    formulation.evaluate(State::new(t, at, &qd), request, &mut terms);
                })
            });
        }

        // f_q at q, as the integrator forms it.
        let all = Request {
            dynamics: true,
            tangents: true,
            constraints: true,
            jacobian: true,
            accel_term: false,
        };
        terms.clear(all);
        formulation.evaluate(State::new(t, &q, &qd), all, &mut terms);
        let penalty = &terms.phi_q.transpose() * &terms.phi_q * (0.25 * h * h * alpha);
        let lead =
            &terms.mass + &terms.damping * (0.5 * h) + &terms.stiffness * (0.25 * h * h) + penalty;
        let (mut factorisation, work) = Factorisation::choose(&lead);
        println!("iltis_phases/{name}: n = {n}, m = {m}, factorisation work {work:.0} flops");
        group.bench_function(BenchmarkId::new("factorise", name), |b| {
            b.iter(|| factorisation.factor(&lead))
        });
        let rhs = DVector::from_fn(n, |i, _| 1.0 + i as f64);
        let mut x = rhs.clone();
        group.bench_function(BenchmarkId::new("solve", name), |b| {
            b.iter(|| {
                x.copy_from(&rhs);
                factorisation.solve(&mut x);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, phases);
criterion_main!(benches);
