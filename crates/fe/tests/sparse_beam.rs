//! Beams of at least `SPARSE_FROM_DOFS` FE DOFs are reduced on sparse matrices (issue 25
//! item 3: no dense N × N matrix for a large built-in model): the same Craig–Bampton basis as
//! an independent dense reduction of the same matrices, the clamped–clamped and cantilever
//! frequencies of beam theory, a beam frame on the same route, and the refusals of what the
//! sparse route does not do.
//!
//! The dense reference is not `craig_bampton::reduce_matrices`: its eigen-solver factorises
//! M (A = L_M⁻¹ K L_M⁻ᵀ, `modal`), whose absolute error ε ‖A‖ ≈ ε ω²_max swamps the lowest
//! ω² of a mesh this fine (elements 2.5 mm long, 10 mm thick: ω²_max of the rotary inertia
//! ≈ 10¹⁹ rad²/s²; on this beam it returns ω₁² = 1.009e5 for 1.116e5, and negative ω² at
//! 300 elements). The reference here factorises K_ii instead, K_ii = L Lᵀ, and solves the
//! symmetric B = L⁻¹ M_ii L⁻ᵀ = U diag(μ) Uᵀ, ω² = 1/μ: the largest μ, the lowest ω², carry
//! an error of ε μ_max, i.e. to round-off relative (Parlett, *The Symmetric Eigenvalue
//! Problem*, 1998, §15.2).

mod common;

use common::rel;
use flexmbd_core::Dim;
use flexmbd_fe::modal::generalized_eigen;
use flexmbd_fe::{
    BeamBodySpec, DofSets, ModeSelection, SPARSE_FROM_DOFS, assembly::to_dense, preprocess,
};
use nalgebra::DMatrix;

/// The steel cantilever of models/cantilever_3d.ron (1 m, 10 × 10 mm) with `elements`
/// elements, its tip's six DOFs as boundary DOFs (static modes) and `modes` normal modes.
fn cantilever(elements: usize, modes: usize) -> BeamBodySpec {
    let text = format!(
        "(dim: Spatial, material: (young_modulus: 2.1e11, density: 7850.0, poisson_ratio: Some(0.3)),
          section: Rectangle(width: 0.01, height: 0.01),
          geometry: (points: [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], elements_per_segment: {elements}),
          frame: Clamped(node: 0),
          boundary: [(node: {elements}, dof: Ux), (node: {elements}, dof: Uy), (node: {elements}, dof: Uz),
                     (node: {elements}, dof: Rx), (node: {elements}, dof: Ry), (node: {elements}, dof: Rz)],
          normal_modes: {modes})"
    );
    BeamBodySpec::from_ron_str(&text, "cantilever").unwrap()
}

fn block(a: &DMatrix<f64>, rows: &[usize], cols: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(rows.len(), cols.len(), |i, j| a[(rows[i], cols[j])])
}

/// The dense reference (module docs): static modes −K_ii⁻¹ K_ib and the `n_d` lowest ω² of
/// (K_ii, M_ii) by the eigenvalues of L⁻¹ M_ii L⁻ᵀ, K_ii = L Lᵀ.
fn dense_reference(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    sets: &DofSets,
    n_d: usize,
) -> (DMatrix<f64>, Vec<f64>) {
    let (i, b) = (&sets.i, &sets.b);
    let chol = block(k, i, i).cholesky().expect("K_ii positive definite");
    let static_interior = -chol.solve(&block(k, i, b));
    let l = chol.l();
    let mut y = block(m, i, i);
    assert!(l.solve_lower_triangular_mut(&mut y));
    let mut b_mat = y.transpose();
    assert!(l.solve_lower_triangular_mut(&mut b_mat));
    let b_mat = (&b_mat + b_mat.transpose()) * 0.5;
    let mut mu: Vec<f64> = b_mat.symmetric_eigenvalues().iter().copied().collect();
    mu.sort_by(|a, b| b.total_cmp(a));
    (static_interior, mu[..n_d].iter().map(|m| 1.0 / m).collect())
}

/// Round-off bound of a computed ω² of the interior mode `x` (N rows, zero off the interior):
/// ε |x|ᵀ|K||x| / xᵀKx, the size of the terms that cancel in the Rayleigh quotient against
/// its value (Parlett 1998, §4.8; for this beam 10⁹ ε: two correct solvers, the sparse and
/// the dense reference, then differ by ~10⁻⁹, which no tolerance below this bound can
/// demand).
fn rounding_bound(k: &DMatrix<f64>, x: nalgebra::DVectorView<f64>) -> f64 {
    let xabs = x.abs();
    let energy = (x.transpose() * k * x)[(0, 0)];
    let terms = (xabs.transpose() * k.abs() * xabs)[(0, 0)];
    f64::EPSILON * terms / energy
}

