//! The ground-sensor calibration run (selector 0 at power-on, seed §2.3):
//! record the raw levels with the sensors on a black line, drive straight
//! forward onto the white background, record again, drive back, done.
//!
//! A pure state machine stepped by the 100 Hz control task; it returns the
//! wheel speeds to apply and, at the end, the record to store in flash. The
//! firmware stores it only once the motors report standstill, because a
//! sector erase stalls the flash bus (and thus the stepper interrupts).
//! (core-algo's `behaviour` calibration layer may replace this.)

use crate::config::CalibrationRecord;
use crate::ground::{CalibrationError, GroundCalibration};

/// Distance driven onto the background, in full steps (the seed's code used
/// 300 ≈ 3.9 cm; its design text 250).
pub const DISTANCE: i32 = 300;
/// Speed of the calibration drive, in steps per second.
pub const SPEED: i16 = 300;
/// Control cycles to wait (motors stopped) before each measurement.
pub const SETTLE_CYCLES: u8 = 10;

/// Where the run is.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Phase {
    /// Waiting for the sensors to settle on black.
    SettleBlack(u8),
    /// Driving forward; black levels recorded.
    Forward,
    /// Waiting on white.
    SettleWhite(u8),
    /// Driving back; both levels recorded.
    Back,
    /// Finished: the record is ready (or was refused).
    Done,
}

/// Output of one step.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Output {
    /// Apply these wheel speeds (left, right).
    Drive(i16, i16),
    /// Finished: stop, then store the record.
    Store(CalibrationRecord),
    /// Finished with levels that make no calibration.
    Failed(CalibrationError),
}

/// The calibration state machine.
#[derive(Clone, Debug)]
pub struct CalibrationRun {
    phase: Phase,
    start_steps: i32,
    black: [u16; 3],
    white: [u16; 3],
}

impl Default for CalibrationRun {
    fn default() -> Self {
        Self::new()
    }
}

impl CalibrationRun {
    /// A run that starts by settling on black.
    pub const fn new() -> Self {
        CalibrationRun {
            phase: Phase::SettleBlack(SETTLE_CYCLES),
            start_steps: 0,
            black: [0; 3],
            white: [0; 3],
        }
    }

    /// Current phase.
    pub const fn phase(&self) -> Phase {
        self.phase
    }

    /// One control cycle with the raw ground deltas and the mean wheel steps.
    pub fn step(&mut self, raw: [u16; 3], steps: i32) -> Output {
        match self.phase {
            Phase::SettleBlack(0) => {
                self.black = raw;
                self.start_steps = steps;
                self.phase = Phase::Forward;
                Output::Drive(SPEED, SPEED)
            }
            Phase::SettleBlack(n) => {
                self.phase = Phase::SettleBlack(n - 1);
                Output::Drive(0, 0)
            }
            Phase::Forward if steps - self.start_steps >= DISTANCE => {
                self.phase = Phase::SettleWhite(SETTLE_CYCLES);
                Output::Drive(0, 0)
            }
            Phase::Forward => Output::Drive(SPEED, SPEED),
            Phase::SettleWhite(0) => {
                self.white = raw;
                self.phase = Phase::Back;
                Output::Drive(-SPEED, -SPEED)
            }
            Phase::SettleWhite(n) => {
                self.phase = Phase::SettleWhite(n - 1);
                Output::Drive(0, 0)
            }
            Phase::Back if steps > self.start_steps => Output::Drive(-SPEED, -SPEED),
            Phase::Back | Phase::Done => {
                self.phase = Phase::Done;
                let rec = CalibrationRecord {
                    black: self.black,
                    white: self.white,
                };
                match GroundCalibration::new(rec.black, rec.white) {
                    Ok(_) => Output::Store(rec),
                    Err(e) => Output::Failed(e),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Simulates the wheel: speed × 10 ms per cycle; floor is black for the
    /// first 100 steps and white beyond.
    fn run(black: u16, white: u16) -> (Output, i32) {
        let mut c = CalibrationRun::new();
        let mut pos = 0i32;
        for _ in 0..2000 {
            let raw = if pos < 100 { [black; 3] } else { [white; 3] };
            match c.step(raw, pos) {
                Output::Drive(l, _) => pos += l as i32 / 100,
                done => return (done, pos),
            }
        }
        panic!("calibration never finished");
    }

    #[test]
    fn records_black_then_white_and_returns() {
        let (out, pos) = run(200, 800);
        assert_eq!(
            out,
            Output::Store(CalibrationRecord {
                black: [200; 3],
                white: [800; 3]
            })
        );
        assert!(pos.abs() <= 3, "ended {pos} steps from the start");
    }

    #[test]
    fn refuses_a_floor_without_contrast() {
        let (out, _) = run(500, 500);
        assert_eq!(out, Output::Failed(CalibrationError::NotBrighter(0)));
    }
}
