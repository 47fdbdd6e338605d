//! Shared helpers of the body tests: random clouds, rotations and states (relative and
//! natural sets), the FE beams the
//! tests reduce, evaluation into fresh storage, cloud-point positions and the finite
//! differences the physics checks difference motions with.
#![allow(dead_code)]

use flexmbd_body::{BodyState, Dim, FlexibleBody, InertiaMethod, NaturalState, NaturalWorkspace};
use flexmbd_fe::foreshortening::foreshortening;
use flexmbd_fe::{
    BeamBodySpec, MassCloud, Mesh, ModeInventory, ReducedBody, ShapeIntegrals, StiffeningIntegrals,
    preprocess, reduce,
};
use nalgebra::{DMatrix, DVector, Matrix2, Matrix3, Quaternion, UnitQuaternion, Vector2, Vector3};
use rand::{Rng, RngExt, SeedableRng, rngs::StdRng};

pub fn rng(seed: u64) -> StdRng {
    StdRng::seed_from_u64(seed)
}

pub fn uni<R: Rng>(r: &mut R, lo: f64, hi: f64) -> f64 {
    r.random_range(lo..hi)
}

pub fn rand_vec<R: Rng>(r: &mut R, s: f64) -> Vector3<f64> {
    Vector3::new(uni(r, -s, s), uni(r, -s, s), uni(r, -s, s))
}

pub fn rand_rotation<R: Rng>(r: &mut R) -> Matrix3<f64> {
    let q = Quaternion::new(
        uni(r, -1.0, 1.0),
        uni(r, -1.0, 1.0),
        uni(r, -1.0, 1.0),
        uni(r, -1.0, 1.0),
    );
    UnitQuaternion::from_quaternion(q)
        .to_rotation_matrix()
        .into_inner()
}

pub fn rot_z(t: f64) -> Matrix3<f64> {
    let (s, c) = t.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// A reduced body around a given cloud: K_ff random SPD, C_ff = 0.01 K_ff.
pub fn body_from_cloud<R: Rng>(r: &mut R, dim: Dim, cloud: MassCloud) -> ReducedBody {
    let n = cloud.n_modes;
    let q = DMatrix::from_fn(n, n, |_, _| uni(r, -1.0, 1.0));
    let k_ff = &q * q.transpose() + DMatrix::identity(n, n) * (n as f64);
    let c_ff = 0.01 * &k_ff;
    body_with_cloud(dim, cloud, k_ff, c_ff)
}

/// A reduced body of a cloud alone (no FE data): the cloud's shape integrals, its modal mass
/// `M_ff = Σ_a Sᵃᵃ`, and the given stiffness and damping.
pub fn body_with_cloud(
    dim: Dim,
    cloud: MassCloud,
    k_ff: DMatrix<f64>,
    c_ff: DMatrix<f64>,
) -> ReducedBody {
    let n = cloud.n_modes;
    let si = ShapeIntegrals::from_cloud(&cloud);
    let mut m_ff = DMatrix::zeros(n, n);
    for a in 0..3 {
        m_ff += &si.s_ab[a][a];
    }
    ReducedBody {
        dim,
        inventory: ModeInventory {
            n_fe_dofs: 0,
            frame_dofs: vec![],
            static_modes: vec![],
            normal_frequencies_hz: vec![1.0; n],
            selection: Default::default(),
            reference: Default::default(),
            point_names: Vec::new(),
        },
        modes: DMatrix::zeros(0, n),
        m_ff,
        k_ff,
        c_ff,
        cloud,
        shape_integrals: si,
        nodes: vec![],
        stiffening: StiffeningIntegrals::default(),
        foreshortening: None,
    }
}

/// A random cloud: positions in a box, positive weights, random mode rows (z = 0 in 2D).
pub fn random_body<R: Rng>(r: &mut R, dim: Dim, n: usize, np: usize) -> ReducedBody {
    let mut positions = Vec::new();
    let mut weights = Vec::new();
    let mut mode_rows = Vec::new();
    for _ in 0..np {
        let mut p = Vector3::new(uni(r, -0.5, 2.0), uni(r, -0.4, 0.4), uni(r, -0.3, 0.3));
        if dim == Dim::Planar {
            p.z = 0.0;
        }
        positions.push(p);
        weights.push(uni(r, 0.1, 1.0));
        for a in 0..3 {
            for _ in 0..n {
                let v = if dim == Dim::Planar && a == 2 {
                    0.0
                } else {
                    uni(r, -0.3, 0.3)
                };
                mode_rows.push(v);
            }
        }
    }
    let cloud = MassCloud {
        n_modes: n,
        positions,
        weights,
        mode_rows,
        description: format!("random cloud, {np} points"),
    };
    body_from_cloud(r, dim, cloud)
}

pub struct OwnedState {
    pub r0: Vector3<f64>,
    pub a: Matrix3<f64>,
    pub omega: Vector3<f64>,
    pub s_dot: Vector3<f64>,
    pub y: Vec<f64>,
    pub y_dot: Vec<f64>,
}

impl OwnedState {
    /// A body without modes at rest with its frame at `r0`, unrotated.
    pub fn rigid_at_rest(r0: Vector3<f64>) -> Self {
        Self {
            r0,
            a: Matrix3::identity(),
            omega: Vector3::zeros(),
            s_dot: Vector3::zeros(),
            y: vec![],
            y_dot: vec![],
        }
    }

    pub fn view(&self) -> BodyState<'_> {
        BodyState {
            r0: self.r0,
            a: self.a,
            omega: self.omega,
            s_dot: self.s_dot,
            y: &self.y,
            y_dot: &self.y_dot,
        }
    }
}

