//! The IAVSD Iltis benchmark vehicle (scene C0, docs/scenes.md §3.3;
//! `models/iltis_vehicle_benchmark.ron`, `models/iltis_bump.ron`) against the only published
//! numbers there are, S9's (scenes.md §2.6, §3.2), in both formulations:
//!
//! - the element forces at the nominal position (S9 `1_Nominal_Report.txt`);
//! - the static equilibrium (S9 `2_Equilibrium_Report.txt`) to the printed digits;
//! - the linearised frequencies with the dampers removed (scenes.md §3.2, DERIVED) to 0.5 %;
//! - the equilibrium holds still for 1 s;
//! - the in-phase cosine bump at 5 m/s against S9's extremes (a few per cent: S9's output is
//!   sampled at about 0.02 s), with the lateral tyre damper that stands for S9's Calspan slip
//!   force (without it the tyre-force minima fell 6–9 % below S9's), and the two formulations
//!   against each other.

use flexmbd::model::{FormulationKind, Scene, parse_set};
use flexmbd::output::History;

const FORMS: [FormulationKind; 2] = [FormulationKind::Absolute, FormulationKind::Relative];

fn scene(file: &str, form: FormulationKind, sets: &[String]) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../models")
        .join(file);
    let mut scene = Scene::load(path).unwrap();
    scene.solver.formulation = form;
    let sets: Vec<_> = sets.iter().map(|s| parse_set(s).unwrap()).collect();
    scene.apply_sets(&sets).unwrap();
    scene
}

fn column(history: &History, name: &str) -> Vec<(f64, f64)> {
    let k = history.header.iter().position(|n| n == name).unwrap();
    history.rows.iter().map(|r| (r[0], r[k])).collect()
}

/// |value − S9| within one unit of S9's last printed digit.
fn check_printed(what: &str, value: f64, s9: f64, unit: f64) {
    eprintln!("  {what}: {value:.6} (S9 {s9})");
    assert!(
        (value - s9).abs() <= unit * (1.0 + 1e-9),
        "{what}: {value} against S9 {s9} (±{unit})"
    );
}

#[test]
fn nominal_position_loads_match_s9() {
    for form in FORMS {
        let s = scene(
            "iltis_vehicle_benchmark.ron",
            form,
            &[
                "solver.initial_state=Given".into(),
                "solver.duration=0.001".into(),
            ],
        );
        let (summary, history) = flexmbd::simulation::run(&s, |_| {}).unwrap();
        assert_eq!(summary.status, "ok", "{:?}", summary.message);
        let at_start = |name: &str| column(&history, name)[0].1;
        eprintln!("{form:?}, nominal position:");
        check_printed("leaf element", at_start("leaf_fl"), -2728.86, 0.01);
        check_printed("strut spring", at_start("strut_fl"), -128.03, 0.01);
        check_printed("front tyre", at_start("tyre_fl"), 3829.50, 0.01);
        check_printed("rear tyre", at_start("tyre_rl"), 3593.52, 0.01);
    }
}

#[test]
fn static_equilibrium_matches_s9_to_the_printed_digits() {
    let degrees = 180.0 / std::f64::consts::PI;
    for form in FORMS {
        let s = scene("iltis_vehicle_benchmark.ron", form, &[]);
        let e = flexmbd::equilibrium::equilibrium(&s).unwrap();
        let v = |name: &str| e.sensor(name).unwrap();
        eprintln!("{form:?}, static equilibrium:");
        check_printed(
            "chassis drop (mm)",
            (v("chassis_z") - 0.570) * 1e3,
            -7.083,
            0.001,
        );
        check_printed("pitch (deg)", v("chassis_pitch") * degrees, 0.1465, 0.0001);
        check_printed("front tyre (N)", v("tyre_fl"), 3831.31, 0.01);
        check_printed("rear tyre (N)", v("tyre_rl"), 3591.91, 0.01);
        check_printed("front strut (N)", v("strut_fl"), -335.29, 0.01);
        check_printed("rear strut (N)", v("strut_rl"), -241.64, 0.01);
        check_printed("front leaf (N)", v("leaf_fl"), -3068.62, 0.01);
        check_printed("rear leaf (N)", v("leaf_rl"), -2885.51, 0.01);
        // Left and right alike, roll zero: the vehicle and its load are symmetric.
        assert!((v("tyre_fl") - v("tyre_fr")).abs() < 1e-6);
        assert!(v("chassis_roll").abs() < 1e-9);
    }
}

