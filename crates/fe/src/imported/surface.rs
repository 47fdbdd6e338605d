//! The outer surface of an imported FE mesh, to draw the body: the faces of its solid
//! elements that belong to exactly one element (a face shared by two elements is inside
//! the body), and every shell or membrane element whole, each as triangles of FE nodes.
//!
//! A face is known by its corner nodes (the mid-edge nodes of C3D10 and C3D20 are not
//! drawn: a face is the flat polygon of its corners); faces of the element types of
//! [`crate::solid::shape`] (Abaqus's node order): a tetrahedron (C3D4, C3D10) has the four
//! triangles of its corners 1–4, a hexahedron (C3D8, C3D20) the six quadrilaterals of its
//! corners 1–8 (1-2-3-4, 5-6-7-8, 1-2-6-5, 2-3-7-6, 3-4-8-7, 4-1-5-8), a wedge (C3D6, C3D15)
//! two triangles and three quadrilaterals. A quadrilateral is two triangles. A boundary
//! face of a solid is turned so that its normal (right-hand rule on its nodes) points away
//! from its element's centroid: outwards. Other element types (beams, springs, plane
//! elements) have no surface here.

use std::collections::HashMap;

use nalgebra::Vector3;

use crate::import::FeMesh;

/// Corner faces of a tetrahedron, hexahedron and wedge (0-based corner numbers).
const TET_FACES: [&[usize]; 4] = [&[0, 1, 2], &[0, 1, 3], &[1, 2, 3], &[2, 0, 3]];
const HEX_FACES: [&[usize]; 6] = [
    &[0, 1, 2, 3],
    &[4, 5, 6, 7],
    &[0, 1, 5, 4],
    &[1, 2, 6, 5],
    &[2, 3, 7, 6],
    &[3, 0, 4, 7],
];
const WEDGE_FACES: [&[usize]; 5] = [
    &[0, 1, 2],
    &[3, 4, 5],
    &[0, 1, 4, 3],
    &[1, 2, 5, 4],
    &[2, 0, 3, 5],
];

/// The outer surface of `mesh` as triangles of node indices plus `offset` (the node rows of
/// an imported body put its interface points first), each turned outwards for a solid.
pub fn outer_surface(mesh: &FeMesh, offset: usize) -> Vec<[usize; 3]> {
    let positions = &mesh.nodes.positions;
    // Per face (its sorted corners): how many elements hold it, and its corners in order.
    let mut faces: HashMap<Vec<usize>, (usize, Vec<usize>)> = HashMap::new();
    let mut order = Vec::new();
    let mut shells = Vec::new();
    for element in &mesh.elements {
        let kind = element.kind.as_str();
        let n = element.nodes.len();
        let table: &[&[usize]] = if kind.starts_with("C3D") {
            match n {
                4 | 10 => &TET_FACES,
                8 | 20 | 27 => &HEX_FACES,
                6 | 15 => &WEDGE_FACES,
                _ => continue,
            }
        } else if kind.starts_with('S') || kind.starts_with("M3D") {
            match n {
                3 | 6 => shells.push(element.nodes[..3].to_vec()),
                4 | 8 | 9 => shells.push(element.nodes[..4].to_vec()),
                _ => {}
            }
            continue;
        } else {
            continue;
        };
        let corners = match table.len() {
            4 => 4,
            6 => 8,
            _ => 6,
        };
        let centroid = element.nodes[..corners]
            .iter()
            .map(|&k| positions[k])
            .sum::<Vector3<f64>>()
            / corners as f64;
        for face in table {
            let mut nodes: Vec<usize> = face.iter().map(|&c| element.nodes[c]).collect();
            if !points_outwards(&nodes, positions, &centroid) {
                nodes.reverse();
            }
            let mut key = nodes.clone();
            key.sort_unstable();
            let entry = faces.entry(key.clone()).or_insert_with(|| {
                order.push(key);
                (0, nodes)
            });
            entry.0 += 1;
        }
    }
    let mut triangles = Vec::new();
    let boundary = order
        .iter()
        .map(|key| &faces[key])
        .filter(|(count, _)| *count == 1)
        .map(|(_, nodes)| nodes);
    for nodes in boundary.chain(shells.iter()) {
        let t = |a: usize, b: usize, c: usize| {
            [nodes[a] + offset, nodes[b] + offset, nodes[c] + offset]
        };
        triangles.push(t(0, 1, 2));
        if nodes.len() == 4 {
            triangles.push(t(0, 2, 3));
        }
    }
    triangles
}

