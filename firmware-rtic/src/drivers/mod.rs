//! e-puck2 drivers, one module per peripheral, mirroring the seed's HAL
//! components. Each is a thin shell around `stm32f4xx-hal` plus the pure
//! logic in `drivers-logic` (which is where the tests are).
//!
//! Under the `qemu` feature the modules that need RCC, GPIO inputs, ADC, I2C
//! or the stepper timers are replaced by `board::emu` (QEMU models none of
//! them); `leds`, `link` and `config` are used by both builds.

pub mod config;
#[cfg(not(feature = "qemu"))]
pub mod ground;
pub mod leds;
pub mod link;
#[cfg(not(feature = "qemu"))]
pub mod motors;
#[cfg(not(feature = "qemu"))]
pub mod proximity;
#[cfg(not(feature = "qemu"))]
pub mod selector;
