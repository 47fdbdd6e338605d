//! The relative formulation's marker kinematics ([`MarkerKinematics`]), over which the force
//! elements of `flexmbd_model::force_elements` are evaluated.
//!
//! A marker's position and velocity are those of the last kinematic pass (the tree's frames,
//! §4.5 steps 1–3). Its Jacobian ∂r_P/∂z is built like the cut-joint rows
//! (docs/methods.md §4.4–§4.6): the marker's velocity per unit rate of every elementary joint
//! on its body's path, u_a = ṡ_a + ω_a × r_P (the twist in the s form), plus the node's modal
//! columns A X^t of a flexible body, in w, then folded into z through L.

use flexmbd_core::MarkerKinematics;
use nalgebra::{DMatrix, DVector, Vector3};

use crate::Relative;
use crate::kinematics::point_at;
use crate::topology::Side;

/// Scratch of one marker Jacobian, sized once: ∂r_P/∂w (3 × n_w) and ∂r_P/∂z (3 × n_z).
#[derive(Clone, Debug, Default)]
pub(crate) struct MarkerJacobian {
    jw: DMatrix<f64>,
    jz: DMatrix<f64>,
}

impl MarkerJacobian {
    pub(crate) fn new(n_w: usize, n_z: usize) -> Self {
        MarkerJacobian {
            jw: DMatrix::zeros(3, n_w),
            jz: DMatrix::zeros(3, n_z),
        }
    }
}

impl MarkerKinematics for Relative {
    type Marker = Side;

    /// From the last kinematic pass, which the caller has run at (q, q̇).
    fn marker_state(
        &self,
        marker: &Side,
        _q: &DVector<f64>,
        _qd: &DVector<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        point_at(self, marker)
    }

    fn marker_jacobian(
        &mut self,
        marker: &Side,
        _q: &DVector<f64>,
        visit: &mut dyn FnMut(usize, Vector3<f64>),
    ) {
        let mut scratch = std::mem::take(&mut self.marker_jacobian);
        let (p, _) = point_at(self, marker);
        scratch.jw.fill(0.0);
        self.add_point_jacobian(marker, &p, 1.0, &mut scratch.jw);
        scratch.jz.fill(0.0);
        for (w, lw) in self.l_rows.iter().enumerate() {
            // Most w columns of one marker are zero (joints off its body's path): adding
            // a·0 would leave every sum as it is, so they are skipped.
            if (0..3).all(|r| scratch.jw[(r, w)] == 0.0) {
                continue;
            }
            for &(c, a) in lw {
                for r in 0..3 {
                    scratch.jz[(r, c)] += a * scratch.jw[(r, w)];
                }
            }
        }
        for i in 0..self.n_z {
            let column = Vector3::new(scratch.jz[(0, i)], scratch.jz[(1, i)], scratch.jz[(2, i)]);
            if column != Vector3::zeros() {
                visit(i, column);
            }
        }
        self.marker_jacobian = scratch;
    }
}

impl Relative {
    /// jw += sign · ∂r_P/∂w for the marker `s` at the point `p`.
    fn add_point_jacobian(&self, s: &Side, p: &Vector3<f64>, sign: f64, jw: &mut DMatrix<f64>) {
        let Some(k) = s.body else { return };
        let b = &self.bodies[k];
        let f = b.frame;
        for &a in &self.paths[f] {
            let elem_twist = &self.elem_twist[a];
            let u = elem_twist.fixed_rows::<3>(0) + elem_twist.fixed_rows::<3>(3).cross(p);
            let wa = self.elem_w[a];
            for r in 0..3 {
                jw[(r, wa)] += sign * u[r];
            }
        }
        if let Some(node) = s.node {
            let a = self.frame_rotation[f];
            for m in 0..b.n_modes {
                let col = a * Vector3::new(
                    b.node_rows.t(node, 0, m),
                    b.node_rows.t(node, 1, m),
                    b.node_rows.t(node, 2, m),
                );
                for r in 0..3 {
                    jw[(r, b.first_mode + m)] += sign * col[r];
                }
            }
        }
    }
}
