//! Kinematics of the planar scene: body frames, markers and body-fixed directions, with
//! their rates, acceleration biases and Jacobian columns (docs/methods.md §3.1, §3.3).
//!
//! - Frame: (r0, u) = T x_b, A = [u  E u].
//! - Marker: r_P = r0 + C(r̄_P + X_P y) u, ṙ_P = ṙ0 + C(p) u̇ + C(ṗ) u, bias 2 C(Ẋ_P ẏ) u̇;
//!   ∂r_P/∂(r0, u) = [I  C(r̄_P + X_P y)] times T, ∂r_P/∂y = A X_P.
//! - Direction: d = A (I + θ_P E) ā = C(ā)(I + θ_P E) u, θ_P = X^r_P y at a flexible node.

use nalgebra::{DMatrix, DVector, Matrix2, Vector2};

use super::Planar;
use super::algebra::{c_of, cross, e_mat};
use super::body::{PlanarBody, Slot};

/// A marker: a ground point, or a body point r_P = r0 + A (r̄_P + X_P y) (the node term on
/// flexible bodies only).
#[derive(Clone, Copy, Debug)]
pub enum PlanarMarker {
    /// A ground point (m, ground components).
    Ground(Vector2<f64>),
    /// A point of a body.
    Body {
        /// Index of the body.
        body: usize,
        /// Position r̄_P in the body frame, undeformed (m).
        rbar: Vector2<f64>,
        /// The FE node it sits on (flexible bodies only).
        node: Option<usize>,
    },
}

/// A body frame's origin r0 and unit vector u (A = [u  E u]), and their rates (ground
/// components).
#[derive(Clone, Copy, Debug)]
pub(super) struct FrameState {
    pub(super) r0: Vector2<f64>,
    pub(super) u: Vector2<f64>,
    pub(super) r0_rate: Vector2<f64>,
    pub(super) u_rate: Vector2<f64>,
}

/// A body-fixed direction d = A (I + θ_node E) ā = C(ā)(I + θ_node E) u: the body-frame
/// direction ā, turned with the frame and, at a flexible node, by the node rotation.
#[derive(Clone, Copy, Debug)]
pub(super) struct Direction {
    /// `None`: the ground (d = ā, ground components).
    pub(super) body: Option<usize>,
    /// The FE node whose rotation turns it (flexible bodies only).
    pub(super) node: Option<usize>,
    /// Body-frame components of the direction (the x axis (1, 0) for angle constraints).
    pub(super) abar: Vector2<f64>,
}

