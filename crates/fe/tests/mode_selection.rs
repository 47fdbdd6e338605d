//! Choosing the dynamic vectors (docs/methods.md §1.6): load-dependent Ritz vectors and
//! the participation ranking, against the lowest normal modes.

mod common;

use common::*;
use flexmbd_core::Dim;
use flexmbd_fe::assembly::to_dense;
use flexmbd_fe::craig_bampton::{InteriorBasis, lowest_normal_modes, reduce_with_basis};
use flexmbd_fe::inertia_loads::inertia_loads;
use flexmbd_fe::modal::generalized_eigen;
use flexmbd_fe::participation::{rank, static_response_shares};
use flexmbd_fe::ritz::load_ritz;
use flexmbd_fe::{BeamBodySpec, Dof, FeError, ModeSelection, NodeDof, preprocess};
use nalgebra::{DMatrix, DVector};

fn with(mut spec: BeamBodySpec, selection: ModeSelection) -> BeamBodySpec {
    spec.mode_selection = selection;
    spec
}

fn max_abs(a: &DMatrix<f64>) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// The reduced body's static response u = X K_ff⁻¹ Xᵀ f to the nodal load f.
fn reduced_deflection(spec: &BeamBodySpec, f: &DVector<f64>) -> DVector<f64> {
    let p = preprocess(spec).unwrap();
    let x = &p.body.modes;
    let q = p
        .body
        .k_ff
        .clone()
        .lu()
        .solve(&(x.transpose() * f))
        .unwrap();
    x * q
}

/// The full FE static response to f with the frame DOFs held (K_ii u_i = f_i).
fn full_deflection(spec: &BeamBodySpec, f: &DVector<f64>) -> DVector<f64> {
    let p = preprocess(spec).unwrap();
    let i = &p.reduction.sets.i;
    let k = to_dense(&p.k);
    let kii = DMatrix::from_fn(i.len(), i.len(), |a, b| k[(i[a], i[b])]);
    let fi = DVector::from_fn(i.len(), |a, _| f[i[a]]);
    let ui = kii.cholesky().unwrap().solve(&fi);
    let mut u = DVector::zeros(f.len());
    for (a, &dof) in i.iter().enumerate() {
        u[dof] = ui[a];
    }
    u
}

#[test]
fn ritz_basis_is_mass_orthonormal_and_stiffness_diagonal() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut spec = with(cantilever(dim, rect10x20(), 12, 6), ModeSelection::LoadRitz);
        spec.boundary = vec![NodeDof {
            node: 12,
            dof: Dof::Uy,
        }];
        let p = preprocess(&spec).unwrap();
        let (ns, n) = (1, 7);
        assert_eq!(p.body.n_modes(), n);
        let m_dd = p.body.m_ff.view((ns, ns), (n - ns, n - ns)).into_owned();
        let k_dd = p.body.k_ff.view((ns, ns), (n - ns, n - ns)).into_owned();
        let orth = max_abs(&(m_dd - DMatrix::identity(n - ns, n - ns)));
        let diag = DMatrix::from_diagonal(&DVector::from_vec(p.reduction.omega_sq.clone()));
        let kdiag = max_abs(&(&k_dd - &diag)) / max_abs(&diag);
        let coupling =
            max_abs(&p.body.k_ff.view((0, ns), (ns, n - ns)).into_owned()) / max_abs(&p.body.k_ff);
        println!(
            "{dim:?}: |M_dd - I| {orth:.2e}, |K_dd - diag ω²|/max {kdiag:.2e}, K_sd {coupling:.2e}"
        );
        assert!(orth < 1e-12 && kdiag < 1e-12 && coupling < 1e-12);
        assert!(p.reduction.omega_sq.windows(2).all(|w| w[0] <= w[1]));
    }
}

#[test]
fn ritz_basis_of_every_interior_dof_equals_all_normal_modes() {
    // 3 elements, clamped: 9 interior DOFs in 2D; 2 elements: 12 in 3D.
    for (dim, elements, interior) in [(Dim::Planar, 3, 9), (Dim::Spatial, 2, 12)] {
        let normal = cantilever(dim, rect10x20(), elements, interior);
        let ritz = with(normal.clone(), ModeSelection::LoadRitz);
        let (a, b) = (preprocess(&normal).unwrap(), preprocess(&ritz).unwrap());
        let worst = worst_relative_difference(&a.reduction.omega_sq, &b.reduction.omega_sq);
        println!("{dim:?}: {interior} Ritz vectors, worst relative ω² difference {worst:.2e}");
        assert_eq!(b.reduction.omega_sq.len(), interior);
        assert!(worst < 1e-9);
    }
}

