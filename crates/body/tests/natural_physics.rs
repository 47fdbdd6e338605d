//! The natural-coordinate terms (docs/methods.md §2.2 absolute set, §2.5, §2.6, §3.1, §3.3),
//! checked physics against physics, beside `natural.rs`:
//!
//! * routes (a) and (b) agree on random clouds and on FE beams (straight, L-shaped with
//!   static modes), off the constraint manifold (non-unit u, non-orthonormal A);
//! * `M = Σ w B_kᵀ B_k` with the test's own `B_k`;
//! * Lagrange: `Q_v = −Ṁ q̇ + ∂T/∂q` with `T = ½ q̇ᵀ M(q) q̇`, by central differences
//!   (independent of both routes' Q_v formulas);
//! * on the manifold the natural set carries the same kinetic energy, mass matrix and
//!   inertia force as the relative set {ṡ, ω, ẏ}: `T` equal, `M̄ = Rᵀ M R`,
//!   `Q̄ = Rᵀ(Q_v − M Ṙ Z)` with `q̇ = R Z`;
//! * the rigid uniform bar from two points gives m/3, m/6, m/3 (§3.1), and a general
//!   rigid planar cloud gives the §3.1 integrals;
//! * gravity rows against `Σ w_k B_kᵀ g` and against `−∂V/∂q` of the potential helper;
//! * body points: Jacobian, velocity, bias and point-force rows against differences.
//!
//! That one evaluation allocates nothing is held in `no_alloc.rs`.

mod common;
use common::*;
use flexmbd_body::NaturalWorkspace;
use flexmbd_body::{BodyPoint, Dim, FlexibleBody, InertiaMethod, NaturalState};
use flexmbd_fe::ReducedBody;
use nalgebra::{DMatrix, DVector, Matrix2, Vector2, Vector3};

// ---------------------------------------------------------------- helpers

const E: Matrix2<f64> = Matrix2::new(0.0, -1.0, 1.0, 0.0);

/// `∂f/∂q` at q by central differences with step h.
fn central_gradient(
    q: &DVector<f64>,
    h: f64,
    mut f: impl FnMut(DVector<f64>) -> f64,
) -> DVector<f64> {
    DVector::from_fn(q.len(), |i, _| {
        let mut qp = q.clone();
        qp[i] += h;
        let mut qm = q.clone();
        qm[i] -= h;
        (f(qp) - f(qm)) / (2.0 * h)
    })
}

/// The cloud's `B_k` (absolute set, §2.2 / §2.5 "2D") written afresh from the
/// position law, for the independent checks.
fn b_k(rb: &ReducedBody, k: usize, st: &NaturalState<'_>) -> DMatrix<f64> {
    let n = rb.cloud.n_modes;
    let x = DMatrix::from_row_slice(3, n, rb.cloud.rows(k));
    let y = DVector::from_column_slice(st.y);
    let rbar = rb.cloud.positions[k] + Vector3::from_iterator((&x * &y).iter().copied());
    match rb.dim {
        Dim::Spatial => {
            let a = st.a;
            let mut b = DMatrix::zeros(3, 12 + n);
            for i in 0..3 {
                b[(i, i)] = 1.0;
                for ax in 0..3 {
                    b[(i, 3 + 3 * ax + i)] = rbar[ax];
                }
            }
            let am = DMatrix::from_fn(3, 3, |i, j| a[(i, j)]);
            b.columns_mut(12, n).copy_from(&(am * x));
            b
        }
        Dim::Planar => {
            let u: Vector2<f64> = st.a.fixed_view::<2, 1>(0, 0).into();
            let a = Matrix2::from_columns(&[u, E * u]);
            let mut b = DMatrix::zeros(2, 4 + n);
            b[(0, 0)] = 1.0;
            b[(1, 1)] = 1.0;
            let bu = Matrix2::identity() * rbar.x + E * rbar.y;
            b.view_mut((0, 2), (2, 2)).copy_from(&bu);
            let am = DMatrix::from_fn(2, 2, |i, j| a[(i, j)]);
            b.columns_mut(4, n).copy_from(&(am * x.rows(0, 2)));
            b
        }
    }
}

