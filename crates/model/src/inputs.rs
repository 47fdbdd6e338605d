//! Named inputs: values a host program sets between the steps of a running simulation
//! (a driver's steering, a road under the wheel, a torque, a spring's stiffness), declared
//! in the scene so that everything they touch is resolved once, when the scene is
//! compiled, and the per-step path neither allocates nor looks a name up.
//!
//! An [`Input`] names what it moves ([`InputKind`]):
//!
//! | kind | values the host sets | before the host sets any |
//! |---|---|---|
//! | `Load { force }` | F_x, F_y, F_z (N), τ_x, τ_y, τ_z (N·m), ground components, of the `Load` force element `force` | the element's `force` and `torque` |
//! | `Driver { driver }` | θ, θ̇, θ̈ of the driven coordinate (rad or m, relative to t = 0, as a law's); rate and acceleration may be left out (0) | the driver's law |
//! | `Road { road }` | Δx, Δz (m): the road's profile moved along x and up, h'(x) = h(x − Δx) + Δz | 0, 0 |
//! | `Scale { force }` | s_k, s_c ≥ 0: the stiffness and damping of the `SpringDamper` or `Link` `force` multiplied by them (a link: its spring and damper laws) | 1, 1 |
//!
//! A driver input's values hold at the end of the step that follows: ALI3-P evaluates the
//! constraints of a step at its end time t_{n+1} only (the position, velocity and
//! acceleration equations of its projections), so the host that sets θ(t_{n+1}),
//! θ̇(t_{n+1}), θ̈(t_{n+1}) before stepping from t_n reproduces the driver with that law
//! (`crates/flexmbd/tests/inputs.rs`). Values, rates and accelerations that do not agree
//! (a value that jumps with a zero rate) are followed all the same, and the velocity
//! projection then makes the motion consistent with the rate.
//!
//! The values live in one shared table of atomics ([`InputValues`], `Relaxed`: a plain
//! load and store on every processor flexmbd runs on) that the compiled force elements and
//! drivers read ([`InputSlots`]) and the simulation writes: one allocation when the scene
//! is compiled, none afterwards.

use std::collections::HashSet;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use flexmbd_core::{Dim, InvalidValue};
use flexmbd_fe::bounds::Range;
use serde::{Deserialize, Serialize};

use crate::error::ModelError;
use crate::scene::{Force, MotionLaw, Scene};

/// A named input (see the module documentation).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Input {
    /// Name, unique among inputs; the host looks it up once.
    pub name: String,
    /// What it sets.
    pub kind: InputKind,
}

/// What an input sets (the values of each kind: the module documentation).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum InputKind {
    /// The force and torque of a `Load` force element (6 values).
    Load {
        /// The `Load` element's name.
        force: String,
    },
    /// The driven coordinate of a driver, instead of its law (1 to 3 values).
    Driver {
        /// The driver's name.
        driver: String,
    },
    /// A road's offset along x and up (2 values).
    Road {
        /// The road's name.
        road: String,
    },
    /// Scale factors of a `SpringDamper`'s or a `Link`'s stiffness and damping (2 values).
    Scale {
        /// The element's name.
        force: String,
    },
}

impl InputKind {
    /// The variant's name, for messages.
    pub fn kind_name(&self) -> &'static str {
        match self {
            InputKind::Load { .. } => "Load",
            InputKind::Driver { .. } => "Driver",
            InputKind::Road { .. } => "Road",
            InputKind::Scale { .. } => "Scale",
        }
    }

    /// The name of what it sets, and the field that names it (`force`, `driver`, `road`).
    fn target(&self) -> (&str, &'static str) {
        match self {
            InputKind::Load { force } | InputKind::Scale { force } => (force, "force"),
            InputKind::Driver { driver } => (driver, "driver"),
            InputKind::Road { road } => (road, "road"),
        }
    }

    /// Values the host may hand it: (fewest, most).
    pub fn arity(&self) -> (usize, usize) {
        match self {
            InputKind::Load { .. } => (6, 6),
            InputKind::Driver { .. } => (1, 3),
            InputKind::Road { .. } | InputKind::Scale { .. } => (2, 2),
        }
    }

    /// Slots it takes in the table: its values, and a driver's flag "set by the host".
    fn slots(&self) -> usize {
        match self {
            InputKind::Driver { .. } => 4,
            other => other.arity().1,
        }
    }
}

