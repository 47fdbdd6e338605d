//! Driven coordinates taken out of the unknowns (rheonomic coordinates).
//!
//! A joint driven by a law, z_c = s θ(t), is a coordinate whose position, rate and
//! acceleration are known at every t. Kept among the unknowns it costs a constraint row
//! z_c − s θ(t) = 0, its multiplier, the projections that enforce ż_c = s θ̇ and
//! z̈_c = s θ̈, and a Newton correction of a value known beforehand. Taken out, the
//! equations of motion of the other coordinates q_f read (q = {q_f; q_d}, q_d = q_d(t)):
//!
//! ```text
//! M_ff q̈_f + Φ_fᵀ λ = Q_f − M_fd q̈_d(t)
//! Φ(q_f, q_d(t)) = 0,   Φ_t ← Φ_t + Φ_d q̇_d(t),   c ← c + Φ_d q̈_d(t)
//! ```
//!
//! with Q, c evaluated at the whole state {q_f; q_d(t)}, {q̇_f; q̇_d(t)} (so every velocity
//! product sees the driven rates), K and C restricted to q_f (the driven coordinates do
//! not vary with the unknowns), and the rows that only prescribed q_d dropped. This is the
//! velocity transformation with a rheonomic term of García de Jalón & Bayo (1994, §5.3)
//! applied to a coordinate subset: the same differential-algebraic equations, in fewer
//! unknowns. A spin-up beam driven at its hub (docs/scenes.md §5) becomes its modal
//! coordinates alone, without constraints.
//!
//! A formulation declares its driven coordinates ([`Formulation::driven_coordinates`]) and
//! gives their motion ([`Formulation::driven_motion`]); [`DrivenEliminated`] wraps it so
//! that the integrator sees the free coordinates only. Its sensors and body poses read the
//! whole state, rebuilt from the free coordinates and the law.

use nalgebra::{DMatrix, DVector};

use crate::{
    BodyMotion, BodyPose, CompiledScene, Coordinates, DeclaredPattern, Formulation, Observe,
    Request, State, SystemTerms,
};

/// The coordinates of a formulation that are known functions of time, and the constraint
/// rows that do nothing but prescribe them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DrivenCoordinates {
    /// The driven coordinates (indices into q), without repeats, in the order in which
    /// [`Formulation::driven_motion`] gives their motion.
    pub coordinates: Vec<usize>,
    /// The rows of Φ that prescribe them (z_c − s θ(t) = 0), without repeats.
    pub rows: Vec<usize>,
}

/// A compiled scene with its driven coordinates taken out of the unknowns (module
/// documentation). Built by [`DrivenEliminated::wrap`], which leaves a scene without driven
/// coordinates as it is.
pub struct DrivenEliminated {
    inner: Box<dyn CompiledScene>,
    /// The free coordinates (indices into the whole q), increasing.
    free: Vec<usize>,
    /// The driven coordinates, in the order of their motion.
    driven: Vec<usize>,
    /// The rows of Φ that stay, increasing.
    kept_rows: Vec<usize>,
    /// The reduced coordinates: free ones of the whole q₀, q̇₀; the kept rows.
    coordinates: Coordinates,
    /// Per driven coordinate, (q_d, q̇_d, q̈_d) at the last time asked.
    motion: Vec<[f64; 3]>,
    /// The whole state handed to the wrapped formulation.
    q: DVector<f64>,
    qd: DVector<f64>,
    qdd: DVector<f64>,
    /// The wrapped formulation's terms at the whole state.
    whole: SystemTerms,
}

impl DrivenEliminated {
    /// `inner` with its driven coordinates taken out, or `inner` itself when it declares
    /// none.
    pub fn wrap(inner: Box<dyn CompiledScene>) -> Box<dyn CompiledScene> {
        match inner.driven_coordinates() {
            Some(d) if !d.coordinates.is_empty() => Box::new(DrivenEliminated::new(inner, d)),
            _ => inner,
        }
    }