fn routes_agree(rb: &ReducedBody, seed: u64, y_scale: f64) -> (f64, f64) {
    let mut r = rng(seed);
    let body = FlexibleBody::new(rb).unwrap();
    let mut ws = body.natural_workspace();
    let n = body.n_modes();
    let mut worst = (0.0f64, 0.0f64);
    for _ in 0..20 {
        let s = random_q(&mut r, rb.dim, n, y_scale);
        let (ma, qa) = eval_natural(&body, &mut ws, &s.view(), InertiaMethod::BMatrix);
        let (mb, qb) = eval_natural(&body, &mut ws, &s.view(), InertiaMethod::ShapeIntegrals);
        let (dm, dq) = (rel_diff_m(&ma, &mb), rel_diff_v(&qa, &qb));
        assert!(
            dm < 1e-10 && dq < 1e-10,
            "{} n={n}: routes differ: M {dm:e}, Q {dq:e}",
            rb.dim
        );
        // Symmetric to round-off (P̄_u of the cloud is itself symmetric only to round-off).
        let ds = rel_diff_m(&mb, &mb.transpose()).max(rel_diff_m(&ma, &ma.transpose()));
        assert!(ds < 1e-15, "M symmetric: {ds:e}");
        if n == 0 {
            assert_eq!(qb.amax(), 0.0, "rigid: Q_v = 0");
        }
        worst = (worst.0.max(dm), worst.1.max(dq));
    }
    worst
}

// ---------------------------------------------------------------- route agreement

#[test]
fn routes_agree_random_clouds() {
    for dim in [Dim::Planar, Dim::Spatial] {
        for (i, n) in [0usize, 1, 3, 8].into_iter().enumerate() {
            let mut r = rng(100 + i as u64);
            let rb = random_body(&mut r, dim, n, 30);
            let w = routes_agree(&rb, 200 + i as u64, 1.0);
            eprintln!("{dim} random cloud n={n}: M {:.1e}, Q {:.1e}", w.0, w.1);
        }
    }
}

#[test]
fn routes_agree_beams() {
    for dim in [Dim::Planar, Dim::Spatial] {
        for (i, (name, rb)) in beams(dim).into_iter().enumerate() {
            let w = routes_agree(&rb, 300 + i as u64, 0.1);
            eprintln!(
                "{name} ({} modes, {} points): M {:.1e}, Q {:.1e}",
                rb.n_modes(),
                rb.cloud.len(),
                w.0,
                w.1
            );
        }
    }
}

/// Route (a) with the test's own `B_k` (no `Ḃ_k`): `M = Σ w B_kᵀ B_k`.
#[test]
fn mass_matrix_is_the_cloud_projection() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut r = rng(7);
        let rb = random_body(&mut r, dim, 4, 12);
        let body = FlexibleBody::new(&rb).unwrap();
        let mut ws = body.natural_workspace();
        let s = random_q(&mut r, dim, 4, 1.0);
        let st = s.view();
        let nc = body.n_natural_coords();
        let mut m_ref = DMatrix::zeros(nc, nc);
        for k in 0..rb.cloud.len() {
            let b = b_k(&rb, k, &st);
            m_ref += rb.cloud.weights[k] * b.transpose() * &b;
        }
        let (m, _) = eval_natural(&body, &mut ws, &st, InertiaMethod::ShapeIntegrals);
        let d = rel_diff_m(&m, &m_ref);
        assert!(d < 1e-12, "{dim}: M vs Σ w BᵀB: {d:e}");
    }
}

// ---------------------------------------------------------------- Lagrange

