//! Foreshortening, FS0 (docs/methods.md §6.3): the scene preparation and the body set-up.
//!
//! - [`prepare`]: FS0 keeps **no axial modes** (`axial_modes` set to 0 on every flexible
//!   beam); it runs in both formulations, 2D and 3D, and needs each flexible beam's frame
//!   clamped at node 0 (the root, x = 0 of F(x)).
//! - [`install`]: computes F at every cloud point and node (`flexmbd_fe::foreshortening`)
//!   and attaches it to the run-time body, which then uses the foreshortened kinematics in
//!   both inertia routes (the scene's `solver.inertia`: B-matrix projection or the FS0 shape
//!   integrals) and in marker/sensor positions. Refuses bent beams, modes with axial content,
//!   and joints or force elements at any marker of the body but its root (docs/methods.md §6.3
//!   limits: the static-mode-as-joint recursion ignores u_fs at other nodes). Elasticity
//!   stays linear, −K_L y.

use flexmbd_body::FlexibleBody;
use flexmbd_fe::{Mesh, ReferenceFrame};
use flexmbd_model::{BodyModel, ModelError, PreparedBody, Scene};

fn refuse(scene: &Scene, what: String) -> ModelError {
    ModelError::Unsupported(format!("{}: foreshortening (FS0): {what}", scene.origin))
}

/// The scene FS0 compiles: every flexible beam without axial modes.
pub fn prepare(scene: &Scene) -> Result<Scene, ModelError> {
    let mut out = scene.clone();
    for b in out.bodies.iter_mut() {
        let BodyModel::Beam(spec) = &mut b.model else {
            continue;
        };
        if !b.flexible {
            continue;
        }
        if spec.frame != (ReferenceFrame::Clamped { node: 0 }) {
            return Err(refuse(
                scene,
                format!(
                    "body `{}`: the frame must be clamped at the root node 0 (methods.md §6.3)",
                    b.name
                ),
            ));
        }
        spec.axial_modes = 0;
    }
    Ok(out)
}

/// Attach FS0 data to a flexible body the formulation just built from `prep`.
pub fn install(
    scene: &Scene,
    prep: &PreparedBody,
    body: &mut FlexibleBody,
) -> Result<(), ModelError> {
    let b = &scene.bodies[prep.index];
    let BodyModel::Beam(spec) = &b.model else {
        return Ok(());
    };
    let invalid = |error| ModelError::Invalid {
        file: scene.origin.clone(),
        error,
    };
    let modes = &prep.reduced.modes;
    // No axial content: FS0 replaces the axial field by the shortening.
    let d = prep.reduced.dim.n_rigid();
    let scale = modes.amax().max(f64::MIN_POSITIVE);
    for j in 0..modes.ncols() {
        let ux = (0..modes.nrows() / d)
            .map(|node| modes[(node * d, j)].abs())
            .fold(0.0, f64::max);
        if ux > 1e-8 * scale {
            return Err(refuse(
                scene,
                format!(
                    "body `{}`: mode {j} has axial content; FS0 keeps no axial modes \
                     (methods.md §6.3)",
                    b.name
                ),
            ));
        }
    }
    let mesh = Mesh::from_spec(spec);
    let data = flexmbd_fe::foreshortening::foreshortening(&mesh, modes).map_err(invalid)?;
    body.set_foreshortening(&data).map_err(invalid)?;
    body.check_inertia_method(scene.solver.inertia)
        .map_err(invalid)?;
    // Joints and force elements only at the root (F = 0 there).
    let markers_used = scene
        .joints
        .iter()
        .flat_map(|j| {
            [
                (&j.body1, &j.marker1, &j.name),
                (&j.body2, &j.marker2, &j.name),
            ]
        })
        .chain(scene.forces.iter().flat_map(|f| {
            let flexmbd_model::Force::SpringDamper {
                name,
                body1,
                marker1,
                body2,
                marker2,
                ..
            } = f;
            [(body1, marker1, name), (body2, marker2, name)]
        }));
    for (body_name, marker, what) in markers_used {
        if *body_name != b.name {
            continue;
        }
        let k = b.markers.iter().position(|m| m.name == *marker);
        let node = k.and_then(|k| prep.marker_nodes[k]);
        let f_zero = node.is_some_and(|nd| data.nodes[nd].amax() == 0.0);
        if !f_zero {
            return Err(refuse(
                scene,
                format!(
                    "body `{}`: `{what}` attaches at marker `{marker}`, beyond the root; a \
                     foreshortened body may have joints and forces at its root only \
                     (methods.md §6.3 limits)",
                    b.name
                ),
            ));
        }
    }
    Ok(())
}
