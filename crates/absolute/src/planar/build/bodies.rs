//! Bodies and their bases (docs/methods.md §3.1, planar formulation).
//!
//! A rigid body with two distinct joint points uses them as its basis x_b = (r_i, r_j), with
//! |r_j − r_i|² = L², and u = R(−φ)(r_j − r_i)/L, r0 = r_i − C(r̄_i) u; any other body (and
//! every flexible body) uses a point (its joint point at the reference node, its first joint
//! point — a rigid body's —, or its own origin, as a flexible body without a reference node,
//! a Buckens beam, does) and its own unit vector u, with |u|² = 1 and r0 = r_P − C(r̄_P) u.
//! Either way (r0, u) = T x_b with a constant T, and a rigid body's natural-set mass matrix
//! and gravity force are projected once: Tᵀ M_f T, Tᵀ Q_g.

use flexmbd_body::FlexibleBody;
use flexmbd_model::{Body, PreparedBody};
use nalgebra::{Matrix2, Matrix4, Vector2, Vector4};

use super::super::algebra::{c_of, e_mat};
use super::super::body::{BodyMarker, PlanarBody, PointSlots, Slot};
use super::super::constraints::{Constraint, Distance, PointOnBody, UnitVector};
use super::super::kinematics::PlanarMarker;
use super::marker_table::{InitialFrame, MarkerTable};
use super::points::Coordinates;
use crate::flex;

/// A body's basis, as chosen.
struct Basis {
    slots: [Slot; 4],
    /// T: (r0, u) = T x_b.
    frame_map: Matrix4<f64>,
    /// Initial rates of the basis' two 2-vectors (rigid motion of the body).
    velocity: [Vector2<f64>; 2],
    /// Markers that are basis points (not tied to the body by a constraint).
    markers: Vec<usize>,
    /// Its distance or unit-vector constraint.
    constraint: Constraint,
}

/// The rigid initial motion (ṙ0, ω) of a body.
struct InitialMotion {
    frame: InitialFrame,
    linear: Vector2<f64>,
    angular: f64,
}

impl InitialMotion {
    /// Velocity of a body point r̄.
    fn velocity_of(&self, rbar: Vector2<f64>) -> Vector2<f64> {
        let th = self.frame.angle;
        let a0 = Matrix2::new(th.cos(), -th.sin(), th.sin(), th.cos());
        self.linear + self.angular * e_mat() * (a0 * rbar)
    }
}

/// The state shared while the bodies are built in order: coordinates and constraints are
/// appended body by body.
pub(super) struct BodyBuilder<'a> {
    pub(super) table: &'a MarkerTable,
    /// The shared point of each global marker (see `points::shared_points`).
    pub(super) points: &'a [Option<PointSlots>],
    pub(super) coordinates: &'a mut Coordinates,
    pub(super) constraints: &'a mut Vec<Constraint>,
    /// (coordinate, initial rate) of every basis coordinate.
    pub(super) initial_rates: &'a mut Vec<(usize, f64)>,
    /// Gravity (m/s², ground components).
    pub(super) gravity: Vector2<f64>,
}

