//! The solid slider-crank (issue 25 item 7(b), models/solid_slider_crank.ron): crank and
//! connecting rod are steel bars of C3D8 bricks from CalculiX (models/fe/README.md), clamped at
//! their first pin with Craig–Bampton static modes of the other, a rigid slider on a rail and
//! a spring to a wall, undamped.
//!
//! - the parts' frequencies are SciPy's on the same matrices to 1e-6;
//! - the absolute and relative formulations converge to one motion at O(h²);
//! - the B-matrix and shape-integral inertia routes agree to round-off; the energy at t = 0 is
//!   the rigid parts' analytic value and is kept;
//! - the slider follows the rigid-link kinematics x = r cos θ + √(L² − r² sin² θ): to the
//!   Newton tolerance with the parts run rigid, and within the parts' measured elastic
//!   deflection at the pins when they are flexible.
//!
//! Sensor columns: slider_x, crank_angle, rod_mid_v, rod_y6, crank_y6, energy.

mod common;
use common::*;
use flexmbd_body::InertiaMethod;
use flexmbd_model::{Axis, BodyModel, Scene, Sensor, SensorKind};

const SCENE: &str = "solid_slider_crank.ron";
const SLIDER: usize = 0;
const ANGLE: usize = 1;
const ENERGY: usize = 5;
const R: f64 = 0.3;
const L: f64 = 1.0;

/// The slider's position of the rigid slider-crank at crank angle θ (no rail offset).
fn rigid_slider(theta: f64) -> f64 {
    R * theta.cos() + (L * L - (R * theta.sin()).powi(2)).sqrt()
}

/// The lines of models/fe/<file> tagged `tag` (the SciPy frequencies, Hz).
fn reference(file: &str, tag: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(models_dir().join("fe").join(file)).unwrap();
    text.lines()
        .filter_map(|l| l.strip_prefix(tag)?.strip_prefix(' '))
        .map(|v| v.trim().parse::<f64>().unwrap())
        .collect()
}

#[test]
fn part_frequencies_are_scipys() {
    let s = model(SCENE);
    for (i, part) in ["crank", "rod"].into_iter().enumerate() {
        let BodyModel::Imported(spec) = &s.bodies[i].model else {
            panic!("{part} is an imported body")
        };
        // As in the scene: frame at the first pin, static modes of the second, so the normal
        // modes are the fixed-interface ones, both pins clamped (SciPy's "OB").
        let body = flexmbd_fe::imported::import_body(spec, &models_dir(), part).unwrap();
        let hz = &body.body.inventory.normal_frequencies_hz;
        let ob = reference(&format!("{part}_scipy_frequencies.txt"), "OB");
        assert_eq!(hz.len(), 2);
        // Without the second pin (its RBE2 spider would stiffen the part) and with 10 modes:
        // the first pin clamped ("O").
        let mut alone = spec.clone();
        alone.interfaces.truncate(1);
        alone.boundary.clear();
        alone.normal_modes = 10;
        let body = flexmbd_fe::imported::import_body(&alone, &models_dir(), part).unwrap();
        let hz_o = &body.body.inventory.normal_frequencies_hz;
        let o = reference(&format!("{part}_scipy_frequencies.txt"), "O");
        assert_eq!((ob.len(), o.len(), hz_o.len()), (10, 10, 10));
        let worst = hz
            .iter()
            .zip(&ob)
            .chain(hz_o.iter().zip(&o))
            .map(|(a, b)| (a / b - 1.0).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "{part}: fixed-interface {hz:.3?} Hz, pin O clamped {hz_o:.3?} Hz; against SciPy within {worst:.1e}"
        );
        assert!(worst < 1e-6, "{part}: {worst:e}");
    }
}

