//! The RON description of one flexible beam body, [`BeamBodySpec`], its loading
//! and its validation.
//!
//! It describes the FE model of docs/methods.md §1.2 (Euler–Bernoulli beams on a
//! polyline, element axes from the orientation vector k̄), the reference
//! conditions of §1.4 (clamped node or 2D pinned–roller chord frame), the
//! Craig–Bampton boundary set and number of normal modes of §1.3, and the
//! damping choice of §1.5. Units are SI throughout.
//!
//! ```ron
//! (
//!     dim: Planar,
//!     material: (young_modulus: 2.1e11, density: 7850.0, poisson_ratio: Some(0.3)),
//!     section: Rectangle(width: 0.01, height: 0.01),
//!     geometry: (points: [[0.0, 0.0], [1.0, 0.0]], elements_per_segment: 20),
//!     frame: Clamped(node: 0),
//!     boundary: [(node: 20, dof: Uy)],
//!     normal_modes: 4,
//!     damping: None,
//! )
//! ```
//!
//! A scene format embeds this struct; [`BeamBodySpec::validate`] refuses a
//! non-physical or inconsistent model with the field path and value
//! ([`flexmbd_core::InvalidValue`]).

use std::collections::HashSet;
use std::path::Path;

use flexmbd_core::{Dim, InvalidValue};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::assembly::dof_slot;
use crate::bounds::{self, MAX_FE_DOFS};
use crate::error::FeError;
use crate::reduced::{Dof, NodeDof};
use crate::section::check_section;
pub use crate::section::{Section, SectionProps};
use crate::selection::ModeSelection;

/// Material constants (SI).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub young_modulus: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
    /// Poisson ratio ν; G = E / (2 (1 + ν)). Give this or `shear_modulus` (3D needs one).
    #[serde(default)]
    pub poisson_ratio: Option<f64>,
    /// Shear modulus G (Pa), used for torsion (3D only).
    #[serde(default)]
    pub shear_modulus: Option<f64>,
}

/// Geometry: a polyline in body components, each segment split into equal elements, or a
/// beam frame of named nodes and members ([`crate::frame`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    /// Polyline points (m), body components: `[x, y]` in 2D, `[x, y, z]` in 3D.
    /// Node 0 is the first point; nodes are numbered along the polyline. Empty for a frame.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub points: Vec<Vec<f64>>,
    /// Elements per segment (≥ 1); for a frame, per member that gives no count.
    pub elements_per_segment: usize,
    /// Orientation vector k̄ (body components) that fixes the element axes:
    /// y_e = k̄ × x_e / |k̄ × x_e|, z_e = x_e × y_e (docs/methods.md §1.2). Default ē₃
    /// (ē₂ for an element parallel to ē₃). In 2D only +ē₃ is allowed.
    #[serde(default)]
    pub orientation: Option<[f64; 3]>,
    /// A frame's named nodes (node k is `nodes[k]`), instead of `points`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub nodes: Vec<crate::frame::FrameNode>,
    /// A frame's members between named nodes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub members: Vec<crate::frame::Member>,
}

impl Geometry {
    /// A beam frame (nodes and members) rather than a polyline.
    pub fn is_frame(&self) -> bool {
        !self.nodes.is_empty() || !self.members.is_empty()
    }
}

/// Reference conditions: which DOFs the floating frame takes (docs/methods.md §1.4).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ReferenceFrame {
    /// Clamped reference node: r = all DOFs of `node` (default node 0). The frame
    /// is rigidly attached to that node's cross-section.
    Clamped {
        /// The reference node.
        #[serde(default)]
        node: usize,
    },
    /// 2D pinned–roller chord frame: r = {u_A, v_A, v_B}; the x axis passes
    /// through nodes A and B, which must lie on the body x axis direction.
    Chord {
        /// Pinned node A.
        a: usize,
        /// Roller node B.
        b: usize,
    },
    /// Expert: an explicit r set. It must be an isostatic support, otherwise the
    /// reduction is refused.
    Dofs(Vec<NodeDof>),
}

impl Default for ReferenceFrame {
    fn default() -> Self {
        ReferenceFrame::Clamped { node: 0 }
    }
}