/// `Q_v = −Ṁ q̇ + ∂T/∂q` by central differences of `M(q)`. M is quadratic in q, so
/// central differences have no truncation error: only round-off remains.
fn lagrange(rb: &ReducedBody, seed: u64, y_scale: f64) -> f64 {
    let mut r = rng(seed);
    let body = FlexibleBody::new(rb).unwrap();
    let mut ws = body.natural_workspace();
    let n = body.n_modes();
    let h = 1e-5;
    let mut worst = 0.0f64;
    for _ in 0..5 {
        let s = random_q(&mut r, rb.dim, n, y_scale);
        let mass = |ws: &mut NaturalWorkspace, q: DVector<f64>| {
            let sq = s.with_q(q);
            eval_natural(&body, ws, &sq.view(), InertiaMethod::ShapeIntegrals).0
        };
        let mp = mass(&mut ws, &s.q + h * &s.qd);
        let mm = mass(&mut ws, &s.q - h * &s.qd);
        let mdot_qd = (mp - mm) / (2.0 * h) * &s.qd;
        let dtdq = central_gradient(&s.q, h, |q| 0.5 * s.qd.dot(&(mass(&mut ws, q) * &s.qd)));
        let q_ref = -mdot_qd + dtdq;
        for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
            let (_, qv) = eval_natural(&body, &mut ws, &s.view(), method);
            let d = rel_diff_v(&qv, &q_ref);
            assert!(d < 1e-6, "{} n={n} {method:?}: Lagrange {d:e}", rb.dim);
            worst = worst.max(d);
        }
    }
    worst
}

#[test]
fn lagrange_check_2d_3d() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut r = rng(11);
        let rb = random_body(&mut r, dim, 5, 25);
        let d = lagrange(&rb, 12, 1.0);
        eprintln!("{dim} random cloud: Lagrange {d:.1e}");
        for (i, (name, rb)) in beams(dim).into_iter().enumerate() {
            let d = lagrange(&rb, 13 + i as u64, 0.1);
            eprintln!("{name}: Lagrange {d:.1e}");
        }
    }
}

// ---------------------------------------------------------------- relative set

fn check_relative(rb: &ReducedBody, seed: u64, y_scale: f64) -> (f64, f64, f64) {
    let mut r = rng(seed);
    let mut body = FlexibleBody::new(rb).unwrap();
    let mut ws = body.natural_workspace();
    let n = body.n_modes();
    let dim = rb.dim;
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..20 {
        let mut st = random_state(&mut r, dim, n);
        for v in st.y.iter_mut() {
            *v *= y_scale;
        }
        let view = st.view();
        let mut z = DVector::zeros(dim.n_rigid() + n);
        match dim {
            Dim::Spatial => {
                z.fixed_rows_mut::<3>(0).copy_from(&st.s_dot);
                z.fixed_rows_mut::<3>(3).copy_from(&st.omega);
            }
            Dim::Planar => {
                z[0] = st.s_dot.x;
                z[1] = st.s_dot.y;
                z[2] = st.omega.z;
            }
        }
        z.rows_mut(dim.n_rigid(), n)
            .copy_from(&DVector::from_column_slice(&st.y_dot));
        let (mrel, qrel) = eval(&mut body, &view, InertiaMethod::ShapeIntegrals);
        let (s, rm, rdz) = natural_from_relative(&view, dim, n);
        assert!((&rm * &z - &s.qd).amax() < 1e-14, "q̇ = R Z");
        for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
            let (m, qv) = eval_natural(&body, &mut ws, &s.view(), method);
            let t_nat = 0.5 * s.qd.dot(&(&m * &s.qd));
            let t_rel = 0.5 * z.dot(&(&mrel * &z));
            let dt = (t_nat - t_rel).abs() / t_rel;
            let dm = rel_diff_m(&(rm.transpose() * &m * &rm), &mrel);
            let dq = rel_diff_v(&(rm.transpose() * (&qv - &m * &rdz)), &qrel);
            assert!(
                dt < 1e-12 && dm < 1e-12 && dq < 1e-12,
                "{dim} n={n} {method:?}: T {dt:e}, M {dm:e}, Q {dq:e}"
            );
            worst = (worst.0.max(dt), worst.1.max(dm), worst.2.max(dq));
        }
    }
    worst
}