/// The ω² of `p`'s reduction against the reference's: each within 10⁻⁹ relative, or within
/// its rounding bound where that is larger.
fn assert_omega_sq(p: &flexmbd_fe::Preprocessed, k: &DMatrix<f64>, reference: &[f64]) {
    let n_s = p.reduction.n_static();
    for (j, (a, b)) in p.reduction.omega_sq.iter().zip(reference).enumerate() {
        let bound = rounding_bound(k, p.reduction.x.column(n_s + j));
        println!(
            "ω² {a} against {b}: {:.2e}, rounding bound {bound:.2e}",
            rel(*a, *b)
        );
        assert!(rel(*a, *b) < 1e-9_f64.max(bound), "ω² {a} against {b}");
    }
}

/// The static modes of `p` against the reference's, column by column: within 10⁻⁹ of the
/// column's largest entry, or within its rounding bound where that is larger: the forward
/// error of a backward-stable solve of K_ii x = b is at most about ε ‖ |K_ii⁻¹| |K_ii| |x| ‖∞
/// / ‖x‖∞ (Skeel's condition number; Higham, *Accuracy and Stability of Numerical
/// Algorithms*, 2nd ed., 2002, §7.2), 10⁷ ε for the tip's transverse static modes here.
fn assert_static_modes(p: &flexmbd_fe::Preprocessed, k: &DMatrix<f64>, reference: &DMatrix<f64>) {
    let i = &p.reduction.sets.i;
    let kii = block(k, i, i);
    let inverse = kii.clone().cholesky().unwrap().inverse();
    for c in 0..reference.ncols() {
        let ours = DMatrix::from_fn(i.len(), 1, |a, _| p.reduction.x[(i[a], c)]);
        let theirs = reference.columns(c, 1);
        let scale = theirs.amax();
        let skeel = (inverse.abs() * (kii.abs() * theirs.abs())).amax() / scale;
        let bound = f64::EPSILON * skeel;
        let d = (&ours - theirs).amax() / scale;
        println!("static mode {c}: {d:.2e} of its largest entry, rounding bound {bound:.2e}");
        assert!(d < 1e-9_f64.max(bound), "static mode {c}: {d:e}");
    }
}

/// 400 elements, 2 406 DOFs: ω² of the six fixed-interface modes to 10⁻⁹ relative and the
/// static modes to 10⁻⁹ of their largest entry against the dense reference; the spectrum of
/// (K_ff, M_ff) against the reference basis's.
#[test]
fn a_large_beam_is_reduced_sparsely_as_densely() {
    let spec = cantilever(400, 6);
    let p = preprocess(&spec).unwrap();
    assert!(p.k.rows() >= SPARSE_FROM_DOFS, "{} DOFs", p.k.rows());
    let (k, m) = (to_dense(&p.k), to_dense(&p.m));
    let sets = &p.reduction.sets;
    let (static_interior, omega_sq) = dense_reference(&k, &m, sets, 6);
    assert_omega_sq(&p, &k, &omega_sq);
    assert_static_modes(&p, &k, &static_interior);
    // The reduced spectrum: the sparse basis's (K_ff, M_ff) against the reference basis's
    // (the static modes replaced by the reference's).
    let mut x = p.reduction.x.clone();
    for (a, &row) in sets.i.iter().enumerate() {
        for c in 0..6 {
            x[(row, c)] = static_interior[(a, c)];
        }
    }
    let sym = |a: DMatrix<f64>| (&a + a.transpose()) * 0.5;
    let theirs = generalized_eigen(
        &sym(x.transpose() * &k * &x),
        &sym(x.transpose() * &m * &x),
        "dense basis",
    )
    .unwrap();
    let ours = generalized_eigen(&p.body.k_ff, &p.body.m_ff, "sparse").unwrap();
    for (j, (a, b)) in ours.omega_sq.iter().zip(&theirs.omega_sq).enumerate() {
        let u = &x * ours.vectors.column(j);
        let bound = rounding_bound(&k, u.column(0));
        println!(
            "reduced ω² {a} against {b}: {:.2e}, rounding bound {bound:.2e}",
            rel(*a, *b)
        );
        assert!(
            rel(*a, *b) < 1e-9_f64.max(bound),
            "reduced ω² {a} against {b}"
        );
    }
}

