//! The dense eigen-solver on fine beam meshes (`modal::generalized_eigen`): a 1 m steel
//! cantilever of 10 × 10 mm keeps its lowest frequencies as its mesh is refined. The mass
//! factor alone gave 10.67 Hz for the first bending pair at 50 elements and 184 Hz at 200
//! (M's rotary entries make it ill conditioned); the backward-error check and the
//! shift-invert solve give the converged value at every mesh.
//!
//! Reference: the Euler–Bernoulli cantilever, f = (β L)² / (2π L²) √(EI / ρA) with
//! β₁L = 1.875104, β₂L = 4.694091: 8.355166 and 52.360931 Hz for E = 2.1e11 Pa,
//! I = 1e-8 / 12 m⁴, ρ = 7850 kg/m³, A = 1e-4 m². The elements' consistent mass carries
//! the rotary inertia ρI, which lowers each by a part growing as (βr)² (Rayleigh beam,
//! r² = I/A = 8.3e-6 m²): the FE values sit 1.9e-5 and 1.35e-4 below, bounded here by 3e-5
//! and 2e-4 (the first bound times (β₂/β₁)² = 6.3, rounded up).

use flexmbd_fe::BeamBodySpec;

/// The four lowest frequencies (Hz) of the cantilever with `elements` elements: the two
/// first bending modes (y, z) and the two second ones.
fn frequencies(elements: usize) -> Vec<f64> {
    let text = format!(
        "(dim: Spatial, material: (young_modulus: 2.1e11, density: 7850.0, poisson_ratio: Some(0.3)),
          section: Rectangle(width: 0.01, height: 0.01),
          geometry: (points: [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], elements_per_segment: {elements}),
          frame: Clamped(node: 0),
          normal_modes: 4)"
    );
    let body =
        flexmbd_fe::reduce(&BeamBodySpec::from_ron_str(&text, "cantilever").unwrap()).unwrap();
    (0..4)
        .map(|j| (body.k_ff[(j, j)] / body.m_ff[(j, j)]).sqrt() / std::f64::consts::TAU)
        .collect()
}

#[test]
fn a_fine_cantilever_keeps_its_lowest_frequencies() {
    // The mesh converges: the second bending pair moves by 2e-6 from 20 to 50 elements, by
    // less than 1e-7 beyond.
    let coarse = frequencies(20);
    for elements in [50, 100, 200] {
        let fine = frequencies(elements);
        eprintln!("{elements} elements: {fine:?}");
        for (j, (f, c)) in fine.iter().zip(&coarse).enumerate() {
            assert!(
                ((f - c) / c).abs() < 1e-5,
                "{elements} elements, mode {j}: {f} Hz against {c} Hz at 20 elements"
            );
            let (analytic, bound) = if j < 2 {
                (8.355166, 3e-5)
            } else {
                (52.360931, 2e-4)
            };
            assert!(
                ((f - analytic) / analytic).abs() < bound,
                "{elements} elements, mode {j}: {f} Hz against {analytic} Hz"
            );
        }
    }
}
