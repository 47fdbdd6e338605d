//! flexmbd as an FMU (Functional Mock-up Interface 3.0, co-simulation): a scene runs
//! inside another simulator — a driving simulator, a controller's test bench, a system
//! model in Modelica, Simulink or Python — with the integrator inside the FMU, as the
//! scene's equations are an index-3 DAE (the FMI standard's co-simulation interface;
//! Chrono's documentation reaches the same conclusion for its own FMUs).
//!
//! This crate is both the FMU's binary (built as a `cdylib`: the C API of [`fmi3`]) and
//! the library `flexmbd fmu` uses to write an FMU ([`package::write_fmu`]): the model
//! description ([`model_description`]) and the zip, with the scene and the files it
//! reads in `resources/`.
//!
//! - **Variables** ([`variables`]): `time`; one input per value of each named input of
//!   the scene; one output per sensor.
//! - **Semantics** ([`instance`]): `doStep` takes whole steps of the scene's step h; the
//!   inputs set before it hold through it; `get/setFMUState` through the integrator's
//!   checkpoint; a refused call or a failed step is `fmi3Error` with its message through
//!   the logger, a panic `fmi3Fatal`, never an unwind into the importer.
//!
//! The standard: Modelica Association, *Functional Mock-up Interface Specification 3.0*
//! (2022), §2 (common API) and §4 (co-simulation).

#![allow(unsafe_code)]

mod ffi;
pub mod fmi2;
pub mod fmi3;
pub mod instance;
pub mod model_description;
pub mod package;
pub mod variables;

pub use instance::{CallError, Instance};
