//! The ground-sensor module on I2C1 (PB8 SCL, PB9 SDA) at 0x60, 200 kHz as
//! in the C firmware. Decoding lives in `drivers_logic::ground`.
//!
//! If the first read fails the module is taken as absent (as the C firmware
//! does) and no further transactions are attempted: a robot without the
//! module still boots and talks.

use drivers_logic::ground::{GroundReading, GroundSensor};
use stm32f4xx_hal::{i2c::I2c, pac::I2C1};

/// The module and whether it answered.
pub struct Ground {
    sensor: GroundSensor<I2c<I2C1>>,
    present: bool,
}

impl Ground {
    /// Probes the module with one read.
    pub fn new(i2c: I2c<I2C1>) -> Self {
        let mut sensor = GroundSensor::new(i2c);
        let present = sensor.read().is_ok();
        if !present {
            defmt::warn!("ground sensor module not found at 0x60");
        }
        Ground { sensor, present }
    }

    /// One blocking read (~1.1 ms at 200 kHz); `None` if absent or on a bus error.
    pub fn read(&mut self) -> Option<GroundReading> {
        if !self.present {
            return None;
        }
        self.sensor.read().ok()
    }
}
