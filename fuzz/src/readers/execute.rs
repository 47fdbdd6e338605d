//! One reader execution: the entry point on the files' texts and, when asked and the
//! model read is small, its reduction; then the class of the outcome. A clear `Err` is
//! the expected answer to a malformed file (`refused`); a model or a reduced body that
//! holds a NaN or an infinity is a defect (`ok_non_finite`). Panics propagate (the
//! worker catches them).

use flexmbd::fe::import::{self, FeModel, ImportOptions, Source};
use flexmbd::fe::imported::{
    Coupling, ImportSource, ImportedBody, ImportedBodySpec, ImportedFrame, InterfaceSpec,
    NodeSelection, Xyz, reduce_imported,
};
use flexmbd::fe::spec::Damping;
use flexmbd::fe::{Dof, FeError};

use super::{Reader, ReaderInput, Reduction};
use crate::execute::{Class, Outcome};

/// The largest model (DOFs) reduced: the bar has 84; a mutant that reads as a larger
/// model is not reduced, so a reduction stays within milliseconds.
pub const MAX_REDUCED_DOFS: usize = 200;

/// The name of the reduced body in errors.
const BODY: &str = "bar";

/// Run `input` and classify the outcome.
pub fn execute_reader(input: &ReaderInput) -> Outcome {
    let files = &input.files;
    if files.len() != input.reader.roles().len() {
        // ReaderInput::new and the worker's decoding refuse this; kept out of the reader.
        return Outcome::new(
            Class::Crash,
            format!(
                "fuzzer error: {} given {} files",
                input.reader.name(),
                files.len()
            ),
        );
    }
    let s = |i: usize| Source::new(&files[i].text, &files[i].name);
    let (t, f) = (&files[0].text, files[0].name.as_str());
    let options = ImportOptions::default();
    match input.reader {
        Reader::Generic => model(
            import::parse_generic(s(0), s(1), s(2), s(3), &options),
            input.reduction,
        ),
        Reader::Ansys => model(
            import::parse_ansys(s(0), s(1), s(2), s(3), &options),
            input.reduction,
        ),
        Reader::Abaqus => model(
            import::parse_abaqus(s(0), s(1), s(2), &options),
            input.reduction,
        ),
        Reader::AbaqusCoordinate => {
            let per_node = [Dof::Ux, Dof::Uy, Dof::Uz];
            let read = import::parse_abaqus_coordinate(s(0), s(1), s(2), &per_node, &options);
            model(read, input.reduction)
        }
        Reader::Calculix => model(
            import::parse_calculix(s(0), s(1), s(2), s(3), &options),
            input.reduction,
        ),
        Reader::AbaqusInp => match import::parse_abaqus_inp(t, f) {
            Ok(mesh) => positions(&mesh.nodes, "mesh").unwrap_or_else(|| {
                let (n, e) = (mesh.nodes.len(), mesh.elements.len());
                Outcome::new(Class::Ok, format!("{n} nodes, {e} elements"))
            }),
            Err(e) => refused(&e),
        },
        Reader::NodeList => match import::parse_node_list(t, f) {
            Ok(nodes) => positions(&nodes, "node list")
                .unwrap_or_else(|| Outcome::new(Class::Ok, format!("{} nodes", nodes.len()))),
            Err(e) => refused(&e),
        },
        Reader::DofMap => entries(import::parse_dof_map(t, f)),
        Reader::AnsysMapping => entries(import::parse_ansys_mapping(t, f)),
        Reader::AnsysNodeVector => entries(import::parse_ansys_node_vector(t, f)),
        Reader::CalculixDof => entries(import::parse_calculix_dof(t, f)),
        Reader::Gmsh => match import::parse_gmsh(t, f) {
            Ok(mesh) => positions(&mesh.nodes, "mesh").unwrap_or_else(|| solid(&mesh, f)),
            Err(e) => refused(&e),
        },
    }
}

/// The largest mesh (nodes) assembled by the built-in solid elements: the seeds have up to
/// 189 (a 10-node tetrahedral block has more and is only read).
pub const MAX_ASSEMBLED_NODES: usize = 400;

/// A Gmsh mesh read: assembled with the built-in solid elements when small.
fn solid(mesh: &import::FeMesh, file: &str) -> Outcome {
    let read = format!(
        "{} nodes, {} elements",
        mesh.nodes.len(),
        mesh.elements.len()
    );
    if mesh.nodes.len() > MAX_ASSEMBLED_NODES || mesh.elements.is_empty() {
        return Outcome::new(Class::Ok, read);
    }
    let material = flexmbd::fe::solid::IsotropicElastic::STEEL;
    let consistent = flexmbd::fe::solid::MassMatrix::Consistent;
    match flexmbd::fe::solid::solid_model(
        mesh,
        file,
        &material,
        consistent,
        &ImportOptions::default(),
    ) {
        Ok(model) => match model_non_finite(&model) {
            Some(bad) => Outcome::new(Class::OkNonFinite, format!("solid model: {bad}")),
            None => Outcome::new(
                Class::Ok,
                format!("{read}; {} DOFs assembled", model.n_dofs()),
            ),
        },
        Err(e) => refused(&e),
    }
}