#[test]
fn manifold_matches_relative_set() {
    for dim in [Dim::Planar, Dim::Spatial] {
        for n in [0usize, 4] {
            let mut r = rng(20 + n as u64);
            let rb = random_body(&mut r, dim, n, 25);
            let w = check_relative(&rb, 21, 1.0);
            eprintln!(
                "{dim} random n={n}: T {:.1e}, RᵀMR {:.1e}, Q {:.1e}",
                w.0, w.1, w.2
            );
        }
        for (i, (name, rb)) in beams(dim).into_iter().enumerate() {
            let w = check_relative(&rb, 22 + i as u64, 0.1);
            eprintln!("{name}: T {:.1e}, RᵀMR {:.1e}, Q {:.1e}", w.0, w.1, w.2);
        }
    }
}

// ---------------------------------------------------------------- rigid bar

/// `q = T p` for p = {r_i, r_j}: `r0 = r_i`, `u = (r_j − r_i)/L`.
fn two_point_map(len: f64) -> DMatrix<f64> {
    let mut t = DMatrix::<f64>::zeros(4, 4);
    t.view_mut((0, 0), (2, 2)).fill_with_identity();
    t.view_mut((2, 0), (2, 2))
        .copy_from(&(-Matrix2::identity() / len));
    t.view_mut((2, 2), (2, 2))
        .copy_from(&(Matrix2::identity() / len));
    t
}

/// 2D, n = 0, uniform bar of length L from points i (= r0) and j: the mass `Tᵀ M T`
/// is the classical `[m/3 I  m/6 I; m/6 I  m/3 I]` (docs/methods.md §3.1).
#[test]
fn rigid_bar_from_two_points() {
    let len = 1.5;
    let rb = beam_spec(Dim::Planar, "[[0,0],[1.5,0]]", "[]", 0, 8);
    assert_eq!(rb.n_modes(), 0);
    let body = FlexibleBody::new(&rb).unwrap();
    let m = body.mass();
    let mut ws = body.natural_workspace();
    let t = two_point_map(len);
    let mut r = rng(5);
    let i2 = Matrix2::identity();
    let mut expect = DMatrix::zeros(4, 4);
    expect.view_mut((0, 0), (2, 2)).copy_from(&(m / 3.0 * i2));
    expect.view_mut((0, 2), (2, 2)).copy_from(&(m / 6.0 * i2));
    expect.view_mut((2, 0), (2, 2)).copy_from(&(m / 6.0 * i2));
    expect.view_mut((2, 2), (2, 2)).copy_from(&(m / 3.0 * i2));
    for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
        // A rigid body's M does not depend on the configuration.
        let s = random_q(&mut r, Dim::Planar, 0, 1.0);
        let mut q = s.q.clone();
        let un = q.fixed_rows::<2>(2).normalize();
        q.fixed_rows_mut::<2>(2).copy_from(&un);
        let (mn, qv) = eval_natural(&body, &mut ws, &s.with_q(q).view(), method);
        assert_eq!(qv.amax(), 0.0);
        let mp = t.transpose() * mn * &t;
        let d = rel_diff_m(&mp, &expect);
        assert!(d < 1e-12, "{method:?}: bar mass {d:e}\n{mp}");
    }
    // The chain rule is the body point j = r0 + L u.
    let pj = BodyPoint::rigid(Vector3::new(len, 0.0, 0.0), 0);
    let st = NaturalState::planar(
        Vector2::new(0.3, -0.2),
        Vector2::new(0.6, 0.8),
        Vector2::zeros(),
        Vector2::zeros(),
        &[],
        &[],
    );
    let rj = body.point_position(&st, &pj);
    assert!((rj - Vector3::new(0.3 + 0.9, -0.2 + 1.2, 0.0)).norm() < 1e-15);
}

