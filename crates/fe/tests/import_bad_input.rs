//! Bad FE exports are refused with the file, the line and what is wrong — never a
//! panic: malformed lines, unknown nodes, sizes that do not match, matrices that are
//! not symmetric or not definite on their diagonal, missing files, and a
//! deterministic mutation run over the real test files (truncations, byte flips).

use std::path::{Path, PathBuf};

use flexmbd_fe::FeError;
use flexmbd_fe::import::{self, ImportOptions, Source};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/import")
        .join(name)
}

fn opts() -> ImportOptions {
    ImportOptions::default()
}

const INP: &str = "*Node\n1, 0, 0, 0\n2, 1, 0, 0\n";
const NODES: &str = "1 0 0 0\n2 1 0 0\n";
const DOFS: &str = "1 ux\n2 ux\n";
const K: &str = "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 1\n2 1 -1\n2 2 1\n";
const M: &str = "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 0.5\n2 2 0.5\n";

fn generic(nodes: &str, dofs: &str, k: &str, m: &str) -> Result<import::FeModel, FeError> {
    import::parse_generic(
        Source::new(nodes, "nodes.txt"),
        Source::new(dofs, "dofs.txt"),
        Source::new(k, "k.mtx"),
        Source::new(m, "m.mtx"),
        &opts(),
    )
}

fn abaqus(inp: &str, stif: &str, mass: &str) -> Result<import::FeModel, FeError> {
    import::parse_abaqus(
        Source::new(inp, "job.inp"),
        Source::new(stif, "job_STIF1.mtx"),
        Source::new(mass, "job_MASS1.mtx"),
        &opts(),
    )
}

fn refused<T: std::fmt::Debug>(r: Result<T, FeError>, want: &str) {
    let e = r.unwrap_err().to_string();
    println!("{e}");
    assert!(e.contains(want), "expected «{want}» in «{e}»");
}

#[test]
fn the_small_models_read() {
    let g = generic(NODES, DOFS, K, M).unwrap();
    assert_eq!(g.n_dofs(), 2);
    // Abaqus pads its fields (published excerpts: `  101,    1,   101,    1,  9.89e+01`).
    let k = "    1,    1,     1,    1,  1.000000000000000e+00\n    2,    1,     1,    1, -1.0e+00\n    2,    1,     2,    1,  1.0e+00\n";
    let a = abaqus(INP, k, "1,1, 1,1, 0.5\n2,1, 2,1, 0.5\n").unwrap();
    assert_eq!(a.n_dofs(), 2);
    assert_eq!(
        flexmbd_fe::assembly::to_dense(&a.k),
        flexmbd_fe::assembly::to_dense(&g.k)
    );
}

#[test]
fn generic_models_refuse_inconsistent_files() {
    refused(
        generic(NODES, "1 ux\n2 ux\n2 uy\n", K, M),
        "k.mtx: size: the matrix is 2 × 2 but the DOF map lists 3 DOFs",
    );
    refused(
        generic(NODES, "1 ux\n3 ux\n", K, M),
        "dofs.txt:2: node: node 3 is not in the node list",
    );
    refused(
        generic(NODES, "1 ux\n1 ux\n", K, M),
        "node 1 ux is listed twice (rows 1 and 2)",
    );
    refused(
        generic("1 0 0 0\n1 1 0 0\n", DOFS, K, M),
        "nodes.txt:2: node: node 1 is defined twice",
    );
    let general =
        "%%MatrixMarket matrix coordinate real general\n2 2 4\n1 1 1\n2 1 -1\n1 2 -1.5\n2 2 1\n";
    refused(
        generic(NODES, DOFS, general, M),
        "k.mtx: K[2, 1]: K is not symmetric: K[2, 1] = -1e0 but K[1, 2] = -1.5e0 (lines 4 and 5)",
    );
    let zero_mass = "%%MatrixMarket matrix coordinate real symmetric\n2 2 1\n1 1 0.5\n";
    refused(
        generic(NODES, DOFS, K, zero_mass),
        "m.mtx: M[2, 2]: the mass diagonal of node 2 ux is 0e0",
    );
    let negative = "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1\n2 2 -1\n";
    refused(
        generic(NODES, DOFS, negative, M),
        "K[2, 2]: the stiffness diagonal of node 2 ux is -1e0 < 0",
    );
    refused(
        generic(
            NODES,
            DOFS,
            "%%MatrixMarket matrix coordinate real symmetric\n3 3 1\n1 1 1\n",
            M,
        ),
        "the matrix is 3 × 3",
    );
    refused(
        generic(
            NODES,
            DOFS,
            K,
            "%%MatrixMarket matrix coordinate real symmetric\n2 2 1\n1 1 inf\n",
        ),
        "m.mtx:3: value: value `inf` is not finite",
    );
    refused(
        generic(
            NODES,
            DOFS,
            "%%MatrixMarket matrix coordinate real symmetric\n1000000000000 1000000000000 1\n",
            M,
        ),
        "k.mtx:2: rows",
    );
    refused(
        generic("", DOFS, K, M),
        "nodes.txt:1: node: the file lists no node",
    );
    refused(
        generic(NODES, "", K, M),
        "dofs.txt:1: dof: the DOF map is empty",
    );
    refused(
        generic(NODES, DOFS, "", M),
        "k.mtx:1: header: the file is empty",
    );
}

