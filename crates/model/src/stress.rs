//! Stress sensors (issue 29 item 3): the stress shapes of a `Stress` sensor's node set,
//! computed once when the scene is prepared, so that a step reads the stress as a small
//! product, σ_node = S_node q, S_node the node's 6 × n rows of the modal stress shapes
//! (`flexmbd_fe::solid::stress`) and q the body's modal coordinates.
//!
//! The body must be a flexible `Imported` body whose source is `Solid` (the built-in
//! elements know the material and the elements; an export's matrices do not); its mesh is
//! read and assembled again for the shapes (the cost of the body's own preparation, once).

use nalgebra::DMatrix;

use flexmbd_core::InvalidValue;
use flexmbd_fe::imported::ImportSource;
use flexmbd_fe::solid::body_stress_shapes;

use crate::bodies::PreparedBody;
use crate::error::ModelError;
use crate::prepared::SensorTarget;
use crate::scene::{BodyModel, Scene, SensorKind};

/// The stress shapes of one sensor's node set: per node of the set, its 6 × n rows
/// (σ_xx, σ_yy, σ_zz, τ_xy, τ_yz, τ_zx per modal coordinate).
#[derive(Clone, Debug, PartialEq)]
pub struct StressSet {
    /// One 6 × n matrix per node of the set.
    pub shapes: Vec<DMatrix<f64>>,
}

/// Build the stress sets of the scene's `Stress` sensors and point each target at its set.
pub(crate) fn stress_sets(
    scene: &Scene,
    bodies: &[PreparedBody],
    sensors: &mut [SensorTarget],
) -> Result<Vec<StressSet>, ModelError> {
    let mut sets = Vec::new();
    for (k, target) in sensors.iter_mut().enumerate() {
        let SensorTarget::Stress { body, table, .. } = target else {
            continue;
        };
        let sensor = &scene.sensors[k];
        let SensorKind::Stress { nodes, .. } = &sensor.kind else {
            continue;
        };
        let b = &scene.bodies[body.0];
        let refuse = |field: &str, value: &str, why: String| {
            scene.invalid(InvalidValue::new(
                format!("sensors[{}].{field}", sensor.name),
                value,
                why,
            ))
        };
        let not_solid = || {
            refuse(
                "body",
                &b.name,
                "a stress sensor needs a body of model Imported with source: Solid (the \
                 built-in solid elements)"
                    .to_string(),
            )
        };
        let BodyModel::Imported(spec) = &b.model else {
            return Err(not_solid());
        };
        let ImportSource::Solid { material, mesh, .. } = &spec.source else {
            return Err(not_solid());
        };
        let prepared = &bodies[body.0];
        if !prepared.flexible {
            return Err(refuse(
                "body",
                &b.name,
                "the body is rigid (flexible: false or no modes): it has no elastic stress"
                    .to_string(),
            ));
        }
        let model = spec
            .source
            .read(&scene.base_directory(), &spec.options)
            .map_err(|e| scene.fe_error(&b.name, e))?;
        let file = mesh.display().to_string();
        let shapes = body_stress_shapes(
            &model,
            material,
            &prepared.reduced,
            spec.interfaces.len(),
            &file,
        )
        .map_err(|e| scene.fe_error(&b.name, e))?;
        let set = model
            .mesh
            .node_sets
            .iter()
            .find(|(name, _)| name.eq_ignore_ascii_case(nodes))
            .map(|(_, set)| set)
            .ok_or_else(|| {
                let names: Vec<&str> = model.mesh.node_sets.keys().map(String::as_str).collect();
                refuse(
                    "nodes",
                    nodes,
                    format!(
                        "{file} has no such node set (its sets: {})",
                        if names.is_empty() {
                            "none".to_string()
                        } else {
                            names.join(", ")
                        }
                    ),
                )
            })?;
        if set.is_empty() {
            return Err(refuse(
                "nodes",
                nodes,
                "the node set holds no node of the solid elements".to_string(),
            ));
        }
        *table = sets.len();
        sets.push(StressSet {
            shapes: set
                .iter()
                .map(|&n| shapes.shapes.rows(6 * n, 6).into_owned())
                .collect(),
        });
    }
    Ok(sets)
}