impl BodyBuilder<'_> {
    /// Body `index`: its basis, its modal coordinates, the constraints that tie its other
    /// joint points to it, and its constant rigid terms.
    pub(super) fn body(&mut self, index: usize, b: &Body, prep: &PreparedBody) -> PlanarBody {
        let body = prep.body.clone();
        let n_modes = body.n_modes();
        let first = self.table.first_of_body[index];
        let markers: Vec<BodyMarker> = (0..b.markers.len())
            .map(|k| BodyMarker {
                position: self.table.position[first + k],
                node: prep.marker_nodes[k],
            })
            .collect();
        // Joint points of this body, in marker order.
        let joint_markers: Vec<usize> = (0..b.markers.len())
            .filter(|&k| self.points[first + k].is_some())
            .collect();
        let v = &b.velocity;
        let motion = InitialMotion {
            frame: self.table.frames[index],
            linear: Vector2::new(v.linear.0[0], v.linear.0[1]),
            angular: v.angular.0[2],
        };
        let two = if prep.flexible {
            None
        } else {
            two_distinct_points(&markers, &joint_markers)
        };
        let basis = match two {
            Some((ka, kb)) => self.two_point_basis(first, &markers, ka, kb, &motion),
            None => self.point_vector_basis(first, prep, &markers, &joint_markers, &motion),
        };
        self.constraints.push(basis.constraint);
        let first_mode = self.coordinates.len();
        self.coordinates
            .initial
            .extend((0..n_modes).map(|j| b.initial_modes.get(j).copied().unwrap_or(0.0)));
        // Other joint points: tied to the body.
        for &k in &joint_markers {
            if basis.markers.contains(&k) {
                continue;
            }
            let point = self.points[first + k].expect("joint point");
            self.constraints.push(Constraint::PointOnBody(PointOnBody {
                marker: PlanarMarker::Body {
                    body: index,
                    rbar: markers[k].position,
                    node: if prep.flexible { markers[k].node } else { None },
                },
                point,
            }));
        }
        for (k, slot) in basis.slots.iter().enumerate() {
            if let Slot::Q(i) = slot {
                self.initial_rates.push((*i, basis.velocity[k / 2][k % 2]));
            }
        }
        let (rigid_mass, rigid_forces) = if prep.flexible {
            (Matrix4::zeros(), Vector4::zeros())
        } else {
            rigid_terms(&body, &basis.frame_map, self.gravity)
        };
        let flexible_workspace = prep.flexible.then(|| flex::Flex2::new(&body, &prep.nodes));
        PlanarBody {
            body,
            slots: basis.slots,
            frame_map: basis.frame_map,
            first_mode,
            n_modes,
            rigid_mass,
            rigid_forces,
            markers,
            flexible_workspace,
        }
    }

    /// The bar basis x_b = (r_a, r_b) of two joint points: u = R(−φ)(r_b − r_a)/L,
    /// r0 = r_a − C(r̄_a) u.
    fn two_point_basis(
        &mut self,
        first: usize,
        markers: &[BodyMarker],
        ka: usize,
        kb: usize,
        motion: &InitialMotion,
    ) -> Basis {
        let pa = self.points[first + ka].expect("joint point");
        let pb = self.points[first + kb].expect("joint point");
        let (ra, rb) = (markers[ka].position, markers[kb].position);
        let (frame_map, length) = two_point_frame_map(ra, rb);
        Basis {
            slots: [pa.x, pa.y, pb.x, pb.y],
            frame_map,
            velocity: [motion.velocity_of(ra), motion.velocity_of(rb)],
            markers: vec![ka, kb],
            constraint: Constraint::Distance(Distance {
                a: pa,
                b: pb,
                length_squared: length * length,
            }),
        }
    }

    /// The basis x_b = (r_P, u) of a point (the joint point at the reference node, the first
    /// joint point, or a new point at the frame origin or reference node) and the body's own
    /// unit vector: r0 = r_P − C(r̄_P) u.
    fn point_vector_basis(
        &mut self,
        first: usize,
        prep: &PreparedBody,
        markers: &[BodyMarker],
        joint_markers: &[usize],
        motion: &InitialMotion,
    ) -> Basis {
        let anchor = match prep.reference_node {
            Some(node) => joint_markers
                .iter()
                .copied()
                .find(|&k| markers[k].node == Some(node)),
            // A flexible body whose frame sits at no node (a Buckens beam): every joint
            // point moves with the modes, so the basis takes a point of its own.
            None if prep.flexible => None,
            None => joint_markers.first().copied(),
        };
        let mut basis_markers = Vec::new();
        let (p, rbar) = match anchor {
            Some(k) => {
                basis_markers.push(k);
                (
                    self.points[first + k].expect("joint point"),
                    markers[k].position,
                )
            }
            None => {
                let rbar = match prep.reference_node {
                    Some(node) => {
                        let pos = prep.nodes.position(node);
                        Vector2::new(pos.x, pos.y)
                    }
                    None => Vector2::zeros(),
                };
                let frame = motion.frame;
                let p = frame.origin + frame.rotation() * rbar;
                (self.coordinates.point(p), rbar)
            }
        };
        let th = motion.frame.angle;
        let u0 = Vector2::new(th.cos(), th.sin());
        let u_slots = self.coordinates.pair(u0);
        Basis {
            slots: [p.x, p.y, u_slots[0], u_slots[1]],
            frame_map: point_vector_frame_map(rbar),
            velocity: [motion.velocity_of(rbar), motion.angular * e_mat() * u0],
            markers: basis_markers,
            constraint: Constraint::UnitVector(UnitVector { u: u_slots }),
        }
    }
}

