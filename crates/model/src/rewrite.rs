//! The scene rewrites a stiffening method asks for (thesis ch. 4; docs/methods.md §6), done once
//! by [`PreparedScene::new`](crate::PreparedScene::new) before any formulation sees the scene:
//!
//! - FNL2 ([`complete_axial_basis`]): a static mode (Craig–Bampton boundary DOF) for the axial
//!   DOF `Ux` of every node but the frame node of every flexible straight beam along body x,
//!   `axial_modes` set to 0 (§6.2 correction: FNL2 locks without the complete axial basis). The
//!   modal-coordinate count changes; `Modal` sensors are re-pointed to the same mode (normal
//!   modes move behind the added static modes), or refused when the original basis had axial
//!   normal modes.
//! - FS0 ([`drop_axial_modes`], §6.3): no axial modes on any flexible beam; its frame must be
//!   clamped at the root node 0.
//! - Substructuring SBn ([`substructure`], §6.4): every flexible straight beam becomes n
//!   linear substructures joined by `Rigid` (bracket) joints.

use std::borrow::Cow;

use flexmbd_fe::{BeamBodySpec, Dof, NodeDof, ReferenceFrame};
use nalgebra::Vector3;

use crate::error::ModelError;
use crate::scene::{
    Body, BodyModel, FormulationKind, Joint, JointKind, Marker, Scene, SensorKind, Stiffening, V3,
};

pub(crate) fn refuse_fs0(scene: &Scene, what: String) -> ModelError {
    ModelError::Unsupported(format!("{}: foreshortening (FS0): {what}", scene.origin))
}

/// The scene to compile for its stiffening choice: FNL2 completes the axial basis of
/// flexible straight beams; FS0 drops the axial modes; SBn splits every flexible beam.
pub fn rewrite_for_stiffening(scene: &Scene) -> Result<Cow<'_, Scene>, ModelError> {
    match scene.solver.stiffening {
        Stiffening::Linear | Stiffening::Fnl1 => Ok(Cow::Borrowed(scene)),
        Stiffening::Fnl2 => complete_axial_basis(scene).map(Cow::Owned),
        Stiffening::Foreshortening => drop_axial_modes(scene).map(Cow::Owned),
        Stiffening::Substructuring(n) => substructure(scene, n).map(Cow::Owned),
    }
}

/// FNL2's axial basis (docs/methods.md §6.2 correction): every node's `Ux` but the frame
/// node's becomes a static mode of every flexible beam (straight, along body x,
/// clamped frame).
pub fn complete_axial_basis(scene: &Scene) -> Result<Scene, ModelError> {
    let mut out = scene.clone();
    for (name, spec) in flexible_beams(&mut out.bodies) {
        let straight = !spec.geometry.is_frame()
            && spec
                .geometry
                .points
                .iter()
                .all(|p| p.iter().skip(1).all(|c| *c == 0.0));
        let ReferenceFrame::Clamped { node: frame } = spec.frame else {
            return Err(ModelError::Unsupported(format!(
                "{}: body `{}`: FNL2 needs a clamped frame (methods.md §6)",
                scene.origin, name
            )));
        };
        if !straight {
            return Err(ModelError::Unsupported(format!(
                "{}: body `{}`: FNL2 needs a straight beam along body x (methods.md §6)",
                scene.origin, name
            )));
        }
        // The axial normal modes are replaced by the complete static basis.
        let (n_static, had_axial) = (spec.boundary.len(), spec.axial_modes > 0);
        spec.axial_modes = 0;
        for node in 0..spec.n_nodes() {
            let nd = NodeDof { node, dof: Dof::Ux };
            if node != frame && !spec.boundary.contains(&nd) {
                spec.boundary.push(nd);
            }
        }
        let added = spec.boundary.len() - n_static;
        // Modal sensors keep naming the same mode: static modes keep their index, normal
        // modes move behind the added static modes. With axial normal modes in the original
        // basis (interleaved with the bending ones by frequency) the map needs the
        // eigen-solution, so such sensors are refused rather than silently re-pointed.
        for sensor in out.sensors.iter_mut() {
            let SensorKind::Modal { body, index } = &mut sensor.kind else {
                continue;
            };
            if body != name || *index < n_static {
                continue;
            }
            if had_axial {
                return Err(ModelError::Unsupported(format!(
                    "{}: sensor `{}`: modal index {} of body `{}` names a normal mode, and FNL2 \
                     replaces that body's axial modes (axial_modes > 0) by static modes, so the \
                     normal modes are renumbered; use a Position sensor or run without axial_modes",
                    scene.origin, sensor.name, index, name
                )));
            }
            *index += added;
        }
    }
    Ok(out)
}

