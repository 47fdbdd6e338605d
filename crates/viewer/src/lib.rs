//! **flexmbd-viewer** — watch a run move: a glTF 2.0 animation of a scene's run
//! ([`glb()`]) and a self-contained web page that plays it ([`page`]), what
//! `flexmbd animate` writes.
//!
//! # What is drawn
//!
//! Each body of the prepared scene is a node whose translation and rotation follow its
//! floating frame {r0, A} at each output instant ([`record()`]; the frame the sensors read,
//! `flexmbd::Simulation::body_poses`). In that frame ([`shapes`]):
//!
//! - a flexible polyline beam is a tube of its section (rectangle, circle, or the circle of
//!   a general section's area) through its FE nodes, deformed by **morph targets**: target
//!   j holds each vertex's displacement in mode j, and its weight at time t is the modal
//!   coordinate y_j(t) times the deformation scale s, so that the drawn displacement is
//!   u = s Φ y, the linear displacement field of the floating frame of reference (Shabana,
//!   *Dynamics of Multibody Systems*, 3rd ed., ch. 5; docs/methods.md §1.1). A vertex at
//!   section offset o from node P moves in mode j by X^t_P,j + X^r_P,j × o (the node's
//!   translation and small-rotation rows). For a body linear in y this is exact at the
//!   nodes. FNL1 and FNL2 stiffen the elastic forces only, so their bodies stay linear in
//!   y and are drawn exactly so; a foreshortened body (FS0) adds its axial shortening
//!   −½ ē₁ yᵀF y by morph targets weighted quadratically in y ([`quadratic`]), exact too;
//! - a beam run rigid is the same tube through its polyline's points, undeformed;
//! - a beam frame (`flexmbd::fe::frame`) is a tube of each member's section along the
//!   member's FE nodes, deformed in the same way when it runs flexible;
//! - an imported FE body with solid or shell elements is its outer surface (the faces
//!   that belong to exactly one element, `flexmbd::fe::imported::surface`): one vertex
//!   per surface node, moved in mode j by the node's translation rows X^t_P,j, so the
//!   drawn surface is exact at every vertex;
//! - any other body (rigid bodies, imported bodies without elements) is a set of sticks
//!   from the centroid of its markers to each marker, moving rigidly with its frame.
//!
//! Each joint is a sphere at its marker on its body2 (body1 when body2 is the ground),
//! moving with the FE node it sits on in a flexible body. Spring-dampers and links are grey
//! cylinders between their markers ([`springs`]); the roads the tyres roll on are strips of
//! ground under the wheels ([`roads`]); loads and tyres are not drawn. Frames are interpolated linearly
//! between output instants (positions, weights; rotations by spherical interpolation).
//! A run that fails is recorded up to its failure, which is marked in the glTF (asset
//! `extras.flexmbd`, the animation's name) and on the page.

#![warn(missing_docs)]

mod builder;
pub mod glb;
pub mod page;
pub mod quadratic;
pub mod record;
pub mod roads;
pub mod shapes;
pub mod springs;

use std::path::Path;

pub use glb::glb;
pub use record::{DEFAULT_FRAMES_PER_SECOND, Recorder, Recording, record, record_or_stop};

use flexmbd::core::Dim;
use flexmbd::model::Scene;

/// The kind of file an animation is written as, from its name's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// `.glb`: the glTF 2.0 binary.
    Glb,
    /// `.html`: the self-contained page.
    Html,
}

impl Format {
    /// The format a path's extension names (`.glb`, `.html` or `.htm`), or why not.
    pub fn of(path: &Path) -> Result<Format, String> {
        match path.extension().and_then(|e| e.to_str()) {
            Some("glb") => Ok(Format::Glb),
            Some("html" | "htm") => Ok(Format::Html),
            _ => Err(format!(
                "{}: an animation is written as .glb (glTF binary) or .html (web page)",
                path.display()
            )),
        }
    }
}

/// Check a deformation scale factor: any finite number (0 draws the bodies undeformed,
/// a negative one mirrors the deformation); NaN or infinite is refused, naming it.
pub fn check_scale(scale: f64) -> Result<f64, String> {
    if scale.is_finite() {
        Ok(scale)
    } else {
        Err(format!(
            "deformation scale {scale}: must be a finite number"
        ))
    }
}

/// The bytes of `recording` in `format`, the deformation drawn `scale` times (checked by
/// [`check_scale`]); `scene` gives the page its up direction (against gravity) and view.
pub fn render(recording: &Recording, scene: &Scene, format: Format, scale: f64) -> Vec<u8> {
    let glb = glb(recording, scale);
    match format {
        Format::Glb => glb,
        Format::Html => {
            let g = nalgebra::Vector3::from(scene.gravity.0);
            let up = if g.norm() > 0.0 {
                -g.normalize()
            } else {
                nalgebra::Vector3::y()
            };
            let view = match scene.dim {
                Dim::Planar => nalgebra::Vector3::z(),
                Dim::Spatial => {
                    let side = up.cross(&nalgebra::Vector3::x());
                    let side = if side.norm() < 1e-6 {
                        up.cross(&nalgebra::Vector3::y())
                    } else {
                        side
                    };
                    (nalgebra::Vector3::x() - 2.0 * side.normalize() + up).normalize()
                }
            };
            page::html(recording, &glb, up.into(), view.into()).into_bytes()
        }
    }
}
