//! Rough loop timing of one inertia evaluation per route (the criterion benches are
//! the lead's). `cargo run --release -p flexmbd-body --example timing`.
//! The bodies are built by the tests' `body_with_cloud` (`tests/common`).

#[path = "../tests/common/mod.rs"]
mod common;

use flexmbd_body::{BodyState, Dim, FlexibleBody, InertiaMethod};
use flexmbd_fe::{MassCloud, ReducedBody};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use std::hint::black_box;
use std::time::Instant;

/// Deterministic pseudo-random numbers in [−1, 1): one fixed cloud, so timings compare across runs.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

fn body(dim: Dim, n: usize, np: usize) -> ReducedBody {
    let mut r = Lcg(7);
    let mut positions = vec![];
    let mut mode_rows = vec![];
    for _ in 0..np {
        let z = if dim == Dim::Planar {
            0.0
        } else {
            0.1 * r.next()
        };
        positions.push(Vector3::new(r.next(), 0.1 * r.next(), z));
        for a in 0..3 {
            for _ in 0..n {
                mode_rows.push(if dim == Dim::Planar && a == 2 {
                    0.0
                } else {
                    r.next()
                });
            }
        }
    }
    let cloud = MassCloud {
        n_modes: n,
        positions,
        weights: vec![1.0 / np as f64; np],
        mode_rows,
        description: "random".into(),
    };
    common::body_with_cloud(dim, cloud, DMatrix::identity(n, n), DMatrix::zeros(n, n))
}

/// Nanoseconds per call of `eval`, repeated until a batch takes over 0.2 s.
fn ns_per_call(mut eval: impl FnMut()) -> f64 {
    let mut reps = 1000usize;
    loop {
        let t = Instant::now();
        for _ in 0..reps {
            eval();
        }
        let dt = t.elapsed().as_secs_f64();
        if dt > 0.2 {
            return dt / reps as f64 * 1e9;
        }
        reps *= 4;
    }
}

fn time(b: &mut FlexibleBody, st: &BodyState<'_>, method: InertiaMethod) -> f64 {
    let nc = b.n_coords();
    let mut m = DMatrix::zeros(nc, nc);
    let mut q = DVector::zeros(nc);
    ns_per_call(|| {
        b.inertia(black_box(st), method, &mut m, &mut q);
        black_box(&m);
    })
}

fn time_nat(b: &FlexibleBody, st: &flexmbd_body::NaturalState<'_>, method: InertiaMethod) -> f64 {
    let nc = b.n_natural_coords();
    let mut ws = b.natural_workspace();
    let mut m = DMatrix::zeros(nc, nc);
    let mut q = DVector::zeros(nc);
    ns_per_call(|| {
        b.inertia_natural(black_box(st), method, &mut ws, &mut m, &mut q);
        black_box(&m);
    })
}

fn main() {
    for (dim, n, np) in [
        (Dim::Spatial, 8, 160),
        (Dim::Spatial, 8, 640),
        (Dim::Spatial, 8, 2560),
        (Dim::Spatial, 0, 6),
        (Dim::Spatial, 20, 640),
        (Dim::Planar, 8, 80),
        (Dim::Planar, 8, 320),
    ] {
        let rb = body(dim, n, np);
        let mut b = FlexibleBody::new(&rb).unwrap();
        let y: Vec<f64> = (0..n).map(|j| 0.01 * j as f64).collect();
        let yd: Vec<f64> = (0..n).map(|j| 0.1 * j as f64).collect();
        let st = match dim {
            Dim::Spatial => BodyState {
                r0: Vector3::new(0.1, 0.2, 0.3),
                a: nalgebra::Rotation3::from_euler_angles(0.1, 0.2, 0.3).into_inner(),
                omega: Vector3::new(0.5, -0.3, 1.0),
                s_dot: Vector3::new(1.0, 0.0, -1.0),
                y: &y,
                y_dot: &yd,
            },
            Dim::Planar => BodyState::planar(
                nalgebra::Vector2::new(0.1, 0.2),
                0.3,
                nalgebra::Vector2::new(1.0, -1.0),
                0.7,
                &y,
                &yd,
            ),
        };
        let ts = time(&mut b, &st, InertiaMethod::ShapeIntegrals);
        let tb = time(&mut b, &st, InertiaMethod::BMatrix);
        print!(
            "{dim} n={n:2} Np={np:5}: shape integrals {ts:8.0} ns, B-matrix {tb:10.0} ns ({:.1} ns/point)",
            tb / np as f64
        );
        if dim == Dim::Planar {
            // The alternative: the 3D path on the same planar body, then extraction.
            let mut rb3 = rb.clone();
            rb3.dim = Dim::Spatial;
            let mut b3 = FlexibleBody::new(&rb3).unwrap();
            let ts3 = time(&mut b3, &st, InertiaMethod::ShapeIntegrals);
            let tb3 = time(&mut b3, &st, InertiaMethod::BMatrix);
            print!("; via 3D path: {ts3:.0} ns / {tb3:.0} ns (before extraction)");
        }
        // Natural coordinates (methods §2.5), a non-orthonormal A.
        let nat = flexmbd_body::NaturalState {
            r0: st.r0,
            a: st.a * 1.01,
            r0_dot: st.s_dot,
            a_dot: st.a * Matrix3::new(0.0, -0.3, 0.2, 0.3, 0.0, -0.1, -0.2, 0.1, 0.0),
            y: &y,
            y_dot: &yd,
        };
        let nat = if dim == Dim::Planar {
            flexmbd_body::NaturalState::planar(
                nalgebra::Vector2::new(0.1, 0.2),
                nalgebra::Vector2::new(0.9, 0.2),
                nalgebra::Vector2::new(1.0, -1.0),
                nalgebra::Vector2::new(-0.1, 0.4),
                &y,
                &yd,
            )
        } else {
            nat
        };
        let tn_s = time_nat(&b, &nat, InertiaMethod::ShapeIntegrals);
        let tn_b = time_nat(&b, &nat, InertiaMethod::BMatrix);
        println!();
        println!(
            "      natural coordinates: shape integrals {tn_s:8.0} ns, B-matrix {tn_b:10.0} ns"
        );
    }
}
