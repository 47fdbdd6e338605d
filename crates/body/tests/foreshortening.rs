//! FS0 (docs/methods.md §6.3) inertia terms on the spin-up beam (docs/scenes.md §5), 2D and 3D:
//!
//! * virtual power / Lagrange: along a smooth prescribed motion, Σ w_k J_kᵀ r̈_k =
//!   M̄ Ż − Q̄_v, with the point positions r_k = r0 + A (r̄_uk + X_k y − ½ ē₁ yᵀF_k y),
//!   r̈_k and Ż from differencing, and the velocity Jacobian J_k = ∂ṙ_k/∂Z built from
//!   finite differences of the positions in y (not from X̂_k); and the kinetic energy
//!   ½ ZᵀM̄Z = ½ Σ w_k |ṙ_k|²;
//! * the centrifugal hand check: at steady spin Ω about the root, the Ω² stiffness of
//!   the modal inertia force on pure bending modes is ∫N_c g_v g_vᵀ dx − Ω² ∫ρA X₂ᵀX₂ dx
//!   (in plane), N_c(x) = Ω² ρA (L² − x²)/2, and ∫N_c g_w g_wᵀ dx out of plane;
//! * the node helper against the kinematics.

mod common;
use common::{MotionSample, PrescribedMotion, d1, d2, rot_z, rz_ry_rx, spin_up_body};
use flexmbd_body::{BodyState, Dim, FlexibleBody, InertiaMethod};
use flexmbd_fe::ReducedBody;
use flexmbd_fe::beam::{VPLANE_2D, VPLANE_3D, WPLANE_3D, hermite};
use flexmbd_fe::cloud::element_local_modes;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

const L: f64 = 10.0;
const RHO_A: f64 = 1.2;

/// Smooth motion: r0(t), A(t) = Rz Ry Rx (Rz only in 2D), y(t).
struct Motion {
    dim: Dim,
    n: usize,
    ys: Vec<f64>,
}

fn f(a: f64, b: f64, c: f64, t: f64) -> f64 {
    a + b * t + c * (1.3 * t + 0.4 * a).sin()
}

impl Motion {
    /// The motion of the spin-up beam checks, its modal amplitudes falling as 1/(1 + j).
    fn new(dim: Dim, n: usize) -> Self {
        Self {
            dim,
            n,
            ys: (0..n).map(|j| 0.8 / (1.0 + j as f64)).collect(),
        }
    }
}

impl PrescribedMotion for Motion {
    fn r0(&self, t: f64) -> Vector3<f64> {
        let z = if self.dim == Dim::Planar {
            0.0
        } else {
            f(0.2, -0.3, 0.4, t)
        };
        Vector3::new(f(0.3, 0.5, -0.7, t), f(-0.4, 0.2, 0.6, t), z)
    }
    fn a(&self, t: f64) -> Matrix3<f64> {
        let alpha = f(0.5, 1.7, 0.9, t);
        if self.dim == Dim::Planar {
            return rot_z(alpha);
        }
        rz_ry_rx(alpha, f(-0.3, 0.8, 0.5, t), f(0.7, -0.6, 0.4, t))
    }
    fn y(&self, t: f64) -> Vec<f64> {
        // Tip deflections of order 1 m on the 10 m beam (mode rows are O(1)).
        (0..self.n)
            .map(|j| {
                let s = self.ys[j];
                f(0.6 * s, -0.4 * s, 0.5 * s, t + j as f64)
            })
            .collect()
    }
}

/// FS0 body-frame position of cloud point k.
fn rbar(rb: &ReducedBody, k: usize, y: &[f64]) -> Vector3<f64> {
    let fs = rb.foreshortening.as_ref().unwrap();
    let r = common::cloud_point(rb, k, y);
    let yv = DVector::from_column_slice(y);
    let q = (yv.transpose() * &fs.cloud[k] * &yv)[0];
    r - fs.axis * (0.5 * q)
}

