//! The FE import readers of `flexmbd_fe::import` as fuzz targets (issue 25 item 9).
//!
//! A reader execution ([`ReaderInput`]) is one entry point of the readers called on the
//! texts of its files — the multi-file readers that give a model (generic, Ansys,
//! Abaqus, Abaqus with coordinate matrices, CalculiX) and the single-file ones (an
//! Abaqus input file, a node list, each kind of DOF map) — and, for some mutants of
//! the small bar, the reduction of the model read with one of two fixed specs
//! ([`Reduction`]). The seeds are the test exports of the readers ([`corpus`]), the
//! mutants are made by [`mutate`], run by [`execute`] in the same supervised workers as
//! the scenes, and a defect is written as a directory of files ([`reproducer`]).

pub mod corpus;
pub mod execute;
pub mod mutate;
pub mod reproducer;

/// A reader entry point of `flexmbd_fe::import`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Reader {
    /// `parse_generic(nodes, dof_map, k, m, options)`.
    Generic,
    /// `parse_ansys(nodes, mapping, k, m, options)` (a `.mapping` file or a node vector).
    Ansys,
    /// `parse_abaqus(inp, stiffness, mass, options)`.
    Abaqus,
    /// `parse_abaqus_coordinate(inp, stiffness, mass, &[Ux, Uy, Uz], options)`.
    AbaqusCoordinate,
    /// `parse_calculix(inp, dof, stiffness, mass, options)`.
    Calculix,
    /// `parse_abaqus_inp(text, file)`.
    AbaqusInp,
    /// `parse_node_list(text, file)`.
    NodeList,
    /// `parse_dof_map(text, file)`.
    DofMap,
    /// `parse_ansys_mapping(text, file)`.
    AnsysMapping,
    /// `parse_ansys_node_vector(text, file)`.
    AnsysNodeVector,
    /// `parse_calculix_dof(text, file)`.
    CalculixDof,
    /// `parse_gmsh(text, file)`, then, for a small mesh, the built-in solid elements'
    /// `solid::solid_model` (steel, consistent mass).
    Gmsh,
}

/// Every reader, in tag order.
pub const READERS: [Reader; 12] = [
    Reader::Generic,
    Reader::Ansys,
    Reader::Abaqus,
    Reader::AbaqusCoordinate,
    Reader::Calculix,
    Reader::AbaqusInp,
    Reader::NodeList,
    Reader::DofMap,
    Reader::AnsysMapping,
    Reader::AnsysNodeVector,
    Reader::CalculixDof,
    Reader::Gmsh,
];

impl Reader {
    /// Its name in outcome lines, signatures and reproducers.
    pub fn name(self) -> &'static str {
        match self {
            Reader::Generic => "generic",
            Reader::Ansys => "ansys",
            Reader::Abaqus => "abaqus",
            Reader::AbaqusCoordinate => "abaqus_coordinate",
            Reader::Calculix => "calculix",
            Reader::AbaqusInp => "abaqus_inp",
            Reader::NodeList => "node_list",
            Reader::DofMap => "dof_map",
            Reader::AnsysMapping => "ansys_mapping",
            Reader::AnsysNodeVector => "ansys_node_vector",
            Reader::CalculixDof => "calculix_dof",
            Reader::Gmsh => "gmsh",
        }
    }

    /// The reader named `name`.
    pub fn from_name(name: &str) -> Option<Reader> {
        READERS.into_iter().find(|r| r.name() == name)
    }

    /// Its tag in worker requests.
    pub fn tag(self) -> u8 {
        READERS.iter().position(|&r| r == self).unwrap_or(0) as u8
    }

    /// The reader of a request tag.
    pub fn from_tag(tag: u8) -> Option<Reader> {
        READERS.get(usize::from(tag)).copied()
    }

    /// The files it takes, in argument order.
    pub fn roles(self) -> &'static [&'static str] {
        match self {
            Reader::Generic => &["nodes", "dof_map", "k", "m"],
            Reader::Ansys => &["nodes", "mapping", "k", "m"],
            Reader::Abaqus | Reader::AbaqusCoordinate => &["inp", "stiffness", "mass"],
            Reader::Calculix => &["inp", "dof", "stiffness", "mass"],
            _ => &["text"],
        }
    }

    /// The call, as a reproducer states it (`flexmbd_fe::import::…`; each argument a
    /// `Source { text, file }` of the file of that role, or the text and its name).
    pub fn call(self) -> String {
        let args = self.roles().join(", ");
        let f = format!("flexmbd_fe::import::parse_{}", self.name());
        match self {
            Reader::AbaqusCoordinate => {
                format!("{f}({args}, &[Dof::Ux, Dof::Uy, Dof::Uz], &ImportOptions::default())")
            }
            r if r.reads_a_model() => format!("{f}({args}, &ImportOptions::default())"),
            _ => format!("{f}(text, file)"),
        }
    }

    /// Whether it reads a whole model (K, M, nodes), which can then be reduced.
    pub fn reads_a_model(self) -> bool {
        matches!(
            self,
            Reader::Generic
                | Reader::Ansys
                | Reader::Abaqus
                | Reader::AbaqusCoordinate
                | Reader::Calculix
        )
    }
}

