//! Bad input is refused with an error that names the field and value; no panic.

mod common;

use common::*;
use flexmbd_core::Dim;
use flexmbd_fe::{BeamBodySpec, Dof, FeError, NodeDof, ReferenceFrame, Section, reduce};

/// The spec is refused naming `field` with `value` (see [`invalid`]); the error.
fn assert_invalid(spec: &BeamBodySpec, field: &str, value: &str) -> flexmbd_core::InvalidValue {
    let e = invalid(spec);
    assert_eq!((e.field.as_str(), e.value.as_str()), (field, value));
    e
}

fn invalid(spec: &BeamBodySpec) -> flexmbd_core::InvalidValue {
    // reduce() validates first; validate() gives the same error.
    match reduce(spec) {
        Err(FeError::Invalid(e)) => {
            let again = spec.validate().unwrap_err();
            assert!(matches!(again, FeError::Invalid(ref x) if *x == e));
            println!("refused: {e}");
            e
        }
        other => panic!("expected Invalid, got {other:?}"),
    }
}

fn base() -> BeamBodySpec {
    cantilever(Dim::Planar, square10(), 4, 2)
}

fn general(area: f64, iy: f64, iz: f64, torsion_j: f64) -> Section {
    Section::General {
        area,
        iy,
        iz,
        torsion_j,
    }
}

#[test]
fn coincident_polyline_points() {
    let mut s = base();
    s.geometry.points = vec![
        vec![0.0, 0.0],
        vec![0.5, 0.0],
        vec![0.5, 0.0],
        vec![1.0, 0.0],
    ];
    let e = invalid(&s);
    assert_eq!(e.field, "geometry.points[2]");
    assert!(
        e.value.contains("0.5") && e.value.contains("length 0"),
        "{}",
        e.value
    );
}

/// One node DOF.
fn at(node: usize, dof: Dof) -> NodeDof {
    NodeDof { node, dof }
}

/// Each edit of the base cantilever is refused naming one field with its value:
/// (case, edit, field, value), the case named as its test was.
#[test]
fn one_bad_value_is_refused_naming_field_and_value() {
    type Edit = fn(&mut BeamBodySpec);
    let cases: [(&str, Edit, &str, &str); 9] = [
        (
            "zero_area",
            |s| s.section = general(0.0, 1e-9, 1e-9, 2e-9),
            "section.area",
            "0",
        ),
        (
            "negative_width",
            |s| {
                s.section = Section::Rectangle {
                    width: -0.01,
                    height: 0.01,
                }
            },
            "section.width",
            "-0.01",
        ),
        (
            "negative_density",
            |s| s.material.density = -7850.0,
            "material.density",
            "-7850",
        ),
        (
            "zero_modulus",
            |s| s.material.young_modulus = 0.0,
            "material.young_modulus",
            "0",
        ),
        (
            "non_finite_modulus",
            |s| s.material.young_modulus = f64::INFINITY,
            "material.young_modulus",
            "inf",
        ),
        (
            "negative_inertia",
            |s| s.section = general(1e-4, 1e-9, -1e-9, 2e-9),
            "section.iz",
            "-1e-9",
        ),
        (
            "zero_elements",
            |s| s.geometry.elements_per_segment = 0,
            "geometry.elements_per_segment",
            "0",
        ),
        (
            "boundary_on_missing_node",
            |s| s.boundary = vec![at(5, Dof::Uy)],
            "boundary[0].node",
            "5",
        ),
        (
            "boundary_dof_invalid_in_2d",
            |s| s.boundary = vec![at(4, Dof::Uz)],
            "boundary[0].dof",
            "Uz",
        ),
    ];
    for (case, edit, field, value) in cases {
        let mut s = base();
        edit(&mut s);
        let e = invalid(&s);
        assert_eq!(
            (e.field.as_str(), e.value.as_str()),
            (field, value),
            "{case}"
        );
    }
}

#[test]
fn duplicate_boundary_dof() {
    let mut s = base();
    s.boundary = vec![at(4, Dof::Uy), at(4, Dof::Uy)];
    let e = invalid(&s);
    assert_eq!(e.field, "boundary[1]");
    assert!(e.value.contains("node: 4") && e.value.contains("Uy"));
}

