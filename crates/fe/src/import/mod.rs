//! Readers of FE exports: nodes, elements, sets, K and M into one [`FeModel`].
//!
//! The accepted formats are documented precisely in `docs/import.md`; each reader's
//! module states its format and the source it was checked against:
//!
//! | export | entry points | files |
//! |---|---|---|
//! | Abaqus input file | [`parse_abaqus_inp`], [`read_abaqus_inp`] | `.inp` ([`abaqus_inp`]) |
//! | Abaqus `*MATRIX GENERATE` | [`parse_abaqus`], [`read_abaqus`] | `.inp`, `_STIF1.mtx`, `_MASS1.mtx` ([`abaqus_mtx`]) |
//! | … with `FORMAT=COORDINATE` | [`parse_abaqus_coordinate`], [`read_abaqus_coordinate`] | the same |
//! | Ansys | [`parse_ansys`], [`read_ansys`] | node list, `.mapping`, K and M in Matrix Market |
//! | CalculiX `SOLVER=MATRIXSTORAGE` | [`parse_calculix`], [`read_calculix`] | `.inp`, `.dof`, `.sti`, `.mas` |
//! | Gmsh MSH 4.1 / 2.2 (mesh only) | [`parse_gmsh`], [`read_gmsh`] | `.msh` ([`gmsh`]; K and M by [`crate::solid`]) |
//! | any FE code | [`parse_generic`], [`read_generic`] | node list, DOF map, K and M in Matrix Market |
//!
//! Every `parse_*` takes the texts and the names to quote in errors (no file system:
//! a fuzzer calls them directly); every `read_*` reads the files and calls it.
//! Whatever the input, a reader returns a model or an [`FeError`] — `Format` with
//! file, line, field and what was found; `Import` for a file-level fault (not
//! symmetric, non-positive mass diagonal, negative stiffness diagonal, a DOF map that
//! does not match the matrices, an unknown node); `Io` naming a missing file — and
//! never panics; sizes declared in a file are bounded by its length before anything
//! is allocated from them.

pub mod abaqus_inp;
pub mod abaqus_mtx;
mod abaqus_resolve;
pub mod dof_map;
pub mod gmsh;
pub mod matrix_market;
mod mesh;
mod model;
pub mod nodes;
pub mod options;
pub mod symmetric;
mod text;

use std::path::Path;

pub use abaqus_inp::parse_abaqus_inp;
pub use abaqus_mtx::ABAQUS_BC_MARKER;
pub use dof_map::{
    DofEntry, parse_ansys_mapping, parse_ansys_node_vector, parse_calculix_dof, parse_dof_map,
};
pub use gmsh::{parse_gmsh, read_gmsh};
pub use mesh::{Element, FeMesh};
pub use model::FeModel;
pub use nodes::{NodeList, parse_node_list};
pub use options::{ImportOptions, PointMass};
pub use symmetric::SYMMETRY_TOL;

use crate::error::FeError;
use crate::reduced::Dof;
use model::{MatrixInput, assemble, resolve_dofs};
use symmetric::Storage;

/// A text to parse and the file name errors quote.
#[derive(Clone, Copy, Debug)]
pub struct Source<'a> {
    /// The contents.
    pub text: &'a str,
    /// The name errors quote (a path, or any label).
    pub file: &'a str,
}

impl<'a> Source<'a> {
    /// A text and its name.
    pub fn new(text: &'a str, file: &'a str) -> Self {
        Source { text, file }
    }
}

fn sources(s: &[Source]) -> String {
    s.iter().map(|s| s.file).collect::<Vec<_>>().join(", ")
}

/// Generic: a node list ([`nodes`]), a DOF map ([`dof_map`]) and K and M in
/// Matrix Market coordinate format.
pub fn parse_generic(
    nodes: Source,
    dof_map: Source,
    k: Source,
    m: Source,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    let entries = parse_dof_map(dof_map.text, dof_map.file)?;
    matrix_market_model(nodes, dof_map, &entries, k, m, options)
}

