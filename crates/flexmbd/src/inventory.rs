//! The mode inventory of a reduced body as printed by `flexmbd modes`, and the reduction of
//! a body-model file of either kind.

use std::path::Path;

use flexmbd_fe::imported::{ImportedBodySpec, import_body};
use flexmbd_fe::{BeamBodySpec, FeError, ModeSelection, ReducedBody, reduce};
use serde::Serialize;

/// A body model's text: a beam (`BeamBodySpec`) or an imported FE body
/// (`ImportedBodySpec`, its export's paths relative to `path`'s directory), or neither
/// (the beam parser's complaint).
pub enum BodyModelFile {
    /// A beam body.
    Beam(BeamBodySpec),
    /// An imported FE body.
    Imported(ImportedBodySpec),
}

impl BodyModelFile {
    /// Parse the text of the body-model file `path`.
    pub fn parse(text: &str, path: &Path) -> Result<Self, FeError> {
        let name = path.display().to_string();
        match BeamBodySpec::from_ron_str(text, &name) {
            Ok(spec) => Ok(BodyModelFile::Beam(spec)),
            Err(beam) => ImportedBodySpec::from_ron_str(text, &name)
                .map(BodyModelFile::Imported)
                .map_err(|_| beam),
        }
    }

    /// Reduce it (validated; an imported body's export read relative to `path`).
    pub fn reduce(&self, path: &Path) -> Result<ReducedBody, FeError> {
        match self {
            BodyModelFile::Beam(spec) => reduce(spec),
            BodyModelFile::Imported(spec) => {
                let base = path.parent().unwrap_or(Path::new("."));
                import_body(spec, base, &path.display().to_string()).map(|b| b.body)
            }
        }
    }
}

/// One static (constraint) mode: the boundary DOF it belongs to.
#[derive(Debug, Serialize)]
pub struct StaticModeRow {
    /// Mode index in **X** (0-based).
    pub index: usize,
    /// FE node of the boundary DOF (an imported body's interface point: see `interface`).
    pub node: usize,
    /// The interface whose point the node is (imported bodies only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interface: Option<String>,
    /// The DOF (`ux`, `uy`, `uz`, `rx`, `ry`, `rz`, in body axes).
    pub dof: &'static str,
}

/// One fixed-interface normal mode (or load-dependent Ritz vector, see [`Inventory::selection`]).
#[derive(Debug, Serialize)]
pub struct NormalModeRow {
    /// Mode index in **X** (0-based; normal modes follow the static ones).
    pub index: usize,
    /// Natural frequency with the boundary held fixed (Hz); the Ritz frequency of a Ritz vector.
    pub frequency_hz: f64,
}

/// A DOF taken by the floating frame.
#[derive(Debug, Serialize)]
pub struct FrameDofRow {
    /// FE node (an imported body's interface point: see `interface`).
    pub node: usize,
    /// The interface whose point the node is (imported bodies only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interface: Option<String>,
    /// The DOF.
    pub dof: &'static str,
}

/// The inventory of one body, serialised as the `--json` output of `flexmbd modes`.
#[derive(Debug, Serialize)]
pub struct Inventory {
    /// The model file it came from.
    pub model: String,
    /// `2D` or `3D`.
    pub dim: String,
    /// DOFs of the free-floating FE model.
    pub n_fe_dofs: usize,
    /// Modal coordinates n = static + normal.
    pub n_modes: usize,
    /// Total mass (kg).
    pub mass: f64,
    /// Centre of mass of the undeformed body (m, body components).
    pub center_of_mass: [f64; 3],
    /// Inertia tensor of the undeformed body about its centre of mass, body axes (kg·m²),
    /// row by row.
    pub inertia: [[f64; 3]; 3],
    /// DOFs the floating frame takes (every mode vanishes there).
    pub frame_dofs: Vec<FrameDofRow>,
    /// Static modes, in mode order.
    pub static_modes: Vec<StaticModeRow>,
    /// Normal modes, in mode order.
    pub normal_modes: Vec<NormalModeRow>,
    /// How they were chosen (`mode_selection`, docs/methods.md §1.6): `LowestFrequency`,
    /// `Participation`, `LoadRitz` (then they are load-dependent Ritz vectors) or
    /// `ProperOrthogonal` (the proper orthogonal modes of a pilot run, with Ritz frequencies).
    pub selection: &'static str,
}