#[test]
fn one_ritz_vector_reproduces_the_static_deflection_under_gravity() {
    // Gravity along body y on a 2D cantilever: the largest static response of the body's
    // load set, so the first Ritz vector; one normal mode misses the static correction.
    let normal = cantilever(Dim::Planar, square10(), 20, 1);
    let ritz = with(normal.clone(), ModeSelection::LoadRitz);
    let p = preprocess(&normal).unwrap();
    let g = p
        .mesh
        .rigid_field(&nalgebra::Vector3::y(), &nalgebra::Vector3::zeros());
    let f = to_dense(&p.m) * g * -9.81;
    let exact = full_deflection(&normal, &f);
    let tip = 20 * 3 + 1;
    let err = |u: &DVector<f64>| (u[tip] - exact[tip]).abs() / exact[tip].abs();
    let (e_ritz, e_normal) = (
        err(&reduced_deflection(&ritz, &f)),
        err(&reduced_deflection(&normal, &f)),
    );
    let field = (reduced_deflection(&ritz, &f) - &exact).amax() / exact.amax();
    println!(
        "tip deflection {:.6e} m: 1 Ritz vector rel. error {e_ritz:.2e} (whole field {field:.2e}), \
         1 normal mode {e_normal:.2e}",
        exact[tip]
    );
    assert!(e_ritz < 1e-10 && field < 1e-10);
    assert!(e_normal > 1e-3);
}

#[test]
fn one_ritz_vector_of_a_single_load_is_its_static_deflection() {
    // A point load at mid-span (node 5 of 10), through the Ritz builder itself.
    let spec = cantilever(Dim::Planar, square10(), 10, 0);
    let p = preprocess(&spec).unwrap();
    let sets = &p.reduction.sets;
    let mut f = DVector::zeros(p.mesh.n_dofs());
    f[5 * 3 + 1] = 100.0;
    let fi = DMatrix::from_fn(sets.i.len(), 1, |a, _| f[sets.i[a]]);
    let mut basis = None;
    let (k, m) = (to_dense(&p.k), to_dense(&p.m));
    reduce_with_basis(&k, &m, sets, "point load", "{}", |ip| {
        let b = load_ritz(ip, &fi, 1, &DMatrix::zeros(sets.i.len(), 0))?;
        basis = Some(b.clone());
        Ok(b)
    })
    .unwrap();
    let x: InteriorBasis = basis.unwrap();
    let v = x.vectors.column(0).into_owned();
    let exact = full_deflection(&spec, &f);
    let ui = DVector::from_fn(sets.i.len(), |a, _| exact[sets.i[a]]);
    // u = v (vᵀ f) / ω̃² with v M-normalised.
    let u = &v * (v.dot(&fi.column(0)) / x.omega_sq[0]);
    let e = (u - &ui).amax() / ui.amax();
    println!("one Ritz vector against K_ii⁻¹ f: {e:.2e}");
    assert!(e < 1e-10);
}

#[test]
fn axial_modes_rank_last_under_a_transverse_load() {
    let spec = cantilever(Dim::Planar, square10(), 10, 0);
    let p = preprocess(&spec).unwrap();
    let sets = &p.reduction.sets;
    let mut ranked = None;
    let (k, m) = (to_dense(&p.k), to_dense(&p.m));
    reduce_with_basis(&k, &m, sets, "transverse", "{}", |ip| {
        let all = generalized_eigen(ip.kii, ip.mii, "all").unwrap();
        // Load 1 of the body's set: translation along y (pure transverse).
        let loads = inertia_loads(&p.mesh, &m, sets, ip.x_static)
            .columns(1, 1)
            .into_owned();
        let shares = static_response_shares(ip, &all.vectors, &all.omega_sq, &loads);
        ranked = Some((rank(&shares), shares, all.vectors.clone()));
        lowest_normal_modes(ip, 0)
    })
    .unwrap();
    let (order, shares, vectors) = ranked.unwrap();
    let axial: Vec<bool> = (0..vectors.ncols())
        .map(|j| {
            let (mut ux, mut rest) = (0.0_f64, 0.0_f64);
            for (a, &dof) in sets.i.iter().enumerate() {
                let v = vectors[(a, j)].abs();
                if dof % 3 == 0 {
                    ux = ux.max(v)
                } else {
                    rest = rest.max(v)
                }
            }
            rest <= 1e-8 * ux
        })
        .collect();
    let n_axial = axial.iter().filter(|&&a| a).count();
    println!(
        "{n_axial} axial modes of {}; shares of the first 4 ranked: {:?}",
        axial.len(),
        order[..4].iter().map(|&k| shares[k]).collect::<Vec<_>>()
    );
    let largest_axial = (0..axial.len())
        .filter(|&k| axial[k])
        .map(|k| shares[k])
        .fold(0.0, f64::max);
    let smallest_other = (0..axial.len())
        .filter(|&k| !axial[k])
        .map(|k| shares[k])
        .fold(1.0, f64::min);
    println!("largest axial share {largest_axial:.2e}, smallest transverse {smallest_other:.2e}");
    assert_eq!(n_axial, 10);
    let tail = &order[order.len() - n_axial..];
    assert!(tail.iter().all(|&k| axial[k]));
    // Round-off only: the eigenvectors' transverse rows are not exactly zero.
    assert!(largest_axial < 1e-20);
    assert!(smallest_other > 1e6 * largest_axial);
    let total: f64 = shares.iter().sum();
    assert!((total - 1.0).abs() < 1e-10, "shares sum to {total}");
}

