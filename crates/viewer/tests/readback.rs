//! The animation read back from its glTF binary with the `gltf` crate (not the writer's
//! code) puts each body where the run's sensors put it.

use flexmbd::model::{Axis, FormulationKind, Scene, Sensor, SensorKind};
use flexmbd_viewer::{Format, Recording, record, render};
use gltf::animation::util::ReadOutputs;
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

fn model(name: &str) -> Scene {
    let path = format!("{}/../../models/{name}", env!("CARGO_MANIFEST_DIR"));
    Scene::load(path).unwrap()
}

/// Per frame, the translation and rotation of node `name`, and the frames' times.
fn node_track(glb: &[u8], name: &str) -> (Vec<f64>, Vec<Vector3<f64>>, Vec<UnitQuaternion<f64>>) {
    let gltf = gltf::Gltf::from_slice(glb).expect("a valid glTF binary");
    let blob = gltf.blob.as_deref().expect("a BIN chunk");
    let animation = gltf.animations().next().expect("one animation");
    let (mut times, mut positions, mut rotations) = (Vec::new(), Vec::new(), Vec::new());
    for channel in animation
        .channels()
        .filter(|c| c.target().node().name() == Some(name))
    {
        let reader = channel.reader(|_| Some(blob));
        times = reader.read_inputs().unwrap().map(f64::from).collect();
        match reader.read_outputs().unwrap() {
            ReadOutputs::Translations(t) => {
                positions = t.map(|p| Vector3::from(p.map(f64::from))).collect()
            }
            ReadOutputs::Rotations(r) => {
                rotations = r
                    .into_f32()
                    .map(|[x, y, z, w]| {
                        UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z).cast())
                    })
                    .collect();
            }
            _ => {}
        }
    }
    (times, positions, rotations)
}

fn position_sensors(scene: &mut Scene, body: &str, marker: &str) {
    for (axis, component) in [("x", Axis::X), ("y", Axis::Y), ("z", Axis::Z)] {
        scene.sensors.push(Sensor {
            name: format!("{body}_{marker}_{axis}"),
            kind: SensorKind::Position {
                body: body.into(),
                marker: marker.into(),
                component,
                frame: None,
            },
            displacement: false,
        });
    }
}

/// The rigid 3D double pendulum in both formulations, animated at 50 frames per second
/// (every 10th step of h = 2 ms): at each of the 101 frames, link1's hinge J and link2's
/// tip carried by their node's translation and rotation lie within 1e-6 m of the
/// run's (`flexmbd::simulation::run`, the CSV's route) position sensors at that time.
#[test]
fn the_glb_reproduces_the_runs_body_positions_at_every_frame() {
    for formulation in [FormulationKind::Absolute, FormulationKind::Relative] {
        let mut scene = model("double_pendulum_3d.ron");
        scene.solver.formulation = formulation;
        position_sensors(&mut scene, "link1", "J");
        position_sensors(&mut scene, "link2", "tip");
        let (summary, history) = flexmbd::simulation::run(&scene, |_| {}).unwrap();
        assert_eq!(summary.status, "ok");
        let recording = record(&scene, 50.0).unwrap();
        let glb = render(&recording, &scene, Format::Glb, 1.0);
        let mut worst: f64 = 0.0;
        for (node, marker, local) in [
            ("link1", "J", [0.7, 0.0, 0.05]),
            ("link2", "tip", [0.5, 0.0, 0.0]),
        ] {
            let (times, positions, rotations) = node_track(&glb, node);
            assert_eq!(
                (times.len(), positions.len(), rotations.len()),
                (101, 101, 101)
            );
            let columns: Vec<_> = ["x", "y", "z"]
                .iter()
                .map(|a| history.column(&format!("{node}_{marker}_{a}")).unwrap())
                .collect();
            let t = history.column("t").unwrap();
            for (k, &time) in times.iter().enumerate() {
                let row = t
                    .iter()
                    .position(|&s| (s - time).abs() < 1e-6)
                    .expect("a row at each frame's time");
                let drawn = positions[k] + rotations[k] * Vector3::from(local);
                let sensed = Vector3::new(columns[0][row], columns[1][row], columns[2][row]);
                worst = worst.max((drawn - sensed).norm());
            }
        }
        assert!(
            worst < 1e-6,
            "{formulation:?}: a marker drawn {worst:e} m from its sensor"
        );
        eprintln!("{formulation:?}: largest distance {worst:e} m");
    }
}

