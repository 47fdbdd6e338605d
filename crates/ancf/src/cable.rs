//! The cable as a [`Formulation`]: constant M, Q = elastic + distributed gravity with
//! the analytic tangent K = −∂Q/∂q, and the root constraints of the driven hub
//! (docs/methods.md §7.3), plus the static-equilibrium solver (§5.4 item 4).
//!
//! Coordinates: node k (k = 0..N) holds r_k (d values) then r′_k (d values) at offset
//! 2dk, so element e owns the contiguous slice [2de, 2de + 4d).
//!
//! Root constraints with n₁(θ) = (−sin θ, cos θ, 0), t₁ = (cos θ, sin θ, 0):
//!
//! - r₁ = 0 (d rows), r₁′·n₁(θ(t)) = 0, and in 3D r₁′·e_z = 0;
//! - Φ_t = ṅ₁·r₁′ with ṅ₁ = −θ̇ t₁;
//! - c = Φ̇_q q̇ + Φ̇_t = n̈₁·r₁′ + 2 ṅ₁·ṙ₁′ with n̈₁ = −θ̈ t₁ − θ̇² n₁.
//!
//! The root axial stretch stays free. θ, θ̇, θ̈ come from
//! [`flexmbd_model::MotionLaw::SpinUp`] (docs/methods.md §6.5).
//!
//! Sensors: the tip displacement in the frame turning with θ,
//! d = A(θ)ᵀ r_tip − (L, 0, 0) (`tip_ux`, `tip_uy`, and `tip_uz` in 3D), and the total
//! energy ½ q̇ᵀMq̇ + U(q) − Q_gᵀq (`energy`; the hub does work on it through the
//! constraint, dE/dt = λᵀΦ_t).

use flexmbd_core::{Coordinates, Dim, Formulation, InvalidValue, Request, State, SystemTerms};
use flexmbd_model::MotionLaw;
use nalgebra::{DMatrix, DVector};

use crate::element::{self, ElementRule, NE};
use crate::spec::CableSpec;

/// Why a static solution failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StaticError {
    /// Newton failed even with the smallest load increment.
    #[error(
        "static Newton did not converge at load factor {load_factor:.4} (increment {increment:.2e}): residual {residual:.3e}"
    )]
    NoConvergence {
        /// Load factor reached.
        load_factor: f64,
        /// Last increment tried.
        increment: f64,
        /// Largest residual entry.
        residual: f64,
    },
}

/// What the static solver did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StaticReport {
    /// Load steps accepted.
    pub load_steps: usize,
    /// Newton iterations, all steps.
    pub iterations: usize,
    /// ‖∂U/∂q − Q_g + Φ_qᵀλ‖∞ and ‖Φ‖∞ at the end.
    pub residual: f64,
    /// Constraint multipliers at equilibrium.
    pub lambda: Vec<f64>,
}

/// A uniform ANCF cable clamped to a driven hub; see the module documentation.
#[derive(Clone, Debug)]
pub struct Cable {
    spec: CableSpec,
    d: usize,
    /// n, m, the initial positions (straight, or the static equilibrium) at rest.
    coordinates: Coordinates,
    law: MotionLaw,
    rule: ElementRule,
    mass: DMatrix<f64>,
    gravity: DVector<f64>,
    names: Vec<String>,
    /// Element gradient and Hessian workspaces.
    grad: [f64; NE],
    hess: [[f64; NE]; NE],
}