#[test]
fn boundary_dof_that_is_a_frame_dof() {
    let mut s = base();
    s.boundary = vec![at(0, Dof::Rz)];
    let e = invalid(&s);
    assert_eq!(e.field, "boundary[0]");
    assert!(e.reason.contains("frame"));
}

#[test]
fn more_modes_than_the_model_has() {
    // 4 elements, 2D: 15 DOFs, 3 frame, 1 boundary → 11 interior.
    let mut s = base();
    s.boundary = vec![at(4, Dof::Uy)];
    s.normal_modes = 12;
    let e = assert_invalid(&s, "normal_modes", "12");
    assert!(e.reason.contains("11"));
    s.normal_modes = 11;
    assert_eq!(reduce(&s).unwrap().n_modes(), 12);
}

#[test]
fn chord_frame_in_3d_has_singular_interior() {
    let mut s = cantilever(Dim::Spatial, square10(), 4, 2);
    s.frame = ReferenceFrame::Chord { a: 0, b: 4 };
    s.origin = "bar3d.ron".into();
    match reduce(&s) {
        Err(e @ FeError::SingularInterior { .. }) => {
            let msg = e.to_string();
            println!("refused: {msg}");
            assert!(msg.contains("bar3d.ron") && msg.contains("ux@0"));
        }
        other => panic!("expected SingularInterior, got {other:?}"),
    }
}

#[test]
fn pin_only_frame_makes_a_rigid_static_mode() {
    // methods.md §1.4 Pitfall: r = pin at A, b = {v_B}: the v_B "static mode" is a rigid rotation.
    let mut s = base();
    s.frame = ReferenceFrame::Dofs(vec![at(0, Dof::Ux), at(0, Dof::Uy)]);
    s.boundary = vec![at(4, Dof::Uy)];
    s.origin = "pitfall".into();
    match reduce(&s) {
        Err(e @ FeError::RigidStaticMode { .. }) => {
            println!("refused: {e}");
            assert!(e.to_string().contains("pitfall"));
        }
        other => panic!("expected RigidStaticMode, got {other:?}"),
    }
    // Without the boundary, the interior itself is singular.
    s.boundary.clear();
    assert!(matches!(reduce(&s), Err(FeError::SingularInterior { .. })));
}

#[test]
fn ron_with_misspelt_field_names_file_line_and_field() {
    let text = "(\n    dim: Planar,\n    material: (young_modulus: 2.1e11, density: 7850.0),\n    section: Circle(diameter: 0.01),\n    geometry: (points: [[0.0, 0.0], [1.0, 0.0]], elements_per_segmnet: 4),\n    normal_modes: 2,\n)\n";
    match BeamBodySpec::from_ron_str(text, "models/typo.ron") {
        Err(e @ FeError::Parse { .. }) => {
            let FeError::Parse {
                ref file,
                line,
                column,
                ref message,
            } = e
            else {
                unreachable!()
            };
            let msg = e.to_string();
            println!("refused: {msg}");
            assert_eq!(file, "models/typo.ron");
            assert_eq!(line, 5);
            assert!(column > 1);
            assert!(message.contains("elements_per_segmnet"), "{message}");
            assert!(msg.starts_with("models/typo.ron:5:"));
        }
        other => panic!("expected Parse, got {other:?}"),
    }
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let e = BeamBodySpec::from_file("/nonexistent/beam.ron").unwrap_err();
    assert!(matches!(e, FeError::Io { .. }));
    assert!(e.to_string().contains("/nonexistent/beam.ron"));
}

#[test]
fn model_files_load_and_reduce() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/");
    for (f, n_s, n_d) in [
        ("cantilever_2d.ron", 0, 4),
        ("cantilever_3d.ron", 0, 6),
        ("four_bar_bar_2d.ron", 2, 2),
    ] {
        let spec = BeamBodySpec::from_file(format!("{dir}{f}")).unwrap();
        let b = reduce(&spec).unwrap();
        assert_eq!(b.inventory.static_modes.len(), n_s, "{f}");
        assert_eq!(b.inventory.normal_frequencies_hz.len(), n_d, "{f}");
        println!("{f}: {:?} Hz", b.inventory.normal_frequencies_hz);
    }
}

