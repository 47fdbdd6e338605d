//! The weights of a body's inertia terms (`flexmbd_body::weights`) at one sample, against
//! what the truncated kinetic energy says each group adds (`terms.rs`):
//!
//! * planar, the second-order terms add only Ī's `yᵀM_yy y` to I_zz: on the modal rows the
//!   force they drop is exactly `−ω² M_yy y` (the centrifugal softening), so their modal
//!   weight is `ω² √(yᵀM_yy y) / ‖F_y‖` in the kinetic norm and their deformation weight
//!   `ω² √(yᵀM K⁻¹M y) / √(yᵀKy)` in the strain-energy norm;
//! * the gyroscopic force −2G(ω̄)ẏ acts on the modal rows alone: its rigid weight is zero;
//! * a threshold outside (0, 1) is refused by name.

mod common;
use common::*;
use flexmbd_body::weights::{MotionSample, TermGroup, WeightMeter};
use flexmbd_body::{BodyState, Dim, FlexibleBody, InertiaMethod};
use nalgebra::{DMatrix, DVector, Vector3};

#[test]
fn one_sample_weighs_what_each_group_adds() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let n = 4;
        let mut r = rng(5);
        let mut body = FlexibleBody::new(&random_body(&mut r, dim, n, 11)).unwrap();
        let s = random_state(&mut r, dim, n);
        let mut acc = |k: f64| {
            let mut v = rand_vec(&mut r, k);
            if dim == Dim::Planar {
                v.z = 0.0;
            }
            v
        };
        let (r0_ddot, omega_dot) = (acc(2.0), acc(3.0));
        let angular = if dim == Dim::Planar {
            Vector3::new(0.0, 0.0, omega_dot.z)
        } else {
            omega_dot
        };
        let y_ddot: Vec<f64> = (0..n).map(|_| uni(&mut r, -1.0, 1.0)).collect();
        let st = BodyState::from_origin_velocity(s.r0, s.a, s.omega, s.s_dot, &s.y, &s.y_dot);
        let sample = MotionSample {
            state: st,
            origin_acceleration: r0_ddot,
            angular_acceleration: angular,
            mode_accelerations: &y_ddot,
        };
        let mut meter = WeightMeter::new(&body, "body").unwrap();
        meter.add(&sample);
        let table = meter.table();
        assert_eq!(table.samples, 1);
        let weight = |g: TermGroup| table.groups.iter().find(|(x, _)| *x == g).unwrap().1;

        let gyro = weight(TermGroup::Gyroscopic);
        eprintln!("{dim}: gyroscopic {gyro:?}");
        assert!(gyro.rigid_max < 1e-14 && gyro.modal_max > 1e-6, "{gyro:?}");
        let full = table
            .candidates
            .iter()
            .find(|(t, _)| t.is_full())
            .unwrap()
            .1;
        assert_eq!(full.max(), 0.0);

        if dim == Dim::Planar {
            // The full modal force, from the kernel.
            let nc = body.n_coords();
            let (mut m, mut q) = (DMatrix::zeros(nc, nc), DVector::zeros(nc));
            body.inertia_origin(&st, InertiaMethod::ShapeIntegrals, &mut m, &mut q);
            let mut z_dot = DVector::zeros(nc);
            z_dot[0] = r0_ddot.x;
            z_dot[1] = r0_ddot.y;
            z_dot[2] = angular.z;
            z_dot.rows_mut(3, n).copy_from_slice(&y_ddot);
            let f_y = (&m * z_dot - q).rows(3, n).into_owned();
            let (myy, k) = (body.m_yy(), body.k_ff().clone());
            let (mi, ki) = (
                myy.clone().try_inverse().unwrap(),
                k.clone().try_inverse().unwrap(),
            );
            let y = DVector::from_column_slice(&s.y);
            let w2 = s.omega.z * s.omega.z;
            let modal = w2 * y.dot(&(&myy * &y)).sqrt() / f_y.dot(&(&mi * &f_y)).sqrt();
            let my = &myy * &y;
            let deformation = w2 * my.dot(&(&ki * &my)).sqrt() / y.dot(&(&k * &y)).sqrt();
            let second = weight(TermGroup::SecondOrder);
            eprintln!(
                "2D second order: {second:?}; expected modal {modal:e}, deformation {deformation:e}"
            );
            assert!(
                (second.modal_max - modal).abs() < 1e-10 * modal,
                "{second:?} vs {modal:e}"
            );
            assert!(
                (second.deformation_max - deformation).abs() < 1e-10 * deformation,
                "{second:?} vs {deformation:e}"
            );
        }
        let err = table.choose(1.0).unwrap_err().to_string();
        assert!(
            err.contains("threshold = 1") && err.contains("(0, 1)"),
            "{err}"
        );
        assert!(table.choose(f64::NAN).is_err() && table.choose(0.0).is_err());
    }
}
