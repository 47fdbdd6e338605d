//! Scenes with imported FE bodies (issue 25 item 5): models/imported_bar_pendulum.ron, a
//! bar of hex8 bricks from a CalculiX export on a ball joint, runs in both formulations
//! and by both inertia routes; its energy at t = 0 is the rigid bar's analytic value, the
//! two formulations converge to one motion at O(h²), and the two routes agree to round-off.
//! Sensor columns: tip_x, tip_y, tip_z, tip_w, y0, energy.

mod common;
use common::*;
use flexmbd_body::InertiaMethod;
use flexmbd_core::Formulation;

const ENERGY: usize = 5;

/// 1/2 m |ω × r_c|² + 1/2 ωᵀ I_c ω + m g z_c for the undeformed steel bar 0.2 × 0.02 × 0.02 m
/// (m = 0.628 kg) spinning at ω = (2, 0, 1.5) rad/s about its root face's centre, its centre
/// of mass r_c = (0.1, 0, 0) from there and z_c = 0.01 m (the scene's comments).
fn analytic_energy() -> f64 {
    let m = 7850.0 * 0.2 * 0.02 * 0.02;
    let (l, b) = (0.2_f64, 0.02_f64);
    let kinetic = 0.5 * m * 0.15_f64.powi(2)
        + 0.5 * (4.0 * m * 2.0 * b * b / 12.0 + 2.25 * m * (l * l + b * b) / 12.0);
    kinetic + m * 9.81 * 0.01
}

#[test]
fn imported_pendulum_runs_in_both_formulations_and_agrees() {
    let s = model("imported_bar_pendulum.ron");
    let (a, r) = (absolute(&s), relative(&s));
    // 4 normal + 6 static modes; absolute: 12 frame coordinates; relative: 3 joint angles.
    assert_eq!((a.n_coordinates(), r.n_coordinates()), (22, 13));
    let d: Vec<f64> = [4e-4f64, 2e-4, 1e-4]
        .iter()
        .map(|&h| {
            let every = (0.01 / h).round() as usize;
            let (x, _) = run_absolute(&s, h, 0.2, every);
            let (y, _) = run_relative(&s, h, 0.2, every);
            for rows in [&x, &y] {
                let e0 = rows[0][ENERGY];
                assert!((e0 / analytic_energy() - 1.0).abs() < 1e-9, "E(0) = {e0}");
            }
            x.iter()
                .zip(&y)
                .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f64::max))
                .fold(0.0, f64::max)
        })
        .collect();
    eprintln!(
        "imported bar pendulum, 0.2 s: max |tip_rel − tip_abs| at h = 0.4, 0.2, 0.1 ms: {:.2e} {:.2e} {:.2e} m",
        d[0], d[1], d[2]
    );
    assert!(d[0] / d[1] > 3.0 && d[1] / d[2] > 3.0, "{d:?}");
    assert!(d[2] < 1e-5, "{d:?}");
}

#[test]
fn imported_pendulum_keeps_its_energy_and_the_routes_agree() {
    let mut s = model("imported_bar_pendulum.ron");
    let (shape, _) = run_absolute(&s, 2e-4, 1.0, 50);
    let e0 = shape[0][ENERGY];
    let drift = shape
        .iter()
        .map(|row| (row[ENERGY] - e0).abs() / e0)
        .fold(0.0, f64::max);
    eprintln!("imported bar pendulum, absolute, h = 0.2 ms, 1 s: energy within {drift:.1e}");
    assert!(drift < 5e-5, "{drift:e}");
    s.solver.inertia = InertiaMethod::BMatrix;
    let (bmatrix, _) = run_absolute(&s, 2e-4, 1.0, 50);
    let worst = shape
        .iter()
        .zip(&bmatrix)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    eprintln!("B-matrix against shape integrals: {worst:.1e} m");
    assert!(worst < 1e-10, "{worst:e}");
}

