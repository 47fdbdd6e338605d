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

/// Scratch of one marker Jacobian, sized once: ∂r_P/∂w (3 × n_w) and ∂r_P/∂z (3 × n_z),
/// both all zeros between queries, and the w and z columns the current query touches (a
/// marker moves with the joints on its body's path only: a handful of the n_w columns).
#[derive(Clone, Debug, Default)]
pub(crate) struct MarkerJacobian {
    jw: DMatrix<f64>,
    jz: DMatrix<f64>,
    touched_w: Vec<usize>,
    touched_z: Vec<usize>,
    z_is_touched: Vec<bool>,
}

impl MarkerJacobian {
    pub(crate) fn new(n_w: usize, n_z: usize) -> Self {
        MarkerJacobian {
            jw: DMatrix::zeros(3, n_w),
            jz: DMatrix::zeros(3, n_z),
            touched_w: Vec::with_capacity(n_w),
            touched_z: Vec::with_capacity(n_z),
            z_is_touched: vec![false; n_z],
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
        self.add_point_jacobian(marker, &p, &mut scratch);
        // J_z = J_w L over the touched w columns in increasing order: the same sums, in the
        // same order, as over every column (the others are zero and were skipped).
        let MarkerJacobian {
            jw,
            jz,
            touched_w,
            touched_z,
            z_is_touched,
        } = &mut scratch;
        touched_w.sort_unstable();
        touched_w.dedup();
        if touched_w.last().is_none_or(|&w| w < self.n_z) {
            // Every touched w is a z coordinate (L's row is (w, 1)): J_z's column is
            // 0 + 1·J_w's (the 0 + turns a −0 into the +0 the sum gives).
            for &w in touched_w.iter() {
                let column = Vector3::new(0.0 + jw[(0, w)], 0.0 + jw[(1, w)], 0.0 + jw[(2, w)]);
                if column != Vector3::zeros() {
                    visit(w, column);
                }
                jw.column_mut(w).fill(0.0);
            }
            touched_w.clear();
            self.marker_jacobian = scratch;
            return;
        }
        for &w in touched_w.iter() {
            if (0..3).all(|r| jw[(r, w)] == 0.0) {
                continue;
            }
            for &(c, a) in &self.l_rows[w] {
                for r in 0..3 {
                    jz[(r, c)] += a * jw[(r, w)];
                }
                if !z_is_touched[c] {
                    z_is_touched[c] = true;
                    touched_z.push(c);
                }
            }
        }
        for &w in touched_w.iter() {
            jw.column_mut(w).fill(0.0);
        }
        touched_w.clear();
        touched_z.sort_unstable();
        for &i in touched_z.iter() {
            let column = Vector3::new(jz[(0, i)], jz[(1, i)], jz[(2, i)]);
            if column != Vector3::zeros() {
                visit(i, column);
            }
            jz.column_mut(i).fill(0.0);
            z_is_touched[i] = false;
        }
        touched_z.clear();
        self.marker_jacobian = scratch;
    }
}

impl Relative {
    /// Writes ∂r_P/∂w for the marker `s` at the point `p` into the scratch's (zero) J_w and
    /// lists the columns it writes.
    fn add_point_jacobian(&self, s: &Side, p: &Vector3<f64>, scratch: &mut MarkerJacobian) {
        let Some(k) = s.body else { return };
        let (jw, touched_w) = (&mut scratch.jw, &mut scratch.touched_w);
        let b = &self.bodies[k];
        let f = b.frame;
        for &a in &self.paths[f] {
            let elem_twist = &self.elem_twist[a];
            let u = elem_twist.fixed_rows::<3>(0) + elem_twist.fixed_rows::<3>(3).cross(p);
            let wa = self.elem_w[a];
            for r in 0..3 {
                jw[(r, wa)] += u[r];
            }
            touched_w.push(wa);
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
                    jw[(r, b.first_mode + m)] += col[r];
                }
                touched_w.push(b.first_mode + m);
            }
        }
    }
}
