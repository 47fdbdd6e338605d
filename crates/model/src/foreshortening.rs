//! Foreshortening, FS0 (docs/methods.md §6.3): the body set-up. F is computed at every cloud
//! point and node (`flexmbd_fe::foreshortening`) and attached to the run-time body, which
//! then uses the foreshortened kinematics in both inertia routes (the scene's
//! `solver.inertia`: B-matrix projection or the FS0 shape integrals) and in marker and
//! sensor positions. Refused: modes with axial content, and joints or force elements at any
//! marker of the body but its root (docs/methods.md §6.3 limits: the static-mode-as-joint
//! recursion ignores u_fs at other nodes). Elasticity stays linear, −K_L y. The scene
//! rewrite that drops the axial modes is [`crate::rewrite::drop_axial_modes`].

use flexmbd_fe::Mesh;

use crate::bodies::PreparedBody;
use crate::error::ModelError;
use crate::rewrite::refuse_fs0 as refuse;
use crate::scene::{BodyModel, Scene};

impl Scene {
    /// Attach FS0 data to a flexible body: F at its cloud points and nodes, in the reduced
    /// body and in the run-time body.
    pub(crate) fn install_foreshortening(&self, prep: &mut PreparedBody) -> Result<(), ModelError> {
        let scene = self;
        let b = &scene.bodies[prep.index];
        let BodyModel::Beam(spec) = &b.model else {
            return Ok(());
        };
        let invalid = |error| scene.invalid(error);
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
        prep.body.set_foreshortening(&data).map_err(invalid)?;
        prep.body
            .check_inertia_method(scene.solver.inertia)
            .map_err(invalid)?;
        // Joints and force elements only at the root (F = 0 there).
        let markers_used = scene
            .joints
            .iter()
            .flat_map(|j| {
                [
                    (j.body1.as_str(), j.marker1.as_str(), j.name.as_str()),
                    (j.body2.as_str(), j.marker2.as_str(), j.name.as_str()),
                ]
            })
            .chain(
                scene
                    .forces
                    .iter()
                    .flat_map(|f| f.ends().map(|(body, marker)| (body, marker, f.name()))),
            );
        for (body_name, marker, what) in markers_used {
            if body_name != b.name {
                continue;
            }
            let k = b.markers.iter().position(|m| m.name == marker);
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
        prep.reduced.foreshortening = Some(data);
        Ok(())
    }
}