#[test]
fn formulations_converge_to_one_motion() {
    let s = model(SCENE);
    let (a, r) = (absolute(&s), relative(&s));
    use flexmbd_core::Formulation;
    eprintln!(
        "coordinates: absolute {}, relative {}",
        a.n_coordinates(),
        r.n_coordinates()
    );
    let d: Vec<f64> = [1e-3f64, 5e-4, 2.5e-4]
        .iter()
        .map(|&h| {
            let every = (0.01 / h).round() as usize;
            let (x, _) = run_absolute(&s, h, 0.5, every);
            let (y, _) = run_relative(&s, h, 0.5, every);
            x.iter()
                .zip(&y)
                .map(|(p, q)| {
                    (p[SLIDER] - q[SLIDER])
                        .abs()
                        .max(R * (p[ANGLE] - q[ANGLE]).abs())
                })
                .fold(0.0, f64::max)
        })
        .collect();
    eprintln!(
        "solid slider-crank, 0.5 s: max |rel − abs| (slider x, r·crank angle) at h = 1, 0.5, 0.25 ms: {:.2e} {:.2e} {:.2e} m",
        d[0], d[1], d[2]
    );
    assert!(d[0] / d[1] > 3.0 && d[1] / d[2] > 3.0, "{d:?}");
    assert!(d[2] < 1e-6, "{d:?}");
}

/// The kinetic energy at t = 0 of the undeformed parts (gravity's and the spring's potential
/// are zero there): the crank, a steel box 0.35 × 0.04 × 0.02 m centred 0.15 m from O, turning
/// at ω0 = 2π rad/s about O; the rod, 1.05 × 0.04 × 0.02 m, turning at r ω0 / L about C (at
/// rest at the dead centre), its centre 0.5 m from C. The consistent mass of trilinear bricks
/// holds a rigid motion's kinetic energy exactly.
fn analytic_energy() -> f64 {
    let w = 2.0 * std::f64::consts::PI;
    let (mc, mr) = (7850.0 * 0.35 * 0.04 * 0.02, 7850.0 * 1.05 * 0.04 * 0.02);
    let ic = mc * ((0.35f64.powi(2) + 0.04f64.powi(2)) / 12.0 + 0.15f64.powi(2));
    let ir = mr * ((1.05f64.powi(2) + 0.04f64.powi(2)) / 12.0 + 0.25);
    0.5 * ic * w * w + 0.5 * ir * (R * w / L).powi(2)
}

#[test]
fn energy_is_kept_and_the_inertia_routes_agree() {
    let mut s = model(SCENE);
    for (name, run) in [
        (
            "absolute",
            run_absolute as fn(&Scene, f64, f64, usize) -> (Vec<Vec<f64>>, f64),
        ),
        ("relative", run_relative),
    ] {
        s.solver.inertia = InertiaMethod::ShapeIntegrals;
        let (shape, _) = run(&s, 1e-3, 1.0, 10);
        let e0 = shape[0][ENERGY];
        assert!(
            (e0 / analytic_energy() - 1.0).abs() < 1e-9,
            "{name}: E(0) = {e0}"
        );
        let drift = shape
            .iter()
            .map(|row| (row[ENERGY] - e0).abs() / e0)
            .fold(0.0, f64::max);
        s.solver.inertia = InertiaMethod::BMatrix;
        let (bmatrix, _) = run(&s, 1e-3, 1.0, 10);
        let worst = shape
            .iter()
            .zip(&bmatrix)
            .map(|(p, q)| {
                (p[SLIDER] - q[SLIDER])
                    .abs()
                    .max((p[ANGLE] - q[ANGLE]).abs())
            })
            .fold(0.0, f64::max);
        eprintln!(
            "{name}, h = 1 ms, 1 s: E(0) = {e0:.6} J ({:.1e} off the rigid parts' value), energy within {drift:.1e}; B-matrix against shape integrals {worst:.1e}",
            e0 / analytic_energy() - 1.0
        );
        assert!(drift < 5e-4, "{name}: {drift:e}");
        assert!(worst < 1e-10, "{name}: {worst:e}");
    }
}

fn position(name: &str, body: &str, marker: &str, component: Axis) -> Sensor {
    Sensor {
        name: name.into(),
        kind: SensorKind::Position {
            body: body.into(),
            marker: marker.into(),
            component,
            frame: Some(body.into()),
        },
        displacement: true,
    }
}

