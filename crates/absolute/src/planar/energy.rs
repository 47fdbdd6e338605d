//! Total mechanical energy of the planar scene: kinetic ½ ẋᵀ M_b ẋ, gravity
//! −gᵀ(m r0 + A m̄(y)), elastic U(y), and the spring–dampers' potential.

use nalgebra::{DVector, Vector2};

use super::Planar;
use super::algebra::c_of;

impl Planar {
    /// Kinetic + gravity + elastic + spring energy at (q, q̇) (J).
    pub(super) fn energy(&mut self, q: &DVector<f64>, qd: &DVector<f64>) -> f64 {
        let mut e = 0.0;
        for body_index in 0..self.bodies.len() {
            let b = &self.bodies[body_index];
            let n_local = 4 + b.n_modes;
            let frame = self.frame(b, q, qd);
            let (r0, u) = (frame.r0, frame.u);
            let xd = b.basis_rate(qd);
            if b.n_modes == 0 {
                e += 0.5 * xd.dot(&(b.rigid_mass * xd));
                // −gᵀ(m r0 + A m̄)
                let mb = b.body.first_moment();
                e -= self
                    .gravity
                    .dot(&(r0 * b.body.mass() + c_of(&Vector2::new(mb.x, mb.y)) * u));
                continue;
            }
            let b = &mut self.bodies[body_index];
            let (y, yd) = (&q.as_slice()[b.modes()], &qd.as_slice()[b.modes()]);
            let ws = b.flexible_workspace.as_mut().expect("workspace");
            ws.evaluate(
                &b.body,
                self.inertia_method,
                r0,
                u,
                frame.r0_rate,
                frame.u_rate,
                y,
                yd,
                self.gravity,
                &b.frame_map,
            );
            // ½ vᵀ M_b v with v = (ẋ_b, ẏ).
            let v = |i: usize| if i < 4 { xd[i] } else { yd[i - 4] };
            let mut kin = 0.0;
            for r in 0..n_local {
                for c in 0..n_local {
                    kin += v(r) * ws.m_b[(r, c)] * v(c);
                }
            }
            e += 0.5 * kin;
            e += ws.potential(&b.body, r0, u, y, self.gravity);
        }
        e + self.force_elements.potential_energy(self, q, qd)
    }
}