/// Ansys: a node list (`NLIST` output, a Workbench table or `id x y z`), the DOF
/// mapping — the `HBMAT` `.mapping` file, or a node vector in Matrix Market `array`
/// format (recognised by its banner; see [`dof_map`]) — and K and M exported as
/// Matrix Market (`*EXPORT, …, MMF`).
pub fn parse_ansys(
    nodes: Source,
    mapping: Source,
    k: Source,
    m: Source,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    let is_vector = mapping
        .text
        .trim_start_matches('\u{feff}')
        .get(..14)
        .is_some_and(|b| b.eq_ignore_ascii_case("%%MatrixMarket"));
    let entries = if is_vector {
        parse_ansys_node_vector(mapping.text, mapping.file)?
    } else {
        parse_ansys_mapping(mapping.text, mapping.file)?
    };
    matrix_market_model(nodes, mapping, &entries, k, m, options)
}

fn matrix_market_model(
    nodes: Source,
    dof_map: Source,
    entries: &[DofEntry],
    k: Source,
    m: Source,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    let mesh = FeMesh::from_nodes(parse_node_list(nodes.text, nodes.file)?);
    let dofs = resolve_dofs(entries, &mesh, dof_map.file)?;
    let km = matrix_market::parse(k.text, k.file)?;
    let mm = matrix_market::parse(m.text, m.file)?;
    let input = |f: &Source, a: matrix_market::MatrixFile| MatrixInput {
        file: f.file.to_string(),
        n: a.n,
        entries: a.entries,
        storage: a.storage,
    };
    assemble(
        sources(&[nodes, dof_map, k, m]),
        mesh,
        dofs,
        input(&k, km),
        input(&m, mm),
        options,
    )
}

/// Abaqus: the input file and the `FORMAT=MATRIX INPUT` (default) matrix output.
pub fn parse_abaqus(
    inp: Source,
    stiffness: Source,
    mass: Source,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    let mesh = parse_abaqus_inp(inp.text, inp.file)?;
    let kl = abaqus_mtx::parse_labelled(stiffness.text, stiffness.file, &mesh)?;
    let ml = abaqus_mtx::parse_labelled(mass.text, mass.file, &mesh)?;
    let dofs = abaqus_mtx::dof_rows(&kl, &ml);
    let n = dofs.len();
    let k = MatrixInput {
        file: stiffness.file.to_string(),
        n,
        entries: abaqus_mtx::numbered(&kl, &dofs, stiffness.file, true, &mesh)?,
        storage: abaqus_mtx::LABELLED_STORAGE,
    };
    let m = MatrixInput {
        file: mass.file.to_string(),
        n,
        entries: abaqus_mtx::numbered(&ml, &dofs, mass.file, false, &mesh)?,
        storage: abaqus_mtx::LABELLED_STORAGE,
    };
    assemble(sources(&[inp, stiffness, mass]), mesh, dofs, k, m, options)
}

/// Abaqus with `FORMAT=COORDINATE` matrices: equations taken node-major over the
/// input file's nodes with the DOFs `per_node` (see [`abaqus_mtx`] for this assumption).
pub fn parse_abaqus_coordinate(
    inp: Source,
    stiffness: Source,
    mass: Source,
    per_node: &[Dof],
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    let mesh = parse_abaqus_inp(inp.text, inp.file)?;
    let dofs = abaqus_mtx::node_major_rows(&mesh, per_node, inp.file)?;
    let n = dofs.len();
    let matrix = |s: Source| -> Result<MatrixInput, FeError> {
        Ok(MatrixInput {
            file: s.file.to_string(),
            n,
            entries: abaqus_mtx::parse_coordinate(s.text, s.file, n)?,
            storage: Storage::Either,
        })
    };
    let (k, m) = (matrix(stiffness)?, matrix(mass)?);
    assemble(sources(&[inp, stiffness, mass]), mesh, dofs, k, m, options)
}

