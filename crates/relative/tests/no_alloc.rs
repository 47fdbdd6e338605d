//! The per-step path (evaluation passes and the ALI3-P step) allocates nothing
//! (counting global allocator).

mod common;
use common::*;

use flexmbd_core::{Formulation, Request, State, SystemTerms};
use flexmbd_integrators::Ali3p;
use nalgebra::DVector;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn steps_and_evaluations_do_not_allocate() {
    let mut scenes = vec![four_bar(0), four_bar(5), model("flexible_pendulum.ron")];
    for extra in [
        "double_pendulum_3d.ron",
        "flexible_pendulum_3d.ron",
        "slider_crank.ron",
        "floating_platform_3d.ron",
    ] {
        if std::path::Path::new(&format!(
            "{}/../../models/{extra}",
            env!("CARGO_MANIFEST_DIR")
        ))
        .exists()
        {
            scenes.push(model(extra));
        }
    }
    // The scene's Distance and PointInPlane constraints as cut rows, on a flexible node.
    scenes.push(flexmbd_test_support::scenes::flexible_pendulum_3d_with_constraints());
    // Buckens beams hung through the inverse node chain of their own modes: translations
    // (the pendulum's pin), and the three rotations of the driven 3D spin-up beam's root.
    for (file, body) in [
        ("flexible_pendulum.ron", "bar"),
        ("spin_up_beam_3d.ron", "beam"),
    ] {
        let set = format!("bodies.{body}.model.Beam.reference=Buckens");
        scenes.push(model_with(
            file,
            flexmbd_model::FormulationKind::Relative,
            &[set],
        ));
    }
    for scene in scenes {
        let mut f = relative(&scene);
        let (n, m) = (f.n_coordinates(), f.n_constraints());
        let mut s = Ali3p::new(&mut f, 0.0, settings(&scene, 1e-3)).unwrap();
        s.step(&mut f).unwrap();
        let mut terms = SystemTerms::new(n, m);
        let (q, qd) = (
            DVector::from_element(n, 0.01),
            DVector::from_element(n, 0.2),
        );
        let before = flexmbd_test_support::allocations();
        for _ in 0..50 {
            s.step(&mut f).unwrap();
        }
        terms.clear(Request::ALL);
        f.evaluate(State::new(0.1, &q, &qd), Request::ALL, &mut terms);
        let count = flexmbd_test_support::allocations() - before;
        assert_eq!(count, 0, "{}: {count} allocations in 50 steps", scene.name);
    }
}
