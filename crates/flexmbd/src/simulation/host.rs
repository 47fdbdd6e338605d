//! The host's side of a running [`Simulation`]: what a program that steps it (a driving
//! simulator, a controller, a script) does between two steps.
//!
//! - **Inputs** declared in the scene ([`flexmbd_model::inputs`]): look one up once by name
//!   ([`Simulation::input`], an [`InputId`]), then set its values before each step
//!   ([`Simulation::set_input`]: no allocation, no string comparison);
//!   [`Simulation::set_input_by_name`] does both. Values out of range are refused with the
//!   input, the value and the reason, and nothing is changed.
//! - **Sensors** by name ([`Simulation::sensor`]) or all at once
//!   ([`Simulation::read_sensors`]).
//! - **State**: the coordinates and rates ([`Simulation::positions`],
//!   [`Simulation::velocities`]) and a new state ([`Simulation::set_state`], checked against
//!   the constraints).
//! - **Analyses** of the scene as given: its static equilibrium, the linearised vibration
//!   about it, a flexible body's mode inventory.
//!
//! Inputs are the host's: [`Simulation::restore`] and a failed step leave them as they are,
//! so that after a step that failed under an absurd input the host sets a sane one and steps
//! on from the last good state.

use flexmbd_core::{InvalidValue, Request, State, SystemTerms};
use flexmbd_integrators::{Ali3p, StartFrom};
use flexmbd_model::CONSTRAINT_TOLERANCE;
use flexmbd_model::inputs::InputKind;
use nalgebra::DVector;

use super::{Simulation, integrator_settings};
use crate::inventory::Inventory;
use crate::{Equilibrium, Error, Vibration};

/// An input of a running simulation, looked up once by name ([`Simulation::input`]): its
/// index among the scene's inputs, so it means the same input in every simulation of that
/// scene (one past their number is refused).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct InputId(usize);

impl Simulation {
    /// The names of the scene's inputs, in the scene's order.
    pub fn input_names(&self) -> impl Iterator<Item = &str> {
        self.inputs.names()
    }

    /// The input `name`, to set with [`set_input`](Simulation::set_input) at every step.
    pub fn input(&self, name: &str) -> Result<InputId, Error> {
        self.inputs.find(name).map(InputId).ok_or_else(|| {
            let known: Vec<&str> = self.inputs.names().collect();
            Error::Input(InvalidValue::new(
                "input",
                name,
                format!(
                    "the scene declares no such input (inputs: {})",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            ))
        })
    }

    /// What input `id` sets.
    pub fn input_kind(&self, id: InputId) -> Result<&InputKind, Error> {
        self.check_input_id(id)?;
        Ok(self.inputs.kind(id.0))
    }

    /// Set input `id` to `values` for the steps that follow (their count and meaning per
    /// kind: [`flexmbd_model::inputs`]). No allocation; a refused value changes nothing.
    pub fn set_input(&mut self, id: InputId, values: &[f64]) -> Result<(), Error> {
        self.check_input_id(id)?;
        self.inputs.set(id.0, values).map_err(Error::Input)
    }

    /// [`input`](Simulation::input) and [`set_input`](Simulation::set_input) in one call.
    pub fn set_input_by_name(&mut self, name: &str, values: &[f64]) -> Result<(), Error> {
        let id = self.input(name)?;
        self.set_input(id, values)
    }

    /// The values input `id` holds now (a driver input: θ, θ̇, θ̈ as last set, zeros
    /// before).
    pub fn input_values(&self, id: InputId) -> Result<Vec<f64>, Error> {
        self.check_input_id(id)?;
        Ok(self.inputs.values(id.0).collect())
    }

    fn check_input_id(&self, id: InputId) -> Result<(), Error> {
        if id.0 < self.inputs.len() {
            return Ok(());
        }
        Err(Error::Input(InvalidValue::new(
            "input",
            id.0,
            format!(
                "not an input of this simulation (it has {})",
                self.inputs.len()
            ),
        )))
    }

    /// The index of sensor `name` in [`sensor_names`](Simulation::sensor_names) and in
    /// what [`read_sensors`](Simulation::read_sensors) writes.
    pub fn sensor_index(&self, name: &str) -> Result<usize, Error> {
        let names = self.sensor_names();
        names.iter().position(|n| n == name).ok_or_else(|| {
            Error::Input(InvalidValue::new(
                "sensor",
                name,
                format!(
                    "the scene has no such sensor (sensors: {})",
                    names.join(", ")
                ),
            ))
        })
    }

    /// The value of sensor `name` at the current state (SI units). Reads every sensor into
    /// a buffer kept for it (no allocation); to read several, [`read_sensors`](Simulation::read_sensors).
    pub fn sensor(&mut self, name: &str) -> Result<f64, Error> {
        let k = self.sensor_index(name)?;
        let mut values = std::mem::take(&mut self.sensor_values);
        self.read_sensors(&mut values);
        let value = values[k];
        self.sensor_values = values;
        Ok(value)
    }

    /// The coordinates q of the formulation at the current time (absolute: natural
    /// coordinates and modal amplitudes; relative: joint coordinates and modal amplitudes).
    pub fn positions(&self) -> &DVector<f64> {
        &self.integrator.q
    }

    /// The rates q̇ at the current time.
    pub fn velocities(&self) -> &DVector<f64> {
        &self.integrator.qd
    }

    /// Continue from the state (q, q̇) at the current time (e.g. positions and velocities
    /// of another run, or [`positions`](Simulation::positions) edited). The state must
    /// satisfy the constraints, ‖Φ(q)‖∞ and ‖Φ_q q̇ + Φ_t‖∞ within
    /// [`CONSTRAINT_TOLERANCE`] (a relative one for the rates: times 1 + ‖q̇‖∞); ALI3-P
    /// then makes it consistent to its own tolerance and finds the accelerations, as at
    /// the start. A refused state changes nothing. The integrator starts anew at the current
    /// time: its counters ([`stats`](Simulation::stats)) count from here.
    pub fn set_state(&mut self, q: &[f64], qd: &[f64]) -> Result<(), Error> {
        let n = self.n_coordinates();
        for (what, v) in [("q", q), ("qd", qd)] {
            if v.len() != n {
                return Err(state_error(
                    what,
                    format!("{} values", v.len()),
                    format!("the formulation has {n} coordinates"),
                ));
            }
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(state_error(
                    &format!("{what}[{i}]"),
                    v[i],
                    "not a finite number",
                ));
            }
        }
        let (q, qd) = (
            DVector::from_column_slice(q),
            DVector::from_column_slice(qd),
        );
        let (position, velocity) = self.constraint_residuals(&q, &qd);
        let scale = 1.0 + qd.amax();
        if position > CONSTRAINT_TOLERANCE {
            return Err(state_error(
                "q",
                format!("‖Φ(q)‖∞ = {position:.3e}"),
                format!(
                    "the positions violate the constraints (tolerance {CONSTRAINT_TOLERANCE:e})"
                ),
            ));
        }
        if velocity > CONSTRAINT_TOLERANCE * scale {
            return Err(state_error(
                "qd",
                format!("‖Φ_q q̇ + Φ_t‖∞ = {velocity:.3e}"),
                format!(
                    "the velocities violate the constraints (tolerance {:.3e})",
                    CONSTRAINT_TOLERANCE * scale
                ),
            ));
        }
        let t = self.time();
        let settings = integrator_settings(&self.setup.solver);
        let f = self.formulation.as_mut();
        self.integrator = Ali3p::new(&mut StartFrom::new(f, q, qd), t, settings)?;
        self.start_time = t;
        self.integrator.checkpoint_into(&mut self.last_good);
        Ok(())
    }

