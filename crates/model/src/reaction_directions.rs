//! The directions in which a joint constrains its two bodies: the unit forces and moments of
//! its reaction on body2 (ground components), at the bodies' present orientations, for the
//! reactions of `flexmbd equilibrium` and the interface-force sensors.
//!
//! | joint | forces | moments |
//! |---|---|---|
//! | Revolute | 3 (planar 2) | 2 ⊥ the axis (planar none) |
//! | Spherical | 3 | — |
//! | Universal | 3 | 1, along arm1 × arm2 |
//! | Prismatic | 2 ⊥ the axis (planar 1) | 3 (planar 1) |
//! | Cylindrical | 2 ⊥ the axis | 2 ⊥ the axis |
//! | Rigid | 3 (planar 2) | 3 (planar 1) |
//! | Free | — | — |
//!
//! A driven joint carries one more: the moment about its axis (revolute) or the force along
//! it (prismatic).

use flexmbd_core::Dim;
use nalgebra::{Matrix3, Vector3};

use crate::scene::{JointKind, V3};

/// Up to three directions, the first `len` of `list`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Directions {
    /// The directions (unit vectors, ground components).
    pub list: [Vector3<f64>; 3],
    /// How many of `list` there are.
    pub len: usize,
}

impl Directions {
    fn of(vs: &[Vector3<f64>]) -> Self {
        let mut d = Directions::default();
        d.list[..vs.len()].copy_from_slice(vs);
        d.len = vs.len();
        d
    }

    fn push(&mut self, v: Vector3<f64>) {
        self.list[self.len] = v;
        self.len += 1;
    }

    /// The directions as a slice.
    pub fn as_slice(&self) -> &[Vector3<f64>] {
        &self.list[..self.len]
    }
}

/// Two unit vectors perpendicular to the unit vector `a` and to each other.
pub fn perpendicular_pair(a: &Vector3<f64>) -> [Vector3<f64>; 2] {
    let helper = if a.x.abs() < 0.6 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let u = a.cross(&helper).normalize();
    [u, a.cross(&u)]
}

/// A joint's constrained directions (forces, moments), ground components, with body1 and
/// body2 turned by `turn1`, `turn2` since the start (R = A A(0)ᵀ; the ground's for a ground
/// body2 is body1's); `driven` adds its driven direction. Allocates nothing.
pub fn joint_directions(
    dim: Dim,
    kind: &JointKind,
    turn1: &Matrix3<f64>,
    turn2: &Matrix3<f64>,
    driven: bool,
) -> (Directions, Directions) {
    let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
    let all = Directions::of(&[x, y, z]);
    let (planar_f, planar_m) = (Directions::of(&[x, y]), Directions::of(&[z]));
    let none = Directions::default();
    let axis = |a: &Option<V3>| match a {
        Some(a) => (turn2 * a.vec()).normalize(),
        None => Vector3::z(),
    };
    let sliding = |a: &V3| (turn2 * a.vec()).normalize();
    match (dim, kind) {
        (_, JointKind::Free) => (none, none),
        (Dim::Planar, JointKind::Revolute { .. }) => {
            (planar_f, if driven { planar_m } else { none })
        }
        (Dim::Planar, JointKind::Prismatic { axis }) => {
            let a = sliding(axis);
            let mut forces = Directions::of(&[Vector3::z().cross(&a)]);
            if driven {
                forces.push(a);
            }
            (forces, planar_m)
        }
        (Dim::Planar, _) => (planar_f, planar_m),
        (Dim::Spatial, JointKind::Revolute { axis: a }) => {
            let a = axis(a);
            let mut moments = Directions::of(&perpendicular_pair(&a));
            if driven {
                moments.push(a);
            }
            (all, moments)
        }
        (Dim::Spatial, JointKind::Spherical) => (all, none),
        (Dim::Spatial, JointKind::Universal { axis1, axis2 }) => {
            let arm = (turn1 * axis1.vec()).cross(&(turn2 * axis2.vec()));
            (all, Directions::of(&[arm.normalize()]))
        }
        (Dim::Spatial, JointKind::Prismatic { axis }) => {
            let a = sliding(axis);
            let mut forces = Directions::of(&perpendicular_pair(&a));
            if driven {
                forces.push(a);
            }
            (forces, all)
        }
        (Dim::Spatial, JointKind::Cylindrical { axis }) => {
            let a = sliding(axis);
            let pair = Directions::of(&perpendicular_pair(&a));
            (pair, pair)
        }
        (Dim::Spatial, JointKind::Rigid) => (all, all),
    }
}

#[cfg(test)]
mod tests {
    use super::perpendicular_pair;
    use nalgebra::Vector3;

    #[test]
    fn perpendicular_pair_is_orthonormal_with_the_axis() {
        for a in [
            Vector3::x(),
            Vector3::y(),
            Vector3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            let [u, v] = perpendicular_pair(&a);
            for (p, q) in [(u, v), (u, a), (v, a)] {
                assert!(p.dot(&q).abs() < 1e-15);
            }
            assert!((u.norm() - 1.0).abs() < 1e-15 && (v.norm() - 1.0).abs() < 1e-15);
        }
    }
}
