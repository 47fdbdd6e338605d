//! The most faithful reference the project can build for a scene (issue 27 item 1): the
//! large-deformation solution where the scene is one the ANCF cable models, converged in
//! its own mesh and step, with its error estimated.
//!
//! The ANCF cable ([`flexmbd_ancf`], docs/methods.md §7.3) is a geometrically exact model
//! of a uniform Euler–Bernoulli beam clamped at its root to a hub driven by the spin-up
//! law — the spin-up beams of docs/scenes.md §5. A scene is recognised as one when it
//! holds exactly that and nothing else: one flexible straight beam along body x from its
//! origin, placed at the ground's origin unrotated, its floating frame clamped at the root
//! node, a revolute joint (axis z) from a ground marker at the origin to a root marker,
//! driven by a `SpinUp` law, no other joint, force, constraint, road or input, no initial
//! velocity or modes. Each judged sensor must be one the cable gives: a position
//! component of the tip marker in the beam's own frame (which turns with the hub, the root
//! being clamped), as a displacement or not, or the hub's joint coordinate.
//!
//! The reference is the cable of 16 elements at the scene's step (at most 1 ms), output
//! at the scene's output times (so no interpolation enters the errors); its error is
//! estimated per sensor as the larger of its differences from the same cable with 32
//! elements and from the same at half the step (Richardson: a converging solution's error
//! is of the order of its change under refinement).

use std::sync::atomic::AtomicBool;

use flexmbd_ancf::{AncfError, CableSpec, History, run_spin_up_or_stop};
use flexmbd_core::Dim;
use flexmbd_model::{
    Axis as Component, BodyModel, InitialState, JointKind, MotionLaw, Orientation, Scene,
    SensorKind,
};

use super::{ReferenceTable, SensorError, SweepError};

/// The cable's mesh of the reference, and of its mesh check (twice as fine).
pub const CABLE_ELEMENTS: usize = 16;
/// The largest step of the reference (s): the report's ANCF step.
pub const CABLE_STEP: f64 = 1e-3;

/// A large-deformation reference: its table, label and estimated error per sensor.
pub(super) struct Faithful {
    pub table: ReferenceTable,
    pub label: String,
    pub margin: Vec<SensorError>,
}

/// What a judged sensor reads off the cable.
#[derive(Clone, Copy, Debug)]
enum Column {
    /// Tip displacement component `k` in the turning frame, plus `offset` (the undeformed
    /// tip's component, for a position that is not a displacement).
    Tip { k: usize, offset: f64 },
    /// The hub angle θ(t) (the joint coordinate, θ(0) = 0).
    Hub,
}

/// The large-deformation reference of `scene` (with its overrides) on `sensors`, or why
/// the project has none for it (`Ok(Err(why))`); `Err` when the cable's own run fails.
pub(super) fn reference(
    scene: &Scene,
    sensors: &[String],
    stop: &AtomicBool,
) -> Result<Result<Faithful, String>, SweepError> {
    let (spec, law, columns) = match recognise(scene, sensors) {
        Ok(found) => found,
        Err(why) => return Ok(Err(why)),
    };
    let h = scene.solver.step.min(CABLE_STEP);
    let interval = scene.solver.output_interval.unwrap_or(scene.solver.step);
    let duration = scene.solver.duration;
    let label = format!("ANCF cable (large deformation), {CABLE_ELEMENTS} elements, h = {h} s");
    let run = |elements: usize, h: f64| -> Result<History, SweepError> {
        let spec = CableSpec {
            elements,
            ..spec.clone()
        };
        let label = format!("ANCF cable, {elements} elements, h = {h} s");
        run_spin_up_or_stop(&spec, h, duration, interval, stop).map_err(|e| match e {
            AncfError::Interrupted { .. } => SweepError::Interrupted { label },
            e => SweepError::ReferenceRun {
                label,
                message: e.to_string(),
            },
        })
    };
    let reference = run(CABLE_ELEMENTS, h)?;
    let finer_mesh = run(2 * CABLE_ELEMENTS, h)?;
    let finer_step = run(CABLE_ELEMENTS, h / 2.0)?;
    let values = |history: &History, column: Column| -> Vec<f64> {
        history
            .t
            .iter()
            .zip(&history.tip)
            .map(|(&t, tip)| match column {
                Column::Tip { k, offset } => tip[k] + offset,
                Column::Hub => law.eval(t).0,
            })
            .collect()
    };
    let table = ReferenceTable::new(
        label.clone(),
        reference.t.clone(),
        sensors.to_vec(),
        columns.iter().map(|&c| values(&reference, c)).collect(),
    )?;
    // The largest and the RMS difference from a refined run (the runs share their output
    // times: the step halves, the interval does not).
    let difference = |other: &History, column: Column| {
        let d: Vec<f64> = values(&reference, column)
            .iter()
            .zip(values(other, column))
            .map(|(a, b)| a - b)
            .collect();
        let max = d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let rms = (d.iter().map(|v| v * v).sum::<f64>() / d.len().max(1) as f64).sqrt();
        (max, rms)
    };
    let margin = sensors
        .iter()
        .zip(&columns)
        .map(|(name, &column)| {
            let mesh = difference(&finer_mesh, column);
            let step = difference(&finer_step, column);
            let (max_abs, rms) = if mesh.0 >= step.0 { mesh } else { step };
            SensorError {
                sensor: name.clone(),
                max_abs,
                rms,
            }
        })
        .collect();
    Ok(Ok(Faithful {
        table,
        label,
        margin,
    }))
}

