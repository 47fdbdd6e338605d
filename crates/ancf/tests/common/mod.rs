//! Shared by the spin-up tests: the quick spin-up and the energy balance of the driven hub.

use flexmbd_ancf::{Cable, CableSpec};
use flexmbd_core::{Dim, Formulation, Request, SystemTerms};
use flexmbd_integrators::{Ali3p, Ali3pSettings};

/// The spin-up beam of `elements` cables with a quick spin-up (T_s = 3 s): short runs that
/// excite the beam strongly.
pub fn quick_spin_up(dim: Dim, elements: usize) -> CableSpec {
    CableSpec {
        t_s: 3.0,
        ..CableSpec::spin_up_beam(dim, elements)
    }
}

/// Energy bookkeeping of one ALI3-P run.
#[derive(Debug)]
pub struct Balance {
    /// ∫ λ_d Φ_t dt (J).
    pub work: f64,
    /// max over t of |E − E₀ − work| (J).
    pub max_balance_error: f64,
    /// Spread of E − Ω_s L_z over t > T_s (J).
    pub jacobi_drift: f64,
}

/// Run `spec` with ALI3-P (static start when gravity is present) and book the energy.
pub fn balance(spec: &CableSpec, h: f64, duration: f64) -> Balance {
    let mut cable = Cable::new(spec).unwrap();
    if spec.gravity.iter().any(|&g| g != 0.0) {
        cable.solve_static(0.0, 10).unwrap();
    }
    let mut s = Ali3p::new(
        &mut cable,
        0.0,
        Ali3pSettings {
            step: h,
            ..Default::default()
        },
    )
    .unwrap();
    let row = cable.driven_row();
    let mut terms = SystemTerms::new(cable.n_coordinates(), cable.n_constraints());
    let req = Request {
        jacobian: true,
        ..Request::default()
    };
    let mut power = |cable: &mut Cable, s: &Ali3p| {
        terms.clear(req);
        cable.evaluate(s.state(), req, &mut terms);
        s.lambda[row] * terms.phi_t[row]
    };
    let e0 = cable.energy(&s.q, &s.qd);
    let (mut work, mut p_prev) = (0.0, power(&mut cable, &s));
    let mut max_err: f64 = 0.0;
    let (mut jacobi_min, mut jacobi_max) = (f64::INFINITY, f64::NEG_INFINITY);
    let steps = (duration / h).round() as usize;
    for _ in 0..steps {
        s.step(&mut cable).unwrap();
        let p = power(&mut cable, &s);
        work += 0.5 * h * (p + p_prev);
        p_prev = p;
        let e = cable.energy(&s.q, &s.qd);
        max_err = max_err.max((e - e0 - work).abs());
        if s.t > spec.t_s + 1e-9 {
            let j = e - spec.omega_s * cable.angular_momentum_z(&s.q, &s.qd);
            jacobi_min = jacobi_min.min(j);
            jacobi_max = jacobi_max.max(j);
        }
    }
    Balance {
        work,
        max_balance_error: max_err,
        jacobi_drift: jacobi_max - jacobi_min,
    }
}
