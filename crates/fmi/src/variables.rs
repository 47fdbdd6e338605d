//! The FMU's variables, numbered once from a started [`Simulation`] so that the model
//! description and the running instance agree on every value reference:
//!
//! | value reference | variable | causality |
//! |---|---|---|
//! | 0 | `time` (s) | independent |
//! | 1 … | one per value of each named input of the scene, in the scene's order (a `Load`'s F_x … τ_z, a `Driver`'s θ, θ̇, θ̈, a `Road`'s Δx, Δz, a `Scale`'s s_k, s_c) | input |
//! | then | each sensor, in [`Simulation::sensor_names`] order | output |
//! | then | each parameter named at export (`flexmbd fmu --parameter PATH`), a real number of the scene at that `--set` path | parameter (fixed: set before `exitInitializationMode`) |
//!
//! An input variable is named `INPUT.COMPONENT` (e.g. `motor.tau_z`) and starts at the
//! value the input holds before the host sets it ([`Simulation::input_values`]).

use flexmbd::Simulation;
use flexmbd::model::inputs::InputKind;
use flexmbd::model::{ElementQuantity, InterfaceQuantity, Scene, SensorKind};

/// One input value of the FMU: input `input` of the scene, its value `component`.
#[derive(Clone, Debug, PartialEq)]
pub struct InputVariable {
    /// `INPUT.COMPONENT`.
    pub name: String,
    /// Index of the input among the scene's inputs.
    pub input: usize,
    /// Index of the value among the input's values.
    pub component: usize,
    /// The value before the host sets one.
    pub start: f64,
    /// SI unit, when the input's kind fixes one.
    pub unit: Option<&'static str>,
    /// What the value is.
    pub description: String,
}

/// One sensor of the scene as an FMU output.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputVariable {
    /// The sensor's name.
    pub name: String,
    /// SI unit, when the sensor's kind fixes one.
    pub unit: Option<&'static str>,
}

/// A real number of the scene, tunable before the start.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterVariable {
    /// Its `--set` path, e.g. `solver.step`.
    pub name: String,
    /// Its value in the scene.
    pub start: f64,
}

/// Every variable of the FMU of a scene, numbered as the module documentation says.
#[derive(Clone, Debug, PartialEq)]
pub struct Variables {
    /// Input values, value references 1 ….
    pub inputs: Vec<InputVariable>,
    /// Sensors, value references after the inputs'.
    pub outputs: Vec<OutputVariable>,
    /// Parameters, value references after the outputs'.
    pub parameters: Vec<ParameterVariable>,
}

/// The value reference of `time`.
pub const TIME: u32 = 0;

/// What a value reference names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    /// The independent variable.
    Time,
    /// Input value `k` of [`Variables::inputs`].
    Input(usize),
    /// Sensor `k` of [`Variables::outputs`].
    Output(usize),
    /// Parameter `k` of [`Variables::parameters`].
    Parameter(usize),
}

impl Variables {
    /// The variables of `simulation`, a simulation of `scene` (for the sensors' units),
    /// with the real numbers of `scene` at the `--set` paths `parameters` as parameters.
    pub fn of(
        simulation: &Simulation,
        scene: &Scene,
        parameters: &[String],
    ) -> Result<Variables, String> {
        let mut inputs = Vec::new();
        for (index, name) in simulation.input_names().enumerate() {
            let id = simulation
                .input(name)
                .expect("an input named by the simulation is one of its inputs");
            let kind = simulation
                .input_kind(id)
                .expect("an input looked up by name is valid");
            let starts = simulation
                .input_values(id)
                .expect("an input looked up by name is valid");
            for (component, start) in starts.into_iter().enumerate() {
                let (label, unit, what) = component_of(kind, component);
                inputs.push(InputVariable {
                    name: format!("{name}.{label}"),
                    input: index,
                    component,
                    start,
                    unit,
                    description: format!("input {name} ({}): {what}", kind.kind_name()),
                });
            }
        }
        let outputs = simulation
            .sensor_names()
            .iter()
            .map(|name| OutputVariable {
                name: name.clone(),
                unit: scene
                    .sensors
                    .iter()
                    .find(|s| &s.name == name)
                    .and_then(|s| sensor_unit(&s.kind)),
            })
            .collect();
        let parameters = parameters
            .iter()
            .map(|path| {
                let start = scene
                    .real_at(path)
                    .map_err(|e| format!("parameter {path}: {e}"))?;
                Ok(ParameterVariable {
                    name: path.clone(),
                    start,
                })
            })
            .collect::<Result<_, String>>()?;
        Ok(Variables {
            inputs,
            outputs,
            parameters,
        })
    }

