//! Derivatives of the cable against finite differences (docs/methods.md §8 items 6 and 11):
//! elastic force = −∂U/∂q, tangent K = −∂Q/∂q, Φ_q, Φ_t and the bias c along a motion;
//! zero elastic force under rigid motion; small-amplitude frequencies against
//! Euler–Bernoulli values.

use flexmbd_ancf::{Cable, CableSpec};
use flexmbd_core::{Dim, Formulation, Request, State, SystemTerms};
use nalgebra::{DMatrix, DVector, Rotation3, SymmetricEigen, Vector3};

fn spec(dim: Dim, elements: usize) -> CableSpec {
    CableSpec {
        gravity: [0.0; 3],
        omega_s: 3.0,
        t_s: 2.0,
        ..CableSpec::spin_up_beam(dim, elements)
    }
}

/// A strongly deformed state: the straight cable plus smooth bending, stretch and twist-like
/// perturbations of positions and slopes (|r′| ≠ 1, r″ ≠ 0, out of plane in 3D).
fn deformed(c: &Cable) -> DVector<f64> {
    let mut q = c.initial_positions().clone();
    let d = c.dim_components();
    let nodes = q.len() / (2 * d);
    let l = c.spec().length;
    for k in 0..nodes {
        let x = l * k as f64 / (nodes - 1) as f64;
        let o = 2 * d * k;
        q[o] += 0.02 * x + 0.1 * (0.3 * x).sin();
        q[o + 1] += 0.05 * x * x + 0.2 * (0.7 * x).cos();
        q[o + d] += 0.02 + 0.03 * (0.3 * x).cos();
        q[o + d + 1] += 0.1 * x - 0.14 * (0.7 * x).sin();
        if d == 3 {
            q[o + 2] += -0.03 * x * x + 0.1 * (0.5 * x).sin();
            q[o + d + 2] += -0.06 * x + 0.05 * (0.5 * x).cos();
        }
    }
    q
}

fn forces(c: &mut Cable, q: &DVector<f64>, tangents: bool) -> SystemTerms {
    let (n, m) = (c.n_coordinates(), c.n_constraints());
    let mut t = SystemTerms::new(n, m);
    let qd = DVector::zeros(n);
    c.evaluate(
        State::new(0.3, q, &qd),
        Request {
            dynamics: true,
            tangents,
            ..Request::default()
        },
        &mut t,
    );
    t
}

/// The cable of `elements` elements and a deformed state of it.
fn deformed_cable(dim: Dim, elements: usize) -> (Cable, DVector<f64>) {
    let c = Cable::new(&spec(dim, elements)).unwrap();
    let q = deformed(&c);
    (c, q)
}

/// q with its coordinate `i` moved by +dx and by −dx.
fn plus_minus(q: &DVector<f64>, i: usize, dx: f64) -> (DVector<f64>, DVector<f64>) {
    let (mut qp, mut qm) = (q.clone(), q.clone());
    qp[i] += dx;
    qm[i] -= dx;
    (qp, qm)
}

#[test]
fn elastic_force_is_minus_energy_gradient() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let (mut c, q) = deformed_cable(dim, 5);
        let qf = forces(&mut c, &q, false).forces;
        let mut worst: f64 = 0.0;
        for i in 0..q.len() {
            let dx = 1e-6;
            let (qp, qm) = plus_minus(&q, i, dx);
            let du = (c.elastic(&qp, None, None) - c.elastic(&qm, None, None)) / (2.0 * dx);
            worst = worst.max((qf[i] + du).abs());
        }
        let scale = qf.amax();
        eprintln!(
            "{dim}: max |Q + ∂U/∂q| = {worst:.3e} (|Q|∞ = {scale:.3e}), U = {:.4e}",
            c.elastic(&q, None, None)
        );
        assert!(worst < 1e-7 * scale, "{dim}: {worst:e} against {scale:e}");
    }
}

#[test]
fn tangent_is_minus_force_jacobian() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let (mut c, q) = deformed_cable(dim, 4);
        let k = forces(&mut c, &q, true).stiffness;
        let n = q.len();
        let mut fd = DMatrix::zeros(n, n);
        for j in 0..n {
            let dx = 1e-6;
            let (qp, qm) = plus_minus(&q, j, dx);
            let col = (forces(&mut c, &qp, false).forces - forces(&mut c, &qm, false).forces)
                / (2.0 * dx);
            fd.column_mut(j).copy_from(&(-col));
        }
        let err = (&k - &fd).amax();
        let asym = (&k - k.transpose()).amax();
        eprintln!(
            "{dim}: max |K − K_fd| = {err:.3e} (|K|max = {:.3e}), asymmetry {asym:.1e}",
            k.amax()
        );
        assert!(err < 1e-7 * k.amax(), "{dim}: {err:e}");
        assert!(asym < 1e-9 * k.amax());
    }
}

