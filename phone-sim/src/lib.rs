//! placeholder
pub mod bench;
pub mod world;
