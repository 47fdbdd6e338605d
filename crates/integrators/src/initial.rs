//! Consistent initial conditions (docs/methods.md §5.4, with its checked corrections):
//!
//! 1. positions: Φ(q₀) = 0 with the user-specified coordinates held, by a
//!    regularised Gauss–Newton iteration (μI + JᵀJ) Δq = −Jᵀ Φ_ext that tolerates
//!    redundant constraints;
//! 2. velocities: the augmented-Lagrangian projection
//!    (M + Φ_qᵀ α₀ Φ_q) q̇ = M q̇* − Φ_qᵀ(α₀ Φ_t + σ), σ ← σ + α₀(Φ_q q̇ + Φ_t),
//!    with the specified velocities as extra rheonomic constraints and α₀ = 10⁴ m_ref
//!    (m_ref the largest diagonal entry of M: what the default step penalty gives h²α/4,
//!    but independent of the step's α, so a run's start does not depend on its penalty);
//! 3. accelerations and multipliers:
//!    (M + Φ_qᵀ α₀ Φ_q) q̈ = Q − Φ_qᵀ(α₀ c + λ), λ ← λ + α₀(Φ_q q̈ + c).
//!
//! Both iterations run in increment form (x ← x − (M + α₀Φ_qᵀΦ_q)⁻¹ α₀ Φ_qᵀ r with r the
//! constraint residual, the same iterates), and stop when the residual and the increment are
//! both at round-off: the matrix has a condition number near 10⁹ on flexible scenes, and a
//! whole solve leaves cond · ε ≈ 10⁻⁸ of noise in the velocities.
//!
//! This runs once per scene; it may allocate.

use flexmbd_core::{Formulation, Request};
use nalgebra::{DMatrix, DVector};

use crate::ali3p::{Ali3p, IntegratorError};
use crate::lu::DenseLu;

const MAX_ITER: usize = 200;

/// Rows `m..` of the augmented Jacobian: one unit row per held coordinate (its position or
/// rate equals the specified one).
fn hold_rows(j: &mut DMatrix<f64>, m: usize, held: &[usize]) {
    for (k, &c) in held.iter().enumerate() {
        j.row_mut(m + k).fill(0.0);
        j[(m + k, c)] = 1.0;
    }
}

pub(crate) fn make_consistent<F: Formulation + ?Sized>(
    s: &mut Ali3p,
    f: &mut F,
) -> Result<(), IntegratorError> {
    let n = f.n_coordinates();
    let m = f.n_constraints();
    let held: Vec<usize> = f.specified_coordinates().to_vec();
    let q_spec = s.q.clone();
    let qd_spec = s.qd.clone();
    let me = m + held.len();
    let mut lu = DenseLu::new(n);
    let singular = |t: f64| {
        move |e: crate::lu::Singular| IntegratorError::Singular {
            t,
            pivot_ratio: e.pivot_ratio,
        }
    };

    // 1. Positions.
    let mut j = DMatrix::zeros(me, n);
    let mut r = DVector::zeros(me);
    let mut phi_norm = f64::INFINITY;
    let mut it = 0;
    while it < MAX_ITER {
        s.eval(
            f,
            Request {
                constraints: true,
                jacobian: true,
                ..Request::default()
            },
        );
        let tt = s.terms();
        j.rows_mut(0, m).copy_from(&tt.phi_q);
        r.rows_mut(0, m).copy_from(&tt.phi);
        hold_rows(&mut j, m, &held);
        for (k, &c) in held.iter().enumerate() {
            r[m + k] = s.q[c] - q_spec[c];
        }
        phi_norm = r.amax();
        if phi_norm <= 1e-13 * s.q.amax().max(1.0) {
            break;
        }
        let mut a = j.transpose() * &j;
        let mu = 1e-10 * (0..n).map(|i| a[(i, i)]).fold(0.0, f64::max).max(1e-300);
        for i in 0..n {
            a[(i, i)] += mu;
        }
        let mut dq = -(j.transpose() * &r);
        lu.factor(&a).map_err(singular(s.t))?;
        lu.solve_in_place(&mut dq);
        s.q += &dq;
        it += 1;
    }
    if phi_norm > 1e-9 * s.q.amax().max(1.0) {
        return Err(IntegratorError::InconsistentStart {
            phi: phi_norm,
            iterations: it,
        });
    }

    // 2. Velocities.
    s.qd.copy_from(&qd_spec);
    s.eval(f, Request::ALL);
    let mass = s.terms().mass.clone();
    let m_ref = (0..n)
        .map(|i| mass[(i, i)].abs())
        .fold(0.0, f64::max)
        .max(1e-12);
    let alpha0 = 1e4 * m_ref;
    let mut jt = DVector::zeros(me);
    {
        let tt = s.terms();
        j.rows_mut(0, m).copy_from(&tt.phi_q);
        jt.rows_mut(0, m).copy_from(&tt.phi_t);
        hold_rows(&mut j, m, &held);
        for (k, &c) in held.iter().enumerate() {
            jt[m + k] = -qd_spec[c];
        }
    }
    let lead = &mass + alpha0 * j.transpose() * &j;
    lu.factor(&lead).map_err(singular(s.t))?;
    // From q̇ = q̇*.
    augmented_lagrangian(&mut lu, &j, &jt, alpha0, 1e-12, &mut s.qd);

    // 3. Accelerations and multipliers.
    s.eval(f, Request::ALL);
    let tt = s.terms();
    let phi_q = tt.phi_q.clone();
    let c = tt.accel_term.clone();
    let forces = tt.forces.clone();
    let lead = &tt.mass + alpha0 * phi_q.transpose() * &phi_q;
    lu.factor(&lead).map_err(singular(s.t))?;
    // The first iterate by a whole solve (with no multipliers), the rest in increment form.
    s.qdd = &forces - alpha0 * (phi_q.transpose() * &c);
    lu.solve_in_place(&mut s.qdd);
    let lambda = augmented_lagrangian(&mut lu, &phi_q, &c, alpha0, 1e-10, &mut s.qdd);
    s.lambda.copy_from(&lambda);
    Ok(())
}

/// The augmented-Lagrangian iterations of steps 2 and 3 in increment form, from x:
/// r = J x + b, σ ← σ + α₀ r, x ← x − (M + α₀JᵀJ)⁻¹ α₀ Jᵀ r with the factorisation in `lu`,
/// until ‖r‖∞ ≤ `tol_r` and the increment is at round-off (both relative to max(1, ‖x‖∞)).
/// Returns the multipliers σ.
fn augmented_lagrangian(
    lu: &mut DenseLu,
    j: &DMatrix<f64>,
    b: &DVector<f64>,
    alpha0: f64,
    tol_r: f64,
    x: &mut DVector<f64>,
) -> DVector<f64> {
    let mut sigma = DVector::zeros(j.nrows());
    for _ in 0..MAX_ITER {
        let r = j * &*x + b;
        sigma += alpha0 * &r;
        let mut dx = -(alpha0 * (j.transpose() * &r));
        lu.solve_in_place(&mut dx);
        *x += &dx;
        let scale = x.amax().max(1.0);
        if r.amax() <= tol_r * scale && dx.amax() <= 1e-15 * scale {
            break;
        }
    }
    sigma
}
