//! Refusals with clear messages, and the floating base.

mod common;
use common::*;
use flexmbd_core::Formulation;
use flexmbd_model::ModelError;

#[test]
fn bodies_not_reaching_the_ground_are_refused() {
    let mut s = four_bar(0);
    // Cut crank2 and crank3 from the ground: crank1's loop alone still reaches it, but
    // removing every ground joint leaves the mechanism floating.
    s.joints.retain(|j| j.body1 != "ground");
    s.drivers.clear();
    match flexmbd_relative::compile(&s) {
        Err(ModelError::Unsupported(m)) => {
            eprintln!("{m}");
            assert!(m.contains("do not reach the ground"), "{m}");
        }
        Err(e) => panic!("unexpected error {e}"),
        Ok(_) => panic!("accepted a floating mechanism"),
    }
}

#[test]
fn a_body_without_joints_is_a_floating_base_in_free_fall() {
    let mut s = model("flexible_pendulum.ron");
    s.joints.clear();
    s.sensors
        .retain(|x| x.name == "tip_y" || x.name == "energy");
    s.bodies[0].flexible = false;
    let f = flexmbd_relative::compile(&s).unwrap();
    assert_eq!((f.n_coordinates(), f.n_constraints()), (3, 0));
    let (rows, _) = run_relative(&s, 1e-3, 1.0, 1000);
    let fall = rows[1][0] - rows[0][0];
    eprintln!("free fall in 1 s: {fall:.9} m");
    assert!((fall + 0.5 * 9.81).abs() < 1e-9, "{fall}");
}

#[test]
fn a_spring_of_zero_length_is_refused() {
    let mut s = four_bar(0);
    // Both markers at the ground pivot A0 at t = 0: no direction for the force.
    s.forces.push(flexmbd_model::Force::SpringDamper {
        name: "k".into(),
        body1: "ground".into(),
        marker1: "A0".into(),
        body2: "crank1".into(),
        marker2: "A".into(),
        stiffness: 10.0,
        damping: 0.0,
        free_length: None,
    });
    match flexmbd_relative::compile(&s) {
        Err(e @ ModelError::Invalid { .. }) => {
            let m = e.to_string();
            assert!(m.contains("forces[k]") && m.contains("coincide"), "{m}");
        }
        Err(e) => panic!("unexpected error {e}"),
        Ok(_) => panic!("accepted a zero-length spring"),
    }
}
