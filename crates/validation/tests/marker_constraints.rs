//! The scene's `Distance` and `PointInPlane` constraints (docs/methods.md §3.4) in the planar
//! and spatial absolute and the relative formulation, physics against physics:
//! - a point mass on a distance constraint from a ground marker is a pendulum: its period is
//!   the closed form 2π√(L/g)(1 + θ₀²/16 + 11θ₀⁴/3072), its energy is conserved, and the four
//!   formulations (2D and 3D, absolute and relative) agree with each other at a small step;
//! - a compound pendulum on a massless rod (a distance constraint): its static equilibrium
//!   carries the weight in the constraint (λ = m g / L for ½(|d|² − L²)) and its linearised
//!   vibration has the closed-form frequencies of the two-angle pendulum; a hanging four-bar
//!   whose coupler is a distance constraint vibrates at one frequency in 2D and 3D, in both
//!   formulations;
//! - a point mass held in a tilted plane (the plane fixed in a turned body) slides at
//!   g sin α down the slope, exactly;
//! - a four-bar whose coupler is a distance constraint (a massless link) moves as the four-bar
//!   with a coupler body of vanishing mass, the difference falling with that mass, in 2D and
//!   in 3D;
//! - on a flexible beam's tip node, both constraints give the same tip path in both
//!   formulations, the difference falling with the step.

mod common;
use common::*;
use flexmbd_core::Dim;
use flexmbd_model::Scene;
use std::f64::consts::PI;

const G: f64 = 9.81;

fn parse(text: &str) -> Scene {
    let s = Scene::from_ron_str(text, "test scene").unwrap();
    s.validate().unwrap();
    s
}

/// A vector literal of the scene's dimension.
fn v(dim: Dim, x: f64, y: f64) -> String {
    match dim {
        Dim::Planar => format!("[{x:?}, {y:?}]"),
        Dim::Spatial => format!("[{x:?}, {y:?}, 0.0]"),
    }
}

/// A point mass m = 1 kg (its marker at its centre of mass) on a distance constraint of
/// length L from the ground marker O, released at rest at θ₀ from the downward vertical, in
/// the x–y plane under gravity −y.
fn pendulum(dim: Dim, length: f64, theta0: f64) -> Scene {
    let inertia = match dim {
        Dim::Planar => "Planar(0.01)".to_string(),
        Dim::Spatial => "Diagonal([0.01, 0.01, 0.01])".to_string(),
    };
    let (x, y) = (length * theta0.sin(), -length * theta0.cos());
    parse(&format!(
        r#"(
    name: "distance pendulum", dim: {dim:?}, gravity: {g},
    ground: [(name: "O", position: {o})],
    bodies: [(name: "bob", origin: {at},
        model: Rigid(mass: 1.0, center_of_mass: {o}, inertia: {inertia}),
        markers: [(name: "c", position: {o})])],
    constraints: [Distance(name: "rod", body1: "ground", marker1: "O", body2: "bob", marker2: "c", length: Some({length:?}))],
    sensors: [(name: "x", kind: Position(body: "bob", marker: "c", component: X)),
              (name: "y", kind: Position(body: "bob", marker: "c", component: Y)),
              (name: "energy", kind: Energy)],
    solver: (step: 1e-3, duration: 1.0),
)"#,
        g = v(dim, 0.0, -G),
        o = v(dim, 0.0, 0.0),
        at = v(dim, x, y),
    ))
}

/// The runs of `scene` at step h for `secs` in its dimension's absolute formulation and in
/// the relative one: (name, rows every step).
fn both_runs(scene: &Scene, h: f64, secs: f64) -> [(String, Vec<Vec<f64>>); 2] {
    let dim = format!("{:?}", scene.dim);
    [
        (format!("absolute {dim}"), run_absolute(scene, h, secs, 1).0),
        (format!("relative {dim}"), run_relative(scene, h, secs, 1).0),
    ]
}

/// The mean period of column c from its upward zero crossings (linearly interpolated).
fn period(rows: &[Vec<f64>], c: usize, h: f64) -> f64 {
    let crossings: Vec<f64> = rows
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[0][c] < 0.0 && w[1][c] >= 0.0)
        .map(|(k, w)| (k as f64 + w[0][c] / (w[0][c] - w[1][c])) * h)
        .collect();
    assert!(crossings.len() >= 3, "{} crossings", crossings.len());
    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
}