/// The shared table of every input's current values (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct InputValues(Arc<[AtomicU64]>);

impl InputValues {
    fn new(values: &[f64]) -> Self {
        InputValues(values.iter().map(|v| AtomicU64::new(v.to_bits())).collect())
    }

    fn get(&self, k: usize) -> f64 {
        f64::from_bits(self.0[k].load(Ordering::Relaxed))
    }

    fn set(&self, k: usize, v: f64) {
        self.0[k].store(v.to_bits(), Ordering::Relaxed);
    }
}

/// One input's values in the shared table, as the element or driver it moves reads them.
#[derive(Clone, Debug)]
pub struct InputSlots {
    values: InputValues,
    start: usize,
}

impl InputSlots {
    /// Its value `k` (no allocation).
    pub fn get(&self, k: usize) -> f64 {
        self.values.get(self.start + k)
    }

    /// Its values `k`, `k + 1`, `k + 2` as a vector.
    pub fn vector(&self, k: usize) -> nalgebra::Vector3<f64> {
        nalgebra::Vector3::new(self.get(k), self.get(k + 1), self.get(k + 2))
    }
}

impl PartialEq for InputSlots {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.values.0, &other.values.0) && self.start == other.start
    }
}

/// A driver's law while it has an input: the scene's law until the host sets the input,
/// then (θ, θ̇, θ̈) as the host set them, held until it sets them again.
#[derive(Clone, Debug, PartialEq)]
pub struct DriverInput {
    /// The scene's law (shared: a formulation may clone the law at every evaluation, and
    /// cloning an `Arc` allocates nothing).
    pub law: Arc<MotionLaw>,
    /// Slots 0–2: θ, θ̇, θ̈; slot 3: 1 once the host has set them.
    pub slots: InputSlots,
}

impl DriverInput {
    /// θ, θ̇, θ̈ at time t.
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        if self.slots.get(3) == 0.0 {
            return self.law.eval(t);
        }
        (self.slots.get(0), self.slots.get(1), self.slots.get(2))
    }
}

/// One compiled input: what it sets and where its values are.
#[derive(Clone, Debug)]
struct Entry {
    name: String,
    kind: InputKind,
    /// Index of its target among the scene's forces, drivers or roads.
    target: usize,
    start: usize,
    /// A `Load` input on a rigid body (a torque needs one).
    torque_allowed: bool,
}

/// The scene's inputs, compiled: their names, targets and the shared table of values.
/// Built by [`crate::PreparedScene::new`]; a simulation keeps a clone to set the values.
#[derive(Clone, Debug, Default)]
pub struct InputTable {
    entries: Vec<Entry>,
    values: InputValues,
    /// The scene is planar (a load: F_x, F_y, τ_z only).
    planar: bool,
}

/// Largest force or torque component an input or a `Load` takes (N, N·m).
pub const LOAD: Range = Range {
    min: -1e12,
    max: 1e12,
    open_min: false,
    unit: "N or N·m",
};
/// Largest road offset (m).
const OFFSET: Range = flexmbd_fe::bounds::POSITION;
/// Range of a stiffness or damping scale factor.
const SCALE: Range = Range {
    min: 0.0,
    max: 1e6,
    open_min: false,
    unit: "",
};

impl InputTable {
    /// Compile the (validated) scene's inputs, each at its start values.
    pub fn new(scene: &Scene) -> Self {
        let mut entries = Vec::with_capacity(scene.inputs.len());
        let mut start_values = Vec::new();
        for input in &scene.inputs {
            let (target, _) = input.kind.target();
            let index = match &input.kind {
                InputKind::Load { .. } | InputKind::Scale { .. } => {
                    scene.forces.iter().position(|f| f.name() == target)
                }
                InputKind::Driver { .. } => scene.drivers.iter().position(|d| d.name == target),
                InputKind::Road { .. } => scene.roads.iter().position(|r| r.name == target),
            };
            let index = index.expect("inputs are validated before they are compiled");
            let torque_allowed = match &scene.forces.get(index) {
                Some(Force::Load { body, .. }) => scene
                    .bodies
                    .iter()
                    .any(|b| &b.name == body && !crate::force_elements::runs_flexible(b)),
                _ => false,
            };
            entries.push(Entry {
                name: input.name.clone(),
                kind: input.kind.clone(),
                target: index,
                start: start_values.len(),
                torque_allowed,
            });
            match (&input.kind, &scene.forces.get(index)) {
                (InputKind::Load { .. }, Some(Force::Load { force, torque, .. })) => {
                    start_values.extend(force.0.iter().chain(&torque.0))
                }
                (InputKind::Scale { .. }, _) => start_values.extend([1.0, 1.0]),
                (kind, _) => start_values.extend(std::iter::repeat_n(0.0, kind.slots())),
            }
        }
        InputTable {
            entries,
            values: InputValues::new(&start_values),
            planar: scene.dim == Dim::Planar,
        }
    }