/// ∂r_k/∂y_j of every cloud position at (r0, A, y), by differences in y_j (step 1e-4).
fn modal_column(
    rb: &ReducedBody,
    r0: Vector3<f64>,
    a: Matrix3<f64>,
    y: &[f64],
    j: usize,
) -> DVector<f64> {
    let shifted = |s: f64| {
        let mut yy = y.to_vec();
        yy[j] += s;
        positions(rb, r0, a, &yy)
    };
    d1(shifted, 0.0, 1e-4)
}

/// Residual of the virtual-power equations `lhs = Σ w J_kᵀ r̈_k = M ż − Q_v`, relative to the
/// largest of |lhs|, |M ż| and |Q_v|.
fn virtual_power_residual(
    lhs: &DVector<f64>,
    mm: &DMatrix<f64>,
    zd: &DVector<f64>,
    qv: &DVector<f64>,
) -> f64 {
    let rhs = mm * zd - qv;
    let scale = lhs.amax().max((mm * zd).amax()).max(qv.amax());
    (lhs - &rhs).amax() / scale
}

/// The virtual power of the cloud accelerations `rddot` along each mode j,
/// `Σ_k w_k (∂r_k/∂y_j) · r̈_k` ([`modal_column`] at (r0, A, y)), into `out` (n).
fn modal_virtual_power(
    rb: &ReducedBody,
    r0: Vector3<f64>,
    a: Matrix3<f64>,
    y: &[f64],
    rddot: &DVector<f64>,
    out: &mut [f64],
) {
    for (j, power) in out.iter_mut().enumerate() {
        *power = weighted_dot(rb, &modal_column(rb, r0, a, y, j), rddot);
    }
}

/// `Σ_k w_k u_k · v_k` over the cloud points of two stacked position-sized vectors.
fn weighted_dot(rb: &ReducedBody, u: &DVector<f64>, v: &DVector<f64>) -> f64 {
    let mut sum = 0.0;
    for k in 0..rb.cloud.len() {
        sum += rb.cloud.weights[k] * u.fixed_rows::<3>(3 * k).dot(&v.fixed_rows::<3>(3 * k));
    }
    sum
}

fn positions(rb: &ReducedBody, r0: Vector3<f64>, a: Matrix3<f64>, y: &[f64]) -> DVector<f64> {
    let np = rb.cloud.len();
    let mut out = DVector::zeros(3 * np);
    for k in 0..np {
        out.fixed_rows_mut::<3>(3 * k)
            .copy_from(&(r0 + a * rbar(rb, k, y)));
    }
    out
}

/// The spin-up beam of 8 elements with `modes` modes (and its FS0 data), built, and the test
/// motion of its frame and modes.
fn spin_up_fs0(dim: Dim, modes: usize) -> (ReducedBody, FlexibleBody, Motion) {
    let (rb, _) = spin_up_body(dim, 8, modes);
    let body = FlexibleBody::new(&rb).unwrap();
    let m = Motion::new(dim, rb.n_modes());
    (rb, body, m)
}