/// The outcome of a model read, reduced as asked when it is small enough.
fn model(read: Result<FeModel, FeError>, reduction: Option<Reduction>) -> Outcome {
    let model = match read {
        Ok(model) => model,
        Err(e) => return refused(&e),
    };
    if let Some(bad) = model_non_finite(&model) {
        return Outcome::new(Class::OkNonFinite, format!("model read: {bad}"));
    }
    let read = format!("{} nodes, {} DOFs", model.mesh.nodes.len(), model.n_dofs());
    match reduction {
        Some(r) if model.n_dofs() <= MAX_REDUCED_DOFS => reduce(&model, r, &read),
        _ => Outcome::new(Class::Ok, read),
    }
}

/// The reduction of a model read.
fn reduce(model: &FeModel, reduction: Reduction, read: &str) -> Outcome {
    match reduce_imported(&reduction_spec(reduction), model, BODY) {
        Ok(body) => match body_non_finite(&body) {
            Some(bad) => Outcome::new(
                Class::OkNonFinite,
                format!("{} reduction: {bad}", reduction.name()),
            ),
            None => Outcome::new(
                Class::Ok,
                format!(
                    "{read}; {} reduction: {} modes",
                    reduction.name(),
                    body.body.n_modes()
                ),
            ),
        },
        Err(e) => checked_refusal(&format!("{} reduction: {e}", reduction.name())),
    }
}

/// The spec of a [`Reduction`] (its source is not read: the model is given).
pub fn reduction_spec(reduction: Reduction) -> ImportedBodySpec {
    let plane_x = |name: &str, x: f64, coupling| InterfaceSpec {
        name: name.into(),
        nodes: NodeSelection::Plane {
            point: Xyz([x, 0.0, 0.0]),
            normal: Xyz([1.0, 0.0, 0.0]),
            tolerance: 1e-6,
        },
        coupling,
    };
    let (frame, root, boundary) = match reduction {
        Reduction::Clamped => (
            ImportedFrame::Interface("root".into()),
            Coupling::Rbe2,
            vec!["tip".to_string()],
        ),
        Reduction::FreeFree => (ImportedFrame::FreeFree, Coupling::Rbe3, Vec::new()),
    };
    ImportedBodySpec {
        source: ImportSource::MatrixMarket {
            nodes: "nodes".into(),
            dofs: "dofs".into(),
            stiffness: "k".into(),
            mass: "m".into(),
        },
        options: ImportOptions::default(),
        interfaces: vec![
            plane_x("root", 0.0, root),
            plane_x("tip", 0.2, Coupling::Rbe3),
        ],
        frame,
        reference: Default::default(),
        boundary,
        normal_modes: 4,
        mode_selection: Default::default(),
        mode_candidates: None,
        pilot_duration: None,
        pilot: None,
        damping: Damping::None,
    }
}

/// The outcome of a DOF map read.
fn entries<T>(read: Result<Vec<T>, FeError>) -> Outcome {
    match read {
        Ok(entries) => Outcome::new(Class::Ok, format!("{} entries", entries.len())),
        Err(e) => refused(&e),
    }
}

/// A refusal: a clear error with a non-empty message.
fn refused(e: &FeError) -> Outcome {
    checked_refusal(&e.to_string())
}

/// `refused` with `message`, or a bad message when it is empty.
fn checked_refusal(message: &str) -> Outcome {
    if message.trim().is_empty() {
        Outcome::new(Class::BadMessage, "refused with an empty message")
    } else {
        Outcome::new(Class::Refused, message)
    }
}

/// A node list read: `ok`, or `ok_non_finite` naming the first non-finite coordinate.
fn positions(nodes: &import::NodeList, what: &str) -> Option<Outcome> {
    let bad = nodes_non_finite(nodes)?;
    Some(Outcome::new(Class::OkNonFinite, format!("{what}: {bad}")))
}

/// The first non-finite node coordinate, named by its node.
fn nodes_non_finite(nodes: &import::NodeList) -> Option<String> {
    nodes.ids.iter().zip(&nodes.positions).find_map(|(id, p)| {
        let v = p.iter().find(|v| !v.is_finite())?;
        Some(format!("node {id} coordinate = {v}"))
    })
}

/// The first non-finite value of a model read (node coordinates, K, M), named.
pub fn model_non_finite(model: &FeModel) -> Option<String> {
    if let Some(bad) = nodes_non_finite(&model.mesh.nodes) {
        return Some(bad);
    }
    for (name, matrix) in [("K", &model.k), ("M", &model.m)] {
        if let Some(i) = first_non_finite(matrix.data().iter().copied()) {
            return Some(format!("{name} entry {i} = {}", matrix.data()[i]));
        }
    }
    None
}

