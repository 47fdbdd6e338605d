//! Linearised free vibration of a [`Formulation`] about a static equilibrium (q*, λ*)
//! (docs/methods.md §5.5): the tangents by central differences, the motions the constraints
//! allow by a null-space basis, the quadratic eigenproblem as a first-order one.
//!
//! With the equations of motion M q̈ + Φ_qᵀλ = Q(q, q̇, t), Φ(q, t) = 0, small motions
//! δq about (q*, λ*) at rest satisfy
//!
//! M δq̈ + C δq̇ + K δq + Φ_qᵀ δλ = 0,  Φ_q δq = 0,
//!
//! K = −∂(Q − Φ_qᵀλ*)/∂q,  C = −∂Q/∂q̇,
//!
//! K holding the **constraint-force stiffness** ∂(Φ_qᵀλ*)/∂q (a pendulum's whole restoring
//! stiffness: its Q, the weight, does not depend on q). With a basis R of the null space of
//! Φ_q (δq = R x, Φ_q R = 0) the multipliers drop out:
//!
//! M_r ẍ + C_r ẋ + K_r x = 0,  M_r = RᵀMR, C_r = RᵀCR, K_r = RᵀKR,
//!
//! and x = x̂ eˢᵗ gives the state-space eigenproblem
//!
//! [0 I; −M_r⁻¹K_r −M_r⁻¹C_r] [x̂; s x̂] = s [x̂; s x̂],
//!
//! solved by faer's real eigendecomposition (Schur). A pair s = −ζω ± iω√(1−ζ²) is one mode
//! of undamped frequency ω = |s|, damping ratio ζ = −Re s/|s| and damped frequency Im s.
//!
//! **Tangents.** The formulations' K omits the constraint curvature and some configuration
//! dependence of the forces (it is what ALI3-P needs, docs/design.md "The integrator"), so
//! here both tangents are central differences of the evaluated forces: column j of K is
//! −(G(q + d e_j) − G(q − d e_j)) / 2d with G = Q − Φ_qᵀλ*, column j of C the same of Q
//! over q̇ at q̇ = 0, with d = [`RELATIVE_STEP`] · max(1, |q_j|) (6·10⁻⁶ ≈ ε^{1/3}, which
//! balances the truncation error d²/6 ‖G‴‖ against the rounding error ε‖G‖/d: both
//! about 10⁻¹¹ relative for forces that vary on the scale of 1 m or 1 rad). For forces
//! linear in q and q̇ (springs, linear elasticity) the difference is exact up to rounding.
//!
//! **Null space.** R is the last n − rank columns of V in the SVD Φ_q = UΣVᵀ (faer), the
//! rank counting singular values above [`RANK_TOLERANCE`] σ_max: redundant constraints (the
//! rigid four-bars) lower the rank, not the number of motions.

use faer::Mat;
use flexmbd_core::{Formulation, Request, State, SystemTerms};
use nalgebra::{DMatrix, DVector};

/// Central-difference step of the tangents, relative to max(1, |q_j|) (≈ ε^{1/3}).
pub const RELATIVE_STEP: f64 = 6e-6;

/// Singular values of Φ_q above this fraction of the largest count towards its rank.
pub const RANK_TOLERANCE: f64 = 1e-9;

/// Eigenvalues |s| at most this fraction of the largest |s| (or of 1 s⁻¹, whichever is
/// larger) are zero modes: free rigid-body motions, whose double zero eigenvalue rounding
/// splits into a pair of about √ε of the largest.
pub const ZERO_TOLERANCE: f64 = 1e-6;

/// Why the linearised vibration could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum VibrationError {
    /// A term at the equilibrium is NaN or infinite.
    #[error("the {what} at the equilibrium is not finite")]
    NonFinite {
        /// Which term.
        what: &'static str,
    },
    /// The mass matrix on the motions the constraints allow is singular.
    #[error(
        "the mass matrix on the {dof} motions the constraints allow is singular (smallest/largest pivot {pivot_ratio:.1e}): a motion without inertia"
    )]
    SingularMass {
        /// Degrees of freedom.
        dof: usize,
        /// Smallest over largest |pivot| of its LU factorisation.
        pivot_ratio: f64,
    },
    /// A decomposition did not converge.
    #[error("the {what} did not converge")]
    NoConvergence {
        /// Which decomposition.
        what: &'static str,
    },
}

