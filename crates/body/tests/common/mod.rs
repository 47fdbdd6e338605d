//! Shared helpers of the body tests: random clouds, rotations and states.
#![allow(dead_code)]

use flexmbd_body::{BodyState, Dim, FlexibleBody, InertiaMethod};
use flexmbd_fe::{MassCloud, ModeInventory, ReducedBody, ShapeIntegrals, StiffeningIntegrals};
use nalgebra::{DMatrix, DVector, Matrix3, Quaternion, UnitQuaternion, Vector3};
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
    let si = ShapeIntegrals::from_cloud(&cloud);
    let mut m_ff = DMatrix::zeros(n, n);
    for a in 0..3 {
        m_ff += &si.s_ab[a][a];
    }
    let q = DMatrix::from_fn(n, n, |_, _| uni(r, -1.0, 1.0));
    let k_ff = &q * q.transpose() + DMatrix::identity(n, n) * (n as f64);
    let c_ff = 0.01 * &k_ff;
    ReducedBody {
        dim,
        inventory: ModeInventory {
            n_fe_dofs: 0,
            frame_dofs: vec![],
            static_modes: vec![],
            normal_frequencies_hz: vec![1.0; n],
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

pub fn eval(
    body: &mut FlexibleBody,
    st: &BodyState<'_>,
    method: InertiaMethod,
) -> (DMatrix<f64>, DVector<f64>) {
    let nc = body.n_coords();
    let mut m = DMatrix::from_element(nc, nc, f64::NAN);
    let mut q = DVector::from_element(nc, f64::NAN);
    body.inertia(st, method, &mut m, &mut q);
    assert!(m.iter().all(|v| v.is_finite()), "every entry of M̄ written");
    assert!(
        q.iter().all(|v| v.is_finite()),
        "every entry of Q̄_v written"
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