/// CalculiX `*FREQUENCY, SOLVER=MATRIXSTORAGE`: the input file (Abaqus syntax), the
/// `.dof` file (`node.dof` per equation) and the `.sti`/`.mas` files (`row column
/// value`, 1-based, upper triangle).
pub fn parse_calculix(
    inp: Source,
    dof: Source,
    stiffness: Source,
    mass: Source,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    let mesh = parse_abaqus_inp(inp.text, inp.file)?;
    let entries = parse_calculix_dof(dof.text, dof.file)?;
    let dofs = resolve_dofs(&entries, &mesh, dof.file)?;
    let n = dofs.len();
    let matrix = |s: Source| -> Result<MatrixInput, FeError> {
        Ok(MatrixInput {
            file: s.file.to_string(),
            n,
            entries: abaqus_mtx::parse_coordinate(s.text, s.file, n)?,
            storage: Storage::OneTriangle,
        })
    };
    let (k, m) = (matrix(stiffness)?, matrix(mass)?);
    assemble(
        sources(&[inp, dof, stiffness, mass]),
        mesh,
        dofs,
        k,
        m,
        options,
    )
}

/// A model from K and M computed in memory (full symmetric storage on `dofs`), through the
/// same checks and options as a read export: the built-in solids ([`crate::solid`]).
pub(crate) fn model_from_matrices(
    source: String,
    mesh: FeMesh,
    dofs: Vec<crate::reduced::NodeDof>,
    k: &sprs::CsMat<f64>,
    m: &sprs::CsMat<f64>,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    let input = |what: &str, a: &sprs::CsMat<f64>| MatrixInput {
        file: format!("{source} ({what} assembled)"),
        n: a.rows(),
        entries: a
            .iter()
            .map(|(&value, (row, col))| symmetric::Entry {
                row,
                col,
                value,
                line: 0,
            })
            .collect(),
        storage: Storage::Full,
    };
    let (ki, mi) = (input("K", k), input("M", m));
    assemble(source, mesh, dofs, ki, mi, options)
}

/// Read the named files, then parse them with `parse`.
fn read_all<const N: usize, T>(
    paths: [&Path; N],
    parse: impl FnOnce([Source; N]) -> Result<T, FeError>,
) -> Result<T, FeError> {
    let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    let texts = paths
        .iter()
        .map(|p| text::read_file(p))
        .collect::<Result<Vec<_>, _>>()?;
    let src: [Source; N] = std::array::from_fn(|i| Source::new(&texts[i], &names[i]));
    parse(src)
}

/// [`parse_abaqus_inp`] on a file.
pub fn read_abaqus_inp(path: &Path) -> Result<FeMesh, FeError> {
    read_all([path], |[s]| parse_abaqus_inp(s.text, s.file))
}

/// [`parse_generic`] on files.
pub fn read_generic(
    nodes: &Path,
    dof_map: &Path,
    k: &Path,
    m: &Path,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    read_all([nodes, dof_map, k, m], |[n, d, k, m]| {
        parse_generic(n, d, k, m, options)
    })
}

/// [`parse_ansys`] on files.
pub fn read_ansys(
    nodes: &Path,
    mapping: &Path,
    k: &Path,
    m: &Path,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    read_all([nodes, mapping, k, m], |[n, d, k, m]| {
        parse_ansys(n, d, k, m, options)
    })
}

/// [`parse_abaqus`] on files.
pub fn read_abaqus(
    inp: &Path,
    stiffness: &Path,
    mass: &Path,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    read_all([inp, stiffness, mass], |[i, k, m]| {
        parse_abaqus(i, k, m, options)
    })
}

/// [`parse_abaqus_coordinate`] on files.
pub fn read_abaqus_coordinate(
    inp: &Path,
    stiffness: &Path,
    mass: &Path,
    per_node: &[Dof],
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    read_all([inp, stiffness, mass], |[i, k, m]| {
        parse_abaqus_coordinate(i, k, m, per_node, options)
    })
}

/// [`parse_calculix`] on files.
pub fn read_calculix(
    inp: &Path,
    dof: &Path,
    stiffness: &Path,
    mass: &Path,
    options: &ImportOptions,
) -> Result<FeModel, FeError> {
    read_all([inp, dof, stiffness, mass], |[i, d, k, m]| {
        parse_calculix(i, d, k, m, options)
    })
}
