//! The pose of every body at the current state, for a viewer: each body's floating frame
//! {r0, A} — the one the sensors read (`flexmbd_core::SensorQuery::body_frame`) — and its
//! modal coordinates y, so that a point of undeformed body position r̄_u is at
//! r0 + A (r̄_u + Φ y) (floating frame of reference, docs/methods.md §1.1). The bodies are
//! those of the prepared scene ([`Simulation::prepared`]): a substructured beam is several.

use flexmbd_core::{BodyMotion, BodyPose};
use flexmbd_model::PreparedScene;

use super::Simulation;

impl Simulation {
    /// The scene as compiled: validated, rewritten for its stiffening method, its bodies
    /// reduced (their nodes and mode rows: [`flexmbd_model::PreparedBody::nodes`]).
    pub fn prepared(&self) -> &PreparedScene {
        &self.prepared
    }

    /// Write the pose of every body of the prepared scene at the current state into `out`
    /// (resized to one per body, in the order of [`PreparedScene::bodies`]). Reads the
    /// state only: the trajectory does not change.
    pub fn body_poses(&mut self, out: &mut Vec<BodyPose>) {
        out.resize(self.prepared.bodies().len(), BodyPose::default());
        let state = self.integrator.state();
        self.formulation.body_poses(state, out);
    }

    /// Write the motion of every body of the prepared scene at the current state into `out`
    /// (resized to one per body): its frame's motion and its modal coordinates, rates and
    /// accelerations. Returns false, writing nothing, when the formulation does not report
    /// them (the absolute one). Reads the state only: the trajectory does not change.
    pub fn body_motions(&mut self, out: &mut Vec<BodyMotion>) -> bool {
        out.resize(self.prepared.bodies().len(), BodyMotion::default());
        let state = self.integrator.state();
        self.formulation.body_motions(state, out)
    }
}

#[cfg(test)]
mod tests {
    use flexmbd_model::{FormulationKind, Scene};

    use crate::Simulation;

    /// The pose's frame carries each body's markers where the position sensors put them, in
    /// both formulations, for the rigid 3D double pendulum after 0.2 s.
    #[test]
    fn poses_put_the_markers_where_the_sensors_do() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../models/double_pendulum_3d.ron"
        );
        for formulation in [FormulationKind::Absolute, FormulationKind::Relative] {
            let mut scene = Scene::load(path).unwrap();
            scene.solver.formulation = formulation;
            let mut sim = Simulation::new(&scene).unwrap();
            sim.advance_to(0.2).unwrap();
            let mut poses = Vec::new();
            sim.body_poses(&mut poses);
            assert_eq!(poses.len(), 2);
            let tip = poses[1].origin + poses[1].rotation * nalgebra::Vector3::new(0.5, 0.0, 0.0);
            for (axis, name) in ["tip_x", "tip_y", "tip_z"].iter().enumerate() {
                let sensor = sim.sensor(name).unwrap();
                assert!(
                    (tip[axis] - sensor).abs() < 1e-9,
                    "{formulation:?} {name}: {} vs {sensor}",
                    tip[axis]
                );
            }
            assert!(poses.iter().all(|p| p.modes.is_empty()));
        }
    }

    /// A flexible body's node moves as r0 + A (r̄_u + X^t y): the flexible pendulum's tip,
    /// a node, lands where its sensors put it after 0.3 s of swinging and bending.
    #[test]
    fn modal_coordinates_move_the_nodes_where_the_sensors_do() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../models/flexible_pendulum.ron"
        );
        for formulation in [FormulationKind::Absolute, FormulationKind::Relative] {
            let mut scene = Scene::load(path).unwrap();
            scene.solver.formulation = formulation;
            let mut sim = Simulation::new(&scene).unwrap();
            sim.advance_to(0.3).unwrap();
            let mut poses = Vec::new();
            sim.body_poses(&mut poses);
            let nodes = &sim.prepared().bodies()[0].nodes;
            let tip = nodes
                .node_at(&nalgebra::Vector3::new(1.0, 0.0, 0.0), 1e-9)
                .unwrap();
            let y = nalgebra::DVector::from_column_slice(&poses[0].modes);
            assert!(y.norm() > 0.0, "the bar bends");
            let local = nodes.position(tip) + nodes.translation_matrix(tip) * y;
            let at = poses[0].origin + poses[0].rotation * local;
            for (axis, name) in ["tip_x", "tip_y"].iter().enumerate() {
                let sensor = sim.sensor(name).unwrap();
                assert!(
                    (at[axis] - sensor).abs() < 1e-9,
                    "{formulation:?} {name}: {} vs {sensor}",
                    at[axis]
                );
            }
        }
    }
}
