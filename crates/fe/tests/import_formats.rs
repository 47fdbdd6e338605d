//! Each reader on its file, and one model read through every format it was converted
//! to: the same K, M and DOF map, bit for bit (tests/data/import/README.md).

use std::path::PathBuf;

use flexmbd_fe::Dof;
use flexmbd_fe::assembly::to_dense;
use flexmbd_fe::import::{self, FeModel, ImportOptions};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/import")
        .join(name)
}

fn calculix() -> FeModel {
    import::read_calculix(
        &data("bar_mesh.inp"),
        &data("bar_free.dof"),
        &data("bar_free.sti"),
        &data("bar_free.mas"),
        &ImportOptions::default(),
    )
    .unwrap()
}

fn generic() -> FeModel {
    import::read_generic(
        &data("bar_nodes.txt"),
        &data("bar_dofs.txt"),
        &data("bar_K.mtx"),
        &data("bar_M.mtx"),
        &ImportOptions::default(),
    )
    .unwrap()
}

fn ansys() -> FeModel {
    import::read_ansys(
        &data("bar_nlist.lis"),
        &data("bar.mapping"),
        &data("bar_K.mtx"),
        &data("bar_M.mtx"),
        &ImportOptions::default(),
    )
    .unwrap()
}

fn abaqus() -> FeModel {
    import::read_abaqus(
        &data("bar_part.inp"),
        &data("bar_STIF1.mtx"),
        &data("bar_MASS1.mtx"),
        &ImportOptions::default(),
    )
    .unwrap()
}

/// Same DOF map, node positions and K, M entries (bit for bit).
fn assert_same(a: &FeModel, b: &FeModel) {
    assert_eq!(a.dofs, b.dofs, "{} vs {}", a.source, b.source);
    assert_eq!(a.mesh.nodes.positions, b.mesh.nodes.positions);
    assert_eq!(
        to_dense(&a.k),
        to_dense(&b.k),
        "K: {} vs {}",
        a.source,
        b.source
    );
    assert_eq!(
        to_dense(&a.m),
        to_dense(&b.m),
        "M: {} vs {}",
        a.source,
        b.source
    );
}

#[test]
fn the_bar_reads_the_same_through_four_formats() {
    let reference = calculix();
    assert_eq!(reference.n_dofs(), 84);
    assert_eq!(reference.mesh.nodes.len(), 28);
    assert_eq!(reference.mesh.elements.len(), 6);
    assert!(reference.mesh.elements.iter().all(|e| e.kind == "C3D8"));
    assert!(reference.k.is_csc() && reference.m.is_csc());
    for other in [generic(), ansys(), abaqus()] {
        assert_same(&reference, &other);
    }
}

#[test]
fn abaqus_ids_are_qualified_by_their_instance() {
    let a = abaqus();
    assert_eq!(a.mesh.nodes.ids[0], "BAR-1.1");
    assert_eq!(a.mesh.elements[0].id, "BAR-1.1");
    let clamp = &a.mesh.node_sets["CLAMP"];
    assert_eq!(clamp.len(), 4);
    assert!(clamp.iter().all(|&n| a.mesh.nodes.positions[n].x == 0.0));
    assert_eq!(a.mesh.element_sets["BAR-1.BAR"].len(), 6);
    assert_eq!(a.dof_row("BAR-1.2", Dof::Uy), Some(4));
}

#[test]
fn a_real_abaqus_cae_input_file_with_an_instance_mesh() {
    let mesh = import::read_abaqus_inp(&data("exudyn/blockC3D20.inp")).unwrap();
    assert_eq!(mesh.nodes.len(), 171);
    assert_eq!(mesh.elements.len(), 20);
    assert!(
        mesh.elements
            .iter()
            .all(|e| e.kind == "C3D20" && e.nodes.len() == 20)
    );
    let first = &mesh.elements[0];
    assert_eq!(first.id, "block-1.1");
    let ids: Vec<&str> = first
        .nodes
        .iter()
        .map(|&n| mesh.nodes.ids[n].as_str())
        .collect();
    assert_eq!(ids[0], "block-1.10");
    assert_eq!(ids[15], "block-1.62", "the continuation line is joined");
    assert_eq!(ids[19], "block-1.66");
    assert_eq!(mesh.node_sets["BLOCK-1.SET-1"].len(), 171);
    assert_eq!(mesh.element_sets["BLOCK-1.SET-1"].len(), 20);
}

#[test]
fn a_real_ansys_export_with_its_node_vector_and_workbench_node_table() {
    let rotor = rotor(&ImportOptions::default());
    assert_eq!(rotor.n_dofs(), 345);
    assert_eq!(rotor.mesh.nodes.len(), 115);
    // The node vector's first entry is node 3: rows 0..3 are its UX, UY, UZ.
    let node3 = rotor.mesh.nodes.index["3"];
    assert_eq!(rotor.dofs[0].node, node3);
    assert_eq!(
        rotor.dofs[..3].iter().map(|d| d.dof).collect::<Vec<_>>(),
        vec![Dof::Ux, Dof::Uy, Dof::Uz]
    );
    assert_eq!(rotor.mesh.nodes.positions[node3].z, 5.00000007e-002);
}

