//! Bad solid input is refused with an error naming the file, line and field, or the element,
//! or the material field and value — never a panic.

use flexmbd_fe::import::{ImportOptions, parse_gmsh};
use flexmbd_fe::solid::{IsotropicElastic, MassMatrix, solid_model};

/// A one-tetrahedron MSH 2.2 file with `elements` as its element lines.
fn msh22(elements: &str) -> String {
    let n = elements.lines().count();
    format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"solid\"\n$EndPhysicalNames\n\
         $Nodes\n6\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 0\n6 1 0 1\n$EndNodes\n\
         $Elements\n{n}\n{elements}$EndElements\n"
    )
}

fn error(text: &str) -> String {
    parse_gmsh(text, "m.msh").unwrap_err().to_string()
}

#[test]
fn msh_errors_name_file_line_and_field() {
    assert!(parse_gmsh(&msh22("1 4 2 1 1 1 2 3 4\n"), "m.msh").is_ok());
    // Extra white space between the fields of a physical name is read.
    let spaced = msh22("1 4 2 1 1 1 2 3 4\n").replace("3 1 \"solid\"", "3   1\t \"solid body\"");
    let m = parse_gmsh(&spaced, "m.msh").unwrap();
    assert_eq!(m.node_sets["solid body"].len(), 4);
    for (text, want) in [
        (
            msh22("1 6 2 1 1 1 2 3 4 5 6\n"),
            "m.msh:19: elementType: the 6-node prism (Gmsh type 6) is not a built-in solid",
        ),
        (
            msh22("1 12 2 1 1 1 2 3 4 5 6\n"),
            "m.msh:19: elementType: the 27-node hexahedron",
        ),
        (
            msh22("1 99 2 1 1 1 2 3 4\n"),
            "m.msh:19: elementType: Gmsh element type 99",
        ),
        (
            msh22("1 4 2 1 1 1 2 3 9\n"),
            "m.msh:19: nodeTag: node 9 is not in $Nodes",
        ),
        (
            msh22("1 4 2 1 1 1 2 3\n"),
            "m.msh:19: nodeTags: a 4-node tetrahedron",
        ),
        (
            msh22("1 4 2 1 1 1 2 3 4\n1 4 2 1 1 1 2 3 5\n"),
            "m.msh:20: elementTag: element 1 is defined twice",
        ),
        (
            msh22("1 4 2 1 1 1 2 3 4\n").replace("4 0 0 1", "4 0 x 1"),
            "m.msh:13: y:",
        ),
        (
            msh22("").replace("2.2 0 8", "2.2 1 8"),
            "m.msh:2: file-type: binary MSH files are not supported",
        ),
        (
            msh22("").replace("2.2 0 8", "3.0 0 8"),
            "m.msh:2: version: MSH version `3.0` is not supported",
        ),
        (
            msh22("").replace("$EndNodes\n", ""),
            "m.msh:8: section: $Nodes has no $EndNodes",
        ),
        (
            msh22("").replace("$Nodes\n6", "$Nodes\n7"),
            "m.msh:15: nodeTag: the section ends before this field",
        ),
        (
            "hello\n".to_string(),
            "m.msh:1: section: expected a section header",
        ),
        (
            "$Nodes\n0\n$EndNodes\n".to_string(),
            "m.msh:1: $MeshFormat: no $MeshFormat section",
        ),
    ] {
        let e = error(&text);
        assert!(e.starts_with(want), "want `{want}`, got `{e}`");
    }
}