#[test]
fn rigid_motion_gives_zero_elastic_force() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut c = Cable::new(&spec(dim, 6)).unwrap();
        let d = c.dim_components();
        let rot = match dim {
            Dim::Planar => Rotation3::from_axis_angle(&Vector3::z_axis(), 2.3),
            Dim::Spatial => Rotation3::from_scaled_axis(Vector3::new(0.4, -1.1, 0.7)),
        };
        let shift = Vector3::new(3.0, -7.0, if d == 3 { 2.5 } else { 0.0 });
        let q0 = c.initial_positions().clone();
        let mut q = q0.clone();
        for k in 0..q.len() / (2 * d) {
            let o = 2 * d * k;
            let mut r = Vector3::zeros();
            let mut s = Vector3::zeros();
            for i in 0..d {
                r[i] = q0[o + i];
                s[i] = q0[o + d + i];
            }
            let (r, s) = (rot * r + shift, rot * s);
            for i in 0..d {
                q[o + i] = r[i];
                q[o + d + i] = s[i];
            }
        }
        let t = forces(&mut c, &q, true);
        let u = c.elastic(&q, None, None);
        eprintln!(
            "{dim}: |Q|∞ = {:.2e} N, U = {u:.2e} J under rigid motion",
            t.forces.amax()
        );
        // Scale: EA ε with ε at round-off.
        assert!(t.forces.amax() < 1e-12 * c.spec().ea, "{}", t.forces.amax());
        assert!(u.abs() < 1e-20 * c.spec().ea);
        // Infinitesimal rigid motions (ω × r, ω × r′ plus a translation of the r's) are
        // zero-energy modes of the tangent at a rigid configuration: K δq = 0.
        let omega = Vector3::new(-0.3, 0.8, 1.2);
        let mut dq = DVector::zeros(q.len());
        for k in 0..q.len() / (2 * d) {
            let o = 2 * d * k;
            let (mut r, mut s) = (Vector3::zeros(), Vector3::zeros());
            for i in 0..d {
                r[i] = q[o + i];
                s[i] = q[o + d + i];
            }
            let om = if d == 2 {
                Vector3::new(0.0, 0.0, omega.z)
            } else {
                omega
            };
            let (vr, vs) = (om.cross(&r) + Vector3::new(0.2, -0.1, 0.3), om.cross(&s));
            for i in 0..d {
                dq[o + i] = vr[i];
                dq[o + d + i] = vs[i];
            }
        }
        let kdq = &t.stiffness * &dq;
        eprintln!("{dim}: |K δq_rigid|∞ = {:.2e}", kdq.amax());
        assert!(kdq.amax() < 1e-12 * t.stiffness.amax() * dq.amax());
    }
}

