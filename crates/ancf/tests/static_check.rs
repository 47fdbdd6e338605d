//! The static check of docs/methods.md §7.3 against the Exudyn ANCFCable example: a 2 m
//! cantilever under its own weight, 32 elements, static tip u_x = −0.5013058140308901 m.

use flexmbd_ancf::{Cable, CableSpec};
use flexmbd_core::Dim;

const EXUDYN_UX: f64 = -0.5013058140308901;

fn tip(dim: Dim, elements: usize, load_steps: usize) -> ([f64; 3], usize, usize, f64) {
    let mut c = Cable::new(&CableSpec::exudyn_cantilever(dim, elements)).unwrap();
    let r = c.solve_static(0.0, load_steps).unwrap();
    let q = c.initial_positions().clone();
    (
        c.tip_displacement(0.0, &q),
        r.load_steps,
        r.iterations,
        r.residual,
    )
}

/// The 32-element cantilever's tip under 10 load steps: its u_x matches Exudyn to 1e-9;
/// the tip displacement and the force residual.
fn tip_against_exudyn(dim: Dim) -> ([f64; 3], f64) {
    let (d, steps, its, res) = tip(dim, 32, 10);
    eprintln!(
        "{dim}: tip {d:?}, error {:.3e}, {steps} load steps, {its} iterations, residual {res:.2e}",
        d[0] - EXUDYN_UX
    );
    assert!((d[0] - EXUDYN_UX).abs() < 1e-9, "u_x = {}", d[0]);
    (d, res)
}

#[test]
fn planar_cantilever_matches_exudyn() {
    let (d, res) = tip_against_exudyn(Dim::Planar);
    assert!((d[1] + 1.23251).abs() < 1e-5, "u_y = {}", d[1]);
    assert!(res < 1e-12 * 1e6, "force residual {res:e} N");
}

#[test]
fn spatial_cantilever_matches_exudyn() {
    let (d, _) = tip_against_exudyn(Dim::Spatial);
    assert!(d[2].abs() < 1e-12);
}
