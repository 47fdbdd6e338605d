//! Shared basic points: the markers joined by revolute and rigid joints are grouped by
//! union–find; a group that touches the ground is a fixed point, any other gets two
//! coordinates (docs/methods.md §3.1, planar formulation).

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use flexmbd_model::{JointKind, ModelError, PreparedScene, Scene};
use nalgebra::Vector2;

use super::super::body::{PointSlots, Slot};
use super::marker_table::MarkerTable;

/// Disjoint sets of 0..n with path compression; a set's root is its smallest member.
pub(super) struct UnionFind(Vec<usize>);

impl UnionFind {
    /// n singletons.
    pub(super) fn new(n: usize) -> UnionFind {
        UnionFind((0..n).collect())
    }

    /// The root of i's set.
    pub(super) fn find(&mut self, i: usize) -> usize {
        let mut r = i;
        while self.0[r] != r {
            r = self.0[r];
        }
        let mut i = i;
        while self.0[i] != r {
            let next = self.0[i];
            self.0[i] = r;
            i = next;
        }
        r
    }

    /// Merge the sets of a and b.
    pub(super) fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
}

/// The initial coordinates q0, allocated in order.
#[derive(Default)]
pub(super) struct Coordinates {
    pub(super) initial: Vec<f64>,
}

impl Coordinates {
    /// Number of coordinates allocated.
    pub(super) fn len(&self) -> usize {
        self.initial.len()
    }

    /// Two new coordinates with initial values (p.x, p.y).
    pub(super) fn pair(&mut self, p: Vector2<f64>) -> [Slot; 2] {
        let n = self.initial.len();
        self.initial.extend([p.x, p.y]);
        [Slot::Q(n), Slot::Q(n + 1)]
    }

    /// A new point at p.
    pub(super) fn point(&mut self, p: Vector2<f64>) -> PointSlots {
        let [x, y] = self.pair(p);
        PointSlots { x, y }
    }
}

/// The shared point of every joint marker (`None` for a marker in no revolute or rigid
/// joint), allocating coordinates for the points that do not touch the ground. Refuses
/// joint kinds the formulation lacks and joined markers that do not coincide at t = 0.
pub(super) fn shared_points(
    prepared: &PreparedScene,
    table: &MarkerTable,
    coordinates: &mut Coordinates,
) -> Result<Vec<Option<PointSlots>>, ModelError> {
    let scene = prepared.scene();
    let mut groups = join_markers(prepared, table)?;
    let in_joint = joint_markers(prepared, table);
    let mut point_of_root: HashMap<usize, PointSlots> = HashMap::new();
    // Ground-touching groups are fixed.
    for global in 0..table.len() {
        if !in_joint[global] {
            continue;
        }
        let root = groups.find(global);
        if table.owner[global].0.is_none() {
            let p = table.position[global];
            point_of_root.insert(
                root,
                PointSlots {
                    x: Slot::Fixed(p.x),
                    y: Slot::Fixed(p.y),
                },
            );
        }
    }
    for global in 0..table.len() {
        if !in_joint[global] {
            continue;
        }
        let root = groups.find(global);
        if let Entry::Vacant(e) = point_of_root.entry(root) {
            e.insert(coordinates.point(table.global_position(global)));
        }
    }
    check_coincidence(scene, table, &in_joint, &mut groups)?;
    Ok((0..table.len())
        .map(|global| {
            if in_joint[global] {
                point_of_root.get(&groups.find(global)).copied()
            } else {
                None
            }
        })
        .collect())
}

/// The groups of markers joined by revolute and rigid joints.
fn join_markers(prepared: &PreparedScene, table: &MarkerTable) -> Result<UnionFind, ModelError> {
    let mut groups = UnionFind::new(table.len());
    for (j, ends) in prepared.scene().joints.iter().zip(prepared.joint_markers()) {
        match j.kind {
            JointKind::Revolute { .. } | JointKind::Rigid => {
                groups.union(table.global(ends.first), table.global(ends.second));
            }
            // Its markers are not shared points: they slide on each other.
            JointKind::Prismatic { .. } => {}
            // A floating base: no equation.
            JointKind::Free => {}
            ref k => {
                return Err(ModelError::Unsupported(format!(
                    "joint `{}`: {:?} joints are not supported by the planar absolute formulation (revolute, prismatic and rigid are)",
                    j.name, k
                )));
            }
        }
    }
    Ok(groups)
}