fn rotor(options: &ImportOptions) -> FeModel {
    import::read_ansys(
        &data("exudyn/rotorAnsysNodalCoordinates.txt"),
        &data("exudyn/rotorAnsysMatrixDofMappingVector.txt"),
        &data("exudyn/rotorAnsysStiffnessMatrixSparse.txt"),
        &data("exudyn/rotorAnsysMassMatrixSparse.txt"),
        options,
    )
    .unwrap()
}

/// Abaqus `FORMAT=COORDINATE` as Abaqus/CAE 2021 writes it (Exudyn's
/// `blockC3D8_STIF1.mtx`: `row col  value`, both triangles): the bar's matrices
/// written that way read back equal, equations node-major over the input file's nodes.
#[test]
fn abaqus_coordinate_layout_reads_node_major() {
    let reference = calculix();
    let write = |a: &sprs::CsMat<f64>| {
        let d = to_dense(a);
        let mut s = String::new();
        for j in 0..d.ncols() {
            for i in 0..d.nrows() {
                if d[(i, j)] != 0.0 {
                    s.push_str(&format!("{} {}  {:e}\n", i + 1, j + 1, d[(i, j)]));
                }
            }
        }
        s
    };
    let inp = std::fs::read_to_string(data("bar_mesh.inp")).unwrap();
    let (k, m) = (write(&reference.k), write(&reference.m));
    let coordinate = import::parse_abaqus_coordinate(
        import::Source::new(&inp, "bar_mesh.inp"),
        import::Source::new(&k, "bar_STIF1.mtx"),
        import::Source::new(&m, "bar_MASS1.mtx"),
        &[Dof::Ux, Dof::Uy, Dof::Uz],
        &ImportOptions::default(),
    )
    .unwrap();
    assert_same(&reference, &coordinate);
}

/// An Ansys `.mapping` in another equation order (the solver ordering), its lines
/// shuffled, with K as a `symmetric` and M as a `general` Matrix Market file: the
/// model is the bar's, row for row through the mapping.
#[test]
fn an_ansys_mapping_in_solver_order_permutes_rows_back() {
    let reference = calculix();
    let n = reference.n_dofs();
    // Solver row s holds reference row perm[s] (a permutation: 5 does not divide n).
    assert_ne!(n % 5, 0);
    let perm: Vec<usize> = (0..n).map(|s| (5 * s + 3) % n).collect();
    let (k, m) = (to_dense(&reference.k), to_dense(&reference.m));
    let mut kt = String::new();
    let mut mt = String::new();
    let (mut nk, mut nm) = (0, 0);
    for j in 0..n {
        for i in 0..n {
            let (kv, mv) = (k[(perm[i], perm[j])], m[(perm[i], perm[j])]);
            if kv != 0.0 && i >= j {
                kt.push_str(&format!("{} {} {kv:e}\n", i + 1, j + 1));
                nk += 1;
            }
            if mv != 0.0 {
                mt.push_str(&format!("{} {} {mv:e}\n", i + 1, j + 1));
                nm += 1;
            }
        }
    }
    let kt = format!("%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {nk}\n{kt}");
    let mt = format!("%%MatrixMarket matrix coordinate real general\n{n} {n} {nm}\n{mt}");
    let label = |d: Dof| match d {
        Dof::Ux => "UX",
        Dof::Uy => "UY",
        _ => "UZ",
    };
    let mut mapping = String::from("Matrix Eqn   Node   DOF\n");
    for s in (0..n).rev() {
        let d = reference.dofs[perm[s]];
        let node = &reference.mesh.nodes.ids[d.node];
        mapping.push_str(&format!("{:10} {node:>6}   {}\n", s + 1, label(d.dof)));
    }
    let nodes = std::fs::read_to_string(data("bar_nlist.lis")).unwrap();
    let permuted = import::parse_ansys(
        import::Source::new(&nodes, "bar_nlist.lis"),
        import::Source::new(&mapping, "solver.mapping"),
        import::Source::new(&kt, "k.mtx"),
        import::Source::new(&mt, "m.mtx"),
        &ImportOptions::default(),
    )
    .unwrap();
    let (kp, mp) = (to_dense(&permuted.k), to_dense(&permuted.m));
    for s in 0..n {
        assert_eq!(permuted.dofs[s], reference.dofs[perm[s]]);
        for t in 0..n {
            assert_eq!(kp[(s, t)], k[(perm[s], perm[t])]);
            assert_eq!(mp[(s, t)], m[(perm[s], perm[t])]);
        }
    }
}