/// The cable, the hub's law and the judged sensors' columns of `scene`, or why the scene
/// is not one the cable models.
fn recognise(
    scene: &Scene,
    sensors: &[String],
) -> Result<(CableSpec, MotionLaw, Vec<Column>), String> {
    let [body] = scene.bodies.as_slice() else {
        return Err(format!(
            "{} bodies (the cable models one beam)",
            scene.bodies.len()
        ));
    };
    let BodyModel::Beam(beam) = &body.model else {
        return Err(format!("body `{}` is not a beam", body.name));
    };
    if !body.flexible {
        return Err(format!("body `{}` is rigid", body.name));
    }
    let points = &beam.geometry.points;
    let along_x = |p: &Vec<f64>| p.iter().skip(1).all(|c| *c == 0.0);
    let length = match points.as_slice() {
        [root, tip] if root.iter().all(|c| *c == 0.0) && along_x(tip) && tip[0] > 0.0 => tip[0],
        _ => {
            return Err(format!(
                "beam `{}` is not one straight segment along x from its origin",
                body.name
            ));
        }
    };
    let unrotated = match body.orientation {
        Orientation::Identity => true,
        Orientation::Angle(a) => a == 0.0,
        _ => false,
    };
    if body.origin.0 != [0.0; 3] || !unrotated {
        return Err(format!(
            "beam `{}` is not at the ground's origin, unrotated",
            body.name
        ));
    }
    if !matches!(beam.frame, flexmbd_fe::ReferenceFrame::Clamped { node: 0 })
        || !beam.boundary.is_empty()
    {
        return Err(format!(
            "beam `{}` is not clamped at its root node only",
            body.name
        ));
    }
    if !body.initial_modes.is_empty()
        || body.velocity.linear.0 != [0.0; 3]
        || body.velocity.angular.0 != [0.0; 3]
        || scene.initial_velocity.0 != [0.0; 3]
    {
        return Err(
            "the scene starts with a velocity or deformation the cable does not take".into(),
        );
    }
    if !scene.forces.is_empty()
        || !scene.constraints.is_empty()
        || !scene.roads.is_empty()
        || !scene.inputs.is_empty()
    {
        return Err("the scene has forces, constraints, roads or inputs beside the beam".into());
    }
    let [joint] = scene.joints.as_slice() else {
        return Err(format!(
            "{} joints (the cable has one hub)",
            scene.joints.len()
        ));
    };
    let marker_at = |name: &str, markers: &[flexmbd_model::Marker]| {
        markers
            .iter()
            .find(|m| m.name == name)
            .map(|m| m.position.0)
    };
    let hub_axis_z = match &joint.kind {
        JointKind::Revolute { axis } => axis
            .as_ref()
            .is_none_or(|a| a.0[0] == 0.0 && a.0[1] == 0.0 && a.0[2] != 0.0),
        _ => false,
    };
    let grounded = joint.body1 == "ground"
        && joint.body2 == body.name
        && marker_at(&joint.marker1, &scene.ground) == Some([0.0; 3])
        && marker_at(&joint.marker2, &body.markers) == Some([0.0; 3]);
    if !hub_axis_z || !grounded {
        return Err(format!(
            "joint `{}` is not a revolute hub about z from the ground's origin to the beam's root",
            joint.name
        ));
    }
    let law = match scene.drivers.as_slice() {
        [driver]
            if driver.joint == joint.name && matches!(driver.law, MotionLaw::SpinUp { .. }) =>
        {
            driver.law.clone()
        }
        _ => {
            return Err(format!(
                "the hub `{}` is not driven by one SpinUp law",
                joint.name
            ));
        }
    };
    let MotionLaw::SpinUp { omega_s, t_s } = law else {
        unreachable!("matched above")
    };
    let section = beam.section.props();
    let e = beam.material.young_modulus;
    if scene.dim == Dim::Spatial && section.iy != section.iz {
        return Err(format!(
            "beam `{}` bends unequally in its two planes (I_y ≠ I_z); the cable is isotropic",
            body.name
        ));
    }
    let gravity = scene.gravity.0;
    if gravity != [0.0; 3] && scene.solver.initial_state != InitialState::StaticEquilibrium {
        return Err(
            "a beam under gravity that does not start in static equilibrium (the cable does)"
                .into(),
        );
    }
    let spec = CableSpec {
        dim: scene.dim,
        length,
        ea: e * section.area,
        ei: e * section.iz,
        rho_a: beam.material.density * section.area,
        elements: CABLE_ELEMENTS,
        gravity: match scene.dim {
            Dim::Planar => [gravity[0], gravity[1], 0.0],
            Dim::Spatial => gravity,
        },
        omega_s,
        t_s,
    };
    let tip = [length, 0.0, 0.0];
    let columns = sensors
        .iter()
        .map(|name| {
            let sensor = scene
                .sensors
                .iter()
                .find(|s| s.name == *name)
                .ok_or_else(|| format!("no sensor `{name}`"))?;
            match &sensor.kind {
                SensorKind::Position { body: b, marker, component, frame }
                    if *b == body.name
                        && frame.as_deref() == Some(body.name.as_str())
                        && marker_at(marker, &body.markers) == Some(tip) =>
                {
                    let k = match component {
                        Component::X => 0,
                        Component::Y => 1,
                        Component::Z => 2,
                    };
                    let offset = if sensor.displacement { 0.0 } else { tip[k] };
                    Ok(Column::Tip { k, offset })
                }
                SensorKind::JointCoordinate { joint: j } if *j == joint.name => Ok(Column::Hub),
                _ => Err(format!(
                    "sensor `{name}` is not the tip's position in the beam's frame nor the hub's angle, which is what the cable gives"
                )),
            }
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok((spec, law, columns))
}
