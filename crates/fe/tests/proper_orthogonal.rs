//! Proper orthogonal modes from a pilot record (docs/methods.md §1.6, `flexmbd_fe::pod`):
//! the basis built from a given record of the candidates' coordinates, against the lowest
//! normal modes, and its refusals. The pilot run itself is the facade's
//! (crates/flexmbd/tests/proper_orthogonal.rs).

mod common;

use std::sync::Arc;

use common::*;
use flexmbd_core::Dim;
use flexmbd_fe::assembly::to_dense;
use flexmbd_fe::pod::{PilotRecord, candidate_count, leading_directions};
use flexmbd_fe::{BeamBodySpec, Dof, FeError, ModeSelection, NodeDof, preprocess};
use nalgebra::{DMatrix, DVector};

/// A deterministic pseudo-random record of `k` coordinates over `samples` samples, the
/// coordinate j of size about 1/(j+1) (a lower mode moves more).
fn record(k: usize, samples: usize) -> PilotRecord {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    PilotRecord {
        coordinates: DMatrix::from_fn(k, samples, |j, _| next() / (j + 1) as f64),
        times: (0..samples).map(|s| s as f64 * 1e-3).collect(),
    }
}

fn proper_orthogonal(mut spec: BeamBodySpec, n: usize, record: PilotRecord) -> BeamBodySpec {
    spec.mode_selection = ModeSelection::ProperOrthogonal;
    spec.normal_modes = n;
    spec.pilot = Some(Arc::new(record));
    spec
}

fn max_abs(a: &DMatrix<f64>) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn proper_orthogonal_modes_of_every_candidate_are_the_lowest_modes() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut lowest = cantilever(dim, rect10x20(), 12, 6);
        lowest.boundary = vec![NodeDof {
            node: 12,
            dof: Dof::Uy,
        }];
        let mut pod = proper_orthogonal(lowest.clone(), 6, record(6, 400));
        pod.mode_candidates = Some(6);
        let (a, b) = (preprocess(&lowest).unwrap(), preprocess(&pod).unwrap());
        let worst = worst_relative_difference(&a.reduction.omega_sq, &b.reduction.omega_sq);
        // Same vectors up to sign: |Φ_lowestᵀ M Φ_pod| is the identity.
        let (xa, xb) = (&a.reduction.x, &b.reduction.x);
        let overlap = (xa.columns(1, 6).transpose() * to_dense(&a.m) * xb.columns(1, 6)).abs();
        let off = max_abs(&(overlap - DMatrix::identity(6, 6)));
        println!("{dim:?}: worst relative ω² difference {worst:.2e}, |overlap − I| {off:.2e}");
        assert_eq!(b.reduction.omega_sq.len(), 6);
        assert!(worst < 1e-10 && off < 1e-8);
        assert_eq!(b.body.inventory.selection, ModeSelection::ProperOrthogonal);
    }
}

#[test]
fn a_record_of_one_mode_gives_that_mode_first() {
    // Only the third candidate moves: the one proper orthogonal mode is that normal mode.
    let lowest = cantilever(Dim::Planar, square10(), 10, 4);
    let mut only_third = record(4, 200);
    for j in [0, 1, 3] {
        only_third.coordinates.row_mut(j).fill(0.0);
    }
    let pod = proper_orthogonal(lowest.clone(), 1, only_third);
    let (a, b) = (preprocess(&lowest).unwrap(), preprocess(&pod).unwrap());
    let (w_lowest, w_pod) = (a.reduction.omega_sq[2], b.reduction.omega_sq[0]);
    let cosine =
        (a.reduction.x.column(2).transpose() * to_dense(&a.m) * b.reduction.x.column(0))[0];
    println!(
        "ω² of mode 3 {w_lowest:.6e}, of the proper orthogonal mode {w_pod:.6e}, cos {cosine}"
    );
    assert!((w_pod - w_lowest).abs() < 1e-10 * w_lowest);
    assert!((cosine.abs() - 1.0).abs() < 1e-10);
}

#[test]
fn leading_directions_hold_the_most_of_the_snapshots() {
    // Snapshots along (1, 1, 0) and, at other instants and ten times smaller, along
    // (0, 0, 1): the first direction is (1, 1, 0)/√2, the second (0, 0, 1).
    let eta = DMatrix::from_fn(3, 50, |i, s| match (i, s % 2) {
        (0 | 1, 0) => (s as f64 * 0.1).sin(),
        (2, 1) => 0.1 * (s as f64 * 0.3).cos(),
        _ => 0.0,
    });
    let u = leading_directions(&eta, 2);
    let first = DVector::from_column_slice(&[1.0, 1.0, 0.0]) / 2f64.sqrt();
    assert!((u.column(0).dot(&first).abs() - 1.0).abs() < 1e-12, "{u}");
    assert!((u[(2, 1)].abs() - 1.0).abs() < 1e-12, "{u}");
}

#[test]
fn proper_orthogonal_modes_without_a_pilot_are_refused_by_name() {
    let mut spec = cantilever(Dim::Planar, square10(), 10, 2);
    spec.mode_selection = ModeSelection::ProperOrthogonal;
    let e = preprocess(&spec).unwrap_err().to_string();
    println!("{e}");
    assert!(e.contains("mode_selection") && e.contains("ProperOrthogonal") && e.contains("pilot"));
    // A record of another basis (3 rows for 4 candidates) is refused, not misread.
    let e = preprocess(&proper_orthogonal(spec.clone(), 2, record(3, 10)))
        .unwrap_err()
        .to_string();
    println!("{e}");
    assert!(e.contains("3 recorded") && e.contains("4 normal modes"));
}

#[test]
fn pilot_duration_and_candidates_are_refused_by_name_and_value() {
    let base = cantilever(Dim::Planar, square10(), 4, 3);
    let refuse = |spec: &BeamBodySpec, field: &str, value: &str| {
        let e = spec.validate().unwrap_err();
        let text = e.to_string();
        assert!(matches!(e, FeError::Invalid(_)), "{text}");
        assert!(text.contains(field) && text.contains(value), "{text}");
        println!("{text}");
    };
    let mut s = base.clone();
    s.pilot_duration = Some(1.0);
    refuse(
        &s,
        "pilot_duration",
        "only used with mode_selection: ProperOrthogonal",
    );
    s.mode_selection = ModeSelection::ProperOrthogonal;
    assert!(s.validate().is_ok());
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        s.pilot_duration = Some(bad);
        refuse(&s, "pilot_duration", &format!("{bad}"));
    }
    s.pilot_duration = None;
    s.mode_candidates = Some(2);
    refuse(&s, "mode_candidates = 2", "at least normal_modes (3)");
    s.mode_candidates = Some(13);
    refuse(&s, "mode_candidates = 13", "interior DOFs");
    s.mode_candidates = Some(12);
    assert!(s.validate().is_ok());
}

#[test]
fn the_default_candidates_are_twice_the_modes_and_at_least_four() {
    let mut spec = cantilever(Dim::Planar, square10(), 10, 1);
    assert_eq!(candidate_count(&spec), 4);
    spec.normal_modes = 3;
    assert_eq!(candidate_count(&spec), 6);
    // 2 elements, clamped: 6 interior DOFs, 2 of them kept as axial modes.
    let mut small = cantilever(Dim::Planar, square10(), 2, 3);
    small.axial_modes = 2;
    assert_eq!(candidate_count(&small), 4);
}
