//! The sparse shift-invert Lanczos eigen-solver against the dense solver and against beam
//! theory, on free-free hex8 boxes (`flexmbd_fe::solid_box`).

use flexmbd_fe::FeError;
use flexmbd_fe::assembly::to_dense;
use flexmbd_fe::modal::{Eigenpairs, generalized_eigen};
use flexmbd_fe::solid_box::SolidBox;
use flexmbd_fe::sparse_eigen::{SparseEigenOptions, lowest_modes, lowest_modes_with_stats};
use nalgebra::DMatrix;
use sprs::{CsMat, TriMat};

fn options() -> SparseEigenOptions {
    SparseEigenOptions::default()
}

/// Groups of indices whose ω² agree to 10⁻⁶ relative (or are all rigid), so that equal
/// eigenvalues are compared as subspaces.
fn clusters(omega_sq: &[f64], rigid_below: f64) -> Vec<Vec<usize>> {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, &w) in omega_sq.iter().enumerate() {
        let joins = groups.last().is_some_and(|g| {
            let prev = omega_sq[*g.last().unwrap()];
            (prev.abs() < rigid_below && w.abs() < rigid_below)
                || (w - prev).abs() <= 1e-6 * w.abs()
        });
        if joins {
            groups.last_mut().unwrap().push(i);
        } else {
            groups.push(vec![i]);
        }
    }
    groups
}

/// The box of the comparisons: 7 × 4 × 3 nodes, 252 DOFs, no two edge lengths equal.
fn small_box() -> SolidBox {
    SolidBox::steel([0.4, 0.23, 0.11], [6, 3, 2])
}

