//! `flexmbd::equilibrium` and `flexmbd::vibration` (docs/methods.md §5.5) against closed-form
//! answers, in both formulations: a pendulum (its frequency comes only from the
//! constraint-force stiffness), a mass on a spring and damper, a hanging mass on a spring
//! (static deflection mg/k, multipliers carrying the weight), the double four-bar (one
//! degree of freedom, redundant constraints) and a clamped flexible beam against its own
//! Craig–Bampton frequencies.

use flexmbd::model::{FormulationKind, Scene};
use flexmbd::{equilibrium, vibration};
use std::f64::consts::PI;

const FORMULATIONS: [FormulationKind; 2] = [FormulationKind::Absolute, FormulationKind::Relative];

fn scene(text: &str, formulation: FormulationKind) -> Scene {
    let mut s = Scene::from_ron_str(text, "test scene").unwrap();
    s.solver.formulation = formulation;
    s.validate().unwrap();
    s
}

fn relative_error(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A planar rigid bar pinned at one end, hanging straight down: mass m, centre of mass at
/// d below the pin, inertia J_G about it. Its small oscillation ω = √(m g d / (J_G + m d²)).
use flexmbd_test_support::scenes::HANGING_PENDULUM as PENDULUM;

#[test]
fn pendulum_frequency_is_sqrt_mgd_over_j_in_both_formulations() {
    let (m, d, jg, g): (f64, f64, f64, f64) = (2.0, 0.6, 0.24, 9.81);
    let exact = (m * g * d / (jg + m * d * d)).sqrt() / (2.0 * PI);
    for form in FORMULATIONS {
        let v = vibration(&scene(PENDULUM, form)).unwrap();
        eprintln!("{form:?}:\n{}", v.to_text());
        assert_eq!(v.dof, 1, "{form:?}");
        let m0 = &v.modes[0];
        assert_eq!(m0.kind, "oscillatory");
        assert!(
            relative_error(m0.frequency_hz, exact) < 1e-6,
            "{form:?}: {} Hz, exact {exact} Hz",
            m0.frequency_hz
        );
        assert!(
            m0.damping_ratio.abs() < 1e-9,
            "{form:?}: ζ = {}",
            m0.damping_ratio
        );
        // The swing moves the tip sideways, not up (first order).
        assert_eq!(m0.sensors[0].name, "tip_x", "{form:?}: {:?}", m0.sensors);
        let tip_y = m0.sensors.iter().find(|s| s.name == "tip_y");
        assert!(
            tip_y.is_none_or(|s| s.value < 1e-3),
            "{form:?}: {:?}",
            m0.sensors
        );
    }
}

/// A point-like block on a vertical spring and damper, hanging under gravity.
fn spring_mass(k: f64, c: f64, m: f64) -> String {
    format!(
        r#"(
    name: "spring mass", dim: Planar, gravity: [0.0, -9.81],
    ground: [(name: "A", position: [0.0, 0.0]), (name: "G", position: [0.0, -1.0])],
    bodies: [(name: "block", origin: [0.0, -1.0],
        model: Rigid(mass: {m}, center_of_mass: [0.0, 0.0], inertia: Planar(0.01)),
        markers: [(name: "P", position: [0.0, 0.0])])],
    joints: [(name: "slide", kind: Prismatic(axis: [0.0, 1.0, 0.0]), body1: "ground", marker1: "G", body2: "block", marker2: "P")],
    forces: [SpringDamper(name: "spring", body1: "ground", marker1: "A", body2: "block", marker2: "P",
        stiffness: {k}, damping: {c}, free_length: Some(1.0))],
    sensors: [(name: "y", kind: Position(body: "block", marker: "P", component: Y))],
    solver: (step: 1e-3, duration: 1.0),
)"#
    )
}

#[test]
fn hanging_mass_on_a_spring_deflects_by_mg_over_k_and_the_spring_carries_the_weight() {
    let (k, m, g) = (4000.0, 3.0, 9.81);
    for form in FORMULATIONS {
        let e = equilibrium(&scene(&spring_mass(k, 0.0, m), form)).unwrap();
        eprintln!("{form:?}:\n{}", e.to_text());
        let y = e.sensor("y").unwrap();
        assert!(
            relative_error(-1.0 - y, m * g / k) < 1e-9,
            "{form:?}: deflection {} m, mg/k = {} m",
            -1.0 - y,
            m * g / k
        );
        assert!(e.solve.residual < 1e-8 && e.solve.phi < 1e-9, "{form:?}");
        // The spring carries the weight, in tension.
        assert_eq!(e.forces.len(), 1);
        assert_eq!(e.forces[0].name, "spring");
        assert!(
            relative_error(e.forces[0].force, m * g) < 1e-9,
            "{form:?}: {:?}",
            e.forces[0]
        );
        assert!(relative_error(e.forces[0].length, 1.0 + m * g / k) < 1e-12);
    }
}

#[test]
fn mass_on_a_spring_and_damper_has_omega_sqrt_k_over_m_and_zeta_c_over_2_sqrt_km() {
    let (k, c, m): (f64, f64, f64) = (4000.0, 12.0, 3.0);
    let omega = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    for form in FORMULATIONS {
        let v = vibration(&scene(&spring_mass(k, c, m), form)).unwrap();
        eprintln!("{form:?}:\n{}", v.to_text());
        assert_eq!(v.dof, 1);
        let m0 = &v.modes[0];
        assert!(
            relative_error(m0.frequency_hz, omega / (2.0 * PI)) < 1e-8,
            "{form:?}"
        );
        assert!(relative_error(m0.damping_ratio, zeta) < 1e-8, "{form:?}");
        let damped = omega * (1.0 - zeta * zeta).sqrt() / (2.0 * PI);
        assert!(
            relative_error(m0.damped_frequency_hz, damped) < 1e-8,
            "{form:?}"
        );
    }
}