    fn new(mut inner: Box<dyn CompiledScene>, d: DrivenCoordinates) -> Self {
        let (n, m) = (inner.n_coordinates(), inner.n_constraints());
        let free: Vec<usize> = (0..n).filter(|i| !d.coordinates.contains(i)).collect();
        let kept_rows: Vec<usize> = (0..m).filter(|r| !d.rows.contains(r)).collect();
        let (mut q0, mut qd0) = (DVector::zeros(n), DVector::zeros(n));
        inner.initial_guess(&mut q0, &mut qd0);
        start_velocities_for_the_law(inner.as_mut(), &free, &d.coordinates, &mut q0, &mut qd0);
        let gather =
            |v: &DVector<f64>| DVector::from_iterator(free.len(), free.iter().map(|&i| v[i]));
        let specified = inner
            .specified_coordinates()
            .iter()
            .filter_map(|s| free.binary_search(s).ok())
            .collect();
        let coordinates = Coordinates {
            specified,
            ..Coordinates::new(gather(&q0), gather(&qd0), kept_rows.len())
        };
        DrivenEliminated {
            motion: vec![[0.0; 3]; d.coordinates.len()],
            driven: d.coordinates,
            whole: SystemTerms::new(n, m),
            q: q0,
            qd: qd0,
            qdd: DVector::zeros(n),
            inner,
            free,
            kept_rows,
            coordinates,
        }
    }

    /// The whole q, q̇, q̈ at the reduced state: the free coordinates from it (q̈ = 0 when it
    /// has none), the driven ones from the law at t.
    fn expand(&mut self, state: State<'_>) {
        self.inner.driven_motion(state.t, &mut self.motion);
        for (k, &i) in self.free.iter().enumerate() {
            self.q[i] = state.q[k];
            self.qd[i] = state.qd[k];
            self.qdd[i] = state.qdd.map_or(0.0, |a| a[k]);
        }
        for (&i, m) in self.driven.iter().zip(&self.motion) {
            (self.q[i], self.qd[i], self.qdd[i]) = (m[0], m[1], m[2]);
        }
    }
}

/// The initial guess made to follow the law at t = 0, with the free rates moved so that
/// the integrator's mass-weighted projection of the free rates lands where the projection
/// of all rates under the driver rows would (methods.md §5.4).
///
/// That projection minimises ½ δᵀ M δ, δ = q̇ − q̇*, under Φ_q q̇ + Φ_t = 0. With the driven
/// rates fixed, δ_d = q̇_d(0) − q̇*_d, its free part satisfies M_ff δ_f + M_fd δ_d + Φ_fᵀ λ = 0,
/// which is the projection of the free rates alone from q̇*_f − M_ff⁻¹ M_fd δ_d. A scene whose
/// start velocities disagree with the law (a crank given ω = −1 rad/s and driven from rest)
/// otherwise starts with other free rates, which excite the flexible bodies' modes: on the
/// double four-bar with a flexible crank, 3.9 Newton iterations a step against 2.0.
fn start_velocities_for_the_law(
    inner: &mut dyn CompiledScene,
    free: &[usize],
    driven: &[usize],
    q0: &mut DVector<f64>,
    qd0: &mut DVector<f64>,
) {
    let mut motion = vec![[0.0; 3]; driven.len()];
    inner.driven_motion(0.0, &mut motion);
    let miss: Vec<f64> = driven
        .iter()
        .zip(&motion)
        .map(|(&i, m)| m[1] - qd0[i])
        .collect();
    for (&i, m) in driven.iter().zip(&motion) {
        (q0[i], qd0[i]) = (m[0], m[1]);
    }
    if miss.iter().all(|&x| x == 0.0) {
        return;
    }
    let mut terms = SystemTerms::new(q0.len(), inner.n_constraints());
    let dynamics = Request {
        dynamics: true,
        ..Request::default()
    };
    inner.evaluate(State::new(0.0, q0, qd0), dynamics, &mut terms);
    let m_ff = DMatrix::from_fn(free.len(), free.len(), |a, b| {
        terms.mass[(free[a], free[b])]
    });
    let m_fd_miss = DVector::from_fn(free.len(), |a, _| {
        driven
            .iter()
            .zip(&miss)
            .map(|(&d, x)| terms.mass[(free[a], d)] * x)
            .sum::<f64>()
    });
    // A singular M_ff (a massless free coordinate) keeps the guess as it is.
    if let Some(shift) = m_ff.cholesky().map(|c| c.solve(&m_fd_miss)) {
        for (&i, s) in free.iter().zip(shift.iter()) {
            qd0[i] -= s;
        }
    }
}