/// An MSH 4.1 file whose element block lies on an entity of another dimension, and an
/// inverted tetrahedron (refused by the assembly, naming the file's element id).
#[test]
fn msh41_block_errors_and_inverted_elements() {
    let text = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n\
                0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n$Elements\n1 1 7 7\n3 1 4 1\n7 1 2 3 4\n\
                $EndElements\n";
    let mesh = parse_gmsh(text, "t.msh").unwrap();
    assert_eq!(mesh.elements[0].id, "7");
    let ok = solid_model(
        &mesh,
        "t.msh",
        &IsotropicElastic::STEEL,
        MassMatrix::Lumped,
        &ImportOptions::default(),
    );
    assert!(ok.is_ok());
    let inverted = text.replace("7 1 2 3 4", "7 1 3 2 4");
    let mesh = parse_gmsh(&inverted, "t.msh").unwrap();
    let Err(e) = solid_model(
        &mesh,
        "t.msh",
        &IsotropicElastic::STEEL,
        MassMatrix::Consistent,
        &ImportOptions::default(),
    ) else {
        panic!("inverted element accepted");
    };
    let e = e.to_string();
    assert!(e.starts_with("element 7 of t.msh"), "{e}");
    assert!(e.contains("non-positive Jacobian"), "{e}");
    let e = error(&text.replace("3 1 4 1\n", "2 1 4 1\n"));
    assert!(
        e.starts_with("m.msh:18: entityDim: a block of 4-node tetrahedron elements is on an entity of dimension 2"),
        "{e}"
    );
    let e = error(&text.replace("1 1 7 7", "1 2 7 7"));
    assert!(
        e.contains("numElements: the header declares 2 elements"),
        "{e}"
    );
}

#[test]
fn unphysical_materials_are_refused_by_field_and_value() {
    let mesh = parse_gmsh(&msh22("1 4 2 1 1 1 2 3 4\n"), "m.msh").unwrap();
    for (m, want) in [
        (
            IsotropicElastic {
                young: 0.0,
                ..IsotropicElastic::STEEL
            },
            "material.young",
        ),
        (
            IsotropicElastic {
                density: -1.0,
                ..IsotropicElastic::STEEL
            },
            "material.density",
        ),
        (
            IsotropicElastic {
                poisson: 0.5,
                ..IsotropicElastic::STEEL
            },
            "material.poisson",
        ),
        (
            IsotropicElastic {
                poisson: -1.0,
                ..IsotropicElastic::STEEL
            },
            "material.poisson",
        ),
        (
            IsotropicElastic {
                young: f64::NAN,
                ..IsotropicElastic::STEEL
            },
            "material.young",
        ),
    ] {
        let Err(e) = solid_model(
            &mesh,
            "m.msh",
            &m,
            MassMatrix::Consistent,
            &ImportOptions::default(),
        ) else {
            panic!("{want} accepted");
        };
        let e = e.to_string();
        assert!(e.contains(want), "{e}");
    }
}

/// A solid body in RON (the body-model file syntax): a physical group that does not exist,
/// a bad Poisson ratio and a mesh of another format are refused by name; the good one reduces.
#[test]
fn solid_body_specs_refuse_missing_groups_and_bad_materials() {
    use flexmbd_fe::imported::{ImportedBodySpec, import_body};
    let base = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gmsh");
    let ron = |mesh: &str, nu: f64, set: &str| {
        format!(
            "(source: Solid(mesh: \"{mesh}\", material: (young: 2.1e11, poisson: {nu}, \
             density: 7850.0), mass_matrix: Lumped), \
             interfaces: [(name: \"root\", nodes: Set(\"{set}\"))], \
             frame: Interface(\"root\"), normal_modes: 2)"
        )
    };
    let build = |text: &str| {
        let spec = ImportedBodySpec::from_ron_str(text, "bar.ron").unwrap();
        import_body(&spec, &base, "bar").map(|b| b.body.inventory.normal_frequencies_hz)
    };
    let f = build(&ron("bar_hex8.msh", 0.3, "root")).unwrap();
    assert_eq!(f.len(), 2);
    assert!(f[0] > 100.0 && (f[1] / f[0] - 1.0).abs() < 1e-6, "{f:?}");
    let e = build(&ron("bar_hex8.msh", 0.3, "clamp"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("clamp"), "{e}");
    let e = build(&ron("bar_hex8.msh", 0.7, "root"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("source.Solid.material.poisson") && e.contains("0.7"),
        "{e}"
    );
    let e = build(&ron("bar.geo", 0.3, "root")).unwrap_err().to_string();
    assert!(e.contains("source.Solid.mesh"), "{e}");
}