/// Largest relative residual of the virtual-power equations and of the kinetic energy.
fn lagrange(dim: Dim, modes: usize) -> (f64, f64) {
    let (rb, mut body, m) = spin_up_fs0(dim, modes);
    let n = rb.n_modes();
    assert!(body.has_foreshortening());
    let (h, nc, np) = (1e-3, body.n_coords(), rb.cloud.len());
    let (mut worst, mut worst_t) = (0.0_f64, 0.0_f64);
    for &t in &[0.0, 0.37, 1.1] {
        let sample = MotionSample::new(&m, dim, t, h);
        let (r0, a, y) = (sample.state.r0, sample.state.a, &sample.state.y);
        let (st, z, zd) = (sample.state.view(), &sample.z, &sample.z_dot);
        let pos_at = |t: f64| positions(&rb, m.r0(t), m.a(t), &m.y(t));
        let rdot = d1(pos_at, t, h);
        let rddot = d2(pos_at, t, h);
        let now = pos_at(t);
        // J columns: rigid ones from ṙ = ṡ + ω × r; modal ones ∂r/∂y_j by differences.
        let nr = nc - n;
        let mut jac = vec![DVector::zeros(3 * np); nc];
        for (i, col) in jac.iter_mut().enumerate().take(nr) {
            let (sd, w) = match (dim, i) {
                (Dim::Spatial, 0..=2) => (Vector3::ith(i, 1.0), Vector3::zeros()),
                (Dim::Spatial, _) => (Vector3::zeros(), Vector3::ith(i - 3, 1.0)),
                (Dim::Planar, 0..=1) => (Vector3::ith(i, 1.0), Vector3::zeros()),
                (Dim::Planar, _) => (Vector3::zeros(), Vector3::z()),
            };
            for k in 0..np {
                let rk = now.fixed_rows::<3>(3 * k).into_owned();
                col.fixed_rows_mut::<3>(3 * k)
                    .copy_from(&(sd + w.cross(&rk)));
            }
        }
        for j in 0..n {
            jac[nr + j] = modal_column(&rb, r0, a, y, j);
        }
        let mut lhs = DVector::<f64>::zeros(nc);
        let mut ke = 0.0;
        for k in 0..np {
            let w = rb.cloud.weights[k];
            for i in 0..nc {
                lhs[i] += w * jac[i]
                    .fixed_rows::<3>(3 * k)
                    .dot(&rddot.fixed_rows::<3>(3 * k));
            }
            ke += 0.5 * w * rdot.fixed_rows::<3>(3 * k).norm_squared();
        }
        let mut mm = DMatrix::zeros(nc, nc);
        let mut qv = DVector::zeros(nc);
        body.inertia(&st, InertiaMethod::BMatrix, &mut mm, &mut qv);
        worst = worst.max(virtual_power_residual(&lhs, &mm, zd, &qv));
        let ke_m = 0.5 * z.dot(&(&mm * z));
        worst_t = worst_t.max((ke - ke_m).abs() / ke);
    }
    (worst, worst_t)
}

#[test]
fn inertia_matches_finite_difference_lagrange_equations() {
    for (dim, modes) in [(Dim::Planar, 4), (Dim::Spatial, 8)] {
        let (e, et) = lagrange(dim, modes);
        eprintln!("FS0 {dim:?}: virtual power residual {e:.2e}, kinetic energy {et:.2e}");
        assert!(e < 1e-6, "{dim:?}: {e}");
        assert!(et < 1e-8, "{dim:?}: {et}");
    }
}

/// ∫₀ᴸ N_c (g_v g_vᵀ, g_w g_wᵀ) dx by 4-point Gauss per element (degree 6: exact).
fn centrifugal_geometric(rb: &ReducedBody, mesh: &flexmbd_fe::Mesh, om: f64) -> [DMatrix<f64>; 2] {
    let n = rb.n_modes();
    let mut out = [DMatrix::zeros(n, n), DMatrix::zeros(n, n)];
    let s = [1.0, -1.0, 1.0, -1.0];
    let mut x0 = 0.0;
    for (e, el) in mesh.elements.iter().enumerate() {
        let l = el.length;
        let xl = element_local_modes(mesh, e, &rb.modes);
        for &(t, wg) in flexmbd_fe::cloud::GAUSS4.iter() {
            let xi = 0.5 * (1.0 + t);
            let x = x0 + xi * l;
            let nc = om * om * RHO_A * (L * L - x * x) / 2.0;
            let (_, hd) = hermite(xi, l);
            let (gv, gw): (Vec<f64>, Vec<f64>) = (0..n)
                .map(|j| match mesh.dim {
                    Dim::Planar => (
                        (0..4).map(|q| hd[q] * xl[(VPLANE_2D[q], j)]).sum::<f64>(),
                        0.0,
                    ),
                    Dim::Spatial => (
                        (0..4).map(|q| hd[q] * xl[(VPLANE_3D[q], j)]).sum::<f64>(),
                        (0..4)
                            .map(|q| s[q] * hd[q] * xl[(WPLANE_3D[q], j)])
                            .sum::<f64>(),
                    ),
                })
                .unzip();
            let w = nc * 0.5 * l * wg;
            for i in 0..n {
                for j in 0..n {
                    out[0][(i, j)] += w * gv[i] * gv[j];
                    out[1][(i, j)] += w * gw[i] * gw[j];
                }
            }
        }
        x0 += l;
    }
    out
}