/// Damping choice (docs/methods.md §1.5). Mass-proportional damping is deliberately absent.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Damping {
    /// No damping: C_ff = 0.
    #[default]
    None,
    /// C_ff = a_K K_ff.
    StiffnessProportional {
        /// a_K (s).
        a_k: f64,
    },
    /// Modal ratio ζ on the normal modes (C_jj = 2 ζ ω_j) and a_K on the static block.
    ModalRatio {
        /// Damping ratio ζ of every normal mode.
        zeta: f64,
        /// a_K (s) applied to the static-mode block K̂_bb.
        a_k_static: f64,
    },
}

/// One flexible beam body, as written in RON.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamBodySpec {
    /// Planar (x–y plane, DOFs u, v, θ per node) or spatial (6 DOFs per node).
    pub dim: Dim,
    /// Material.
    pub material: Material,
    /// Cross-section.
    pub section: Section,
    /// Polyline and mesh.
    pub geometry: Geometry,
    /// Reference conditions (default `Clamped(node: 0)`).
    #[serde(default)]
    pub frame: ReferenceFrame,
    /// The floating frame's reference condition (default `InterfaceFixed`: the modes vanish
    /// on `frame`'s DOFs; `Buckens`: they are made M-orthogonal to the rigid-body motions,
    /// [`crate::reference`]).
    #[serde(default)]
    pub reference: crate::ReferenceCondition,
    /// Boundary DOFs: one static mode each, in this order (docs/methods.md §1.3–§1.4).
    #[serde(default)]
    pub boundary: Vec<NodeDof>,
    /// Number of fixed-interface normal modes n_d.
    pub normal_modes: usize,
    /// Purely axial normal modes kept in addition (geometric stiffening, docs/methods.md §6;
    /// docs/scenes.md §5 "4 bending + 2 axial"). When > 0, `normal_modes` counts the lowest
    /// modes that are not purely axial, and the lowest `axial_modes` purely axial ones
    /// (only Ux rows, i.e. a beam along body x) are added; normal modes stay in
    /// ascending frequency. 0 (default): the `normal_modes` lowest modes of any kind.
    #[serde(default)]
    pub axial_modes: usize,
    /// Which vectors make the dynamic basis (docs/methods.md §1.6): the lowest normal modes
    /// (default), those the body's loads excite most, or load-dependent Ritz vectors;
    /// `normal_modes` counts them either way.
    #[serde(default)]
    pub mode_selection: ModeSelection,
    /// With `mode_selection: Participation`: rank the lowest this many (non-axial) normal
    /// modes (default: all of them). With `ProperOrthogonal`: the pilot run's basis, the
    /// lowest this many (non-axial) normal modes (default [`crate::pod::candidate_count`]:
    /// max(2 `normal_modes`, 4), at most the interior DOFs left after the axial modes).
    #[serde(default)]
    pub mode_candidates: Option<usize>,
    /// With `mode_selection: ProperOrthogonal`: how long the pilot run is (s; default:
    /// [`crate::pod::DEFAULT_PILOT_FRACTION`] of the scene's duration; never longer than the
    /// scene).
    #[serde(default)]
    pub pilot_duration: Option<f64>,
    /// With `mode_selection: ProperOrthogonal`: the modal coordinates the pilot run recorded
    /// (set by the facade that runs the pilot, `flexmbd::pilot`; never read from RON).
    #[serde(skip)]
    pub pilot: Option<std::sync::Arc<crate::pod::PilotRecord>>,
    /// Damping (default `None`).
    #[serde(default)]
    pub damping: Damping,
    /// Where this spec came from (file name or the origin given to
    /// [`BeamBodySpec::from_ron_str`]); used to name the spec in errors.
    #[serde(skip)]
    pub origin: String,
}