/// The stiffening methods need element data an imported model does not have: refused by name.
#[test]
fn stiffening_methods_are_refused_for_an_imported_body() {
    let mut s = model("imported_bar_pendulum.ron");
    for method in [
        flexmbd_model::Stiffening::Fnl1,
        flexmbd_model::Stiffening::Fnl2,
        flexmbd_model::Stiffening::Foreshortening,
        flexmbd_model::Stiffening::Substructuring(4),
    ] {
        s.solver.stiffening = method;
        let err = flexmbd_model::PreparedScene::new(&s)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("`bar` is an imported FE model"),
            "{method:?}: {err}"
        );
    }
}

const BOTH: [flexmbd_model::FormulationKind; 2] = [
    flexmbd_model::FormulationKind::Absolute,
    flexmbd_model::FormulationKind::Relative,
];

/// The sensor history of `s` run to its end in formulation `f`.
fn history_in(
    s: &mut flexmbd_model::Scene,
    f: flexmbd_model::FormulationKind,
) -> flexmbd::output::History {
    s.solver.formulation = f;
    let (summary, history) = flexmbd::simulation::run(s, |_| {}).unwrap();
    assert_eq!(summary.status, "ok", "{f:?}");
    history
}

/// The imported bar pendulum with a marker `corner` at the tip face's FE corner node
/// (0.2, 0, 0) and no sensors.
fn pendulum_with_corner_marker() -> flexmbd_model::Scene {
    let mut s = model("imported_bar_pendulum.ron");
    s.bodies[0].markers.push(flexmbd_model::Marker {
        name: "corner".into(),
        position: flexmbd_model::V3([0.2, 0.0, 0.0]),
    });
    s.sensors.clear();
    s
}

/// A mesh node of an imported body is read through a marker on it (issue 25 item 6): the
/// `Position` sensor in the body's frame with `displacement: true` is the node's elastic
/// displacement X^t_P y (X^t_P its node rows, y the modal coordinates read by `Modal`
/// sensors), in both formulations; here at a corner of the bar's tip face, an FE node the
/// tip's RBE3 average does not hold rigid. The sensor is a difference of positions of the
/// bar's size (0.2 m) in a frame that the absolute formulation keeps orthonormal only to its
/// Newton tolerance ε (1e-9): it holds to ε · 0.2 m = 2e-10 m (1.0e-11 m measured; the
/// relative formulation's exact frame, 6e-17 m), while the node moves by up to 1.6e-7 m.
#[test]
fn a_mesh_node_reads_its_elastic_displacement() {
    use flexmbd_model::{Axis, Sensor, SensorKind};
    let mut s = pendulum_with_corner_marker();
    for (axis, name) in [(Axis::X, "u_x"), (Axis::Y, "u_y"), (Axis::Z, "u_z")] {
        s.sensors.push(Sensor {
            name: name.into(),
            kind: SensorKind::Position {
                body: "bar".into(),
                marker: "corner".into(),
                component: axis,
                frame: Some("bar".into()),
            },
            displacement: true,
        });
    }
    let n_modes = 10;
    for k in 0..n_modes {
        s.sensors.push(Sensor {
            name: format!("y{k}"),
            kind: SensorKind::Modal {
                body: "bar".into(),
                index: k,
            },
            displacement: false,
        });
    }
    s.solver.duration = 0.05;
    let prepared = flexmbd_model::PreparedScene::new(&s).unwrap();
    let rows = &prepared.bodies()[0].nodes;
    let node = rows
        .node_at(&nalgebra::Vector3::new(0.2, 0.0, 0.0), 1e-12)
        .unwrap();
    assert!(
        node >= 2,
        "the corner is an FE node, after the two interface points"
    );
    for f in BOTH {
        let history = history_in(&mut s, f);
        let (mut largest, mut worst): (f64, f64) = (0.0, 0.0);
        for row in &history.rows {
            let y = &row[4..4 + n_modes];
            for a in 0..3 {
                let expected: f64 = rows
                    .translation_row(node, a)
                    .iter()
                    .zip(y)
                    .map(|(x, y)| x * y)
                    .sum();
                largest = largest.max(expected.abs());
                worst = worst.max((row[1 + a] - expected).abs());
                assert!(
                    (row[1 + a] - expected).abs() <= s.solver.newton_tolerance * 0.2,
                    "{f:?} t = {}: u_{a} = {} against X y = {expected}",
                    row[0],
                    row[1 + a]
                );
            }
        }
        eprintln!(
            "{f:?}: node displacement up to {largest:.2e} m, against X y within {worst:.1e} m"
        );
        assert!(
            largest > 1e-8,
            "{f:?}: the node hardly moves ({largest:e} m)"
        );
    }
}

