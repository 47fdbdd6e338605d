//! The joints' reactions of `flexmbd::equilibrium` (module `equilibrium::reactions`) against
//! closed-form answers, in both formulations: a hanging pendulum's pin carries the weight
//! and no moment (planar and spatial), a bar held on a pin by an inclined spring (statically
//! determinate), and a hinge on two coaxial bearings (redundant: the axial split is not
//! unique, the minimum-norm one is reported and flagged).

use flexmbd::equilibrium;
use flexmbd::model::{FormulationKind, Scene};

const FORMULATIONS: [FormulationKind; 2] = [FormulationKind::Absolute, FormulationKind::Relative];
const G: f64 = 9.81;

fn scene(text: &str, formulation: FormulationKind) -> Scene {
    let mut s = Scene::from_ron_str(text, "test scene").unwrap();
    s.solver.formulation = formulation;
    s.validate().unwrap();
    s
}

fn assert_close(what: &str, value: [f64; 3], expected: [f64; 3], tolerance: f64) {
    for a in 0..3 {
        assert!(
            (value[a] - expected[a]).abs() <= tolerance,
            "{what}: {value:?}, expected {expected:?} (±{tolerance})"
        );
    }
}

use flexmbd_test_support::scenes::HANGING_PENDULUM as PENDULUM;

/// The same bar in space, hinged about ground z and hanging along −y.
const PENDULUM_3D: &str = r#"(
    name: "pendulum 3d", dim: Spatial, gravity: [0.0, -9.81, 0.0],
    ground: [(name: "O", position: [0.0, 0.0, 0.0])],
    bodies: [(name: "bar", origin: [0.0, 0.0, 0.0],
        model: Rigid(mass: 2.0, center_of_mass: [0.0, -0.6, 0.1], inertia: Diagonal([0.24, 0.01, 0.24])),
        markers: [(name: "O", position: [0.0, 0.0, 0.0])])],
    joints: [(name: "pin", kind: Revolute(axis: Some([0.0, 0.0, 1.0])), body1: "ground", marker1: "O", body2: "bar", marker2: "O")],
    solver: (step: 1e-3, duration: 1.0),
)"#;

#[test]
fn hanging_pendulum_pin_carries_the_weight_up_and_no_moment() {
    let m = 2.0;
    for form in FORMULATIONS {
        let e = equilibrium(&scene(PENDULUM, form)).unwrap();
        eprintln!("{form:?}:\n{}", e.to_text());
        let r = e.reactions.as_ref().expect("reactions computed");
        assert_eq!((r.equations, r.unknowns, r.rank), (3, 2, 2), "{form:?}");
        assert!(!r.redundant);
        assert_eq!(r.joints.len(), 1);
        let pin = &r.joints[0];
        assert_eq!(
            (pin.name.as_str(), pin.kind, pin.body.as_str()),
            ("pin", "Revolute", "bar")
        );
        assert_close("planar pin force", pin.force, [0.0, m * G, 0.0], 1e-9);
        assert_close("planar pin moment", pin.moment, [0.0; 3], 1e-12);
    }
}

#[test]
fn spatial_pendulum_pin_carries_the_weight_and_the_off_plane_moment() {
    // The centre of mass sits 0.1 m along the hinge axis from the pin: the weight's moment
    // about the pin is r_G × W = (0, −0.6, 0.1) × (0, −m g, 0) = (0.1 m g, 0, 0), which the
    // pin balances with (−0.1 m g, 0, 0) on the bar, and nothing about the axis z.
    let m = 2.0;
    for form in FORMULATIONS {
        let e = equilibrium(&scene(PENDULUM_3D, form)).unwrap();
        eprintln!("{form:?}:\n{}", e.to_text());
        let r = e.reactions.as_ref().unwrap();
        assert_eq!((r.equations, r.unknowns, r.rank), (6, 5, 5), "{form:?}");
        let pin = &r.joints[0];
        assert_close("spatial pin force", pin.force, [0.0, m * G, 0.0], 1e-9);
        assert_close(
            "spatial pin moment",
            pin.moment,
            [-0.1 * m * G, 0.0, 0.0],
            1e-9,
        );
    }
}

/// A planar bar (mass m, centre of mass at c from the pin) pinned at x = 0 and held level by
/// a spring from its tip (L, 0) to the ground point (L − a, h), its free length chosen so
/// that the bar is level at rest: tension T = m g c ℓ / (L h), ℓ = √(a² + h²). It starts
/// tilted by `start` (rad).
fn bar_on_a_spring(m: f64, c: f64, l: f64, a: f64, h: f64, k: f64, start: f64) -> String {
    let ell = (a * a + h * h).sqrt();
    let tension = m * G * c * ell / (l * h);
    let free = ell - tension / k;
    format!(
        r#"(
    name: "bar on a spring", dim: Planar, gravity: [0.0, -9.81],
    ground: [(name: "O", position: [0.0, 0.0]), (name: "A", position: [{ax}, {h}])],
    bodies: [(name: "bar", orientation: Angle({start}), model: Rigid(mass: {m}, center_of_mass: [{c}, 0.0], inertia: Planar(0.3)),
        markers: [(name: "O", position: [0.0, 0.0]), (name: "tip", position: [{l}, 0.0])])],
    joints: [(name: "pin", kind: Revolute(), body1: "ground", marker1: "O", body2: "bar", marker2: "O")],
    forces: [SpringDamper(name: "spring", body1: "ground", marker1: "A", body2: "bar", marker2: "tip",
        stiffness: {k}, damping: 0.0, free_length: Some({free}))],
    solver: (step: 1e-3, duration: 1.0),
)"#,
        ax = l - a
    )
}

