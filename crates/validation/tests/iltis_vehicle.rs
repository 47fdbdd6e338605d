//! Scene C, the Iltis vehicle in the thesis configuration (`models/iltis_vehicle.ron`,
//! docs/scenes.md §3.4–§3.7): the chassis free, at every corner the A-arm, leaf-spring link and
//! tie rod of scene B as beam bodies (rigid by default, flexible by `--set`), in both
//! formulations. Fast checks only; the 8 s runs and their CPU times belong to the report.
//!
//! - Rigid: the §3.4 equilibrium (7.373 mm, 0.1472°, tyres 3855.29 / 3615.83 N, leaf elements
//!   −3077.46 / −2893.55 N, struts −338.88 / −246.58 N) in both formulations.
//! - Twelve flexible bodies: the equilibrium moves by an amount ∝ 1/E (E, 10E, 100E).
//! - Around the first step down of the road (moved so that the front wheels reach it 0.1 s
//!   after the static start), both formulations agree, rigid and with 12 flexible bodies, to
//!   1e-6 of the ranges at h = 0.25 ms, and their difference falls with the step (h = 1, 0.5,
//!   0.25 ms).
//! - With 12 flexible bodies a step allocates nothing, in either formulation.
//!
//! As scene B's table (tests/iltis_suspension.rs), §3.4's lies below the weight its own masses
//! give: the model's 1523.172 kg (§3.4: 1523.17) weigh 14942.32 N, the four tyres of the table
//! carry 2 × (3855.29 + 3615.83) = 14942.24 N. The checks hold every force to one unit of its
//! printed digit plus that 0.08 N deficit (found: front tyre +0.010 N, rear +0.031 N), the tyres'
//! sum to m g itself, and the drop and pitch to their printed digits.

use flexmbd::Simulation;
use flexmbd::model::{BodyModel, FormulationKind, Scene};
use flexmbd::output::History;
use flexmbd_test_support::iltis::{
    assert_shifts_fall_as_one_over_e, vehicle_flexible, vehicle_near_the_first_step,
    vehicle_stiffness,
};

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

const FORMS: [FormulationKind; 2] = [FormulationKind::Absolute, FormulationKind::Relative];
/// The chassis centre of mass at the nominal position (docs/scenes.md §2.1).
const NOMINAL_Z: f64 = 0.570;
const G: f64 = 9.81;

fn scene(form: FormulationKind, sets: &[String]) -> Scene {
    flexmbd_test_support::scenes::model_with("iltis_vehicle.ron", form, sets)
}

/// The vehicle's whole mass, from the scene itself (beam bodies by their FE mass).
fn vehicle_mass(scene: &Scene) -> f64 {
    scene
        .bodies
        .iter()
        .map(|b| match &b.model {
            BodyModel::Rigid { mass, .. } => *mass,
            BodyModel::Beam(spec) => flexmbd_fe::reduce(spec).unwrap().mass(),
            BodyModel::Imported(_) => unreachable!("the Iltis scenes import no FE model"),
        })
        .sum()
}

/// |value − table| within `tolerance`, printed.
fn check_table(what: &str, value: f64, table: f64, tolerance: f64) {
    eprintln!("  {what}: {value:.6} (§3.4 {table}, {:+.4})", value - table);
    assert!(
        (value - table).abs() <= tolerance,
        "{what}: {value} against §3.4's {table} (±{tolerance})"
    );
}

const TABLE_TYRES: [f64; 2] = [3855.29, 3615.83];

#[test]
fn rigid_thesis_configuration_equilibrium_matches_section_3_4_in_both_formulations() {
    let mut found = Vec::new();
    for form in FORMS {
        let s = scene(form, &[]);
        let weight = vehicle_mass(&s) * G;
        let deficit = weight - 2.0 * (TABLE_TYRES[0] + TABLE_TYRES[1]);
        eprintln!("{form:?}: weight {weight:.4} N, the table's deficit {deficit:.4} N");
        assert!((0.07..0.09).contains(&deficit), "{deficit}");
        let e = flexmbd::equilibrium::equilibrium(&s).unwrap();
        let v = |name: &str| e.sensor(name).unwrap();
        let tyres: f64 = ["fl", "fr", "rl", "rr"]
            .iter()
            .map(|c| v(&format!("tyre_{c}")))
            .sum();
        assert!((tyres - weight).abs() < 1e-6 * weight, "{tyres} {weight}");
        let drop = (NOMINAL_Z - v("chassis_z")) * 1e3;
        check_table("chassis drop (mm)", drop, 7.373, 0.0005);
        // Nose down is a positive rotation about y (the front axle lower).
        let pitch = v("chassis_pitch").to_degrees();
        check_table("pitch (deg)", pitch, 0.1472, 0.00005);
        let force = 0.01 + deficit;
        check_table("front tyre (N)", v("tyre_fl"), TABLE_TYRES[0], force);
        check_table("rear tyre (N)", v("tyre_rl"), TABLE_TYRES[1], force);
        check_table("front leaf (N)", v("leaf_fl"), -3077.46, force);
        check_table("rear leaf (N)", v("leaf_rl"), -2893.55, force);
        check_table("front strut (N)", v("strut_fl"), -338.88, force);
        check_table("rear strut (N)", v("strut_rl"), -246.58, force);
        // Left and right alike (the vehicle and the road are symmetric).
        assert!((v("tyre_fl") - v("tyre_fr")).abs() < 1e-6);
        assert!(v("chassis_roll").abs() < 1e-9);
        found.push([
            v("chassis_z"),
            v("chassis_pitch"),
            v("tyre_fl"),
            v("tyre_rl"),
        ]);
    }
    for k in 0..4 {
        let (a, r) = (found[0][k], found[1][k]);
        assert!((a - r).abs() <= 1e-9 * a.abs().max(1.0), "{k}: {a} {r}");
    }
}