/// The linearised equations about an equilibrium, on the n coordinates, and the basis R
/// (n × r) of the motions the constraints allow.
#[derive(Clone, Debug)]
pub struct Linearisation {
    /// M (n × n).
    pub mass: DMatrix<f64>,
    /// K = −∂(Q − Φ_qᵀλ*)/∂q (n × n), the constraint-force stiffness included.
    pub stiffness: DMatrix<f64>,
    /// C = −∂Q/∂q̇ (n × n).
    pub damping: DMatrix<f64>,
    /// R (n × r), orthonormal columns, Φ_q R = 0.
    pub basis: DMatrix<f64>,
}

/// What a mode is, from its eigenvalue s.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModeKind {
    /// A complex pair s, s̄: an oscillation.
    Oscillatory,
    /// |s| ≈ 0 ([`ZERO_TOLERANCE`]): a free (rigid-body) motion.
    Zero,
    /// Real s < 0: a motion that decays without oscillating (ζ ≥ 1 reported as 1).
    Overdamped,
    /// Real s > 0: a motion that grows (the equilibrium is unstable; ζ reported as −1).
    Unstable,
}

/// One mode of the linearised free vibration.
#[derive(Clone, Debug)]
pub struct Mode {
    /// Eigenvalue s (1/s): real and imaginary parts (the one with Im s ≥ 0 of a pair).
    pub eigenvalue: (f64, f64),
    /// Undamped frequency |s|/2π (Hz).
    pub frequency_hz: f64,
    /// Damped frequency Im s/2π (Hz); 0 for a real s.
    pub damped_frequency_hz: f64,
    /// Damping ratio −Re s/|s| (0 for a zero mode).
    pub damping_ratio: f64,
    /// Kind.
    pub kind: ModeKind,
    /// Mode shape δq = R x̂ on the n coordinates, (re, im), scaled so that its largest
    /// component is 1.
    pub shape: Vec<(f64, f64)>,
}

/// Q − Φ_qᵀλ at (q, q̇), with M and Φ_q left in `terms`.
fn net_force<F: Formulation + ?Sized>(
    f: &mut F,
    state: State<'_>,
    lambda: &DVector<f64>,
    terms: &mut SystemTerms,
) -> DVector<f64> {
    let req = Request {
        tangents: false,
        ..Request::ALL
    };
    terms.clear(req);
    f.evaluate(state, req, terms);
    let mut g = terms.forces.clone();
    g.gemv_tr(-1.0, &terms.phi_q, lambda, 1.0);
    g
}

/// The linearised equations of `f` about (q, λ) at time t and rest (module documentation):
/// M, K (constraint-force stiffness included) and C by central differences, and R.
pub fn linearise<F: Formulation + ?Sized>(
    f: &mut F,
    t: f64,
    q: &DVector<f64>,
    lambda: &DVector<f64>,
) -> Result<Linearisation, VibrationError> {
    let (n, m) = (f.n_coordinates(), f.n_constraints());
    let mut terms = SystemTerms::new(n, m);
    let zero = DVector::zeros(n);
    net_force(f, State::new(t, q, &zero), lambda, &mut terms);
    let mass = terms.mass.clone();
    let phi_q = terms.phi_q.clone();
    if !mass.iter().all(|v| v.is_finite()) {
        return Err(VibrationError::NonFinite {
            what: "mass matrix",
        });
    }
    if !phi_q.iter().all(|v| v.is_finite()) {
        return Err(VibrationError::NonFinite {
            what: "constraint Jacobian",
        });
    }
    let mut stiffness = DMatrix::zeros(n, n);
    let mut damping = DMatrix::zeros(n, n);
    let (mut qp, mut vp) = (q.clone(), zero.clone());
    for j in 0..n {
        let d = RELATIVE_STEP * q[j].abs().max(1.0);
        qp[j] = q[j] + d;
        let plus = net_force(f, State::new(t, &qp, &zero), lambda, &mut terms);
        qp[j] = q[j] - d;
        let minus = net_force(f, State::new(t, &qp, &zero), lambda, &mut terms);
        qp[j] = q[j];
        stiffness.set_column(j, &((minus - plus) / (2.0 * d)));
        let d = RELATIVE_STEP;
        vp[j] = d;
        let plus = net_force(f, State::new(t, q, &vp), lambda, &mut terms);
        vp[j] = -d;
        let minus = net_force(f, State::new(t, q, &vp), lambda, &mut terms);
        vp[j] = 0.0;
        damping.set_column(j, &((minus - plus) / (2.0 * d)));
    }
    for (what, a) in [("stiffness", &stiffness), ("damping", &damping)] {
        if !a.iter().all(|v| v.is_finite()) {
            return Err(VibrationError::NonFinite { what });
        }
    }
    Ok(Linearisation {
        mass,
        stiffness,
        damping,
        basis: null_space(&phi_q)?,
    })
}