    /// The inputs' names, in the scene's order (an input's id is its index here).
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.entries.iter().map(|e| e.name.as_str())
    }

    /// The number of inputs.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when the scene declares no input.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The index of the input `name`.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.entries.iter().position(|e| e.name == name)
    }

    /// What input `k` sets.
    pub fn kind(&self, k: usize) -> &InputKind {
        &self.entries[k].kind
    }

    fn slots(&self, start: usize) -> InputSlots {
        InputSlots {
            values: self.values.clone(),
            start,
        }
    }

    /// The slots of the input on force element `k` (a `Load` or a `Scale`), if any.
    pub fn force_slots(&self, k: usize) -> Option<InputSlots> {
        self.entries
            .iter()
            .find(|e| {
                matches!(e.kind, InputKind::Load { .. } | InputKind::Scale { .. }) && e.target == k
            })
            .map(|e| self.slots(e.start))
    }

    /// The slots of the input on road `k`, if any.
    pub fn road_slots(&self, k: usize) -> Option<InputSlots> {
        self.entries
            .iter()
            .find(|e| matches!(e.kind, InputKind::Road { .. }) && e.target == k)
            .map(|e| self.slots(e.start))
    }

    /// The slots of the input on driver `k`, if any.
    pub fn driver_slots(&self, k: usize) -> Option<InputSlots> {
        self.entries
            .iter()
            .find(|e| matches!(e.kind, InputKind::Driver { .. }) && e.target == k)
            .map(|e| self.slots(e.start))
    }

    /// Set input `k` to `values` (no allocation; the error names the input, the value and
    /// the reason). A driver input's missing rate or acceleration is 0.
    ///
    /// # Panics
    /// If `k` is not an input of this table.
    pub fn set(&self, k: usize, values: &[f64]) -> Result<(), InvalidValue> {
        let entry = &self.entries[k];
        self.check(entry, values)?;
        for (i, &v) in values.iter().enumerate() {
            self.values.set(entry.start + i, v);
        }
        if let InputKind::Driver { .. } = entry.kind {
            for i in values.len()..3 {
                self.values.set(entry.start + i, 0.0);
            }
            self.values.set(entry.start + 3, 1.0);
        }
        Ok(())
    }

    /// The values input `k` holds now (a driver: θ, θ̇, θ̈ as last set, zeros before).
    pub fn values(&self, k: usize) -> impl Iterator<Item = f64> + '_ {
        let e = &self.entries[k];
        (0..e.kind.arity().1).map(move |i| self.values.get(e.start + i))
    }

    /// `values` fit input `entry`: their count, each finite and in range, and in a
    /// planar scene a load in the plane.
    fn check(&self, entry: &Entry, values: &[f64]) -> Result<(), InvalidValue> {
        let field = |i: usize| format!("inputs[{}][{i}]", entry.name);
        let (fewest, most) = entry.kind.arity();
        if !(fewest..=most).contains(&values.len()) {
            let wanted = match (fewest, most) {
                (a, b) if a == b => format!("{a}"),
                (a, b) => format!("{a} to {b}"),
            };
            return Err(InvalidValue::new(
                format!("inputs[{}]", entry.name),
                format!("{} values", values.len()),
                format!("a {} input takes {wanted} values", entry.kind.kind_name()),
            ));
        }
        let range = match entry.kind {
            InputKind::Load { .. } => LOAD,
            InputKind::Driver { .. } => flexmbd_fe::bounds::POSITION,
            InputKind::Road { .. } => OFFSET,
            InputKind::Scale { .. } => SCALE,
        };
        for (i, &v) in values.iter().enumerate() {
            // The field's name only for a refusal: a value in range allocates nothing.
            if !range.contains(v) {
                range.check(&field(i), v)?;
            }
        }
        let load = matches!(entry.kind, InputKind::Load { .. });
        if load && !entry.torque_allowed && values[3..6] != [0.0; 3] {
            return Err(InvalidValue::new(
                format!("inputs[{}][3..6]", entry.name),
                format!("{:?}", &values[3..6]),
                "a torque needs a rigid body, and this load's body is flexible",
            ));
        }
        if self.planar && load {
            for i in [2, 3, 4] {
                if values[i] != 0.0 {
                    return Err(InvalidValue::new(
                        field(i),
                        values[i],
                        "a planar scene's load is F_x, F_y and τ_z: F_z, τ_x and τ_y must be 0",
                    ));
                }
            }
        }
        Ok(())
    }
}