/// −∂Q̄_v,y/∂y at y = 0, steady spin Ω about the root (r0 = 0, ṡ = 0, ẏ = 0), by a
/// Richardson pair of central differences (exact for the cubic Q̄_v,y(y)).
fn spin_stiffness(body: &mut FlexibleBody, om: f64) -> DMatrix<f64> {
    let n = body.n_modes();
    let nc = body.n_coords();
    let nr = nc - n;
    let q = |body: &mut FlexibleBody, y: &[f64]| {
        let yd = vec![0.0; n];
        let st = BodyState {
            r0: Vector3::zeros(),
            a: Matrix3::identity(),
            omega: Vector3::new(0.0, 0.0, om),
            s_dot: Vector3::zeros(),
            y,
            y_dot: &yd,
        };
        let mut mm = DMatrix::zeros(nc, nc);
        let mut qv = DVector::zeros(nc);
        body.inertia(&st, InertiaMethod::BMatrix, &mut mm, &mut qv);
        qv.rows(nr, n).into_owned()
    };
    let d = 1e-3;
    let mut k = DMatrix::zeros(n, n);
    for j in 0..n {
        let at = |body: &mut FlexibleBody, s: f64| {
            let mut y = vec![0.0; n];
            y[j] = s;
            q(body, &y)
        };
        let c1 = at(body, d) - at(body, -d);
        let c2 = at(body, 2.0 * d) - at(body, -2.0 * d);
        let col = (c1 * 8.0 - c2) / (12.0 * d);
        k.set_column(j, &(-col));
    }
    k
}

#[test]
fn centrifugal_stiffness_hand_check() {
    let om = 6.0;
    // 2D: ∫N_c g_v g_vᵀ − Ω² ∫ρA X₂ᵀX₂ (= Ω² M_ff for pure bending modes, consistent mass).
    let (rb, mesh) = spin_up_body(Dim::Planar, 20, 4);
    let mut body = FlexibleBody::new(&rb).unwrap();
    let k = spin_stiffness(&mut body, om);
    let [kv, _] = centrifugal_geometric(&rb, &mesh, om);
    let expect = &kv - &rb.m_ff * (om * om);
    let e2 = (&k - &expect).amax() / expect.amax();
    eprintln!(
        "hand check 2D: relative error {e2:.2e} (|K_Ω| = {:.4e})",
        expect.amax()
    );
    assert!(e2 < 1e-9, "{e2}");
    // 3D, spin about z: in-plane (v) as in 2D, out-of-plane (w) only ∫N_c g_w g_wᵀ. The
    // section-point cloud also carries the section rotations (rotary inertia), so the
    // softening is Ω² Σ w (X₁ᵀX₁ + X₂ᵀX₂) of the cloud (X₁ = rotary part for bending modes).
    let (rb, mesh) = spin_up_body(Dim::Spatial, 20, 8);
    let mut body = FlexibleBody::new(&rb).unwrap();
    let k = spin_stiffness(&mut body, om);
    let [kv, kw] = centrifugal_geometric(&rb, &mesh, om);
    let n = rb.n_modes();
    let mut s12 = DMatrix::zeros(n, n);
    for kk in 0..rb.cloud.len() {
        let x = rb.cloud.rows(kk);
        for i in 0..n {
            for j in 0..n {
                s12[(i, j)] += rb.cloud.weights[kk] * (x[i] * x[j] + x[n + i] * x[n + j]);
            }
        }
    }
    let expect = &kv + &kw - s12 * (om * om);
    let e3 = (&k - &expect).amax() / expect.amax();
    eprintln!("hand check 3D: relative error {e3:.2e}");
    assert!(e3 < 1e-9, "{e3}");
}

