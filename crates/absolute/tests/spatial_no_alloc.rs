//! The spatial formulation's per-step path allocates nothing (counting global allocator):
//! evaluation passes of every kind and whole ALI3-P steps, on the rigid double pendulum
//! (constant rigid-body terms, spherical and revolute joints) and the flexible pendulum
//! (natural-set inertia, gravity, elastic forces and tangents), and the FS0 spin-up beam
//! (both inertia routes, tip sensors with the foreshortening shift), and a spring–damper to a
//! flexible body's node (force elements with their tangents), and the scene's distance and
//! point-in-plane constraints on such a node.

mod common;
use common::*;
use flexmbd_body::InertiaMethod;
use flexmbd_core::Observe as _;
use flexmbd_core::{Formulation, Request, SystemTerms};
use flexmbd_test_support::scenes::model;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn spatial_steps_do_not_allocate() {
    let mut scenes = vec![
        model("double_pendulum_3d.ron"),
        model("flexible_pendulum_3d.ron"),
    ];
    let mut bm = model("flexible_pendulum_3d.ron");
    bm.solver.inertia = InertiaMethod::BMatrix;
    scenes.push(bm);
    // FS0 (docs/methods.md §6.3): the 3D spin-up beam, both inertia routes.
    let mut fs0 = model("spin_up_beam_3d.ron");
    fs0.solver.stiffening = flexmbd_model::Stiffening::Foreshortening;
    scenes.push(fs0.clone());
    fs0.solver.inertia = InertiaMethod::BMatrix;
    scenes.push(fs0);
    // A spring–damper from the ground to the flexible pendulum's tip node.
    let mut sprung = model("flexible_pendulum_3d.ron");
    sprung.forces.push(flexmbd_model::Force::SpringDamper {
        name: "anchor_tip".into(),
        body1: "ground".into(),
        marker1: "O".into(),
        body2: "beam".into(),
        marker2: "tip".into(),
        stiffness: 30.0,
        damping: 0.2,
        free_length: Some(0.5),
    });
    scenes.push(sprung);
    // The scene's Distance and PointInPlane constraints on the tip node.
    scenes.push(flexmbd_test_support::scenes::flexible_pendulum_3d_with_constraints());
    for scene in &scenes {
        let mut f = absolute(scene);
        let mut s = ali3p_at(&mut f, 1e-3);
        let mut out = SystemTerms::new(f.n_coordinates(), f.n_constraints());
        // Warm up (lazily sized storage, if any).
        for _ in 0..5 {
            s.step(&mut f).unwrap();
        }
        let mut sens = vec![0.0; f.sensor_names().len()];
        let before = flexmbd_test_support::allocations();
        for _ in 0..100 {
            s.step(&mut f).unwrap();
        }
        f.sensors(s.state(), &mut sens);
        for req in [Request::ALL, Request::CONSTRAINTS] {
            out.clear(req);
            f.evaluate(s.state(), req, &mut out);
        }
        let n = flexmbd_test_support::allocations() - before;
        assert_eq!(n, 0, "{}: {n} allocations in 100 steps", scene.name);
    }
}