/// One file of a reader execution.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReaderFile {
    /// Its name (errors quote it; a reproducer writes the file under it).
    pub name: String,
    /// Its text.
    pub text: String,
}

/// The reduction of a model read, with a fixed spec made for the bar of the seeds
/// (0.2 m along x; `crates/fe/tests/imported_body.rs`): interfaces `root` (the nodes
/// in the plane x = 0) and `tip` (x = 0.2), four normal modes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Reduction {
    /// Clamped at `root` (RBE2), Craig–Bampton static modes of `tip` (RBE3).
    Clamped,
    /// Free-free, both interfaces RBE3.
    FreeFree,
}

impl Reduction {
    /// Its name in reproducers.
    pub fn name(self) -> &'static str {
        match self {
            Reduction::Clamped => "clamped",
            Reduction::FreeFree => "free_free",
        }
    }

    /// The reduction named `name` (`none` is no reduction).
    pub fn from_name(name: &str) -> Option<Option<Reduction>> {
        match name {
            "none" => Some(None),
            "clamped" => Some(Some(Reduction::Clamped)),
            "free_free" => Some(Some(Reduction::FreeFree)),
            _ => None,
        }
    }
}

/// One reader execution: the reader, its files in argument order and, for a reader of
/// models, the reduction tried when the model is read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReaderInput {
    /// The entry point.
    pub reader: Reader,
    /// Its files, one per [`Reader::roles`].
    pub files: Vec<ReaderFile>,
    /// The reduction of the model read, if any.
    pub reduction: Option<Reduction>,
}

impl ReaderInput {
    /// An input, checked: one file per role, a reduction only for a reader of models.
    pub fn new(
        reader: Reader,
        files: Vec<ReaderFile>,
        reduction: Option<Reduction>,
    ) -> Result<ReaderInput, String> {
        let roles = reader.roles();
        if files.len() != roles.len() {
            return Err(format!(
                "{} takes {} files ({}), given {}",
                reader.name(),
                roles.len(),
                roles.join(", "),
                files.len()
            ));
        }
        if reduction.is_some() && !reader.reads_a_model() {
            return Err(format!("{} reads no model to reduce", reader.name()));
        }
        Ok(ReaderInput {
            reader,
            files,
            reduction,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_tags_round_trip() {
        for r in READERS {
            assert_eq!(Reader::from_name(r.name()), Some(r));
            assert_eq!(Reader::from_tag(r.tag()), Some(r));
        }
        assert_eq!(Reader::from_tag(READERS.len() as u8), None);
    }

    #[test]
    fn an_input_has_one_file_per_role() {
        let file = ReaderFile {
            name: "a".into(),
            text: String::new(),
        };
        assert!(ReaderInput::new(Reader::DofMap, vec![file.clone()], None).is_ok());
        assert!(ReaderInput::new(Reader::Generic, vec![file.clone()], None).is_err());
        let reduced = ReaderInput::new(Reader::DofMap, vec![file], Some(Reduction::Clamped));
        assert!(reduced.is_err());
    }
}
