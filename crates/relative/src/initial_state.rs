//! The initial state: z(0) from the placements (joint coordinates 0, modes from
//! `initial_modes`) and ż(0) by the kinetic-energy-weighted least-squares fit of the scene's
//! body velocities, M ż = Σ_k R_kᵀ M̄_k Z*_k, with the columns of R_k from velocity passes
//! at ż = e_c (docs/methods.md §4.6). The integrator makes both consistent with the
//! constraints (§5.4). The fit's SVD sees only a finite, non-empty matrix and runs under an
//! iteration cap, so no scene can make it panic or loop.

use flexmbd_body::BodyState;
use flexmbd_core::Dim;
use flexmbd_model::{ModelError, Scene};
use nalgebra::{DMatrix, DVector, Vector3, Vector6};

use crate::body_kernels::{BodyKernel, FrameMotion, rigid_dense_terms};
use crate::system::Relative;

/// The SVD's iteration cap in the velocity fit (it converges in a few sweeps per singular
/// value; the cap only turns a pathological matrix into an error instead of a hang).
const SVD_MAX_ITERATIONS: usize = 100_000;

impl Relative {
    /// z(0): the joints at their t = 0 placement (z = 0), the modes as given.
    pub(crate) fn initial_coordinates(&mut self, scene: &Scene) {
        for (k, b) in scene.bodies.iter().enumerate() {
            let (o, n) = (self.bodies[k].first_mode, self.bodies[k].n_modes);
            for m in 0..n {
                self.coordinates.q0[o + m] = b.initial_modes.get(m).copied().unwrap_or(0.0);
            }
        }
    }

    /// ż(0): the kinetic-energy-weighted least-squares fit of the scene's body velocities,
    /// M ż = Σ_k R_kᵀ M̄_k Z*_k (exact when the given velocities are consistent). Nothing to
    /// fit without coordinates; a fit whose matrix is not finite or whose SVD does not
    /// converge is refused, naming the scene.
    pub(crate) fn initial_velocities(&mut self, scene: &Scene) -> Result<(), ModelError> {
        let n = self.tree.n_z;
        if n == 0 {
            return Ok(());
        }
        let q0 = self.coordinates.q0.clone();
        let zero = DVector::zeros(n);
        self.kinematics(&q0, &zero);
        let mut m = DMatrix::<f64>::zeros(n, n);
        let mut b = DVector::<f64>::zeros(n);
        // Columns of R: velocity pass with ż = e_c.
        let nb = self.bodies.len();
        let mut cols: Vec<Vec<DVector<f64>>> = vec![Vec::new(); nb];
        for c in 0..n {
            let mut e = DVector::zeros(n);
            e[c] = 1.0;
            self.kinematics(&q0, &e);
            for k in 0..nb {
                let bk = &self.bodies[k];
                let nc = self.tree.rigid_size() + bk.n_modes;
                let z = self.frames.velocity[bk.frame];
                let mut col = DVector::zeros(nc);
                for i in 0..self.tree.rigid_size() {
                    col[i] = z[self.tree.rigid_entries()[i]];
                }
                for mm in 0..bk.n_modes {
                    col[self.tree.rigid_size() + mm] = e[bk.first_mode + mm];
                }
                cols[k].push(col);
            }
        }
        self.kinematics(&q0, &zero);
        for k in 0..nb {
            let f = self.bodies[k].frame;
            let (r0, a) = (self.frames.position[f], self.frames.rotation[f]);
            let frame = FrameMotion {
                velocity: Vector6::zeros(),
                bias: Vector6::zeros(),
                ..self.frame_motion(k)
            };
            let bk = &mut self.bodies[k];
            let y: Vec<f64> = q0.as_slice()[bk.first_mode..bk.first_mode + bk.n_modes].to_vec();
            let yd = vec![0.0; bk.n_modes];
            let state = BodyState {
                r0,
                a,
                omega: Vector3::zeros(),
                s_dot: Vector3::zeros(),
                y: &y,
                y_dot: &yd,
            };
            let m_bar = match &mut bk.kernel {
                BodyKernel::Flexible(f) => {
                    f.body.inertia(
                        &state,
                        self.assembly.inertia_method,
                        &mut f.m_bar,
                        &mut f.q_bar,
                    );
                    f.m_bar.clone()
                }
                kernel => {
                    rigid_dense_terms(kernel, &frame, &Vector3::zeros())
                        .expect("a body without a flexible kernel is rigid")
                        .0
                }
            };
            let v = &scene.bodies[k].velocity;
            let mut w = v.angular.vec();
            let mut lin = v.linear.vec();
            if self.tree.dim == Dim::Planar {
                w = Vector3::new(0.0, 0.0, w.z);
                lin.z = 0.0;
            }
            let s_dot = lin + r0.cross(&w);
            let mut target6 = Vector6::zeros();
            target6.fixed_rows_mut::<3>(0).copy_from(&s_dot);
            target6.fixed_rows_mut::<3>(3).copy_from(&w);
            let nc = self.tree.rigid_size() + bk.n_modes;
            let mut target = DVector::zeros(nc);
            for i in 0..self.tree.rigid_size() {
                target[i] = target6[self.tree.rigid_entries()[i]];
            }
            let mt = &m_bar * &target;
            for c in 0..n {
                let mc = &m_bar * &cols[k][c];
                b[c] += cols[k][c].dot(&mt);
                for d in 0..n {
                    m[(c, d)] += cols[k][d].dot(&mc);
                }
            }
        }
        let refuse = |what: &str| {
            ModelError::Unsupported(format!(
                "{}: the initial velocity fit (docs/methods.md §4.6) {what}",
                scene.origin
            ))
        };
        if !(m.iter().all(|x| x.is_finite()) && b.iter().all(|x| x.is_finite())) {
            return Err(refuse(
                "has non-finite terms: the placements or velocities are out of range",
            ));
        }
        // The tolerance of `DMatrix::svd`, with a cap on the iterations.
        let svd = m
            .try_svd(true, true, 5.0 * f64::EPSILON, SVD_MAX_ITERATIONS)
            .ok_or_else(|| refuse("did not converge"))?;
        let max_sv: f64 = svd.singular_values.max();
        if let Ok(x) = svd.solve(&b, 1e-12 * max_sv.max(1e-300)) {
            self.coordinates.qd0.copy_from(&x);
        }
        Ok(())
    }
}