/// T of a bar basis (r_a, r_b) with the points at r̄_a, r̄_b in the body frame, and the
/// distance L: u = R(−φ)(r_b − r_a)/L, r0 = r_a − C(r̄_a) u, φ the angle of r̄_b − r̄_a.
fn two_point_frame_map(ra: Vector2<f64>, rb: Vector2<f64>) -> (Matrix4<f64>, f64) {
    let d = rb - ra;
    let length = d.norm();
    let phi = d.y.atan2(d.x);
    // u = R(−φ)(r_j − r_i)/L ; r0 = r_i − C(r̄_i) u.
    let rot = Matrix2::new(phi.cos(), phi.sin(), -phi.sin(), phi.cos()) / length;
    let mut tm = Matrix4::zeros();
    tm.fixed_view_mut::<2, 2>(2, 0).copy_from(&(-rot));
    tm.fixed_view_mut::<2, 2>(2, 2).copy_from(&rot);
    let ci = c_of(&ra);
    let r0_a = Matrix2::identity() + ci * rot;
    let r0_b = -(ci * rot);
    tm.fixed_view_mut::<2, 2>(0, 0).copy_from(&r0_a);
    tm.fixed_view_mut::<2, 2>(0, 2).copy_from(&r0_b);
    (tm, length)
}

/// T of a point-and-vector basis (r_P, u) with the point at r̄_P: r0 = r_P − C(r̄_P) u.
fn point_vector_frame_map(rbar: Vector2<f64>) -> Matrix4<f64> {
    let mut tm = Matrix4::identity();
    tm.fixed_view_mut::<2, 2>(0, 2).copy_from(&(-c_of(&rbar)));
    tm
}

/// The first two joint points of a body (in marker order) that are distinct.
fn two_distinct_points(markers: &[BodyMarker], joint_markers: &[usize]) -> Option<(usize, usize)> {
    for (x, &ka) in joint_markers.iter().enumerate() {
        for &kb in &joint_markers[x + 1..] {
            let (pa, pb) = (markers[ka].position, markers[kb].position);
            if (pb - pa).norm() > 1e-9 {
                return Some((ka, kb));
            }
        }
    }
    None
}

