//! The double four-bar (IFToMM A02, N = 2; docs/scenes.md §1) built with flexmbd's builders:
//! the scene of `models/double_four_bar.ron` in code. Shared with the workspace's builder test
//! (`crates/flexmbd/tests/builder.rs`), which checks that it equals the model file.

use std::f64::consts::FRAC_PI_2;

use flexmbd::core::Dim;
use flexmbd::fe::{BeamBodySpec, Dof, Material, NodeDof, Section};
use flexmbd::model::builder::{BodyBuilder, SceneBuilder};
use flexmbd::model::{
    Axis, GROUND, Joint, JointKind, ModelError, Orientation, Scene, Sensor, SensorKind, Solver,
};

/// One 1 m steel bar of the four-bar: 10 elements, frame clamped at the first pin, the second
/// pin's two translations as static modes, 2 normal modes (scenes.md §1).
fn bar_spec() -> BeamBodySpec {
    let mut spec = BeamBodySpec::straight(Dim::Planar, steel(), bar_section(), 1.0, 10);
    spec.boundary = vec![
        NodeDof {
            node: 10,
            dof: Dof::Ux,
        },
        NodeDof {
            node: 10,
            dof: Dof::Uy,
        },
    ];
    spec.normal_modes = 2;
    spec
}

/// Steel as scenes.md §1 gives it.
fn steel() -> Material {
    Material {
        young_modulus: 2.1e11,
        density: 7850.0,
        poisson_ratio: Some(0.3),
        shear_modulus: None,
    }
}

/// 1 kg over 1 m of steel: A = m/(ρL), a solid circle (scenes.md §1).
fn bar_section() -> Section {
    Section::General {
        area: 1.2739e-4,
        iy: 1.2914e-9,
        iz: 1.2914e-9,
        torsion_j: 2.5828e-9,
    }
}

/// A bar at `origin` turned by `angle`, rigid, with its pins A and B and a velocity guess.
fn bar(
    name: &str,
    origin: [f64; 3],
    angle: f64,
    linear: [f64; 3],
    angular: [f64; 3],
) -> BodyBuilder {
    BodyBuilder::beam(name, bar_spec())
        .origin(origin)
        .orientation(Orientation::Angle(angle))
        .flexible(false)
        .marker("A", [0.0, 0.0, 0.0])
        .marker("B", [1.0, 0.0, 0.0])
        .velocity(linear, angular)
}

/// The double four-bar (IFToMM A02, N = 2; scenes.md §1) in code.
pub fn double_four_bar() -> Result<Scene, ModelError> {
    let revolute = || JointKind::Revolute { axis: None };
    let crank = [0.0, 0.0, -1.0];
    let still = [0.0; 3];
    SceneBuilder::new("double four-bar", Dim::Planar)
        .description(
            "IFToMM A02 with N = 2: three cranks and two couplers, 7 revolute joints, mobility 1",
        )
        .gravity([0.0, -9.81, 0.0])
        .ground_marker("A0", [0.0, 0.0, 0.0])
        .ground_marker("A1", [1.0, 0.0, 0.0])
        .ground_marker("A2", [2.0, 0.0, 0.0])
        .body(bar("crank1", [0.0, 0.0, 0.0], FRAC_PI_2, still, crank))
        .body(bar(
            "coupler1",
            [0.0, 1.0, 0.0],
            0.0,
            [1.0, 0.0, 0.0],
            still,
        ))
        .body(bar("crank2", [1.0, 0.0, 0.0], FRAC_PI_2, still, crank))
        .body(bar(
            "coupler2",
            [1.0, 1.0, 0.0],
            0.0,
            [1.0, 0.0, 0.0],
            still,
        ))
        .body(bar("crank3", [2.0, 0.0, 0.0], FRAC_PI_2, still, crank))
        .joint(Joint::new(
            "A0",
            revolute(),
            (GROUND, "A0"),
            ("crank1", "A"),
        ))
        .joint(Joint::new(
            "B0",
            revolute(),
            ("crank1", "B"),
            ("coupler1", "A"),
        ))
        .joint(Joint::new(
            "A1",
            revolute(),
            (GROUND, "A1"),
            ("crank2", "A"),
        ))
        .joint(Joint::new(
            "B1a",
            revolute(),
            ("crank2", "B"),
            ("coupler1", "B"),
        ))
        .joint(Joint::new(
            "B1b",
            revolute(),
            ("crank2", "B"),
            ("coupler2", "A"),
        ))
        .joint(Joint::new(
            "A2",
            revolute(),
            (GROUND, "A2"),
            ("crank3", "A"),
        ))
        .joint(Joint::new(
            "B2",
            revolute(),
            ("crank3", "B"),
            ("coupler2", "B"),
        ))
        .sensor(Sensor::new(
            "B0_x",
            SensorKind::position("crank1", "B", Axis::X),
        ))
        .sensor(Sensor::new(
            "B0_y",
            SensorKind::position("crank1", "B", Axis::Y),
        ))
        .sensor(Sensor::new("energy", SensorKind::Energy))
        .solver(Solver::new(1e-3, 5.0).output_interval(0.01))
        .build()
}