#[test]
fn crlf_files_read_as_lf_files() {
    let crlf = |s: &str| s.replace('\n', "\r\n");
    let a = generic(NODES, DOFS, K, M).unwrap();
    let b = generic(&crlf(NODES), &crlf(DOFS), &crlf(K), &crlf(M)).unwrap();
    assert_eq!((a.k, a.m, a.dofs), (b.k, b.m, b.dofs));
    let inp = std::fs::read_to_string(data("exudyn/blockC3D20.inp")).unwrap();
    let lf = import::parse_abaqus_inp(&inp, "lf").unwrap();
    let cr = import::parse_abaqus_inp(&crlf(&inp), "crlf").unwrap();
    assert_eq!(lf, cr);
}

#[test]
fn abaqus_input_files_refuse_malformed_meshes() {
    let inp = |s: &str| import::parse_abaqus_inp(s, "job.inp");
    refused(inp(""), "job.inp:1: *Node: the input file defines no node");
    refused(
        inp("** only a comment\n*Heading\ntext\n"),
        "defines no node",
    );
    refused(
        inp("*Node\n1, 0, 0, 0\n1, 1, 0, 0\n"),
        "job.inp:3: node: node 1 is defined twice",
    );
    refused(
        inp("*Node\n1, 0, nan, 0\n"),
        "job.inp:2: y: value `nan` is not finite",
    );
    refused(
        inp("*Node\n1\n"),
        "job.inp:2: *Node: expected `label, x[, y[, z]]`, found 1 fields",
    );
    refused(
        inp("*Node\n-4, 0, 0, 0\n"),
        "label: labels are positive integers, found -4",
    );
    refused(
        inp(&format!("{INP}*Element, type=C3D8\n1, 1, 2\n")),
        "job.inp:5: *Element: element 1 of type C3D8 has 2 nodes, expected 8",
    );
    refused(
        inp(&format!("{INP}*Element, type=B31\n1, 1, 7\n")),
        "job.inp:5: *Element: element 1 refers to node `7`, which is not defined",
    );
    refused(
        inp(&format!("{INP}*Element\n1, 1, 2\n")),
        "job.inp:4: *ELEMENT: the parameter type= is missing",
    );
    refused(
        inp(&format!("{INP}*Element, type=B31\n1, 1, 2\n1, 2, 1\n")),
        "job.inp:6: label: element 1 is defined twice",
    );
    refused(
        inp(&format!("{INP}*Include, input=more.inp\n")),
        "job.inp:4: *Include: included files are not read",
    );
    refused(
        inp("*Node, system=C\n1, 1, 0, 0\n"),
        "only rectangular coordinates",
    );
    refused(
        inp(&format!("{INP}*Nset, nset=A, generate\n1, 4000000000, 1\n")),
        "job.inp:5: generate: 1…4000000000 step 1 names 4000000000 labels, more than the 2 defined",
    );
    refused(
        inp(&format!("{INP}*Nset, nset=A, generate\n2, 1\n")),
        "last 1 is below first 2",
    );
    refused(
        inp(&format!("{INP}*Nset, nset=A\n1, B\n")),
        "job.inp:5: set: set `B` is not defined",
    );
    refused(
        inp(&format!("{INP}*Nset, nset=A\n1, 9\n")),
        "job.inp:5: A: node `9` is not defined",
    );
    refused(
        inp("*Assembly, name=A\n*Instance, name=I, part=P\n*End Instance\n*End Assembly\n"),
        "job.inp:2: part: instance I refers to part P, which is not defined",
    );
    refused(
        inp(
            "*Part, name=P\n*Node\n1, 0, 0, 0\n*End Part\n*Assembly, name=A\n*Instance, name=I, part=P\n1, 2\n",
        ),
        "job.inp:7: *Instance: expected a translation",
    );
    refused(
        inp(
            "*Part, name=P\n*Node\n1,0,0,0\n*End Part\n*Assembly, name=A\n*Instance, name=I, part=P\n0,0,0\n0,0,0, 0,0,0, 90\n",
        ),
        "rotation axis points coincide",
    );
    refused(
        inp("*Part, name=P\n*Node\n1, 0, 0, 0\n"),
        "job.inp:3: end of file: the file ends inside *Part P, before its *End Part",
    );
    refused(
        inp("*Assembly, name=A\n*Instance, name=I, part=P\n*End Assembly\n"),
        "job.inp:3: *END ASSEMBLY: not allowed here (inside *Instance, before its *End Instance)",
    );
    refused(
        inp("*Node\n1, 0, 0, 0\n*End Part\n"),
        "job.inp:3: *END PART: not allowed here (outside any part or assembly)",
    );
    refused(
        inp("*Part, name=P\n*Part, name=Q\n"),
        "job.inp:2: *PART: not allowed here (inside *Part P, before its *End Part)",
    );
    // A set named over and over: refused by the work budget, not computed for ever.
    let mut hostile = String::from("*Node, nset=ALL\n");
    for k in 1..=2000 {
        hostile.push_str(&format!("{k}, 0, 0, 0\n"));
    }
    hostile.push_str("*Nset, nset=MANY\n");
    for _ in 0..2000 {
        hostile.push_str("ALL, ALL, ALL, ALL, ALL, ALL, ALL, ALL\n");
    }
    refused(
        inp(&hostile),
        "the sets of this file name more than 64 members per node and element",
    );
}