impl Cable {
    /// Build the cable, straight along +x, at rest.
    pub fn new(spec: &CableSpec) -> Result<Cable, InvalidValue> {
        spec.validate()?;
        let d = spec.dim.n_trans();
        let ne = spec.elements;
        let n = 2 * d * (ne + 1);
        let m = match spec.dim {
            Dim::Planar => 3,
            Dim::Spatial => 5,
        };
        let le = spec.length / ne as f64;
        let rule = ElementRule {
            d,
            ea: spec.ea,
            ei: spec.ei,
            axial: element::gauss_points(le, 5),
            bending: element::gauss_points(le, 3),
        };
        let ms = element::mass_scalar(spec.rho_a, le);
        let ls = element::load_scalar(le);
        let mut mass = DMatrix::zeros(n, n);
        let mut gravity = DVector::zeros(n);
        for e in 0..ne {
            let o = 2 * d * e;
            for i in 0..4 {
                for k in 0..d {
                    gravity[o + i * d + k] += ls[i] * spec.rho_a * spec.gravity[k];
                    for j in 0..4 {
                        mass[(o + i * d + k, o + j * d + k)] += ms[i][j];
                    }
                }
            }
        }
        let mut q0 = DVector::zeros(n);
        for k in 0..=ne {
            q0[2 * d * k] = le * k as f64;
            q0[2 * d * k + d] = 1.0;
        }
        let mut names: Vec<String> = ["tip_ux", "tip_uy", "tip_uz"][..d]
            .iter()
            .map(|s| s.to_string())
            .collect();
        names.push("energy".into());
        Ok(Cable {
            spec: spec.clone(),
            d,
            coordinates: Coordinates::new(q0, DVector::zeros(n), m),
            law: MotionLaw::SpinUp {
                omega_s: spec.omega_s,
                t_s: spec.t_s,
            },
            rule,
            mass,
            gravity,
            names,
            grad: [0.0; NE],
            hess: [[0.0; NE]; NE],
        })
    }

    /// The description this cable was built from.
    pub fn spec(&self) -> &CableSpec {
        &self.spec
    }
    /// Components per vector (2 or 3).
    pub fn dim_components(&self) -> usize {
        self.d
    }
    /// The constant mass matrix.
    pub fn mass(&self) -> &DMatrix<f64> {
        &self.mass
    }
    /// The constant gravity force vector Q_g.
    pub fn gravity_forces(&self) -> &DVector<f64> {
        &self.gravity
    }
    /// The initial positions used by [`Formulation::initial_guess`] (straight, or the
    /// static equilibrium after [`Cable::solve_static`]).
    pub fn initial_positions(&self) -> &DVector<f64> {
        &self.coordinates.q0
    }
    /// Replace the initial positions.
    pub fn set_initial_positions(&mut self, q: &DVector<f64>) {
        self.coordinates.q0.copy_from(q);
    }
    /// Index of the row r₁′·n₁(θ) = 0 (the driven one) among the constraints.
    pub fn driven_row(&self) -> usize {
        self.d
    }
    /// θ, θ̇, θ̈ of the hub.
    pub fn hub(&self, t: f64) -> (f64, f64, f64) {
        self.law.eval(t)
    }

    /// Elastic energy U(q); with `grad`, sets ∂U/∂q; with `tangent`, adds ∂²U/∂q² into it.
    pub fn elastic(
        &mut self,
        q: &DVector<f64>,
        mut grad: Option<&mut DVector<f64>>,
        mut tangent: Option<&mut DMatrix<f64>>,
    ) -> f64 {
        if let Some(g) = grad.as_deref_mut() {
            g.fill(0.0);
        }
        let d = self.d;
        let nd = 4 * d;
        let mut u = 0.0;
        for e in 0..self.spec.elements {
            let o = 2 * d * e;
            let qe = &q.as_slice()[o..o + nd];
            self.grad = [0.0; NE];
            let want_h = tangent.is_some();
            if want_h {
                self.hess = [[0.0; NE]; NE];
            }
            u += self.rule.energy(
                qe,
                Some(&mut self.grad),
                if want_h { Some(&mut self.hess) } else { None },
            );
            if let Some(g) = grad.as_deref_mut() {
                for i in 0..nd {
                    g[o + i] += self.grad[i];
                }
            }
            if let Some(k) = tangent.as_deref_mut() {
                for j in 0..nd {
                    for i in 0..nd {
                        k[(o + i, o + j)] += self.hess[i][j];
                    }
                }
            }
        }
        u
    }

    /// Tip displacement in the frame turning with θ(t): d = A(θ)ᵀ r_tip − (L, 0, 0).
    pub fn tip_displacement(&self, t: f64, q: &DVector<f64>) -> [f64; 3] {
        let (th, _, _) = self.law.eval(t);
        let o = 2 * self.d * self.spec.elements;
        let (c, s) = (th.cos(), th.sin());
        let (x, y) = (q[o], q[o + 1]);
        let z = if self.d == 3 { q[o + 2] } else { 0.0 };
        [c * x + s * y - self.spec.length, -s * x + c * y, z]
    }