pub fn random_state<R: Rng>(r: &mut R, dim: Dim, n: usize) -> OwnedState {
    let y: Vec<f64> = (0..n).map(|_| uni(r, -0.5, 0.5)).collect();
    let y_dot: Vec<f64> = (0..n).map(|_| uni(r, -2.0, 2.0)).collect();
    match dim {
        Dim::Spatial => OwnedState {
            r0: rand_vec(r, 2.0),
            a: rand_rotation(r),
            omega: rand_vec(r, 3.0),
            s_dot: rand_vec(r, 2.0),
            y,
            y_dot,
        },
        Dim::Planar => {
            let mut r0 = rand_vec(r, 2.0);
            r0.z = 0.0;
            let mut s_dot = rand_vec(r, 2.0);
            s_dot.z = 0.0;
            OwnedState {
                r0,
                a: rot_z(uni(r, -3.0, 3.0)),
                omega: Vector3::new(0.0, 0.0, uni(r, -3.0, 3.0)),
                s_dot,
                y,
                y_dot,
            }
        }
    }
}

/// Rigid natural coordinates of one body: 4 in 2D (r0, u), 12 in 3D (r0, u, v, w).
pub fn n_rigid(dim: Dim) -> usize {
    if dim == Dim::Planar { 4 } else { 12 }
}

/// Coordinates and velocities of one body in the natural set.
#[derive(Clone)]
pub struct Q {
    pub dim: Dim,
    pub q: DVector<f64>,
    pub qd: DVector<f64>,
}

impl Q {
    pub fn view(&self) -> NaturalState<'_> {
        NaturalState::from_coords(self.dim, self.q.as_slice(), self.qd.as_slice())
    }
    pub fn with_q(&self, q: DVector<f64>) -> Q {
        Q {
            dim: self.dim,
            q,
            qd: self.qd.clone(),
        }
    }
}