/// A general rigid planar cloud: `Tᵀ M T` equals the §3.1 integrals
/// `M_ii = ∫((1−c1)² + c2²) I`, `M_ij = ∫((1−c1)c1 − c2²) I + ∫c2 E`, `M_jj = ∫(c1² + c2²) I`
/// with `c1 = x̄/L`, `c2 = ȳ/L`.
#[test]
fn rigid_planar_cloud_two_points() {
    let mut r = rng(31);
    let rb = random_body(&mut r, Dim::Planar, 0, 15);
    let body = FlexibleBody::new(&rb).unwrap();
    let mut ws = body.natural_workspace();
    let len = 1.3;
    let (mut mii, mut mij_i, mut mij_e, mut mjj) = (0.0, 0.0, 0.0, 0.0);
    for k in 0..rb.cloud.len() {
        let w = rb.cloud.weights[k];
        let (c1, c2) = (rb.cloud.positions[k].x / len, rb.cloud.positions[k].y / len);
        mii += w * ((1.0 - c1).powi(2) + c2 * c2);
        mij_i += w * ((1.0 - c1) * c1 - c2 * c2);
        mij_e += w * c2;
        mjj += w * (c1 * c1 + c2 * c2);
    }
    let st = NaturalState::planar(
        Vector2::new(1.0, 2.0),
        Vector2::new(0.0, 1.0),
        Vector2::zeros(),
        Vector2::zeros(),
        &[],
        &[],
    );
    let (mn, _) = eval_natural(&body, &mut ws, &st, InertiaMethod::ShapeIntegrals);
    let t = two_point_map(len);
    let mp = t.transpose() * mn * &t;
    let i2 = Matrix2::identity();
    let mut e = DMatrix::zeros(4, 4);
    e.view_mut((0, 0), (2, 2)).copy_from(&(mii * i2));
    e.view_mut((0, 2), (2, 2))
        .copy_from(&(mij_i * i2 + mij_e * E));
    e.view_mut((2, 0), (2, 2))
        .copy_from(&(mij_i * i2 + mij_e * E.transpose()));
    e.view_mut((2, 2), (2, 2)).copy_from(&(mjj * i2));
    let d = rel_diff_m(&mp, &e);
    assert!(d < 1e-12, "§3.1 planar integrals: {d:e}\n{mp}\n{e}");
}

// ---------------------------------------------------------------- gravity

#[test]
fn gravity_rows() {
    let g = Vector3::new(0.3, -9.81, 1.2);
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut bodies: Vec<(String, ReducedBody)> = vec![];
        for n in [0usize, 3] {
            let mut r = rng(40 + n as u64);
            bodies.push((format!("random n={n}"), random_body(&mut r, dim, n, 20)));
        }
        for (name, rb) in beams(dim) {
            bodies.push((name.to_string(), rb));
        }
        for (i, (name, rb)) in bodies.iter().enumerate() {
            let body = FlexibleBody::new(rb).unwrap();
            let nc = body.n_natural_coords();
            let mut r = rng(50 + i as u64);
            let ys = if name.starts_with("random") { 1.0 } else { 0.1 };
            let s = random_q(&mut r, dim, body.n_modes(), ys);
            let st = s.view();
            let mut qg = vec![0.0; nc];
            // 2D bodies see the in-plane components only.
            let g_used = if dim == Dim::Planar {
                Vector3::new(g.x, g.y, 0.0)
            } else {
                g
            };
            body.gravity_natural(&st, &g_used, &mut qg);
            let qg = DVector::from_vec(qg);
            // Σ w_k B_kᵀ g.
            let gd = DVector::from_column_slice(&g.as_slice()[..dim.n_trans()]);
            let mut q_ref = DVector::zeros(nc);
            for k in 0..rb.cloud.len() {
                q_ref += rb.cloud.weights[k] * b_k(rb, k, &st).transpose() * &gd;
            }
            let d = rel_diff_v(&qg, &q_ref);
            assert!(d < 1e-12, "{name}: gravity vs Σ w Bᵀ g: {d:e}");
            // −∂V/∂q (V quadratic in q: central differences exact up to round-off).
            let h = 1e-5;
            let q_fd = -central_gradient(&s.q, h, |q| {
                body.natural_potential_energy(&s.with_q(q).view(), &g)
            });
            let d2 = rel_diff_v(&qg, &q_fd);
            assert!(d2 < 1e-8, "{name}: gravity vs −∂V/∂q: {d2:e}");
            eprintln!("{dim} {name}: Σ wBᵀg {d:.1e}, −∂V/∂q {d2:.1e}");
        }
    }
}