/// The velocity of a mesh node (issue 25 item 6), ground and body components, in both
/// formulations, at the corner node of `a_mesh_node_reads_its_elastic_displacement`:
/// - at t = 0 the bar is undeformed and its frame is the ground's, so both readings are the
///   scene's rigid start v₀ + ω × r = (0.015, 0.02, −0.02) + (2, 0, 1.5) × (0.2, 0, 0)
///   = (0.015, 0.32, −0.02) m/s;
/// - body components are the same vector in the body's axes, Aᵀṙ: the same length;
/// - the reading is the derivative of the position reading: over each step the chord
///   (r_{n+1} − r_n)/h equals the mean (ṙ_n + ṙ_{n+1})/2 to the trapezoidal rule's
///   O(h²) (the integrator's own relation between q and q̇, mapped through the marker's
///   smooth kinematics): the rigid swing's share, h² ω³ r / 12 ≈ (2e-4)² · 2.5³ · 0.2 / 12
///   ≈ 1e-8 m/s, is below the elastic vibration's (1.1e-6 m/s measured in both
///   formulations); 1e-5 m/s holds it with margin while a velocity off by a part in 10⁴ of
///   the node's 0.3 m/s fails.
///
/// The absolute formulation's A is orthonormal to its Newton tolerance ε = 1e-9: the lengths
/// agree to ε · 0.3 m/s (6e-11 m/s measured; relative 4e-16).
#[test]
fn a_mesh_node_reads_its_velocity_in_ground_and_body_components() {
    use flexmbd_model::{Axis, Sensor, SensorKind};
    let mut s = pendulum_with_corner_marker();
    let axes = [Axis::X, Axis::Y, Axis::Z];
    for (kind, frame) in [("r", None), ("v", None), ("v_body", Some("bar"))] {
        for (a, axis) in axes.iter().enumerate() {
            let (body, marker) = ("bar".to_string(), "corner".to_string());
            let frame: Option<String> = frame.map(Into::into);
            s.sensors.push(Sensor {
                name: format!("{kind}{a}"),
                kind: if kind == "r" {
                    SensorKind::Position {
                        body,
                        marker,
                        component: *axis,
                        frame,
                    }
                } else {
                    SensorKind::Velocity {
                        body,
                        marker,
                        component: *axis,
                        frame,
                    }
                },
                displacement: false,
            });
        }
    }
    let h = s.solver.step;
    s.solver.duration = 0.1;
    s.solver.output_interval = Some(h);
    let start = [0.015, 0.32, -0.02];
    for f in BOTH {
        let history = history_in(&mut s, f);
        let rows = &history.rows;
        let (r, v, w) = (1, 4, 7);
        for a in 0..3 {
            assert!(
                (rows[0][v + a] - start[a]).abs() < 1e-12,
                "{f:?}: {:?}",
                rows[0]
            );
            assert!(
                (rows[0][w + a] - start[a]).abs() < 1e-12,
                "{f:?}: {:?}",
                rows[0]
            );
        }
        let norm = |row: &[f64], c: usize| (0..3).map(|a| row[c + a].powi(2)).sum::<f64>().sqrt();
        let (mut length_gap, mut chord_gap, mut turned): (f64, f64, f64) = (0.0, 0.0, 0.0);
        for pair in rows.windows(2) {
            let (p, q) = (&pair[0], &pair[1]);
            length_gap = length_gap.max((norm(q, v) - norm(q, w)).abs());
            turned = turned.max((q[v] - q[w]).abs());
            for a in 0..3 {
                let chord = (q[r + a] - p[r + a]) / h;
                chord_gap = chord_gap.max((chord - 0.5 * (p[v + a] + q[v + a])).abs());
            }
        }
        eprintln!(
            "{f:?}: |v| − |v_body| within {length_gap:.1e} m/s (components differ by up to \
             {turned:.2} m/s); chord against mean velocity within {chord_gap:.1e} m/s"
        );
        assert!(length_gap < 3e-10, "{f:?}: {length_gap:e}");
        assert!(
            turned > 0.05,
            "{f:?}: the body's axes hardly turned ({turned:e})"
        );
        assert!(chord_gap < 1e-5, "{f:?}: {chord_gap:e}");
    }
}