#[test]
fn distance_pendulum_has_the_closed_form_period_and_keeps_its_energy() {
    let (length, theta0, h): (f64, f64, f64) = (0.8, 0.1, 1e-3);
    let t0 = 2.0 * PI * (length / G).sqrt();
    let exact = t0 * (1.0 + theta0 * theta0 / 16.0 + 11.0 * theta0.powi(4) / 3072.0);
    let swing_energy = G * length * (1.0 - theta0.cos());
    for dim in [Dim::Planar, Dim::Spatial] {
        let scene = pendulum(dim, length, theta0);
        for (name, rows) in both_runs(&scene, h, 4.0 * t0) {
            let t = period(&rows, 0, h);
            let drift = drift(&rows, 2);
            eprintln!(
                "{name}: period {t:.9} s, closed form {exact:.9} s ({:.1e}); energy drift {drift:.1e} J",
                (t - exact) / exact
            );
            // The trapezoidal rule lengthens the period by (ωh)²/12 ≈ 1e-6.
            assert!(((t - exact) / exact).abs() < 5e-6, "{name}: {t} vs {exact}");
            assert!(drift < 1e-4 * swing_energy, "{name}: drift {drift} J");
            // The bob stays on the circle.
            for r in &rows {
                let l = (r[0] * r[0] + r[1] * r[1]).sqrt();
                assert!((l - length).abs() < 1e-8, "{name}: |d| = {l}");
            }
        }
    }
}

#[test]
fn distance_pendulum_agrees_in_every_formulation() {
    // A large swing (θ₀ = 1.2 rad): all four runs integrate the same motion; their
    // differences are their O(h²) errors.
    let h = 2.5e-4;
    let mut runs = Vec::new();
    for dim in [Dim::Planar, Dim::Spatial] {
        runs.extend(both_runs(&pendulum(dim, 1.0, 1.2), h, 2.0));
    }
    let (reference_name, reference) = &runs[0];
    for (name, rows) in &runs[1..] {
        let d = worst_difference(reference, rows, &[0, 1]);
        eprintln!("{name} against {reference_name}: {d:.2e} of the range");
        assert!(d < 1e-6, "{name}: {d:e}");
    }
}

/// A compound pendulum on a massless rod, in the plane: a body (m = 1 kg, centre of mass d
/// below its marker c, inertia J about it) whose marker c hangs at the length L below the
/// ground marker O on a `Distance` constraint, under gravity −y.
fn rod_and_bob(length: f64, d: f64, j: f64) -> Scene {
    parse(&format!(
        r#"(
    name: "rod and bob", dim: Planar, gravity: [0.0, -9.81],
    ground: [(name: "O", position: [0.0, 0.0])],
    bodies: [(name: "bob", origin: [0.0, {y:?}],
        model: Rigid(mass: 1.0, center_of_mass: [0.0, {c:?}], inertia: Planar({j:?})),
        markers: [(name: "c", position: [0.0, 0.0])])],
    constraints: [Distance(name: "rod", body1: "ground", marker1: "O", body2: "bob", marker2: "c", length: None)],
    sensors: [(name: "x", kind: Position(body: "bob", marker: "c", component: X)),
              (name: "y", kind: Position(body: "bob", marker: "c", component: Y))],
    solver: (step: 1e-3, duration: 1.0),
)"#,
        y = -length,
        c = -d
    ))
}

#[test]
fn rod_and_bob_equilibrium_carries_the_weight_and_vibrates_at_the_closed_form() {
    let (length, d, j, m) = (0.8, 0.2, 0.01, 1.0);
    // Linearised in the rod's and the bob's angles from the vertical:
    // M = [[m L², m L d], [m L d, m d² + J]], K = diag(m g L, m g d); det(K − ω² M) = 0.
    let a = m * length * length * j;
    let b = -(m * G * length * (m * d * d + j) + m * G * d * m * length * length);
    let c = m * m * G * G * length * d;
    let root = (b * b - 4.0 * a * c).sqrt();
    let exact = [(-b - root) / (2.0 * a), (-b + root) / (2.0 * a)].map(|w2| w2.sqrt() / (2.0 * PI));
    for formulation in [
        flexmbd_model::FormulationKind::Absolute,
        flexmbd_model::FormulationKind::Relative,
    ] {
        let mut scene = rod_and_bob(length, d, j);
        scene.solver.formulation = formulation;
        let e = flexmbd::equilibrium(&scene).unwrap();
        // Hanging straight down; the rod is the last row, and with Φ = ½(|d|² − L²) the bob
        // feels −λ d = (0, λ L): λ = m g / L.
        let (x, y) = (e.sensor("x").unwrap(), e.sensor("y").unwrap());
        assert!(
            x.abs() < 1e-9 && (y + length).abs() < 1e-9,
            "{formulation:?}: ({x}, {y})"
        );
        let lambda = *e.multipliers.last().unwrap();
        assert!(
            (lambda - m * G / length).abs() < 1e-9 * G,
            "{formulation:?}: λ = {lambda}, m g / L = {}",
            m * G / length
        );
        let vib = flexmbd::vibration(&scene).unwrap();
        let found = vib.frequencies("oscillatory");
        eprintln!("{formulation:?}: {found:?} Hz, closed form {exact:?} Hz");
        assert_eq!(found.len(), 2, "{formulation:?}:\n{}", vib.to_text());
        for (f, x) in found.iter().zip(exact) {
            assert!(
                (f - x).abs() < 1e-6 * x,
                "{formulation:?}: {f} Hz, closed form {x} Hz"
            );
        }
    }
}

