//! A flexible body from an imported FE model (issue 25; docs/import.md for the files,
//! docs/methods.md §1.3–§1.4 and §2.1–§2.3 for the reduction and the inertia data).
//!
//! [`ImportedBodySpec`] names the export ([`ImportSource`]: Abaqus, Ansys, CalculiX or
//! any FE code through Matrix Market, or a solid mesh — Gmsh or Abaqus input — whose K and M
//! the built-in solid elements compute, [`crate::solid`]), the [`ImportOptions`], the **interfaces** — node sets
//! chosen by name or by geometry, each joined to one interface point, the body's marker
//! site, as a rigid spider (RBE2) or a weighted average (RBE3) — the reference frame and
//! the modes. [`reduce_imported`] turns it, with the model read, into the same
//! [`ReducedBody`] a built-in beam gives, through a sparse pipeline:
//!
//! 1. interfaces: the multipoint constraints of every interface written as one sparse map
//!    u = T ũ from the retained coordinates ũ (the FE DOFs left independent and six
//!    coordinates per interface point) to the FE DOFs ([`interfaces`]);
//! 2. K̃ = Tᵀ K T, M̃ = Tᵀ M T (sparse);
//! 3. the reference frame: **clamped** to an interface point (its six coordinates are the
//!    frame DOFs, zero in every mode) with Craig–Bampton's static modes of the `boundary`
//!    interfaces (K̃_ii⁻¹ by one sparse Cholesky) and fixed-interface normal modes, or
//!    **free-free**: the lowest elastic modes of the unconstrained body, its six rigid-body
//!    modes removed (they are M-orthogonal to them, so the frame follows the mean axes of
//!    the linear theory) ([`reduction`]); the normal modes are the lowest, or chosen by
//!    participation, or load-dependent Ritz vectors, as `mode_selection` says
//!    ([`selection`]);
//! 4. X = T X̃ on the FE DOFs, the mass cloud as an exact rewriting of the sparse mass
//!    matrix, the 13 shape integrals from that cloud, and the node rows: the interface
//!    points first, then every FE node ([`inertia`]).
//!
//! An imported body is spatial. Its stiffening data is empty: the stiffening methods that
//! need element data (FNL1, FNL2, FS0) and substructuring are refused for it by the scene —
//! except FNL1 for a solid mesh (`source: Solid`), whose K_Gk the scene computes from the
//! elements ([`crate::solid::body_geometric_stiffness`]).

pub mod inertia;
pub mod interfaces;
pub mod reduction;
pub mod selection;
pub mod surface;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::FeError;
use crate::import::{self, FeModel, ImportOptions};
use crate::reduced::{Dof, NodeDof, ReducedBody};
use crate::selection::ModeSelection;
use crate::solid::{IsotropicElastic, MassMatrix};
use crate::spec::Damping;

pub use interfaces::{Coupling, InterfaceSpec, NodeSelection, Xyz};

/// The files of an FE export (paths relative to the scene or body-model file).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ImportSource {
    /// Abaqus: the input file and the `*MATRIX GENERATE` output (`_STIF1.mtx`, `_MASS1.mtx`).
    Abaqus {
        /// The `.inp` file (nodes, elements, sets).
        input: PathBuf,
        /// The stiffness matrix file.
        stiffness: PathBuf,
        /// The mass matrix file.
        mass: PathBuf,
    },
    /// Ansys: a node list, the DOF mapping of the matrix export, K and M in Matrix Market.
    Ansys {
        /// The node-coordinate list.
        nodes: PathBuf,
        /// The `.mapping` file (or the node vector) of the matrix export.
        mapping: PathBuf,
        /// K in Matrix Market.
        stiffness: PathBuf,
        /// M in Matrix Market.
        mass: PathBuf,
    },
    /// CalculiX `*FREQUENCY, SOLVER=MATRIXSTORAGE`: the input file, `.dof`, `.sti`, `.mas`.
    Calculix {
        /// The `.inp` file.
        input: PathBuf,
        /// The `.dof` file.
        dofs: PathBuf,
        /// The `.sti` file.
        stiffness: PathBuf,
        /// The `.mas` file.
        mass: PathBuf,
    },
    /// A solid mesh whose K and M the built-in elements compute ([`crate::solid`]): a Gmsh
    /// `.msh` file (4.1 or 2.2 ASCII; physical groups are node sets) or an Abaqus/CalculiX
    /// `.inp` file of C3D4, C3D10, C3D8 and C3D20 elements.
    Solid {
        /// The mesh file (`.msh` or `.inp`).
        mesh: PathBuf,
        /// The isotropic linear-elastic material (SI units).
        material: IsotropicElastic,
        /// Consistent (default) or lumped mass.
        #[serde(default)]
        mass_matrix: MassMatrix,
    },
    /// Any FE code: a node list, a DOF map and K, M in Matrix Market (docs/import.md).
    MatrixMarket {
        /// The node-coordinate list.
        nodes: PathBuf,
        /// The DOF map (one line per matrix row).
        dofs: PathBuf,
        /// K in Matrix Market.
        stiffness: PathBuf,
        /// M in Matrix Market.
        mass: PathBuf,
    },
}

