//! Spring–dampers in the relative formulation (`models/slider_crank.ron`: a spring–damper
//! from the wall to the slider; here also one from a node of the flexible rod to the
//! ground, so the modal columns of the Jacobian are exercised):
//! - Q of the springs is −∂V/∂z of their energy (finite differences), C = −∂Q/∂ż exactly;
//!   also for a spring on a body hung from a flexible node (markers moving with node joints);

mod common;
use common::*;
use flexmbd_core::Formulation;
use flexmbd_model::{FormulationKind, Scene};

fn scene() -> Scene {
    let mut s = slider_crank_with_rod_spring();
    s.solver.formulation = FormulationKind::Relative;
    s
}

#[test]
fn spring_forces_are_minus_the_energy_gradient_and_c_is_exact() {
    let with = scene();
    let (mut a, mut b) = with_and_without_forces(&with, flexmbd_relative::compile);
    let n = a.n_coordinates();
    let ie = sensor_column(&with, "energy");
    let (mut q, mut qd) = (a.coordinates().q0.clone(), a.coordinates().qd0.clone());
    // A deformed, moved state (joint angles and modal coordinates).
    for i in 0..n {
        q[i] += 0.05 * ((i as f64) * 1.3 + 0.4).sin() * if i >= 3 { 1e-3 } else { 1.0 };
        qd[i] = 0.7 * ((i as f64) * 0.7 + 0.1).cos() * if i >= 3 { 1e-2 } else { 1.0 };
    }
    let eps = |j| if j >= 3 { 1e-7 } else { 1e-6 };
    let (err, q_spring) = spring_gradient_error(&mut a, &mut b, ie, &q, eps);
    eprintln!("|Q_spring + ∂V/∂z| {err:.1e} (|Q_spring| {q_spring:.2})");
    // Measured 6.8e-9 (the differences' own error) against |Q_spring| = 12.
    assert!(q_spring > 1.0 && err < 1e-8 * q_spring, "{err:e}");
    // C = −∂Q/∂ż of the springs (Q is linear in ż).
    let cerr = spring_damping_error(&mut a, &mut b, &q, &qd);
    eprintln!("|C_spring − (−∂Q/∂ż)| {cerr:.1e}");
    assert!(cerr < 1e-9, "{cerr:e}");
}

/// A marker whose body hangs from a flexible body's node moves with node joints (w columns
/// that are combinations of z, folded through L): the double four-bar with crank1 flexible,
/// its coupler carried by crank1's tip node, and a spring–damper from the ground to the
/// coupler's far end. Reproduces the marker Jacobian's fold through L, which the rigid scenes
/// (columns handed over directly) do not reach.
#[test]
fn spring_on_a_body_hung_from_a_flexible_node_is_minus_the_energy_gradient() {
    let mut with = four_bar(1);
    with.solver.formulation = FormulationKind::Relative;
    with.forces.push(flexmbd_model::Force::SpringDamper {
        name: "hung".into(),
        body1: "ground".into(),
        marker1: "A2".into(),
        body2: "coupler1".into(),
        marker2: "B".into(),
        stiffness: 500.0,
        damping: 3.0,
        free_length: Some(0.5),
    });
    let (mut a, mut b) = with_and_without_forces(&with, flexmbd_relative::compile);
    let n = a.n_coordinates();
    let ie = sensor_column(&with, "energy");
    let (mut q, mut qd) = (a.coordinates().q0.clone(), a.coordinates().qd0.clone());
    for i in 0..n {
        q[i] += 1e-3 * ((i as f64) * 1.3 + 0.4).sin();
        qd[i] += 0.1 * ((i as f64) * 0.7 + 0.1).cos();
    }
    let (err, q_spring) = spring_gradient_error(&mut a, &mut b, ie, &q, |_| 1e-7);
    eprintln!("|Q_spring + ∂V/∂z| {err:.1e} (|Q_spring| {q_spring:.2})");
    // Measured 8.0e-7 (the differences' own error) against |Q_spring| = 647.
    assert!(
        q_spring > 1.0 && err < 1e-8 * q_spring,
        "{err:e} of {q_spring}"
    );
    let cerr = spring_damping_error(&mut a, &mut b, &q, &qd);
    eprintln!("|C_spring − (−∂Q/∂ż)| {cerr:.1e}");
    assert!(cerr < 1e-9, "{cerr:e}");
}
