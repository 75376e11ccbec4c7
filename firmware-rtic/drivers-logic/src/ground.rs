//! Ground-sensor module (three floor IR sensors) on I2C1 at 7-bit address 0x60.
//!
//! One transaction reads everything: write the register pointer 0x00, then a
//! repeated-start read of 21 bytes, all 16-bit values big-endian:
//! 3 × delta (left, centre, right), 3 × ambient, the module revision, then the
//! optional cliff sensors. Values are 10-bit (0 = black or no floor, 1023 =
//! white). The driver is generic over `embedded_hal::i2c::I2c` so the
//! firmware passes the HAL's `I2c<I2C1>` and the tests a mock.

use embedded_hal::i2c::I2c;

/// 7-bit I2C address of the module.
pub const ADDRESS: u8 = 0x60;
/// First register of the block read.
pub const START_REGISTER: u8 = 0x00;
/// Length of the block read.
pub const FRAME_LEN: usize = 21;

/// Calibrated value of the black line.
pub const BLACK_LEVEL: u16 = 256;
/// Calibrated value of the white background.
pub const WHITE_LEVEL: u16 = 768;
/// Largest calibrated value.
pub const MAX_LEVEL: u16 = 1023;

/// One decoded reading of the three floor sensors.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GroundReading {
    /// Reflected minus ambient: left, centre, right.
    pub delta: [u16; 3],
    /// Ambient light: left, centre, right (0 = strong light).
    pub ambient: [u16; 3],
    /// Module software revision.
    pub revision: u8,
}

impl GroundReading {
    /// Decodes the 21-byte block (the cliff values are ignored).
    pub fn decode(frame: &[u8; FRAME_LEN]) -> Self {
        let be = |i: usize| u16::from_be_bytes([frame[i], frame[i + 1]]);
        GroundReading {
            delta: [be(0), be(2), be(4)],
            ambient: [be(6), be(8), be(10)],
            revision: frame[12],
        }
    }
}

/// The module on a bus.
#[derive(Debug)]
pub struct GroundSensor<I> {
    i2c: I,
}

impl<I: I2c> GroundSensor<I> {
    /// Wraps the bus; no transaction yet.
    pub const fn new(i2c: I) -> Self {
        GroundSensor { i2c }
    }

    /// Reads and decodes one frame.
    pub fn read(&mut self) -> Result<GroundReading, I::Error> {
        let mut buf = [0u8; FRAME_LEN];
        self.i2c.write_read(ADDRESS, &[START_REGISTER], &mut buf)?;
        Ok(GroundReading::decode(&buf))
    }

    /// Gives the bus back.
    pub fn release(self) -> I {
        self.i2c
    }
}

/// Per-sensor linear map from raw deltas to the calibrated scale: raw black →
/// [`BLACK_LEVEL`], raw white → [`WHITE_LEVEL`], clamped to 0..=[`MAX_LEVEL`].
/// Fixed point with 11 fractional bits, as the seed's `sen_line_calibrate`.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GroundCalibration {
    black: [u16; 3],
    /// (WHITE−BLACK)·2048 / (white−black) per sensor.
    gain: [u32; 3],
}

/// Why a calibration was refused.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CalibrationError {
    /// Sensor `0` read black at least as bright as white.
    NotBrighter(u8),
}

impl GroundCalibration {
    /// The identity-like map used until a calibration exists: raw 0..1023
    /// unchanged (black 256, white 768).
    pub const IDENTITY: GroundCalibration = GroundCalibration {
        black: [BLACK_LEVEL; 3],
        gain: [2048; 3],
    };

    /// The map from raw black and white readings.
    pub fn new(black: [u16; 3], white: [u16; 3]) -> Result<Self, CalibrationError> {
        let mut gain = [0u32; 3];
        for i in 0..3 {
            if white[i] <= black[i] {
                return Err(CalibrationError::NotBrighter(i as u8));
            }
            gain[i] = ((WHITE_LEVEL - BLACK_LEVEL) as u32 * 2048) / (white[i] - black[i]) as u32;
        }
        Ok(GroundCalibration { black, gain })
    }

    /// Calibrated value of sensor `i` for raw `raw`.
    pub fn apply_one(&self, i: usize, raw: u16) -> u16 {
        let d = raw as i32 - self.black[i] as i32;
        let v = BLACK_LEVEL as i32 + ((d * self.gain[i] as i32) >> 11);
        v.clamp(0, MAX_LEVEL as i32) as u16
    }

    /// Calibrated values of all three sensors.
    pub fn apply(&self, raw: [u16; 3]) -> [u16; 3] {
        [
            self.apply_one(0, raw[0]),
            self.apply_one(1, raw[1]),
            self.apply_one(2, raw[2]),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_hal::i2c::ErrorKind;
    use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    use std::vec;

    fn frame() -> [u8; FRAME_LEN] {
        let mut f = [0u8; FRAME_LEN];
        f[..13].copy_from_slice(&[
            0x01, 0x2C, 0x03, 0xE8, 0x00, 0x0A, // deltas 300, 1000, 10
            0x03, 0xFF, 0x02, 0x00, 0x00, 0x01, // ambient 1023, 512, 1
            7,
        ]);
        f
    }

    #[test]
    fn decodes_big_endian() {
        let r = GroundReading::decode(&frame());
        assert_eq!(r.delta, [300, 1000, 10]);
        assert_eq!(r.ambient, [1023, 512, 1]);
        assert_eq!(r.revision, 7);
    }

    #[test]
    fn reads_through_one_write_read() {
        let expect = [Transaction::write_read(
            ADDRESS,
            vec![0x00],
            frame().to_vec(),
        )];
        let mut mock = Mock::new(&expect);
        let mut g = GroundSensor::new(mock.clone());
        assert_eq!(g.read().unwrap().delta, [300, 1000, 10]);
        mock.done();
    }

    #[test]
    fn bus_errors_propagate() {
        let expect = [
            Transaction::write_read(ADDRESS, vec![0x00], vec![0; FRAME_LEN])
                .with_error(ErrorKind::Other),
        ];
        let mut mock = Mock::new(&expect);
        let mut g = GroundSensor::new(mock.clone());
        assert!(g.read().is_err());
        mock.done();
    }

    #[test]
    fn calibration_maps_black_and_white() {
        let c = GroundCalibration::new([100, 120, 90], [700, 820, 600]).unwrap();
        assert_eq!(c.apply([100, 120, 90]), [256, 256, 256]);
        let w = c.apply([700, 820, 600]);
        for v in w {
            assert!((767..=768).contains(&v), "{v}");
        }
        assert!((169..=171).contains(&c.apply_one(0, 0))); // below black, still > 0
        assert_eq!(c.apply_one(0, 1023), MAX_LEVEL);
        assert_eq!(
            GroundCalibration::IDENTITY.apply([5, 500, 1023]),
            [5, 500, 1023]
        );
    }

    #[test]
    fn calibration_refuses_inverted_levels() {
        assert_eq!(
            GroundCalibration::new([100, 500, 90], [700, 500, 600]),
            Err(CalibrationError::NotBrighter(1))
        );
    }
}