/// Every flexible beam of `bodies`, by name, its spec open to the rewrite.
fn flexible_beams(bodies: &mut [Body]) -> impl Iterator<Item = (&str, &mut BeamBodySpec)> {
    bodies.iter_mut().filter_map(|b| match &mut b.model {
        BodyModel::Beam(spec) if b.flexible => Some((b.name.as_str(), spec)),
        _ => None,
    })
}

/// Substructuring SBn (methods.md §6.4, scenes.md §5): every flexible beam (straight along
/// body x, frame clamped at node 0, one segment) becomes n bodies `{name}_1` …
/// `{name}_n`, each a 2-element beam (whatever the original mesh; markers must sit on
/// the new nodes), frame clamped at its inner node, static modes of
/// every DOF of its outer node (2D: u, v, θ; 3D: 6) and one fixed-interface mode per
/// bending plane (3D: 2), linear elasticity; consecutive bodies are joined by `Rigid`
/// joints `{name}_bracket_k` between `outer` and `inner` markers. Markers, joints and
/// sensors naming the beam move to the substructure that holds the point (the root to
/// the first, a point on an interface to the inner end of the outer body, the tip to the
/// last); a sensor frame naming the beam becomes the first substructure's frame, which is
/// the beam's floating frame. `Modal` sensors and initial modes of a split beam are refused.
pub fn substructure(scene: &Scene, n: usize) -> Result<Scene, ModelError> {
    check_substructuring(scene, n)?;
    let mut out = scene.clone();
    out.solver.stiffening = Stiffening::Linear;
    out.bodies.clear();
    out.joints = scene.joints.clone();
    let mut split = SplitBeams::default();
    for b in &scene.bodies {
        match &b.model {
            BodyModel::Beam(spec) if b.flexible => {
                check_splittable_beam(scene, b, spec)?;
                split_beam(b, spec, n, &mut out, &mut split);
            }
            _ => out.bodies.push(b.clone()),
        }
    }
    repoint_to_substructures(scene, &mut out, &split)?;
    Ok(out)
}

/// Elements of each substructure's mesh (docs/methods.md §6.4 prototype, docs/scenes.md §5).
const SUBSTRUCTURE_ELEMENTS: usize = 2;

/// Substructuring cannot rewrite this scene: `what` says why, after the file name.
fn refuse_substructuring(scene: &Scene, what: String) -> ModelError {
    ModelError::Unsupported(format!("{}: {what}", scene.origin))
}

/// SBn as a whole: at least one substructure, and the relative formulation (the only
/// one that joins substructures by `Rigid` brackets).
fn check_substructuring(scene: &Scene, n: usize) -> Result<(), ModelError> {
    if n == 0 {
        return Err(refuse_substructuring(
            scene,
            "substructuring needs n ≥ 1 substructures".into(),
        ));
    }
    if scene.solver.formulation != FormulationKind::Relative {
        return Err(refuse_substructuring(
            scene,
            format!(
                "substructuring SB{n} runs in the relative formulation only (methods.md §6.4); \
                 use --formulation relative"
            ),
        ));
    }
    Ok(())
}

/// A flexible beam can be split only if it is one straight segment from the origin along
/// body x, with its frame clamped at node 0, and has no initial modes (they would not
/// map onto the substructures' bases).
fn check_splittable_beam(scene: &Scene, b: &Body, spec: &BeamBodySpec) -> Result<(), ModelError> {
    let pts = &spec.geometry.points;
    let straight = pts.len() == 2
        && pts[0].iter().all(|c| *c == 0.0)
        && pts[1].iter().skip(1).all(|c| *c == 0.0)
        && pts[1][0] > 0.0;
    if !straight || spec.frame != (ReferenceFrame::Clamped { node: 0 }) {
        return Err(refuse_substructuring(
            scene,
            format!(
                "body `{}`: substructuring needs a straight beam from the origin along body x \
                 with its frame clamped at node 0",
                b.name
            ),
        ));
    }
    if !b.initial_modes.is_empty() {
        return Err(refuse_substructuring(
            scene,
            format!(
                "body `{}`: initial modes of a split beam are not supported",
                b.name
            ),
        ));
    }
    Ok(())
}