#[test]
fn node_helper_matches_kinematics_and_routes() {
    let (rb, _) = spin_up_body(Dim::Planar, 20, 4);
    let body = FlexibleBody::new(&rb).unwrap();
    let fs = rb.foreshortening.as_ref().unwrap();
    let y = [0.3, -0.1, 0.05, 0.02];
    let yd = [0.7, 0.2, -0.3, 0.1];
    let tip = rb.nodes.len() - 1;
    let sh = body.node_foreshortening(tip, &y, &yd).unwrap();
    let yv = DVector::from_column_slice(&y);
    let ydv = DVector::from_column_slice(&yd);
    let f = &fs.nodes[tip];
    assert!((sh.position.x + 0.5 * (yv.transpose() * f * &yv)[0]).abs() < 1e-14);
    assert!((sh.velocity.x + (ydv.transpose() * f * &yv)[0]).abs() < 1e-14);
    assert!((sh.bias.x + (ydv.transpose() * f * &ydv)[0]).abs() < 1e-14);
    assert_eq!(sh.position.y, 0.0);
    // The root does not move; the Jacobian is the rate's coefficient.
    let root = body.node_foreshortening(0, &y, &yd).unwrap();
    assert_eq!(root.position, Vector3::zeros());
    let mut j = DMatrix::zeros(3, 4);
    body.add_node_foreshortening_jacobian(tip, &y, &mut j);
    assert!((j.row(0).dot(&ydv.transpose()) - sh.velocity.x).abs() < 1e-13);
    // Both routes evaluate a foreshortened body (tests/fs0_routes.rs compares them).
    body.check_inertia_method(InertiaMethod::ShapeIntegrals)
        .unwrap();
    body.check_inertia_method(InertiaMethod::BMatrix).unwrap();
    // Without FS0 data nothing changes.
    let mut plain = rb.clone();
    plain.foreshortening = None;
    let p = FlexibleBody::new(&plain).unwrap();
    assert!(p.node_foreshortening(tip, &y, &yd).is_none());
    p.check_inertia_method(InertiaMethod::ShapeIntegrals)
        .unwrap();
    // At y = 0 FS0 equals the plain B-matrix route.
    let (mut b1, mut b2) = (body.clone(), p.clone());
    let z = [0.0; 4];
    let st = BodyState::planar(
        nalgebra::Vector2::new(0.3, -0.2),
        0.4,
        nalgebra::Vector2::new(0.1, 0.5),
        1.3,
        &z,
        &yd,
    );
    let (mut m1, mut q1, mut m2, mut q2) = (
        DMatrix::zeros(7, 7),
        DVector::zeros(7),
        DMatrix::zeros(7, 7),
        DVector::zeros(7),
    );
    b1.inertia(&st, InertiaMethod::BMatrix, &mut m1, &mut q1);
    b2.inertia(&st, InertiaMethod::BMatrix, &mut m2, &mut q2);
    assert!((&m1 - &m2).amax() < 1e-12 * m2.amax());
    // Q differs by the velocity-product term −Σ w B_kᵀ A ē₁ ẏᵀF_k ẏ only.
    assert!((&q1 - &q2).amax() > 0.0);
}

