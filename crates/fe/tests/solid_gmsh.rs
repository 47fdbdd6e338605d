//! Gmsh meshes (crates/fe/tests/data/gmsh/, made by its generate.py with Gmsh 4.8.4) read
//! and assembled with the built-in solid elements: the 4.1 and 2.2 files of one mesh agree,
//! the physical groups are the named node sets, the mass is ρ V in each direction for
//! consistent and lumped mass, and K annihilates the six rigid-body motions.

use std::path::PathBuf;

use flexmbd_fe::import::{FeMesh, ImportOptions, read_gmsh};
use flexmbd_fe::solid::{IsotropicElastic, MassMatrix, solid_model};
use sprs::CsMat;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/gmsh")
        .join(name)
}

fn mesh(name: &str) -> FeMesh {
    read_gmsh(&data(name)).unwrap()
}

fn product(a: &CsMat<f64>, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    for (v, (r, c)) in a.iter() {
        y[r] += v * x[c];
    }
    y
}

/// The six rigid-body displacement fields of the nodes (translations, rotations about the
/// origin), node-major.
fn rigid_modes(positions: &[nalgebra::Vector3<f64>]) -> Vec<Vec<f64>> {
    (0..6)
        .map(|k| {
            positions
                .iter()
                .flat_map(|p| {
                    if k < 3 {
                        [0, 1, 2].map(|d| f64::from(u8::from(d == k)))
                    } else {
                        let axis = nalgebra::Vector3::ith(k - 3, 1.0);
                        let u = axis.cross(p);
                        [u.x, u.y, u.z]
                    }
                })
                .collect()
        })
        .collect()
}

#[test]
fn msh_41_and_22_files_of_one_mesh_agree() {
    let (a, b) = (mesh("block_tet4_41.msh"), mesh("block_tet4_22.msh"));
    assert_eq!(a.nodes.ids, b.nodes.ids);
    assert_eq!(a.nodes.positions, b.nodes.positions);
    assert_eq!(a.elements, b.elements);
    assert_eq!(a.node_sets, b.node_sets);
    assert_eq!(a.element_sets, b.element_sets);
    assert!(a.elements.iter().all(|e| e.kind == "C3D4"));
    // The face x = 0 is the set `root`, the face x = 0.1 `tip`, the point (0, 0, 0) `corner`.
    for (set, x) in [("root", 0.0), ("tip", 0.1)] {
        let nodes = &a.node_sets[set];
        assert!(nodes.len() >= 4);
        assert!(
            nodes
                .iter()
                .all(|&n| (a.nodes.positions[n].x - x).abs() < 1e-12)
        );
        let on_face = a.nodes.positions.iter().filter(|p| (p.x - x).abs() < 1e-12);
        assert_eq!(on_face.count(), nodes.len(), "{set}");
    }
    assert_eq!(a.node_sets["corner"].len(), 1);
    assert_eq!(a.nodes.positions[a.node_sets["corner"][0]].norm(), 0.0);
    assert_eq!(a.element_sets["block"].len(), a.elements.len());
}

#[test]
fn mass_is_rho_v_and_rigid_motion_is_stress_free() {
    let steel = IsotropicElastic::STEEL;
    for (file, kind, volume) in [
        ("block_tet4_41.msh", "C3D4", 0.1 * 0.04 * 0.02),
        ("block_tet10.msh", "C3D10", 0.1 * 0.04 * 0.02),
        ("bar_hex8.msh", "C3D8", 0.2 * 0.02 * 0.02),
        ("bar_hex20_22.msh", "C3D20", 0.2 * 0.02 * 0.02),
    ] {
        let m = mesh(file);
        assert!(m.elements.iter().all(|e| e.kind == kind), "{file}");
        for rule in [MassMatrix::Consistent, MassMatrix::Lumped] {
            let model = solid_model(&m, file, &steel, rule, &ImportOptions::default()).unwrap();
            let rigid = rigid_modes(&model.mesh.nodes.positions);
            let mass = steel.density * volume;
            for t in &rigid[..3] {
                let total: f64 = product(&model.m, t).iter().zip(t).map(|(a, b)| a * b).sum();
                assert!(
                    (total / mass - 1.0).abs() < 1e-12,
                    "{file} {rule:?}: {total}"
                );
            }
            if rule == MassMatrix::Lumped {
                assert!(model.m.iter().all(|(v, (r, c))| r == c || *v == 0.0));
                assert!(model.m.diag().iter().all(|(_, &v)| v > 0.0), "{file}");
            }
            let kmax = model.k.data().iter().fold(0.0_f64, |a, v| a.max(v.abs()));
            for (k, u) in rigid.iter().enumerate() {
                let f = product(&model.k, u);
                let worst = f.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
                assert!(worst < 1e-11 * kmax, "{file}: rigid mode {k}: {worst:e}");
            }
        }
    }
}

