//! Inspection: the total mechanical energy (the `Energy` sensor),
//! E = ½ Σ_k Z_kᵀ M̄_k Z_k − Σ_k g·(m_k r0_k + A_k m̄_k(y)) + Σ_k U_k(y) + the spring
//! potentials, and the public inspectors for tests and tools (they allocate; they are not
//! on the per-step path).

use nalgebra::{DMatrix, DVector};

use crate::system::Relative;

impl Relative {
    /// Total mechanical energy: ½ Σ Z_kᵀ M̄_k Z_k + gravity potential + ½ Σ yᵀ K_ff y.
    pub(crate) fn energy(&mut self, z: &DVector<f64>, zd: &DVector<f64>) -> f64 {
        let mut e = 0.0;
        for k in 0..self.bodies.len() {
            let state = self.body_state(k, z, zd);
            let inertia_method = self.inertia_method;
            let (rigid_size, rigid_entries, g) =
                (self.rigid_size, self.rigid_entries, self.gravity);
            let zr = self.frame_velocity[self.bodies[k].frame];
            let b = &mut self.bodies[k];
            b.body
                .inertia(&state, inertia_method, &mut b.m_bar, &mut b.q_bar);
            let nc = rigid_size + b.n_modes;
            let v = |i: usize| {
                if i < rigid_size {
                    zr[rigid_entries[i]]
                } else {
                    state.y_dot[i - rigid_size]
                }
            };
            let mut kin = 0.0;
            for r in 0..nc {
                for c in 0..nc {
                    kin += v(r) * b.m_bar[(r, c)] * v(c);
                }
            }
            e += 0.5 * kin;
            let mb = b.body.first_moment_at(state.y);
            e -= g.dot(&(state.r0 * b.body.mass() + state.a * mb));
            e += b.body.strain_energy(state.y);
        }
        e + self.force_elements.potential_energy(self, z, zd)
    }

    /// Names of the coordinates z (joint coordinates, then `body.y<m>`).
    pub fn coordinate_names(&self) -> &[String] {
        &self.coordinate_names
    }
}

/// Inspection, for tests and tools (allocates; not on the per-step path).
impl Relative {
    /// Number of bodies.
    pub fn n_bodies(&self) -> usize {
        self.bodies.len()
    }
    /// Rigid velocity entries per body: 3 (2D: ṡx, ṡy, ωz) or 6 (3D: ṡ, ω).
    pub fn rigid_size(&self) -> usize {
        self.rigid_size
    }
    /// First modal coordinate of body k in z, and its number of modes.
    pub fn body_modes(&self, k: usize) -> (usize, usize) {
        (self.bodies[k].first_mode, self.bodies[k].n_modes)
    }
    /// Body k's velocity Z_k = {ṡ; ω; ẏ} and its velocity-product acceleration
    /// {D_k; 0} = (Ṙ ż)_k at (z, ż), in the body-term order of `flexmbd-body`.
    pub fn body_velocity(
        &mut self,
        z: &DVector<f64>,
        zd: &DVector<f64>,
        k: usize,
    ) -> (DVector<f64>, DVector<f64>) {
        self.kinematics(z, zd);
        let b = &self.bodies[k];
        let (zr, d) = (self.frame_velocity[b.frame], self.frame_bias[b.frame]);
        let nc = self.rigid_size + b.n_modes;
        let mut v = DVector::zeros(nc);
        let mut dv = DVector::zeros(nc);
        for i in 0..self.rigid_size {
            v[i] = zr[self.rigid_entries[i]];
            dv[i] = d[self.rigid_entries[i]];
        }
        for m in 0..b.n_modes {
            v[self.rigid_size + m] = zd[b.first_mode + m];
        }
        (v, dv)
    }
    /// Body k's M̄_k and Q̄_k (inertia, gravity, elastic forces) in the s form at (z, ż).
    pub fn body_terms(
        &mut self,
        z: &DVector<f64>,
        zd: &DVector<f64>,
        k: usize,
    ) -> (DMatrix<f64>, DVector<f64>) {
        self.kinematics(z, zd);
        self.evaluate_bodies(z, zd);
        (self.bodies[k].m_bar.clone(), self.bodies[k].q_bar.clone())
    }
    /// Total mechanical energy at (z, ż) (the `Energy` sensor).
    pub fn total_energy(&mut self, z: &DVector<f64>, zd: &DVector<f64>) -> f64 {
        self.kinematics(z, zd);
        self.energy(z, zd)
    }
}