    /// Total energy ½ q̇ᵀMq̇ + U(q) − Q_gᵀq.
    pub fn energy(&mut self, q: &DVector<f64>, qd: &DVector<f64>) -> f64 {
        let n = self.coordinates.len();
        let mut kin = 0.0;
        for j in 0..n {
            let mut col = 0.0;
            for i in 0..n {
                col += self.mass[(i, j)] * qd[i];
            }
            kin += col * qd[j];
        }
        0.5 * kin + self.elastic(q, None, None) - self.gravity.dot(q)
    }

    /// Angular momentum about the hub axis z, ∫ ρA (r × ṙ)·e_z dx = Σ M̂ᵢⱼ (xᵢ ẏⱼ − yᵢ ẋⱼ).
    pub fn angular_momentum_z(&self, q: &DVector<f64>, qd: &DVector<f64>) -> f64 {
        let (d, n) = (self.d, self.coordinates.len());
        let mut h = 0.0;
        for i in (0..n).step_by(d) {
            for j in (0..n).step_by(d) {
                let mij = self.mass[(i, j)];
                if mij != 0.0 {
                    h += mij * (q[i] * qd[j + 1] - q[i + 1] * qd[j]);
                }
            }
        }
        h
    }

    /// Root constraints Φ at (t, q) (see the module documentation).
    fn constraints(&self, t: f64, q: &DVector<f64>, phi: &mut DVector<f64>) {
        let d = self.d;
        let (th, _, _) = self.law.eval(t);
        for k in 0..d {
            phi[k] = q[k];
        }
        phi[d] = -th.sin() * q[d] + th.cos() * q[d + 1];
        if d == 3 {
            phi[4] = q[5];
        }
    }

    fn jacobian(
        &self,
        t: f64,
        q: &DVector<f64>,
        phi_q: &mut DMatrix<f64>,
        phi_t: &mut DVector<f64>,
    ) {
        let d = self.d;
        let (th, thd, _) = self.law.eval(t);
        let (c, s) = (th.cos(), th.sin());
        for k in 0..d {
            phi_q[(k, k)] = 1.0;
        }
        phi_q[(d, d)] = -s;
        phi_q[(d, d + 1)] = c;
        if d == 3 {
            phi_q[(4, 5)] = 1.0;
        }
        // Φ_t = ṅ₁·r₁′, ṅ₁ = −θ̇ t₁.
        phi_t[d] = -thd * (c * q[d] + s * q[d + 1]);
    }

    /// Static equilibrium at time t (hub angle θ(t) held) under the full gravity load:
    /// Newton on ∂U/∂q − μ Q_g + Φ_qᵀλ = 0, Φ = 0 with the bordered tangent
    /// [K Φ_qᵀ; Φ_q 0], load factor μ raised to 1 in `load_steps` increments, halved on
    /// failure and doubled again (up to 1/`load_steps`) after a step that took ≤ 5
    /// iterations (docs/methods.md §5.4 item 4). Starts from and updates the initial positions.
    pub fn solve_static(&mut self, t: f64, load_steps: usize) -> Result<StaticReport, StaticError> {
        let (n, m) = (self.coordinates.len(), self.coordinates.n_constraints);
        let mut q = self.coordinates.q0.clone();
        let mut lambda = DVector::zeros(m);
        let mut grad = DVector::zeros(n);
        let mut k = DMatrix::zeros(n, n);
        let mut phi = DVector::zeros(m);
        let mut phi_q = DMatrix::zeros(m, n);
        let mut phi_t = DVector::zeros(m);
        let mut a = DMatrix::zeros(n + m, n + m);
        let mut r = DVector::zeros(n + m);
        let mut report = StaticReport::default();
        let mut mu = 0.0;
        let mut inc = 1.0 / load_steps.max(1) as f64;
        let scale = self.gravity.amax().max(self.spec.ea * 1e-6).max(1e-300);
        let mut last_res;
        loop {
            let target = if mu + inc > 1.0 - 1e-9 { 1.0 } else { mu + inc };
            let (q_save, l_save) = (q.clone(), lambda.clone());
            let mut converged = false;
            last_res = f64::INFINITY;
            let mut step_iterations = 0;
            for _ in 0..30 {
                step_iterations += 1;
                report.iterations += 1;
                k.fill(0.0);
                self.elastic(&q, Some(&mut grad), Some(&mut k));
                phi_q.fill(0.0);
                self.constraints(t, &q, &mut phi);
                self.jacobian(t, &q, &mut phi_q, &mut phi_t);
                let mut res = grad.clone();
                res.axpy(-target, &self.gravity, 1.0);
                res.gemv_tr(1.0, &phi_q, &lambda, 1.0);
                last_res = res.amax() / scale + phi.amax();
                r.rows_mut(0, n).copy_from(&(-&res));
                r.rows_mut(n, m).copy_from(&(-&phi));
                a.fill(0.0);
                a.view_mut((0, 0), (n, n)).copy_from(&k);
                a.view_mut((0, n), (n, m)).copy_from(&phi_q.transpose());
                a.view_mut((n, 0), (m, n)).copy_from(&phi_q);
                let Some(x) = a.clone().lu().solve(&r) else {
                    break;
                };
                if !x.iter().all(|v| v.is_finite()) {
                    break;
                }
                q += x.rows(0, n);
                lambda += x.rows(n, m);
                let dq = x.rows(0, n).amax();
                if dq <= 1e-12 * q.amax().max(1.0) {
                    converged = true;
                    break;
                }
            }
            if converged {
                mu = target;
                report.load_steps += 1;
                // Grow a halved increment again after an easy step.
                if step_iterations <= 5 {
                    inc = (2.0 * inc).min(1.0 / load_steps.max(1) as f64);
                }
                if mu >= 1.0 {
                    break;
                }
            } else {
                q = q_save;
                lambda = l_save;
                inc *= 0.5;
                if inc < 1e-6 {
                    return Err(StaticError::NoConvergence {
                        load_factor: mu,
                        increment: inc,
                        residual: last_res,
                    });
                }
            }
        }
        // Final residual at the solution.
        self.elastic(&q, Some(&mut grad), None);
        self.constraints(t, &q, &mut phi);
        let mut res = grad.clone();
        res -= &self.gravity;
        res.gemv_tr(1.0, &phi_q, &lambda, 1.0);
        report.residual = res.amax().max(phi.amax());
        report.lambda = lambda.iter().copied().collect();
        self.coordinates.q0 = q;
        Ok(report)
    }
}