#[test]
fn gravity_and_first_moment_include_the_shortening() {
    for (dim, modes) in [(Dim::Planar, 4), (Dim::Spatial, 8)] {
        let (rb, body, m) = spin_up_fs0(dim, modes);
        let n = rb.n_modes();
        let (r0, a, y) = (m.r0(0.3), m.a(0.3), m.y(0.3));
        let g = match dim {
            Dim::Planar => Vector3::new(3.0, -9.81, 0.0),
            Dim::Spatial => Vector3::new(2.0, 1.0, -9.81),
        };
        // m̄(y) = Σ w r̄_k(y).
        let mut mb = Vector3::zeros();
        for k in 0..rb.cloud.len() {
            mb += rb.cloud.weights[k] * rbar(&rb, k, &y);
        }
        let e = (body.first_moment_at(&y) - mb).amax() / mb.amax();
        assert!(e < 1e-13, "{dim:?}: first moment {e}");
        // Modal gravity force = ∂/∂y (g · Σ w r_k) by central differences.
        let yd = vec![0.0; n];
        let st = BodyState {
            r0,
            a,
            omega: Vector3::zeros(),
            s_dot: Vector3::zeros(),
            y: &y,
            y_dot: &yd,
        };
        let nc = body.n_coords();
        let mut out = vec![0.0; nc];
        body.gravity_forces(&st, &g, &mut out);
        let pot = |yy: &[f64]| {
            let p = positions(&rb, r0, a, yy);
            (0..rb.cloud.len())
                .map(|k| rb.cloud.weights[k] * g.dot(&p.fixed_rows::<3>(3 * k)))
                .sum::<f64>()
        };
        let mut worst = 0.0_f64;
        let scale = out[nc - n..].iter().fold(0.0_f64, |s, v| s.max(v.abs()));
        for j in 0..n {
            let d = 1e-4;
            let at = |s: f64| {
                let mut yy = y.clone();
                yy[j] += s;
                pot(&yy)
            };
            let fd = (at(-2.0 * d) - 8.0 * at(-d) + 8.0 * at(d) - at(2.0 * d)) / (12.0 * d);
            worst = worst.max((fd - out[nc - n + j]).abs() / scale);
        }
        eprintln!("FS0 {dim:?}: modal gravity vs potential gradient {worst:.2e}");
        if dim == Dim::Planar {
            // Natural coordinates: the same modal gravity force.
            let u = a.column(0).xy();
            let z2 = nalgebra::Vector2::zeros();
            let nat = flexmbd_body::NaturalState::planar(r0.xy(), u, z2, z2, &y, &yd);
            let mut gn = vec![0.0; 4 + n];
            body.gravity_natural(&nat, &g, &mut gn);
            for j in 0..n {
                assert!((gn[4 + j] - out[nc - n + j]).abs() < 1e-12 * scale);
            }
        }
        assert!(worst < 1e-8, "{dim:?}: {worst}");
    }
}

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn fs0_evaluation_allocates_nothing() {
    for (dim, modes) in [(Dim::Planar, 4), (Dim::Spatial, 8)] {
        let (rb, _) = spin_up_body(dim, 8, modes);
        let n = rb.n_modes();
        let mut body = FlexibleBody::new(&rb).unwrap();
        let m = Motion {
            dim,
            n,
            ys: vec![0.3; n],
        };
        let (y, yd) = (m.y(0.2), m.y(0.5));
        let st = BodyState {
            r0: m.r0(0.2),
            a: m.a(0.2),
            omega: Vector3::new(0.1, -0.2, 1.3),
            s_dot: Vector3::new(0.4, 0.1, -0.2),
            y: &y,
            y_dot: &yd,
        };
        let st = if dim == Dim::Planar {
            BodyState {
                omega: Vector3::new(0.0, 0.0, 1.3),
                s_dot: Vector3::new(0.4, 0.1, 0.0),
                ..st
            }
        } else {
            st
        };
        let nc = body.n_coords();
        let (mut mm, mut q, mut qg) = (DMatrix::zeros(nc, nc), DVector::zeros(nc), vec![0.0; nc]);
        let g = Vector3::new(0.0, -9.81, 0.0);
        let before = flexmbd_test_support::allocations();
        for _ in 0..3 {
            body.inertia(&st, InertiaMethod::BMatrix, &mut mm, &mut q);
            body.inertia_origin(&st, InertiaMethod::BMatrix, &mut mm, &mut q);
            body.gravity_forces(&st, &g, &mut qg);
            let sh = body.node_foreshortening(8, &y, &yd).unwrap();
            assert!(sh.position.x < 0.0);
        }
        assert_eq!(flexmbd_test_support::allocations(), before, "{dim:?}");
    }
}