/// Where the split beams' markers went, to re-point what named them.
#[derive(Default)]
struct SplitBeams {
    /// (old body, old marker) → (new body, new marker name).
    moved: Vec<(String, String, String, String)>,
    /// (split beam, its first substructure).
    first_of: Vec<(String, String)>,
}

impl SplitBeams {
    /// Re-point a (body, marker) pair to the substructure that now holds the marker.
    fn remap(&self, body: &mut String, marker: &mut String) {
        if let Some((_, _, nb, nm)) = self
            .moved
            .iter()
            .find(|(ob, om, _, _)| ob == body && om == marker)
        {
            *body = nb.clone();
            *marker = nm.clone();
        }
    }

    /// A frame naming a split beam becomes its first substructure's frame, which is the
    /// beam's floating frame.
    fn remap_frame(&self, frame: &mut Option<String>) {
        if let Some(name) = frame
            && let Some((_, first)) = self.first_of.iter().find(|(o, _)| o == name)
        {
            *name = first.clone();
        }
    }

    /// Whether `body` is a beam that was split (its name no longer exists).
    fn is_split(&self, body: &str) -> bool {
        self.first_of.iter().any(|(o, _)| o == body)
    }
}

/// Name of substructure `k` (0-based) of beam `b`: `{name}_{k+1}`.
fn substructure_name(b: &Body, k: usize) -> String {
    format!("{}_{}", b.name, k + 1)
}

/// Replace beam `b` in `out` by its `n` substructures, joined by `Rigid` brackets, and
/// record in `split` where its markers went.
fn split_beam(b: &Body, spec: &BeamBodySpec, n: usize, out: &mut Scene, split: &mut SplitBeams) {
    split
        .first_of
        .push((b.name.clone(), substructure_name(b, 0)));
    for k in 0..n {
        out.bodies
            .push(substructure_body(b, spec, n, k, &mut split.moved));
        if k > 0 {
            out.joints.push(bracket(b, k));
        }
    }
}

/// Substructure `k` of the `n` of beam `b`: a 2-element beam of length L/n, placed and
/// moving as that stretch of the original beam, holding the beam's markers on it.
fn substructure_body(
    b: &Body,
    spec: &BeamBodySpec,
    n: usize,
    k: usize,
    moved: &mut Vec<(String, String, String, String)>,
) -> Body {
    let ls = spec.geometry.points[1][0] / n as f64;
    let offset = b.orientation.matrix() * Vector3::new(k as f64 * ls, 0.0, 0.0);
    let w = b.velocity.angular.vec();
    let mut velocity = b.velocity.clone();
    velocity.linear = V3((b.velocity.linear.vec() + w.cross(&offset)).into());
    Body {
        name: substructure_name(b, k),
        origin: V3((b.origin.vec() + offset).into()),
        orientation: b.orientation.clone(),
        model: BodyModel::Beam(substructure_spec(spec, ls)),
        flexible: true,
        markers: substructure_markers(b, n, k, ls, moved),
        velocity,
        initial_modes: Vec::new(),
        inertia_terms: b.inertia_terms,
    }
}

