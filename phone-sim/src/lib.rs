//! placeholder
pub mod sensor_world;
