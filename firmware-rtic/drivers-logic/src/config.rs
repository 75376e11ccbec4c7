//! The calibration record kept in flash sector 11 (0x080E_0000, 128 KiB).
//!
//! The C firmware keeps an append-only msgpack log there; we only need the
//! ground-sensor black and white levels (the seed kept 24 bytes in EEPROM),
//! so the record is a fixed 32-byte block: magic, version, the levels, and a
//! CRC-32 over everything before it. An erased sector (all 0xFF) or a torn
//! write fails the magic or the CRC, and the firmware falls back to
//! [`crate::ground::GroundCalibration::IDENTITY`].

/// First address of flash sector 11.
pub const SECTOR_ADDRESS: u32 = 0x080E_0000;
/// Sector number for the erase command.
pub const SECTOR: u8 = 11;
/// Offset of sector 11 from the start of flash.
pub const SECTOR_OFFSET: usize = 0x000E_0000;
/// Encoded record length.
pub const RECORD_LEN: usize = 32;
/// "EPK2" little-endian.
pub const MAGIC: u32 = u32::from_le_bytes(*b"EPK2");
/// Layout version; bump on any change.
pub const VERSION: u16 = 1;

/// Raw ground-sensor levels measured on the line and on the background.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CalibrationRecord {
    /// Raw deltas on black: left, centre, right.
    pub black: [u16; 3],
    /// Raw deltas on white: left, centre, right.
    pub white: [u16; 3],
}

/// Why stored bytes were not accepted.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RecordError {
    /// Fewer than [`RECORD_LEN`] bytes.
    Short,
    /// No record there (erased or foreign data).
    BadMagic,
    /// A record of another layout version.
    Version(u16),
    /// The checksum does not match: torn write or bit rot.
    Checksum,
}

impl CalibrationRecord {
    /// The 32-byte image: magic, version, 2 reserved bytes, black, white,
    /// 8 reserved bytes (0xFF, so they need no programming), CRC-32.
    pub fn encode(&self) -> [u8; RECORD_LEN] {
        let mut b = [0xFFu8; RECORD_LEN];
        b[0..4].copy_from_slice(&MAGIC.to_le_bytes());
        b[4..6].copy_from_slice(&VERSION.to_le_bytes());
        for (i, v) in self.black.iter().chain(self.white.iter()).enumerate() {
            b[8 + 2 * i..10 + 2 * i].copy_from_slice(&v.to_le_bytes());
        }
        let crc = crc32(&b[..RECORD_LEN - 4]);
        b[RECORD_LEN - 4..].copy_from_slice(&crc.to_le_bytes());
        b
    }

    /// Parses and checks an image.
    pub fn decode(b: &[u8]) -> Result<Self, RecordError> {
        if b.len() < RECORD_LEN {
            return Err(RecordError::Short);
        }
        let le32 = |i: usize| u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        let le16 = |i: usize| u16::from_le_bytes([b[i], b[i + 1]]);
        if le32(0) != MAGIC {
            return Err(RecordError::BadMagic);
        }
        if le16(4) != VERSION {
            return Err(RecordError::Version(le16(4)));
        }
        if le32(RECORD_LEN - 4) != crc32(&b[..RECORD_LEN - 4]) {
            return Err(RecordError::Checksum);
        }
        Ok(CalibrationRecord {
            black: [le16(8), le16(10), le16(12)],
            white: [le16(14), le16(16), le16(18)],
        })
    }
}

/// CRC-32 (IEEE 802.3, reflected, init and final xor 0xFFFF_FFFF), bitwise:
/// 32 bytes once per boot do not justify a table in flash.
pub fn crc32(data: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &byte in data {
        crc ^= byte as u32;
        for _ in 0..8 {
            let mask = (crc & 1).wrapping_neg();
            crc = (crc >> 1) ^ (0xEDB8_8320 & mask);
        }
    }
    !crc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_check_value() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
    }

    #[test]
    fn roundtrip() {
        let r = CalibrationRecord {
            black: [1, 2, 3],
            white: [700, 800, 900],
        };
        let b = r.encode();
        assert_eq!(CalibrationRecord::decode(&b), Ok(r));
    }

    #[test]
    fn rejects_erased_torn_and_short() {
        assert_eq!(
            CalibrationRecord::decode(&[0xFF; RECORD_LEN]),
            Err(RecordError::BadMagic)
        );
        assert_eq!(CalibrationRecord::decode(&[0; 4]), Err(RecordError::Short));
        let mut b = CalibrationRecord {
            black: [1, 2, 3],
            white: [7, 8, 9],
        }
        .encode();
        b[10] ^= 0x40;
        assert_eq!(CalibrationRecord::decode(&b), Err(RecordError::Checksum));
        let mut b = CalibrationRecord::default().encode();
        b[4] = 9;
        assert_eq!(CalibrationRecord::decode(&b), Err(RecordError::Version(9)));
    }
}
