//! Bad input is refused with the offending field named; static load stepping recovers from
//! a single requested load step.

use flexmbd_ancf::{AncfError, Cable, CableSpec, run_spin_up};
use flexmbd_core::Dim;

#[test]
fn bad_values_name_their_field() {
    let ok = CableSpec::spin_up_beam(Dim::Planar, 4);
    let cases: Vec<(CableSpec, &str)> = vec![
        (
            CableSpec {
                length: -1.0,
                ..ok.clone()
            },
            "length",
        ),
        (
            CableSpec {
                ea: 0.0,
                ..ok.clone()
            },
            "ea",
        ),
        (
            CableSpec {
                ei: f64::NAN,
                ..ok.clone()
            },
            "ei",
        ),
        (
            CableSpec {
                rho_a: -2.0,
                ..ok.clone()
            },
            "rho_a",
        ),
        (
            CableSpec {
                elements: 0,
                ..ok.clone()
            },
            "elements",
        ),
        (
            CableSpec {
                gravity: [0.0, 0.0, -9.81],
                ..ok.clone()
            },
            "gravity[2]",
        ),
        (
            CableSpec {
                gravity: [f64::INFINITY, 0.0, 0.0],
                ..ok.clone()
            },
            "gravity[0]",
        ),
        (
            CableSpec {
                omega_s: f64::NAN,
                ..ok.clone()
            },
            "omega_s",
        ),
        (
            CableSpec {
                t_s: 0.0,
                ..ok.clone()
            },
            "t_s",
        ),
    ];
    for (spec, field) in cases {
        let e = Cable::new(&spec).unwrap_err();
        assert_eq!(e.field, field, "{e}");
    }
    for (h, d, o, field) in [
        (0.0, 1.0, 0.1, "step"),
        (1e-3, -1.0, 0.1, "duration"),
        (1e-3, 1.0, 1e-4, "output_interval"),
    ] {
        match run_spin_up(&ok, h, d, o) {
            Err(AncfError::Invalid(e)) => assert_eq!(e.field, field),
            other => panic!("{field}: {other:?}"),
        }
    }
}

#[test]
fn spec_round_trips_through_serde() {
    let spec = CableSpec::spin_up_beam(Dim::Spatial, 16);
    let json = serde_json::to_string(&spec).unwrap();
    for f in [
        "dim", "length", "ea", "ei", "rho_a", "elements", "gravity", "omega_s", "t_s",
    ] {
        assert!(json.contains(&format!("\"{f}\"")), "{f} in {json}");
    }
    let back: CableSpec = serde_json::from_str(&json).unwrap();
    assert_eq!(back, spec);
    assert!(serde_json::from_str::<CableSpec>(&json.replace("\"ea\"", "\"EA\"")).is_err());
}

#[test]
fn static_load_stepping() {
    // The Exudyn cantilever converges in one load step and in ten to the same point.
    let mut c = Cable::new(&CableSpec::exudyn_cantilever(Dim::Planar, 32)).unwrap();
    let r = c.solve_static(0.0, 1).unwrap();
    let d = c.tip_displacement(0.0, &c.initial_positions().clone());
    eprintln!(
        "one load step: {} accepted, {} iterations, u_x {}",
        r.load_steps, r.iterations, d[0]
    );
    assert!((d[0] + 0.5013058140308901).abs() < 1e-9);
    // A cable 1000 times softer in bending hangs almost vertically: one full-load Newton
    // solve fails from the straight start and the increment is halved until it converges.
    let soft = CableSpec {
        ei: 14.0,
        ..CableSpec::spin_up_beam(Dim::Spatial, 16)
    };
    let mut c = Cable::new(&soft).unwrap();
    let r = c.solve_static(0.0, 1).unwrap();
    let d = c.tip_displacement(0.0, &c.initial_positions().clone());
    eprintln!(
        "soft cable: {} load steps, {} iterations, residual {:.1e}, tip {d:?}",
        r.load_steps, r.iterations, r.residual
    );
    assert!(r.load_steps > 1);
    assert!(r.residual < 1e-12 * soft.ea);
    assert!(d[2] < -8.0, "{d:?}");
}
