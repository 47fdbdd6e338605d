//! FNL1 / FNL2 elastic models (docs/methods.md §6.1–§6.2): strain-free rigid motion, FNL2
//! force = −∇U and tangent = Hessian, FNL1 tangent = −∂Q/∂y, K_Gk of bending modes.

use flexmbd_body::ElasticModel;
use flexmbd_core::Dim;
use flexmbd_fe::{BeamBodySpec, Dof, NodeDof, ReducedBody, reduce};
use flexmbd_stiffening::{Kind, Nonlinear};
use nalgebra::DMatrix;

/// The spin-up beam of docs/scenes.md §5 with `axial` = the nodes whose Ux is a static mode.
fn beam(dim: Dim, axial: &[usize], bending: usize) -> ReducedBody {
    beam_with(dim, axial, bending, 0)
}

/// As [`beam`], with `axial_normal` purely axial cantilever normal modes.
fn beam_with(dim: Dim, axial: &[usize], bending: usize, axial_normal: usize) -> ReducedBody {
    let pts = match dim {
        Dim::Planar => "[[0.0, 0.0], [10.0, 0.0]]",
        Dim::Spatial => "[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]",
    };
    let text = format!(
        "(dim: {dim:?}, material: (young_modulus: 7e10, density: 3000.0, shear_modulus: Some(3.5e10)),
          section: General(area: 4e-4, iy: 2e-7, iz: 2e-7, torsion_j: 4e-7),
          geometry: (points: {pts}, elements_per_segment: 20),
          frame: Clamped(node: 0), boundary: [], normal_modes: {bending}, axial_modes: {axial_normal})"
    );
    let mut spec = BeamBodySpec::from_ron_str(&text, "test").unwrap();
    spec.boundary = axial
        .iter()
        .map(|&node| NodeDof { node, dof: Dof::Ux })
        .collect();
    reduce(&spec).unwrap()
}

/// A deformation of realistic size: axial static modes ~1 mm, bending modal amplitudes ~0.3.
fn sample_y(body: &ReducedBody, seed: u64) -> Vec<f64> {
    let n = body.n_modes();
    let ns = body.inventory.static_modes.len();
    let mut s = seed;
    (0..n)
        .map(|i| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let r = ((s >> 11) as f64 / (1u64 << 53) as f64) - 0.5;
            if i < ns { 2e-3 * r } else { 0.6 * r }
        })
        .collect()
}

fn forces(m: &dyn ElasticModel, y: &[f64]) -> Vec<f64> {
    let mut f = vec![0.0; y.len()];
    m.forces(y, &vec![0.0; y.len()], &mut f);
    f
}

fn tangent(m: &dyn ElasticModel, y: &[f64]) -> DMatrix<f64> {
    let n = y.len();
    let mut k = DMatrix::zeros(n, n);
    m.add_tangents(y, &vec![0.0; n], 1.0, 0.0, k.view_mut((0, 0), (n, n)));
    k
}

/// The central-difference step of coordinate `j` at `y` (scaled to it) and y ± that step.
fn perturbed(y: &[f64], j: usize) -> (f64, Vec<f64>, Vec<f64>) {
    let h = 1e-6 * y[j].abs().max(1e-4);
    let (mut yp, mut ym) = (y.to_vec(), y.to_vec());
    yp[j] += h;
    ym[j] -= h;
    (h, yp, ym)
}

/// −∂Q/∂y by central differences, step scaled per coordinate.
fn fd_tangent(m: &dyn ElasticModel, y: &[f64]) -> DMatrix<f64> {
    let n = y.len();
    let mut k = DMatrix::zeros(n, n);
    for j in 0..n {
        let (h, yp, ym) = perturbed(y, j);
        let (fp, fm) = (forces(m, &yp), forces(m, &ym));
        for i in 0..n {
            k[(i, j)] = -(fp[i] - fm[i]) / (2.0 * h);
        }
    }
    k
}

/// The largest entry of the body's geometric stiffness matrices K_G.
fn largest_k_g(body: &ReducedBody) -> f64 {
    body.stiffening
        .k_g
        .iter()
        .map(|m| m.amax())
        .fold(0.0, f64::max)
}

fn rel_err(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).amax() / b.amax()
}

fn bodies() -> Vec<ReducedBody> {
    let all: Vec<usize> = (1..=20).collect();
    vec![
        beam_with(Dim::Planar, &[], 4, 2),
        beam_with(Dim::Spatial, &[], 8, 2),
        beam(Dim::Planar, &[10, 20], 4),
        beam(Dim::Planar, &all, 4),
        beam(Dim::Spatial, &[10, 20], 8),
        beam(Dim::Spatial, &all, 8),
    ]
}

#[test]
fn undeformed_and_rigidly_moving_body_is_strain_free() {
    // The elastic force depends on (y, ẏ) only; a rigid motion of the body is a motion
    // of its frame with y = 0 (and ẏ = 0 after it). Without damping every model gives
    // Q = 0 there, whatever ẏ, and the linear part of the tangent is K_L.
    for body in bodies() {
        let n = body.n_modes();
        for kind in [Kind::Fnl1, Kind::Fnl2] {
            let m = Nonlinear::new(kind, &body);
            let mut f = vec![1.0; n];
            m.forces(&vec![0.0; n], &vec![0.3; n], &mut f);
            assert!(f.iter().all(|v| *v == 0.0), "{kind:?}: {f:?}");
            let k = tangent(&m, &vec![0.0; n]);
            assert!((&k - &body.k_ff).amax() <= 1e-12 * body.k_ff.amax());
            assert_eq!(m.strain_energy(&vec![0.0; n]), 0.0);
        }
    }
}

