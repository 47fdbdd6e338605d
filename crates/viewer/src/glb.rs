//! The glTF 2.0 binary of a [`Recording`]: one node per body with its mesh
//! ([`BodyShape`](crate::shapes::BodyShape)), one animation whose channels drive each node's translation r0 and
//! rotation (the quaternion of A) and each flexible body's morph-target weights (its modal
//! coordinates y times the deformation scale), sampled at the recording's instants and
//! interpolated linearly. The JSON is written by `gltf-json`; the container (12-byte
//! header, JSON chunk, BIN chunk, each padded to 4 bytes) by hand, as the glTF 2.0
//! specification's section 4.4 lays it out. A run that failed is marked in the asset's
//! `extras` (`flexmbd.status`, `failed_at`, `message`) and in the animation's name.

use gltf_json as json;
use json::validation::USize64;
use nalgebra::{Rotation3, UnitQuaternion, Vector3};

use crate::builder::Builder;
use crate::record::Recording;

/// Body colours (linear RGB), one after another.
const PALETTE: [[f32; 3]; 6] = [
    [0.10, 0.35, 0.80],
    [0.85, 0.35, 0.05],
    [0.10, 0.60, 0.25],
    [0.70, 0.10, 0.55],
    [0.80, 0.65, 0.05],
    [0.05, 0.60, 0.65],
];

/// The rotation A of a frame as a unit quaternion [x, y, z, w], A made orthonormal first
/// (natural coordinates satisfy their unit-length constraints to the Newton tolerance
/// only), on the side of `previous` (q and −q are one rotation; linear interpolation wants
/// neighbours close).
fn quaternion(a: &nalgebra::Matrix3<f64>, previous: Option<[f32; 4]>) -> [f32; 4] {
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_eps(
        a,
        1e-12,
        100,
        Rotation3::identity(),
    ));
    let mut v = [q.i as f32, q.j as f32, q.k as f32, q.w as f32];
    if previous.is_some_and(|p| p.iter().zip(&v).map(|(a, b)| a * b).sum::<f32>() < 0.0) {
        v = v.map(|c| -c);
    }
    v
}