impl ImportSource {
    /// The files it names, as written.
    pub fn paths(&self) -> Vec<&Path> {
        match self {
            ImportSource::Abaqus {
                input,
                stiffness,
                mass,
            } => vec![input, stiffness, mass],
            ImportSource::Ansys {
                nodes,
                mapping,
                stiffness,
                mass,
            } => vec![nodes, mapping, stiffness, mass],
            ImportSource::Calculix {
                input,
                dofs,
                stiffness,
                mass,
            }
            | ImportSource::MatrixMarket {
                nodes: input,
                dofs,
                stiffness,
                mass,
            } => vec![input, dofs, stiffness, mass],
            ImportSource::Solid { mesh, .. } => vec![mesh],
        }
        .into_iter()
        .map(PathBuf::as_path)
        .collect()
    }

    /// The files it names, to rewrite them (e.g. an FMU that ships them in its own folder).
    pub fn paths_mut(&mut self) -> Vec<&mut PathBuf> {
        match self {
            ImportSource::Abaqus {
                input,
                stiffness,
                mass,
            } => vec![input, stiffness, mass],
            ImportSource::Ansys {
                nodes,
                mapping,
                stiffness,
                mass,
            } => vec![nodes, mapping, stiffness, mass],
            ImportSource::Calculix {
                input,
                dofs,
                stiffness,
                mass,
            }
            | ImportSource::MatrixMarket {
                nodes: input,
                dofs,
                stiffness,
                mass,
            } => vec![input, dofs, stiffness, mass],
            ImportSource::Solid { mesh, .. } => vec![mesh],
        }
    }

    /// Read the model, the paths taken relative to `base` (the directory of the file
    /// that names them).
    pub fn read(&self, base: &Path, options: &ImportOptions) -> Result<FeModel, FeError> {
        let p = |path: &PathBuf| base.join(path);
        match self {
            ImportSource::Abaqus {
                input,
                stiffness,
                mass,
            } => import::read_abaqus(&p(input), &p(stiffness), &p(mass), options),
            ImportSource::Ansys {
                nodes,
                mapping,
                stiffness,
                mass,
            } => import::read_ansys(&p(nodes), &p(mapping), &p(stiffness), &p(mass), options),
            ImportSource::Calculix {
                input,
                dofs,
                stiffness,
                mass,
            } => import::read_calculix(&p(input), &p(dofs), &p(stiffness), &p(mass), options),
            ImportSource::MatrixMarket {
                nodes,
                dofs,
                stiffness,
                mass,
            } => import::read_generic(&p(nodes), &p(dofs), &p(stiffness), &p(mass), options),
            ImportSource::Solid {
                mesh,
                material,
                mass_matrix,
            } => {
                material.validate("source.Solid.material")?;
                let path = p(mesh);
                let file = path.display().to_string();
                let is = |ext: &str| {
                    path.extension()
                        .is_some_and(|e| e.eq_ignore_ascii_case(ext))
                };
                let fe_mesh = if is("msh") {
                    import::read_gmsh(&path)?
                } else if is("inp") {
                    import::read_abaqus_inp(&path)?
                } else {
                    return Err(invalid(
                        "source.Solid.mesh".to_string(),
                        file,
                        "must be a Gmsh `.msh` or an Abaqus/CalculiX `.inp` file",
                    ));
                };
                crate::solid::solid_model(&fe_mesh, &file, material, *mass_matrix, options)
            }
        }
    }
}

