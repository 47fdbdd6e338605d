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
    match flexmbd_model::PreparedScene::new(&s).and_then(|p| flexmbd_relative::compile(&p)) {
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
    let f = relative(&s);
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
    match flexmbd_model::PreparedScene::new(&s).and_then(|p| flexmbd_relative::compile(&p)) {
        Err(e @ ModelError::Invalid { .. }) => {
            let m = e.to_string();
            assert!(m.contains("forces[k]") && m.contains("coincide"), "{m}");
        }
        Err(e) => panic!("unexpected error {e}"),
        Ok(_) => panic!("accepted a zero-length spring"),
    }
}

#[test]
fn redundant_closures_run_and_inconsistent_ones_are_refused() {
    // Redundant: the joint at B2 written twice (the second copy is cut into the same two
    // closure equations). ALI3-P's penalty form tolerates the rank deficiency: same motion.
    let base = four_bar(0);
    let mut redundant = base.clone();
    // Every joint twice: the twins of tree joints give identically zero rows, those of the
    // two cut joints duplicate their closure equations.
    for j in base.joints.clone() {
        let mut twin = j;
        twin.name = format!("{}_twin", twin.name);
        redundant.joints.push(twin);
    }
    let (fa, fb) = (relative(&base), relative(&redundant));
    assert!(fb.n_constraints() > fa.n_constraints());
    let (a, _) = run_relative(&base, 1e-3, 1.0, 100);
    let (b, _) = run_relative(&redundant, 1e-3, 1.0, 100);
    let d = largest_difference(&a, &b, &[0, 1]);
    eprintln!("redundant closure: max |ΔB0| {d:.1e} m over 1 s");
    assert!(d < 1e-8, "{d:e}");
    // Inconsistent: coupler2's far marker at 5 m, so the loop cannot close in any position
    // (B1 is at most 2 m from A2 and B2 at most 1 m from it): its joined markers do not
    // coincide at t = 0, which the prepared scene refuses for both formulations alike.
    let mut bad = base;
    let coupler2 = bad
        .bodies
        .iter_mut()
        .find(|b| b.name == "coupler2")
        .unwrap();
    coupler2
        .markers
        .iter_mut()
        .find(|m| m.name == "B")
        .unwrap()
        .position
        .0[0] = 5.0;
    let err = match flexmbd_model::PreparedScene::new(&bad) {
        Ok(_) => panic!("an inconsistent loop must not start"),
        Err(e) => e.to_string(),
    };
    eprintln!("{err}");
    assert!(
        err.contains("joints[B2]") && err.contains("must coincide at t = 0"),
        "{err}"
    );
}
