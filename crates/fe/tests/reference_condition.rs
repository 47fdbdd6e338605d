//! The Buckens reference condition (`flexmbd_fe::reference`): the first-order coupling
//! integrals vanish, the basis spans the interface-fixed one's deformations modulo rigid
//! motion, and the free-free frequencies it implies are the interface-fixed floating body's.

use flexmbd_core::Dim;
use flexmbd_fe::{Preprocessed, ReferenceCondition, preprocess, reference};
use nalgebra::DMatrix;

/// A bent steel beam (two segments, so no symmetry hides a term), static modes at the far
/// end, `normal` fixed-interface modes, frame clamped at node 0.
fn bent_beam(dim: Dim, normal: usize, reference: ReferenceCondition) -> Preprocessed {
    let (points, section, boundary) = match dim {
        Dim::Planar => (
            "[[0.0, 0.0], [0.6, 0.0], [0.9, 0.4]]",
            "Rectangle(width: 0.01, height: 0.02)",
            "[(node: 12, dof: Ux), (node: 12, dof: Uy)]",
        ),
        Dim::Spatial => (
            "[[0.0, 0.0, 0.0], [0.6, 0.0, 0.0], [0.9, 0.4, 0.2]]",
            "Rectangle(width: 0.01, height: 0.02)",
            "[(node: 12, dof: Ux), (node: 12, dof: Uy), (node: 12, dof: Uz)]",
        ),
    };
    let text = format!(
        "(dim: {dim:?}, material: (young_modulus: 2.1e11, density: 7850.0, poisson_ratio: Some(0.3)), \
         section: {section}, geometry: (points: {points}, elements_per_segment: 6), \
         frame: Clamped(node: 0), reference: {}, boundary: {boundary}, normal_modes: {normal})",
        reference.name()
    );
    let spec = flexmbd_fe::BeamBodySpec::from_ron_str(&text, "bent beam").unwrap();
    preprocess(&spec).unwrap()
}

fn max_abs(m: &DMatrix<f64>) -> f64 {
    m.iter().fold(0.0, |a, v| a.max(v.abs()))
}

/// ∫ r̄_u × X dm from the shape integrals: (c, :) = Sᵃ_b − Sᵇ_a, (a, b, c) cyclic.
fn rotational_coupling(si: &flexmbd_fe::ShapeIntegrals) -> DMatrix<f64> {
    let n = si.s.ncols();
    DMatrix::from_fn(3, n, |c, j| {
        let (a, b) = ((c + 1) % 3, (c + 2) % 3);
        si.s_a[a][(b, j)] - si.s_a[b][(a, j)]
    })
}

#[test]
fn buckens_makes_the_first_order_coupling_integrals_vanish() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let fixed = bent_beam(dim, 4, ReferenceCondition::InterfaceFixed);
        let buckens = bent_beam(dim, 4, ReferenceCondition::Buckens);
        let (m, len) = (fixed.body.mass(), 1.0);
        // Scale of a coupling entry: m · max |X|.
        let scale = m * max_abs(&buckens.body.modes);
        let si_f = &fixed.body.shape_integrals;
        let si_b = &buckens.body.shape_integrals;
        // Interface-fixed: both couplings are of the order of the scale (the test can fail).
        assert!(max_abs(&si_f.s) > 1e-2 * scale, "{dim}: S fixed");
        assert!(
            max_abs(&rotational_coupling(si_f)) > 1e-2 * scale * len,
            "{dim}: C fixed"
        );
        // Buckens: S = 0 and the skew part of Sᵃ (∫ r̄ × X dm) = 0 to round-off.
        let s = max_abs(&si_b.s) / scale;
        let c = max_abs(&rotational_coupling(si_b)) / (scale * len);
        assert!(s < 1e-13, "{dim}: S / scale = {s:e}");
        assert!(c < 1e-13, "{dim}: (∫ r̄ × X dm) / scale = {c:e}");
        // Rᵀ M X on the FE model itself.
        let r = reference::rigid_modes(&buckens.mesh);
        let mx = flexmbd_fe::sparse_reduction::sparse_times_dense(&buckens.m, &buckens.body.modes);
        let rmx = max_abs(&(r.transpose() * mx)) / scale;
        assert!(rmx < 1e-13, "{dim}: RᵀMX / scale = {rmx:e}");
        // The frame node now moves with the modes.
        assert!(max_abs(&buckens.body.nodes[0].translation) > 1e-3 * max_abs(&buckens.body.modes));
        assert_eq!(
            buckens.body.inventory.reference,
            ReferenceCondition::Buckens
        );
    }
}