#[test]
fn abaqus_parts_instances_placements_and_sets() {
    let text = "*Heading\n*PART, NAME=p\n*Node, nset=ALL\n1, 1., 0., 0.\n2, 2., 0., 0.\n\
                *Element, type=T3D2, elset=E\n1, 1, 2\n*Nset, nset=ENDS\n1, 2\n*End Part\n\
                *Assembly, name=A\n*Instance, name=a, part=P\n*End Instance\n\
                *Instance, name=b, part=P\n 0, 0, 1\n 0, 0, 0, 0, 0, 1, 90\n*End Instance\n\
                *Node\n100, 5, 5, 5\n*Nset, nset=TIPS, instance=b\n2\n*Nset, nset=MIX\na.1, 100\n\
                *Nset, nset=FROM_E, instance=a, elset=E\n*End Assembly\n";
    let mesh = import::parse_abaqus_inp(text, "job.inp").unwrap();
    assert_eq!(mesh.nodes.ids, vec!["100", "a.1", "a.2", "b.1", "b.2"]);
    let b2 = mesh.nodes.positions[mesh.nodes.index["b.2"]];
    // (2, 0, 0) + (0, 0, 1), then 90° about z: (0, 2, 1).
    assert!(
        (b2 - nalgebra::Vector3::new(0.0, 2.0, 1.0)).norm() < 1e-15,
        "{b2}"
    );
    assert_eq!(mesh.elements[1].id, "b.1");
    assert_eq!(mesh.node_sets["TIPS"], vec![mesh.nodes.index["b.2"]]);
    assert_eq!(mesh.node_sets["MIX"], vec![0, 1]);
    assert_eq!(mesh.node_sets["FROM_E"], vec![1, 2]);
    assert_eq!(mesh.node_sets["A.ALL"], vec![1, 2]);
    assert_eq!(mesh.node_sets["B.ENDS"], vec![3, 4]);
    assert_eq!(mesh.element_sets["B.E"], vec![1]);
}

