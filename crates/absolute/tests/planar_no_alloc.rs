//! The step loop of the planar absolute formulation allocates nothing after set-up,
//! with rigid and flexible bodies and both inertia routes (counting allocator).

mod common;
use common::*;
use flexmbd_test_support::scenes::model;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn distance_constraint_steps_allocate_nothing() {
    // The outer cranks' tips held at their distance (redundant for rigid bars, binding for
    // the flexible ones).
    let mut scene = model("double_four_bar.ron");
    for b in scene.bodies.iter_mut().take(3) {
        b.flexible = true;
    }
    scene.constraints.push(flexmbd_model::Constraint::Distance {
        name: "tips".into(),
        body1: "crank1".into(),
        marker1: "B".into(),
        body2: "crank3".into(),
        marker2: "B".into(),
        length: None,
    });
    assert_steps_allocate_nothing(scene, 300);
}

#[test]
fn flexible_four_bar_steps_allocate_nothing() {
    let mut scene = model("double_four_bar.ron");
    for b in scene.bodies.iter_mut().take(3) {
        b.flexible = true;
    }
    assert_steps_allocate_nothing(scene, 300);
}