#[test]
fn hanging_four_bar_with_a_distance_coupler_vibrates_alike_in_2d_and_3d() {
    use flexmbd_model::FormulationKind::{Absolute, Relative};
    let hanging = four_bar_with_coupler(None, (-PI / 2.0, -PI / 2.0));
    // The 3D scene in the relative formulation only: the static solver does not converge on
    // this four-bar written in 3D in natural coordinates, with the coupler a body as well as
    // a distance constraint (‖g‖ stalls near 1e-8).
    let runs = [
        (hanging.clone(), Absolute),
        (hanging.clone(), Relative),
        (planar_scene_in_3d(&hanging), Relative),
    ];
    let mut frequencies = Vec::new();
    for (mut s, formulation) in runs {
        s.solver.formulation = formulation;
        let vib = flexmbd::vibration(&s).unwrap_or_else(|e| panic!("{e}"));
        let found = vib.frequencies("oscillatory");
        let label = format!("{:?} {formulation:?}", s.dim);
        eprintln!("{label}: {found:?} Hz");
        assert_eq!(found.len(), 1, "{label}:\n{}", vib.to_text());
        frequencies.push((label, found[0]));
    }
    let (_, f0) = frequencies[0];
    // Hanging cranks of 1 and 1.5 m, coupled: near their own frequencies as pendulums
    // (0.61 and 0.50 Hz).
    assert!(f0 > 0.3 && f0 < 0.7, "{f0} Hz");
    for (label, f) in &frequencies {
        assert!(
            (f - f0).abs() < 1e-6 * f0,
            "{label}: {f} Hz against {f0} Hz"
        );
    }
}

/// A point mass held by a `PointInPlane` constraint in the plane of a ramp body (turned by α
/// about y, bolted to the ground), the plane's normal given in the ramp's components as its
/// z axis, started in the plane with a velocity along the plane; or (`on_ground`) the same
/// plane carried by the ground, its normal (sin α, 0, cos α) in ground components.
fn sliding_block(alpha: f64, on_ground: bool) -> Scene {
    let plane = if on_ground {
        format!(
            r#"PointInPlane(name: "on_ramp", body1: "ground", marker1: "R", normal: ({:?}, 0.0, {:?}), body2: "block", marker2: "c")"#,
            alpha.sin(),
            alpha.cos()
        )
    } else {
        r#"PointInPlane(name: "on_ramp", body1: "ramp", marker1: "P", normal: (0.0, 0.0, 1.0), body2: "block", marker2: "c")"#.to_string()
    };
    parse(&format!(
        r#"(
    name: "sliding block", dim: Spatial, gravity: [0.0, 0.0, -9.81],
    ground: [(name: "R", position: [0.3, 0.0, 0.2])],
    bodies: [
        (name: "ramp", origin: [0.3, 0.0, 0.2], orientation: AxisAngle(axis: [0.0, 1.0, 0.0], angle: {alpha:?}),
         model: Rigid(mass: 5.0, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([0.2, 0.2, 0.2])),
         markers: [(name: "R", position: [0.0, 0.0, 0.0]), (name: "P", position: [0.1, 0.2, 0.0])]),
        (name: "block", origin: [0.3, 0.2, 0.2],
         model: Rigid(mass: 2.0, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([0.01, 0.02, 0.03])),
         markers: [(name: "c", position: [0.0, 0.0, 0.0])],
         velocity: (linear: [0.0, 0.5, 0.0]))],
    joints: [(name: "bolt", kind: Rigid, body1: "ground", marker1: "R", body2: "ramp", marker2: "R")],
    constraints: [{plane}],
    sensors: [(name: "x", kind: Position(body: "block", marker: "c", component: X)),
              (name: "y", kind: Position(body: "block", marker: "c", component: Y)),
              (name: "z", kind: Position(body: "block", marker: "c", component: Z))],
    solver: (step: 1e-3, duration: 1.0),
)"#
    ))
}