/// Whether the polygon `nodes` (right-hand rule) faces away from `centroid`.
fn points_outwards(nodes: &[usize], positions: &[Vector3<f64>], centroid: &Vector3<f64>) -> bool {
    let p = |k: usize| positions[nodes[k]];
    let mut normal = Vector3::zeros();
    for k in 1..nodes.len() - 1 {
        normal += (p(k) - p(0)).cross(&(p(k + 1) - p(0)));
    }
    let centre = nodes.iter().map(|&k| positions[k]).sum::<Vector3<f64>>() / nodes.len() as f64;
    normal.dot(&(centre - centroid)) >= 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::import::{Element, NodeList};

    fn mesh(positions: Vec<[f64; 3]>, elements: Vec<(&str, Vec<usize>)>) -> FeMesh {
        let mut nodes = NodeList::default();
        for (k, p) in positions.into_iter().enumerate() {
            nodes.ids.push(k.to_string());
            nodes.index.insert(k.to_string(), k);
            nodes.positions.push(Vector3::from(p));
        }
        FeMesh {
            nodes,
            elements: elements
                .into_iter()
                .enumerate()
                .map(|(k, (kind, nodes))| Element {
                    id: k.to_string(),
                    kind: kind.into(),
                    nodes,
                })
                .collect(),
            ..FeMesh::default()
        }
    }

    /// Two unit cubes side by side along x: the shared face is inside, the other ten faces
    /// are the surface (20 triangles), every one turned outwards, and their areas add up to
    /// the box's 10 m².
    #[test]
    fn two_hexahedra_have_ten_outer_faces_turned_outwards() {
        let mut positions = Vec::new();
        for x in [0.0, 1.0, 2.0] {
            for (y, z) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                positions.push([x, y, z]);
            }
        }
        // Abaqus order: corners 1-4 at one x face counter-clockwise, 5-8 at the other.
        let hex = |a: usize| vec![a, a + 4, a + 7, a + 3, a + 1, a + 5, a + 6, a + 2];
        let m = mesh(positions, vec![("C3D8", hex(0)), ("C3D8", hex(4))]);
        let triangles = outer_surface(&m, 2);
        assert_eq!(triangles.len(), 20);
        let centre = Vector3::new(1.0, 0.5, 0.5);
        let mut area = 0.0;
        for t in &triangles {
            let p = |k: usize| m.nodes.positions[t[k] - 2];
            let normal = (p(1) - p(0)).cross(&(p(2) - p(0)));
            area += normal.norm() / 2.0;
            let middle = (p(0) + p(1) + p(2)) / 3.0;
            assert!(normal.dot(&(middle - centre)) > 0.0, "{t:?} faces inwards");
        }
        assert!((area - 10.0).abs() < 1e-12, "area {area}");
    }

    /// A tetrahedron's four faces all outwards; a shell element drawn whole; a beam not.
    #[test]
    fn a_tetrahedron_a_shell_and_a_beam() {
        let positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let m = mesh(
            positions,
            vec![
                ("C3D4", vec![0, 1, 2, 3]),
                ("S3", vec![1, 2, 3]),
                ("B31", vec![0, 1]),
            ],
        );
        let triangles = outer_surface(&m, 0);
        assert_eq!(triangles.len(), 5);
        let centroid = Vector3::new(0.25, 0.25, 0.25);
        for t in &triangles[..4] {
            assert!(points_outwards(t, &m.nodes.positions, &centroid));
        }
        assert_eq!(triangles[4], [1, 2, 3]);
    }
}