// ---------------------------------------------------------------- body points

#[test]
fn body_points() {
    for dim in [Dim::Planar, Dim::Spatial] {
        for (name, rb) in beams(dim) {
            let body = FlexibleBody::new(&rb).unwrap();
            let n = body.n_modes();
            let nc = body.n_natural_coords();
            let nt = dim.n_trans();
            let tip = rb.nodes.last().unwrap();
            let points = [
                BodyPoint::from_node(tip),
                BodyPoint::from_node(&rb.nodes[3]),
                BodyPoint::rigid(tip.position, n),
            ];
            let mut r = rng(60);
            let s = random_q(&mut r, dim, n, 0.1);
            let st = s.view();
            let h = 1e-5;
            let pos = |p: &BodyPoint, q: DVector<f64>| body.point_position(&s.with_q(q).view(), p);
            for p in &points {
                let mut jac = DMatrix::from_element(nt, nc, f64::NAN);
                body.point_jacobian(&st, p, &mut jac);
                // Jacobian by central differences (r_P bilinear: exact up to round-off).
                let mut jfd = DMatrix::zeros(nt, nc);
                for j in 0..nc {
                    let mut qp = s.q.clone();
                    qp[j] += h;
                    let mut qm = s.q.clone();
                    qm[j] -= h;
                    let d = (pos(p, qp) - pos(p, qm)) / (2.0 * h);
                    for i in 0..nt {
                        jfd[(i, j)] = d[i];
                    }
                }
                let dj = rel_diff_m(&jac, &jfd);
                assert!(dj < 1e-8, "{name}: point Jacobian {dj:e}");
                // Velocity = J q̇.
                let v = body.point_velocity(&st, p);
                let jv = &jac * &s.qd;
                for i in 0..nt {
                    assert!((v[i] - jv[i]).abs() < 1e-13 * jv.amax().max(1.0));
                }
                // Bias: d²/dt² r_P(q + t q̇) at t = 0 (q̈ = 0); exact for a quadratic.
                let ht = 1e-3;
                let rp = pos(p, &s.q + ht * &s.qd);
                let rm = pos(p, &s.q - ht * &s.qd);
                let acc = (rp - 2.0 * body.point_position(&st, p) + rm) / (ht * ht);
                let bias = body.point_bias(&st, p);
                let db = (acc - bias).amax() / bias.amax().max(1e-3);
                assert!(db < 1e-6, "{name}: bias {db:e} ({bias} vs {acc})");
                // Point-force rows = Jᵀ f.
                let f = Vector3::new(1.5, -2.0, if dim == Dim::Planar { 0.0 } else { 0.7 });
                let mut qf = vec![0.0; nc];
                body.add_point_force(&st, p, &f, &mut qf);
                let qf_ref = jac.transpose() * DVector::from_column_slice(&f.as_slice()[..nt]);
                let df = rel_diff_v(&DVector::from_vec(qf), &qf_ref);
                assert!(df < 1e-13, "{name}: point force rows {df:e}");
            }
            // The clamped root node moves with the frame origin.
            let root = BodyPoint::from_node(&rb.nodes[0]);
            let d = (body.point_position(&st, &root) - st.r0).norm();
            assert!(d < 1e-12, "{name}: root node at r0: {d:e}");
        }
    }
}

#[test]
fn coords_round_trip() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut r = rng(72);
        let s = random_q(&mut r, dim, 3, 1.0);
        let mut q = vec![0.0; s.q.len()];
        let mut qd = vec![0.0; s.q.len()];
        s.view().to_coords(dim, &mut q, &mut qd);
        assert_eq!(q.as_slice(), s.q.as_slice());
        assert_eq!(qd.as_slice(), s.qd.as_slice());
    }
}
