//! A beam frame as a flexible body in a scene (`flexmbd_fe::frame`): the A-arm of
//! docs/scenes.md §2.8 (a V of two tube legs with a strut bracket from an interior node, in its
//! own axes, rounded to 0.1 mm) hung from the ground by spherical joints at its two pivots P±
//! and swinging about the pivot axis under gravity. The frame is clamped at P+, the
//! translations of P− and of the ball-joint node B are static modes, 2 fixed-interface modes.
//! Both formulations integrate the same equations: their histories of B and S1 converge to
//! each other as O(h²), and the undamped system keeps its energy.
//!
//! Measured (0.5 s, h = 1e-3, 5e-4, 2.5e-4): relative vs absolute 2.2e-5, 5.7e-6, 1.5e-6 of
//! B's range; energy drift (of m g × B's drop) 1.4e-5, 3.0e-6, 8.7e-7 absolute, 6.5e-6,
//! 1.3e-6, 1.5e-7 relative.

mod common;
use common::*;

const A_ARM_PENDULUM: &str = r#"(
    name: "a-arm pendulum",
    dim: Spatial,
    gravity: [0.0, 0.0, -9.81],
    ground: [(name: "Gf", position: [0.108, 0.3214, 0.0]), (name: "Gr", position: [-0.108, 0.3214, 0.0])],
    bodies: [
        (name: "arm", flexible: true, model: Beam((
            dim: Spatial,
            material: (young_modulus: 2.1e11, density: 7850.0, poisson_ratio: Some(0.3)),
            section: General(area: 1.0487e-3, iy: 2.402e-7, iz: 2.402e-7, torsion_j: 4.804e-7),
            geometry: (
                elements_per_segment: 1,
                nodes: [(name: "B", position: [0.0, 0.0, 0.0]), (name: "P+", position: [0.108, 0.3214, 0.0]),
                        (name: "P-", position: [-0.108, 0.3214, 0.0]), (name: "N_S", position: [0.024478, 0.072845, 0.0]),
                        (name: "S1", position: [0.075, 0.072845, -0.0047])],
                members: [(from: "B", to: "N_S"), (from: "N_S", to: "P+", elements: Some(3)),
                          (from: "B", to: "P-", elements: Some(4)), (from: "N_S", to: "S1")],
            ),
            frame: Clamped(node: 1),
            boundary: [(node: 2, dof: Ux), (node: 2, dof: Uy), (node: 2, dof: Uz),
                       (node: 0, dof: Ux), (node: 0, dof: Uy), (node: 0, dof: Uz)],
            normal_modes: 2,
         )),
         markers: [(name: "Pf", position: [0.108, 0.3214, 0.0]), (name: "Pr", position: [-0.108, 0.3214, 0.0]),
                   (name: "B", position: [0.0, 0.0, 0.0]), (name: "S1", position: [0.075, 0.072845, -0.0047])]),
    ],
    joints: [
        (name: "front", kind: Spherical, body1: "ground", marker1: "Gf", body2: "arm", marker2: "Pf"),
        (name: "rear", kind: Spherical, body1: "ground", marker1: "Gr", body2: "arm", marker2: "Pr"),
    ],
    sensors: [
        (name: "B_z", kind: Position(body: "arm", marker: "B", component: Z)),
        (name: "S1_z", kind: Position(body: "arm", marker: "S1", component: Z)),
        (name: "energy", kind: Energy),
    ],
    solver: (step: 1e-3, duration: 0.5, output_interval: Some(0.01)),
)
"#;

#[test]
fn a_flexible_a_arm_frame_swings_alike_in_both_formulations() {
    let s = flexmbd_model::Scene::from_ron_str(A_ARM_PENDULUM, "a_arm_pendulum.ron").unwrap();
    s.validate().unwrap();
    let (b_z, energy) = (sensor_column(&s, "B_z"), sensor_column(&s, "energy"));
    let (mut d, mut drifts) = (Vec::new(), Vec::new());
    for h in [1e-3_f64, 5e-4, 2.5e-4] {
        let every = (0.01 / h).round() as usize;
        let (a, phi_a) = run_absolute(&s, h, 0.5, every);
        let (r, phi_r) = run_relative(&s, h, 0.5, every);
        let column = |x: &[Vec<f64>], c: usize| x.iter().map(|row| row[c]).collect::<Vec<_>>();
        let range = |v: &[f64]| {
            v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
        };
        let (za, zr) = (column(&a, b_z), column(&r, b_z));
        // The arm swings: B falls by more than 20 cm in 0.5 s (the test would be empty otherwise).
        assert!(range(&za) > 0.2, "B moves {} m", range(&za));
        let diff = za
            .iter()
            .zip(&zr)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
            / range(&za);
        d.push(diff);
        // Energy: constant up to the trapezoidal rule's O(h²) error; scale m g × B's drop.
        let scale = 6.0 * 9.81 * range(&za);
        let drift = |x: &[Vec<f64>]| {
            x.iter()
                .map(|row| (row[energy] - x[0][energy]).abs())
                .fold(0.0, f64::max)
                / scale
        };
        let (ea, er) = (drift(&a), drift(&r));
        eprintln!(
            "h = {h:e}: relative vs absolute {diff:.2e} of B's range; energy drift {ea:.1e} {er:.1e}; |Φ| {phi_a:.1e} {phi_r:.1e}"
        );
        drifts.push(ea.max(er));
        assert!(phi_a < 1e-9 && phi_r < 1e-9, "{phi_a:e} {phi_r:e}");
    }
    assert!(d[2] < 1e-5, "{d:?}");
    assert!(drifts[2] < 2e-6, "{drifts:?}");
    assert!(
        drifts[0] / drifts[1] > 3.0 && drifts[1] / drifts[2] > 3.0,
        "not O(h²): {drifts:?}"
    );
    assert!(d[0] / d[1] > 3.0 && d[1] / d[2] > 3.0, "not O(h²): {d:?}");
}
