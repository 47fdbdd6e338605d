//! Eigenfrequencies against Euler–Bernoulli theory (docs/methods.md §1.2, §8 item 1).

mod common;

use common::*;
use flexmbd_core::Dim;
use flexmbd_fe::assembly::{Mesh, to_dense};
use flexmbd_fe::beam::MassModel;
use flexmbd_fe::modal::{Eigenpairs, constrained_eigen, generalized_eigen};
use flexmbd_fe::{Section, reduce};
use nalgebra::DMatrix;

/// Which family a 3D mode belongs to: 0 axial (Ux), 1 v-plane (Uy, Rz), 2 w-plane (Uz, Ry), 3 torsion (Rx).
fn family_3d(v: &nalgebra::DVectorView<f64>) -> usize {
    let mut e = [0.0; 4];
    for (i, x) in v.iter().enumerate() {
        let g = match i % 6 {
            0 => 0,
            1 | 5 => 1,
            2 | 4 => 2,
            _ => 3,
        };
        e[g] += x * x;
    }
    let tot: f64 = e.iter().sum();
    let (imax, emax) = e
        .iter()
        .enumerate()
        .fold((0, 0.0), |b, (i, &x)| if x > b.1 { (i, x) } else { b });
    assert!(
        emax > (1.0 - 1e-12) * tot,
        "mode families are coupled: {e:?}"
    );
    imax
}

fn family_2d(v: &nalgebra::DVectorView<f64>) -> usize {
    let mut e = [0.0; 2];
    for (i, x) in v.iter().enumerate() {
        e[usize::from(i % 3 != 0)] += x * x;
    }
    assert!(e[0].min(e[1]) < 1e-12 * (e[0] + e[1]));
    usize::from(e[1] > e[0])
}

/// Frequencies (Hz) of the modes of family `fam`, skipping near-zero (rigid) ones.
fn family_hz(e: &Eigenpairs, fam: usize, dim: Dim, skip_rigid: usize) -> Vec<f64> {
    let hz = e.frequencies_hz();
    (skip_rigid..hz.len())
        .filter(|&j| {
            let c = e.vectors.column(j);
            match dim {
                Dim::Planar => family_2d(&c) == fam,
                Dim::Spatial => family_3d(&c) == fam,
            }
        })
        .map(|j| hz[j])
        .collect()
}

fn full_model(
    dim: Dim,
    section: Section,
    n_el: usize,
    model: MassModel,
) -> (Mesh, DMatrix<f64>, DMatrix<f64>) {
    let spec = cantilever(dim, section, n_el, 0);
    spec.validate().unwrap();
    let mesh = Mesh::from_spec(&spec);
    let a = mesh.assemble(model);
    let (k, m) = (to_dense(&a.k), to_dense(&a.m));
    (mesh, k, m)
}

#[test]
fn cantilever_2d_first_three_within_0p1_percent() {
    let spec = cantilever(Dim::Planar, square10(), 20, 4);
    let body = reduce(&spec).unwrap();
    let hz = &body.inventory.normal_frequencies_hz;
    let (a, i) = (1e-4, 1e-4 * 1e-4 / 12.0);
    for j in 0..3 {
        let th = eb_hz(CANTILEVER_BL[j], E * i, RHO * a, 1.0);
        let r = rel(hz[j], th);
        println!(
            "2D cantilever mode {}: {:.6} Hz, theory {:.6} Hz, rel {:.2e}",
            j + 1,
            hz[j],
            th,
            r
        );
        assert!(r < 1e-3);
    }
}

fn cantilever_3d_families(model: MassModel) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let (mesh, k, m) = full_model(Dim::Spatial, rect10x20(), 20, model);
    let fixed: Vec<usize> = (0..6).collect();
    let e = constrained_eigen(&k, &m, &fixed, "3D cantilever").unwrap();
    let _ = mesh;
    (
        family_hz(&e, 1, Dim::Spatial, 0),
        family_hz(&e, 2, Dim::Spatial, 0),
        family_hz(&e, 3, Dim::Spatial, 0),
    )
}

