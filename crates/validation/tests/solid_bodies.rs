//! A scene with a built-in solid body meshed by Gmsh (issue 29 item 5):
//! models/solid_bar_pendulum.ron is models/imported_bar_pendulum.ron with the bar's K and M
//! assembled by flexmbd's own C3D8 elements from a Gmsh mesh of the same bricks, instead of
//! read from CalculiX's export. CalculiX's C3D8 K and M equal ours to 4e-14
//! (crates/fe/tests/solid_calculix.rs), so the reduced bodies and the motions must agree (to
//! far below the time-discretisation error); the solid scene runs in both formulations and
//! they converge to one motion at O(h²).
//! Sensor columns: tip_x, tip_y, tip_z, tip_w, y0, energy.

mod common;
use std::path::Path;

use common::*;
use flexmbd_core::Formulation;
use flexmbd_fe::imported::{ImportedBodySpec, import_body};
use flexmbd_model::BodyModel;

fn spec(file: &str) -> ImportedBodySpec {
    match &model(file).bodies[0].model {
        BodyModel::Imported(spec) => spec.clone(),
        _ => panic!("{file}: the bar is not an imported body"),
    }
}

fn models_dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../models"))
}

#[test]
fn gmsh_solid_body_equals_the_calculix_import_of_the_same_mesh() {
    let solid = import_body(&spec("solid_bar_pendulum.ron"), models_dir(), "bar").unwrap();
    let ccx = import_body(&spec("imported_bar_pendulum.ron"), models_dir(), "bar").unwrap();
    // The physical groups are the end faces: 4 nodes each, at x = 0 and x = 0.2.
    assert_eq!(solid.interfaces.len(), 2);
    for ((name, p), (name_c, p_c)) in solid.interfaces.iter().zip(&ccx.interfaces) {
        assert_eq!(name, name_c);
        assert!((p - p_c).norm() < 1e-14, "{name}: {p} vs {p_c}");
    }
    let (f, f_c) = (
        &solid.body.inventory.normal_frequencies_hz,
        &ccx.body.inventory.normal_frequencies_hz,
    );
    assert_eq!(f.len(), f_c.len());
    for (a, b) in f.iter().zip(f_c) {
        assert!((a / b - 1.0).abs() < 1e-9, "{a} Hz vs {b} Hz");
    }
    eprintln!("solid bar: fixed-interface frequencies {f:.3?} Hz, CalculiX import {f_c:.3?} Hz");
    let (m, m_c) = (
        solid.body.shape_integrals.mass,
        ccx.body.shape_integrals.mass,
    );
    assert!((m / m_c - 1.0).abs() < 1e-12, "{m} vs {m_c}");
}

#[test]
fn gmsh_solid_pendulum_runs_in_both_formulations_and_matches_the_import() {
    let s = model("solid_bar_pendulum.ron");
    let (a, r) = (absolute(&s), relative(&s));
    assert_eq!((a.n_coordinates(), r.n_coordinates()), (22, 13));
    let tip =
        |rows: &[Vec<f64>]| -> Vec<[f64; 3]> { rows.iter().map(|r| [r[0], r[1], r[2]]).collect() };
    let largest = |x: &[[f64; 3]], y: &[[f64; 3]]| {
        x.iter()
            .zip(y)
            .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f64::max))
            .fold(0.0, f64::max)
    };
    let d: Vec<f64> = [4e-4f64, 2e-4, 1e-4]
        .iter()
        .map(|&h| {
            let every = (0.01 / h).round() as usize;
            let (x, _) = run_absolute(&s, h, 0.2, every);
            let (y, _) = run_relative(&s, h, 0.2, every);
            largest(&tip(&x), &tip(&y))
        })
        .collect();
    eprintln!(
        "solid bar pendulum, 0.2 s: max |tip_rel − tip_abs| at h = 0.4, 0.2, 0.1 ms: {:.2e} {:.2e} {:.2e} m",
        d[0], d[1], d[2]
    );
    assert!(d[0] / d[1] > 3.0 && d[1] / d[2] > 3.0, "{d:?}");
    assert!(d[2] < 1e-5, "{d:?}");
    // The same motion as the CalculiX import, in each formulation.
    let imported = model("imported_bar_pendulum.ron");
    for (name, run) in [
        ("absolute", run_absolute as fn(&_, f64, f64, usize) -> _),
        ("relative", run_relative),
    ] {
        let (x, _) = run(&s, 2e-4, 0.2, 50);
        let (y, _) = run(&imported, 2e-4, 0.2, 50);
        let diff = largest(&tip(&x), &tip(&y));
        let energy = (x[0][5] - y[0][5]).abs();
        eprintln!(
            "{name}: solid against import, max tip difference {diff:.2e} m, E(0) {energy:.1e} J"
        );
        // Not round-off, and not fully explained: the two models differ at about 1e-14
        // relative (CalculiX prints K and M to 14 digits) and this undamped run with stiff
        // tip modes amplifies such differences — K of the import scaled by 1 + 1e-13 alone
        // moves its tip by 3.0e-9 m (measured with these runs) — but that accounts for less
        // than the 3.2e-8 m measured here; the double lowest fixed-interface pair (3847.128
        // Hz twice: the square section), whose basis each reduction picks for itself, is a
        // candidate for the rest. The time-discretisation gap between the formulations at
        // this step is 1.0e-6 m, 30 times larger.
        assert!(diff < 1e-7, "{name}: {diff:e}");
        assert!(energy < 1e-12, "{name}: {energy:e}");
    }
}