/// A random state off the manifold: 3D `A = R (I + N)`, |N_ij| ≤ 0.25; 2D `|u| ∈ [0.7, 1.3]`.
pub fn random_q<R: Rng>(r: &mut R, dim: Dim, n: usize, y_scale: f64) -> Q {
    let nr = n_rigid(dim);
    let mut q = DVector::zeros(nr + n);
    let mut qd = DVector::zeros(nr + n);
    match dim {
        Dim::Spatial => {
            let pert = Matrix3::from_fn(|_, _| uni(r, -0.25, 0.25));
            let a = rand_rotation(r) * (Matrix3::identity() + pert);
            let ad = Matrix3::from_fn(|_, _| uni(r, -2.0, 2.0));
            q.fixed_rows_mut::<3>(0).copy_from(&rand_vec(r, 2.0));
            qd.fixed_rows_mut::<3>(0).copy_from(&rand_vec(r, 2.0));
            for c in 0..3 {
                q.fixed_rows_mut::<3>(3 + 3 * c).copy_from(&a.column(c));
                qd.fixed_rows_mut::<3>(3 + 3 * c).copy_from(&ad.column(c));
            }
        }
        Dim::Planar => {
            let t = uni(r, -3.0, 3.0);
            let s = uni(r, 0.7, 1.3);
            q[0] = uni(r, -2.0, 2.0);
            q[1] = uni(r, -2.0, 2.0);
            q[2] = s * t.cos();
            q[3] = s * t.sin();
            for i in 0..4 {
                qd[i] = uni(r, -2.0, 2.0);
            }
        }
    }
    for j in 0..n {
        q[nr + j] = y_scale * uni(r, -0.5, 0.5);
        qd[nr + j] = uni(r, -2.0, 2.0);
    }
    Q { dim, q, qd }
}

pub fn eval(
    body: &mut FlexibleBody,
    st: &BodyState<'_>,
    method: InertiaMethod,
) -> (DMatrix<f64>, DVector<f64>) {
    written(body.n_coords(), |m, q| body.inertia(st, method, m, q))
}

/// M (nc × nc) and Q (nc) written by `fill` into NaN-filled storage, checked that every entry
/// is written.
fn written(
    nc: usize,
    fill: impl FnOnce(&mut DMatrix<f64>, &mut DVector<f64>),
) -> (DMatrix<f64>, DVector<f64>) {
    let mut m = DMatrix::from_element(nc, nc, f64::NAN);
    let mut q = DVector::from_element(nc, f64::NAN);
    fill(&mut m, &mut q);
    assert!(m.iter().all(|v| v.is_finite()), "every entry of M written");
    assert!(
        q.iter().all(|v| v.is_finite()),
        "every entry of Q_v written"
    );
    (m, q)
}

/// max |a − b| / max |b|.
pub fn rel_diff_m(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    assert_eq!(a.shape(), b.shape());
    let scale = b.amax().max(f64::MIN_POSITIVE);
    (a - b).amax() / scale
}

pub fn rel_diff_v(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.amax().max(f64::MIN_POSITIVE);
    (a - b).amax() / scale
}

/// Route evaluation in natural coordinates into fresh storage, checking that every entry
/// is written.
pub fn eval_natural(
    body: &FlexibleBody,
    ws: &mut NaturalWorkspace,
    st: &NaturalState<'_>,
    method: InertiaMethod,
) -> (DMatrix<f64>, DVector<f64>) {
    written(body.n_natural_coords(), |m, q| {
        body.inertia_natural(st, method, ws, m, q)
    })
}

/// A steel beam of 0.02 × 0.01 section along the polyline `points` (RON), clamped at node 0,
/// with the static `boundary` modes and `normal` normal modes, reduced by `flexmbd_fe::reduce`.
pub fn beam_spec(
    dim: Dim,
    points: &str,
    boundary: &str,
    normal: usize,
    elems: usize,
) -> ReducedBody {
    let d = if dim == Dim::Planar {
        "Planar"
    } else {
        "Spatial"
    };
    let text = format!(
        "(dim: {d}, material: (young_modulus: 2.1e11, density: 7850.0, poisson_ratio: Some(0.3)),
          section: Rectangle(width: 0.02, height: 0.01),
          geometry: (points: {points}, elements_per_segment: {elems}),
          frame: Clamped(node: 0), boundary: {boundary}, normal_modes: {normal})"
    );
    let s = BeamBodySpec::from_ron_str(&text, "test beam").unwrap();
    reduce(&s).unwrap()
}

