//! The initial state: z(0) from the placements (joint coordinates 0, modes from
//! `initial_modes`) and ż(0) by the kinetic-energy-weighted least-squares fit of the scene's
//! body velocities, M ż = Σ_k R_kᵀ M̄_k Z*_k (docs/methods.md §4.4). The integrator makes both
//! consistent with the constraints.

use flexmbd_body::BodyState;
use flexmbd_core::Dim;
use flexmbd_model::Scene;
use nalgebra::{DMatrix, DVector, Vector3, Vector6};

use crate::system::Relative;

impl Relative {
    /// ż(0): the kinetic-energy-weighted least-squares fit of the scene's body velocities,
    /// M ż = Σ_k R_kᵀ M̄_k Z*_k (exact when the given velocities are consistent).
    pub(crate) fn initial_velocities(&mut self, scene: &Scene) {
        let n = self.n_z;
        let q0 = self.q0.clone();
        let zero = DVector::zeros(n);
        self.kinematics(&q0, &zero);
        let mut m = DMatrix::zeros(n, n);
        let mut b = DVector::zeros(n);
        // Columns of R: velocity pass with ż = e_c.
        let nb = self.bodies.len();
        let mut cols: Vec<Vec<DVector<f64>>> = vec![Vec::new(); nb];
        for c in 0..n {
            let mut e = DVector::zeros(n);
            e[c] = 1.0;
            self.kinematics(&q0, &e);
            for k in 0..nb {
                let bk = &self.bodies[k];
                let nc = self.nr + bk.n;
                let z = self.fr_z[bk.frame];
                let mut col = DVector::zeros(nc);
                for i in 0..self.nr {
                    col[i] = z[self.rmap[i]];
                }
                for mm in 0..bk.n {
                    col[self.nr + mm] = e[bk.y_off + mm];
                }
                cols[k].push(col);
            }
        }
        self.kinematics(&q0, &zero);
        for k in 0..nb {
            let f = self.bodies[k].frame;
            let (r0, a) = (self.fr_r[f], self.fr_a[f]);
            let bk = &mut self.bodies[k];
            let y: Vec<f64> = q0.as_slice()[bk.y_off..bk.y_off + bk.n].to_vec();
            let yd = vec![0.0; bk.n];
            let state = BodyState {
                r0,
                a,
                omega: Vector3::zeros(),
                s_dot: Vector3::zeros(),
                y: &y,
                y_dot: &yd,
            };
            bk.body
                .inertia(&state, self.method, &mut bk.m_bar, &mut bk.q_bar);
            let v = &scene.bodies[k].velocity;
            let mut w = v.angular.vec();
            let mut lin = v.linear.vec();
            if self.dim == Dim::Planar {
                w = Vector3::new(0.0, 0.0, w.z);
                lin.z = 0.0;
            }
            let s_dot = lin + r0.cross(&w);
            let mut target6 = Vector6::zeros();
            target6.fixed_rows_mut::<3>(0).copy_from(&s_dot);
            target6.fixed_rows_mut::<3>(3).copy_from(&w);
            let nc = self.nr + bk.n;
            let mut target = DVector::zeros(nc);
            for i in 0..self.nr {
                target[i] = target6[self.rmap[i]];
            }
            let mt = &bk.m_bar * &target;
            for c in 0..n {
                let mc = &bk.m_bar * &cols[k][c];
                b[c] += cols[k][c].dot(&mt);
                for d in 0..n {
                    m[(c, d)] += cols[k][d].dot(&mc);
                }
            }
        }
        let svd = m.svd(true, true);
        let max_sv: f64 = svd.singular_values.max();
        if let Ok(x) = svd.solve(&b, 1e-12 * max_sv.max(1e-300)) {
            self.qd0.copy_from(&x);
        }
    }
}