#[test]
fn buckens_spans_the_same_deformations_modulo_rigid_motion() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let fixed = bent_beam(dim, 5, ReferenceCondition::InterfaceFixed);
        let buckens = bent_beam(dim, 5, ReferenceCondition::Buckens);
        // X_B − X_I is a rigid motion: its least-squares residual on R vanishes.
        let r = reference::rigid_modes(&fixed.mesh);
        let d = &buckens.body.modes - &fixed.body.modes;
        let coef = (r.transpose() * &r)
            .cholesky()
            .unwrap()
            .solve(&(r.transpose() * &d));
        let residual = max_abs(&(&d - &r * coef)) / max_abs(&fixed.body.modes);
        assert!(residual < 1e-13, "{dim}: residual {residual:e}");
        assert!(
            max_abs(&d) > 1e-3 * max_abs(&fixed.body.modes),
            "{dim}: moved"
        );
        // The strain energy of every deformation is the same: K_ff equal.
        let dk = max_abs(&(&buckens.body.k_ff - &fixed.body.k_ff)) / max_abs(&fixed.body.k_ff);
        assert!(dk < 1e-12, "{dim}: K_ff {dk:e}");
    }
}

/// The elastic eigenvalues ω² of K x = ω² M x (M SPD), ascending.
fn eigenvalues(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Vec<f64> {
    let l = m.clone().cholesky().unwrap().l();
    let li = l.clone().try_inverse().unwrap();
    let a = &li * k * li.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let mut w: Vec<f64> = a.symmetric_eigen().eigenvalues.iter().copied().collect();
    w.sort_by(f64::total_cmp);
    w
}

/// The free-floating body's linearised mass and stiffness in (rigid, modal) coordinates:
/// M = [RᵀMR RᵀMX; XᵀMR XᵀMX], K = diag(0, K_ff).
fn floating(p: &Preprocessed) -> (DMatrix<f64>, DMatrix<f64>) {
    let r = reference::rigid_modes(&p.mesh);
    let x = &p.body.modes;
    let basis = DMatrix::from_fn(r.nrows(), r.ncols() + x.ncols(), |i, j| {
        if j < r.ncols() {
            r[(i, j)]
        } else {
            x[(i, j - r.ncols())]
        }
    });
    let mb = flexmbd_fe::sparse_reduction::sparse_times_dense(&p.m, &basis);
    let m = basis.transpose() * mb;
    let nr = r.ncols();
    let mut k = DMatrix::zeros(m.nrows(), m.ncols());
    k.view_mut((nr, nr), (x.ncols(), x.ncols()))
        .copy_from(&p.body.k_ff);
    (k, m)
}

#[test]
fn buckens_modal_matrices_give_the_free_free_frequencies() {
    // Buckens: M̄ is block-diagonal at rest, so (K_ff, M_ff) alone give the free-floating
    // body's elastic frequencies, which the interface-fixed basis gives only with its
    // rigid–modal coupling; both are the Rayleigh–Ritz values on the same space.
    for dim in [Dim::Planar, Dim::Spatial] {
        let fixed = bent_beam(dim, 6, ReferenceCondition::InterfaceFixed);
        let buckens = bent_beam(dim, 6, ReferenceCondition::Buckens);
        let w_b = eigenvalues(&buckens.body.k_ff, &buckens.body.m_ff);
        let (k, m) = floating(&fixed);
        let nr = dim.n_rigid();
        // The floating model's nr rigid eigenvalues are ≈ 0 (K singular): drop them.
        let shifted = eigenvalues(&(&k + &m * 1.0), &m);
        let w_f: Vec<f64> = shifted[nr..].iter().map(|w| w - 1.0).collect();
        for (a, b) in w_b.iter().zip(&w_f) {
            assert!((a - b).abs() < 1e-9 * a, "{dim}: {a} vs {b}");
        }
        // Without the coupling the interface-fixed (K_ff, M_ff) are the clamped body's,
        // far from these (the test can fail).
        let w_c = eigenvalues(&fixed.body.k_ff, &fixed.body.m_ff);
        assert!(
            (w_c[0] - w_b[0]).abs() > 0.1 * w_b[0],
            "{dim}: {} {}",
            w_c[0],
            w_b[0]
        );
    }
}

#[test]
fn free_free_beam_frequency_against_the_closed_form() {
    // A straight uniform beam, all-but-few modes: the first elastic free-free frequency
    // β₁L = 4.730041 (Euler–Bernoulli), ω = β₁² √(EI/(ρA)); 40 elements converge it to 1e-6.
    let text = "(dim: Planar, material: (young_modulus: 2.1e11, density: 7850.0, poisson_ratio: Some(0.3)), \
         section: Rectangle(width: 0.01, height: 0.01), geometry: (points: [[0.0, 0.0], [1.0, 0.0]], elements_per_segment: 40), \
         frame: Clamped(node: 0), reference: Buckens, normal_modes: 12)";
    let spec = flexmbd_fe::BeamBodySpec::from_ron_str(text, "free-free beam").unwrap();
    let p = preprocess(&spec).unwrap();
    let w = eigenvalues(&p.body.k_ff, &p.body.m_ff);
    let (e, rho, a, i): (f64, f64, f64, f64) = (2.1e11, 7850.0, 1e-4, 1e-8 / 12.0);
    let exact = 4.730_040_7_f64.powi(2) * (e * i / (rho * a)).sqrt();
    let got = w[0].sqrt();
    eprintln!("free-free ω₁: {got} rad/s, closed form {exact} rad/s");
    assert!((got - exact).abs() < 1e-4 * exact, "{got} vs {exact}");
}

/// Entries of a matrix above `tol`.
fn nonzero(m: &DMatrix<f64>, tol: f64) -> usize {
    m.iter().filter(|v| v.abs() > tol).count()
}

#[test]
fn spin_up_beam_shape_integrals_counted_per_condition() {
    // The 2D spin-up beam's body (models/spin_up_beam_2d.ron: 20 elements, 4 bending + 2
    // axial modes): how many shape-integral numbers each condition leaves non-zero
    // (above 1e-12 of the body's m · max|X| · L²).
    let text = |reference: &str| {
        format!(
            "(dim: Planar, material: (young_modulus: 7e10, density: 3000.0, poisson_ratio: None, shear_modulus: Some(3.5e10)), \
             section: General(area: 4e-4, iy: 2e-7, iz: 2e-7, torsion_j: 4e-7), \
             geometry: (points: [[0.0, 0.0], [10.0, 0.0]], elements_per_segment: 20), \
             frame: Clamped(node: 0), reference: {reference}, normal_modes: 4, axial_modes: 2)"
        )
    };
    let mut counts = Vec::new();
    for reference in ["InterfaceFixed", "Buckens"] {
        let spec =
            flexmbd_fe::BeamBodySpec::from_ron_str(&text(reference), "spin-up beam").unwrap();
        let p = preprocess(&spec).unwrap();
        let si = &p.body.shape_integrals;
        let tol = 1e-12 * p.body.mass() * max_abs(&p.body.modes) * 100.0;
        let s = nonzero(&si.s, tol);
        let skew = nonzero(&rotational_coupling(si), tol);
        let sa: usize = si.s_a.iter().map(|m| nonzero(m, tol)).sum();
        let sab: usize = si.s_ab.iter().flatten().map(|m| nonzero(m, tol)).sum();
        eprintln!("{reference}: S {s}, ∫ r̄ × X dm {skew}, Sᵃ {sa}, Sᵃᵇ {sab}");
        counts.push((s, skew));
    }
    // Interface-fixed: the bending modes have S_y and ∫ r̄ × X dm (z), the axial ones S_x:
    // 6 + 4 numbers; Buckens: none.
    assert_eq!(counts[0], (6, 4));
    assert_eq!(counts[1], (0, 0));
}