#[test]
fn ron_with_misspelt_section_field_is_refused() {
    let text = "(dim: Planar, material: (young_modulus: 2.1e11, density: 7850.0),\n section: Rectangle(width: 0.01, heigth: 0.01),\n geometry: (points: [[0.0, 0.0], [1.0, 0.0]], elements_per_segment: 4), normal_modes: 2)";
    let e = BeamBodySpec::from_ron_str(text, "inline").unwrap_err();
    println!("refused: {e}");
    assert!(matches!(e, FeError::Parse { line: 2, .. }));
    assert!(e.to_string().contains("heigth"));
}

#[test]
fn axial_modes_error_names_axial_modes() {
    // 4 elements along x, clamped: 12 interior DOFs, of which 4 axial (Ux of nodes 1–4).
    // The count of axial modes is known only from the eigen-solution: refused by reduce.
    let mut s = base();
    s.axial_modes = 5;
    let Err(FeError::Invalid(e)) = reduce(&s) else {
        panic!("5 axial modes of 4 accepted");
    };
    assert_eq!((e.field.as_str(), e.value.as_str()), ("axial_modes", "5"));
    assert!(e.reason.contains("only 4 purely axial"), "{e}");
    // More than the interior DOFs left after the normal modes: refused before reduction.
    s.axial_modes = 50;
    let e = assert_invalid(&s, "axial_modes", "50");
    assert!(
        e.reason.contains("12 interior DOFs, 10 of them left"),
        "{e}"
    );
}

#[test]
fn hyperstatic_frame_is_refused() {
    // Four DOFs where a planar body has three rigid-body motions.
    let mut s = base();
    s.frame = ReferenceFrame::Dofs(vec![
        at(0, Dof::Ux),
        at(0, Dof::Uy),
        at(0, Dof::Rz),
        at(4, Dof::Uy),
    ]);
    let e = assert_invalid(&s, "frame.Dofs", "4 DOFs");
    assert!(e.reason.contains("hyperstatic"), "{e}");
}

#[test]
fn out_of_range_material_and_geometry_are_refused_before_reduction() {
    let mut s = base();
    s.material.young_modulus = 1e20;
    let e = assert_invalid(&s, "material.young_modulus", "1e20");
    assert!(
        e.reason.contains("out of range") && e.reason.contains("1e15"),
        "{e}"
    );
    let mut s = base();
    s.geometry.points[1][0] = 1e300;
    let e = assert_invalid(&s, "geometry.points[1][0]", "1e300");
    assert!(e.reason.contains("out of range"), "{e}");
    let mut s = base();
    s.geometry.points[1][0] = 1e-9;
    let e = assert_invalid(&s, "geometry.elements_per_segment", "4");
    assert!(e.reason.contains("elements"), "{e}");
}

#[test]
fn element_count_of_u64_max_states_the_memory_without_overflow() {
    let mut s = base();
    s.geometry.elements_per_segment = usize::MAX;
    let e = assert_invalid(&s, "geometry.elements_per_segment", &usize::MAX.to_string());
    assert!(
        e.reason.contains("55340232221128654848 FE DOFs") && e.reason.contains("bytes each"),
        "{e}"
    );
    // Memory, sparse and dense: 1 200 003 DOFs need about 3.6 GB reduced on sparse matrices
    // (3 000 bytes per DOF), 11.5 TB for each dense N × N matrix.
    s.geometry.elements_per_segment = 400_000;
    let e = invalid(&s);
    assert!(
        e.reason.contains("1200003 FE DOFs")
            && e.reason.contains("for memory")
            && e.reason.contains("3.6 GB")
            && e.reason.contains("11.5 TB each"),
        "{e}"
    );
    // 60 003 DOFs, refused before the sparse route, are accepted now.
    s.geometry.elements_per_segment = 20_000;
    assert!(s.validate().is_ok());
}
