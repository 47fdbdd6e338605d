//! The seed inputs of the reader targets: the readers' test exports in
//! `crates/fe/tests/data/import/` (the CalculiX bar converted to every format, and
//! Exudyn's real Abaqus input file and Ansys rotor export in `exudyn/`), each with the
//! entry point that reads it. Every seed must read cleanly as it is.

use std::path::{Path, PathBuf};

use super::execute::execute_reader;
use super::{Reader, ReaderFile, ReaderInput};
use crate::corpus::workspace_root;
use crate::execute::Class;

/// One seed: an entry point and its files (in argument order) as they are.
#[derive(Clone, Debug)]
pub struct ReaderSeed {
    /// The entry point.
    pub reader: Reader,
    /// Its files.
    pub files: Vec<ReaderFile>,
    /// Whether its mutants may be reduced (the bar: 84 DOFs, a fixed spec fits it).
    pub reducible: bool,
}

/// The seeds: reader, files relative to the data directory, reducible.
const SEEDS: &[(Reader, &[&str], bool)] = &[
    (
        Reader::Generic,
        &["bar_nodes.txt", "bar_dofs.txt", "bar_K.mtx", "bar_M.mtx"],
        true,
    ),
    (
        Reader::Ansys,
        &["bar_nlist.lis", "bar.mapping", "bar_K.mtx", "bar_M.mtx"],
        true,
    ),
    (
        Reader::Ansys,
        &[
            "exudyn/rotorAnsysNodalCoordinates.txt",
            "exudyn/rotorAnsysMatrixDofMappingVector.txt",
            "exudyn/rotorAnsysStiffnessMatrixSparse.txt",
            "exudyn/rotorAnsysMassMatrixSparse.txt",
        ],
        false,
    ),
    (
        Reader::Abaqus,
        &["bar_part.inp", "bar_STIF1.mtx", "bar_MASS1.mtx"],
        true,
    ),
    (
        Reader::AbaqusCoordinate,
        &["bar_mesh.inp", "bar_free.sti", "bar_free.mas"],
        true,
    ),
    (
        Reader::Calculix,
        &[
            "bar_mesh.inp",
            "bar_free.dof",
            "bar_free.sti",
            "bar_free.mas",
        ],
        true,
    ),
    (Reader::AbaqusInp, &["bar_mesh.inp"], false),
    (Reader::AbaqusInp, &["bar_part.inp"], false),
    (Reader::AbaqusInp, &["exudyn/blockC3D20.inp"], false),
    (Reader::NodeList, &["bar_nodes.txt"], false),
    (Reader::NodeList, &["bar_nlist.lis"], false),
    (
        Reader::NodeList,
        &["exudyn/rotorAnsysNodalCoordinates.txt"],
        false,
    ),
    (Reader::DofMap, &["bar_dofs.txt"], false),
    (Reader::AnsysMapping, &["bar.mapping"], false),
    (
        Reader::AnsysNodeVector,
        &["exudyn/rotorAnsysMatrixDofMappingVector.txt"],
        false,
    ),
    (Reader::CalculixDof, &["bar_free.dof"], false),
    // The Gmsh meshes of the solid-element tests (crates/fe/tests/data/gmsh).
    (Reader::Gmsh, &["../gmsh/block_tet4_41.msh"], false),
    (Reader::Gmsh, &["../gmsh/block_tet4_22.msh"], false),
    (Reader::Gmsh, &["../gmsh/bar_hex8.msh"], false),
    (Reader::Gmsh, &["../gmsh/bar_hex20_22.msh"], false),
];

/// The readers' test data (the default corpus).
pub fn default_import_data_dir() -> PathBuf {
    workspace_root().join("crates/fe/tests/data/import")
}

/// The seeds (the bar in every format, the Exudyn exports) read from `dir`, each checked
/// to read cleanly (an error names the seed that does not).
pub fn load_reader_corpus(dir: &Path) -> Result<Vec<ReaderSeed>, String> {
    SEEDS
        .iter()
        .map(|&(reader, paths, reducible)| {
            let files = paths
                .iter()
                .map(|p| read_file(&dir.join(p)))
                .collect::<Result<Vec<_>, _>>()?;
            let seed = ReaderSeed {
                reader,
                files,
                reducible,
            };
            check_seed(&seed)?;
            Ok(seed)
        })
        .collect()
}

/// A file of a seed, named by its file name (as the reproducers write it).
fn read_file(path: &Path) -> Result<ReaderFile, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string());
    Ok(ReaderFile { name, text })
}

/// A seed reads cleanly as it is.
fn check_seed(seed: &ReaderSeed) -> Result<(), String> {
    let input = ReaderInput::new(seed.reader, seed.files.clone(), None)?;
    let outcome = execute_reader(&input);
    if outcome.class == Class::Ok {
        Ok(())
    } else {
        Err(format!(
            "seed {} of {} does not read: {} {}",
            describe(seed),
            seed.reader.name(),
            outcome.class.name(),
            outcome.detail
        ))
    }
}

/// The seed's reader and files, as reproducers name it.
pub fn describe(seed: &ReaderSeed) -> String {
    let names: Vec<&str> = seed.files.iter().map(|f| f.name.as_str()).collect();
    format!("{}({})", seed.reader.name(), names.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::readers::READERS;

    #[test]
    fn every_seed_reads_and_every_reader_has_one() {
        let corpus = load_reader_corpus(&default_import_data_dir()).unwrap();
        assert_eq!(corpus.len(), SEEDS.len());
        for r in READERS {
            assert!(corpus.iter().any(|s| s.reader == r), "{r:?} has no seed");
        }
    }
}
