//! The calibration record in flash sector 11 (0x080E_0000).
//!
//! Erasing a 128 KiB sector stalls every instruction fetch from flash for
//! about a second, stepper interrupts included; [`ConfigStore::store`] is
//! therefore only callable with proof that the motors stand still.

use drivers_logic::config::{
    CalibrationRecord, RECORD_LEN, RecordError, SECTOR, SECTOR_ADDRESS, SECTOR_OFFSET,
};
use stm32f4xx_hal::{flash::FlashExt, pac::FLASH};

/// Proof, taken under the motors' lock, that both wheels are stopped.
pub struct MotorsStopped(());

impl MotorsStopped {
    /// Only the motor owner should build this, right after checking.
    pub fn checked(stopped: bool) -> Option<Self> {
        stopped.then_some(MotorsStopped(()))
    }
}

/// Why storing failed.
#[derive(Clone, Copy, Debug, defmt::Format)]
pub enum StoreError {
    /// Erase or program failed.
    Flash,
    /// Read back differs.
    Verify,
}

/// Access to the record.
pub struct ConfigStore {
    flash: FLASH,
}

impl ConfigStore {
    /// Wraps the flash interface.
    pub fn new(flash: FLASH) -> Self {
        ConfigStore { flash }
    }

    /// Reads and checks the stored record.
    ///
    /// Reads the fixed address directly rather than through the HAL's
    /// `FlashExt::read`, which first reads the flash-size register: QEMU's
    /// netduinoplus2 does not map that register and would bus-fault.
    pub fn load(&self) -> Result<CalibrationRecord, RecordError> {
        CalibrationRecord::decode(record_bytes())
    }

    /// Erases sector 11 and writes `record` (blocking, ~1 s).
    pub fn store(
        &mut self,
        record: &CalibrationRecord,
        _: MotorsStopped,
    ) -> Result<(), StoreError> {
        let image = record.encode();
        {
            let mut unlocked = self.flash.unlocked();
            unlocked.erase(SECTOR).map_err(|_| StoreError::Flash)?;
            unlocked
                .program(SECTOR_OFFSET, image.iter())
                .map_err(|_| StoreError::Flash)?;
        }
        match self.load() {
            Ok(r) if r == *record => Ok(()),
            _ => Err(StoreError::Verify),
        }
    }
}

/// The record's bytes in memory-mapped flash.
#[allow(unsafe_code)]
fn record_bytes() -> &'static [u8] {
    // SAFETY: 0x080E_0000..+32 is memory-mapped flash on every STM32F405/407
    // with 1 MiB (the e-puck2's F407VG and QEMU's F405). memory.x keeps code
    // and data out of sector 11, so nothing aliases it mutably; the only
    // writer is `store`, which takes `&mut self` and is done before we read.
    unsafe { core::slice::from_raw_parts(SECTOR_ADDRESS as *const u8, RECORD_LEN) }
}