/// The reference frame of an imported body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ImportedFrame {
    /// Floating: the free-free modes, the six rigid-body modes removed.
    FreeFree,
    /// Clamped to the named interface's point: its six coordinates are the frame's.
    Interface(String),
}

/// One flexible body from an imported FE model, as written in RON.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImportedBodySpec {
    /// The export's files.
    pub source: ImportSource,
    /// Unit scales and point masses.
    #[serde(default)]
    pub options: ImportOptions,
    /// The interfaces, in the order of the body's interface points (node rows 0, 1, …).
    #[serde(default)]
    pub interfaces: Vec<InterfaceSpec>,
    /// The reference frame.
    pub frame: ImportedFrame,
    /// The floating frame's reference condition with `frame: Interface(NAME)` (default
    /// `InterfaceFixed`: the modes vanish on the interface point's six coordinates;
    /// `Buckens`: they are made M-orthogonal to the rigid-body motions, [`crate::reference`]).
    /// A `FreeFree` body's modes satisfy the Buckens conditions already: either value is
    /// accepted there and changes nothing.
    #[serde(default)]
    pub reference: crate::ReferenceCondition,
    /// Interfaces whose six coordinates get Craig–Bampton static modes (a clamped frame
    /// only); they come first in the mode matrix, six per interface.
    #[serde(default)]
    pub boundary: Vec<String>,
    /// Number of normal modes kept (fixed-interface, or free-free elastic).
    pub normal_modes: usize,
    /// How the normal modes are chosen (docs/methods.md §1.6, [`selection`]): the lowest
    /// (default), by participation, load-dependent Ritz vectors, or the proper orthogonal
    /// modes of a pilot run.
    #[serde(default)]
    pub mode_selection: ModeSelection,
    /// `Participation` and `ProperOrthogonal` only: the lowest modes the kept ones are
    /// chosen among (default max(2 `normal_modes`, 4), at most the model's).
    #[serde(default)]
    pub mode_candidates: Option<usize>,
    /// `ProperOrthogonal` only: how long the pilot run is (s; default: the scene's
    /// duration, [`crate::pod::DEFAULT_PILOT_FRACTION`]; never longer than the scene).
    #[serde(default)]
    pub pilot_duration: Option<f64>,
    /// `ProperOrthogonal` only: the modal coordinates the pilot run recorded (set by the
    /// facade that runs the pilot, `flexmbd::pilot`; never read from RON).
    #[serde(skip)]
    pub pilot: Option<std::sync::Arc<crate::pod::PilotRecord>>,
    /// Damping of the modal coordinates.
    #[serde(default)]
    pub damping: Damping,
}

impl ImportedBodySpec {
    /// Parse a body-model file's RON text (`origin_name` names it in errors).
    pub fn from_ron_str(text: &str, origin_name: &str) -> Result<Self, FeError> {
        ron::from_str(text).map_err(|e| FeError::Parse {
            file: origin_name.to_string(),
            line: e.span.start.line,
            column: e.span.start.col,
            message: e.code.to_string(),
        })
    }

    /// K, the lowest normal modes a `ProperOrthogonal` body's pilot run keeps and its proper
    /// orthogonal modes are taken from: `mode_candidates`, or max(2 `normal_modes`, 4).
    pub fn pilot_candidates(&self) -> usize {
        self.mode_candidates
            .unwrap_or_else(|| (2 * self.normal_modes).max(4))
    }

    /// The body the pilot runs in place of this one: its lowest [`Self::pilot_candidates`]
    /// normal modes.
    pub fn pilot_spec(&self) -> ImportedBodySpec {
        ImportedBodySpec {
            normal_modes: self.pilot_candidates(),
            mode_selection: ModeSelection::LowestFrequency,
            mode_candidates: None,
            pilot_duration: None,
            pilot: None,
            ..self.clone()
        }
    }

    /// The pilot record's modal coordinates (K × samples) of a `ProperOrthogonal` body,
    /// refused by name when no pilot ran (a body-model file on its own).
    pub(crate) fn pilot_coordinates(&self, body: &str) -> Result<&nalgebra::DMatrix<f64>, FeError> {
        match &self.pilot {
            Some(record) => Ok(&record.coordinates),
            None => Err(invalid(
                format!("{body}.mode_selection"),
                ModeSelection::ProperOrthogonal.name(),
                "needs the modal coordinates of a pilot run of the scene, which the flexmbd \
                 facade records when it prepares a scene (Simulation::new, simulate, sweep): a \
                 body model on its own has no pilot (methods.md §1.6)",
            )),
        }
    }