/// ∫φ′² / ∫φ² for the cantilever mode with βL (L = 1), by 2000-interval Gauss quadrature.
fn cantilever_slope_ratio(bl: f64) -> f64 {
    let s = (bl.cosh() + bl.cos()) / (bl.sinh() + bl.sin());
    let phi = |x: f64| (bl * x).cosh() - (bl * x).cos() - s * ((bl * x).sinh() - (bl * x).sin());
    let dphi =
        |x: f64| bl * ((bl * x).sinh() + (bl * x).sin() - s * ((bl * x).cosh() - (bl * x).cos()));
    let (mut a, mut b) = (0.0, 0.0);
    let n = 2000;
    let h = 1.0 / n as f64;
    for i in 0..n {
        for (t, w) in flexmbd_fe::cloud::GAUSS4 {
            let x = (i as f64 + 0.5 * (1.0 + t)) * h;
            a += 0.5 * h * w * dphi(x).powi(2);
            b += 0.5 * h * w * phi(x).powi(2);
        }
    }
    a / b
}

/// Mode `j` of the 3D cantilever in both bending planes, (v, w) Hz, within 0.1 % of the
/// theory (tv, tw).
fn assert_cantilever_planes(mass: &str, j: usize, (v, w): (f64, f64), (tv, tw): (f64, f64)) {
    println!(
        "3D {mass} mode {}: v {:.6} (th {:.6}, {:.2e}), w {:.6} (th {:.6}, {:.2e})",
        j + 1,
        v,
        tv,
        rel(v, tv),
        w,
        tw,
        rel(w, tw)
    );
    assert!(rel(v, tv) < 1e-3);
    assert!(rel(w, tw) < 1e-3);
}

#[test]
fn cantilever_3d_both_planes_and_torsion() {
    let area = 0.01 * 0.02;
    let iz = 0.02 * 0.01f64.powi(3) / 12.0;
    let iy = 0.01 * 0.02f64.powi(3) / 12.0;
    // Without bending rotary inertia: pure Euler–Bernoulli theory.
    let (v, w, t) = cantilever_3d_families(MassModel::Consistent);
    for j in 0..3 {
        let tv = eb_hz(CANTILEVER_BL[j], E * iz, RHO * area, 1.0);
        let tw = eb_hz(CANTILEVER_BL[j], E * iy, RHO * area, 1.0);
        assert_cantilever_planes("consistent", j, (v[j], w[j]), (tv, tw));
    }
    // The default Rayleigh mass: against Rayleigh-corrected theory,
    // ω_R = ω / √(1 + (I/A) ∫φ′²/∫φ²) (Rayleigh quotient with the EB mode shape).
    let (vr, wr, tr) = cantilever_3d_families(MassModel::Rayleigh);
    for j in 0..3 {
        let q = cantilever_slope_ratio(CANTILEVER_BL[j]);
        let tv = eb_hz(CANTILEVER_BL[j], E * iz, RHO * area, 1.0) / (1.0 + iz / area * q).sqrt();
        let tw = eb_hz(CANTILEVER_BL[j], E * iy, RHO * area, 1.0) / (1.0 + iy / area * q).sqrt();
        assert_cantilever_planes("Rayleigh", j, (vr[j], wr[j]), (tv, tw));
        assert!(
            vr[j] < v[j] && wr[j] < w[j],
            "rotary inertia lowers frequencies"
        );
    }
    // Torsion, fixed–free: f = (2j−1)/(4L) √(GJ/(ρ I_p)), J Saint-Venant.
    let g = E / (2.0 * (1.0 + NU));
    let r: f64 = 0.5;
    let j_sv = 0.02 * 0.01f64.powi(3) * (1.0 / 3.0 - 0.21 * r * (1.0 - r.powi(4) / 12.0));
    let th = 1.0 / 4.0 * (g * j_sv / (RHO * (iy + iz))).sqrt();
    println!(
        "3D torsion mode 1: {:.4} Hz (consistent), {:.4} Hz (Rayleigh), theory {:.4} Hz",
        t[0], tr[0], th
    );
    assert!(rel(t[0], th) < 2e-3);
    assert!(
        rel(tr[0], t[0]) < 1e-12,
        "torsion has no bending rotary inertia"
    );
}

#[test]
fn convergence_order_is_four() {
    // Mode 3 of the 2D cantilever at 4, 8, 16 elements.
    let (a, i) = (1e-4, 1e-4 * 1e-4 / 12.0);
    let th = eb_hz(CANTILEVER_BL[2], E * i, RHO * a, 1.0);
    let errs: Vec<f64> = [4, 8, 16]
        .iter()
        .map(|&n| {
            let body = reduce(&cantilever(Dim::Planar, square10(), n, 3)).unwrap();
            rel(body.inventory.normal_frequencies_hz[2], th)
        })
        .collect();
    let p1 = (errs[0] / errs[1]).log2();
    let p2 = (errs[1] / errs[2]).log2();
    println!("mode 3 errors {errs:?}, orders {p1:.3} {p2:.3}");
    assert!((3.5..4.5).contains(&p1), "order {p1}");
    assert!((3.5..4.5).contains(&p2), "order {p2}");
}