/// The rigid-link formula: with the parts run rigid (`flexible: false`) the slider follows it
/// to the Newton tolerance; flexible, it departs from it by no more than the pins' elastic
/// displacements allow. The slider is x = B_x + √(ℓ² − B_y²), B the crank pin and ℓ the rod's
/// pin distance; to first order δx = δB_x − B_y/√(L² − B_y²) δB_y + L/√(L² − B_y²) δℓ, with
/// |B_y| ≤ r, so |δx| ≤ 1.05 (|u_B| + |u_C,x|) (r/√(L² − r²) = 0.31, L/√(L² − r²) = 1.048):
/// u_B the crank's elastic displacement at B (crank frame), u_C,x the rod's at C along the
/// rod (rod frame; the lateral one changes ℓ at second order), read by sensors. With the
/// pins' displacements put into the formula exactly (B = R(θ)(r + u_B), ℓ = |(L + u_C,x,
/// u_C,y)|), the slider is where the deformed links put it, to the Newton tolerance.
#[test]
fn slider_follows_the_rigid_link_kinematics_within_the_elastic_deflection() {
    let rigid_run = |s: &Scene| {
        let (rows, _) = run_absolute(s, 1e-3, 1.0, 10);
        rows
    };
    let mut rigid = model(SCENE);
    rigid.bodies[0].flexible = false;
    rigid.bodies[1].flexible = false;
    rigid.sensors.truncate(2);
    let rows = rigid_run(&rigid);
    let worst_rigid = rows
        .iter()
        .map(|r| (r[SLIDER] - rigid_slider(r[ANGLE])).abs())
        .fold(0.0, f64::max);
    let swing = rows.iter().map(|r| r[ANGLE].abs()).fold(0.0, f64::max);
    eprintln!(
        "parts rigid: slider against the formula within {worst_rigid:.1e} m (crank swings to {swing:.2} rad)"
    );
    assert!(worst_rigid < 1e-8, "{worst_rigid:e}");
    assert!(swing > 2.0, "the crank hardly turns: {swing}");

    let mut s = model(SCENE);
    s.sensors.push(position("uB_x", "crank", "B", Axis::X));
    s.sensors.push(position("uB_y", "crank", "B", Axis::Y));
    s.sensors.push(position("uC_x", "rod", "C", Axis::X));
    s.sensors.push(position("uC_y", "rod", "C", Axis::Y));
    let (ub_x, ub_y, uc_x, uc_y) = (
        sensor_column(&s, "uB_x"),
        sensor_column(&s, "uB_y"),
        sensor_column(&s, "uC_x"),
        sensor_column(&s, "uC_y"),
    );
    for (name, run) in [
        (
            "absolute",
            run_absolute as fn(&Scene, f64, f64, usize) -> (Vec<Vec<f64>>, f64),
        ),
        ("relative", run_relative),
    ] {
        let (rows, _) = run(&s, 1e-3, 1.0, 10);
        let (mut worst, mut deflection, mut ratio): (f64, f64, f64) = (0.0, 0.0, 0.0);
        let mut exact: f64 = 0.0;
        for r in &rows {
            // The deformed links, exactly: B = R(θ) (r + u_B), ℓ = |(L + u_C,x, u_C,y)|.
            let (c, sn) = (r[ANGLE].cos(), r[ANGLE].sin());
            let (bx, by) = (
                (R + r[ub_x]) * c - r[ub_y] * sn,
                (R + r[ub_x]) * sn + r[ub_y] * c,
            );
            let ell = (L + r[uc_x]).hypot(r[uc_y]);
            exact = exact.max((r[SLIDER] - bx - (ell * ell - by * by).sqrt()).abs());
            let bound = 1.05 * (r[ub_x].hypot(r[ub_y]) + r[uc_x].abs());
            let off = (r[SLIDER] - rigid_slider(r[ANGLE])).abs();
            worst = worst.max(off);
            deflection = deflection.max(bound);
            // 1e-8 m: the Newton tolerance's share (the rigid run above)
            assert!(
                off <= bound + 1e-8,
                "{name} t-row: off {off:e} against the bound {bound:e}"
            );
            if bound > 1e-7 {
                ratio = ratio.max(off / bound);
            }
        }
        // The sensors and the slider agree to the Newton tolerance (1e-9 on the positions).
        assert!(exact < 1e-8, "{name}: {exact:e}");
        let mid = rows.iter().map(|r| r[2].abs()).fold(0.0, f64::max);
        eprintln!(
            "{name}: slider off the rigid formula by up to {worst:.2e} m, off the deformed links' by {exact:.1e} m; pin deflection bound up to {deflection:.2e} m (off / bound up to {ratio:.2} where the bound exceeds 1e-7 m); rod mid-span lateral {mid:.2e} m"
        );
        assert!(worst > 1e-7, "{name}: the parts do not deform ({worst:e})");
        assert!(mid > 1e-6, "{name}: the rod does not bend ({mid:e})");
    }
}