/// The FE beams the route checks run on: a straight cantilever and an L-shaped beam with
/// static modes at the corner.
pub fn beams(dim: Dim) -> Vec<(&'static str, ReducedBody)> {
    match dim {
        Dim::Spatial => vec![
            (
                "3D straight",
                beam_spec(dim, "[[0,0,0],[1,0,0]]", "[]", 6, 10),
            ),
            (
                "3D L-beam + static",
                beam_spec(
                    dim,
                    "[[0,0,0],[0.6,0,0],[0.6,0.4,0]]",
                    "[(node: 12, dof: Uz), (node: 12, dof: Uy)]",
                    5,
                    6,
                ),
            ),
        ],
        Dim::Planar => vec![
            ("2D straight", beam_spec(dim, "[[0,0],[1,0]]", "[]", 4, 10)),
            (
                "2D L-beam + static",
                beam_spec(
                    dim,
                    "[[0,0],[0.6,0],[0.6,0.4]]",
                    "[(node: 12, dof: Ux), (node: 12, dof: Uy)]",
                    3,
                    6,
                ),
            ),
        ],
    }
}

/// The spin-up beam (docs/scenes.md §5: 10 m, clamped at the root) with its FS0 data, and the
/// mesh it was reduced from.
pub fn spin_up_body(dim: Dim, elements: usize, modes: usize) -> (ReducedBody, Mesh) {
    let (d, pts) = match dim {
        Dim::Planar => ("Planar", "[[0.0, 0.0], [10.0, 0.0]]"),
        Dim::Spatial => ("Spatial", "[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]"),
    };
    let text = format!(
        "(dim: {d}, material: (young_modulus: 7e10, density: 3000.0, poisson_ratio: None, shear_modulus: Some(3.5e10)),
          section: General(area: 4e-4, iy: 2e-7, iz: 2e-7, torsion_j: 4e-7),
          geometry: (points: {pts}, elements_per_segment: {elements}),
          frame: Clamped(node: 0), boundary: [], normal_modes: {modes})"
    );
    let spec = BeamBodySpec::from_ron_str(&text, "spin-up beam").unwrap();
    let p = preprocess(&spec).unwrap();
    let mut rb = p.body;
    rb.foreshortening = Some(foreshortening(&p.mesh, &rb.modes).unwrap());
    (rb, p.mesh)
}

/// Body-frame position of cloud point k of a linear body at modal coordinates y: `r̄_k + X_k y`.
pub fn cloud_point(rb: &ReducedBody, k: usize, y: &[f64]) -> Vector3<f64> {
    let n = y.len();
    let x = rb.cloud.rows(k);
    let mut p = rb.cloud.positions[k];
    for c in 0..3 {
        for j in 0..n {
            p[c] += x[c * n + j] * y[j];
        }
    }
    p
}

/// The rows of the spatial relative set {ṡ; ω; ẏ} (6 + n) a body of `dim` keeps: all in 3D,
/// ṡx, ṡy, ωz and the modes in 2D.
pub fn kept_rows(dim: Dim, n: usize) -> Vec<usize> {
    match dim {
        Dim::Spatial => (0..6 + n).collect(),
        Dim::Planar => [0, 1, 5].into_iter().chain(6..6 + n).collect(),
    }
}

/// 4th-order central first derivative of a vector function.
pub fn d1<F: Fn(f64) -> DVector<f64>>(g: F, t: f64, h: f64) -> DVector<f64> {
    (g(t - 2.0 * h) - 8.0 * g(t - h) + 8.0 * g(t + h) - g(t + 2.0 * h)) / (12.0 * h)
}

