//! A body of the planar scene: its basis x_b = (a, b) slot by slot (a coordinate or a fixed
//! value), the constant map T to its frame, its markers and the local point r̄_P + X_P y.

use std::ops::Range;

use flexmbd_body::FlexibleBody;
use nalgebra::{DVector, Matrix4, Vector2, Vector4};

use super::kinematics::PlanarMarker;
use crate::flex;

/// One scalar of a basis: a coordinate or a fixed value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Slot {
    /// The coordinate q[i].
    Q(usize),
    /// A fixed value (a ground point's component).
    Fixed(f64),
}

impl Slot {
    /// The value in q.
    #[inline]
    pub(super) fn get(self, q: &DVector<f64>) -> f64 {
        match self {
            Slot::Q(i) => q[i],
            Slot::Fixed(v) => v,
        }
    }

    /// The rate in q̇ (zero when fixed).
    #[inline]
    pub(super) fn rate(self, qd: &DVector<f64>) -> f64 {
        match self {
            Slot::Q(i) => qd[i],
            Slot::Fixed(_) => 0.0,
        }
    }
}

/// A point of the scene in the coordinates: its two ground components.
#[derive(Clone, Copy, Debug)]
pub(super) struct PointSlots {
    pub(super) x: Slot,
    pub(super) y: Slot,
}

/// A marker of a body as compiled.
pub(super) struct BodyMarker {
    /// Undeformed position r̄_P in the body frame (m).
    pub(super) position: Vector2<f64>,
    /// The FE node it sits on (its own node on flexible bodies, from the prepared scene).
    pub(super) node: Option<usize>,
}

/// A body of the planar scene: its basis x_b, the constant map T to its frame (r0, u), its
/// modal coordinates and markers.
pub(crate) struct PlanarBody {
    pub(super) body: FlexibleBody,
    /// The basis x_b = (a, b), slot by slot.
    pub(super) slots: [Slot; 4],
    /// T: (r0, u) = T x_b.
    pub(super) frame_map: Matrix4<f64>,
    /// First modal coordinate in q.
    pub(super) first_mode: usize,
    /// Number of modal coordinates (0 for a rigid body).
    pub(super) n_modes: usize,
    /// Rigid bodies: the constant Tᵀ M_f T in basis coordinates.
    pub(super) rigid_mass: Matrix4<f64>,
    /// Rigid bodies: the constant Tᵀ Q_gravity in basis coordinates.
    pub(super) rigid_forces: Vector4<f64>,
    pub(super) markers: Vec<BodyMarker>,
    /// Per-evaluation storage of a flexible body (frame-coordinate terms).
    pub(super) flexible_workspace: Option<flex::Flex2>,
}

impl PlanarBody {
    /// The modal coordinates' indices in q.
    pub(super) fn modes(&self) -> Range<usize> {
        self.first_mode..self.first_mode + self.n_modes
    }

    /// The basis x_b at q.
    #[inline]
    pub(super) fn basis(&self, q: &DVector<f64>) -> Vector4<f64> {
        Vector4::from_fn(|i, _| self.slots[i].get(q))
    }

    /// The basis rate ẋ_b at q̇.
    #[inline]
    pub(super) fn basis_rate(&self, qd: &DVector<f64>) -> Vector4<f64> {
        Vector4::from_fn(|i, _| self.slots[i].rate(qd))
    }

    /// Marker `k` of this body (index `body` in the scene), its node on a flexible body only.
    pub(super) fn marker_by_index(&self, body: usize, k: usize) -> PlanarMarker {
        PlanarMarker::Body {
            body,
            rbar: self.markers[k].position,
            node: if self.n_modes > 0 {
                self.markers[k].node
            } else {
                None
            },
        }
    }

    /// Rotation row X^r_z of a node (1 × n).
    pub(super) fn rot_row(&self, node: usize) -> &[f64] {
        self.flexible_workspace
            .as_ref()
            .map_or(&[], |f| f.rot_row(node))
    }

    /// Node rotation θ = X^r_z y and its rate.
    pub(super) fn node_rotation(
        &self,
        node: usize,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (f64, f64) {
        let r = self.rot_row(node);
        let mut th = 0.0;
        let mut thd = 0.0;
        for j in 0..self.n_modes {
            th += r[j] * q[self.first_mode + j];
            thd += r[j] * qd[self.first_mode + j];
        }
        (th, thd)
    }

    /// Local (body-frame) position r̄_P + X_P y of a marker (FS0: plus the node's
    /// foreshortening), and its rate.
    pub(super) fn local_point(
        &self,
        rbar: Vector2<f64>,
        node: Option<usize>,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector2<f64>, Vector2<f64>) {
        match (node, &self.flexible_workspace) {
            (Some(node), Some(f)) => {
                let (tx, ty) = f.trans_rows(node);
                let (mut p, mut pd) = (rbar, Vector2::zeros());
                for j in 0..self.n_modes {
                    let (yj, ydj) = (q[self.first_mode + j], qd[self.first_mode + j]);
                    p.x += tx[j] * yj;
                    p.y += ty[j] * yj;
                    pd.x += tx[j] * ydj;
                    pd.y += ty[j] * ydj;
                }
                // FS0 (docs/methods.md §6.3): the node's axial shift −½ ē₁ yᵀF y and its rate.
                let (y, yd) = (&q.as_slice()[self.modes()], &qd.as_slice()[self.modes()]);
                if let Some(sh) = self.body.node_foreshortening(node, y, yd) {
                    p += sh.position.xy();
                    pd += sh.velocity.xy();
                }
                (p, pd)
            }
            _ => (rbar, Vector2::zeros()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slots_read_coordinates_or_fixed_values() {
        let q = DVector::from_vec(vec![1.5, -2.0]);
        let qd = DVector::from_vec(vec![0.25, 4.0]);
        assert_eq!(Slot::Q(1).get(&q), -2.0);
        assert_eq!(Slot::Q(1).rate(&qd), 4.0);
        assert_eq!(Slot::Fixed(7.0).get(&q), 7.0);
        assert_eq!(Slot::Fixed(7.0).rate(&qd), 0.0);
    }
}
