//! Floor-sensor calibration: line and background values per sensor.
//!
//! The seed's procedure: the robot stands with its floor sensors on a line
//! and only background in the 5 cm ahead; it stores the line values, drives
//! 250 steps forward and stores the background values. From the two levels
//! of each sensor follows a linear map onto the 2010 scale (line 256,
//! background 768), so every later threshold works under any light.
//!
//! A calibration is refused with an error code when the line is not clearly
//! darker than the background: a robot placed off the line, or facing along
//! it, would otherwise store a map that sees nodes everywhere or nowhere.
//! The accepted values are kept in a 16-byte [`Record`] with a CRC-16 so that
//! the firmware can put it in flash and reject a torn or foreign record.

use super::{BACKGROUND_LEVEL, FloorImage, LINE_LEVEL};
use crc::{CRC_16_IBM_3740, Crc, NoTable};

/// Samples averaged per level, to beat the sensors' noise.
pub const SAMPLES: u16 = 8;
/// Distance from the line to the background position, in motor steps (the
/// seed's quarter wheel turn).
pub const DRIVE_STEPS: i32 = 250;
/// The line must read at most this fraction (in percent) of the background.
/// The seed: a 70 % black reads about a third of white; 70 % leaves room
/// for dim light without accepting a robot that is not on a line.
pub const MAX_LINE_PERCENT: u32 = 70;
/// The background must read at least this raw value; below it the sensor
/// sees no floor (or is covered) and no threshold would be meaningful.
pub const MIN_BACKGROUND: u16 = 80;

/// Why a calibration was refused. Each has a stable code for the LEDs and
/// the phone.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum CalibrationError {
    /// The sensor's line value is not darker than its background value by
    /// the margin: the robot did not stand on a line, or faced along it.
    NoContrast {
        /// Sensor index, 0 left, 1 centre, 2 right.
        sensor: u8,
    },
    /// The sensor's background reads too dark: no floor under it.
    TooDark {
        /// Sensor index, 0 left, 1 centre, 2 right.
        sensor: u8,
    },
}

impl CalibrationError {
    /// A one-byte code: high nibble the kind (1 no contrast, 2 too dark),
    /// low nibble the sensor.
    pub const fn code(self) -> u8 {
        match self {
            CalibrationError::NoContrast { sensor } => 0x10 | (sensor & 0x0f),
            CalibrationError::TooDark { sensor } => 0x20 | (sensor & 0x0f),
        }
    }
}

/// The two levels of the three floor sensors and the map they define.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Calibration {
    line: [u16; 3],
    background: [u16; 3],
}

impl Calibration {
    /// Checks and accepts raw line and background values (left, centre,
    /// right). Refuses when a sensor's line is not at most
    /// [`MAX_LINE_PERCENT`] of its background, or the background is darker
    /// than [`MIN_BACKGROUND`].
    pub fn new(line: [u16; 3], background: [u16; 3]) -> Result<Calibration, CalibrationError> {
        for (i, (l, b)) in line.iter().zip(background.iter()).enumerate() {
            let sensor = i as u8;
            if *b < MIN_BACKGROUND {
                return Err(CalibrationError::TooDark { sensor });
            }
            if u32::from(*l) * 100 > u32::from(*b) * MAX_LINE_PERCENT {
                return Err(CalibrationError::NoContrast { sensor });
            }
        }
        Ok(Calibration { line, background })
    }

    /// The identity-like map for tests and for a robot that has never been
    /// calibrated: line 256 and background 768 raw.
    pub const IDENTITY: Calibration = Calibration {
        line: [LINE_LEVEL; 3],
        background: [BACKGROUND_LEVEL; 3],
    };

    /// Raw line values (left, centre, right).
    pub const fn line(&self) -> [u16; 3] {
        self.line
    }

    /// Raw background values (left, centre, right).
    pub const fn background(&self) -> [u16; 3] {
        self.background
    }

    /// The raw value below which the sensor counts as clearly black: 50 % of
    /// its white value, the seed's node threshold.
    pub fn node_threshold(&self, sensor: usize) -> u16 {
        self.background.get(sensor).map_or(0, |w| w / 2)
    }

    /// Maps one raw reading of `sensor` linearly so that its line value
    /// reads 256 and its background 768, clamped to 0..=1023.
    pub fn apply_one(&self, sensor: usize, raw: u16) -> u16 {
        let (Some(l), Some(b)) = (self.line.get(sensor), self.background.get(sensor)) else {
            return raw.min(1023);
        };
        let span = i32::from(*b) - i32::from(*l);
        if span <= 0 {
            return raw.min(1023);
        }
        let scaled = i32::from(LINE_LEVEL)
            + (i32::from(raw) - i32::from(*l)) * i32::from(BACKGROUND_LEVEL - LINE_LEVEL) / span;
        // Clamped into 0..=1023, so the conversion cannot fail.
        u16::try_from(scaled.clamp(0, 1023)).unwrap_or(0)
    }

    /// Maps a raw floor triple (left, centre, right).
    pub fn apply(&self, raw: [u16; 3]) -> FloorImage {
        FloorImage {
            left: self.apply_one(0, raw[0]),
            centre: self.apply_one(1, raw[1]),
            right: self.apply_one(2, raw[2]),
        }
    }