    /// Number of modal coordinates: six per boundary interface, then the normal modes.
    pub fn n_modes(&self) -> usize {
        self.boundary
            .len()
            .saturating_mul(6)
            .saturating_add(self.normal_modes)
    }
}

/// The six coordinates of an interface point, in mode order.
pub const POINT_DOFS: [Dof; 6] = [Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz];

/// The coordinates of interface point `point` as node DOFs of the body's node rows (the
/// interface points are nodes 0, 1, … of the reduced body).
pub fn point_dofs(point: usize) -> impl Iterator<Item = NodeDof> {
    POINT_DOFS
        .into_iter()
        .map(move |dof| NodeDof { node: point, dof })
}

/// The reduced body of an imported model and what the scene needs to place it.
#[derive(Clone, Debug)]
pub struct ImportedBody {
    /// The reduced body: node rows 0..`interfaces.len()` are the interface points, the FE
    /// nodes follow in the model's order.
    pub body: ReducedBody,
    /// Name and position (body components, m) of every interface point.
    pub interfaces: Vec<(String, nalgebra::Vector3<f64>)>,
    /// The node ids of the FE model, in node-row order after the interface points.
    pub node_ids: Vec<String>,
    /// The outer surface of the model's elements, triangles of node rows (empty for a
    /// model without solid or shell elements), to draw it ([`surface`]).
    pub surface: Vec<[usize; 3]>,
}

impl ImportedBody {
    /// The node row of an FE node by its id in the file.
    pub fn node_row(&self, id: &str) -> Option<usize> {
        self.node_ids
            .iter()
            .position(|n| n == id)
            .map(|k| k + self.interfaces.len())
    }
}

/// Read the export named by `spec` (paths relative to `base`) and reduce it.
pub fn import_body(
    spec: &ImportedBodySpec,
    base: &Path,
    name: &str,
) -> Result<ImportedBody, FeError> {
    let model = spec.source.read(base, &spec.options)?;
    reduce_imported(spec, &model, name)
}

/// Reduce an imported model as `spec` says (module docs). `name` names the body in errors.
pub fn reduce_imported(
    spec: &ImportedBodySpec,
    model: &FeModel,
    name: &str,
) -> Result<ImportedBody, FeError> {
    check_spec(spec, name)?;
    check_positions(model, name)?;
    let couplings = interfaces::resolve(&spec.interfaces, model, name)?;
    let map = interfaces::RetainedMap::new(model, &couplings, name)?;
    let reduced = reduction::reduce(spec, model, &couplings, &map, name)?;
    let body = inertia::reduced_body(spec, model, &couplings, &map, reduced, name)?;
    check_finite(&body, name)?;
    Ok(ImportedBody {
        body,
        interfaces: couplings
            .iter()
            .map(|c| (c.name.clone(), c.point))
            .collect(),
        node_ids: model.mesh.nodes.ids.clone(),
        surface: surface::outer_surface(&model.mesh, couplings.len()),
    })
}

fn invalid(field: String, value: impl std::fmt::Display, why: impl Into<String>) -> FeError {
    FeError::Invalid(flexmbd_core::InvalidValue::new(field, value, why))
}

/// Every node within the scene's position range (`bounds::POSITION`), so that the inertia
/// integrals (second moments of the positions) stay finite.
fn check_positions(model: &FeModel, name: &str) -> Result<(), FeError> {
    for (k, p) in model.mesh.nodes.positions.iter().enumerate() {
        let field = format!("{name}: node {}", model.mesh.nodes.ids[k]);
        crate::bounds::POSITION.check_all(&field, p.as_slice())?;
    }
    Ok(())
}