/// The glTF 2.0 binary (`.glb`) of `recording`, the modal coordinates multiplied by `scale`
/// in the morph weights (the caller checks that it is finite).
pub fn glb(recording: &Recording, scale: f64) -> Vec<u8> {
    let mut b = Builder {
        root: json::Root::default(),
        bin: Vec::new(),
    };
    let times: Vec<f32> = recording.times.iter().map(|&t| t as f32).collect();
    let input = b.floats(&times, json::accessor::Type::Scalar, 1, true, None);
    let ending = if recording.interrupted {
        "interrupted"
    } else {
        "failed"
    };
    let status = match &recording.failure {
        None => serde_json::json!({ "status": "ok" }),
        Some((t, message)) => {
            serde_json::json!({ "status": ending, "failed_at": t, "message": message })
        }
    };
    let name = match &recording.failure {
        None => recording.scene.clone(),
        Some((t, _)) => format!("{} (run {ending} at t = {t} s)", recording.scene),
    };
    let mut animation = json::Animation {
        name: Some(name),
        channels: Vec::new(),
        samplers: Vec::new(),
        extensions: None,
        extras: None,
    };
    let mut nodes = Vec::new();
    for (k, shape) in recording.bodies.iter().enumerate() {
        let mesh = b.mesh(shape, PALETTE[k % PALETTE.len()]);
        let mut rotations: Vec<[f32; 4]> = Vec::with_capacity(times.len());
        for frame in &recording.poses {
            rotations.push(quaternion(&frame[k].rotation, rotations.last().copied()));
        }
        let translations: Vec<f32> = recording
            .poses
            .iter()
            .flat_map(|f| f[k].origin.iter().map(|&c| c as f32).collect::<Vec<_>>())
            .collect();
        let n_modes = if mesh.is_some() {
            shape.targets.len()
        } else {
            0
        };
        let node = b.root.push(json::Node {
            name: Some(shape.name.clone()),
            mesh,
            translation: translations.get(..3).map(|t| [t[0], t[1], t[2]]),
            rotation: rotations.first().map(|&r| json::scene::UnitQuaternion(r)),
            weights: (n_modes > 0).then(|| vec![0.0; n_modes]),
            ..Default::default()
        });
        nodes.push(node);
        if times.is_empty() {
            continue;
        }
        let output = b.floats(&translations, json::accessor::Type::Vec3, 3, false, None);
        b.channel(
            &mut animation,
            input,
            output,
            node,
            json::animation::Property::Translation,
        );
        let flat: Vec<f32> = rotations.into_iter().flatten().collect();
        let output = b.floats(&flat, json::accessor::Type::Vec4, 4, false, None);
        b.channel(
            &mut animation,
            input,
            output,
            node,
            json::animation::Property::Rotation,
        );
        if n_modes > 0 {
            let weights: Vec<f32> = recording
                .poses
                .iter()
                .flat_map(|f| {
                    shape
                        .weights(&f[k].modes, scale)
                        .into_iter()
                        .map(|w| w as f32)
                })
                .collect();
            let output = b.floats(&weights, json::accessor::Type::Scalar, 1, false, None);
            b.channel(
                &mut animation,
                input,
                output,
                node,
                json::animation::Property::MorphTargetWeights,
            );
        }
    }
    let spring_mesh = (!recording.springs.is_empty())
        .then(|| b.mesh(&recording.spring_shape, [0.35, 0.35, 0.35]))
        .flatten();
    for (k, name) in recording.springs.iter().enumerate() {
        let ends = recording.spring_ends.iter().map(|frame| frame[k]);
        let (mut translations, mut rotations, mut scales) =
            (Vec::new(), Vec::<[f32; 4]>::new(), Vec::new());
        for [p1, p2] in ends {
            let d = p2 - p1;
            let turn = UnitQuaternion::rotation_between(&Vector3::y(), &d).unwrap_or_else(|| {
                UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
            });
            translations.extend(p1.iter().map(|&c| c as f32));
            rotations.push(quaternion(
                &turn.to_rotation_matrix().into_inner(),
                rotations.last().copied(),
            ));
            scales.extend([1.0, d.norm() as f32, 1.0]);
        }
        let node = b.root.push(json::Node {
            name: Some(name.clone()),
            mesh: spring_mesh,
            ..Default::default()
        });
        nodes.push(node);
        if times.is_empty() {
            continue;
        }
        let flat: Vec<f32> = rotations.into_iter().flatten().collect();
        for (values, type_, width, path) in [
            (
                translations,
                json::accessor::Type::Vec3,
                3,
                json::animation::Property::Translation,
            ),
            (
                flat,
                json::accessor::Type::Vec4,
                4,
                json::animation::Property::Rotation,
            ),
            (
                scales,
                json::accessor::Type::Vec3,
                3,
                json::animation::Property::Scale,
            ),
        ] {
            let output = b.floats(&values, type_, width, false, None);
            b.channel(&mut animation, input, output, node, path);
        }
    }
    for road in &recording.roads {
        // Scenery of the ground frame, marked so that the page neither follows nor fits it.
        let mesh = b.mesh(&road.shape(), [0.32, 0.30, 0.27]);
        nodes.push(
            b.root.push(json::Node {
                name: Some(road.name.clone()),
                mesh,
                extras: serde_json::value::to_raw_value(
                    &serde_json::json!({ "flexmbd": { "ground": true } }),
                )
                .ok(),
                ..Default::default()
            }),
        );
    }
    if !animation.channels.is_empty() {
        b.root.push(animation);
    }
    let scene = b.root.push(json::Scene {
        name: Some(recording.scene.clone()),
        nodes,
        extensions: None,
        extras: None,
    });
    b.root.scene = Some(scene);
    b.root.asset = json::Asset {
        generator: Some(format!("flexmbd {}", env!("CARGO_PKG_VERSION"))),
        extras: serde_json::value::to_raw_value(&serde_json::json!({ "flexmbd": status })).ok(),
        ..Default::default()
    };
    while !b.bin.len().is_multiple_of(4) {
        b.bin.push(0);
    }
    b.root.push(json::Buffer {
        byte_length: USize64(b.bin.len() as u64),
        name: None,
        uri: None,
        extensions: None,
        extras: None,
    });
    container(
        &json::serialize::to_vec(&b.root).expect("a glTF document serialises"),
        &b.bin,
    )
}

/// The GLB container: header (magic, version 2, length), the JSON chunk padded with
/// spaces, the BIN chunk padded with zeros (glTF 2.0 §4.4).
fn container(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| n.div_ceil(4) * 4;
    let (json_len, bin_len) = (pad(json.len()), pad(bin.len()));
    let total = 12 + 8 + json_len + 8 + bin_len;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json);
    out.resize(12 + 8 + json_len, b' ');
    out.extend_from_slice(&(bin_len as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out.resize(total, 0);
    out
}