/// A rigid body's constant terms in basis coordinates: Tᵀ M_f T and Tᵀ Q_g, with
/// M_f = [[m I, C(m̄)], [C(m̄)ᵀ, (P̄₁₁ + P̄₂₂) I]] (m̄, P̄ the first and second moments
/// about the frame origin) and Q_g = (m g, C(m̄)ᵀ g).
fn rigid_terms(
    body: &FlexibleBody,
    frame_map: &Matrix4<f64>,
    g: Vector2<f64>,
) -> (Matrix4<f64>, Vector4<f64>) {
    let t = frame_map;
    let mass = body.mass();
    let mb = body.first_moment();
    let p = body.second_moment();
    let cm = c_of(&Vector2::new(mb.x, mb.y));
    let mut mf = Matrix4::zeros();
    mf.fixed_view_mut::<2, 2>(0, 0)
        .copy_from(&(Matrix2::identity() * mass));
    mf.fixed_view_mut::<2, 2>(0, 2).copy_from(&cm);
    mf.fixed_view_mut::<2, 2>(2, 0).copy_from(&cm.transpose());
    mf.fixed_view_mut::<2, 2>(2, 2)
        .copy_from(&(Matrix2::identity() * (p[(0, 0)] + p[(1, 1)])));
    let m_const = t.transpose() * mf * t;
    let mut qf = Vector4::zeros();
    qf.fixed_rows_mut::<2>(0).copy_from(&(g * mass));
    qf.fixed_rows_mut::<2>(2).copy_from(&(cm.transpose() * g));
    let q_const = t.transpose() * qf;
    (m_const, q_const)
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd_body::ReducedBody;
    use flexmbd_core::Dim;
    use nalgebra::{Matrix3, Vector3};

    fn marker(x: f64, y: f64) -> BodyMarker {
        BodyMarker {
            position: Vector2::new(x, y),
            node: None,
        }
    }

    /// A body at angle θ with origin o: its markers' ground positions.
    fn place(o: Vector2<f64>, th: f64, rbar: Vector2<f64>) -> Vector2<f64> {
        o + Matrix2::new(th.cos(), -th.sin(), th.sin(), th.cos()) * rbar
    }

    #[test]
    fn two_point_map_gives_the_frame() {
        let (ra, rb) = (Vector2::new(0.2, -0.1), Vector2::new(1.1, 0.4));
        let (o, th) = (Vector2::new(0.5, 2.0), 0.7);
        let (t, length) = two_point_frame_map(ra, rb);
        assert!((length - (rb - ra).norm()).abs() < 1e-15);
        let (pa, pb) = (place(o, th, ra), place(o, th, rb));
        let f = t * Vector4::new(pa.x, pa.y, pb.x, pb.y);
        assert!((f.fixed_rows::<2>(0) - o).norm() < 1e-14, "r0 {f}");
        let u = Vector2::new(th.cos(), th.sin());
        assert!((f.fixed_rows::<2>(2) - u).norm() < 1e-14, "u {f}");
    }

    #[test]
    fn point_vector_map_gives_the_frame() {
        let rbar = Vector2::new(0.3, -0.2);
        let (o, th) = (Vector2::new(-1.0, 0.5), -2.1);
        let p = place(o, th, rbar);
        let u = Vector2::new(th.cos(), th.sin());
        let f = point_vector_frame_map(rbar) * Vector4::new(p.x, p.y, u.x, u.y);
        assert!((f.fixed_rows::<2>(0) - o).norm() < 1e-14, "r0 {f}");
        assert!((f.fixed_rows::<2>(2) - u).norm() == 0.0, "u {f}");
    }

    /// docs/methods.md §3.1: a uniform bar on its two end points has the mass matrix
    /// m/3, m/6, m/3 (times I), and its weight splits evenly between the points.
    #[test]
    fn uniform_bar_mass_matrix_is_the_classical_one() {
        let (m, l) = (2.0, 1.5);
        let reduced = ReducedBody::rigid(
            Dim::Planar,
            m,
            Vector3::new(l / 2.0, 0.0, 0.0),
            Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, m * l * l / 12.0)),
        )
        .unwrap();
        let body = FlexibleBody::new(&reduced).unwrap();
        let (t, _) = two_point_frame_map(Vector2::zeros(), Vector2::new(l, 0.0));
        let g = Vector2::new(0.0, -9.81);
        let (mass, forces) = rigid_terms(&body, &t, g);
        let i2 = Matrix2::<f64>::identity();
        let expected = [[m / 3.0, m / 6.0], [m / 6.0, m / 3.0]];
        for (r, row) in expected.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                let block = mass.fixed_view::<2, 2>(2 * r, 2 * c);
                assert!(
                    (block - i2 * *v).amax() < 1e-12,
                    "block ({r}, {c}): {block}"
                );
            }
        }
        let half_weight = Vector4::new(0.0, -9.81 * m / 2.0, 0.0, -9.81 * m / 2.0);
        assert!((forces - half_weight).amax() < 1e-12, "{forces}");
    }

    #[test]
    fn two_distinct_points_skips_coincident_ones() {
        let markers = [marker(0.0, 0.0), marker(0.0, 0.0), marker(1.0, 0.0)];
        assert_eq!(two_distinct_points(&markers, &[0, 1, 2]), Some((0, 2)));
        assert_eq!(two_distinct_points(&markers, &[0, 1]), None);
        assert_eq!(two_distinct_points(&markers, &[2]), None);
    }

    #[test]
    fn initial_motion_is_rigid() {
        let frame = InitialFrame {
            origin: Vector2::zeros(),
            angle: std::f64::consts::FRAC_PI_2,
        };
        let motion = InitialMotion {
            frame,
            linear: Vector2::new(1.0, 0.0),
            angular: 2.0,
        };
        // r̄ = (1, 0) is at (0, 1): ω × r = 2 (−1, 0).
        let v = motion.velocity_of(Vector2::new(1.0, 0.0));
        assert!((v - Vector2::new(-1.0, 0.0)).norm() < 1e-15, "{v}");
    }
}
