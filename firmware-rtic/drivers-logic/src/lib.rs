//! # drivers-logic
//!
//! The parts of the e-puck2 drivers that do not touch a register: step
//! sequences and timer periods, the proximity sampling schedule, the decoding
//! of the ground-sensor module's I2C frame, the selector, the LED levels, the
//! calibration record stored in flash.
//!
//! Why a separate crate: the firmware builds only for `thumbv7em-none-eabihf`,
//! so everything that can be wrong without hardware lives here and is tested
//! with plain `cargo test` on the host (with `embedded-hal-mock` where a bus is
//! involved). The firmware's driver modules are thin shells around these
//! types.
#![no_std]
#![deny(unsafe_code)]
#![warn(missing_docs)]

#[cfg(test)]
extern crate std;

pub mod calibration;
pub mod config;
pub mod ground;
pub mod leds;
pub mod proximity;
pub mod selector;
pub mod stepper;
