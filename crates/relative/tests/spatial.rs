//! 3D: the recursive terms against dense products and Lagrange's equations, cut-joint
//! and scene-constraint (distance, point in plane) Jacobians and bias by differences, energy conservation (docs/methods.md §4 in 3D, §8 items
//! 6–8); the runs against the spatial natural-coordinate formulation are in
//! `crates/validation/tests/formulations_agree_spatial.rs`.

mod common;
use common::*;
use flexmbd_core::Formulation;
use flexmbd_model::{BodyModel, Constraint, JointKind, Marker, Scene, V3};
use nalgebra::Vector3;

/// Two flexible beams in a chain on ball joints: the first carries static modes at its tip
/// (3 translations, §4.3 node frame), the second hangs there. The stiff axial static mode
/// (~2.5 kHz, undamped) needs a small step for the energy test (docs/methods.md §4.3 note).
fn flexible_chain_3d() -> Scene {
    let mut s = model("flexible_pendulum_3d.ron");
    let mut b2 = s.bodies[0].clone();
    b2.name = "beam2".into();
    b2.origin = V3([1.0, 0.0, 0.0]);
    // The whole chain spins rigidly about the vertical at t = 0.
    b2.velocity.angular = V3([0.0, 0.0, 1.5]);
    b2.velocity.linear = V3([0.0, 1.5, 0.0]);
    if let BodyModel::Beam(spec) = &mut s.bodies[0].model {
        spec.boundary = ["Ux", "Uy", "Uz"]
            .iter()
            .map(|d| flexmbd_model::NodeDof {
                node: 20,
                dof: match *d {
                    "Ux" => flexmbd_model::Dof::Ux,
                    "Uy" => flexmbd_model::Dof::Uy,
                    _ => flexmbd_model::Dof::Uz,
                },
            })
            .collect();
        spec.normal_modes = 4;
    }
    if let BodyModel::Beam(spec) = &mut b2.model {
        spec.normal_modes = 4;
    }
    s.bodies[0].velocity.angular = V3([0.0, 0.0, 1.5]);
    s.bodies.push(b2);
    s.joints.push(flexmbd_model::Joint {
        name: "ball2".into(),
        kind: JointKind::Spherical,
        body1: "beam".into(),
        marker1: "tip".into(),
        body2: "beam2".into(),
        marker2: "root".into(),
    });
    s.sensors
        .retain(|x| x.name == "energy" || x.name.starts_with("tip_"));
    s.validate().unwrap();
    s
}

/// The flexible chain with the scene's constraints as cut rows: the second beam's tip at its
/// distance from a ground point, and a ground point held in the plane through the first
/// beam's tip node (static modes) normal to (0.2, 0.5, 1.0) in the beam's axes, which the
/// node's rotation turns.
fn constrained_chain_3d() -> Scene {
    let mut s = flexible_chain_3d();
    let normal = Vector3::new(0.2, 0.5, 1.0);
    // The first beam is not turned at t = 0: its tip is at (1, 0, 0) in the ground too.
    let q = Vector3::x() + normal.normalize().cross(&Vector3::x()).normalize() * 0.4;
    s.ground.extend([
        Marker {
            name: "far".into(),
            position: V3([1.5, 0.5, 0.3]),
        },
        Marker {
            name: "Q".into(),
            position: V3([q.x, q.y, q.z]),
        },
    ]);
    s.constraints = vec![
        Constraint::Distance {
            name: "rod".into(),
            body1: "ground".into(),
            marker1: "far".into(),
            body2: "beam2".into(),
            marker2: "tip".into(),
            length: None,
        },
        Constraint::PointInPlane {
            name: "plane".into(),
            body1: "beam".into(),
            marker1: "tip".into(),
            normal: V3([normal.x, normal.y, normal.z]),
            body2: "ground".into(),
            marker2: "Q".into(),
        },
    ];
    s.validate().unwrap();
    s
}