#[test]
fn undamped_frequencies_match_the_derived_ones_within_half_a_percent() {
    let undamped: Vec<String> = ["fl", "fr", "rl", "rr"]
        .iter()
        .map(|c| format!("forces.strut_{c}.damper=Zero"))
        .collect();
    for form in FORMS {
        let s = scene("iltis_vehicle_benchmark.ron", form, &undamped);
        let v = flexmbd::vibration::vibration(&s).unwrap();
        let found = v.frequencies("oscillatory");
        eprintln!("{form:?}: {found:?}");
        for (what, reference) in [
            ("pitch-dominant", 1.590),
            ("bounce-dominant", 1.849),
            ("front wheel hop", 14.42),
            ("rear wheel hop", 14.43),
        ] {
            let near = found
                .iter()
                .copied()
                .min_by(|a, b| (a - reference).abs().total_cmp(&(b - reference).abs()))
                .unwrap();
            assert!(
                (near - reference).abs() <= 0.005 * reference,
                "{form:?}: {what} {near} Hz against {reference} Hz"
            );
        }
    }
}

#[test]
fn the_equilibrium_holds_still_for_one_second() {
    for form in FORMS {
        let s = scene("iltis_vehicle_benchmark.ron", form, &[]);
        let (summary, history) = flexmbd::simulation::run(&s, |_| {}).unwrap();
        assert_eq!(summary.status, "ok", "{:?}", summary.message);
        for name in ["chassis_x", "chassis_z", "wheel_fl_z", "wheel_rl_z"] {
            let c = column(&history, name);
            let drift = c.iter().map(|p| (p.1 - c[0].1).abs()).fold(0.0, f64::max);
            eprintln!("{form:?}: {name} moves by at most {drift:.2e} m");
            assert!(drift < 1e-6, "{form:?}: {name} moved by {drift} m");
        }
    }
}

/// (time, value) of the largest (`max`) or smallest value.
fn extreme(c: &[(f64, f64)], max: bool) -> (f64, f64) {
    let mut best = c[0];
    for &p in c {
        if (max && p.1 > best.1) || (!max && p.1 < best.1) {
            best = p;
        }
    }
    best
}

fn within(what: &str, value: f64, s9: f64, relative: f64) {
    eprintln!(
        "  {what}: {value:.4} (S9 {s9}, {:+.2} %)",
        100.0 * (value - s9) / s9
    );
    assert!(
        (value - s9).abs() <= relative * s9.abs(),
        "{what}: {value} against S9 {s9}"
    );
}

#[test]
fn cosine_bump_at_5_m_s_reproduces_s9_extremes_in_both_formulations() {
    let degrees = 180.0 / std::f64::consts::PI;
    let mut histories = Vec::new();
    for form in FORMS {
        let s = scene("iltis_bump.ron", form, &[]);
        let (summary, history) = flexmbd::simulation::run(&s, |_| {}).unwrap();
        assert_eq!(summary.status, "ok", "{:?}", summary.message);
        let z = column(&history, "chassis_z");
        let (t_rise, top) = extreme(&z, true);
        let pitch = column(&history, "chassis_pitch");
        let (t_lo, lo) = extreme(&pitch, false);
        let (t_hi, hi) = extreme(&pitch, true);
        let front = column(&history, "tyre_fl");
        let rear = column(&history, "tyre_rl");
        eprintln!("{form:?}:");
        within("rise (mm)", (top - z[0].1) * 1e3, 127.8, 0.05);
        within("time of the rise (s)", t_rise, 0.725, 0.05);
        within("pitch minimum (deg)", lo * degrees, -6.35, 0.05);
        within("its time (s)", t_lo, 0.538, 0.05);
        within("pitch maximum (deg)", hi * degrees, 7.64, 0.05);
        within("its time (s)", t_hi, 1.033, 0.05);
        within(
            "front tyre maximum (N)",
            extreme(&front, true).1,
            6202.4,
            0.05,
        );
        within(
            "rear tyre maximum (N)",
            extreme(&rear, true).1,
            5664.2,
            0.05,
        );
        within(
            "front tyre minimum (N)",
            extreme(&front, false).1,
            1300.5,
            0.05,
        );
        within(
            "rear tyre minimum (N)",
            extreme(&rear, false).1,
            1360.1,
            0.05,
        );
        histories.push(history);
    }
    // From the static start the formulations differ by where each put the equilibrium along
    // its neutral motions (forward, sideways, yaw): taken back to second order only (3 µm of
    // chassis x), which bounds the agreement here; from one and the same start, see below.
    for name in ["chassis_z", "chassis_pitch", "wheel_fl_z", "tyre_fl"] {
        let difference = relative_difference(&histories[0], &histories[1], name);
        eprintln!("{name}: formulations differ by {difference:.2e} of the range");
        assert!(difference <= 1e-5, "{name}: {difference} of the range");
    }
}

