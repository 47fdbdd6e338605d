//! From a scene body to a body ready to run: the plain data of FE preprocessing (a
//! [`ReducedBody`] for every body; rigid bodies and beams run rigid have zero modes), the
//! FE node each marker of a flexible body sits on, and the run-time [`FlexibleBody`] with
//! the elastic model of the scene's stiffening method installed (FNL1, FNL2 from
//! `flexmbd-stiffening`; FS0's shortening data attached, docs/methods.md §6.2–§6.3).

use flexmbd_body::{ElasticModel, FlexibleBody, NodeRows};
use flexmbd_core::InvalidValue;
use flexmbd_fe::imported::{ImportSource, reduce_imported};
use flexmbd_fe::solid::body_geometric_stiffness;
use flexmbd_fe::{ReducedBody, ReferenceFrame, reduce};
use flexmbd_stiffening::Nonlinear;

use crate::error::ModelError;
use crate::scene::{Body, BodyModel, ImportedBodySpec, ImportedFrame, Scene, Stiffening};

/// The preprocessed form of one scene body.
#[derive(Clone, Debug)]
pub struct PreparedBody {
    /// Index in `Scene::bodies` of the prepared (rewritten) scene.
    pub index: usize,
    /// Reduced data (zero modes when rigid), with the FS0 data when foreshortened.
    pub reduced: ReducedBody,
    /// The run-time body, its elastic model installed.
    pub body: FlexibleBody,
    /// Positions and mode rows of the body's nodes, the one view of them the formulations
    /// read (empty for a rigid body).
    pub nodes: NodeRows,
    /// True when the body has modal coordinates.
    pub flexible: bool,
    /// For each marker of the body, the FE node it sits on (flexible bodies only).
    pub marker_nodes: Vec<Option<usize>>,
    /// The FE node the floating frame is attached to (flexible bodies only): a beam's clamped
    /// node, chord frame's pinned node, or first node of an explicit DOF set, an imported
    /// body's frame interface point; `None` with `reference: Buckens` or `frame: FreeFree`
    /// (the frame is attached to no node).
    pub reference_node: Option<usize>,
    /// The outer surface of an imported body's FE elements, triangles of `nodes` indices
    /// (flexmbd_fe::imported::surface), to draw it; empty for other bodies.
    pub surface: Vec<[usize; 3]>,
}