/// A run that fails (the flexible pendulum at h = 2 s fails its first step) is animated up
/// to the failure, marked in the asset's extras and the animation's name, and the file is a
/// valid glTF binary.
#[test]
fn a_failed_run_is_animated_up_to_its_failure_and_marked() {
    let mut scene = model("flexible_pendulum.ron");
    scene.solver.step = 2.0;
    scene.solver.duration = 4.0;
    let recording: Recording = record(&scene, 60.0).unwrap();
    assert_eq!(recording.times, vec![0.0]);
    let (t, message) = recording.failure.clone().expect("the failure kept");
    assert_eq!(t, 2.0);
    let glb = render(&recording, &scene, Format::Glb, 1.0);
    let gltf = gltf::Gltf::from_slice(&glb).expect("a valid glTF binary");
    let extras = gltf
        .as_json()
        .asset
        .extras
        .as_ref()
        .expect("extras")
        .get()
        .to_string();
    assert!(
        extras.contains("\"status\":\"failed\"") && extras.contains("\"failed_at\":2.0"),
        "{extras}"
    );
    assert!(
        extras.contains(&serde_json::to_string(&message).unwrap()[1..20]),
        "{extras}"
    );
    let name = gltf
        .animations()
        .next()
        .unwrap()
        .name()
        .unwrap()
        .to_string();
    assert!(name.contains("failed at t = 2 s"), "{name}");
}

/// The flexible pendulum's morph weights are its modal coordinates times the scale, and the
/// morph targets move the tip node's vertices' centroid by X^t y: drawn tip = sensed tip.
#[test]
fn the_morph_targets_put_the_flexible_tip_where_its_sensors_do() {
    let scene = model("flexible_pendulum.ron");
    let recording = record(&scene, 10.0).unwrap();
    let k = 5; // t = 0.5 s
    let shape = &recording.bodies[0];
    let pose = &recording.poses[k][0];
    assert!(pose.modes.iter().any(|y| y.abs() > 0.0));
    // The tip node's section: the 12 vertices (a general section's circle) at x = 1 m.
    let ring: Vec<usize> = (0..shape.positions.len())
        .filter(|&v| (shape.positions[v].x - 1.0).abs() < 1e-9)
        .collect();
    assert_eq!(ring.len(), 12);
    let shifted = |v: usize| {
        shape.positions[v]
            + shape
                .targets
                .iter()
                .zip(&pose.modes)
                .map(|(t, y)| t[v] * *y)
                .sum::<Vector3<f64>>()
    };
    let deformed = ring.iter().map(|&v| shifted(v)).sum::<Vector3<f64>>() / 12.0;
    let tip = pose.origin + pose.rotation * deformed;
    let names = &recording.sensor_names;
    for (axis, name) in ["tip_x", "tip_y"].iter().enumerate() {
        let sensed = recording.sensors[k][names.iter().position(|n| n == name).unwrap()];
        assert!(
            (tip[axis] - sensed).abs() < 1e-9,
            "{name}: drawn {} sensed {sensed}",
            tip[axis]
        );
    }
}