impl BeamBodySpec {
    /// A straight beam along body x from the origin: `length` (m) in `elements` equal
    /// elements, its frame clamped at node 0, no static modes and no normal modes yet (set
    /// `boundary` and `normal_modes`), no damping. For scenes built in code; not validated.
    pub fn straight(
        dim: Dim,
        material: Material,
        section: Section,
        length: f64,
        elements: usize,
    ) -> Self {
        let end = match dim {
            Dim::Planar => vec![length, 0.0],
            Dim::Spatial => vec![length, 0.0, 0.0],
        };
        let start = vec![0.0; end.len()];
        BeamBodySpec {
            dim,
            material,
            section,
            geometry: Geometry {
                points: vec![start, end],
                elements_per_segment: elements,
                orientation: None,
                nodes: Vec::new(),
                members: Vec::new(),
            },
            frame: ReferenceFrame::Clamped { node: 0 },
            reference: crate::ReferenceCondition::InterfaceFixed,
            boundary: Vec::new(),
            normal_modes: 0,
            axial_modes: 0,
            mode_selection: ModeSelection::LowestFrequency,
            mode_candidates: None,
            pilot_duration: None,
            pilot: None,
            damping: Damping::None,
            origin: String::new(),
        }
    }

    /// Parse a spec from RON text. `origin_name` (a file name or a label) is
    /// named in parse errors and kept in [`BeamBodySpec::origin`].
    /// The spec is **not** validated here; call [`BeamBodySpec::validate`].
    pub fn from_ron_str(text: &str, origin_name: &str) -> Result<Self, FeError> {
        let mut spec: BeamBodySpec = ron::from_str(text).map_err(|e| FeError::Parse {
            file: origin_name.to_string(),
            line: e.span.start.line,
            column: e.span.start.col,
            message: e.code.to_string(),
        })?;
        spec.origin = origin_name.to_string();
        Ok(spec)
    }