/// The first three 2D bending frequencies `v` (10 mm square, 1 m) against Euler–Bernoulli
/// with the roots βL = `beta_l(j)`, within 0.1 %.
fn assert_2d_bending(case: &str, v: &[f64], beta_l: impl Fn(usize) -> f64) {
    let (a, i) = (1e-4, 1e-4 * 1e-4 / 12.0);
    for j in 0..3 {
        let th = eb_hz(beta_l(j), E * i, RHO * a, 1.0);
        println!(
            "2D {case} mode {}: {:.6} Hz, theory {:.6}, rel {:.2e}",
            j + 1,
            v[j],
            th,
            rel(v[j], th)
        );
        assert!(rel(v[j], th) < 1e-3);
    }
}

/// The first three 3D bending frequencies of each plane, `v` and `w` (10 × 20 mm, 1 m),
/// against Euler–Bernoulli with the roots βL = `beta_l(j)`, within 0.1 %.
fn assert_3d_bending(v: &[f64], w: &[f64], beta_l: impl Fn(usize) -> f64) {
    let area = 0.01 * 0.02;
    let iz = 0.02 * 0.01f64.powi(3) / 12.0;
    let iy = 0.01 * 0.02f64.powi(3) / 12.0;
    for j in 0..3 {
        let bl = beta_l(j);
        let (tv, tw) = (
            eb_hz(bl, E * iz, RHO * area, 1.0),
            eb_hz(bl, E * iy, RHO * area, 1.0),
        );
        assert!(rel(v[j], tv) < 1e-3, "v {j}: {} vs {tv}", v[j]);
        assert!(rel(w[j], tw) < 1e-3, "w {j}: {} vs {tw}", w[j]);
    }
}

/// The first `n` eigenvalues are rigid modes (below 1e-8 of the first elastic one).
fn assert_rigid_modes(e: &Eigenpairs, n: usize) {
    let scale = e.omega_sq[n];
    for j in 0..n {
        assert!(
            e.omega_sq[j].abs() < 1e-8 * scale,
            "rigid mode {j}: {}",
            e.omega_sq[j]
        );
    }
}

#[test]
fn pinned_pinned_2d_and_3d() {
    let pinned_bl = |j: usize| std::f64::consts::PI * (j + 1) as f64;
    let (_, k, m) = full_model(Dim::Planar, square10(), 20, MassModel::Consistent);
    let n = k.nrows();
    let e = constrained_eigen(&k, &m, &[0, 1, n - 2], "pinned-pinned 2D").unwrap();
    assert_2d_bending(
        "pinned-pinned",
        &family_hz(&e, 1, Dim::Planar, 0),
        pinned_bl,
    );
    let (_, k, m) = full_model(Dim::Spatial, rect10x20(), 20, MassModel::Consistent);
    let n = k.nrows();
    let fixed = [0, 1, 2, 3, n - 6 + 1, n - 6 + 2];
    let e = constrained_eigen(&k, &m, &fixed, "pinned-pinned 3D").unwrap();
    let v = family_hz(&e, 1, Dim::Spatial, 0);
    let w = family_hz(&e, 2, Dim::Spatial, 0);
    assert_3d_bending(&v, &w, pinned_bl);
}

#[test]
fn free_free_2d_and_3d() {
    let free_bl = |j: usize| FREE_FREE_BL[j];
    let (_, k, m) = full_model(Dim::Planar, square10(), 20, MassModel::Consistent);
    let e = generalized_eigen(&k, &m, "free-free 2D").unwrap();
    assert_rigid_modes(&e, 3);
    assert_2d_bending("free-free", &family_hz(&e, 1, Dim::Planar, 3), free_bl);
    let (_, k, m) = full_model(Dim::Spatial, rect10x20(), 20, MassModel::Consistent);
    let e = generalized_eigen(&k, &m, "free-free 3D").unwrap();
    assert_rigid_modes(&e, 6);
    let v = family_hz(&e, 1, Dim::Spatial, 6);
    let w = family_hz(&e, 2, Dim::Spatial, 6);
    assert_3d_bending(&v, &w, free_bl);
}