/// Largest |a − b| of the sensor `name` over the histories, over the range of a.
fn relative_difference(a: &History, b: &History, name: &str) -> f64 {
    let (a, b) = (column(a, name), column(b, name));
    let range = a.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max)
        - a.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let diff = a
        .iter()
        .zip(&b)
        .map(|(p, q)| (p.1 - q.1).abs())
        .fold(0.0, f64::max);
    diff / range
}

/// From the same start (the nominal position, released at 5 m/s onto the bump), the two
/// formulations solve the same equations and differ only by their truncation errors: below
/// 10⁻⁶ of the range at h = 1 ms, and falling as the step does (O(h²): measured 1.7·10⁻⁷ of the
/// range of the front tyre force at 1 ms, 9.8·10⁻⁹ at 0.25 ms).
#[test]
fn the_formulations_agree_on_the_bump_and_converge_together() {
    let mut worst = Vec::new();
    for step in [1e-3, 2.5e-4] {
        let sets = [
            "solver.initial_state=Given".to_string(),
            "solver.duration=0.8".to_string(),
            "solver.output_interval=0.01".to_string(),
            format!("solver.step={step}"),
        ];
        let run = |form| {
            let s = scene("iltis_bump.ron", form, &sets);
            let (summary, history) = flexmbd::simulation::run(&s, |_| {}).unwrap();
            assert_eq!(summary.status, "ok", "{:?}", summary.message);
            history
        };
        let (a, b) = (
            run(FormulationKind::Absolute),
            run(FormulationKind::Relative),
        );
        let largest = ["chassis_z", "chassis_pitch", "wheel_fl_z", "tyre_fl"]
            .iter()
            .map(|n| relative_difference(&a, &b, n))
            .fold(0.0, f64::max);
        eprintln!("h = {step}: the formulations differ by {largest:.2e} of the range");
        assert!(largest <= 1e-6, "h = {step}: {largest}");
        worst.push(largest);
    }
    assert!(
        worst[1] < worst[0] / 4.0,
        "no convergence with the step: {worst:?}"
    );
}

#[test]
fn at_10_m_s_the_wheels_lift_off() {
    let s = scene(
        "iltis_bump.ron",
        FormulationKind::Relative,
        &flexmbd_test_support::iltis::bump_at_speed(10.0),
    );
    let (summary, history) = flexmbd::simulation::run(&s, |_| {}).unwrap();
    assert_eq!(summary.status, "ok", "{:?}", summary.message);
    let z = column(&history, "chassis_z");
    let rise = (extreme(&z, true).1 - z[0].1) * 1e3;
    let lowest = ["tyre_fl", "tyre_rl"]
        .iter()
        .map(|n| extreme(&column(&history, n), false).1)
        .fold(f64::INFINITY, f64::min);
    eprintln!("10 m/s: rise {rise:.1} mm (S9 314.1), lowest tyre force {lowest} N");
    assert_eq!(
        lowest, 0.0,
        "a wheel must leave the road: the tyre force is then exactly 0"
    );
    within("rise at 10 m/s (mm)", rise, 314.1, 0.05);
}