    /// The value reference of input value `k`.
    pub fn input_reference(&self, k: usize) -> u32 {
        1 + k as u32
    }

    /// The value reference of output `k`.
    pub fn output_reference(&self, k: usize) -> u32 {
        1 + (self.inputs.len() + k) as u32
    }

    /// The value reference of parameter `k`.
    pub fn parameter_reference(&self, k: usize) -> u32 {
        1 + (self.inputs.len() + self.outputs.len() + k) as u32
    }

    /// The number of value references (`time` included).
    pub fn len(&self) -> usize {
        1 + self.inputs.len() + self.outputs.len() + self.parameters.len()
    }

    /// Whether there is no variable but `time`.
    pub fn is_empty(&self) -> bool {
        self.len() == 1
    }

    /// What value reference `vr` names, `None` when none.
    pub fn reference(&self, vr: u32) -> Option<Reference> {
        let k = vr as usize;
        let (n_in, n_out) = (self.inputs.len(), self.outputs.len());
        match k {
            0 => Some(Reference::Time),
            k if k <= n_in => Some(Reference::Input(k - 1)),
            k if k <= n_in + n_out => Some(Reference::Output(k - 1 - n_in)),
            k if k < self.len() => Some(Reference::Parameter(k - 1 - n_in - n_out)),
            _ => None,
        }
    }
}

/// The label, unit and meaning of value `k` of an input of `kind`
/// ([`flexmbd::model::inputs`]).
fn component_of(kind: &InputKind, k: usize) -> (&'static str, Option<&'static str>, &'static str) {
    const LOAD: [(&str, &str, &str); 6] = [
        ("F_x", "N", "force, ground x"),
        ("F_y", "N", "force, ground y"),
        ("F_z", "N", "force, ground z"),
        ("tau_x", "N.m", "torque, ground x"),
        ("tau_y", "N.m", "torque, ground y"),
        ("tau_z", "N.m", "torque, ground z"),
    ];
    match kind {
        InputKind::Load { .. } => {
            let (label, unit, what) = LOAD[k];
            (label, Some(unit), what)
        }
        // A driver's coordinate is an angle or a length, as its joint says.
        InputKind::Driver { .. } => [
            (
                "theta",
                None,
                "driven coordinate at the end of the next step (rad or m)",
            ),
            ("theta_dot", None, "its rate (rad/s or m/s)"),
            ("theta_ddot", None, "its acceleration (rad/s2 or m/s2)"),
        ][k],
        InputKind::Road { .. } => [
            ("dx", Some("m"), "road profile moved along x"),
            ("dz", Some("m"), "road profile moved up"),
        ][k],
        InputKind::Scale { .. } => [
            ("s_k", None, "stiffness scale factor (>= 0)"),
            ("s_c", None, "damping scale factor (>= 0)"),
        ][k],
    }
}

/// The SI unit of a sensor of `kind`, when the kind fixes one.
fn sensor_unit(kind: &SensorKind) -> Option<&'static str> {
    match kind {
        SensorKind::Position { .. } => Some("m"),
        SensorKind::Velocity { .. } => Some("m/s"),
        SensorKind::Energy => Some("J"),
        SensorKind::Angle { .. } => Some("rad"),
        SensorKind::ElementForce { quantity, .. } => Some(match quantity {
            ElementQuantity::Force => "N",
            ElementQuantity::Length => "m",
        }),
        SensorKind::InterfaceForce { quantity, .. } => Some(match quantity {
            InterfaceQuantity::Force => "N",
            InterfaceQuantity::Moment => "N.m",
        }),
        _ => None,
    }
}
