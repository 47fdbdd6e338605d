//! The road under a vehicle's tyres drawn as a strip of ground, read back from the glTF.

use flexmbd::model::Scene;
use flexmbd::model::roads::Profile;
use flexmbd_viewer::{Format, record, render};
use nalgebra::Vector3;

/// The Iltis vehicle on its ramp road (a table: up 0.1 m over 3.97–4.97 m, a step down at
/// 10.97 m), run 1 s: the glb has one node `road`, marked as ground (its extras), not
/// animated, whose every vertex lies on the profile z = h(x) (a step's vertical face at
/// either height), reaching from behind the rear wheels to beyond the ramp's top at
/// 4.97 m, across both wheel tracks; a scene without tyres has no such node.
#[test]
fn the_ramp_is_drawn_under_the_wheels_on_its_profile() {
    let path = format!(
        "{}/../../models/iltis_vehicle.ron",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut scene = Scene::load(path).unwrap();
    scene.solver.duration = 1.0;
    let profile = scene.roads[0].profile.clone();
    assert!(matches!(profile, Profile::Table { .. }));
    let recording = record(&scene, 20.0).unwrap();
    assert!(recording.failure.is_none());
    let glb = render(&recording, &scene, Format::Glb, 1.0);
    let gltf = gltf::Gltf::from_slice(&glb).unwrap();
    let blob = gltf.blob.as_deref().unwrap();
    let road = gltf.nodes().find(|n| n.name() == Some("road")).unwrap();
    let extras = road.extras().as_ref().unwrap().get();
    assert!(extras.contains("\"ground\":true"), "{extras}");
    let animation = gltf.animations().next().unwrap();
    assert!(
        animation
            .channels()
            .all(|c| c.target().node().index() != road.index())
    );
    let primitive = road.mesh().unwrap().primitives().next().unwrap();
    let positions: Vec<Vector3<f64>> = primitive
        .reader(|_| Some(blob))
        .read_positions()
        .unwrap()
        .map(|p| Vector3::from(p.map(f64::from)))
        .collect();
    let mut worst: f64 = 0.0;
    for p in &positions {
        let (below, above) = (profile.eval(p.x - 1e-6).0, profile.eval(p.x + 1e-6).0);
        worst = worst.max((p.z - below).abs().min((p.z - above).abs()));
    }
    assert!(worst < 1e-6, "a vertex {worst:e} m off the profile");
    let least = |f: fn(&Vector3<f64>) -> f64| positions.iter().map(f).fold(f64::INFINITY, f64::min);
    let most =
        |f: fn(&Vector3<f64>) -> f64| positions.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
    let top = positions
        .iter()
        .filter(|p| (p.z - 0.1).abs() < 1e-6)
        .count();
    eprintln!(
        "road: x {:.2}..{:.2} m, y {:.2}..{:.2} m, {} vertices, {top} on the ramp's top",
        least(|p| p.x),
        most(|p| p.x),
        least(|p| p.y),
        most(|p| p.y),
        positions.len()
    );
    assert!(
        least(|p| p.x) < -2.0 && most(|p| p.x) > 4.97,
        "the strip covers the ramp"
    );
    assert!(
        least(|p| p.y) < -0.8 && most(|p| p.y) > 0.8,
        "both wheel tracks"
    );
    assert!(top >= 4, "the ramp's top drawn");

    let path = format!(
        "{}/../../models/double_pendulum_3d.ron",
        env!("CARGO_MANIFEST_DIR")
    );
    let scene = Scene::load(path).unwrap();
    let mut short = scene.clone();
    short.solver.duration = 0.1;
    let recording = record(&short, 20.0).unwrap();
    assert!(recording.roads.is_empty());
}
