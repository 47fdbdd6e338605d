//! The two routes on beam bodies from FE preprocessing (`flexmbd_fe::reduce`):
//! a straight cantilever and an L-shaped (bent polyline) beam, 2D and 3D, with and
//! without static modes; and the rigid limit of a 0-mode beam against the uniform bar.

mod common;
use common::*;
use flexmbd_body::{Dim, FlexibleBody, InertiaMethod};
use flexmbd_fe::{BeamBodySpec, ReducedBody, reduce};
use nalgebra::{Matrix3, Vector3};

const TOL: f64 = 1e-10;

fn routes_agree(rb: &ReducedBody, seed: u64) -> (f64, f64) {
    let mut r = rng(seed);
    let mut body = FlexibleBody::new(rb).unwrap();
    let n = body.n_modes();
    // Modal coordinates scaled to visible deflections (mode rows are O(1) at the tip).
    let mut worst = (0.0f64, 0.0f64);
    for _ in 0..20 {
        let mut st = random_state(&mut r, rb.dim, n);
        for v in st.y.iter_mut() {
            *v *= 0.1;
        }
        let (ma, qa) = eval(&mut body, &st.view(), InertiaMethod::BMatrix);
        let (mb, qb) = eval(&mut body, &st.view(), InertiaMethod::ShapeIntegrals);
        let (dm, dq) = (rel_diff_m(&ma, &mb), rel_diff_v(&qa, &qb));
        assert!(dm < TOL && dq < TOL, "routes differ: M̄ {dm:e}, Q̄ {dq:e}");
        worst = (worst.0.max(dm), worst.1.max(dq));
    }
    // M_yy of the cloud equals the reduced M_ff (consistent cloud, docs/methods.md §2.3).
    let myy = body.m_yy();
    let d = (&myy - body.m_ff()).amax() / body.m_ff().amax().max(1e-300);
    if n > 0 {
        assert!(d < 1e-10, "Σ S^aa vs M_ff: {d:e}");
    }
    worst
}

#[test]
fn straight_and_l_beams_3d() {
    for ((name, rb), seed) in beams(Dim::Spatial).into_iter().zip([1, 2]) {
        let w = routes_agree(&rb, seed);
        let (n, np) = (rb.n_modes(), rb.cloud.len());
        eprintln!("{name} ({n} modes, {np} points): {:.1e} {:.1e}", w.0, w.1);
    }
}

#[test]
fn cantilever_model_file_3d() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../models/cantilever_3d.ron"
    );
    let s = BeamBodySpec::from_file(path).expect("models/cantilever_3d.ron parses");
    let rb = reduce(&s).unwrap();
    assert_eq!(rb.n_modes(), 6, "the model file asks for 6 normal modes");
    routes_agree(&rb, 3);
}

#[test]
fn straight_and_l_beams_2d() {
    for ((name, rb), seed) in beams(Dim::Planar).into_iter().zip([4, 5]) {
        let w = routes_agree(&rb, seed);
        eprintln!("{name} ({} modes): {:.1e} {:.1e}", rb.n_modes(), w.0, w.1);
    }
}

/// A 0-mode beam is a rigid uniform bar: m = ρAL, static moment m L/2, inertia about
/// the clamped end m L²/3 plus the section's rotary inertia (3D section points give
/// ρ I L about the bending axes and ρ (I_y + I_z) L about the beam axis; the 2D cloud
/// has no rotary inertia).
#[test]
fn zero_mode_beam_is_the_uniform_bar() {
    let (rho, wdt, ht, len): (f64, f64, f64, f64) = (7850.0, 0.02, 0.01, 1.0);
    let area = wdt * ht;
    let m = rho * area * len;
    let iz = ht * wdt.powi(3) / 12.0; // ∫ y² dA, y along the width
    let iy = wdt * ht.powi(3) / 12.0;
    let rb3 = beam_spec(Dim::Spatial, "[[0,0,0],[1,0,0]]", "[]", 0, 8);
    assert_eq!(rb3.n_modes(), 0);
    let mut b3 = FlexibleBody::new(&rb3).unwrap();
    let j_end = Matrix3::from_diagonal(&Vector3::new(
        rho * (iy + iz) * len,
        m * len * len / 3.0 + rho * iy * len,
        m * len * len / 3.0 + rho * iz * len,
    ));
    let st = OwnedState::rigid_at_rest(Vector3::zeros());
    for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
        let (mm, _) = eval(&mut b3, &st.view(), method);
        assert!((mm[(0, 0)] - m).abs() < 1e-12 * m);
        assert!((mm[(1, 5)] - m * len / 2.0).abs() < 1e-12 * m);
        let j = mm.fixed_view::<3, 3>(3, 3).into_owned();
        assert!((j - j_end).amax() < 1e-12 * j_end.amax(), "{j} vs {j_end}");
    }
    let rb2 = beam_spec(Dim::Planar, "[[0,0],[1,0]]", "[]", 0, 8);
    let mut b2 = FlexibleBody::new(&rb2).unwrap();
    let st2 = flexmbd_body::BodyState::planar(
        nalgebra::Vector2::zeros(),
        0.0,
        nalgebra::Vector2::zeros(),
        0.0,
        &[],
        &[],
    );
    for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
        let mut mm = nalgebra::DMatrix::zeros(3, 3);
        let mut q = nalgebra::DVector::zeros(3);
        b2.inertia(&st2, method, &mut mm, &mut q);
        assert!((mm[(0, 0)] - m).abs() < 1e-12 * m);
        assert!((mm[(1, 2)] - m * len / 2.0).abs() < 1e-12 * m);
        assert!(
            (mm[(2, 2)] - m * len * len / 3.0).abs() < 1e-12 * m,
            "{}",
            mm[(2, 2)]
        );
    }
}