#[test]
fn participation_skips_the_torsion_mode_the_lowest_frequencies_take() {
    // A 3D cantilever, 10 × 20 mm: its 10 lowest modes are 9 bending modes and the first
    // torsion mode (595 Hz), which the inertia loads barely move (the section's polar
    // inertia is tiny against its bending reach); the ranking takes the axial mode
    // (1294 Hz, excited by the axial translation and centrifugal loads) instead.
    let lowest = cantilever(Dim::Spatial, rect10x20(), 12, 10);
    let ranked = with(lowest.clone(), ModeSelection::Participation);
    let (a, b) = (preprocess(&lowest).unwrap(), preprocess(&ranked).unwrap());
    let torsion = |x: &DMatrix<f64>| -> Vec<bool> {
        (0..x.ncols())
            .map(|j| {
                let rx = (0..x.nrows())
                    .step_by(6)
                    .map(|r| x[(r + 3, j)].abs())
                    .fold(0.0, f64::max);
                let rest = (0..x.nrows())
                    .filter(|r| r % 6 != 3)
                    .map(|r| x[(r, j)].abs())
                    .fold(0.0, f64::max);
                rest < 1e-8 * rx
            })
            .collect()
    };
    println!("lowest: {:?} Hz", a.body.inventory.normal_frequencies_hz);
    println!("ranked: {:?} Hz", b.body.inventory.normal_frequencies_hz);
    assert!(torsion(&a.reduction.x).iter().any(|&t| t));
    assert!(torsion(&b.reduction.x).iter().all(|&t| !t));
    assert_eq!(b.body.n_modes(), 10);
}

#[test]
fn mode_candidates_are_refused_by_name_and_value() {
    let base = cantilever(Dim::Planar, square10(), 4, 3);
    let refuse = |spec: &BeamBodySpec, value: &str| {
        let e = spec.validate().unwrap_err();
        let text = e.to_string();
        assert!(matches!(e, FeError::Invalid(_)), "{text}");
        assert!(
            text.contains("mode_candidates") && text.contains(value),
            "{text}"
        );
        println!("{text}");
    };
    let mut s = base.clone();
    s.mode_candidates = Some(5);
    refuse(&s, "5");
    let mut s = with(base.clone(), ModeSelection::Participation);
    s.mode_candidates = Some(2);
    refuse(&s, "2");
    s.mode_candidates = Some(13);
    refuse(&s, "13");
    s.mode_candidates = Some(12);
    assert!(s.validate().is_ok());
}

#[test]
fn mode_selection_reads_from_ron_and_defaults_to_lowest_frequency() {
    let text = |extra: &str| {
        format!(
            "(dim: Planar, material: (young_modulus: 2.1e11, density: 7850.0),
              section: Circle(diameter: 0.01),
              geometry: (points: [[0.0, 0.0], [1.0, 0.0]], elements_per_segment: 4),
              normal_modes: 2{extra})"
        )
    };
    let plain = BeamBodySpec::from_ron_str(&text(""), "plain").unwrap();
    assert_eq!(plain.mode_selection, ModeSelection::LowestFrequency);
    let ritz = BeamBodySpec::from_ron_str(&text(", mode_selection: LoadRitz"), "ritz").unwrap();
    assert_eq!(ritz.mode_selection, ModeSelection::LoadRitz);
    let ranked = BeamBodySpec::from_ron_str(
        &text(", mode_selection: Participation, mode_candidates: Some(6)"),
        "ranked",
    )
    .unwrap();
    assert_eq!(ranked.mode_candidates, Some(6));
    let e = BeamBodySpec::from_ron_str(&text(", mode_selection: Krylov"), "bad").unwrap_err();
    println!("{e}");
    assert!(e.to_string().contains("Krylov"));
}