/// 4th-order central second derivative of a vector function.
pub fn d2<F: Fn(f64) -> DVector<f64>>(g: F, t: f64, h: f64) -> DVector<f64> {
    (-g(t - 2.0 * h) + 16.0 * g(t - h) - 30.0 * g(t) + 16.0 * g(t + h) - g(t + 2.0 * h))
        / (12.0 * h * h)
}

/// A prescribed smooth motion of the body frame and the modes.
pub trait PrescribedMotion {
    fn r0(&self, t: f64) -> Vector3<f64>;
    fn a(&self, t: f64) -> Matrix3<f64>;
    fn y(&self, t: f64) -> Vec<f64>;
}

/// Z(t) = {ṡ; ω; ẏ} of a motion: ω̃ = Ȧ Aᵀ, ṡ = ṙ0 + r0 × ω (differenced with step h).
pub fn z_of<M: PrescribedMotion>(m: &M, t: f64, h: f64) -> (Vector3<f64>, Vector3<f64>, Vec<f64>) {
    let ad = d1(|t| DVector::from_column_slice(m.a(t).as_slice()), t, h);
    let w = Matrix3::from_column_slice(ad.as_slice()) * m.a(t).transpose();
    let omega = Vector3::new(
        0.5 * (w[(2, 1)] - w[(1, 2)]),
        0.5 * (w[(0, 2)] - w[(2, 0)]),
        0.5 * (w[(1, 0)] - w[(0, 1)]),
    );
    let r0d = d1(|t| DVector::from_column_slice(m.r0(t).as_slice()), t, h);
    let r0d = Vector3::new(r0d[0], r0d[1], r0d[2]);
    let yd = d1(|t| DVector::from_vec(m.y(t)), t, h);
    (r0d + m.r0(t).cross(&omega), omega, yd.as_slice().to_vec())
}

/// A prescribed motion sampled at t: the frame and the modes, Z = {ṡ; ω; ẏ} differenced with
/// step 1e-4, and Ż from differencing Z(t) with step h.
pub struct MotionSample {
    /// The frame, Z and the modes at t.
    pub state: OwnedState,
    /// Z in the body's relative set (2D keeps ṡx, ṡy, ωz).
    pub z: DVector<f64>,
    pub z_dot: DVector<f64>,
}

impl MotionSample {
    pub fn new<M: PrescribedMotion>(m: &M, dim: Dim, t: f64, h: f64) -> Self {
        let (s_dot, omega, y_dot) = z_of(m, t, 1e-4);
        let z = z_vec(dim, &s_dot, &omega, &y_dot);
        let z_dot = d1(
            |t| {
                let (s, w, yd) = z_of(m, t, 1e-4);
                z_vec(dim, &s, &w, &yd)
            },
            t,
            h,
        );
        let state = OwnedState {
            r0: m.r0(t),
            a: m.a(t),
            omega,
            s_dot,
            y: m.y(t),
            y_dot,
        };
        Self { state, z, z_dot }
    }
}

/// The Z vector of the body's relative set (2D keeps ṡx, ṡy, ωz).
pub fn z_vec(dim: Dim, s: &Vector3<f64>, w: &Vector3<f64>, yd: &[f64]) -> DVector<f64> {
    let mut v = match dim {
        Dim::Spatial => vec![s.x, s.y, s.z, w.x, w.y, w.z],
        Dim::Planar => vec![s.x, s.y, w.z],
    };
    v.extend_from_slice(yd);
    DVector::from_vec(v)
}