/// The bar pendulum's tip (x, y, z) over 0.2 s with its bar's normal modes chosen by
/// `selection` (`normal_modes` of them, among `candidates` for proper orthogonal modes),
/// in formulation `f`.
fn tip_history(
    selection: flexmbd_fe::ModeSelection,
    normal_modes: usize,
    candidates: Option<usize>,
    f: flexmbd_model::FormulationKind,
) -> Vec<[f64; 3]> {
    let mut s = model("imported_bar_pendulum.ron");
    let flexmbd_model::BodyModel::Imported(spec) = &mut s.bodies[0].model else {
        panic!("the bar is imported");
    };
    spec.mode_selection = selection;
    spec.normal_modes = normal_modes;
    spec.mode_candidates = candidates;
    s.solver.duration = 0.2;
    history_in(&mut s, f)
        .rows
        .iter()
        .map(|r| [r[1], r[2], r[3]])
        .collect()
}

fn largest_difference(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()))
        .fold(0.0, f64::max)
}

/// Proper orthogonal modes of an imported body (issue 25 item 2): the pilot run keeps the
/// bar's lowest K normal modes and records their coordinates, and the body takes the n
/// leading directions of that record (Kerschen et al. 2005), in both formulations.
/// With n = K the span is the lowest K modes' and the motion is theirs (Rayleigh–Ritz in
/// the same span), to Newton's tolerance on the bar's size, 1e-9 · 0.2 m (3e-13 m measured);
/// with n < K the run takes the two directions the pilot's motion used most (which here
/// change the tip by some 1e-8 m either way: the tip follows the six static modes).
#[test]
fn imported_proper_orthogonal_modes_come_from_the_pilot() {
    use flexmbd_fe::ModeSelection::{LowestFrequency, ProperOrthogonal};
    for f in BOTH {
        let lowest4 = tip_history(LowestFrequency, 4, None, f);
        let pod4 = tip_history(ProperOrthogonal, 4, Some(4), f);
        let same = largest_difference(&pod4, &lowest4);
        let lowest2 = tip_history(LowestFrequency, 2, None, f);
        let pod2 = tip_history(ProperOrthogonal, 2, Some(4), f);
        let (e_lowest, e_pod) = (
            largest_difference(&lowest2, &lowest4),
            largest_difference(&pod2, &lowest4),
        );
        eprintln!(
            "{f:?}: POD 4 of 4 against the lowest 4: {same:.2e} m; against the lowest 4, \
             2 lowest modes {e_lowest:.2e} m, 2 proper orthogonal modes {e_pod:.2e} m"
        );
        assert!(same < 2e-10, "{f:?}: {same:e}");
    }
}
