//! The step loop of the flexible slider-crank (prismatic joint, spring–damper, state-dependent
//! tangents) allocates nothing after set-up, with both inertia routes (counting allocator).

mod common;
use common::*;
use flexmbd_test_support::scenes::model;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn slider_crank_steps_allocate_nothing() {
    let mut scene = model("slider_crank.ron");
    scene.bodies[0].flexible = true;
    assert_steps_allocate_nothing(scene, 300);
}