    /// Read and parse a spec from a RON file (not validated).
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self, FeError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| FeError::Io {
            file: name.clone(),
            source,
        })?;
        Self::from_ron_str(&text, &name)
    }

    /// Number of DOFs per node: 3 (2D) or 6 (3D).
    pub fn dofs_per_node(&self) -> usize {
        self.dim.n_rigid()
    }

    /// Number of FE nodes of the mesh.
    pub fn n_nodes(&self) -> usize {
        if self.geometry.is_frame() {
            return crate::frame::frame_node_count(self);
        }
        let segs = self.geometry.points.len().saturating_sub(1);
        segs.saturating_mul(self.geometry.elements_per_segment)
            .saturating_add(1)
    }

    /// Number of DOFs N of the free-floating FE model.
    pub fn n_fe_dofs(&self) -> usize {
        self.n_nodes().saturating_mul(self.dofs_per_node())
    }

    /// The reference (r) DOFs implied by [`BeamBodySpec::frame`], in order.
    pub fn frame_dofs(&self) -> Vec<NodeDof> {
        match &self.frame {
            ReferenceFrame::Clamped { node } => node_dofs(self.dim)
                .iter()
                .map(|&dof| NodeDof { node: *node, dof })
                .collect(),
            ReferenceFrame::Chord { a, b } => vec![
                NodeDof {
                    node: *a,
                    dof: Dof::Ux,
                },
                NodeDof {
                    node: *a,
                    dof: Dof::Uy,
                },
                NodeDof {
                    node: *b,
                    dof: Dof::Uy,
                },
            ],
            ReferenceFrame::Dofs(d) => d.clone(),
        }
    }

    /// Shear modulus G: `shear_modulus`, else E / (2 (1 + ν)), else (2D only, unused) E / 2.6.
    pub fn shear_modulus(&self) -> f64 {
        let m = &self.material;
        match (m.shear_modulus, m.poisson_ratio) {
            (Some(g), _) => g,
            (None, Some(nu)) => m.young_modulus / (2.0 * (1.0 + nu)),
            (None, None) => m.young_modulus / 2.6,
        }
    }

    /// A polyline point as a 3-vector (2D points get z = 0).
    pub fn point(&self, i: usize) -> Vector3<f64> {
        let p = &self.geometry.points[i];
        Vector3::new(
            p.first().copied().unwrap_or(0.0),
            p.get(1).copied().unwrap_or(0.0),
            p.get(2).copied().unwrap_or(0.0),
        )
    }

    /// Check the spec; refuses with the field path and value of the first problem found.
    pub fn validate(&self) -> Result<(), FeError> {
        self.validate_inner().map_err(FeError::Invalid)
    }

    /// The checks of [`BeamBodySpec::validate`], one part of the spec at a time in
    /// the order of its fields. The order matters: the frame and boundary checks
    /// use the mesh (node count, node positions) and the orientation check the
    /// segment directions, which only exist once the geometry has passed.
    fn validate_inner(&self) -> Result<(), InvalidValue> {
        self.check_material()?;
        check_section(&self.section, "section")?;
        if self.geometry.is_frame() {
            crate::frame::check_frame_geometry(self, check_section)?;
        } else {
            self.check_polyline()?;
            self.check_elements_per_segment()?;
            self.check_orientation()?;
        }
        self.check_frame()?;
        self.check_boundary()?;
        self.check_normal_modes()?;
        crate::selection::check(self)?;
        self.check_damping()
    }

    /// E and ρ positive and in range ([`bounds`]); at most one of ν and G, each in its physical range; a 3D
    /// beam needs one of them for its torsion stiffness.
    fn check_material(&self) -> Result<(), InvalidValue> {
        let m = &self.material;
        bounds::MODULUS.check("material.young_modulus", m.young_modulus)?;
        bounds::DENSITY.check("material.density", m.density)?;
        if m.poisson_ratio.is_some() && m.shear_modulus.is_some() {
            return Err(InvalidValue::new(
                "material.shear_modulus",
                m.shear_modulus.unwrap_or_default(),
                "give either poisson_ratio or shear_modulus, not both",
            ));
        }
        if let Some(nu) = m.poisson_ratio
            && !(nu.is_finite() && nu > -1.0 && nu <= 0.5)
        {
            return Err(InvalidValue::new(
                "material.poisson_ratio",
                nu,
                "must be finite and in (-1, 0.5]",
            ));
        }
        if let Some(g) = m.shear_modulus {
            bounds::MODULUS.check("material.shear_modulus", g)?;
        }
        if self.dim == Dim::Spatial && m.poisson_ratio.is_none() && m.shear_modulus.is_none() {
            return Err(InvalidValue::new(
                "material.shear_modulus",
                "None",
                "a 3D beam needs poisson_ratio or shear_modulus (torsion)",
            ));
        }
        Ok(())
    }

    /// At least two points, each with as many components as the dimension has
    /// translations, each in [`bounds::POSITION`], and no zero-length segment (its element axes and
    /// lengths would be undefined).
    fn check_polyline(&self) -> Result<(), InvalidValue> {
        let points = &self.geometry.points;
        if points.len() < 2 {
            return Err(InvalidValue::new(
                "geometry.points",
                format!("{} point(s)", points.len()),
                "a polyline needs at least 2 points",
            ));
        }
        let want = self.dim.n_trans();
        for (i, p) in points.iter().enumerate() {
            let field = format!("geometry.points[{i}]");
            if p.len() != want {
                return Err(InvalidValue::new(
                    field,
                    format!("{p:?}"),
                    format!("a {} point has {want} components", self.dim),
                ));
            }
            bounds::POSITION.check_all(&field, p)?;
        }
        for i in 1..points.len() {
            let len = (self.point(i) - self.point(i - 1)).norm();
            if len.is_nan() || len <= 0.0 {
                return Err(InvalidValue::new(
                    format!("geometry.points[{i}]"),
                    format!("{:?} (segment length {len})", points[i]),
                    format!(
                        "segment {} has zero length: points[{i}] coincides with points[{}]",
                        i - 1,
                        i - 1
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Each segment is split into at least one element, no element shorter than
    /// [`bounds::ELEMENT_LENGTH`], and the mesh has at most [`MAX_FE_DOFS`] DOFs (the
    /// refusal states the memory it would need, counted without overflow).
    fn check_elements_per_segment(&self) -> Result<(), InvalidValue> {
        let per = self.geometry.elements_per_segment;
        let field = "geometry.elements_per_segment";
        if per == 0 {
            return Err(InvalidValue::new(field, 0, "must be at least 1"));
        }
        let segments = self.geometry.points.len() - 1;
        let dofs = (segments as u128 * per as u128 + 1) * self.dofs_per_node() as u128;
        if dofs > MAX_FE_DOFS as u128 {
            return Err(InvalidValue::new(
                field,
                per,
                format!(
                    "too large: {segments} segment(s) × {per} elements give {dofs} FE DOFs; {}",
                    bounds::too_many_dofs(dofs)
                ),
            ));
        }
        for i in 1..self.geometry.points.len() {
            let len = (self.point(i) - self.point(i - 1)).norm() / per as f64;
            if !bounds::ELEMENT_LENGTH.contains(len) {
                return Err(InvalidValue::new(
                    field,
                    per,
                    format!(
                        "segment {} gives elements {len:e} m long: allowed {}",
                        i - 1,
                        bounds::ELEMENT_LENGTH
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The orientation vector k̄, when given, is finite, in range and non-zero; in 2D it is
    /// +ē₃ (the element axes of a planar beam are fixed), in 3D it is parallel to
    /// no segment (y_e = k̄ × x_e would vanish).
    fn check_orientation(&self) -> Result<(), InvalidValue> {
        let Some(k) = self.geometry.orientation else {
            return Ok(());
        };
        bounds::AXIS_COMPONENT.check_all("geometry.orientation", &k)?;
        let kv = Vector3::from(k);
        let kval = format!("{k:?}");
        if kv.norm() < bounds::MIN_AXIS_NORM {
            return Err(InvalidValue::new(
                "geometry.orientation",
                kval,
                format!(
                    "must be a non-zero vector (norm at least {:e})",
                    bounds::MIN_AXIS_NORM
                ),
            ));
        }
        match self.dim {
            Dim::Planar => {
                if kv.x != 0.0 || kv.y != 0.0 || kv.z <= 0.0 {
                    return Err(InvalidValue::new(
                        "geometry.orientation",
                        kval,
                        "in 2D the element axes are fixed by k = +e3; omit it or give [0, 0, 1]",
                    ));
                }
            }
            Dim::Spatial => {
                for i in 1..self.geometry.points.len() {
                    let x = (self.point(i) - self.point(i - 1)).normalize();
                    if kv.normalize().cross(&x).norm() < 1e-9 {
                        return Err(InvalidValue::new(
                            "geometry.orientation",
                            kval,
                            format!("is parallel to segment {}; element axes undefined", i - 1),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// `node` (named `field` in the error) is a node of the mesh.
    fn check_node(&self, field: &str, node: usize) -> Result<(), InvalidValue> {
        let n_nodes = self.n_nodes();
        if node >= n_nodes {
            Err(InvalidValue::new(
                field,
                node,
                format!("no such node (the mesh has nodes 0..{})", n_nodes - 1),
            ))
        } else {
            Ok(())
        }
    }

    /// The reference conditions name nodes of the mesh and DOFs of its nodes, take no
    /// DOF twice, and an explicit r set takes no more DOFs than the rigid-body motions
    /// (a hyperstatic frame; fewer are refused by the reduction, docs/methods.md §1.4).
    fn check_frame(&self) -> Result<(), InvalidValue> {
        match &self.frame {
            ReferenceFrame::Clamped { node } => self.check_node("frame.node", *node)?,
            ReferenceFrame::Chord { a, b } => self.check_chord(*a, *b)?,
            ReferenceFrame::Dofs(d) => {
                let rigid = self.dim.n_rigid();
                if d.len() > rigid {
                    return Err(InvalidValue::new(
                        "frame.Dofs",
                        format!("{} DOFs", d.len()),
                        format!(
                            "hyperstatic: an isostatic support takes exactly the {rigid} \
                             rigid-body DOFs of a {} body (methods.md §1.4)",
                            self.dim
                        ),
                    ));
                }
                for (k, nd) in d.iter().enumerate() {
                    self.check_node(&format!("frame.dofs[{k}].node"), nd.node)?;
                    if dof_slot(self.dim, nd.dof).is_none() {
                        return Err(InvalidValue::new(
                            format!("frame.dofs[{k}].dof"),
                            format!("{:?}", nd.dof),
                            format!("not a DOF of a {} beam node", self.dim),
                        ));
                    }
                }
            }
        }
        let frame = self.frame_dofs();
        let frame_set: HashSet<NodeDof> = frame.iter().copied().collect();
        if frame_set.len() != frame.len() {
            return Err(InvalidValue::new(
                "frame",
                format!("{:?}", self.frame),
                "repeats a DOF",
            ));
        }
        Ok(())
    }

    /// The chord frame's nodes A and B exist and differ; in 2D they lie on a line
    /// parallel to body x, since the roller at B takes the body-y DOF v_B.
    fn check_chord(&self, a: usize, b: usize) -> Result<(), InvalidValue> {
        self.check_node("frame.a", a)?;
        self.check_node("frame.b", b)?;
        if a == b {
            return Err(InvalidValue::new(
                "frame.b",
                b,
                "the chord needs two different nodes",
            ));
        }
        if self.dim == Dim::Planar {
            let pa = crate::assembly::node_position(self, a);
            let pb = crate::assembly::node_position(self, b);
            let d = pb - pa;
            if d.y.abs() > 1e-12 * d.norm() {
                return Err(InvalidValue::new(
                    "frame.b",
                    b,
                    "nodes A and B of the chord frame must lie on a line parallel to body x \
                     (v_B is the body-y DOF of B)",
                ));
            }
        }
        Ok(())
    }

    /// Each boundary DOF is a DOF of a mesh node, given once, and not a frame DOF
    /// (every mode vanishes on the frame DOFs, so its static mode would be zero).
    fn check_boundary(&self) -> Result<(), InvalidValue> {
        let frame_set: HashSet<NodeDof> = self.frame_dofs().into_iter().collect();
        let mut seen = HashSet::new();
        for (k, nd) in self.boundary.iter().enumerate() {
            self.check_node(&format!("boundary[{k}].node"), nd.node)?;
            if dof_slot(self.dim, nd.dof).is_none() {
                return Err(InvalidValue::new(
                    format!("boundary[{k}].dof"),
                    format!("{:?}", nd.dof),
                    format!(
                        "not a DOF of a {} beam node (2D nodes have Ux, Uy, Rz)",
                        self.dim
                    ),
                ));
            }
            if !seen.insert(*nd) {
                return Err(InvalidValue::new(
                    format!("boundary[{k}]"),
                    format!("(node: {}, dof: {:?})", nd.node, nd.dof),
                    "duplicate boundary DOF",
                ));
            }
            if frame_set.contains(nd) {
                return Err(InvalidValue::new(
                    format!("boundary[{k}]"),
                    format!("(node: {}, dof: {:?})", nd.node, nd.dof),
                    "is a frame (reference) DOF; every mode vanishes there",
                ));
            }
        }
        Ok(())
    }

    /// No more normal modes (`normal_modes`, then `normal_modes + axial_modes`) than
    /// interior DOFs (those neither frame nor boundary); each refusal names its own field.
    fn check_normal_modes(&self) -> Result<(), InvalidValue> {
        let interior = self
            .n_fe_dofs()
            .saturating_sub(self.frame_dofs().len() + self.boundary.len());
        if self.normal_modes > interior {
            return Err(InvalidValue::new(
                "normal_modes",
                self.normal_modes,
                format!("the model has only {interior} interior DOFs"),
            ));
        }
        if self.axial_modes > interior - self.normal_modes {
            return Err(InvalidValue::new(
                "axial_modes",
                self.axial_modes,
                format!(
                    "the model has {interior} interior DOFs, {} of them left after the {} \
                     normal modes",
                    interior - self.normal_modes,
                    self.normal_modes
                ),
            ));
        }
        Ok(())
    }

    /// Damping coefficients non-negative and in range ([`bounds`]).
    fn check_damping(&self) -> Result<(), InvalidValue> {
        match self.damping {
            Damping::None => {}
            Damping::StiffnessProportional { a_k } => {
                bounds::DAMPING_COEFFICIENT.check("damping.a_k", a_k)?;
            }
            Damping::ModalRatio { zeta, a_k_static } => {
                bounds::DAMPING_RATIO.check("damping.zeta", zeta)?;
                bounds::DAMPING_COEFFICIENT.check("damping.a_k_static", a_k_static)?;
            }
        }
        Ok(())
    }
}

/// The DOFs of one node, in storage order: 2D (Ux, Uy, Rz), 3D (Ux, Uy, Uz, Rx, Ry, Rz).
pub fn node_dofs(dim: Dim) -> &'static [Dof] {
    match dim {
        Dim::Planar => &[Dof::Ux, Dof::Uy, Dof::Rz],
        Dim::Spatial => &[Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz],
    }
}
