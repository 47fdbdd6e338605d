//! The flexmbd scene (`models/*.ron`): bodies (rigid, or flexible beams), joints,
//! force elements, drivers, sensors and solver settings, described once and
//! compiled by either formulation. Loading validates everything and reports
//! errors with the file, the line and the field; units are SI. [`PreparedScene`] is the
//! stage every formulation starts from: the scene validated, rewritten for its stiffening
//! method, its bodies reduced and built, its names resolved into typed ids.

pub mod bodies;
pub mod builder;
pub mod consistency;
pub mod constraint_equations;
pub mod direction;
pub mod error;
mod force_checks;
pub mod force_elements;
mod force_ends;
mod foreshortening;
mod initial_velocity;
pub mod inputs;
pub mod interface_force;
mod interface_system;
pub mod laws;
pub mod lines;
pub mod load;
pub mod prepared;
pub mod reaction_directions;
pub mod rewrite;
pub mod roads;
pub mod scene;
pub mod scene_constraints;
pub mod sensor_spec;
pub mod sensors;
pub mod stress;
mod values;

pub use bodies::PreparedBody;
pub use direction::Direction;
pub use error::ModelError;
pub use inputs::{Input, InputKind};
pub use laws::Law;
pub use load::parse_set;
pub use prepared::{BodyId, JointId, MarkerId, MarkerPair, PreparedScene, SensorTarget};
pub use roads::{Contact, Profile, Road};
pub use scene::*;
