//! # phone-sim
//!
//! The phone side and the simulator of e-puck Conquest, behind the binary
//! `conquest`: field files and generators ([`field`]), pictures of fields
//! ([`render`]), and, as the project grows, the world simulator, the robot
//! proxies, the observable environment, the web UI and the benchmark runner.
//! Robot decisions are not made here: they live in `core-algo`, shared with
//! the firmware.

pub mod bench;
pub mod cli;
pub mod connect_cmd;
pub mod environment;
pub mod explore_cmd;
pub mod field;
pub mod handlers;
pub mod phone;
pub mod proxy;
pub mod qemu;
pub mod render;
pub mod sensor_world;
pub mod sim;
pub mod world;