#[test]
fn abaqus_matrix_files_refuse_what_they_cannot_map() {
    let m = "1,1, 1,1, 0.5\n2,1, 2,1, 0.5\n";
    let k = "1,1, 1,1, 1\n2,1, 1,1, -1\n2,1, 2,1, 1\n";
    // Instance names match in any case; a plain label finds the only instance's node.
    let inst = "*Part, name=P\n*Node\n1, 0, 0, 0\n2, 1, 0, 0\n*End Part\n\
                *Assembly, name=A\n*Instance, name=Part-1-1, part=P\n*End Instance\n*End Assembly\n";
    let model = abaqus(inst, "PART-1-1.1,1, PART-1-1.1,1, 1\n2,1, 2,1, 1\n", m).unwrap();
    assert_eq!(model.mesh.nodes.ids, vec!["Part-1-1.1", "Part-1-1.2"]);
    refused(
        abaqus(INP, "-1,1, -1,1, 1\n", m),
        "job_STIF1.mtx:1: row node: negative label -1 is an Abaqus internal node",
    );
    refused(
        abaqus(INP, "1,1, 1,1, 1e36\n2,1, 2,1, 1\n", m),
        "job_STIF1.mtx:1: value: stiffness 1e36 on node 1 ux is Abaqus's marker",
    );
    refused(
        abaqus(INP, "1,8, 1,8, 1\n", m),
        "job_STIF1.mtx:1: row dof: DOF 8 is not a displacement or rotation",
    );
    refused(
        abaqus(INP, "3,1, 3,1, 1\n", m),
        "job_STIF1.mtx:1: row node: node `3` is not in the input file",
    );
    refused(
        abaqus(INP, "*CLOAD\n", m),
        "job_STIF1.mtx:1: line: keyword `*CLOAD`",
    );
    refused(
        abaqus(INP, "1,1, 1,1\n", m),
        "job_STIF1.mtx:1: line: expected 5 fields",
    );
    refused(
        abaqus(INP, "", m),
        "job_STIF1.mtx:1: entry: the matrix file has no entry",
    );
    refused(
        abaqus(INP, &format!("{k}1,1, 2,1, -2\n"), m),
        "K is not symmetric",
    );
    refused(
        abaqus(INP, &format!("{k}2,1, 2,1, 1\n"), m),
        "job_STIF1.mtx: K[2, 2]: entry given twice (lines 3 and 4)",
    );
    refused(
        abaqus(INP, k, "1,1, 1,1, 0.5\n"),
        "job_MASS1.mtx: M[2, 2]: the mass diagonal of node 2 ux is 0e0",
    );
}

#[test]
fn missing_files_are_named() {
    let missing = Path::new("/nonexistent/job_STIF1.mtx");
    let e = import::read_abaqus(
        &data("bar_part.inp"),
        missing,
        &data("bar_MASS1.mtx"),
        &opts(),
    )
    .unwrap_err();
    assert!(
        matches!(&e, FeError::Io { file, .. } if file == "/nonexistent/job_STIF1.mtx"),
        "{e}"
    );
    println!("{e}");
}