impl Scene {
    /// Input names unique; each names a force element, driver or road that exists and can
    /// take it (a `Load` input a `Load` element, a `Scale` input a `SpringDamper` or a
    /// `Link`); one input per target.
    pub(crate) fn check_inputs(&self) -> Result<(), ModelError> {
        let mut names = HashSet::new();
        let mut targets = HashSet::new();
        for input in &self.inputs {
            if !names.insert(input.name.as_str()) {
                return Err(self.repeated_name("inputs", &input.name, "input"));
            }
            let kind = input.kind.kind_name();
            let (target, key) = input.kind.target();
            let field = format!("inputs[{}].kind.{kind}.{key}", input.name);
            self.check_input_target(&input.kind, target, &field)?;
            let shared = matches!(input.kind, InputKind::Load { .. } | InputKind::Scale { .. });
            if !targets.insert((if shared { "force" } else { kind }, target)) {
                return Err(self.invalid(InvalidValue::new(
                    field,
                    target,
                    "another input already sets it (one input per force element, driver or road)",
                )));
            }
        }
        Ok(())
    }

    fn check_input_target(
        &self,
        kind: &InputKind,
        target: &str,
        field: &str,
    ) -> Result<(), ModelError> {
        let wrong = |what: &str| {
            Err(self.invalid(InvalidValue::new(
                field,
                target,
                format!("a {} input {what}", kind.kind_name()),
            )))
        };
        match kind {
            InputKind::Load { .. } | InputKind::Scale { .. } => {
                let Some(force) = self.forces.iter().find(|f| f.name() == target) else {
                    return Err(self.missing(field.to_string(), "force element", target));
                };
                match (kind, force) {
                    (InputKind::Load { .. }, Force::Load { .. }) => Ok(()),
                    (InputKind::Load { .. }, f) => wrong(&format!(
                        "sets a `Load` force element; `{target}` is a {}",
                        f.kind_name()
                    )),
                    (_, Force::SpringDamper { .. } | Force::Link { .. }) => Ok(()),
                    (_, f) => wrong(&format!(
                        "scales a `SpringDamper` or a `Link`; `{target}` is a {}",
                        f.kind_name()
                    )),
                }
            }
            InputKind::Driver { .. } => {
                if self.drivers.iter().any(|d| d.name == target) {
                    return Ok(());
                }
                let known: Vec<&str> = self.drivers.iter().map(|d| d.name.as_str()).collect();
                Err(self.missing_named(field, "driver", target, &known))
            }
            InputKind::Road { .. } => {
                if self.roads.iter().any(|r| r.name == target) {
                    return Ok(());
                }
                let known: Vec<&str> = self.roads.iter().map(|r| r.name.as_str()).collect();
                Err(self.missing_named(field, "road", target, &known))
            }
        }
    }

    fn missing_named(
        &self,
        field: &str,
        kind: &'static str,
        name: &str,
        known: &[&str],
    ) -> ModelError {
        ModelError::Missing {
            file: self.origin.clone(),
            line: crate::lines::line_of(&self.source, field),
            item: field.to_string(),
            kind,
            name: name.to_string(),
            hint: format!(" (known: {})", known.join(", ")),
        }
    }
}