/// A substructure's beam spec: length `ls`, 2 elements, frame clamped at its inner node,
/// static modes of every DOF of its outer node (2D: u, v, θ; 3D: 6), one fixed-interface
/// mode per bending plane (the lowest), no axial modes.
fn substructure_spec(spec: &BeamBodySpec, ls: f64) -> BeamBodySpec {
    let planar = spec.dim == flexmbd_core::Dim::Planar;
    let dofs: &[Dof] = if planar {
        &[Dof::Ux, Dof::Uy, Dof::Rz]
    } else {
        &[Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz]
    };
    let point = |x: f64| -> Vec<f64> {
        if planar {
            vec![x, 0.0]
        } else {
            vec![x, 0.0, 0.0]
        }
    };
    let per = SUBSTRUCTURE_ELEMENTS;
    let mut sub = spec.clone();
    sub.geometry.points = vec![point(0.0), point(ls)];
    sub.geometry.elements_per_segment = per;
    sub.boundary = dofs.iter().map(|&dof| NodeDof { node: per, dof }).collect();
    sub.normal_modes = if planar { 1 } else { 2 };
    sub.axial_modes = 0;
    // SBn's bodies have their own basis: the lowest modes, whatever the beam chose.
    sub.mode_selection = flexmbd_fe::ModeSelection::LowestFrequency;
    sub.mode_candidates = None;
    sub
}

/// Substructure `k`'s markers: `inner` and `outer` (for the brackets), then those of
/// beam `b`'s markers that lie on it (a point on an interface goes to the inner end of
/// the outer substructure, the tip to the last), each recorded in `moved`.
fn substructure_markers(
    b: &Body,
    n: usize,
    k: usize,
    ls: f64,
    moved: &mut Vec<(String, String, String, String)>,
) -> Vec<Marker> {
    let v3 = |x: f64| V3([x, 0.0, 0.0]);
    let mut markers = vec![
        Marker {
            name: "inner".into(),
            position: v3(0.0),
        },
        Marker {
            name: "outer".into(),
            position: v3(ls),
        },
    ];
    for m in &b.markers {
        let x = m.position.0[0];
        let kk = ((x / ls + 1e-9).floor() as usize).min(n - 1);
        if kk == k {
            markers.push(Marker {
                name: m.name.clone(),
                position: v3(x - k as f64 * ls),
            });
            moved.push((
                b.name.clone(),
                m.name.clone(),
                substructure_name(b, k),
                m.name.clone(),
            ));
        }
    }
    markers
}

/// The `Rigid` joint `{name}_bracket_k` from substructure k-1's `outer` marker to
/// substructure k's `inner` marker.
fn bracket(b: &Body, k: usize) -> Joint {
    Joint {
        name: format!("{}_bracket_{k}", b.name),
        kind: JointKind::Rigid,
        body1: substructure_name(b, k - 1),
        marker1: "outer".into(),
        body2: substructure_name(b, k),
        marker2: "inner".into(),
    }
}

/// Re-point joints, forces, constraints and Position/Velocity sensors of `out` from the split beams'
/// markers to the substructures that now hold them; refuse `Modal` sensors of a split
/// beam, whose modal coordinates no longer exist.
fn repoint_to_substructures(
    scene: &Scene,
    out: &mut Scene,
    split: &SplitBeams,
) -> Result<(), ModelError> {
    for j in out.joints.iter_mut() {
        split.remap(&mut j.body1, &mut j.marker1);
        split.remap(&mut j.body2, &mut j.marker2);
    }
    for f in out.forces.iter_mut() {
        for (body, marker) in f.ends_mut() {
            split.remap(body, marker);
        }
    }
    for c in out.constraints.iter_mut() {
        for (body, marker) in c.ends_mut() {
            split.remap(body, marker);
        }
    }
    for s in out.sensors.iter_mut() {
        if let Some((body, marker, frame)) = s.kind.marker_mut() {
            split.remap(body, marker);
            split.remap_frame(frame);
        } else if let SensorKind::Modal { body, .. } = &s.kind
            && split.is_split(body)
        {
            return Err(refuse_substructuring(
                scene,
                format!(
                    "sensor `{}`: modal coordinates of a split beam do not exist under substructuring",
                    s.name
                ),
            ));
        }
    }
    Ok(())
}

/// The scene FS0 compiles: every flexible beam without axial modes.
pub fn drop_axial_modes(scene: &Scene) -> Result<Scene, ModelError> {
    let mut out = scene.clone();
    for (name, spec) in flexible_beams(&mut out.bodies) {
        if spec.frame != (ReferenceFrame::Clamped { node: 0 }) {
            return Err(refuse_fs0(
                scene,
                format!(
                    "body `{}`: the frame must be clamped at the root node 0 (methods.md §6.3)",
                    name
                ),
            ));
        }
        spec.axial_modes = 0;
    }
    Ok(out)
}