/// Planar natural coordinates q = {r0, u, y} with a non-unit u(t): Σ w J_kᵀ r̈_k =
/// M q̈ − Q_v, with r_k = r0 + [u  E u] r̄_k(y) and J_k from the position law
/// (∂r/∂r0 = I, ∂r/∂u = r̄1 I + r̄2 E, ∂r/∂y by differences).
#[test]
fn natural_planar_inertia_matches_virtual_power() {
    let (rb, body, m) = spin_up_fs0(Dim::Planar, 4);
    let n = rb.n_modes();
    let mut nws = body.natural_workspace();
    let uvec = |t: f64| {
        let (s, c) = f(0.5, 1.7, 0.9, t).sin_cos();
        nalgebra::Vector2::new(c, s) * (1.0 + 0.1 * (2.0 * t).sin())
    };
    let amat = |t: f64| {
        let u = uvec(t);
        Matrix3::new(u.x, -u.y, 0.0, u.y, u.x, 0.0, 0.0, 0.0, 1.0)
    };
    let qvec = |t: f64| {
        let (r0, u) = (m.r0(t), uvec(t));
        let mut v = vec![r0.x, r0.y, u.x, u.y];
        v.extend(m.y(t));
        DVector::from_vec(v)
    };
    let pos_at = |t: f64| positions(&rb, m.r0(t), amat(t), &m.y(t));
    let (h, np, nc) = (1e-3, rb.cloud.len(), 4 + n);
    let mut worst = 0.0_f64;
    for &t in &[0.0, 0.37, 1.1] {
        let (q, qd, qdd) = (qvec(t), d1(qvec, t, h), d2(qvec, t, h));
        let y: Vec<f64> = q.rows(4, n).iter().copied().collect();
        let yd: Vec<f64> = qd.rows(4, n).iter().copied().collect();
        let st = flexmbd_body::NaturalState::planar(
            q.fixed_rows::<2>(0).into_owned(),
            q.fixed_rows::<2>(2).into_owned(),
            qd.fixed_rows::<2>(0).into_owned(),
            qd.fixed_rows::<2>(2).into_owned(),
            &y,
            &yd,
        );
        let mut mm = DMatrix::zeros(nc, nc);
        let mut qv = DVector::zeros(nc);
        body.inertia_natural(&st, InertiaMethod::BMatrix, &mut nws, &mut mm, &mut qv);
        let rddot = d2(pos_at, t, h);
        let (r0, a) = (m.r0(t), amat(t));
        let mut lhs = DVector::<f64>::zeros(nc);
        for k in 0..np {
            let w = rb.cloud.weights[k];
            let acc = rddot.fixed_rows::<3>(3 * k).into_owned();
            let rbk = rbar(&rb, k, &y);
            lhs[0] += w * acc.x;
            lhs[1] += w * acc.y;
            // ∂r/∂u_x = (r̄1, r̄2), ∂r/∂u_y = (−r̄2, r̄1).
            lhs[2] += w * (rbk.x * acc.x + rbk.y * acc.y);
            lhs[3] += w * (-rbk.y * acc.x + rbk.x * acc.y);
        }
        modal_virtual_power(&rb, r0, a, &y, &rddot, &mut lhs.as_mut_slice()[4..]);
        worst = worst.max(virtual_power_residual(&lhs, &mm, &qdd, &qv));
    }
    eprintln!("FS0 natural planar: virtual power residual {worst:.2e}");
    assert!(worst < 1e-6, "{worst}");
}