    /// The flash record of this calibration.
    pub fn record(&self) -> Record {
        let mut bytes = [0u8; RECORD_LEN];
        bytes[0] = RECORD_MAGIC;
        bytes[1] = RECORD_VERSION;
        for (i, v) in self.line.iter().chain(self.background.iter()).enumerate() {
            let at = 2 + 2 * i;
            bytes[at..at + 2].copy_from_slice(&v.to_le_bytes());
        }
        let crc = CRC.checksum(&bytes[..RECORD_LEN - 2]);
        bytes[RECORD_LEN - 2..].copy_from_slice(&crc.to_le_bytes());
        Record(bytes)
    }
}

/// Length of a [`Record`] in bytes.
pub const RECORD_LEN: usize = 16;
const RECORD_MAGIC: u8 = 0xCA;
const RECORD_VERSION: u8 = 1;
const CRC: Crc<u16, NoTable> = Crc::<u16, NoTable>::new(&CRC_16_IBM_3740);

/// A calibration as stored in flash: magic 0xCA, version 1, line and
/// background values as little-endian u16 (left, centre, right each), then
/// CRC-16/IBM-3740 of the first 14 bytes, little-endian.
///
/// Sixteen bytes fit one flash write unit of any page size the STM32F4 or
/// the 2010 EEPROM offer, and the CRC catches a torn or erased record.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Record(pub [u8; RECORD_LEN]);

/// Why a stored record was not loaded.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum RecordError {
    /// Not the length of a record.
    Length,
    /// Wrong magic byte or version: erased flash or another format.
    Format,
    /// The checksum does not match: a torn write or bit rot.
    Checksum,
    /// The stored values do not pass [`Calibration::new`].
    Refused(CalibrationError),
}

impl Record {
    /// Reads a record from stored bytes and validates it completely.
    pub fn load(bytes: &[u8]) -> Result<Calibration, RecordError> {
        if bytes.len() != RECORD_LEN {
            return Err(RecordError::Length);
        }
        if bytes.first() != Some(&RECORD_MAGIC) || bytes.get(1) != Some(&RECORD_VERSION) {
            return Err(RecordError::Format);
        }
        let (body, tail) = bytes.split_at(RECORD_LEN - 2);
        let stored = u16::from_le_bytes([tail[0], tail[1]]);
        if CRC.checksum(body) != stored {
            return Err(RecordError::Checksum);
        }
        let mut v = [0u16; 6];
        for (i, slot) in v.iter_mut().enumerate() {
            let at = 2 + 2 * i;
            *slot = u16::from_le_bytes([body[at], body[at + 1]]);
        }
        Calibration::new([v[0], v[1], v[2]], [v[3], v[4], v[5]]).map_err(RecordError::Refused)
    }
}

/// Accumulates [`SAMPLES`] raw floor triples into their mean.
///
/// Kept separate from the driving so that the calibration layer is only a
/// sequence of "sample here, drive there".
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct LevelSampler {
    pub(crate) sums: [u32; 3],
    pub(crate) count: u16,
}

impl LevelSampler {
    /// Adds one raw triple; returns the mean once [`SAMPLES`] are in.
    pub fn add(&mut self, raw: [u16; 3]) -> Option<[u16; 3]> {
        for (s, r) in self.sums.iter_mut().zip(raw) {
            *s += u32::from(r);
        }
        self.count += 1;
        if self.count < SAMPLES {
            return None;
        }
        let n = u32::from(self.count);
        let mean = self.sums.map(|s| u16::try_from(s / n).unwrap_or(u16::MAX));
        *self = LevelSampler::default();
        Some(mean)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_line_and_background_to_the_2010_scale() {
        let c = Calibration::new([300, 310, 290], [900, 880, 920]).unwrap();
        assert_eq!(c.apply([300, 310, 290]).values(), [256, 256, 256]);
        assert_eq!(c.apply([900, 880, 920]).values(), [768, 768, 768]);
        assert_eq!(c.apply_one(0, 0), 0);
        assert_eq!(c.apply_one(0, 1023), 872);
        assert_eq!(c.node_threshold(0), 450);
        assert_eq!(c.node_threshold(7), 0);
        assert_eq!(c.apply_one(9, 5000), 1023);
    }

    #[test]
    fn refuses_without_contrast_or_floor() {
        assert_eq!(
            Calibration::new([800, 300, 300], [900, 900, 900]),
            Err(CalibrationError::NoContrast { sensor: 0 })
        );
        assert_eq!(
            Calibration::new([300, 300, 30], [900, 900, 50]),
            Err(CalibrationError::TooDark { sensor: 2 })
        );
        assert_eq!(CalibrationError::NoContrast { sensor: 1 }.code(), 0x11);
        assert_eq!(CalibrationError::TooDark { sensor: 2 }.code(), 0x22);
    }

    #[test]
    fn record_round_trips_and_detects_damage() {
        let c = Calibration::new([300, 310, 290], [900, 880, 920]).unwrap();
        let r = c.record();
        assert_eq!(Record::load(&r.0), Ok(c));
        for i in 0..RECORD_LEN {
            let mut bad = r.0;
            bad[i] ^= 0x04;
            assert!(Record::load(&bad).is_err(), "flip in byte {i}");
        }
        assert_eq!(Record::load(&r.0[..15]), Err(RecordError::Length));
        assert_eq!(Record::load(&[0xff; 16]), Err(RecordError::Format));
    }

    #[test]
    fn sampler_averages() {
        let mut s = LevelSampler::default();
        for i in 0..SAMPLES - 1 {
            assert_eq!(s.add([i, 100, 1023]), None);
        }
        assert_eq!(s.add([7, 100, 1023]), Some([3, 100, 1023]));
    }
}