/// With the 12 beam bodies flexible the equilibrium differs from the rigid one by an amount
/// ∝ 1/E: the chassis sits lower, the struts carry less, the front-left A-arm deflects.
#[test]
fn twelve_flexible_bodies_move_the_equilibrium_as_one_over_e() {
    let form = FormulationKind::Relative;
    let rigid = flexmbd::equilibrium::equilibrium(&scene(form, &[])).unwrap();
    let mut shifts = Vec::new();
    for factor in [1.0, 10.0, 100.0] {
        let mut sets = vehicle_flexible(12);
        sets.extend(vehicle_stiffness(factor));
        let e = flexmbd::equilibrium::equilibrium(&scene(form, &sets)).unwrap();
        let shift = |name: &str| e.sensor(name).unwrap() - rigid.sensor(name).unwrap();
        let s = [
            shift("chassis_z"),
            shift("strut_fl"),
            shift("strut_rl"),
            shift("aarm_fl_deflection"),
        ];
        eprintln!(
            "E × {factor}: chassis z {:.3e} m, struts fl / rl {:.3e} / {:.3e} N, A-arm deflection {:.3e} m",
            s[0], s[1], s[2], s[3]
        );
        shifts.push(s);
    }
    assert_shifts_fall_as_one_over_e(&shifts);
}

fn column(history: &History, name: &str) -> Vec<f64> {
    let k = history.header.iter().position(|n| n == name).unwrap();
    history.rows.iter().map(|r| r[k]).collect()
}

fn range(v: &[f64]) -> f64 {
    v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
}

/// Largest |a − b| of sensor `name` over a's range.
fn relative_difference(a: &History, b: &History, name: &str) -> f64 {
    let (a, b) = (column(a, name), column(b, name));
    let diff = a
        .iter()
        .zip(&b)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max);
    diff / range(&a)
}

fn run(form: FormulationKind, sets: &[String]) -> History {
    let (summary, history) = flexmbd::simulation::run(&scene(form, sets), |_| {}).unwrap();
    assert_eq!(
        summary.status, "ok",
        "{form:?} {sets:?}: {:?}",
        summary.message
    );
    history
}

const COMPARED: [&str; 4] = ["chassis_z", "chassis_pitch", "wheel_fl_z", "tyre_fl"];

/// Around the first step down, the two formulations agree, rigid and with 12 flexible
/// bodies, to 1e-6 of the ranges at h = 0.25 ms, and their difference falls as the step does
/// (h = 1, 0.5, 0.25 ms): by 4.2–4.5 per halving rigid (second order), by 2.8–2.9 with the
/// flexible bodies, whose fixed-interface modes (388 Hz and up, §2.8) these steps do not
/// resolve (§2.10), so the pair is not yet in its asymptotic range.
#[test]
fn the_formulations_converge_together_over_the_first_step_down() {
    for (k, per_halving) in [(0, 3.0), (12, 2.5)] {
        let mut worst = Vec::new();
        for step in [1e-3, 5e-4, 2.5e-4] {
            let mut sets = vehicle_flexible(k);
            sets.extend(vehicle_near_the_first_step());
            sets.push(format!("solver.step={step}"));
            let (a, r) = (
                run(FormulationKind::Absolute, &sets),
                run(FormulationKind::Relative, &sets),
            );
            // The front wheels leave the road and land: the tyre force falls to 0.
            let tyre = column(&r, "tyre_fl");
            assert!(tyre.contains(&0.0), "{k}: the wheel stays down");
            let largest = COMPARED
                .iter()
                .map(|n| relative_difference(&a, &r, n))
                .fold(0.0, f64::max);
            eprintln!(
                "{k} flexible, h = {step}: the formulations differ by {largest:.2e} of the range"
            );
            worst.push(largest);
        }
        assert!(worst[2] < 1e-6, "{k} flexible: {worst:?}");
        assert!(
            worst[1] < worst[0] / per_halving && worst[2] < worst[1] / per_halving,
            "{k} flexible: {worst:?}"
        );
    }
}

/// With the 12 beam bodies flexible, a step (after a few have sized everything) and reading
/// the sensors allocate nothing, in either formulation.
#[test]
fn twelve_flexible_bodies_step_without_allocating() {
    for form in FORMS {
        let mut sets = vehicle_flexible(12);
        sets.extend(vehicle_near_the_first_step());
        let mut sim = Simulation::new(&scene(form, &sets)).unwrap();
        let mut values = vec![0.0; sim.sensor_names().len()];
        for _ in 0..3 {
            sim.step().unwrap();
        }
        let before = flexmbd_test_support::allocations();
        // 150 steps at h = 1 ms: through the front wheels' step down at 0.1 s.
        for _ in 0..150 {
            sim.step().unwrap();
        }
        sim.read_sensors(&mut values);
        let made = flexmbd_test_support::allocations() - before;
        assert_eq!(
            made, 0,
            "{form:?}: {made} allocations in 150 steps and a reading"
        );
    }
}