/// A mesh in millimetres with `length_scale: 1e-3` assembles the K and M of the mesh in
/// metres (the scale acts on the positions before the elements; the material stays SI).
#[test]
fn length_scale_applies_to_the_mesh_before_the_elements() {
    let m = mesh("block_tet4_41.msh");
    let mut mm = m.clone();
    for p in &mut mm.nodes.positions {
        *p *= 1000.0;
    }
    let steel = IsotropicElastic::STEEL;
    let si = solid_model(
        &m,
        "m",
        &steel,
        MassMatrix::Consistent,
        &ImportOptions::default(),
    )
    .unwrap();
    let options = ImportOptions {
        length_scale: 1e-3,
        ..ImportOptions::default()
    };
    let scaled = solid_model(&mm, "mm", &steel, MassMatrix::Consistent, &options).unwrap();
    for (a, b) in [(&si.k, &scaled.k), (&si.m, &scaled.m)] {
        let scale = a.data().iter().fold(0.0_f64, |s, v| s.max(v.abs()));
        let worst = a
            .iter()
            .map(|(v, (r, c))| (v - b.get(r, c).copied().unwrap_or(0.0)).abs())
            .fold(0.0_f64, f64::max);
        assert!(worst < 1e-12 * scale, "{:e}", worst / scale);
    }
}

/// MSH 4.1 details Gmsh writes on other meshes: a parametric node block (its u, v skipped),
/// a physical group without a name (set `dim:tag`), a name with spaces, a 10-node
/// tetrahedron's mid-edge nodes 8 and 9 swapped into Abaqus order.
#[test]
fn msh41_parametric_nodes_unnamed_groups_and_tet10_order() {
    let text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
        $PhysicalNames\n1\n3 7 \"the solid\"\n$EndPhysicalNames\n\
        $Entities\n0 0 1 1\n4 0 0 0 1 1 0 1 5 0\n1 0 0 0 1 1 1 1 7 0\n$EndEntities\n\
        $Nodes\n2 10 1 10\n2 4 1 3\n1\n2\n3\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n\
        3 1 0 7\n4\n5\n6\n7\n8\n9\n10\n0 0 1\n0.5 0 0\n0.5 0.5 0\n0 0.5 0\n0 0 0.5\n0 0.5 0.5\n0.5 0 0.5\n\
        $EndNodes\n\
        $Elements\n2 2 1 2\n2 4 2 1\n1 1 2 3\n3 1 11 1\n2 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";
    let m = flexmbd_fe::import::parse_gmsh(text, "t.msh").unwrap();
    assert_eq!(m.nodes.len(), 10);
    assert_eq!(m.elements.len(), 1);
    assert_eq!(m.elements[0].kind, "C3D10");
    // Gmsh's node 9 (edge 2-3) and 10 (edge 1-3) become Abaqus's 10 and 9 (0-based 9, 8).
    let ids: Vec<&str> = m.elements[0]
        .nodes
        .iter()
        .map(|&n| m.nodes.ids[n].as_str())
        .collect();
    assert_eq!(ids, ["1", "2", "3", "4", "5", "6", "7", "8", "10", "9"]);
    assert_eq!(m.node_sets["2:5"].len(), 3);
    assert_eq!(m.node_sets["the solid"].len(), 10);
    assert_eq!(m.element_sets["the solid"], vec![0]);
    // The element is the unit corner tetrahedron with straight edges: volume 1/6.
    let model = solid_model(
        &m,
        "t.msh",
        &IsotropicElastic::STEEL,
        MassMatrix::Lumped,
        &ImportOptions::default(),
    )
    .unwrap();
    let total: f64 = model.m.diag().iter().map(|(_, &v)| v).sum::<f64>() / 3.0;
    assert!((total / (7850.0 / 6.0) - 1.0).abs() < 1e-12, "{total}");
}

/// Gmsh's quadratic elements of a box have straight edges: after the reordering into
/// Abaqus order every mid-edge node sits at the middle of its edge's corners.
#[test]
fn quadratic_elements_read_in_abaqus_node_order() {
    use flexmbd_fe::solid::shape::{HEX20_EDGES, TET10_EDGES};
    for (file, edges, corners) in [
        ("bar_hex20_22.msh", &HEX20_EDGES[..], 8),
        ("block_tet10.msh", &TET10_EDGES[..], 4),
    ] {
        let m = mesh(file);
        let x = &m.nodes.positions;
        for e in &m.elements {
            for (k, [a, b]) in edges.iter().enumerate() {
                let mid = (x[e.nodes[*a]] + x[e.nodes[*b]]) * 0.5;
                let d = (x[e.nodes[corners + k]] - mid).norm();
                assert!(d < 1e-12, "{file}: element {} edge {k}: {d:e}", e.id);
            }
        }
    }
}