    /// ‖Φ(q)‖∞ and ‖Φ_q q̇ + Φ_t‖∞ at the current time.
    fn constraint_residuals(&mut self, q: &DVector<f64>, qd: &DVector<f64>) -> (f64, f64) {
        let (n, m) = (self.n_coordinates(), self.n_constraints());
        let mut terms = SystemTerms::new(n, m);
        let request = Request {
            constraints: true,
            jacobian: true,
            ..Request::default()
        };
        terms.clear(request);
        let state = State::new(self.time(), q, qd);
        self.formulation.evaluate(state, request, &mut terms);
        let velocity = &terms.phi_q * qd + &terms.phi_t;
        (terms.phi.amax(), velocity.amax())
    }

    /// The static equilibrium of the scene as given ([`crate::equilibrium()`]: its values,
    /// not the inputs set since).
    pub fn equilibrium(&self) -> Result<Equilibrium, Error> {
        crate::equilibrium(&self.scene)
    }

    /// The linearised free vibration of the scene as given about its static equilibrium
    /// ([`crate::vibration()`]).
    pub fn vibration(&self) -> Result<Vibration, Error> {
        crate::vibration(&self.scene)
    }

    /// The mode inventory of flexible body `body` as the scene reduces it (static modes,
    /// normal modes, frame degrees of freedom; [`Inventory`]).
    pub fn mode_inventory(&self, body: &str) -> Result<Inventory, Error> {
        let prepared = crate::pilot::prepared_scene(&self.scene, &super::NO_STOP)?;
        let flexible = prepared
            .body_id(body)
            .map(|id| prepared.body(id))
            .filter(|b| b.flexible);
        match flexible {
            Some(b) => Ok(Inventory::of(body, &b.reduced)),
            None => Err(Error::Input(InvalidValue::new(
                "body",
                body,
                "not a flexible body of the scene: only a flexible body has modes",
            ))),
        }
    }
}

fn state_error(field: &str, value: impl std::fmt::Display, reason: impl Into<String>) -> Error {
    Error::Input(InvalidValue::new(field, value, reason))
}
