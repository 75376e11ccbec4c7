//! The board: clocks, pins and driver construction.
//!
//! Two implementations with the same surface (`init`, `Board`, `Motors`,
//! `Proximity`, `Ground`, `SYSCLK_HZ`, `EMULATED`; the emulated one adds
//! `exit`):
//! * `real`: the e-puck2 (24 MHz HSE bypass → 168 MHz, every driver);
//! * `emu` (feature `qemu`): QEMU's netduinoplus2, which models no RCC, GPIO,
//!   ADC-with-DMA, I2C or flash controller; it runs on the internal clock and
//!   puts virtual motors and sensors in place of the e-puck drivers. The link
//!   (USART3), the LEDs (writes are ignored) and the config reader are the
//!   real drivers in both; the emulated board adds the body channel (USART2).

#[cfg(feature = "qemu")]
mod emu;
#[cfg(feature = "qemu")]
pub use emu::*;
#[cfg(not(feature = "qemu"))]
mod real;
#[cfg(not(feature = "qemu"))]
pub use real::*;

use crate::drivers::{config::ConfigStore, leds::Leds};
use stm32f4xx_hal::{pac::USART3, serial::Serial};

/// Everything `init` hands to the tasks.
pub struct Board {
    /// Both steppers.
    pub motors: Motors,
    /// The IR ring.
    pub prox: Proximity,
    /// The floor sensors.
    pub ground: Ground,
    /// The STM32's LEDs.
    pub leds: Leds,
    /// Selector position at power-on.
    pub selector: u8,
    /// A fresh random number at every boot: the link's session nonce.
    pub nonce: u32,
    /// USART3, configured for 115200 8N1, not yet listening.
    pub serial: Serial<USART3>,
    /// USART2 of the emulated board: the body channel to the host's
    /// simulated body, 115200 8N1, not yet listening.
    #[cfg(feature = "qemu")]
    pub body_serial: Serial<stm32f4xx_hal::pac::USART2>,
    /// The calibration record store.
    pub config: ConfigStore,
}
