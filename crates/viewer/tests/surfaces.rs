//! Flexible bodies other than polyline beams drawn deformed: a solid FE body's outer
//! surface and a beam frame's member tubes, their morph targets (weighted by the modal
//! coordinates) moving each FE node's vertices by s Φ y, checked against the run's own
//! node displacement sensors (`Position … frame: Some(body), displacement: true`: the
//! node's elastic displacement in the body's floating frame).

use flexmbd::model::{Axis, Marker, Scene, Sensor, SensorKind, V3};
use flexmbd_viewer::{Format, Recording, record, render};
use nalgebra::Vector3;

fn model(name: &str) -> Scene {
    let path = format!("{}/../../models/{name}", env!("CARGO_MANIFEST_DIR"));
    Scene::load(path).unwrap()
}

/// Sensors of the elastic displacement of `marker` on `body`, in its frame, x, y, z.
fn displacement_sensors(scene: &mut Scene, body: &str, marker: &str) -> [String; 3] {
    [("x", Axis::X), ("y", Axis::Y), ("z", Axis::Z)].map(|(axis, component)| {
        let name = format!("{marker}_u{axis}");
        scene.sensors.push(Sensor {
            name: name.clone(),
            kind: SensorKind::Position {
                body: body.into(),
                marker: marker.into(),
                component,
                frame: Some(body.into()),
            },
            displacement: true,
        });
        name
    })
}

/// The mean morph displacement Σ_j y_j d_j(v) over the vertices `vertices` of body `b` at
/// frame `k` of `recording`, scaled by `s`.
fn drawn(recording: &Recording, b: usize, k: usize, vertices: &[usize], s: f64) -> Vector3<f64> {
    let shape = &recording.bodies[b];
    let modes = &recording.poses[k][b].modes;
    vertices
        .iter()
        .map(|&v| {
            shape
                .targets
                .iter()
                .zip(modes)
                .map(|(t, y)| t[v] * (s * y))
                .sum::<Vector3<f64>>()
        })
        .sum::<Vector3<f64>>()
        / vertices.len() as f64
}

/// The largest gap, over the frames, between s times the sensed displacement and the
/// drawn one, and the largest sensed displacement.
fn worst(
    recording: &Recording,
    b: usize,
    vertices: &[usize],
    sensors: &[String],
    axes: &[usize],
    s: f64,
) -> (f64, f64) {
    let column = |name: &String| {
        recording
            .sensor_names
            .iter()
            .position(|n| n == name)
            .unwrap()
    };
    let (mut gap, mut largest) = (0.0f64, 0.0f64);
    for k in 0..recording.times.len() {
        let d = drawn(recording, b, k, vertices, s);
        for (name, &axis) in sensors.iter().zip(axes) {
            let sensed = recording.sensors[k][column(name)];
            gap = gap.max((d[axis] - s * sensed).abs());
            largest = largest.max(sensed.abs());
        }
    }
    (gap, largest)
}

