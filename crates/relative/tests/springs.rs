//! Spring–dampers in the relative formulation (`models/slider_crank.ron`: a spring–damper
//! from the wall to the slider; here also one from a node of the flexible rod to the
//! ground, so the modal columns of the Jacobian are exercised):
//! - Q of the springs is −∂V/∂z of their energy (finite differences), C = −∂Q/∂ż exactly;

mod common;
use common::*;
use flexmbd_core::Observe as _;
use flexmbd_core::{Formulation, State, SystemTerms};
use flexmbd_model::{FormulationKind, Scene};
use nalgebra::DVector;

fn scene() -> Scene {
    let mut s = slider_crank_with_rod_spring();
    s.solver.formulation = FormulationKind::Relative;
    s
}

fn eval(f: &mut impl Formulation, q: &DVector<f64>, qd: &DVector<f64>) -> SystemTerms {
    terms_at(f, 0.0, q, qd)
}

#[test]
fn spring_forces_are_minus_the_energy_gradient_and_c_is_exact() {
    let with = scene();
    let (mut a, mut b) = with_and_without_forces(&with, flexmbd_relative::compile);
    let n = a.n_coordinates();
    let ie = sensor_column(&with, "energy");
    let (mut q, mut qd) = (DVector::zeros(n), DVector::zeros(n));
    a.initial_guess(&mut q, &mut qd);
    // A deformed, moved state (joint angles and modal coordinates).
    for i in 0..n {
        q[i] += 0.05 * ((i as f64) * 1.3 + 0.4).sin() * if i >= 3 { 1e-3 } else { 1.0 };
        qd[i] = 0.7 * ((i as f64) * 0.7 + 0.1).cos() * if i >= 3 { 1e-2 } else { 1.0 };
    }
    let zero = DVector::zeros(n);
    let energy = |f: &mut flexmbd_relative::Relative, q: &DVector<f64>| {
        let mut out = vec![0.0; with.sensors.len()];
        f.sensors(State::new(0.0, q, &zero), &mut out);
        out[ie]
    };
    let dq = eval(&mut a, &q, &zero).forces - eval(&mut b, &q, &zero).forces;
    let err = energy_gradient_error(
        n,
        |j| if j >= 3 { 1e-7 } else { 1e-6 },
        |j| dq[j],
        |j, e| {
            let mut qe = q.clone();
            qe[j] += e;
            (energy(&mut a, &qe), energy(&mut b, &qe))
        },
    );
    eprintln!("|Q_spring + ∂V/∂z| {err:.1e} (|Q_spring| {:.2})", dq.amax());
    // Measured 6.8e-9 (the differences' own error) against |Q_spring| = 12.
    assert!(dq.amax() > 1.0 && err < 1e-8 * dq.amax(), "{err:e}");
    // C = −∂Q/∂ż of the springs (Q is linear in ż).
    let cerr = damping_error(n, |j| {
        let mut qdp = qd.clone();
        if let Some(j) = j {
            qdp[j] += 1.0;
        }
        (eval(&mut a, &q, &qdp), eval(&mut b, &q, &qdp))
    });
    eprintln!("|C_spring − (−∂Q/∂ż)| {cerr:.1e}");
    assert!(cerr < 1e-9, "{cerr:e}");
}
