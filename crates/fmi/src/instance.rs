//! One FMU instance in safe Rust: the scene read from the FMU's resources, its
//! [`Simulation`], the input values the master sets, the state machine of FMI 3.0
//! co-simulation (instantiated → initialisation mode → step mode → terminated), and the
//! checks that turn a bad call into an error message instead of a loop or a panic. The C
//! API ([`crate::fmi3`]) is a thin layer over this.
//!
//! - **Inputs** (value references: [`crate::variables`]) are checked when set: a NaN or an
//!   infinite value, or a value the scene's input refuses (a negative scale), is an error
//!   and changes nothing. A value set is handed to the simulation at once
//!   ([`Simulation::set_input`]) and holds through the steps that follow, as in the
//!   library.
//! - **doStep** from the current communication point t_c over h_c takes n = h_c / h steps
//!   of the scene's own step h. h_c must be positive and finite, and a whole number of
//!   steps within a relative 10⁻⁹ (the rule of a run's duration); t_c must be the current
//!   time within h/2. A failed step leaves the simulation at its last good state and the
//!   instance in an error state: every later `doStep` is refused until `reset`.
//! - **Inputs set before `exitInitializationMode`** hold from t = 0: the simulation starts
//!   with them ([`Simulation::with_inputs`]).
//! - **FMU state** is a checkpoint of the integrator ([`Simulation::checkpoint`]) with
//!   the input values: restoring one returns the inputs to their saved values.

use std::path::Path;

use flexmbd::integrators::Checkpoint;
use flexmbd::model::Scene;
use flexmbd::model::inputs::InputKind;
use flexmbd::simulation::MAX_STEPS;
use flexmbd::{Error, Simulation};

use crate::variables::{Reference, Variables};

/// The scene's file in the FMU's `resources/`.
pub const SCENE_FILE: &str = "scene.ron";
/// The parameters' `--set` paths in the FMU's `resources/`, one a line (absent: none).
pub const PARAMETERS_FILE: &str = "parameters.txt";

/// A refused call: what the logger is told.
#[derive(Clone, Debug, PartialEq)]
pub struct CallError(pub String);

impl std::fmt::Display for CallError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

fn refuse<T>(message: impl Into<String>) -> Result<T, CallError> {
    Err(CallError(message.into()))
}

/// Where an instance is in its life (FMI 3.0 co-simulation states).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Made, not yet initialising: inputs may be set.
    Instantiated,
    /// Between `enterInitializationMode` and `exitInitializationMode`.
    Initialization,
    /// Stepping.
    Step,
    /// After `terminate`.
    Terminated,
    /// A step failed: only reading, `terminate`, `reset` and `freeInstance` are allowed.
    Failed,
}

/// A saved state of an instance ([`Instance::state`]); serialised as RON text
/// ([`FmuState::to_bytes`]), which keeps every `f64` exactly.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct FmuState {
    checkpoint: Checkpoint,
    input_values: Vec<f64>,
    touched: Vec<bool>,
}

impl FmuState {
    /// The state as bytes (`serializeFMUState`).
    pub fn to_bytes(&self) -> Result<Vec<u8>, CallError> {
        ron::to_string(self)
            .map(String::into_bytes)
            .map_err(|e| CallError(format!("cannot serialise the FMU state: {e}")))
    }

    /// A state from bytes of [`to_bytes`](FmuState::to_bytes) (`deserializeFMUState`);
    /// anything else is refused.
    pub fn from_bytes(bytes: &[u8]) -> Result<FmuState, CallError> {
        let text = std::str::from_utf8(bytes)
            .map_err(|_| CallError("not a serialised state of this FMU (not UTF-8)".into()))?;
        ron::from_str(text)
            .map_err(|e| CallError(format!("not a serialised state of this FMU: {e}")))
    }
}

/// One instance of the FMU (see the module documentation).
pub struct Instance {
    scene: Scene,
    simulation: Simulation,
    variables: Variables,
    /// The value of each input variable, as last set (or its start value).
    input_values: Vec<f64>,
    /// Per input of the scene: its first input variable and its number of values.
    input_ranges: Vec<(usize, usize)>,
    /// Per input of the scene: set by the master since the start (a driver follows its
    /// law until then).
    touched: Vec<bool>,
    /// Per input of the scene: a driver's.
    drivers: Vec<bool>,
    sensors: Vec<f64>,
    sensors_fresh: bool,
    mode: Mode,
    /// Each parameter's value, as last set (or the scene's).
    parameter_values: Vec<f64>,
    /// A parameter was set: the simulation starts again from the changed scene.
    parameters_changed: bool,
}