impl Scene {
    /// Preprocess every body (FE reduction, rigid mass models, elastic models). The scene
    /// must already be rewritten for its stiffening method: use
    /// [`PreparedScene::new`](crate::PreparedScene::new), which does both.
    pub(crate) fn prepare_bodies(&self) -> Result<Vec<PreparedBody>, ModelError> {
        self.bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let mut prepared = self.prepare_body(i, b)?;
                self.install_stiffening(&mut prepared)?;
                self.install_inertia_terms(b, &mut prepared)?;
                Ok(prepared)
            })
            .collect()
    }

    fn prepare_body(&self, index: usize, b: &Body) -> Result<PreparedBody, ModelError> {
        let fe_err = |source| self.fe_error(&b.name, source);
        match &b.model {
            BodyModel::Rigid {
                mass,
                center_of_mass,
                inertia,
            } => {
                let reduced =
                    ReducedBody::rigid(self.dim, *mass, center_of_mass.vec(), inertia.tensor())
                        .map_err(|e: InvalidValue| {
                            self.invalid(InvalidValue {
                                field: format!("bodies[{}].model.Rigid.{}", b.name, e.field),
                                ..e
                            })
                        })?;
                Ok(PreparedBody {
                    index,
                    body: self.run_time_body(&reduced)?,
                    nodes: NodeRows::from_reduced(&reduced),
                    reduced,
                    flexible: false,
                    marker_nodes: vec![None; b.markers.len()],
                    reference_node: None,
                    surface: Vec::new(),
                })
            }
            BodyModel::Beam(spec) => {
                let mut spec = spec.clone();
                if !b.flexible {
                    // The rigid body with the beam's mass properties: no modes at all.
                    spec.boundary.clear();
                    spec.normal_modes = 0;
                }
                let reduced = reduce(&spec).map_err(fe_err)?;
                let nodes = NodeRows::from_reduced(&reduced);
                let length: f64 = spec
                    .geometry
                    .points
                    .windows(2)
                    .map(|w| {
                        let d: f64 = w[0].iter().zip(&w[1]).map(|(a, c)| (c - a) * (c - a)).sum();
                        d.sqrt()
                    })
                    .sum();
                let marker_nodes = self.marker_nodes(b, &nodes, length, b.flexible, || {
                    "a marker of a flexible body must sit on an FE node".to_string()
                })?;
                let flexible = b.flexible && reduced.n_modes() > 0;
                // A Buckens frame is the linearised mean axes: attached to no node.
                let interface_fixed =
                    spec.reference == flexmbd_fe::ReferenceCondition::InterfaceFixed;
                let reference_node = (flexible && interface_fixed).then(|| match &spec.frame {
                    ReferenceFrame::Clamped { node } => *node,
                    ReferenceFrame::Chord { a, .. } => *a,
                    ReferenceFrame::Dofs(dofs) => dofs.first().map_or(0, |d| d.node),
                });
                Ok(PreparedBody {
                    index,
                    body: self.run_time_body(&reduced)?,
                    nodes,
                    flexible,
                    reduced,
                    marker_nodes,
                    reference_node,
                    surface: Vec::new(),
                })
            }
            BodyModel::Imported(spec) => self.prepare_imported(index, b, spec),
        }
    }

    /// An imported FE body: its export read (paths relative to the scene file) and reduced;
    /// its markers on interface points or FE nodes. Run rigid, it keeps the model's mass
    /// properties and no modes.
    fn prepare_imported(
        &self,
        index: usize,
        b: &Body,
        spec: &ImportedBodySpec,
    ) -> Result<PreparedBody, ModelError> {
        let mut spec = spec.clone();
        if !b.flexible {
            spec.boundary.clear();
            spec.normal_modes = 0;
            spec.frame = ImportedFrame::FreeFree;
            spec.interfaces.clear();
        }
        let name = format!("bodies[{}].model.Imported", b.name);
        let fe_err = |e| self.fe_error(&b.name, e);
        let model = spec
            .source
            .read(&self.base_directory(), &spec.options)
            .map_err(fe_err)?;
        let imported = reduce_imported(&spec, &model, &name).map_err(fe_err)?;
        let mut reduced = imported.body;
        if let ImportSource::Solid { material, mesh, .. } = &spec.source
            && b.flexible
            && self.solver.stiffening == Stiffening::Fnl1
        {
            // FNL1 of a solid: K_Gk from the stress of each mode (flexmbd_fe::solid::geometric).
            let file = mesh.display().to_string();
            reduced.stiffening.k_g = body_geometric_stiffness(
                &model,
                material,
                &reduced,
                imported.interfaces.len(),
                &file,
            )
            .map_err(fe_err)?;
        }
        let nodes = NodeRows::from_reduced(&reduced);
        let flexible = b.flexible && reduced.n_modes() > 0;
        let size = (0..nodes.len())
            .map(|k| nodes.position(k).norm())
            .fold(1.0f64, f64::max);
        let marker_nodes = self.marker_nodes(b, &nodes, size, flexible, || {
            format!(
                "a marker of an imported flexible body must sit on an interface point ({}) or \
                 an FE node",
                imported
                    .interfaces
                    .iter()
                    .map(|(n, p)| format!("{n} at [{}, {}, {}]", p.x, p.y, p.z))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })?;
        // A Buckens frame is the linearised mean axes: attached to no interface point.
        let interface_fixed = spec.reference == flexmbd_fe::ReferenceCondition::InterfaceFixed;
        let reference_node = match (&spec.frame, flexible && interface_fixed) {
            (ImportedFrame::Interface(frame), true) => {
                imported.interfaces.iter().position(|(n, _)| n == frame)
            }
            _ => None,
        };
        Ok(PreparedBody {
            index,
            body: self.run_time_body(&reduced)?,
            nodes,
            flexible,
            reduced,
            marker_nodes,
            reference_node,
            surface: imported.surface,
        })
    }

    /// The node each marker of `b` sits on (within 1e-9 of `size`, at least 1e-9 m); when
    /// `required`, a marker on no node is refused with `why`.
    fn marker_nodes(
        &self,
        b: &Body,
        nodes: &NodeRows,
        size: f64,
        required: bool,
        why: impl Fn() -> String,
    ) -> Result<Vec<Option<usize>>, ModelError> {
        b.markers
            .iter()
            .map(|m| {
                let node = nodes.node_at(&m.position.vec(), 1e-9 * size.max(1.0));
                if required && node.is_none() {
                    return Err(self.invalid(InvalidValue::new(
                        format!("bodies[{}].markers[{}].position", b.name, m.name),
                        format!("{:?}", m.position.0),
                        why(),
                    )));
                }
                Ok(node)
            })
            .collect()
    }

    /// The files the scene's imported and solid bodies read (FE exports, meshes), as the
    /// bodies are prepared: each relative to [`base_directory`](Self::base_directory).
    pub fn fe_files(&self) -> Vec<std::path::PathBuf> {
        let base = self.base_directory();
        self.bodies
            .iter()
            .filter_map(|b| match &b.model {
                BodyModel::Imported(spec) => Some(spec.source.paths()),
                _ => None,
            })
            .flatten()
            .map(|p| base.join(p))
            .collect()
    }

    /// The directory an imported body's files are relative to: the scene file's, or the
    /// working directory for a scene built in code.
    pub fn base_directory(&self) -> std::path::PathBuf {
        let origin = std::path::Path::new(&self.origin);
        match origin.parent() {
            Some(dir) if origin.is_file() => dir.to_path_buf(),
            _ => std::path::PathBuf::from("."),
        }
    }

    fn run_time_body(&self, reduced: &ReducedBody) -> Result<FlexibleBody, ModelError> {
        FlexibleBody::new(reduced).map_err(|error| self.invalid(error))
    }

    /// Install the elastic model of `solver.stiffening` on a flexible body (a no-op for rigid
    /// bodies and for `Linear`), and FS0's shortening data.
    fn install_stiffening(&self, prepared: &mut PreparedBody) -> Result<(), ModelError> {
        if !prepared.flexible || prepared.body.n_modes() == 0 {
            return Ok(());
        }
        if let Some(model) = elastic_model(self.solver.stiffening, &prepared.reduced) {
            prepared.body.set_elastic_model(model);
        }
        if self.solver.stiffening == Stiffening::Foreshortening {
            self.install_foreshortening(prepared)?;
        }
        Ok(())
    }
}