/// The glb's morph-weight channel of a flexible body holds its modal coordinates times the
/// deformation scale, frame by frame (read back with the `gltf` crate).
#[test]
fn the_morph_weights_are_the_modal_coordinates_times_the_scale() {
    let scene = model("flexible_pendulum.ron");
    let recording = record(&scene, 20.0).unwrap();
    let glb = render(&recording, &scene, Format::Glb, -30.0);
    let gltf = gltf::Gltf::from_slice(&glb).unwrap();
    let blob = gltf.blob.as_deref().unwrap();
    let channel = gltf
        .animations()
        .next()
        .unwrap()
        .channels()
        .find(|c| c.target().property() == gltf::animation::Property::MorphTargetWeights)
        .expect("a weights channel");
    let ReadOutputs::MorphTargetWeights(weights) =
        channel.reader(|_| Some(blob)).read_outputs().unwrap()
    else {
        panic!("weights")
    };
    let weights: Vec<f32> = weights.into_f32().collect();
    let expected: Vec<f64> = recording
        .poses
        .iter()
        .flat_map(|f| f[0].modes.iter().map(|y| -30.0 * y))
        .collect();
    assert_eq!(weights.len(), expected.len());
    assert!(expected.iter().any(|w| w.abs() > 1e-6), "the bar bends");
    for (w, e) in weights.iter().zip(&expected) {
        assert!(
            (f64::from(*w) - e).abs() <= 1e-6 * e.abs().max(1e-6),
            "{w} vs {e}"
        );
    }
}

/// The slider-crank's spring, read back from the glb: its node sits at the wall marker and,
/// turned and scaled along y, reaches the slider's pin where the pin's sensor puts it.
#[test]
fn the_spring_reaches_from_the_wall_to_the_slider_pin() {
    let scene = model("slider_crank.ron");
    let recording = record(&scene, 50.0).unwrap();
    let glb = render(&recording, &scene, Format::Glb, 1.0);
    let gltf = gltf::Gltf::from_slice(&glb).unwrap();
    let blob = gltf.blob.as_deref().unwrap();
    let (mut start, mut turn, mut stretch) = (Vec::new(), Vec::new(), Vec::new());
    let animation = gltf.animations().next().unwrap();
    for channel in animation
        .channels()
        .filter(|c| c.target().node().name() == Some("spring"))
    {
        match channel.reader(|_| Some(blob)).read_outputs().unwrap() {
            ReadOutputs::Translations(t) => {
                start = t.map(|p| Vector3::from(p.map(f64::from))).collect()
            }
            ReadOutputs::Rotations(r) => {
                turn = r
                    .into_f32()
                    .map(|[x, y, z, w]| {
                        UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z).cast::<f64>())
                    })
                    .collect()
            }
            ReadOutputs::Scales(s) => stretch = s.map(|s| f64::from(s[1])).collect(),
            _ => {}
        }
    }
    let x = recording
        .sensor_names
        .iter()
        .position(|n| n == "slider_x")
        .unwrap();
    assert_eq!(start.len(), recording.times.len());
    let wall = scene
        .ground
        .iter()
        .find(|m| m.name == "wall")
        .unwrap()
        .position
        .vec();
    for k in 0..start.len() {
        assert!(
            (start[k] - wall).norm() < 1e-6,
            "frame {k}: starts at {}",
            start[k]
        );
        let end = start[k] + turn[k] * Vector3::new(0.0, stretch[k], 0.0);
        let pin = Vector3::new(recording.sensors[k][x], 0.0, 0.0);
        assert!(
            (end - pin).norm() < 1e-5,
            "frame {k}: ends at {end}, the pin at {pin}"
        );
    }
}

/// A stop flag already set: the start is recorded, then the recording ends, marked
/// interrupted (not failed) in the glb.
#[test]
fn an_interrupted_run_is_animated_up_to_the_stop_and_marked() {
    let scene = model("double_pendulum_3d.ron");
    let stop = std::sync::atomic::AtomicBool::new(true);
    let recording = flexmbd_viewer::record_or_stop(&scene, 60.0, &stop).unwrap();
    assert_eq!(recording.times, vec![0.0]);
    assert!(recording.interrupted);
    let glb = render(&recording, &scene, Format::Glb, 1.0);
    let gltf = gltf::Gltf::from_slice(&glb).unwrap();
    let extras = gltf
        .as_json()
        .asset
        .extras
        .as_ref()
        .unwrap()
        .get()
        .to_string();
    assert!(extras.contains("\"status\":\"interrupted\""), "{extras}");
    let name = gltf
        .animations()
        .next()
        .unwrap()
        .name()
        .unwrap()
        .to_string();
    assert!(name.contains("interrupted at t = 0 s"), "{name}");
}