#[test]
fn fnl2_force_is_minus_energy_gradient_and_tangent_is_hessian() {
    for body in bodies() {
        let m = Nonlinear::fnl2(&body);
        for seed in 1..4 {
            let y = sample_y(&body, seed);
            let n = y.len();
            let f = forces(&m, &y);
            let mut worst: f64 = 0.0;
            let fmax = f.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
            for j in 0..n {
                let (h, yp, ym) = perturbed(&y, j);
                let g = (m.strain_energy(&yp) - m.strain_energy(&ym)) / (2.0 * h);
                worst = worst.max((f[j] + g).abs());
            }
            assert!(worst <= 1e-6 * fmax, "force vs −∇U: {worst:e} of {fmax:e}");
            let k = tangent(&m, &y);
            let e = rel_err(&k, &fd_tangent(&m, &y));
            assert!(e < 1e-6, "Hessian: {e:e}");
            assert!((&k - k.transpose()).amax() <= 1e-12 * k.amax());
            // The nonlinear terms matter at this amplitude (not a trivially linear check).
            assert!(rel_err(&k, &body.k_ff) > 1e-3);
        }
    }
}

#[test]
fn fnl1_tangent_is_minus_force_jacobian() {
    for body in bodies() {
        let m = Nonlinear::fnl1(&body);
        assert!(!m.is_symmetric() && !m.is_linear());
        for seed in 1..4 {
            let y = sample_y(&body, seed);
            let k = tangent(&m, &y);
            let e = rel_err(&k, &fd_tangent(&m, &y));
            assert!(e < 1e-6, "FNL1 tangent: {e:e}");
            assert!(
                (&k - k.transpose()).amax() > 1e-6 * k.amax(),
                "not symmetric"
            );
            // FNL1 = −(K_L + K_G(y)) y.
            let mut kg = body.k_ff.clone();
            for (k, kgk) in body.stiffening.k_g.iter().enumerate() {
                kg += kgk * y[k];
            }
            let expect = -(kg * nalgebra::DVector::from_column_slice(&y));
            let f = forces(&m, &y);
            for i in 0..y.len() {
                assert!((f[i] - expect[i]).abs() <= 1e-10 * expect.amax());
            }
        }
    }
}

#[test]
fn k_g_vanishes_for_bending_modes_of_a_straight_beam() {
    for body in bodies() {
        let n = body.n_modes();
        let kmax = largest_k_g(&body);
        assert!(kmax > 0.0);
        let mut n_bending = 0;
        for k in 0..n {
            // Axial rows of mode k (every node's Ux).
            let amax = |row: usize| {
                body.nodes
                    .iter()
                    .map(|nd| nd.translation[(row, k)].abs())
                    .fold(0.0, f64::max)
            };
            let (axial, transverse) = (amax(0), amax(1).max(amax(2)));
            if axial <= 1e-10 * transverse {
                n_bending += 1;
                assert!(body.stiffening.k_g[k].amax() <= 1e-12 * kmax, "mode {k}");
            } else {
                assert!(
                    body.stiffening.k_g[k].amax() > 1e-6 * kmax,
                    "axial mode {k}"
                );
                // H (element means of G) lives on the bending modes only.
                for g in &body.stiffening.g_mean {
                    assert!(g.row(k).amax() <= 1e-10 * g.amax());
                }
            }
        }
        let expect = if body.dim == Dim::Planar { 4 } else { 8 };
        assert_eq!(n_bending, expect);
    }
}

#[test]
fn element_mean_h_matches_hand_value_for_one_element() {
    // One element, one bending static mode v(L) = 1 (θ free → interior): Ḡ = yᵀ K_σ y / L.
    let text = "(dim: Planar, material: (young_modulus: 7e10, density: 3000.0),
          section: General(area: 4e-4, iy: 2e-7, iz: 2e-7, torsion_j: 4e-7),
          geometry: (points: [[0.0, 0.0], [2.0, 0.0]], elements_per_segment: 1),
          frame: Clamped(node: 0), boundary: [(node: 1, dof: Uy)], normal_modes: 0)";
    let body = reduce(&BeamBodySpec::from_ron_str(text, "t").unwrap()).unwrap();
    // Static mode: v = 1, θ = 3/(2L) (K_ii⁻¹ K_ib of the cantilever); ∫v'² = 6/(5L).
    let l = 2.0;
    let g = body.stiffening.g_mean[0][(0, 0)];
    assert!((g - 6.0 / (5.0 * l) / l).abs() < 1e-12, "{g}");
    assert!((body.stiffening.h_weight[0] - 2.8e7 * l).abs() < 1e-6);
}

#[test]
fn axial_normal_modes_are_selected_after_the_bending_modes() {
    // docs/scenes.md §5: 4 bending + 2 axial cantilever modes. Derived frequencies: bending
    // 3.80, 23.8, 66.6, 130.6 rad/s; axial (2k − 1) π/(2L) √(EA/ρA) = 759, 2277 rad/s.
    let body = beam_with(Dim::Planar, &[], 4, 2);
    let w: Vec<f64> = body
        .inventory
        .normal_frequencies_hz
        .iter()
        .map(|f| f * 2.0 * std::f64::consts::PI)
        .collect();
    assert_eq!(w.len(), 6);
    for (got, want) in w.iter().zip([3.80, 23.8, 66.6, 130.6, 759.0, 2277.0]) {
        assert!((got / want - 1.0).abs() < 0.01, "{got} vs {want}");
    }
    // The two axial modes carry K_G, the bending ones do not.
    let kmax = largest_k_g(&body);
    for k in 0..6 {
        assert_eq!(
            body.stiffening.k_g[k].amax() > 1e-9 * kmax,
            k >= 4,
            "mode {k}"
        );
    }
}