/// The reduced body holds finite numbers only: an export whose K or M entries are finite but
/// so large that the reduction overflows is refused here rather than run.
fn check_finite(body: &ReducedBody, name: &str) -> Result<(), FeError> {
    fn bad<'a>(values: impl IntoIterator<Item = &'a f64>) -> Option<f64> {
        values.into_iter().copied().find(|v| !v.is_finite())
    }
    let si = &body.shape_integrals;
    let nodes = body.nodes.iter();
    let found = [
        ("modes", bad(body.modes.iter())),
        ("K_ff", bad(body.k_ff.iter())),
        ("M_ff", bad(body.m_ff.iter())),
        ("C_ff", bad(body.c_ff.iter())),
        (
            "mass cloud",
            bad(body.cloud.weights.iter().chain(&body.cloud.mode_rows)),
        ),
        (
            "second moment",
            bad(si.second_moment.iter().chain([&si.mass])),
        ),
        (
            "shape integrals",
            bad(si.s.iter().chain(si.s_a.iter().flat_map(|m| m.iter()))),
        ),
        (
            "shape integrals S^ab",
            bad(si.s_ab.iter().flatten().flat_map(|m| m.iter())),
        ),
        (
            "node rows",
            bad(nodes.flat_map(|n| n.translation.iter().chain(n.rotation.iter()))),
        ),
    ];
    match found.into_iter().find_map(|(what, v)| v.map(|v| (what, v))) {
        Some((what, v)) => Err(invalid(
            format!("{name}: the reduced {what}"),
            v,
            "the reduction overflowed: an entry of K or M, or a node coordinate, of the export \
             is too large",
        )),
        None => Ok(()),
    }
}

/// The checks that need no model: mode selection, frame and boundary names.
fn check_spec(spec: &ImportedBodySpec, name: &str) -> Result<(), FeError> {
    if let Some(d) = spec.pilot_duration {
        if spec.mode_selection != ModeSelection::ProperOrthogonal {
            return Err(invalid(
                format!("{name}.pilot_duration"),
                d,
                format!(
                    "only used with mode_selection: ProperOrthogonal (this body has {})",
                    spec.mode_selection.name()
                ),
            ));
        }
        if !(d.is_finite() && d > 0.0) {
            return Err(invalid(
                format!("{name}.pilot_duration"),
                d,
                "must be finite and positive (s)",
            ));
        }
    }
    if let Some(c) = spec.mode_candidates {
        if !matches!(
            spec.mode_selection,
            ModeSelection::Participation | ModeSelection::ProperOrthogonal
        ) {
            return Err(invalid(
                format!("{name}.mode_candidates"),
                c,
                format!(
                    "only used with mode_selection: Participation or ProperOrthogonal (this \
                     body has {})",
                    spec.mode_selection.name()
                ),
            ));
        }
        if c < spec.normal_modes {
            return Err(invalid(
                format!("{name}.mode_candidates"),
                c,
                format!(
                    "must be at least normal_modes ({}): the kept modes are chosen among the \
                     candidates",
                    spec.normal_modes
                ),
            ));
        }
    }
    let known = |n: &str| spec.interfaces.iter().any(|i| i.name == n);
    for (k, i) in spec.interfaces.iter().enumerate() {
        if spec.interfaces[..k].iter().any(|j| j.name == i.name) {
            return Err(invalid(
                format!("{name}.interfaces[{k}].name"),
                &i.name,
                "interface names must be unique",
            ));
        }
    }
    if let ImportedFrame::Interface(f) = &spec.frame
        && !known(f)
    {
        return Err(invalid(
            format!("{name}.frame"),
            f,
            "names no interface of the body",
        ));
    }
    for (k, b) in spec.boundary.iter().enumerate() {
        if !known(b) {
            return Err(invalid(
                format!("{name}.boundary[{k}]"),
                b,
                "names no interface of the body",
            ));
        }
        if spec.frame == ImportedFrame::Interface(b.clone()) {
            return Err(invalid(
                format!("{name}.boundary[{k}]"),
                b,
                "is the frame's interface: its coordinates are the frame's, not static modes",
            ));
        }
        if spec.boundary[..k].contains(b) {
            return Err(invalid(
                format!("{name}.boundary[{k}]"),
                b,
                "is listed twice",
            ));
        }
    }
    if spec.frame == ImportedFrame::FreeFree && !spec.boundary.is_empty() {
        return Err(invalid(
            format!("{name}.boundary"),
            spec.boundary.join(", "),
            "static modes need a clamped frame (frame: Interface(NAME)); a free-free body \
             takes normal modes only",
        ));
    }
    Ok(())
}