impl Formulation for DrivenEliminated {
    fn coordinates(&self) -> &Coordinates {
        &self.coordinates
    }

    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        let rows = !self.kept_rows.is_empty();
        if !req.dynamics && !rows {
            return;
        }
        self.expand(state);
        // Φ_t and c of the kept rows take Φ_d times the driven rates and accelerations.
        let inner_req = Request {
            constraints: req.constraints && rows,
            jacobian: (req.jacobian || req.accel_term) && rows,
            accel_term: req.accel_term && rows,
            ..req
        };
        self.whole.clear(inner_req);
        self.inner.evaluate(
            State::new(state.t, &self.q, &self.qd),
            inner_req,
            &mut self.whole,
        );
        let w = &self.whole;
        if req.dynamics {
            for (a, &j) in self.free.iter().enumerate() {
                for (b, &i) in self.free.iter().enumerate() {
                    out.mass[(b, a)] = w.mass[(i, j)];
                }
            }
            for (b, &i) in self.free.iter().enumerate() {
                let mut q = w.forces[i];
                for (&d, m) in self.driven.iter().zip(&self.motion) {
                    q -= w.mass[(i, d)] * m[2];
                }
                out.forces[b] = q;
            }
            if req.tangents {
                for (a, &j) in self.free.iter().enumerate() {
                    for (b, &i) in self.free.iter().enumerate() {
                        out.stiffness[(b, a)] = w.stiffness[(i, j)];
                        out.damping[(b, a)] = w.damping[(i, j)];
                    }
                }
            }
        }
        for (r, &row) in self.kept_rows.iter().enumerate() {
            if req.constraints {
                out.phi[r] = w.phi[row];
            }
            if req.jacobian {
                for (a, &j) in self.free.iter().enumerate() {
                    out.phi_q[(r, a)] = w.phi_q[(row, j)];
                }
                let mut phi_t = w.phi_t[row];
                for (&d, m) in self.driven.iter().zip(&self.motion) {
                    phi_t += w.phi_q[(row, d)] * m[1];
                }
                out.phi_t[r] = phi_t;
            }
            if req.accel_term {
                let mut c = w.accel_term[row];
                for (&d, m) in self.driven.iter().zip(&self.motion) {
                    c += w.phi_q[(row, d)] * m[2];
                }
                out.accel_term[r] = c;
            }
        }
    }

    fn constant_tangents(&self) -> bool {
        self.inner.constant_tangents()
    }
    fn constant_mass(&self) -> bool {
        self.inner.constant_mass()
    }
    fn symmetric_tangent(&self) -> bool {
        self.inner.symmetric_tangent()
    }
    fn predictor_repeats_miss(&self) -> bool {
        self.inner.predictor_repeats_miss()
    }
    /// The wrapped formulation's pattern on the free coordinates and the kept rows.
    fn declared_pattern(&self) -> Option<DeclaredPattern> {
        let p = self.inner.declared_pattern()?;
        let reduce = |cols: &[usize]| -> Vec<usize> {
            cols.iter()
                .filter_map(|c| self.free.binary_search(c).ok())
                .collect()
        };
        Some(DeclaredPattern {
            coupled: p
                .coupled
                .iter()
                .map(|g| reduce(g))
                .filter(|g| !g.is_empty())
                .collect(),
            jacobian_rows: self
                .kept_rows
                .iter()
                .map(|&r| reduce(&p.jacobian_rows[r]))
                .collect(),
        })
    }
}

