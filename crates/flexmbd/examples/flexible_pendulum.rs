//! A flexible pendulum built in code (no scene file): a 1 m steel bar of 10 Euler–Bernoulli
//! elements reduced to 4 fixed-interface normal modes (docs/methods.md §1.3), pinned at one end
//! and released horizontal under gravity — `models/flexible_pendulum.ron` written with the
//! builders of `flexmbd::model::builder`. It prints the tip's path and the energy, which the
//! trapezoidal rule of ALI3-P keeps (docs/methods.md §5.1).
//!
//! Run: `cargo run --release -p flexmbd --example flexible_pendulum`

use flexmbd::Simulation;
use flexmbd::core::Dim;
use flexmbd::fe::{BeamBodySpec, Material, Section};
use flexmbd::model::builder::{BodyBuilder, SceneBuilder};
use flexmbd::model::{Axis, GROUND, Joint, JointKind, Sensor, SensorKind, Solver};

fn main() -> Result<(), flexmbd::Error> {
    // The bar: steel, 1 kg over 1 m (A = m/(ρL)), a solid circular section.
    let steel = Material {
        young_modulus: 2.1e11,
        density: 7850.0,
        poisson_ratio: Some(0.3),
        shear_modulus: None,
    };
    let section = Section::General {
        area: 1.2739e-4,
        iy: 1.2914e-9,
        iz: 1.2914e-9,
        torsion_j: 2.5828e-9,
    };
    let mut bar = BeamBodySpec::straight(Dim::Planar, steel, section, 1.0, 10);
    bar.normal_modes = 4;
    let scene = SceneBuilder::new("flexible pendulum", Dim::Planar)
        .gravity([0.0, -9.81, 0.0])
        .ground_marker("O", [0.0, 0.0, 0.0])
        .body(
            BodyBuilder::beam("bar", bar)
                .marker("pin", [0.0, 0.0, 0.0])
                .marker("tip", [1.0, 0.0, 0.0]),
        )
        .joint(Joint::new(
            "pin",
            JointKind::Revolute { axis: None },
            (GROUND, "O"),
            ("bar", "pin"),
        ))
        .sensor(Sensor::new(
            "tip_x",
            SensorKind::position("bar", "tip", Axis::X),
        ))
        .sensor(Sensor::new(
            "tip_y",
            SensorKind::position("bar", "tip", Axis::Y),
        ))
        .sensor(Sensor::new("energy", SensorKind::Energy))
        .solver(Solver::new(1e-3, 2.0))
        .build()?;

    let mut simulation = Simulation::new(&scene)?;
    let mut sensors = vec![0.0; simulation.sensor_names().len()];
    println!(
        "{:>6} {:>10} {:>10} {:>12}",
        "t (s)", "tip x (m)", "tip y (m)", "energy (J)"
    );
    for k in 0..=10 {
        simulation.advance_to(0.2 * k as f64)?;
        simulation.read_sensors(&mut sensors);
        println!(
            "{:6.2} {:10.5} {:10.5} {:12.6}",
            simulation.time(),
            sensors[0],
            sensors[1],
            sensors[2]
        );
    }
    Ok(())
}