impl Formulation for Cable {
    fn coordinates(&self) -> &Coordinates {
        &self.coordinates
    }
    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        let State { t, q, qd, .. } = state;
        let d = self.d;
        if req.dynamics {
            out.mass.copy_from(&self.mass);
            let nd = 4 * d;
            for e in 0..self.spec.elements {
                let o = 2 * d * e;
                let qe = &q.as_slice()[o..o + nd];
                self.grad = [0.0; NE];
                if req.tangents {
                    self.hess = [[0.0; NE]; NE];
                    self.rule
                        .energy(qe, Some(&mut self.grad), Some(&mut self.hess));
                    // K = −∂Q/∂q = ∂²U/∂q².
                    for j in 0..nd {
                        for i in 0..nd {
                            out.stiffness[(o + i, o + j)] += self.hess[i][j];
                        }
                    }
                } else {
                    self.rule.energy(qe, Some(&mut self.grad), None);
                }
                for i in 0..nd {
                    out.forces[o + i] -= self.grad[i];
                }
            }
            out.forces += &self.gravity;
        }
        if req.constraints {
            self.constraints(t, q, &mut out.phi);
        }
        if req.jacobian {
            self.jacobian(t, q, &mut out.phi_q, &mut out.phi_t);
        }
        if req.accel_term {
            let (th, thd, thdd) = self.law.eval(t);
            let (c, s) = (th.cos(), th.sin());
            // n̈₁ = −θ̈ t₁ − θ̇² n₁, ṅ₁ = −θ̇ t₁.
            let nddx = -thdd * c + thd * thd * s;
            let nddy = -thdd * s - thd * thd * c;
            let (ndx, ndy) = (-thd * c, -thd * s);
            out.accel_term[d] =
                nddx * q[d] + nddy * q[d + 1] + 2.0 * (ndx * qd[d] + ndy * qd[d + 1]);
        }
    }
}

impl flexmbd_core::Observe for Cable {
    fn sensor_names(&self) -> &[String] {
        &self.names
    }
    fn sensors(&mut self, state: State<'_>, out: &mut [f64]) {
        let State { t, q, qd, .. } = state;
        let tip = self.tip_displacement(t, q);
        let d = self.d;
        out[..d].copy_from_slice(&tip[..d]);
        out[d] = self.energy(q, qd);
    }
    /// The cable has no floating frame: nothing is written.
    fn body_poses(&mut self, _state: State<'_>, _out: &mut [flexmbd_core::BodyPose]) {}
}
