//! The step loop of the planar absolute formulation allocates nothing after set-up,
//! with rigid and flexible bodies and both inertia routes (counting allocator).

mod common;
use common::*;
use flexmbd_body::InertiaMethod;
use flexmbd_test_support::scenes::model;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn flexible_four_bar_steps_allocate_nothing() {
    for method in [InertiaMethod::ShapeIntegrals, InertiaMethod::BMatrix] {
        let mut scene = model("double_four_bar.ron");
        for b in scene.bodies.iter_mut().take(3) {
            b.flexible = true;
        }
        scene.solver.inertia = method;
        let allocated = step_loop_allocations(&scene, 300);
        assert_eq!(
            allocated, 0,
            "{method:?}: the step loop allocated {allocated} times"
        );
    }
}