/// Sparse against dense on the same matrices: ω² to 10⁻⁹ relative (elastic), the rigid
/// ones both ≤ 10⁻⁸ of the first elastic, and each sparse vector lies in the dense
/// eigenspace of its eigenvalue (|projection| = 1 to 10⁻⁸), M-orthonormal.
#[test]
fn agrees_with_the_dense_solver_on_a_free_free_box() {
    let b = small_box();
    let (k, m) = b.assemble().unwrap();
    let n_modes = 20;
    let (sparse, stats) = lowest_modes_with_stats(&k, &m, n_modes, &options()).unwrap();
    assert!(
        !stats.dense,
        "{} DOFs must take the sparse route",
        b.n_dofs()
    );
    let (kd, md) = (to_dense(&k), to_dense(&m));
    let dense = generalized_eigen(&kd, &md, "box")
        .unwrap()
        .truncate(n_modes);
    let first_elastic = dense.omega_sq[6];
    for i in 0..6 {
        assert!(
            sparse.omega_sq[i].abs() <= 1e-8 * first_elastic,
            "rigid {i}: {}",
            sparse.omega_sq[i]
        );
        assert!(dense.omega_sq[i].abs() <= 1e-8 * first_elastic);
    }
    for i in 6..n_modes {
        let rel = (sparse.omega_sq[i] - dense.omega_sq[i]).abs() / dense.omega_sq[i];
        assert!(
            rel <= 1e-9,
            "mode {i}: {} vs {} ({rel:e})",
            sparse.omega_sq[i],
            dense.omega_sq[i]
        );
    }
    let gram = sparse.vectors.transpose() * &md * &sparse.vectors;
    assert!((gram - DMatrix::identity(n_modes, n_modes)).amax() < 1e-10);
    let cross = sparse.vectors.transpose() * &md * &dense.vectors;
    for group in clusters(&dense.omega_sq, 1e-8 * first_elastic) {
        for &i in &group {
            let projection: f64 = group
                .iter()
                .map(|&j| cross[(i, j)].powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(
                (projection - 1.0).abs() < 1e-8,
                "mode {i} in {group:?}: {projection}"
            );
        }
    }
    assert!(
        stats.residuals.iter().all(|&r| r <= 1e-10),
        "{:?}",
        stats.residuals
    );
    assert_eq!(stats.factorisations, 1);
}

/// A free-free solid has exactly six rigid-body modes: six ω² at most 10⁻⁸ of the first
/// elastic one, then elastic ones well above.
#[test]
fn a_free_free_box_has_six_rigid_body_modes() {
    let b = SolidBox::steel([1.0, 0.5, 0.3], [12, 6, 4]);
    let (k, m) = b.assemble().unwrap();
    let (pairs, stats) = lowest_modes_with_stats(&k, &m, 12, &options()).unwrap();
    let first_elastic = pairs.omega_sq[6];
    assert!(first_elastic > 0.0);
    let rigid = pairs
        .omega_sq
        .iter()
        .filter(|w| w.abs() <= 1e-8 * first_elastic)
        .count();
    assert_eq!(rigid, 6, "{:?}", pairs.omega_sq);
    assert!(pairs.omega_sq.windows(2).all(|w| w[0] <= w[1]));
    assert!(
        stats.residuals.iter().all(|&r| r <= 1e-10),
        "{:?}",
        stats.residuals
    );
}

/// Free-free Euler–Bernoulli bar, first bending mode: ω = (β₁L)² √(EI / (ρ A L⁴)),
/// β₁L = 4.730040745 (Blevins, *Formulas for Natural Frequency and Mode Shape*, 1979,
/// table 8-1).
fn euler_bernoulli_free_free(b: &SolidBox) -> f64 {
    let [l, w, h] = b.lengths;
    let (area, inertia) = (w * h, w * h.powi(3) / 12.0);
    4.730040745_f64.powi(2) * (b.young * inertia / (b.density * area * l.powi(4))).sqrt()
}

/// A slender free-free bar (1 m × 25 mm × 25 mm, L/h = 40) meshed with 1, 2 and 4 cubic
/// bricks through the section. The fully integrated hex8 locks in bending, so its first
/// bending frequency lies above the beam's and falls as O(h²) under refinement; the limit,
/// extrapolated from the two finer meshes, lies within 0.5 % of Timoshenko's, which for this
/// slenderness is below Euler–Bernoulli's by about 0.24 % (shear and rotary inertia:
/// ½ (β₁ r)² (1 + E / κG) with r² = h²/12, κ = 0.85).
#[test]
fn a_bars_bending_frequency_converges_to_beam_theory() {
    let mut frequencies = Vec::new();
    let mut reference = 0.0;
    for through in [1, 2, 4] {
        let b = SolidBox::steel([1.0, 0.025, 0.025], [40 * through, through, through]);
        let (k, m) = b.assemble().unwrap();
        let pairs = lowest_modes(&k, &m, 8, &options()).unwrap();
        // Modes 7 and 8: bending in y and z (square section, equal).
        let (w7, w8) = (pairs.omega_sq[6], pairs.omega_sq[7]);
        assert!((w7 - w8).abs() <= 1e-8 * w7, "{w7} {w8}");
        frequencies.push(w7.sqrt());
        reference = euler_bernoulli_free_free(&b);
    }
    let timoshenko = reference * (1.0 - 0.0024);
    let ratios: Vec<f64> = frequencies.iter().map(|f| f / timoshenko).collect();
    assert!(
        ratios.windows(2).all(|r| r[0] > r[1] && r[1] > 1.0),
        "{ratios:?}"
    );
    let order = ((ratios[0] - ratios[1]) / (ratios[1] - ratios[2])).log2();
    assert!(
        (1.5..2.5).contains(&order),
        "observed order {order}, ratios {ratios:?}"
    );
    let extrapolated = ratios[2] - (ratios[1] - ratios[2]) / (2f64.powf(order) - 1.0);
    assert!(
        (extrapolated - 1.0).abs() < 5e-3,
        "extrapolated {extrapolated}, ratios {ratios:?}"
    );
}

/// Two runs give the same bits.
#[test]
fn runs_are_bitwise_reproducible() {
    let b = SolidBox::steel([0.5, 0.3, 0.2], [8, 5, 3]);
    let (k, m) = b.assemble().unwrap();
    let first = lowest_modes(&k, &m, 15, &options()).unwrap();
    let second = lowest_modes(&k, &m, 15, &options()).unwrap();
    let bits = |p: &Eigenpairs| -> Vec<u64> {
        p.omega_sq
            .iter()
            .chain(p.vectors.iter())
            .map(|v| v.to_bits())
            .collect()
    };
    assert_eq!(bits(&first), bits(&second));
}

/// A small model (below twice the basis) is solved densely, with the same contract.
#[test]
fn a_tiny_model_is_solved_densely() {
    let b = SolidBox::steel([0.2, 0.1, 0.1], [2, 1, 1]);
    let (k, m) = b.assemble().unwrap();
    let (pairs, stats) = lowest_modes_with_stats(&k, &m, 10, &options()).unwrap();
    assert!(stats.dense);
    assert_eq!(pairs.omega_sq.len(), 10);
    assert_eq!(pairs.vectors.shape(), (b.n_dofs(), 10));
}

fn diagonal(values: &[f64]) -> CsMat<f64> {
    let mut t = TriMat::new((values.len(), values.len()));
    for (i, &v) in values.iter().enumerate() {
        t.add_triplet(i, i, v);
    }
    t.to_csc()
}

#[test]
fn refuses_bad_input_with_clear_errors() {
    let b = small_box();
    let (k, m) = b.assemble().unwrap();
    let n = b.n_dofs();
    let smaller = diagonal(&vec![1.0; n - 3]);
    assert!(matches!(
        lowest_modes(&k, &smaller, 5, &options()),
        Err(FeError::Dimension { .. })
    ));
    assert!(matches!(
        lowest_modes(&k, &m, n + 1, &options()),
        Err(FeError::TooManyModes { .. })
    ));
    // M with a negative diagonal entry.
    let mut bad_m = diagonal(&vec![1.0; n]);
    bad_m.data_mut()[7] = -1.0;
    let err = lowest_modes(&k, &bad_m, 5, &options()).unwrap_err();
    assert!(
        matches!(err, FeError::NotPositiveDefinite { pivot: 7, .. }),
        "{err}"
    );
    // A non-symmetric K.
    let mut t = TriMat::new((n, n));
    for (v, (r, c)) in k.iter() {
        t.add_triplet(r, c, if (r, c) == (0, 1) { v + 1.0 } else { *v });
    }
    let asym: CsMat<f64> = t.to_csc();
    let err = lowest_modes(&asym, &m, 5, &options()).unwrap_err();
    assert!(matches!(err, FeError::NotSymmetric { .. }), "{err}");
    // A shift above the lowest eigenvalue: K − σM indefinite, reported with σ.
    let above = SparseEigenOptions {
        shift: Some(1e12),
        ..options()
    };
    let err = lowest_modes(&k, &m, 5, &above).unwrap_err();
    assert!(
        matches!(err, FeError::ShiftedNotPositiveDefinite { shift, .. } if shift == 1e12),
        "{err}"
    );
    assert!(err.to_string().contains("1e12"), "{err}");
    // No restarts allowed and a tolerance out of reach in one cycle.
    let bounded = SparseEigenOptions {
        max_restarts: 0,
        basis_size: Some(32),
        tol: 1e-15,
        ..options()
    };
    let err = lowest_modes(&k, &m, 20, &bounded).unwrap_err();
    assert!(
        matches!(err, FeError::SparseEigenNoConvergence { .. }),
        "{err}"
    );
    // Non-finite values.
    let mut nan_k = k.clone();
    nan_k.data_mut()[0] = f64::NAN;
    assert!(matches!(
        lowest_modes(&nan_k, &m, 5, &options()),
        Err(FeError::NotSymmetric { .. })
    ));
}

/// A lumped (diagonal) mass: K − σM merges two different patterns. The sparse solver still
/// agrees with the dense one, and CSR storage of the same matrices gives the same bits.
#[test]
fn a_lumped_mass_and_csr_storage() {
    let b = small_box();
    let (k, m) = b.assemble().unwrap();
    let row_sums: Vec<f64> = (0..b.n_dofs())
        .map(|j| m.outer_view(j).unwrap().iter().map(|(_, v)| v).sum())
        .collect();
    let lumped = diagonal(&row_sums);
    let sparse = lowest_modes(&k, &lumped, 12, &options()).unwrap();
    let dense = generalized_eigen(&to_dense(&k), &to_dense(&lumped), "lumped box")
        .unwrap()
        .truncate(12);
    for i in 6..12 {
        let rel = (sparse.omega_sq[i] - dense.omega_sq[i]).abs() / dense.omega_sq[i];
        assert!(rel <= 1e-9, "mode {i}: {rel:e}");
    }
    let csr = lowest_modes(&k.to_csr(), &lumped.to_csr(), 12, &options()).unwrap();
    assert_eq!(csr, sparse);
}