/// Orthonormal basis of the null space of `a` (m × n) from its SVD (module documentation).
pub fn null_space(a: &DMatrix<f64>) -> Result<DMatrix<f64>, VibrationError> {
    let (m, n) = a.shape();
    if m == 0 || a.amax() == 0.0 {
        return Ok(DMatrix::identity(n, n));
    }
    let fa = Mat::<f64>::from_fn(m, n, |i, j| a[(i, j)]);
    let svd = fa.svd().map_err(|_| VibrationError::NoConvergence {
        what: "singular value decomposition of the constraint Jacobian",
    })?;
    let s = svd.S().column_vector();
    let s_max = s[0];
    let rank = (0..m.min(n))
        .filter(|&i| s[i] > RANK_TOLERANCE * s_max)
        .count();
    let v = svd.V();
    Ok(DMatrix::from_fn(n, n - rank, |i, j| v[(i, rank + j)]))
}

impl Linearisation {
    /// Degrees of freedom r: the motions the constraints allow.
    pub fn dof(&self) -> usize {
        self.basis.ncols()
    }

    /// RᵀAR.
    fn reduce(&self, a: &DMatrix<f64>) -> DMatrix<f64> {
        self.basis.transpose() * a * &self.basis
    }

    /// The state-space matrix [0 I; −M_r⁻¹K_r −M_r⁻¹C_r] (2r × 2r).
    fn state_matrix(&self) -> Result<DMatrix<f64>, VibrationError> {
        let r = self.dof();
        let lu = self.reduce(&self.mass).lu();
        let u = lu.u();
        let pivots = u.diagonal().map(f64::abs);
        let pivot_ratio = if r == 0 {
            1.0
        } else {
            pivots.min() / pivots.max()
        };
        if pivot_ratio.is_nan() || pivot_ratio <= 1e-13 {
            return Err(VibrationError::SingularMass {
                dof: r,
                pivot_ratio,
            });
        }
        let mut kc = DMatrix::zeros(r, 2 * r);
        kc.columns_mut(0, r)
            .copy_from(&self.reduce(&self.stiffness));
        kc.columns_mut(r, r).copy_from(&self.reduce(&self.damping));
        let kc = lu.solve(&kc).ok_or(VibrationError::SingularMass {
            dof: r,
            pivot_ratio,
        })?;
        let mut a = DMatrix::zeros(2 * r, 2 * r);
        a.view_mut((0, r), (r, r)).fill_with_identity();
        a.view_mut((r, 0), (r, 2 * r)).copy_from(&(-kc));
        Ok(a)
    }