impl Planar {
    /// The body's frame (r0, u) = T x_b and its rate T ẋ_b.
    pub(super) fn frame(
        &self,
        body: &PlanarBody,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> FrameState {
        let x = body.basis(q);
        let xd = body.basis_rate(qd);
        let f = body.frame_map * x;
        let fd = body.frame_map * xd;
        FrameState {
            r0: Vector2::new(f[0], f[1]),
            u: Vector2::new(f[2], f[3]),
            r0_rate: Vector2::new(fd[0], fd[1]),
            u_rate: Vector2::new(fd[2], fd[3]),
        }
    }

    /// A direction d (ground components), its rate and its bias (second derivative at
    /// q̈ = 0).
    pub(super) fn direction(
        &self,
        d: &Direction,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        match d.body {
            None => (d.abar, Vector2::zeros(), Vector2::zeros()),
            Some(body_index) => {
                let b = &self.bodies[body_index];
                let FrameState { u, u_rate: ud, .. } = self.frame(b, q, qd);
                // (I + θE) u, then C(ā) (commutes with E).
                let (x, xd, xb) = match d.node {
                    None => (u, ud, Vector2::zeros()),
                    Some(node) => {
                        let (th, thd) = b.node_rotation(node, q, qd);
                        let e = e_mat();
                        (
                            u + th * (e * u),
                            ud + th * (e * ud) + thd * (e * u),
                            2.0 * thd * (e * ud),
                        )
                    }
                };
                let ca = c_of(&d.abar);
                (ca * x, ca * xd, ca * xb)
            }
        }
    }

    /// The angle from d₁ to d₂ at q, atan2(d₁ × d₂, d₁ · d₂).
    pub(super) fn angle(&self, d1: &Direction, d2: &Direction, q: &DVector<f64>) -> f64 {
        let (a, _, _) = self.direction(d1, q, &self.zero_rates);
        let (b, _, _) = self.direction(d2, q, &self.zero_rates);
        cross(&a, &b).atan2(a.dot(&b))
    }

    /// Add wᵀ ∂d/∂q to `row` of Φ_q.
    pub(super) fn add_direction_jacobian(
        &self,
        d: &Direction,
        w: &Vector2<f64>,
        q: &DVector<f64>,
        phi_q: &mut DMatrix<f64>,
        row: usize,
    ) {
        let Some(body_index) = d.body else { return };
        let b = &self.bodies[body_index];
        // d = C(ā) d_x: wᵀ ∂d/∂q = (C(ā)ᵀ w)ᵀ ∂d_x/∂q.
        let w = &(c_of(&d.abar).transpose() * w);
        let (th, u) = match d.node {
            Some(node) => {
                let f = b.frame_map * b.basis(q);
                let u = Vector2::new(f[2], f[3]);
                let th: f64 = (0..b.n_modes)
                    .map(|j| b.rot_row(node)[j] * q[b.first_mode + j])
                    .sum();
                (th, u)
            }
            None => (0.0, Vector2::zeros()),
        };
        // ∂d/∂u = I + θ E ; ∂u/∂x_b = T[2..4, :]
        let e = e_mat();
        let du = Matrix2::identity() + th * e;
        let wt_du = du.transpose() * w;
        for k in 0..4 {
            if let Slot::Q(i) = b.slots[k] {
                phi_q[(row, i)] += wt_du.x * b.frame_map[(2, k)] + wt_du.y * b.frame_map[(3, k)];
            }
        }
        if let Some(node) = d.node {
            // ∂d/∂y_j = E u · X^r_{node, j}
            let eu = e * u;
            let s = w.dot(&eu);
            let rot_row = b.rot_row(node);
            for j in 0..b.n_modes {
                phi_q[(row, b.first_mode + j)] += s * rot_row[j];
            }
        }
    }

    /// A marker's position r_P, velocity ṙ_P and bias r̈_P|q̈=0 = 2 C(Ẋ_P ẏ) u̇
    /// (r_P is bilinear in (u, y)).
    pub(super) fn marker_motion(
        &self,
        marker: &PlanarMarker,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        match *marker {
            PlanarMarker::Ground(p) => (p, Vector2::zeros(), Vector2::zeros()),
            PlanarMarker::Body { body, rbar, node } => {
                let b = &self.bodies[body];
                let frame = self.frame(b, q, qd);
                let (r0, u, r0d, ud) = (frame.r0, frame.u, frame.r0_rate, frame.u_rate);
                let (p, pd) = b.local_point(rbar, node, q, qd);
                let (cp, cpd) = (c_of(&p), c_of(&pd));
                (r0 + cp * u, r0d + cp * ud + cpd * u, 2.0 * (cpd * ud))
            }
        }
    }

    /// The non-zero columns ∂r_P/∂q_i of a marker, visited as (i, column):
    /// ∂r_P/∂(r0, u) = [I  C(r̄_P + X_P y)] times T for the basis, A X_P for the modes.
    pub(super) fn marker_columns(
        &self,
        marker: &PlanarMarker,
        q: &DVector<f64>,
        mut visit: impl FnMut(usize, Vector2<f64>),
    ) {
        let PlanarMarker::Body { body, rbar, node } = *marker else {
            return;
        };
        let b = &self.bodies[body];
        let f = b.frame_map * b.basis(q);
        let u = Vector2::new(f[2], f[3]);
        let mut p = rbar;
        let flex = match (node, &b.flexible_workspace) {
            (Some(node), Some(fw)) => {
                let (tx, ty) = fw.trans_rows(node);
                for j in 0..b.n_modes {
                    let yj = q[b.first_mode + j];
                    p.x += tx[j] * yj;
                    p.y += ty[j] * yj;
                }
                Some((tx, ty))
            }
            _ => None,
        };
        let cp = c_of(&p);
        for k in 0..4 {
            if let Slot::Q(i) = b.slots[k] {
                let col = Vector2::new(b.frame_map[(0, k)], b.frame_map[(1, k)])
                    + cp * Vector2::new(b.frame_map[(2, k)], b.frame_map[(3, k)]);
                visit(i, col);
            }
        }
        if let Some((tx, ty)) = flex {
            let eu = e_mat() * u;
            for j in 0..b.n_modes {
                visit(b.first_mode + j, u * tx[j] + eu * ty[j]);
            }
        }
    }

    /// Slide (r_P2 − r_P1) · d₁ of a prismatic joint.
    pub(super) fn slide(
        &self,
        p1: &PlanarMarker,
        p2: &PlanarMarker,
        d1: &Direction,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> f64 {
        let (r1, _, _) = self.marker_motion(p1, q, qd);
        let (r2, _, _) = self.marker_motion(p2, q, qd);
        let (d, _, _) = self.direction(d1, q, qd);
        (r2 - r1).dot(&d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planar::tests::{compiled, model};
    use nalgebra::{Matrix3, Vector3};

    /// The slider-crank with a flexible crank and rod, at a state off the constraints:
    /// (planar, q, q̇).
    fn slider_crank() -> (Planar, DVector<f64>, DVector<f64>) {
        let mut scene = model("slider_crank.ron");
        scene.bodies[0].flexible = true;
        let planar = compiled(&scene);
        let q0 = &planar.coordinates.q0;
        let wobble = |k: usize, s: f64| (0.7 * k as f64 + s).sin();
        let q = DVector::from_fn(q0.len(), |k, _| q0[k] + 0.05 * wobble(k, 0.3));
        let qd = DVector::from_fn(q.len(), |k, _| wobble(k, 1.1));
        (planar, q, qd)
    }

    /// Markers of every kind: ground, rigid body, flexible body at a node and at the frame.
    fn markers(planar: &Planar) -> Vec<PlanarMarker> {
        let ground = PlanarMarker::Ground(Vector2::new(1.3, 0.0));
        let mut list = vec![ground];
        // crank O, B, B; rod B, mid, C; slider pin three times.
        for (b, indices) in [(0, [0, 1, 1]), (1, [0, 1, 2]), (2, [0; 3])] {
            list.extend(indices.map(|k| planar.bodies[b].marker_by_index(b, k)));
        }
        assert!(matches!(list[5], PlanarMarker::Body { node: Some(_), .. }));
        list
    }

    /// Directions of every kind: ground, rigid body, flexible body at a node.
    fn directions(planar: &Planar) -> Vec<Direction> {
        let abar = Vector2::new(0.6, -0.8);
        let mut list = vec![Direction {
            body: None,
            node: None,
            abar,
        }];
        for (b, k) in [(0, 1), (1, 1), (1, 2), (2, 0)] {
            list.push(Direction {
                body: Some(b),
                node: planar.bodies[b].markers[k].node,
                abar,
            });
        }
        assert!(list[3].node.is_some());
        list
    }

    #[test]
    fn marker_columns_are_the_jacobian_of_its_position() {
        let (planar, q, qd) = slider_crank();
        let h = 1e-6;
        for marker in markers(&planar) {
            let mut jacobian = DMatrix::zeros(2, q.len());
            planar.marker_columns(&marker, &q, |i, col| {
                jacobian.fixed_view_mut::<2, 1>(0, i).copy_from(&col);
            });
            for i in 0..q.len() {
                let (mut qp, mut qm) = (q.clone(), q.clone());
                qp[i] += h;
                qm[i] -= h;
                let fd = (planar.marker_motion(&marker, &qp, &qd).0
                    - planar.marker_motion(&marker, &qm, &qd).0)
                    / (2.0 * h);
                let col = jacobian.column(i);
                assert!((col - fd).norm() < 1e-8, "{marker:?} q[{i}]: {col} vs {fd}");
            }
            let (_, v, _) = planar.marker_motion(&marker, &q, &qd);
            assert!((jacobian * &qd - v).norm() < 1e-12, "{marker:?}: ṙ ≠ J q̇");
        }
    }

    /// Along q(t) = q + t q̇ (q̈ = 0) the rate is the first derivative and the bias the second.
    #[test]
    fn rates_and_biases_are_the_derivatives_along_a_straight_path() {
        let (planar, q, qd) = slider_crank();
        for marker in markers(&planar) {
            let label = format!("{marker:?}");
            along_path(&label, &q, &qd, |q| planar.marker_motion(&marker, q, &qd));
        }
        for d in directions(&planar) {
            along_path(&format!("{d:?}"), &q, &qd, |q| planar.direction(&d, q, &qd));
        }
    }

    /// `motion(q)` = (x, ẋ, bias) at (q, q̇): ẋ and the bias against the first and second
    /// central differences of x along q + t q̇.
    fn along_path(
        label: &str,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        motion: impl Fn(&DVector<f64>) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>),
    ) {
        let h = 1e-4;
        let (x, xd, bias) = motion(q);
        let (xp, xm) = (motion(&(q + qd * h)).0, motion(&(q - qd * h)).0);
        assert!(((xp - xm) / (2.0 * h) - xd).norm() < 1e-7, "{label} rate");
        let second = (xp - 2.0 * x + xm) / (h * h);
        assert!((second - bias).norm() < 1e-5, "{label}: {second} vs {bias}");
    }

    #[test]
    fn direction_jacobian_matches_finite_differences() {
        let (planar, q, qd) = slider_crank();
        let (w, h) = (Vector2::new(0.3, 1.2), 1e-6);
        for d in directions(&planar) {
            let mut row = DMatrix::zeros(1, q.len());
            planar.add_direction_jacobian(&d, &w, &q, &mut row, 0);
            for i in 0..q.len() {
                let (mut qp, mut qm) = (q.clone(), q.clone());
                qp[i] += h;
                qm[i] -= h;
                let fd = w
                    .dot(&(planar.direction(&d, &qp, &qd).0 - planar.direction(&d, &qm, &qd).0))
                    / (2.0 * h);
                assert!(
                    (row[i] - fd).abs() < 1e-8,
                    "{d:?} q[{i}]: {} vs {fd}",
                    row[i]
                );
            }
        }
    }

    #[test]
    fn frame_rotation_turns_the_body_x_axis() {
        let (planar, q, qd) = slider_crank();
        for b in 0..planar.bodies.len() {
            let u = planar.frame(&planar.bodies[b], &q, &qd).u;
            let (_, a) = flexmbd_core::SensorQuery::body_frame(&planar, b, &q);
            let ex = Vector3::new(u.x, u.y, 0.0) / u.norm();
            assert!((a * Vector3::x() - ex).norm() < 1e-15);
            assert!((a.transpose() * a - Matrix3::identity()).amax() < 1e-15);
        }
    }
}