/// The Gmsh solid cantilever (C3D20, 10 × 2 × 2): its outer surface is drawn (the corner
/// nodes of its 4 · 10 · 2 + 2 · 2 · 2 = 88 boundary quadrilaterals, 176 triangles, turned
/// outwards),
/// and the vertex at the tip's corner node (0.2, 0, 0) moves by s Φ y: at each of 51 frames
/// of the settling run its drawn displacement is s times the node's sensed displacement in
/// the body frame, to 1e-12 m of a displacement of micrometres (s = 1) and to 1e-9 m of
/// millimetres (s = 1000).
#[test]
fn a_solid_bodys_surface_moves_its_nodes_as_their_sensors() {
    let mut scene = model("solid_cantilever.ron");
    scene.bodies[0].markers.push(Marker {
        name: "corner".into(),
        position: V3([0.2, 0.0, 0.0]),
    });
    let sensors = displacement_sensors(&mut scene, "bar", "corner");
    let recording = record(&scene, 500.0).unwrap();
    assert!(recording.failure.is_none());
    assert_eq!(recording.times.len(), 51);
    let shape = &recording.bodies[0];
    assert_eq!(shape.targets.len(), recording.poses[0][0].modes.len());
    // 4 long faces of 10 x 2 quadrilaterals, 2 ends of 2 x 2, and the weld's sphere (120)
    let surface_triangles = 2 * (4 * 10 * 2 + 2 * 2 * 2);
    assert_eq!(shape.triangles.len(), surface_triangles + 120);
    // one vertex per surface corner node: 9 per section, less the 9 interior ones
    assert_eq!(shape.positions.len(), 9 * 11 - 9 + 62);
    // every surface triangle faces away from the bar's axis or its end faces
    for t in &shape.triangles[..surface_triangles] {
        let p = |i: usize| shape.positions[t[i] as usize];
        let normal = (p(1) - p(0)).cross(&(p(2) - p(0)));
        let middle = (p(0) + p(1) + p(2)) / 3.0;
        let axis_point = Vector3::new(middle.x.clamp(0.01, 0.19), 0.005, 0.005);
        assert!(
            normal.dot(&(middle - axis_point)) > 0.0,
            "{t:?} faces inwards"
        );
    }
    let corner: Vec<usize> = (0..shape.positions.len())
        .filter(|&v| (shape.positions[v] - Vector3::new(0.2, 0.0, 0.0)).norm() < 1e-12)
        .collect();
    assert_eq!(corner.len(), 1, "one vertex per surface node");
    for (s, tolerance) in [(1.0, 1e-12), (1000.0, 1e-9)] {
        let (gap, largest) = worst(&recording, 0, &corner, &sensors, &[0, 1, 2], s);
        assert!(largest > 1e-6, "the tip sags: {largest:e} m");
        assert!(
            gap < tolerance,
            "s = {s}: drawn {gap:e} m from s times the sensor"
        );
        eprintln!("s = {s}: largest displacement {largest:e} m, gap {gap:e} m");
    }
    // and the glb holds the surface with its morph targets
    let glb = render(&recording, &scene, Format::Glb, 1.0);
    let gltf = gltf::Gltf::from_slice(&glb).unwrap();
    let mesh = gltf.meshes().find(|m| m.name() == Some("bar")).unwrap();
    let primitive = mesh.primitives().next().unwrap();
    assert_eq!(primitive.morph_targets().len(), shape.targets.len());
}

/// The Iltis front-left A-arm run flexible (a beam frame: two legs and a bracket) is drawn as
/// its members' tubes deformed by morph targets: the vertices around its ball-joint node B
/// (the member rings there and the joint's sphere) move on average by the node's X^t y,
/// its sensed elastic displacement normal to the arm's plane (the scene's
/// `aarm_fl_deflection`, and the in-plane ones added here), to 1e-12 m, for 0.2 s.
#[test]
fn a_beam_frames_members_are_tubes_moving_their_nodes_as_their_sensors() {
    let mut scene = model("iltis_suspension.ron");
    scene.solver.duration = 0.2;
    let arm = scene
        .bodies
        .iter()
        .position(|b| b.name == "aarm_fl")
        .unwrap();
    scene.bodies[arm].flexible = true;
    let sensors = displacement_sensors(&mut scene, "aarm_fl", "B");
    let recording = record(&scene, 100.0).unwrap();
    assert!(recording.failure.is_none(), "{:?}", recording.failure);
    let b = recording
        .bodies
        .iter()
        .position(|s| s.name == "aarm_fl")
        .unwrap();
    let shape = &recording.bodies[b];
    assert!(
        !shape.targets.is_empty(),
        "the arm's tubes carry morph targets"
    );
    let at = scene.bodies[arm]
        .markers
        .iter()
        .find(|m| m.name == "B")
        .unwrap()
        .position
        .vec();
    let near: Vec<usize> = (0..shape.positions.len())
        .filter(|&v| (shape.positions[v] - at).norm() < 0.03)
        .collect();
    assert!(near.len() >= 12, "{} vertices around B", near.len());
    let (gap, largest) = worst(&recording, b, &near, &sensors, &[0, 1, 2], 1.0);
    assert!(largest > 1e-7, "the arm bends: {largest:e} m");
    assert!(gap < 1e-12, "drawn {gap:e} m from the sensor");
    let deflection = recording
        .sensor_names
        .iter()
        .position(|n| n == "aarm_fl_deflection")
        .unwrap();
    let k = recording.times.len() - 1;
    let z = drawn(&recording, b, k, &near, 1.0).z;
    assert!((z - recording.sensors[k][deflection]).abs() < 1e-12);
    eprintln!("A-arm B: largest displacement {largest:e} m, gap {gap:e} m");
}
