//! Stiffened bodies drawn as they move: the 2D spin-up beam spun up hard (Ωs = 6 rad/s in
//! Ts = 4 s instead of 15 s, so that its 10 m beam's tip lags by 2.7 m and, under FS0 and
//! FNL2, draws in by 0.43 m), its tip ring's drawn
//! displacement read back from the glTF binary against the run's own tip displacement
//! sensors (in the beam frame). FS0 moves the tip by X y − ½ ē₁ yᵀF y, drawn by the
//! quadratic targets of `flexmbd_viewer::quadratic`; FNL1 and FNL2 stiffen the elastic
//! forces only and are drawn by one target per mode.

use flexmbd::model::{BodyModel, MotionLaw, Scene, Stiffening};
use flexmbd_viewer::{Format, Recording, record, render};
use gltf::animation::util::ReadOutputs;
use nalgebra::Vector3;

fn spin_up(stiffening: Stiffening) -> Scene {
    spin_up_meshed(stiffening, 20)
}

/// The spin-up beam of `elements` elements.
fn spin_up_meshed(stiffening: Stiffening, elements: usize) -> Scene {
    let path = format!(
        "{}/../../models/spin_up_beam_2d.ron",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut scene = Scene::load(path).unwrap();
    scene.solver.stiffening = stiffening;
    let BodyModel::Beam(beam) = &mut scene.bodies[0].model else {
        unreachable!("the spin-up beam is a beam")
    };
    beam.geometry.elements_per_segment = elements;
    scene.solver.duration = 5.0;
    scene.drivers[0].law = MotionLaw::SpinUp {
        omega_s: 6.0,
        t_s: 4.0,
    };
    scene
}

/// The beam's mesh read back from `glb`: base positions, morph targets, and per frame the
/// animated weights.
struct Drawn {
    positions: Vec<Vector3<f64>>,
    targets: Vec<Vec<Vector3<f64>>>,
    weights: Vec<Vec<f64>>,
}

fn read_back(glb: &[u8]) -> Drawn {
    let gltf = gltf::Gltf::from_slice(glb).expect("a valid glTF binary");
    let blob = gltf.blob.as_deref().expect("a BIN chunk");
    let mesh = gltf.meshes().find(|m| m.name() == Some("beam")).unwrap();
    let primitive = mesh.primitives().next().unwrap();
    let reader = primitive.reader(|_| Some(blob));
    let vector = |p: [f32; 3]| Vector3::from(p.map(f64::from));
    let positions = reader.read_positions().unwrap().map(vector).collect();
    let targets: Vec<Vec<Vector3<f64>>> = reader
        .read_morph_targets()
        .map(|(p, _, _)| p.unwrap().map(vector).collect())
        .collect();
    let animation = gltf.animations().next().unwrap();
    let channel = animation
        .channels()
        .find(|c| {
            c.target().node().name() == Some("beam")
                && matches!(
                    c.target().property(),
                    gltf::animation::Property::MorphTargetWeights
                )
        })
        .unwrap();
    let ReadOutputs::MorphTargetWeights(w) = channel.reader(|_| Some(blob)).read_outputs().unwrap()
    else {
        unreachable!("a weights channel")
    };
    let flat: Vec<f64> = w.into_f32().map(f64::from).collect();
    let weights = flat.chunks(targets.len()).map(<[f64]>::to_vec).collect();
    Drawn {
        positions,
        targets,
        weights,
    }
}

/// The mean drawn displacement of the tip ring's vertices (x = 10 m) at each frame, from
/// the first `count` targets.
fn tip_displacements(drawn: &Drawn, count: usize) -> Vec<Vector3<f64>> {
    let tip: Vec<usize> = (0..drawn.positions.len())
        .filter(|&v| (drawn.positions[v].x - 10.0).abs() < 1e-5)
        .collect();
    assert_eq!(tip.len(), 12, "the tip's ring of a circular section");
    drawn
        .weights
        .iter()
        .map(|w| {
            tip.iter()
                .map(|&v| {
                    (0..count)
                        .map(|m| w[m] * drawn.targets[m][v])
                        .sum::<Vector3<f64>>()
                })
                .sum::<Vector3<f64>>()
                / tip.len() as f64
        })
        .collect()
}

/// The largest gap, over the frames, between the drawn tip displacement and the sensed
/// one (`tip_ux`, `tip_uy`), and the largest sensed displacement.
fn gap(recording: &Recording, drawn: &[Vector3<f64>]) -> (f64, f64) {
    let column = |name: &str| {
        recording
            .sensor_names
            .iter()
            .position(|n| n == name)
            .unwrap()
    };
    let (ux, uy) = (column("tip_ux"), column("tip_uy"));
    let (mut worst, mut largest) = (0.0f64, 0.0f64);
    for (row, d) in recording.sensors.iter().zip(drawn) {
        let sensed = Vector3::new(row[ux], row[uy], 0.0);
        worst = worst.max((d - sensed).norm());
        largest = largest.max(sensed.norm());
    }
    (worst, largest)
}

/// FS0: the beam of 4 bending modes on 20 elements gets 4 · 5 / 2 = 10 quadratic targets
/// by pairs (fewer than its 20 shortening nodes), on 6 elements 6 by nodes (fewer than 10
/// pairs); read back from the glb at each of 301 frames the tip ring moves as the run's
/// tip displacement sensors (which include the shortening) to f32 round-off, at a tip
/// deflection of 2.7 m and a shortening of 0.43 m, which the modes' targets alone miss.
#[test]
fn a_foreshortened_beam_is_drawn_shortened_as_its_tip_sensors() {
    for (elements, quadratic) in [(20, 10), (6, 6)] {
        let scene = spin_up_meshed(Stiffening::Foreshortening, elements);
        let recording = record(&scene, 60.0).unwrap();
        assert!(recording.failure.is_none(), "{:?}", recording.failure);
        let n = recording.poses[0][0].modes.len();
        assert_eq!(n, 4, "FS0 keeps the bending modes only");
        let shape = &recording.bodies[0];
        assert_eq!(shape.quadratic.len(), quadratic);
        assert_eq!(shape.targets.len(), n + quadratic);
        let drawn = read_back(&render(&recording, &scene, Format::Glb, 1.0));
        assert_eq!(drawn.weights.len(), recording.times.len());
        let (worst, largest) = gap(&recording, &tip_displacements(&drawn, drawn.targets.len()));
        let (linear, _) = gap(&recording, &tip_displacements(&drawn, n));
        eprintln!(
            "FS0, {elements} elements: largest tip displacement {largest:.3} m, drawn within \
             {worst:.2e} m (modes' targets alone: {linear:.3} m off)"
        );
        assert!(largest > 2.0, "a large deformation: {largest} m");
        assert!(linear > 0.4, "the shortening shows: {linear} m");
        assert!(worst < 1e-6 * largest, "drawn {worst:e} m from the sensors");
    }
}

/// FNL1 (4 bending + 2 axial modes) and FNL2 (4 bending modes and the complete axial basis,
/// 24) move points linearly in y: one target per mode and no quadratic one, and the tip
/// ring read back from the glb moves as the tip sensors to f32 round-off.
#[test]
fn fnl1_and_fnl2_beams_are_linear_in_their_modes_and_drawn_so() {
    for (stiffening, modes) in [(Stiffening::Fnl1, 6), (Stiffening::Fnl2, 24)] {
        let scene = spin_up(stiffening);
        let recording = record(&scene, 60.0).unwrap();
        assert!(recording.failure.is_none(), "{:?}", recording.failure);
        let shape = &recording.bodies[0];
        assert_eq!(recording.poses[0][0].modes.len(), modes);
        assert!(shape.quadratic.is_empty());
        assert_eq!(shape.targets.len(), modes);
        let drawn = read_back(&render(&recording, &scene, Format::Glb, 1.0));
        let (worst, largest) = gap(&recording, &tip_displacements(&drawn, modes));
        eprintln!(
            "{stiffening:?}: largest tip displacement {largest:.3} m, drawn within {worst:.2e} m"
        );
        assert!(largest > 2.0, "a large deformation: {largest} m");
        assert!(worst < 1e-6 * largest, "drawn {worst:e} m from the sensors");
    }
}
