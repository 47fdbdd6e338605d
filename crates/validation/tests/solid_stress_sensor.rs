//! Stress sensors on a solid body (issue 29 item 3): models/solid_cantilever.ron, a steel
//! cantilever of Gmsh-meshed C3D20 bricks settling under its own weight, reports the largest
//! von Mises and principal stress over its mid-span section. Settled, both formulations
//! report the static stress of the reduced body computed independently here through the FE
//! API (K_ff q = Sᵀ g, then the modal stress shapes), and that stress is the cantilever's
//! bending stress, σ = w (L/2)² / 2 · (h/2) / I = 231026 Pa (Euler–Bernoulli), within the
//! modal truncation and the section's 3D effects.
//! Sensor columns: mid_von_mises, mid_principal, tip_z (and mid_sxx, added by a test).

mod common;
use std::path::Path;

use common::*;
use flexmbd_fe::imported::{ImportSource, import_body};
use flexmbd_fe::solid::body_stress_shapes;
use flexmbd_fe::solid::stress::{Stress, largest_principal, von_mises};
use flexmbd_model::{BodyModel, Sensor, SensorKind, StressQuantity};
use nalgebra::Vector3;

fn models_dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../models"))
}

/// (von Mises, largest principal, largest σ_xx) of the reduced body's static response to
/// gravity, the largest over the node set `mid`, through the FE API alone.
fn static_stress() -> (f64, f64, f64) {
    let s = model("solid_cantilever.ron");
    let BodyModel::Imported(spec) = &s.bodies[0].model else {
        panic!("the bar is not an imported body")
    };
    let ImportSource::Solid { material, .. } = &spec.source else {
        panic!("the bar is not a solid")
    };
    let body = import_body(spec, models_dir(), "bar").unwrap();
    let model = spec.source.read(models_dir(), &spec.options).unwrap();
    let shapes = body_stress_shapes(
        &model,
        material,
        &body.body,
        body.interfaces.len(),
        "cantilever",
    )
    .unwrap();
    let f = body.body.shape_integrals.s.transpose() * Vector3::new(0.0, 0.0, -9.81);
    let q = body.body.k_ff.clone().lu().solve(&f).unwrap();
    let mid = &model.mesh.node_sets["mid"];
    let stress =
        |n: usize| Stress::from_iterator((shapes.shapes.rows(6 * n, 6) * &q).iter().copied());
    let vm = mid
        .iter()
        .map(|&n| von_mises(&stress(n)))
        .fold(0.0, f64::max);
    let p1 = mid
        .iter()
        .map(|&n| largest_principal(&stress(n)))
        .fold(f64::MIN, f64::max);
    let sxx = mid.iter().map(|&n| stress(n)[0]).fold(f64::MIN, f64::max);
    (vm, p1, sxx)
}

#[test]
fn settled_stress_sensors_equal_the_static_fe_stress_and_the_beam_formula() {
    let mut s = model("solid_cantilever.ron");
    s.sensors.push(Sensor {
        name: "mid_sxx".into(),
        kind: SensorKind::Stress {
            body: "bar".into(),
            nodes: "mid".into(),
            quantity: StressQuantity::Sxx,
        },
        ..s.sensors[0].clone()
    });
    let (vm, p1, sxx) = static_stress();
    let w = 7850.0 * 1e-4 * 9.81;
    let (l, h) = (0.2_f64, 0.01_f64);
    let beam = w * (l / 2.0).powi(2) / 2.0 * (h / 2.0) / (h.powi(4) / 12.0);
    eprintln!(
        "static FE route: von Mises {vm:.2} Pa ({:+.3} % of the beam's {beam:.2} Pa), largest \
         principal {p1:.2} Pa ({:+.3} %)",
        100.0 * (vm / beam - 1.0),
        100.0 * (p1 / beam - 1.0)
    );
    eprintln!(
        "largest sigma_xx {sxx:.2} Pa ({:+.3} %)",
        100.0 * (sxx / beam - 1.0)
    );
    assert!((vm / beam - 1.0).abs() < 0.015 && (p1 / beam - 1.0).abs() < 0.015);
    assert!((sxx / beam - 1.0).abs() < 0.015);
    let (a, _) = run_absolute(&s, 2e-4, 0.1, 10);
    let (r, _) = run_relative(&s, 2e-4, 0.1, 10);
    for (name, rows) in [("absolute", &a), ("relative", &r)] {
        let last = rows.last().unwrap();
        eprintln!(
            "{name}: settled von Mises {:.4} Pa, principal {:.4} Pa",
            last[0], last[1]
        );
        assert!(
            (last[0] / vm - 1.0).abs() < 1e-6,
            "{name}: {} vs {vm}",
            last[0]
        );
        assert!(
            (last[1] / p1 - 1.0).abs() < 1e-6,
            "{name}: {} vs {p1}",
            last[1]
        );
        assert_eq!(rows[0][0], 0.0);
    }
    let worst = a
        .iter()
        .zip(&r)
        .map(|(x, y)| (x[0] - y[0]).abs())
        .fold(0.0, f64::max);
    eprintln!("absolute against relative, von Mises history: {worst:.2e} Pa");
    assert!(worst < 1e-3 * vm, "{worst:e}");
}

#[test]
fn stress_sensors_are_refused_off_solid_bodies_and_sets() {
    let mut s = model("solid_cantilever.ron");
    s.sensors[0].kind = SensorKind::Stress {
        body: "bar".into(),
        nodes: "middle".into(),
        quantity: StressQuantity::VonMises,
    };
    let e = flexmbd_model::PreparedScene::new(&s)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("sensors[mid_von_mises].nodes") && e.contains("bar, mid, root, tip"),
        "{e}"
    );
    let mut p = model("imported_bar_pendulum.ron");
    p.sensors.push(Sensor {
        name: "root_stress".into(),
        kind: SensorKind::Stress {
            body: "bar".into(),
            nodes: "root".into(),
            quantity: StressQuantity::VonMises,
        },
        ..p.sensors[0].clone()
    });
    let e = flexmbd_model::PreparedScene::new(&p)
        .unwrap_err()
        .to_string();
    assert!(e.contains("source: Solid"), "{e}");
}
