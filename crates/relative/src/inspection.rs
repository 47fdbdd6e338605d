//! Inspection: the total mechanical energy (the `Energy` sensor),
//! E = ½ Σ_k Z_kᵀ M̄_k Z_k − Σ_k g·(m_k r0_k + A_k m̄_k(y)) + Σ_k U_k(y) + the spring
//! potentials, and the public inspectors for tests and tools (they allocate; they are not
//! on the per-step path).

use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

use crate::body_kernels::{BodyKernel, rigid_dense_terms};
use crate::system::Relative;

impl Relative {
    /// Total mechanical energy: ½ Σ Z_kᵀ M̄_k Z_k + gravity potential + Σ U_k(y).
    pub(crate) fn energy(&mut self, z: &DVector<f64>, zd: &DVector<f64>) -> f64 {
        let mut e = 0.0;
        for k in 0..self.bodies.len() {
            let state = self.body_state(k, z, zd);
            let frame = self.frame_motion(k);
            let (rigid_size, rigid_entries, g) = (
                self.tree.rigid_size(),
                self.tree.rigid_entries(),
                self.assembly.gravity,
            );
            let zr = frame.velocity;
            let (inertia_method, b) = (self.assembly.inertia_method, &mut self.bodies[k]);
            let v = |i: usize| {
                if i < rigid_size {
                    zr[rigid_entries[i]]
                } else {
                    state.y_dot[i - rigid_size]
                }
            };
            // ½ Zᵀ M̄ Z over the body's nc velocity entries, M̄ given entry by entry.
            let kinetic = |m: &dyn Fn(usize, usize) -> f64, nc: usize| {
                let mut kin = 0.0;
                for r in 0..nc {
                    for c in 0..nc {
                        kin += v(r) * m(r, c) * v(c);
                    }
                }
                0.5 * kin
            };
            match &mut b.kernel {
                BodyKernel::Flexible(f) => {
                    f.body
                        .inertia(&state, inertia_method, &mut f.m_bar, &mut f.q_bar);
                    e += kinetic(&|r, c| f.m_bar[(r, c)], rigid_size + b.n_modes);
                    e += f.body.strain_energy(state.y);
                }
                BodyKernel::RigidSpatial(r) => {
                    let (mut m6, mut p6) = (Matrix6::zeros(), Vector6::zeros());
                    r.terms(&frame, &g, &mut m6, &mut p6);
                    e += kinetic(&|i, j| m6[(i, j)], 6);
                }
                BodyKernel::RigidPlanar(r) => {
                    let (mut m6, mut p6) = (Matrix6::zeros(), Vector6::zeros());
                    r.terms(&frame, &g, &mut m6, &mut p6);
                    let at = |i: usize| rigid_entries[i];
                    e += kinetic(&|i, j| m6[(at(i), at(j))], 3);
                }
            }
            let (mass, mb) = b.kernel.mass_and_first_moment(state.y);
            e -= g.dot(&(state.r0 * mass + state.a * mb));
        }
        e + self.forces.elements.potential_energy(self, z, zd)
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
        self.tree.rigid_size()
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
        let (zr, d) = (self.frames.velocity[b.frame], self.frames.bias[b.frame]);
        let nc = self.tree.rigid_size() + b.n_modes;
        let mut v = DVector::zeros(nc);
        let mut dv = DVector::zeros(nc);
        for i in 0..self.tree.rigid_size() {
            v[i] = zr[self.tree.rigid_entries()[i]];
            dv[i] = d[self.tree.rigid_entries()[i]];
        }
        for m in 0..b.n_modes {
            v[self.tree.rigid_size() + m] = zd[b.first_mode + m];
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
        let frame = self.frame_motion(k);
        let kernel = &self.bodies[k].kernel;
        match kernel.flexible() {
            Some(f) => f.dense_terms(self.tree.rigid_entries()),
            None => rigid_dense_terms(kernel, &frame, &self.assembly.gravity)
                .expect("a body without a flexible kernel is rigid"),
        }
    }
    /// Total mechanical energy at (z, ż) (the `Energy` sensor).
    pub fn total_energy(&mut self, z: &DVector<f64>, zd: &DVector<f64>) -> f64 {
        self.kinematics(z, zd);
        self.energy(z, zd)
    }
}