    /// The modes of the free vibration, one per complex pair or real eigenvalue, sorted
    /// by undamped frequency (module documentation).
    pub fn modes(&self) -> Result<Vec<Mode>, VibrationError> {
        let r = self.dof();
        if r == 0 {
            return Ok(Vec::new());
        }
        let a = self.state_matrix()?;
        let fa = Mat::<f64>::from_fn(2 * r, 2 * r, |i, j| a[(i, j)]);
        let eig = fa.eigen().map_err(|_| VibrationError::NoConvergence {
            what: "eigendecomposition of the state-space matrix",
        })?;
        let (values, vectors) = (eig.S().column_vector(), eig.U());
        let s_max = (0..2 * r).map(|k| values[k].norm()).fold(1.0, f64::max);
        let mut modes = Vec::new();
        for k in 0..2 * r {
            let s = values[k];
            if s.im < 0.0 {
                continue; // the conjugate of a pair already taken
            }
            let x: Vec<_> = (0..r).map(|i| vectors[(i, k)]).collect();
            modes.push(self.mode((s.re, s.im), &x, s_max));
        }
        modes.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
        Ok(modes)
    }

    /// One mode from its eigenvalue `s` and reduced shape `x`.
    fn mode(&self, s: (f64, f64), x: &[faer::c64], s_max: f64) -> Mode {
        let two_pi = 2.0 * std::f64::consts::PI;
        let omega = s.0.hypot(s.1);
        let kind = if omega <= ZERO_TOLERANCE * s_max {
            ModeKind::Zero
        } else if s.1 > 0.0 {
            ModeKind::Oscillatory
        } else if s.0 < 0.0 {
            ModeKind::Overdamped
        } else {
            ModeKind::Unstable
        };
        let damping_ratio = match kind {
            ModeKind::Zero => 0.0,
            _ => -s.0 / omega,
        };
        // δq = R x̂, scaled so that its largest component is 1.
        let n = self.basis.nrows();
        let mut shape: Vec<faer::c64> = (0..n)
            .map(|i| {
                x.iter()
                    .enumerate()
                    .map(|(j, xj)| *xj * self.basis[(i, j)])
                    .sum()
            })
            .collect();
        let big = shape
            .iter()
            .copied()
            .max_by(|a, b| a.norm().total_cmp(&b.norm()))
            .unwrap_or(faer::c64::new(1.0, 0.0));
        if big.norm() > 0.0 {
            shape.iter_mut().for_each(|v| *v /= big);
        }
        Mode {
            eigenvalue: s,
            frequency_hz: omega / two_pi,
            damped_frequency_hz: s.1 / two_pi,
            damping_ratio,
            kind,
            shape: shape.iter().map(|v| (v.re, v.im)).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd_core::Coordinates;

    /// A point mass m in the plane on a rod of length L from the origin (Φ = ½(x² + y² − L²)),
    /// under gravity −g ŷ and a nonlinear restoring force −k sin(x) along x (its central
    /// difference is not exact), with a viscous damper c along y.
    struct RodMass {
        coords: Coordinates,
        m: f64,
        g: f64,
        k: f64,
        c: f64,
        l: f64,
    }

    impl Formulation for RodMass {
        fn coordinates(&self) -> &Coordinates {
            &self.coords
        }
        fn evaluate(&mut self, s: State<'_>, req: Request, out: &mut SystemTerms) {
            let (x, y) = (s.q[0], s.q[1]);
            if req.dynamics {
                out.mass[(0, 0)] = self.m;
                out.mass[(1, 1)] = self.m;
                out.forces[0] = -self.k * x.sin();
                out.forces[1] = -self.m * self.g - self.c * s.qd[1];
            }
            if req.constraints {
                out.phi[0] = 0.5 * (x * x + y * y - self.l * self.l);
            }
            if req.jacobian {
                out.phi_q[(0, 0)] = x;
                out.phi_q[(0, 1)] = y;
            }
        }
    }

    /// Hanging at (0, −L) with λ = m g / L (Q − Φ_qᵀλ = 0): K = diag(k, 0) + λ∇²Φ =
    /// diag(k + mg/L, mg/L) — λ∇²Φ = λI is the constraint-force stiffness — and C = diag(0, c).
    #[test]
    fn central_differences_give_the_tangents_and_the_constraint_force_stiffness() {
        let (m, g, k, c, l) = (2.0, 9.81, 30.0, 0.7, 1.5);
        let mut f = RodMass {
            coords: Coordinates::zeros(2, 1),
            m,
            g,
            k,
            c,
            l,
        };
        let q = DVector::from_column_slice(&[0.0, -l]);
        let lambda = DVector::from_column_slice(&[m * g / l]);
        let lin = linearise(&mut f, 0.0, &q, &lambda).unwrap();
        // Truncation error of −k sin at x = 0: k d²/6, 6e-12 relative to k.
        let expected_k = k + m * g / l;
        eprintln!(
            "K_xx error {:.1e} relative",
            (lin.stiffness[(0, 0)] - expected_k).abs() / expected_k
        );
        assert!((lin.stiffness[(0, 0)] - expected_k).abs() < 1e-10 * expected_k);
        assert!((lin.stiffness[(1, 1)] - m * g / l).abs() < 1e-9 * expected_k);
        assert!(lin.stiffness[(0, 1)].abs() + lin.stiffness[(1, 0)].abs() < 1e-9 * expected_k);
        assert!((lin.damping[(1, 1)] - c).abs() < 1e-9 * c);
        assert!(lin.damping[(0, 0)].abs() < 1e-12);
        // The motion the rod allows is along x.
        assert_eq!(lin.dof(), 1);
        assert!((lin.basis[(0, 0)].abs() - 1.0).abs() < 1e-15);
        let modes = lin.modes().unwrap();
        let omega = (expected_k / m).sqrt();
        assert_eq!(modes.len(), 1);
        assert_eq!(modes[0].kind, ModeKind::Oscillatory);
        assert!((modes[0].frequency_hz * 2.0 * std::f64::consts::PI - omega).abs() < 1e-9 * omega);
        assert!(modes[0].damping_ratio.abs() < 1e-12);
    }

    /// Redundant rows lower the rank, not the number of motions: a Jacobian with a row
    /// repeated and one scaled has a null space of n − (independent rows).
    #[test]
    fn redundant_constraint_rows_leave_the_null_space_its_dimension() {
        let a = DMatrix::from_row_slice(
            3,
            4,
            &[1.0, 2.0, 0.0, 0.0, 1.0, 2.0, 0.0, 0.0, 0.0, 0.0, 3.0, 1.0],
        );
        let r = null_space(&a).unwrap();
        assert_eq!(r.ncols(), 2);
        assert!((&a * &r).amax() < 1e-14);
        assert!((r.transpose() * &r - DMatrix::identity(2, 2)).amax() < 1e-14);
    }

    /// A free mass (no force, no constraint) has a zero mode; a negative stiffness an
    /// unstable pair; strong damping an overdamped pair.
    #[test]
    fn zero_unstable_and_overdamped_modes_are_flagged() {
        let lin = |k: f64, c: f64| Linearisation {
            mass: DMatrix::from_diagonal_element(1, 1, 2.0),
            stiffness: DMatrix::from_diagonal_element(1, 1, k),
            damping: DMatrix::from_diagonal_element(1, 1, c),
            basis: DMatrix::identity(1, 1),
        };
        let kinds = |l: Linearisation| {
            let mut k: Vec<_> = l.modes().unwrap().iter().map(|m| m.kind).collect();
            k.sort_by_key(|k| *k as u8);
            k
        };
        assert!(kinds(lin(0.0, 0.0)).iter().all(|k| *k == ModeKind::Zero));
        assert_eq!(
            kinds(lin(-8.0, 0.0)),
            [ModeKind::Overdamped, ModeKind::Unstable]
        );
        // c = 3 c_crit: two real decaying roots.
        let c = 3.0 * 2.0 * (8.0_f64 * 2.0).sqrt();
        assert_eq!(
            kinds(lin(8.0, c)),
            [ModeKind::Overdamped, ModeKind::Overdamped]
        );
    }

    /// A motion without inertia is refused, not divided by zero.
    #[test]
    fn a_massless_motion_is_refused() {
        let lin = Linearisation {
            mass: DMatrix::zeros(1, 1),
            stiffness: DMatrix::from_diagonal_element(1, 1, 1.0),
            damping: DMatrix::zeros(1, 1),
            basis: DMatrix::identity(1, 1),
        };
        assert!(matches!(
            lin.modes(),
            Err(VibrationError::SingularMass { dof: 1, .. })
        ));
    }
}