fn check_terms(scene: &Scene) {
    at_test_states(scene, 0..3, |f, z, zd, t| {
        let r = dense_r(f, &z);
        let (m, q) = dense_terms(f, &z, &zd, &r);
        let dm = (&t.mass - &m).amax() / m.amax();
        let dq = (&t.forces - &q).amax() / q.amax();
        // Lagrange: Q = −Ṁ ż + ∂T/∂z − ∂V/∂z.
        let rhs = lagrange_forces(f, &z, &zd, 1e-6);
        let dl = (&t.forces - &rhs).amax() / t.forces.amax().max(1.0);
        // Constraints along z + s ż.
        let (mut ev, mut ea) = (0.0, 0.0);
        if f.n_constraints() > 0 {
            (ev, ea) = constraint_rate_errors(f, &z, &zd, &t);
        }
        eprintln!(
            "{}: |M − RᵀM̄R| {dm:.1e}, |Q − Rᵀ(Q̄ − M̄Ṙż)| {dq:.1e}, Lagrange {dl:.1e}, Φ_z ż {ev:.1e}, c {ea:.1e}",
            scene.name
        );
        assert!(dm < 1e-12 && dq < 1e-12, "dm {dm:e} dq {dq:e}");
        assert!(dl < 1e-6, "Lagrange {dl:e}");
        assert!(ev < 1e-7 && ea < 1e-4, "ev {ev:e} ea {ea:e}");
    });
}

#[test]
fn spatial_terms_match_dense_products_lagrange_and_differences() {
    check_terms(&model("double_pendulum_3d.ron"));
    check_terms(&model("flexible_pendulum_3d.ron"));
    check_terms(&flexible_chain_3d());
    let constrained = constrained_chain_3d();
    let rows = |s: &Scene| relative(s).n_constraints();
    assert_eq!(rows(&constrained), rows(&flexible_chain_3d()) + 2);
    check_terms(&constrained);
    check_terms(&planar_scene_in_3d(&four_bar(0)));
}

/// `scene` with every beam's `reference: Buckens`.
fn buckens(mut scene: Scene) -> Scene {
    for b in &mut scene.bodies {
        if let BodyModel::Beam(spec) = &mut b.model {
            spec.reference = flexmbd_model::ReferenceCondition::Buckens;
        }
    }
    scene
}

#[test]
fn buckens_terms_match_dense_products_lagrange_and_differences() {
    // The inverse node chain of a Buckens child's own modes (topology.rs): translations only
    // (ball joints), a Buckens child at a moving node of a Buckens parent, and the three
    // rotations of a revolute's node (the spin-up beam).
    check_terms(&buckens(model("flexible_pendulum_3d.ron")));
    check_terms(&buckens(flexible_chain_3d()));
    // The 3D spin-up beam on its revolute, linear and undriven (the check's Lagrange
    // equations know the linear elastic potential, its constraint rates no Φ_t).
    let mut spin_up = model("spin_up_beam_3d.ron");
    spin_up.solver.stiffening = flexmbd_model::Stiffening::Linear;
    spin_up.drivers.clear();
    check_terms(&spin_up);
    check_terms(&buckens(spin_up));
}

#[test]
fn flexible_pendulum_3d_conserves_energy() {
    for (scene, h) in [
        (model("flexible_pendulum_3d.ron"), 5e-4),
        (flexible_chain_3d(), 1.25e-4),
    ] {
        let f = relative(&scene);
        let ie = scene
            .sensors
            .iter()
            .position(|s| s.name == "energy")
            .unwrap();
        let (rows, _) = run_relative(&scene, h, 10.0, (0.01 / h).round() as usize);
        let e0 = rows[0][ie];
        let drift = rows.iter().map(|r| (r[ie] - e0).abs()).fold(0.0, f64::max);
        // Scale: m g L per beam (0.785 kg, 1 m), the order of the energy exchanged.
        let scale = 0.785 * 9.81 * 1.0 * scene.bodies.len() as f64;
        eprintln!(
            "{} ({} coordinates), h = {h:e}: energy drift over 10 s {drift:.2e} J ({:.2e} relative)",
            scene.name,
            f.n_coordinates(),
            drift / scale
        );
        assert!(drift / scale < 1e-4, "{drift:e}");
    }
}