#[test]
fn block_in_a_tilted_plane_slides_at_g_sin_alpha() {
    let (alpha, h) = (0.4_f64, 1e-3);
    // The plane's normal n = (sin α, 0, cos α); gravity's part along the plane is
    // g sin α (cos α, 0, −sin α), and the in-plane start velocity (0, 0.5, 0) is kept.
    let down = Vector::new(alpha.cos(), 0.0, -alpha.sin()) * (G * alpha.sin());
    let start = Vector::new(0.3, 0.2, 0.2);
    let runs = [false, true].map(|on_ground| {
        let [a, r] = both_runs(&sliding_block(alpha, on_ground), h, 1.0);
        let carrier = if on_ground { "ground" } else { "ramp" };
        [a, r].map(|(name, rows)| (format!("{name}, plane of the {carrier}"), rows))
    });
    for (name, rows) in runs.into_iter().flatten() {
        let mut worst = 0.0f64;
        for (k, r) in rows.iter().enumerate() {
            let t = k as f64 * h;
            let exact = start + Vector::new(0.0, 0.5, 0.0) * t + down * (0.5 * t * t);
            worst = worst.max((Vector::new(r[0], r[1], r[2]) - exact).norm());
        }
        let travelled = (down * 0.5).norm();
        eprintln!(
            "{name}: largest distance from ½ g sin α t² {worst:.1e} m (travel {travelled:.3} m)"
        );
        assert!(worst < 1e-8, "{name}: {worst:e} m");
    }
}

type Vector = nalgebra::Vector3<f64>;

/// A crank–rocker four-bar in the plane: crank (1 m, 1 kg) at the ground point A0, rocker
/// (1.5 m, 1.5 kg) at A1, two metres apart, at the angles `(crank, rocker)` from the ground
/// x axis, at rest. The coupler joining the crank's tip B to the rocker's tip C is a bar
/// body of `coupler_mass` (`Some`) with revolutes at both ends, or a `Distance` constraint
/// (`None`, a massless link).
fn four_bar_with_coupler(coupler_mass: Option<f64>, (crank, rocker): (f64, f64)) -> Scene {
    let b = [crank.cos(), crank.sin()];
    let c = [2.0 + 1.5 * rocker.cos(), 1.5 * rocker.sin()];
    let l = (c[0] - b[0]).hypot(c[1] - b[1]);
    let angle = (c[1] - b[1]).atan2(c[0] - b[0]);
    let (coupler, joints, constraints) = match coupler_mass {
        Some(m) => (
            format!(
                r#"(name: "coupler", origin: [{bx:?}, {by:?}], orientation: Angle({angle:?}),
         model: Rigid(mass: {m:?}, center_of_mass: [{h:?}, 0.0], inertia: Planar({i:?})),
         markers: [(name: "B", position: [0.0, 0.0]), (name: "C", position: [{l:?}, 0.0])]),"#,
                bx = b[0],
                by = b[1],
                h = 0.5 * l,
                i = m * l * l / 12.0
            ),
            r#"(name: "B", kind: Revolute(), body1: "crank", marker1: "B", body2: "coupler", marker2: "B"),
        (name: "C", kind: Revolute(), body1: "coupler", marker1: "C", body2: "rocker", marker2: "C"),"#,
            "",
        ),
        None => (
            String::new(),
            "",
            r#"Distance(name: "coupler", body1: "crank", marker1: "B", body2: "rocker", marker2: "C", length: None)"#,
        ),
    };
    parse(&format!(
        r#"(
    name: "four-bar", dim: Planar, gravity: [0.0, -9.81],
    ground: [(name: "A0", position: [0.0, 0.0]), (name: "A1", position: [2.0, 0.0])],
    bodies: [
        (name: "crank", origin: [0.0, 0.0], orientation: Angle({crank:?}),
         model: Rigid(mass: 1.0, center_of_mass: [0.5, 0.0], inertia: Planar(0.0833333333333)),
         markers: [(name: "A", position: [0.0, 0.0]), (name: "B", position: [1.0, 0.0])]),
        {coupler}
        (name: "rocker", origin: [2.0, 0.0], orientation: Angle({rocker:?}),
         model: Rigid(mass: 1.5, center_of_mass: [0.75, 0.0], inertia: Planar(0.28125)),
         markers: [(name: "A", position: [0.0, 0.0]), (name: "C", position: [1.5, 0.0])])],
    joints: [
        (name: "A0", kind: Revolute(), body1: "ground", marker1: "A0", body2: "crank", marker2: "A"),
        (name: "A1", kind: Revolute(), body1: "ground", marker1: "A1", body2: "rocker", marker2: "A"),
        {joints}
    ],
    constraints: [{constraints}],
    sensors: [(name: "Bx", kind: Position(body: "crank", marker: "B", component: X)),
              (name: "By", kind: Position(body: "crank", marker: "B", component: Y)),
              (name: "Cx", kind: Position(body: "rocker", marker: "C", component: X))],
    solver: (step: 1e-3, duration: 2.0),
)"#
    ))
}