/// `Rz(α) Ry(β) Rx(γ)`.
pub fn rz_ry_rx(alpha: f64, beta: f64, gamma: f64) -> Matrix3<f64> {
    let (sb, cb) = beta.sin_cos();
    let (sg, cg) = gamma.sin_cos();
    let ry = Matrix3::new(cb, 0.0, sb, 0.0, 1.0, 0.0, -sb, 0.0, cb);
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, cg, -sg, 0.0, sg, cg);
    rot_z(alpha) * ry * rx
}

/// On the manifold, `q̇ = R Z`. 3D: `ṙ0 = ṡ − r̃0 ω`, `ė_a = −ẽ_a ω`; 2D: `ṙ0 = ṡ + ω E r0`,
/// `u̇ = ω E u`. Returns (natural state, R, Ṙ Z).
pub fn natural_from_relative(
    st: &BodyState<'_>,
    dim: Dim,
    n: usize,
) -> (Q, DMatrix<f64>, DVector<f64>) {
    let nr = n_rigid(dim);
    let mut q = DVector::zeros(nr + n);
    let mut qd = DVector::zeros(nr + n);
    let r0d = st.r0_dot();
    let om = st.omega;
    match dim {
        Dim::Spatial => {
            let mut rm = DMatrix::zeros(12 + n, 6 + n);
            let mut rdz = DVector::zeros(12 + n);
            q.fixed_rows_mut::<3>(0).copy_from(&st.r0);
            qd.fixed_rows_mut::<3>(0).copy_from(&r0d);
            rm.view_mut((0, 0), (3, 3)).fill_with_identity();
            rm.view_mut((0, 3), (3, 3))
                .copy_from(&(-flexmbd_core::skew(&st.r0)));
            rdz.fixed_rows_mut::<3>(0).copy_from(&om.cross(&r0d));
            for a in 0..3 {
                let e: Vector3<f64> = st.a.column(a).into();
                let ed = om.cross(&e);
                q.fixed_rows_mut::<3>(3 + 3 * a).copy_from(&e);
                qd.fixed_rows_mut::<3>(3 + 3 * a).copy_from(&ed);
                rm.view_mut((3 + 3 * a, 3), (3, 3))
                    .copy_from(&(-flexmbd_core::skew(&e)));
                rdz.fixed_rows_mut::<3>(3 + 3 * a).copy_from(&om.cross(&ed));
            }
            rm.view_mut((12, 6), (n, n)).fill_with_identity();
            for j in 0..n {
                q[12 + j] = st.y[j];
                qd[12 + j] = st.y_dot[j];
            }
            (Q { dim, q, qd }, rm, rdz)
        }
        Dim::Planar => {
            let w = om.z;
            let e90 = Matrix2::new(0.0, -1.0, 1.0, 0.0);
            let mut rm = DMatrix::zeros(4 + n, 3 + n);
            let mut rdz = DVector::zeros(4 + n);
            let r0 = st.r0.xy();
            let u: Vector2<f64> = st.a.fixed_view::<2, 1>(0, 0).into();
            let (r0d, ud) = (r0d.xy(), w * e90 * u);
            q.fixed_rows_mut::<2>(0).copy_from(&r0);
            q.fixed_rows_mut::<2>(2).copy_from(&u);
            qd.fixed_rows_mut::<2>(0).copy_from(&r0d);
            qd.fixed_rows_mut::<2>(2).copy_from(&ud);
            rm.view_mut((0, 0), (2, 2)).fill_with_identity();
            rm.view_mut((0, 2), (2, 1)).copy_from(&(e90 * r0));
            rm.view_mut((2, 2), (2, 1)).copy_from(&(e90 * u));
            rm.view_mut((4, 3), (n, n)).fill_with_identity();
            rdz.fixed_rows_mut::<2>(0).copy_from(&(w * e90 * r0d));
            rdz.fixed_rows_mut::<2>(2).copy_from(&(w * e90 * ud));
            for j in 0..n {
                q[4 + j] = st.y[j];
                qd[4 + j] = st.y_dot[j];
            }
            (Q { dim, q, qd }, rm, rdz)
        }
    }
}