/// The rigid double four-bar (models/double_four_bar.ron, bars rigid) has one degree of
/// freedom despite its redundant constraints. With gravity upwards its cranks, upright,
/// hang: one oscillation, whose frequency both formulations agree on. (With the scene's
/// gravity the upright cranks are an unstable equilibrium: a real pair ±s, tested too.)
#[test]
fn rigid_double_four_bar_has_one_mode_both_formulations_agree() {
    let mut freq = Vec::new();
    for form in FORMULATIONS {
        let mut s = flexmbd_test_support::scenes::four_bar(0);
        s.solver.formulation = form;
        let upright = vibration(&s).unwrap();
        eprintln!("{form:?}:\n{}", upright.to_text());
        let mut kinds: Vec<_> = upright.modes.iter().map(|m| m.kind.as_str()).collect();
        kinds.sort();
        assert_eq!(kinds, ["overdamped", "unstable"], "{form:?}");
        s.gravity = flexmbd::model::V3([0.0, 9.81, 0.0]);
        let v = vibration(&s).unwrap();
        eprintln!("{form:?}, gravity up:\n{}", v.to_text());
        assert_eq!(v.dof, 1, "{form:?}");
        assert_eq!(v.frequencies("oscillatory").len(), 1, "{form:?}");
        // The same |s| as the unstable pair: the linearisation is symmetric in g.
        assert!(relative_error(v.modes[0].frequency_hz, upright.modes[0].frequency_hz) < 1e-6);
        freq.push(v.modes[0].frequency_hz);
    }
    assert!(freq[0] > 0.0);
    assert!(relative_error(freq[0], freq[1]) < 1e-6, "{freq:?}");
}

/// The vibration of `s` in formulation `form` and the frequencies of its oscillatory modes
/// (Hz), which must be `count`.
fn oscillatory_in(
    s: &mut Scene,
    form: FormulationKind,
    count: usize,
) -> (flexmbd::Vibration, Vec<f64>) {
    s.solver.formulation = form;
    let v = vibration(s).unwrap();
    eprintln!("{form:?}:\n{}", v.to_text());
    let f = v.frequencies("oscillatory");
    assert_eq!(f.len(), count, "{form:?}");
    (v, f)
}

/// The flexible pendulum's bar (models/flexible_pendulum.ron: frame clamped at node 0, four
/// Craig–Bampton normal modes) fixed to the ground by a rigid joint at that node, gravity
/// off: its free vibration is the reduced body's own, the frequencies of its normal modes.
#[test]
fn clamped_flexible_bar_vibrates_at_its_craig_bampton_frequencies() {
    let mut s = flexmbd_test_support::scenes::model("flexible_pendulum.ron");
    s.gravity = flexmbd::model::V3([0.0, 0.0, 0.0]);
    s.joints[0].kind = flexmbd::model::JointKind::Rigid;
    s.sensors.retain(|sensor| sensor.name != "angle"); // a rigid joint has no angle
    let flexmbd::model::BodyModel::Beam(spec) = &s.bodies[0].model else {
        panic!("the bar is a beam");
    };
    let body = flexmbd::fe::reduce(spec).unwrap();
    let cb: Vec<f64> = flexmbd::inventory::Inventory::of("bar", &body)
        .normal_modes
        .iter()
        .map(|m| m.frequency_hz)
        .collect();
    assert_eq!(cb.len(), 4);
    for form in FORMULATIONS {
        let (_, f) = oscillatory_in(&mut s, form, 4);
        for (a, b) in f.iter().zip(&cb) {
            assert!(
                relative_error(*a, *b) < 1e-8,
                "{form:?}: {a} Hz, Craig–Bampton {b} Hz"
            );
        }
    }
}

/// The flexible pendulum hanging at rest: its first mode is the swing, close to the rigid
/// bar's √(3g/2L)/2π (the bar is stiff: its first bending mode is at 8.4 Hz in the pinned
/// frame), and both formulations agree on every frequency.
#[test]
fn hanging_flexible_pendulum_swings_near_the_rigid_bar_frequency_in_both_formulations() {
    let mut s = flexmbd_test_support::scenes::model("flexible_pendulum.ron");
    s.bodies[0].orientation = flexmbd::model::Orientation::Angle(-std::f64::consts::FRAC_PI_2);
    let rigid = (3.0_f64 * 9.81 / 2.0).sqrt() / (2.0 * PI);
    let mut all = Vec::new();
    for form in FORMULATIONS {
        let (v, f) = oscillatory_in(&mut s, form, 5);
        assert!(
            relative_error(f[0], rigid) < 1e-3,
            "{form:?}: {} Hz, rigid {rigid} Hz",
            f[0]
        );
        assert_eq!(v.modes[0].sensors[0].name, "tip_x", "{form:?}");
        all.push(f);
    }
    for (a, b) in all[0].iter().zip(&all[1]) {
        assert!(relative_error(*a, *b) < 1e-6, "{all:?}");
    }
}
