//! The step loop of the planar absolute formulation allocates nothing after set-up,
//! with rigid and flexible bodies and both inertia routes (counting allocator).

mod common;
use common::*;
use flexmbd_test_support::scenes::model;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn flexible_four_bar_steps_allocate_nothing() {
    let mut scene = model("double_four_bar.ron");
    for b in scene.bodies.iter_mut().take(3) {
        b.flexible = true;
    }
    assert_steps_allocate_nothing(scene, 300);
}