#[test]
fn bar_held_level_by_an_inclined_spring_loads_its_pin_as_the_statics_by_hand() {
    let (m, c, l, a, h, k) = (3.0, 0.4, 1.2, 0.3, 0.8, 5000.0);
    // The pin on the bar: F = (m g c a / (L h), m g (1 − c/L)), no moment.
    let expected = [m * G * c * a / (l * h), m * G * (1.0 - c / l), 0.0];
    // Tilted, so that the static solve is not handed its answer; and level, at its answer
    // (the relative formulation's net torque is then round-off: the static solve used to run
    // out of iterations there, its residual scale being that round-off).
    for (form, start) in FORMULATIONS.into_iter().flat_map(|f| [(f, 0.05), (f, 0.0)]) {
        let e = equilibrium(&scene(&bar_on_a_spring(m, c, l, a, h, k, start), form))
            .unwrap_or_else(|e| panic!("{form:?} from {start} rad: {e}"));
        eprintln!("{form:?}:\n{}", e.to_text());
        let ell = (a * a + h * h).sqrt();
        assert!((e.forces[0].force - m * G * c * ell / (l * h)).abs() < 1e-8);
        let pin = &e.reactions.as_ref().unwrap().joints[0];
        assert_close("pin force", pin.force, expected, 1e-8);
        assert_close("pin moment", pin.moment, [0.0; 3], 1e-12);
    }
}

/// A door of 20 kg on two coaxial hinges (ground z axis) 1 m apart, its centre of mass 0.5 m
/// out along x, halfway up: the hinges' axial forces are not determined by statics.
const DOOR: &str = r#"(
    name: "door", dim: Spatial, gravity: [0.0, 0.0, -9.81],
    ground: [(name: "H1", position: [0.0, 0.0, 0.0]), (name: "H2", position: [0.0, 0.0, 1.0])],
    bodies: [(name: "door", model: Rigid(mass: 20.0, center_of_mass: [0.5, 0.0, 0.5], inertia: Diagonal([2.0, 2.0, 2.0])),
        markers: [(name: "H1", position: [0.0, 0.0, 0.0]), (name: "H2", position: [0.0, 0.0, 1.0])])],
    joints: [
        (name: "lower", kind: Revolute(axis: Some([0.0, 0.0, 1.0])), body1: "ground", marker1: "H1", body2: "door", marker2: "H1"),
        (name: "upper", kind: Revolute(axis: Some([0.0, 0.0, 1.0])), body1: "ground", marker1: "H2", body2: "door", marker2: "H2"),
    ],
    solver: (step: 1e-3, duration: 1.0),
)"#;

#[test]
fn door_on_two_coaxial_hinges_is_flagged_redundant_and_gets_the_minimum_norm_split() {
    let weight = 20.0 * G;
    for form in FORMULATIONS {
        let e = equilibrium(&scene(DOOR, form)).unwrap();
        eprintln!("{form:?}:\n{}", e.to_text());
        let r = e.reactions.as_ref().unwrap();
        assert!(r.redundant && r.rank < r.unknowns, "{form:?}: {r:?}");
        assert!(
            e.to_text().contains("redundant constraints"),
            "the text says so"
        );
        assert!(r.residual_force < 1e-9 && r.residual_moment < 1e-9, "{r:?}");
        let (lower, upper) = (&r.joints[0], &r.joints[1]);
        // Together they carry the weight; the minimum-norm set splits the vertical load and
        // the moments evenly, and holds the door's lean by a horizontal couple.
        assert!((lower.force[2] + upper.force[2] - weight).abs() < 1e-9);
        assert!((lower.force[2] - upper.force[2]).abs() < 1e-9);
        // Moment balance about H1 along y: the weight's moment (r_G × W)_y = 0.5 · weight,
        // the upper hinge's force at z = 1, (r_H2 × F)_y = F_x, and the hinges' own moments.
        let moment_y = lower.moment[1] + upper.moment[1] + upper.force[0] + 0.5 * weight;
        assert!(moment_y.abs() < 1e-9, "{form:?}: {moment_y}");
        // Nothing about the axis, no sideways force.
        assert!(lower.moment[2].abs() < 1e-12 && upper.moment[2].abs() < 1e-12);
        assert!(lower.force[1].abs() < 1e-9 && upper.force[1].abs() < 1e-9);
    }
}

#[test]
fn fnl2_equilibrium_of_the_spin_up_beam_skips_the_reactions_instead_of_failing() {
    // FNL2's rewrite adds axial static modes that no sensor of the scene can name: the
    // reactions' modal probes once made the whole command fail ("has 6 modal coordinates").
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/spin_up_beam_2d.ron");
    let mut s = Scene::load(path).unwrap();
    s.solver.stiffening = flexmbd::model::Stiffening::Fnl2;
    let e = equilibrium(&s).unwrap();
    assert!(e.reactions.is_none() && e.reactions_skipped);
    assert!(e.to_text().contains("joint reactions: not computed"));
    // The linear beam gets them: the hub holds the beam level against gravity.
    s.solver.stiffening = flexmbd::model::Stiffening::Linear;
    let e = equilibrium(&s).unwrap();
    assert!(!e.reactions_skipped);
    assert_eq!(e.reactions.unwrap().joints.len(), s.joints.len());
}
