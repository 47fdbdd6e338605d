//! The flexmbd scene (`models/*.ron`): bodies (rigid, or flexible beams), joints,
//! force elements, drivers, sensors and solver settings, described once and
//! compiled by either formulation. Loading validates everything and reports
//! errors with the file, the line and the field; units are SI.

pub mod bodies;
pub mod error;
pub mod load;
pub mod scene;

pub use bodies::PreparedBody;
pub use error::ModelError;
pub use load::parse_set;
pub use scene::*;