/// Spatial natural coordinates q = {r0, u, v, w, y} with a non-orthonormal A(t) = R(t)(I + εS(t)):
/// Σ w J_kᵀ r̈_k = M q̈ − Q_v for both routes, with r_k = r0 + A r̄_k(y), J_k from the position
/// law (∂r/∂r0 = I, ∂r/∂e_a = r̄_a I, ∂r/∂y by differences) and r̈_k, q̇, q̈ by differencing.
#[test]
fn natural_spatial_inertia_matches_virtual_power() {
    let (rb, body, m) = spin_up_fs0(Dim::Spatial, 8);
    let n = rb.n_modes();
    let mut nws = body.natural_workspace();
    let amat = |t: f64| {
        let s = Matrix3::new(
            (1.1 * t).sin(),
            0.3 * t,
            -0.2,
            0.1,
            (0.7 * t).cos(),
            0.4 * t,
            -0.3 * t,
            0.2,
            (0.5 * t).sin(),
        );
        m.a(t) * (Matrix3::identity() + 0.05 * s)
    };
    let qvec = |t: f64| {
        let (r0, a) = (m.r0(t), amat(t));
        let mut v: Vec<f64> = r0.iter().copied().collect();
        v.extend(a.iter().copied()); // column-major: u, v, w
        v.extend(m.y(t));
        DVector::from_vec(v)
    };
    let pos_at = |t: f64| positions(&rb, m.r0(t), amat(t), &m.y(t));
    let (h, np, nc) = (1e-3, rb.cloud.len(), 12 + n);
    let mut worst = [0.0_f64; 2];
    for &t in &[0.0, 0.37, 1.1] {
        let (q, qd, qdd) = (qvec(t), d1(qvec, t, h), d2(qvec, t, h));
        let y: Vec<f64> = q.rows(12, n).iter().copied().collect();
        let yd: Vec<f64> = qd.rows(12, n).iter().copied().collect();
        let st = flexmbd_body::NaturalState {
            r0: Vector3::new(q[0], q[1], q[2]),
            a: Matrix3::from_column_slice(&q.as_slice()[3..12]),
            r0_dot: Vector3::new(qd[0], qd[1], qd[2]),
            a_dot: Matrix3::from_column_slice(&qd.as_slice()[3..12]),
            y: &y,
            y_dot: &yd,
        };
        let rddot = d2(pos_at, t, h);
        let (r0, a) = (m.r0(t), amat(t));
        let mut lhs = DVector::<f64>::zeros(nc);
        for k in 0..np {
            let w = rb.cloud.weights[k];
            let acc = rddot.fixed_rows::<3>(3 * k).into_owned();
            let rbk = rbar(&rb, k, &y);
            for i in 0..3 {
                lhs[i] += w * acc[i];
                for b in 0..3 {
                    lhs[3 + 3 * b + i] += w * rbk[b] * acc[i];
                }
            }
        }
        modal_virtual_power(&rb, r0, a, &y, &rddot, &mut lhs.as_mut_slice()[12..]);
        for (r, method) in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals]
            .into_iter()
            .enumerate()
        {
            let mut mm = DMatrix::zeros(nc, nc);
            let mut qv = DVector::zeros(nc);
            body.inertia_natural(&st, method, &mut nws, &mut mm, &mut qv);
            worst[r] = worst[r].max(virtual_power_residual(&lhs, &mm, &qdd, &qv));
        }
    }
    eprintln!(
        "FS0 natural spatial: virtual power residual {:.2e} (B-matrix), {:.2e} (shape integrals)",
        worst[0], worst[1]
    );
    // Measured 2.1e-11 for both routes (the differencing's own error); bound 1e-8.
    assert!(worst[0] < 1e-8 && worst[1] < 1e-8, "{worst:?}");
}
