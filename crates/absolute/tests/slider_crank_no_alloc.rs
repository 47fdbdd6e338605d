//! The step loop of the flexible slider-crank (prismatic joint, spring–damper, state-dependent
//! tangents) allocates nothing after set-up, with both inertia routes (counting allocator).

use flexmbd_body::InertiaMethod;
use flexmbd_integrators::{Ali3p, Ali3pSettings};
use flexmbd_model::Scene;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn slider_crank_steps_allocate_nothing() {
    for method in [InertiaMethod::ShapeIntegrals, InertiaMethod::BMatrix] {
        let mut scene = Scene::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../models/slider_crank.ron"
        ))
        .unwrap();
        scene.bodies[0].flexible = true;
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