/// The instantiation token of the FMU of a scene whose `scene.ron` is `text` and whose
/// parameters are `parameters`: FNV-1a (64 bits) of both, so that an FMU's binary refuses
/// another FMU's resources.
pub fn token(text: &str, parameters: &[String]) -> String {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let tail = parameters
        .iter()
        .map(|p| format!("\n{p}"))
        .collect::<String>();
    for byte in text.bytes().chain(tail.bytes()) {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{{flexmbd-{hash:016x}}}")
}

impl Instance {
    /// Read `scene.ron` from the FMU's resource directory `resources`, check it against
    /// the instantiation `token` and start its simulation.
    pub fn from_resources(resources: &Path, token_given: &str) -> Result<Instance, CallError> {
        let path = resources.join(SCENE_FILE);
        let text = std::fs::read_to_string(&path).map_err(|e| {
            CallError(format!(
                "cannot read the scene {}: {e} (is the resource path the FMU's resources/ folder?)",
                path.display()
            ))
        })?;
        let parameters: Vec<String> = match std::fs::read_to_string(resources.join(PARAMETERS_FILE))
        {
            Ok(list) => list.lines().map(String::from).collect(),
            Err(_) => Vec::new(),
        };
        let expected = token(&text, &parameters);
        if token_given != expected {
            return refuse(format!(
                "instantiation token {token_given} is not this FMU's ({expected}): the model description and {} differ",
                path.display()
            ));
        }
        let scene = Scene::load(&path).map_err(|e| CallError(e.to_string()))?;
        Instance::new(scene, &parameters)
    }

    /// An instance of `scene` (validated), at t = 0, with the real numbers at the `--set`
    /// paths `parameters` as parameters.
    pub fn new(scene: Scene, parameters: &[String]) -> Result<Instance, CallError> {
        let simulation = Simulation::new(&scene).map_err(|e| CallError(e.to_string()))?;
        let variables = Variables::of(&simulation, &scene, parameters).map_err(CallError)?;
        let mut input_ranges: Vec<(usize, usize)> = Vec::new();
        for (k, v) in variables.inputs.iter().enumerate() {
            match input_ranges.get_mut(v.input) {
                Some(range) => range.1 += 1,
                None => input_ranges.push((k, 1)),
            }
        }
        let drivers = simulation
            .input_names()
            .map(|name| {
                let kind = simulation
                    .input(name)
                    .and_then(|id| simulation.input_kind(id));
                matches!(kind, Ok(InputKind::Driver { .. }))
            })
            .collect();
        Ok(Instance {
            parameter_values: variables.parameters.iter().map(|p| p.start).collect(),
            parameters_changed: false,
            drivers,
            input_values: variables.inputs.iter().map(|v| v.start).collect(),
            touched: vec![false; input_ranges.len()],
            input_ranges,
            sensors: vec![0.0; variables.outputs.len()],
            sensors_fresh: false,
            variables,
            simulation,
            scene,
            mode: Mode::Instantiated,
        })
    }

    /// The FMU's variables.
    pub fn variables(&self) -> &Variables {
        &self.variables
    }

    /// Where the instance is in its life.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The simulation, for tests and measurements.
    pub fn simulation(&self) -> &Simulation {
        &self.simulation
    }

    /// `enterInitializationMode`: from the instantiated state only. The start time must
    /// be 0 (the scene starts there).
    pub fn enter_initialization(&mut self, start_time: f64) -> Result<(), CallError> {
        self.require(&[Mode::Instantiated], "enterInitializationMode")?;
        if start_time != 0.0 {
            return refuse(format!(
                "startTime = {start_time}: the scene's simulation starts at t = 0"
            ));
        }
        self.mode = Mode::Initialization;
        Ok(())
    }

    /// `exitInitializationMode`: step mode follows. When inputs were set before, the
    /// simulation starts again with them ([`Simulation::with_inputs`]): its consistent
    /// initial conditions (and static equilibrium, if the scene asks for one) hold them,
    /// as with the same values written into the scene.
    pub fn exit_initialization(&mut self) -> Result<(), CallError> {
        self.require(&[Mode::Initialization], "exitInitializationMode")?;
        if self.touched.iter().any(|&t| t) || self.parameters_changed {
            let names: Vec<String> = (0..self.input_ranges.len())
                .map(|input| self.input_name(input).to_string())
                .collect();
            let inputs: Vec<(&str, &[f64])> = (0..self.input_ranges.len())
                .filter(|&input| self.touched[input])
                .map(|input| {
                    let (first, n) = self.input_ranges[input];
                    (names[input].as_str(), &self.input_values[first..first + n])
                })
                .collect();
            let sets: Vec<(String, String)> = self
                .variables
                .parameters
                .iter()
                .zip(&self.parameter_values)
                .map(|(p, v)| (p.name.clone(), format!("{v:?}")))
                .collect();
            let mut scene = self.scene.clone();
            scene
                .apply_sets(&sets)
                .map_err(|e| CallError(e.to_string()))?;
            self.simulation =
                Simulation::with_inputs(&scene, &inputs).map_err(|e| CallError(e.to_string()))?;
            self.sensors_fresh = false;
        }
        self.mode = Mode::Step;
        Ok(())
    }

    /// The name of input `input` of the scene.
    fn input_name(&self, input: usize) -> &str {
        let (first, _) = self.input_ranges[input];
        self.variables.inputs[first]
            .name
            .rsplit_once('.')
            .map_or("", |(name, _)| name)
    }

    /// `terminate`.
    pub fn terminate(&mut self) -> Result<(), CallError> {
        self.require(&[Mode::Step, Mode::Failed], "terminate")?;
        self.mode = Mode::Terminated;
        Ok(())
    }

    /// `reset`: a new simulation of the same scene, inputs at their start values.
    pub fn reset(&mut self) -> Result<(), CallError> {
        let parameters: Vec<String> = self
            .variables
            .parameters
            .iter()
            .map(|p| p.name.clone())
            .collect();
        *self = Instance::new(self.scene.clone(), &parameters)?;
        Ok(())
    }

    fn require(&self, modes: &[Mode], call: &str) -> Result<(), CallError> {
        if modes.contains(&self.mode) {
            return Ok(());
        }
        let after = if self.mode == Mode::Failed {
            " (a step failed: reset or free the instance)"
        } else {
            ""
        };
        refuse(format!(
            "{call} is not allowed in the {:?} state{after}",
            self.mode
        ))
    }

    /// The values of the variables `vrs`, into `values`.
    pub fn get(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), CallError> {
        if vrs.len() != values.len() {
            return refuse(format!(
                "{} value references but room for {} values",
                vrs.len(),
                values.len()
            ));
        }
        for (&vr, value) in vrs.iter().zip(values.iter_mut()) {
            *value = match self.reference(vr)? {
                Reference::Time => self.simulation.time(),
                Reference::Input(k) => self.input_values[k],
                Reference::Parameter(k) => self.parameter_values[k],
                Reference::Output(k) => {
                    if !self.sensors_fresh {
                        self.simulation.read_sensors(&mut self.sensors);
                        self.sensors_fresh = true;
                    }
                    self.sensors[k]
                }
            };
        }
        Ok(())
    }

    /// Set the input variables `vrs` to `values`, each checked (finite, accepted by its
    /// input) before any is set: a refused call changes nothing.
    pub fn set(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), CallError> {
        self.require(
            &[Mode::Instantiated, Mode::Initialization, Mode::Step],
            "setFloat64",
        )?;
        if vrs.len() != values.len() {
            return refuse(format!(
                "{} value references but {} values",
                vrs.len(),
                values.len()
            ));
        }
        let mut candidate = self.input_values.clone();
        let mut changed = vec![false; self.input_ranges.len()];
        let mut parameters = self.parameter_values.clone();
        let mut parameters_changed = false;
        for (&vr, &value) in vrs.iter().zip(values) {
            let k = match self.reference(vr)? {
                Reference::Input(k) => k,
                Reference::Parameter(k) => {
                    let name = &self.variables.parameters[k].name;
                    if self.mode == Mode::Step {
                        return refuse(format!(
                            "parameter {name} (value reference {vr}) is fixed: it is set before exitInitializationMode"
                        ));
                    }
                    if !value.is_finite() {
                        return refuse(format!(
                            "{name} (value reference {vr}) = {value}: must be finite"
                        ));
                    }
                    parameters[k] = value;
                    parameters_changed = true;
                    continue;
                }
                _ => {
                    return refuse(format!(
                        "value reference {vr} is not an input or a parameter: it cannot be set"
                    ));
                }
            };
            let variable = &self.variables.inputs[k];
            if !value.is_finite() {
                return refuse(format!(
                    "{} (value reference {vr}) = {value}: must be finite",
                    variable.name
                ));
            }
            candidate[k] = value;
            changed[variable.input] = true;
        }
        // Each changed input whole, checked by the simulation; those already handed over
        // are given their values back if a later one is refused (a driver never set
        // before cannot return to its law: its values are checked against a wide position
        // range, rarely refused).
        let before = self.input_values.clone();
        let changed_inputs: Vec<usize> = (0..changed.len()).filter(|&i| changed[i]).collect();
        for (done, &input) in changed_inputs.iter().enumerate() {
            if let Err(e) = self.push_input(input, &candidate) {
                for &other in &changed_inputs[..done] {
                    if self.touched[other] || !self.drivers[other] {
                        let _ = self.push_input(other, &before);
                    }
                }
                return refuse(e.to_string());
            }
        }
        for (input, &c) in changed.iter().enumerate() {
            self.touched[input] |= c;
        }
        self.input_values = candidate;
        self.parameter_values = parameters;
        self.parameters_changed |= parameters_changed;
        self.sensors_fresh = false;
        Ok(())
    }

    /// Hand input `input` its values from `values` (all input variables).
    fn push_input(&mut self, input: usize, values: &[f64]) -> Result<(), Error> {
        let (first, n) = self.input_ranges[input];
        let id = self.simulation.input(self.input_name(input))?;
        self.simulation.set_input(id, &values[first..first + n])
    }

    fn reference(&self, vr: u32) -> Result<Reference, CallError> {
        self.variables.reference(vr).ok_or_else(|| {
            CallError(format!(
                "unknown value reference {vr}: this FMU's are 0 to {}",
                self.variables.len() - 1
            ))
        })
    }

    /// `doStep` from `t_c` over `h_c` (see the module documentation). On a failed step the
    /// error is returned and the time of the last good state is [`Simulation::time`].
    pub fn do_step(&mut self, t_c: f64, h_c: f64) -> Result<(), CallError> {
        self.require(&[Mode::Step], "doStep")?;
        let h = self.simulation.step_size();
        if !(h_c.is_finite() && h_c > 0.0) {
            return refuse(format!(
                "communicationStepSize = {h_c}: must be positive and finite"
            ));
        }
        let time = self.simulation.time();
        if !(t_c.is_finite() && (t_c - time).abs() <= 0.5 * h) {
            return refuse(format!(
                "currentCommunicationPoint = {t_c} s, but the FMU is at t = {time} s"
            ));
        }
        let ratio = h_c / h;
        let n = ratio.round();
        if n < 1.0 || (ratio - n).abs() > 1e-9 * n || n > MAX_STEPS as f64 {
            return refuse(format!(
                "communicationStepSize = {h_c} s is not a whole number (1 to {MAX_STEPS}) of the scene's steps h = {h} s ({ratio} steps)"
            ));
        }
        self.sensors_fresh = false;
        for _ in 0..n as u64 {
            if let Err(e) = self.simulation.step() {
                self.mode = Mode::Failed;
                return refuse(format!(
                    "the step from t = {} s failed: {e}",
                    self.simulation.time()
                ));
            }
        }
        Ok(())
    }

    /// The current state (integrator and inputs), to return to with
    /// [`set_state`](Instance::set_state).
    pub fn state(&self) -> FmuState {
        FmuState {
            checkpoint: self.simulation.checkpoint(),
            input_values: self.input_values.clone(),
            touched: self.touched.clone(),
        }
    }

    /// Return to `state`, a state of this instance or of another instance of the same
    /// FMU. The inputs return to their saved values, except a driver input the master
    /// had not set when the state was saved: it keeps what it has now (a driver set once
    /// does not return to its law).
    pub fn set_state(&mut self, state: &FmuState) -> Result<(), CallError> {
        let size = (
            self.simulation.n_coordinates(),
            self.simulation.n_constraints(),
        );
        if state.input_values.len() != self.input_values.len()
            || state.touched.len() != self.touched.len()
            || state.checkpoint.size() != size
        {
            return refuse("the FMU state was taken from another FMU");
        }
        self.simulation.restore(&state.checkpoint);
        for input in 0..self.input_ranges.len() {
            if state.touched[input] || !self.drivers[input] {
                self.push_input(input, &state.input_values)
                    .map_err(|e| CallError(e.to_string()))?;
                let (first, n) = self.input_ranges[input];
                self.input_values[first..first + n]
                    .copy_from_slice(&state.input_values[first..first + n]);
                self.touched[input] |= state.touched[input];
            }
        }
        self.sensors_fresh = false;
        if self.mode == Mode::Failed {
            self.mode = Mode::Step;
        }
        Ok(())
    }
}
