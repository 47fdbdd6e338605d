//! The rigid double four-bar in relative coordinates (docs/scenes.md §1, docs/methods.md §4.6).

mod common;
use common::*;
use flexmbd_core::Formulation;

#[test]
fn rigid_four_bar_has_five_coordinates_and_reaches_the_reference() {
    let scene = four_bar(0);
    let f = relative(&scene);
    assert_eq!(f.n_coordinates(), 5);
    assert_eq!(f.n_constraints(), 4);
    let (rows, phi) = run_relative(&scene, 1e-3, 10.0, 10);
    let last = rows.last().unwrap();
    let err = ((last[0] - 0.32846).powi(2) + (last[1] - 0.94452).powi(2)).sqrt();
    let e0 = rows[0][2];
    let drift = rows.iter().map(|r| (r[2] - e0).abs()).fold(0.0, f64::max);
    eprintln!(
        "B0(10 s) = ({:.6}, {:.6}), error {err:.2e} m; max ‖Φ‖ {phi:.2e}; energy {e0:.4} J, drift {drift:.2e} J",
        last[0], last[1]
    );
    assert!(err < 1e-4, "B0 error {err:e}");
    assert!(phi <= 1e-9, "constraints {phi:e}");
}