impl Inventory {
    /// Collect the inventory of `body`, loaded from `model`.
    pub fn of(model: &str, body: &ReducedBody) -> Self {
        let inv = &body.inventory;
        let ns = inv.static_modes.len();
        Inventory {
            model: model.to_string(),
            dim: body.dim.to_string(),
            n_fe_dofs: inv.n_fe_dofs,
            n_modes: inv.n_modes(),
            mass: body.mass(),
            center_of_mass: body.shape_integrals.center_of_mass().into(),
            inertia: body
                .shape_integrals
                .inertia_about_center_of_mass()
                .transpose()
                .into(),
            frame_dofs: inv
                .frame_dofs
                .iter()
                .map(|d| FrameDofRow {
                    node: d.node,
                    interface: inv.point_names.get(d.node).cloned(),
                    dof: d.dof.name(),
                })
                .collect(),
            static_modes: inv
                .static_modes
                .iter()
                .enumerate()
                .map(|(index, d)| StaticModeRow {
                    index,
                    node: d.node,
                    interface: inv.point_names.get(d.node).cloned(),
                    dof: d.dof.name(),
                })
                .collect(),
            normal_modes: inv
                .normal_frequencies_hz
                .iter()
                .enumerate()
                .map(|(j, &f)| NormalModeRow {
                    index: ns + j,
                    frequency_hz: f,
                })
                .collect(),
            selection: inv.selection.name(),
        }
    }

    /// Human-readable table.
    pub fn to_text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "model        {}", self.model);
        let _ = writeln!(s, "dimension    {}", self.dim);
        let _ = writeln!(s, "FE DOFs      {}", self.n_fe_dofs);
        let _ = writeln!(s, "mass         {:.6} kg", self.mass);
        let [cx, cy, cz] = self.center_of_mass;
        let _ = writeln!(s, "centre of mass ({cx:.6}, {cy:.6}, {cz:.6}) m, body axes");
        let rows = self
            .inertia
            .map(|[a, b, c]| format!("[{a:.6e}, {b:.6e}, {c:.6e}]"));
        let _ = writeln!(s, "inertia about it (kg·m², body axes) {}", rows.join(" "));
        let frame: Vec<String> = self
            .frame_dofs
            .iter()
            .map(|d| match &d.interface {
                Some(name) => format!("{}@{name}", d.dof),
                None => format!("{}@{}", d.dof, d.node),
            })
            .collect();
        let _ = writeln!(s, "frame takes  {}", frame.join(" "));
        // Load-dependent Ritz vectors and proper orthogonal modes both carry Ritz frequencies.
        let ritz = self.selection == ModeSelection::LoadRitz.name()
            || self.selection == ModeSelection::ProperOrthogonal.name();
        let kind = if ritz { "Ritz" } else { "normal" };
        let _ = writeln!(
            s,
            "modes        {} ({} static + {} {kind})",
            self.n_modes,
            self.static_modes.len(),
            self.normal_modes.len()
        );
        if self.selection != ModeSelection::LowestFrequency.name() {
            let _ = writeln!(s, "chosen by    {} (methods.md §1.6)", self.selection);
        }
        for m in &self.static_modes {
            let _ = match &m.interface {
                Some(name) => writeln!(s, "  [{:2}] static  interface {name} {}", m.index, m.dof),
                None => writeln!(s, "  [{:2}] static  node {:3} {}", m.index, m.node, m.dof),
            };
        }
        let row = if ritz { "ritz  " } else { "normal" };
        for m in &self.normal_modes {
            let _ = writeln!(s, "  [{:2}] {row}  {:12.4} Hz", m.index, m.frequency_hz);
        }
        s
    }
}