/// Which markers are joint points (appear in a revolute or rigid joint).
fn joint_markers(prepared: &PreparedScene, table: &MarkerTable) -> Vec<bool> {
    let mut in_joint = vec![false; table.len()];
    for (j, ends) in prepared.scene().joints.iter().zip(prepared.joint_markers()) {
        if matches!(j.kind, JointKind::Revolute { .. } | JointKind::Rigid) {
            in_joint[table.global(ends.first)] = true;
            in_joint[table.global(ends.second)] = true;
        }
    }
    in_joint
}

/// Every joint marker must be where its group's root marker is at t = 0.
fn check_coincidence(
    scene: &Scene,
    table: &MarkerTable,
    in_joint: &[bool],
    groups: &mut UnionFind,
) -> Result<(), ModelError> {
    for global in 0..table.len() {
        if in_joint[global] {
            let p = table.global_position(global);
            let root_p = table.global_position(groups.find(global));
            if (p - root_p).norm() > 1e-6 {
                let (name, mname) = table.name(scene, global);
                return Err(ModelError::Unsupported(format!(
                    "{}: marker `{name}.{mname}` is at ({:.6}, {:.6}) but the joint point it shares is at ({:.6}, {:.6}); joined markers must coincide at t = 0",
                    scene.origin, p.x, p.y, root_p.x, root_p.y
                )));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd_model::MarkerId;

    #[test]
    fn union_find_groups_under_the_smallest_member() {
        let mut groups = UnionFind::new(6);
        groups.union(4, 2);
        groups.union(5, 4);
        groups.union(1, 3);
        assert_eq!(groups.find(5), 2);
        assert_eq!(groups.find(4), 2);
        assert_eq!(groups.find(3), 1);
        assert_eq!(groups.find(0), 0);
        groups.union(3, 5);
        for i in 1..6 {
            assert_eq!(groups.find(i), 1, "{i}");
        }
        // Path compression: every member now points at the root.
        assert!(groups.0[1..].iter().all(|&r| r == 1), "{:?}", groups.0);
    }

    #[test]
    fn coordinates_are_allocated_in_order() {
        let mut c = Coordinates::default();
        let p = c.point(Vector2::new(1.0, 2.0));
        assert_eq!((p.x, p.y), (Slot::Q(0), Slot::Q(1)));
        assert_eq!(c.pair(Vector2::new(3.0, 4.0)), [Slot::Q(2), Slot::Q(3)]);
        assert_eq!(c.len(), 4);
        assert_eq!(c.initial, [1.0, 2.0, 3.0, 4.0]);
    }

    /// The slider-crank: O is on the ground (fixed), B and C are shared by two bodies, the
    /// prismatic joint's markers and the other markers are no points.
    #[test]
    fn slider_crank_shares_its_revolute_points() {
        let scene = crate::planar::tests::model("slider_crank.ron");
        let prepared = PreparedScene::new(&scene).unwrap();
        let table = MarkerTable::new(&scene);
        let mut coordinates = Coordinates::default();
        let points = shared_points(&prepared, &table, &mut coordinates).unwrap();
        let at = |body: &str, marker: &str| {
            let body = prepared.body_id(body);
            let markers = body.map_or(&scene.ground, |b| &scene.bodies[b.0].markers);
            let index = markers.iter().position(|m| m.name == marker).unwrap();
            points[table.global(MarkerId { body, index })]
        };
        let o = at("crank", "O").unwrap();
        assert_eq!((o.x, o.y), (Slot::Fixed(0.0), Slot::Fixed(0.0)));
        let (b, c) = (at("crank", "B").unwrap(), at("slider", "pin").unwrap());
        assert_eq!((b.x, b.y), (Slot::Q(0), Slot::Q(1)));
        assert_eq!((c.x, c.y), (Slot::Q(2), Slot::Q(3)));
        assert_eq!(at("rod", "B").map(|p| p.x), Some(Slot::Q(0)));
        assert_eq!(at("rod", "C").map(|p| p.x), Some(Slot::Q(2)));
        assert!(at("rod", "mid").is_none() && at("ground", "rail").is_none());
        assert_eq!(coordinates.initial, [0.3, 0.0, 1.3, 0.0]);
    }

    #[test]
    fn joined_markers_must_coincide() {
        // Refused once for both formulations by the prepared scene (the model's check);
        // `check_coincidence` stays as the formulation's own guard.
        let mut scene = crate::planar::tests::model("slider_crank.ron");
        scene.bodies[2].origin.0[1] = 0.01;
        let e = PreparedScene::new(&scene).unwrap_err().to_string();
        assert!(e.contains("slider.pin") && e.contains("coincide"), "{e}");
    }
}