/// Clamped at both ends (the fixed-interface problem), the lowest ω is (β₁L)² √(EI/(ρA L⁴)),
/// β₁L = 4.730041 (Blevins 1979, table 8-1), twice (y and z bending of the square section),
/// to 10⁻⁴: the elements' own error is far below that at 400 elements, but their consistent
/// mass carries the section's rotary inertia, which Euler–Bernoulli theory omits and which
/// lowers ω by a share of order (β₁L)² (r/L)² / 2 ≈ 10⁻⁴ (r² = I/A). And with the tip's
/// static modes, the lowest frequency of (K_ff, M_ff) is the cantilever's,
/// (1.875104²/2π) √(EI/(ρA L⁴)) = 8.3598 Hz for E = 2.1e11 Pa, I = 1e-8/12 m⁴,
/// ρ = 7850 kg/m³, A = 1e-4 m², L = 1 m, to 10⁻⁴ (the six static and six normal modes span
/// it to about that).
#[test]
fn a_large_beam_has_the_clamped_and_cantilever_frequencies() {
    let body = flexmbd_fe::reduce(&cantilever(400, 6)).unwrap();
    let (ei, rho_a): (f64, f64) = (2.1e11 * 1e-8 / 12.0, 7850.0 * 1e-4);
    let omega = |beta_l: f64| beta_l.powi(2) * (ei / rho_a).sqrt();
    let clamped = omega(4.730_040_745).powi(2);
    let f = &body.inventory.normal_frequencies_hz;
    let clamped_hz = clamped.sqrt() / (2.0 * std::f64::consts::PI);
    for w in &f[..2] {
        println!("clamped–clamped {w} Hz against {clamped_hz} Hz");
        assert!(rel(*w, clamped_hz) < 1e-4, "{w} Hz against {clamped_hz} Hz");
    }
    let e = generalized_eigen(&body.k_ff, &body.m_ff, "cantilever").unwrap();
    let f1 = e.frequencies_hz()[0];
    let analytic = omega(1.875_104_069) / (2.0 * std::f64::consts::PI);
    println!("cantilever {f1} Hz against {analytic} Hz");
    assert!(
        (f1 / analytic - 1.0).abs() < 1e-4,
        "{f1} Hz against {analytic} Hz"
    );
}

/// A planar portal frame (two 1 m columns, a 1 m beam, clamped at one foot) of 2 403 DOFs
/// takes the sparse route and gives the same ω² as the dense reference.
#[test]
fn a_large_beam_frame_is_reduced_sparsely() {
    let per = 267; // 3 members × 267 elements: 802 nodes, 2 406 DOFs
    let text = format!(
        "(dim: Planar, material: (young_modulus: 2.1e11, density: 7850.0, poisson_ratio: Some(0.3)),
          section: Rectangle(width: 0.02, height: 0.02),
          geometry: (elements_per_segment: {per},
                     nodes: [(name: \"a\", position: [0.0, 0.0]), (name: \"b\", position: [0.0, 1.0]),
                             (name: \"c\", position: [1.0, 1.0]), (name: \"d\", position: [1.0, 0.0])],
                     members: [(from: \"a\", to: \"b\"), (from: \"b\", to: \"c\"), (from: \"c\", to: \"d\")]),
          frame: Clamped(node: 0),
          boundary: [(node: 3, dof: Ux), (node: 3, dof: Uy)],
          normal_modes: 4)"
    );
    let spec = BeamBodySpec::from_ron_str(&text, "portal").unwrap();
    let p = preprocess(&spec).unwrap();
    assert!(p.k.rows() >= SPARSE_FROM_DOFS, "{} DOFs", p.k.rows());
    let (k, m) = (to_dense(&p.k), to_dense(&p.m));
    let (static_interior, omega_sq) = dense_reference(&k, &m, &p.reduction.sets, 4);
    assert_omega_sq(&p, &k, &omega_sq);
    assert_static_modes(&p, &k, &static_interior);
    assert_eq!(p.body.stiffening.k_g.len(), p.body.modes.ncols());
}

/// What the sparse route does not do is refused, naming the field and the reason; one DOF
/// below the threshold the same spec is reduced densely as before.
#[test]
fn selections_that_need_every_mode_are_refused_on_the_sparse_route() {
    let mut spec = cantilever(400, 6);
    spec.mode_selection = ModeSelection::LoadRitz;
    let e = preprocess(&spec).unwrap_err().to_string();
    assert!(
        e.contains("mode_selection = LoadRitz")
            && e.contains("2406 FE DOFs")
            && e.contains("sparse"),
        "{e}"
    );
    let mut spec = cantilever(400, 6);
    spec.axial_modes = 1;
    let e = preprocess(&spec).unwrap_err().to_string();
    assert!(e.contains("axial_modes = 1") && e.contains("sparse"), "{e}");
    // 2D, 666 elements: 2 001 DOFs, sparse; 665: 1 998, dense, and LoadRitz is accepted.
    let planar = |elements| {
        let mut s = common::cantilever(Dim::Planar, common::square10(), elements, 2);
        s.mode_selection = ModeSelection::LoadRitz;
        s
    };
    assert!(preprocess(&planar(666)).is_err());
    assert!(preprocess(&planar(665)).is_ok());
}

/// The cap is memory: a beam above it is refused before anything is assembled, saying so.
#[test]
fn a_beam_above_the_cap_is_refused_for_memory() {
    let e = cantilever(200_000, 6).validate().unwrap_err().to_string();
    assert!(
        e.contains("1200006 FE DOFs")
            && e.contains("at most 1000000 FE DOFs are allowed, for memory"),
        "{e}"
    );
}
