//! The step loop of the planar absolute formulation allocates nothing after set-up,
//! with rigid and flexible bodies and both inertia routes (counting allocator).

use flexmbd_body::InertiaMethod;
use flexmbd_integrators::{Ali3p, Ali3pSettings};
use flexmbd_model::Scene;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn flexible_four_bar_steps_allocate_nothing() {
    for method in [InertiaMethod::ShapeIntegrals, InertiaMethod::BMatrix] {
        let mut scene = Scene::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../models/double_four_bar.ron"
        ))
        .unwrap();
        for b in scene.bodies.iter_mut().take(3) {
            b.flexible = true;
        }
        scene.solver.inertia = method;
        let mut f = flexmbd_model::PreparedScene::new(&scene)
            .and_then(|p| flexmbd_absolute::compile(&p))
            .unwrap();
        let mut s = Ali3p::new(&mut f, 0.0, Ali3pSettings::default()).unwrap();
        s.step(&mut f).unwrap();
        let before = flexmbd_test_support::allocations();
        for _ in 0..300 {
            s.step(&mut f).unwrap();
        }
        let allocated = flexmbd_test_support::allocations() - before;
        assert_eq!(
            allocated, 0,
            "{method:?}: the step loop allocated {allocated} times"
        );
    }
}