/// Deterministic mutations of the real files: every reader returns, Ok or Err.
#[test]
fn mutated_real_files_never_panic() {
    let read = |n: &str| std::fs::read(data(n)).unwrap();
    let sets: Vec<Vec<Vec<u8>>> = vec![
        ["bar_nodes.txt", "bar_dofs.txt", "bar_K.mtx", "bar_M.mtx"]
            .map(read)
            .to_vec(),
        ["bar_nlist.lis", "bar.mapping", "bar_K.mtx", "bar_M.mtx"]
            .map(read)
            .to_vec(),
        ["bar_part.inp", "bar_STIF1.mtx", "bar_MASS1.mtx"]
            .map(read)
            .to_vec(),
        [
            "bar_mesh.inp",
            "bar_free.dof",
            "bar_free.sti",
            "bar_free.mas",
        ]
        .map(read)
        .to_vec(),
        ["exudyn/blockC3D20.inp"].map(read).to_vec(),
    ];
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let (mut ok, mut refused) = (0, 0);
    for round in 0..4000 {
        let set = round % sets.len();
        let mut files = sets[set].clone();
        let which = (next() % files.len() as u64) as usize;
        let f = &mut files[which];
        match round % 4 {
            0 => f.truncate((next() % (f.len() as u64 + 1)) as usize),
            1 => {
                for _ in 0..1 + next() % 8 {
                    let at = (next() % f.len() as u64) as usize;
                    let alphabet = b"0123456789,.-+eE* \n\r%#x";
                    f[at] = alphabet[(next() % alphabet.len() as u64) as usize];
                }
            }
            2 => {
                let at = (next() % f.len() as u64) as usize;
                let len = (next() % 64) as usize;
                let chunk: Vec<u8> = f[at..(at + len).min(f.len())].to_vec();
                f.splice(at..at, chunk);
            }
            _ => {
                let at = (next() % f.len() as u64) as usize;
                f.drain(at..(at + (next() % 200) as usize).min(f.len()));
            }
        }
        let texts: Vec<String> = files
            .iter()
            .map(|b| String::from_utf8_lossy(b).into_owned())
            .collect();
        let s = |i: usize| Source::new(&texts[i], "mutated");
        let result = match set {
            0 => import::parse_generic(s(0), s(1), s(2), s(3), &opts()).map(|_| ()),
            1 => import::parse_ansys(s(0), s(1), s(2), s(3), &opts()).map(|_| ()),
            2 => import::parse_abaqus(s(0), s(1), s(2), &opts()).map(|_| ()),
            3 => import::parse_calculix(s(0), s(1), s(2), s(3), &opts()).map(|_| ()),
            _ => import::parse_abaqus_inp(&texts[0], "mutated").map(|_| ()),
        };
        match result {
            Ok(()) => ok += 1,
            Err(_) => refused += 1,
        }
    }
    println!("4000 mutated inputs: {ok} read, {refused} refused, no panic");
    assert!(refused > 1000);
}

/// Lines of separators, signs, comment and keyword marks inserted into every file of
/// every reader: each reader returns (Ok or Err) on each.
#[test]
fn degenerate_lines_never_panic() {
    let sets: [&[&str]; 5] = [
        &["bar_nodes.txt", "bar_dofs.txt", "bar_K.mtx", "bar_M.mtx"],
        &["bar_nlist.lis", "bar.mapping", "bar_K.mtx", "bar_M.mtx"],
        &["bar_part.inp", "bar_STIF1.mtx", "bar_MASS1.mtx"],
        &[
            "bar_mesh.inp",
            "bar_free.dof",
            "bar_free.sti",
            "bar_free.mas",
        ],
        &[
            "exudyn/rotorAnsysNodalCoordinates.txt",
            "exudyn/rotorAnsysMatrixDofMappingVector.txt",
            "exudyn/rotorAnsysStiffnessMatrixSparse.txt",
            "exudyn/rotorAnsysMassMatrixSparse.txt",
        ],
    ];
    let lines = [
        ",",
        " , ",
        ",,,",
        "-",
        "+",
        ".",
        "*",
        "**",
        "*,",
        "*=",
        "%",
        "#",
        "\t",
        "1,",
        "e",
        "1 1",
        "\u{feff}",
        "9223372036854775807, 1, 1, 1",
        "1.",
        ".1",
    ];
    let mut count = 0;
    for (set, names) in sets.iter().enumerate() {
        let texts: Vec<String> = names
            .iter()
            .map(|n| std::fs::read_to_string(data(n)).unwrap())
            .collect();
        for which in 0..texts.len() {
            for bad in lines {
                for at_line in [0usize, 1, 2, 3, 5] {
                    let mut t = texts.clone();
                    let mut v: Vec<&str> = t[which].lines().collect();
                    let at = at_line.min(v.len());
                    v.insert(at, bad);
                    t[which] = v.join("\n");
                    let s = |i: usize| Source::new(&t[i], "degenerate");
                    let _ = match set {
                        0 => import::parse_generic(s(0), s(1), s(2), s(3), &opts()).map(|_| ()),
                        1 | 4 => import::parse_ansys(s(0), s(1), s(2), s(3), &opts()).map(|_| ()),
                        2 => import::parse_abaqus(s(0), s(1), s(2), &opts()).map(|_| ()),
                        _ => import::parse_calculix(s(0), s(1), s(2), s(3), &opts()).map(|_| ()),
                    };
                    count += 1;
                }
            }
        }
    }
    println!("{count} inputs with a degenerate line: no panic");
}