/// The first non-finite value of a reduced body (modes, reduced matrices, mass cloud,
/// shape integrals, node rows, frequencies, interface points), named.
pub fn body_non_finite(imported: &ImportedBody) -> Option<String> {
    let b = &imported.body;
    let si = &b.shape_integrals;
    let named = |name: &str, values: &[f64]| (name.to_string(), values.to_vec());
    let mut parts: Vec<(String, Vec<f64>)> = vec![
        named("frequencies", &b.inventory.normal_frequencies_hz),
        named("modes", b.modes.as_slice()),
        named("m_ff", b.m_ff.as_slice()),
        named("k_ff", b.k_ff.as_slice()),
        named("c_ff", b.c_ff.as_slice()),
        named("cloud weights", &b.cloud.weights),
        named("cloud mode rows", &b.cloud.mode_rows),
        named("mass", &[si.mass]),
        named("first moment", si.first_moment.as_slice()),
        named("second moment", si.second_moment.as_slice()),
        named("S", si.s.as_slice()),
    ];
    for (k, p) in b.cloud.positions.iter().enumerate() {
        parts.push(named(&format!("cloud position {k}"), p.as_slice()));
    }
    for (a, m) in si.s_a.iter().enumerate() {
        parts.push(named(&format!("S_a[{a}]"), m.as_slice()));
    }
    for (a, row) in si.s_ab.iter().enumerate() {
        for (c, m) in row.iter().enumerate() {
            parts.push(named(&format!("S_ab[{a}][{c}]"), m.as_slice()));
        }
    }
    for (name, p) in &imported.interfaces {
        parts.push(named(&format!("interface point {name}"), p.as_slice()));
    }
    for (k, node) in b.nodes.iter().enumerate() {
        parts.push(named(
            &format!("node {k} position"),
            node.position.as_slice(),
        ));
        parts.push(named(
            &format!("node {k} translation"),
            node.translation.as_slice(),
        ));
        parts.push(named(
            &format!("node {k} rotation"),
            node.rotation.as_slice(),
        ));
    }
    parts.into_iter().find_map(|(name, values)| {
        first_non_finite(values.iter().copied()).map(|i| format!("{name}[{i}] = {}", values[i]))
    })
}

/// The index of the first non-finite value.
fn first_non_finite(values: impl Iterator<Item = f64>) -> Option<usize> {
    values
        .enumerate()
        .find(|(_, v)| !v.is_finite())
        .map(|(i, _)| i)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::readers::corpus::{default_import_data_dir, load_reader_corpus};

    fn bar() -> crate::readers::corpus::ReaderSeed {
        let corpus = load_reader_corpus(&default_import_data_dir()).unwrap();
        corpus
            .into_iter()
            .find(|s| s.reader == Reader::Calculix)
            .unwrap()
    }

    #[test]
    fn the_bar_reduces_with_both_specs() {
        for r in [Reduction::Clamped, Reduction::FreeFree] {
            let seed = bar();
            let input = ReaderInput::new(seed.reader, seed.files, Some(r)).unwrap();
            let o = execute_reader(&input);
            assert_eq!(o.class, Class::Ok, "{r:?}: {}", o.detail);
            assert!(o.detail.contains("reduction: "), "{}", o.detail);
        }
    }

    #[test]
    fn a_nan_in_a_model_read_is_found() {
        let seed = bar();
        let s = |i: usize| Source::new(&seed.files[i].text, &seed.files[i].name);
        let mut model =
            import::parse_calculix(s(0), s(1), s(2), s(3), &ImportOptions::default()).unwrap();
        assert_eq!(model_non_finite(&model), None);
        model.m.data_mut()[5] = f64::NAN;
        assert_eq!(model_non_finite(&model).as_deref(), Some("M entry 5 = NaN"));
        model.mesh.nodes.positions[1].y = f64::INFINITY;
        assert_eq!(
            model_non_finite(&model).as_deref(),
            Some("node 2 coordinate = inf")
        );
    }

    #[test]
    fn a_nan_in_a_reduced_body_is_found() {
        let seed = bar();
        let s = |i: usize| Source::new(&seed.files[i].text, &seed.files[i].name);
        let model =
            import::parse_calculix(s(0), s(1), s(2), s(3), &ImportOptions::default()).unwrap();
        let mut body = reduce_imported(&reduction_spec(Reduction::Clamped), &model, BODY).unwrap();
        assert_eq!(body_non_finite(&body), None);
        body.body.shape_integrals.s_ab[1][2][(0, 0)] = f64::NEG_INFINITY;
        assert_eq!(
            body_non_finite(&body).as_deref(),
            Some("S_ab[1][2][0] = -inf")
        );
    }
}