impl Scene {
    /// Install `b.inertia_terms` on its run-time body (issue 31). A truncated choice is refused
    /// by name where it has no meaning or no kernel: a body without modes, the B-matrix route
    /// (a mass cloud has no named terms) and FS0 (by the body). Both formulations drop terms
    /// (the relative set in `flexmbd_body`'s `terms.rs`, the natural set in `natural_terms.rs`).
    fn install_inertia_terms(
        &self,
        b: &Body,
        prepared: &mut PreparedBody,
    ) -> Result<(), ModelError> {
        let terms = b.inertia_terms;
        if terms.is_full() {
            return Ok(());
        }
        let field = format!("bodies[{}].inertia_terms", b.name);
        let refuse = |why: &str| Err(self.invalid(InvalidValue::new(&field, terms, why)));
        if !prepared.flexible || prepared.body.n_modes() == 0 {
            return refuse("only a flexible body has inertia terms to drop; this one runs rigid");
        }
        if self.solver.inertia == flexmbd_body::InertiaMethod::BMatrix {
            return refuse(
                "the B-matrix route sums a mass cloud and has no named terms: use \
                 solver.inertia: ShapeIntegrals to drop terms",
            );
        }
        prepared
            .body
            .set_inertia_terms(terms, &field)
            .map_err(|e| self.invalid(e))
    }
}

/// The elastic model that `stiffening` gives a reduced body (`None`: keep the body's
/// linear model; FS0 keeps it too, its stiffening is in the kinematics; a substructured
/// scene's bodies are linear).
fn elastic_model(stiffening: Stiffening, body: &ReducedBody) -> Option<Box<dyn ElasticModel>> {
    match stiffening {
        Stiffening::Fnl1 => Some(Box::new(Nonlinear::fnl1(body))),
        Stiffening::Fnl2 => Some(Box::new(Nonlinear::fnl2(body))),
        Stiffening::Linear | Stiffening::Foreshortening | Stiffening::Substructuring(_) => None,
    }
}