/// Φ, Φ_q, Φ_t at (t, q(t)) and c at (t, q(t), q̇(t)) along q(t) = q_a + sin(ωt) v + t² w,
/// against central differences of Φ(t, q(t)) in t: Φ̇ = Φ_q q̇ + Φ_t, Φ̈ = Φ_q q̈ + c.
#[test]
fn constraint_rates_match_finite_differences_along_a_motion() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut c = Cable::new(&spec(dim, 3)).unwrap();
        let (n, m) = (c.n_coordinates(), c.n_constraints());
        let qa = deformed(&c);
        let v = DVector::from_fn(n, |i, _| ((i * 7 % 5) as f64 - 2.0) * 0.1);
        let w = DVector::from_fn(n, |i, _| ((i * 3 % 7) as f64 - 3.0) * 0.05);
        let om = 1.7;
        let q_at = |t: f64| &qa + (om * t).sin() * &v + t * t * &w;
        let qd_at = |t: f64| om * (om * t).cos() * &v + 2.0 * t * &w;
        let qdd_at = |t: f64| -om * om * (om * t).sin() * &v + 2.0 * &w;
        let mut terms = SystemTerms::new(n, m);
        let phi = |c: &mut Cable, t: f64| {
            let mut tt = SystemTerms::new(n, m);
            c.evaluate(
                State::new(t, &q_at(t), &qd_at(t)),
                Request::CONSTRAINTS,
                &mut tt,
            );
            tt.phi
        };
        // During the spin-up (θ̈ ≠ 0), at T_s and after it.
        for t in [0.7, 1.3, 2.0, 2.9] {
            terms.clear(Request::ALL);
            c.evaluate(State::new(t, &q_at(t), &qd_at(t)), Request::ALL, &mut terms);
            // Rate with dt = 1e-5 (truncation ~1e-10), acceleration with dt = 1e-4.
            let e = 1e-5;
            let rate_fd = (phi(&mut c, t + e) - phi(&mut c, t - e)) / (2.0 * e);
            let dt = 1e-4;
            let (pp, p0, pm) = (phi(&mut c, t + dt), phi(&mut c, t), phi(&mut c, t - dt));
            let acc_fd = (&pp - 2.0 * &p0 + &pm) / (dt * dt);
            let rate = &terms.phi_q * qd_at(t) + &terms.phi_t;
            let acc = &terms.phi_q * qdd_at(t) + &terms.accel_term;
            let (e1, e2) = ((rate - rate_fd).amax(), (acc - acc_fd).amax());
            eprintln!("{dim} t = {t}: |Φ̇ − fd| = {e1:.2e}, |Φ̈ − fd| = {e2:.2e}");
            assert!((&terms.phi - p0).amax() == 0.0);
            assert!(e1 < 1e-8, "{dim} t = {t}: rate {e1:e}");
            assert!(e2 < 1e-6, "{dim} t = {t}: acceleration {e2:e}");
            // Φ_q against differences of Φ in q at fixed t.
            for j in 0..n {
                let dx = 1e-6;
                let (mut qp, mut qm) = (q_at(t), q_at(t));
                qp[j] += dx;
                qm[j] -= dx;
                let mut tp = SystemTerms::new(n, m);
                let mut tm = SystemTerms::new(n, m);
                c.evaluate(State::new(t, &qp, &qd_at(t)), Request::CONSTRAINTS, &mut tp);
                c.evaluate(State::new(t, &qm, &qd_at(t)), Request::CONSTRAINTS, &mut tm);
                let col = (tp.phi - tm.phi) / (2.0 * dx);
                assert!((col - terms.phi_q.column(j)).amax() < 1e-9);
            }
        }
    }
}

/// Small-amplitude frequencies of the clamped cable (root constraints eliminated) against
/// the Euler–Bernoulli cantilever, ω_j = (β_j L)² √(EI/(ρA L⁴)), and the first axial
/// frequency (π/2)√(EA/ρA)/L (docs/scenes.md §5: 3.80, 23.8, 66.6 and 759 rad/s).
#[test]
fn small_amplitude_frequencies_match_euler_bernoulli() {
    let mut c = Cable::new(&spec(Dim::Planar, 16)).unwrap();
    let q = c.initial_positions().clone();
    let k = forces(&mut c, &q, true).stiffness;
    let mass = c.mass().clone();
    // Clamped: r₁ = 0 and r₁′_y = 0 (coordinates 0, 1, 3); r₁′_x (2) stays free.
    let free: Vec<usize> = (0..q.len()).filter(|i| ![0, 1, 3].contains(i)).collect();
    let kf = k.select_rows(&free).select_columns(&free);
    let mf = mass.select_rows(&free).select_columns(&free);
    let l = mf.clone().cholesky().unwrap().l();
    let li = l.clone().try_inverse().unwrap();
    let a = &li * kf * li.transpose();
    let mut w2: Vec<f64> = SymmetricEigen::new(0.5 * (&a + a.transpose()))
        .eigenvalues
        .iter()
        .copied()
        .collect();
    w2.sort_by(f64::total_cmp);
    let w: Vec<f64> = w2.iter().map(|x| x.max(0.0).sqrt()).collect();
    let s = c.spec().clone();
    let base = (s.ei / (s.rho_a * s.length.powi(4))).sqrt();
    let beta = [
        1.875_104_068_711_961,
        4.694_091_132_974_175,
        7.854_757_438_237_613,
    ];
    let bending: Vec<f64> = beta.iter().map(|b| b * b * base).collect();
    let axial = std::f64::consts::FRAC_PI_2 * (s.ea / s.rho_a).sqrt() / s.length;
    eprintln!("ω = {:?}; EB bending {bending:?}, axial {axial}", &w[..5]);
    // 16 Hermite elements: relative errors 1.3e-7, 5.1e-6, 4.0e-5 (they grow as (j/n)⁴).
    for (j, (wb, tol)) in bending.iter().zip([1e-6, 2e-5, 1e-4]).enumerate() {
        let rel = (w[j] - wb).abs() / wb;
        assert!(
            rel < tol,
            "bending mode {j}: {} against {wb} ({rel:e})",
            w[j]
        );
    }
    let wa = w
        .iter()
        .copied()
        .min_by(|x, y| (x - axial).abs().total_cmp(&(y - axial).abs()))
        .unwrap();
    assert!(
        (wa - axial).abs() / axial < 1e-5,
        "axial {wa} against {axial}"
    );
}