impl Observe for DrivenEliminated {
    fn sensor_names(&self) -> &[String] {
        self.inner.sensor_names()
    }
    fn sensors(&mut self, state: State<'_>, out: &mut [f64]) {
        self.expand(state);
        let whole = State::new(state.t, &self.q, &self.qd).with_accelerations(&self.qdd);
        self.inner.sensors(whole, out);
    }
    fn body_poses(&mut self, state: State<'_>, out: &mut [BodyPose]) {
        self.expand(state);
        let whole = State::new(state.t, &self.q, &self.qd).with_accelerations(&self.qdd);
        self.inner.body_poses(whole, out);
    }
    fn body_motions(&mut self, state: State<'_>, out: &mut [BodyMotion]) -> bool {
        self.expand(state);
        let whole = State::new(state.t, &self.q, &self.qd).with_accelerations(&self.qdd);
        self.inner.body_motions(whole, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// q = (q₀, q₁), q₀ = a t² driven: M = [2 1; 1 3], Q = (q₀ + q̇₁, 5 q₁), K = −∂Q/∂q,
    /// rows: the driver q₀ − a t² = 0 and Φ = q₀ q₁ − 1 (Φ_t = 0, c = 2 q̇₀ q̇₁).
    struct Toy {
        coordinates: Coordinates,
        a: f64,
    }

    impl Formulation for Toy {
        fn coordinates(&self) -> &Coordinates {
            &self.coordinates
        }
        fn evaluate(&mut self, s: State<'_>, req: Request, out: &mut SystemTerms) {
            let (q, qd) = (s.q, s.qd);
            if req.dynamics {
                out.mass.copy_from_slice(&[2.0, 1.0, 1.0, 3.0]);
                out.forces.copy_from_slice(&[q[0] + qd[1], 5.0 * q[1]]);
                out.stiffness.copy_from_slice(&[-1.0, 0.0, 0.0, -5.0]);
                out.damping.copy_from_slice(&[0.0, 0.0, -1.0, 0.0]);
            }
            let a = self.a;
            if req.constraints {
                out.phi
                    .copy_from_slice(&[q[0] - a * s.t * s.t, q[0] * q[1] - 1.0]);
            }
            if req.jacobian {
                out.phi_q.copy_from_slice(&[1.0, q[1], 0.0, q[0]]);
                out.phi_t.copy_from_slice(&[-2.0 * a * s.t, 0.0]);
            }
            if req.accel_term {
                out.accel_term
                    .copy_from_slice(&[-2.0 * a, 2.0 * qd[0] * qd[1]]);
            }
        }
        fn driven_coordinates(&self) -> Option<DrivenCoordinates> {
            Some(DrivenCoordinates {
                coordinates: vec![0],
                rows: vec![0],
            })
        }
        fn driven_motion(&self, t: f64, out: &mut [[f64; 3]]) {
            out[0] = [self.a * t * t, 2.0 * self.a * t, 2.0 * self.a];
        }
    }

    impl Observe for Toy {
        fn sensor_names(&self) -> &[String] {
            &[]
        }
        fn sensors(&mut self, _: State<'_>, _: &mut [f64]) {}
        fn body_poses(&mut self, _: State<'_>, _: &mut [BodyPose]) {}
    }

    /// The toy at q = (0, 2), q̇ = (0.5, 0.25), a = 0.75.
    fn toy() -> Box<dyn CompiledScene> {
        Box::new(Toy {
            coordinates: Coordinates::new(
                DVector::from_vec(vec![0.0, 2.0]),
                DVector::from_vec(vec![0.5, 0.25]),
                2,
            ),
            a: 0.75,
        })
    }

    #[test]
    fn the_free_equations_take_the_law_through_the_driven_columns() {
        let mut f = DrivenEliminated::wrap(toy());
        assert_eq!((f.n_coordinates(), f.n_constraints()), (1, 1));
        let (t, q1, qd1) = (2.0, 0.4, -0.3);
        let (q0, qd0, qdd0) = (0.75 * t * t, 1.5 * t, 1.5);
        let (q, qd) = (DVector::from_element(1, q1), DVector::from_element(1, qd1));
        let mut out = SystemTerms::new(1, 1);
        f.evaluate(State::new(t, &q, &qd), Request::ALL, &mut out);
        assert_eq!(out.mass[(0, 0)], 3.0);
        // Q₁ − M₁₀ q̈₀.
        assert_eq!(out.forces[0], 5.0 * q1 - 1.0 * qdd0);
        assert_eq!((out.stiffness[(0, 0)], out.damping[(0, 0)]), (-5.0, 0.0));
        assert_eq!(out.phi[0], q0 * q1 - 1.0);
        assert_eq!(out.phi_q[(0, 0)], q0);
        // Φ_t + Φ_q0 q̇₀ and c + Φ_q0 q̈₀.
        assert_eq!(out.phi_t[0], q1 * qd0);
        assert_eq!(out.accel_term[0], 2.0 * qd0 * qd1 + q1 * qdd0);
    }

    #[test]
    fn start_rates_are_projected_as_under_the_driver_rows() {
        // At t = 0 the law has q̇₀ = 0 where the guess says 0.5: the free rate moves by
        // −M₁₁⁻¹ M₁₀ (0 − 0.5) = 0.5 / 3.
        let f = DrivenEliminated::wrap(toy());
        let c = f.coordinates();
        assert_eq!(c.q0.as_slice(), &[2.0]);
        assert!(
            (c.qd0[0] - (0.25 + 0.5 / 3.0)).abs() < 1e-15,
            "{}",
            c.qd0[0]
        );
    }
}