/// Released at rest with the crank at 60° and the rocker upright.
const RELEASED: (f64, f64) = (PI / 3.0, PI / 2.0);

#[test]
fn four_bar_with_a_distance_coupler_moves_as_with_a_coupler_of_vanishing_mass() {
    let (h, secs) = (1e-3, 2.0);
    let cols = [0, 1, 2];
    for (label, in_dim) in [
        ("2D", (|s: &Scene| s.clone()) as fn(&Scene) -> Scene),
        ("3D", planar_scene_in_3d),
    ] {
        let massless = in_dim(&four_bar_with_coupler(None, RELEASED));
        let [(a_name, a), (r_name, r)] = both_runs(&massless, h, secs);
        let between = worst_difference(&a, &r, &cols);
        eprintln!("{label}: {a_name} against {r_name}: {between:.1e} of the range");
        assert!(between < 1e-4, "{label}: {between:e}");
        // The coupler body's mass and inertia add O(m) to the motion: the difference to the
        // massless link falls in proportion, in both formulations.
        for (name, massless_rows) in [(a_name, a), (r_name, r)] {
            let d: Vec<f64> = [1e-2, 1e-3]
                .iter()
                .map(|&m| {
                    let body = in_dim(&four_bar_with_coupler(Some(m), RELEASED));
                    let rows = if name.starts_with("absolute") {
                        run_absolute(&body, h, secs, 1).0
                    } else {
                        run_relative(&body, h, secs, 1).0
                    };
                    worst_difference(&massless_rows, &rows, &cols)
                })
                .collect();
            eprintln!("{label} {name}: coupler of 1e-2, 1e-3 kg against the link: {d:?}");
            assert!(
                d[0] / d[1] > 8.0 && d[0] / d[1] < 12.0,
                "{label} {name}: {d:?}"
            );
            assert!(d[1] < 1e-3, "{label} {name}: {d:?}");
        }
    }
}

#[test]
fn constraints_on_a_flexible_node_agree_between_the_formulations() {
    // The flexible 3D pendulum (undamped beam) with a distance and a point-in-plane
    // constraint on its tip node: the tip's path in the two formulations, the difference
    // falling with the step. The steps are small: at h = 1 ms the natural-coordinate run of
    // this scene loses energy stability and fails, as it does when the distance is a light
    // link body on two spherical joints instead (the loaded tip node excites the beam's
    // stiff undamped modes); the relative one runs.
    let scene = flexmbd_test_support::scenes::flexible_pendulum_3d_with_constraints();
    let tip = [0, 1, 2];
    let d: Vec<f64> = [2.5e-4_f64, 1.25e-4, 6.25e-5]
        .iter()
        .map(|&h| {
            let every = (0.01 / h).round() as usize;
            let (a, _) = run_absolute(&scene, h, 0.5, every);
            let (r, _) = run_relative(&scene, h, 0.5, every);
            worst_difference(&a, &r, &tip)
        })
        .collect();
    eprintln!("flexible pendulum with constraints, tip, relative vs absolute / range: {d:?}");
    assert!(d[0] > 2.0 * d[1] && d[1] > 2.0 * d[2], "{d:?}");
    assert!(d[2] < 1e-5, "{d:?}");
}
