//! One record in flash: the schema version, the settings in postcard, and a CRC.
//!
//! ```text
//! version:u16 LE | postcard(settings of that version) | crc32c(version | postcard):u32 LE
//! ```
//!
//! sequential-storage checks its own CRC over each item; this one is ours, so a record is
//! checked whatever carries it (a file exported by a tool, a future storage layer).

use crc::{Crc, CRC_32_ISCSI};

use crate::schema::{Settings, SCHEMA_VERSION};
use crate::schema_v1;

const CRC32C: Crc<u32> = Crc::<u32>::new(&CRC_32_ISCSI);
const VERSION_LEN: usize = 2;
const CRC_LEN: usize = 4;

/// The largest record, bytes: the version, the largest postcard encoding of [`Settings`] (about
/// 260 bytes with every string full and every varint at its longest) and the CRC, with room to grow.
pub const MAX_RECORD_LEN: usize = 512;

/// Why a record was not read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RecordError {
    /// Shorter than a version and a CRC, or the CRC does not match.
    Crc,
    /// The CRC matches but the version is not one this build reads.
    UnknownVersion(u16),
    /// The CRC matches but the body does not decode as its version's schema, or is out of range.
    Malformed,
    /// The settings do not fit [`MAX_RECORD_LEN`] (a bug: every valid settings fit).
    TooLong,
}

/// Encode `settings` as a current-version record into `buf`; returns the record's length.
pub fn encode(settings: &Settings, buf: &mut [u8]) -> Result<usize, RecordError> {
    encode_version(SCHEMA_VERSION, settings, buf)
}

/// Encode any serialisable body under `version` (tests write older schemas with it).
pub fn encode_version<T: serde::Serialize>(
    version: u16,
    body: &T,
    buf: &mut [u8],
) -> Result<usize, RecordError> {
    if buf.len() < VERSION_LEN + CRC_LEN {
        return Err(RecordError::TooLong);
    }
    buf[..VERSION_LEN].copy_from_slice(&version.to_le_bytes());
    let end = buf.len() - CRC_LEN;
    let n = postcard::to_slice(body, &mut buf[VERSION_LEN..end])
        .map_err(|_| RecordError::TooLong)?
        .len();
    let data_end = VERSION_LEN + n;
    let crc = CRC32C.checksum(&buf[..data_end]);
    buf[data_end..data_end + CRC_LEN].copy_from_slice(&crc.to_le_bytes());
    Ok(data_end + CRC_LEN)
}

/// Decode a record. Returns the settings in the current schema and the version they were read as
/// (`< SCHEMA_VERSION`: migrated).
pub fn decode(record: &[u8]) -> Result<(Settings, u16), RecordError> {
    if record.len() < VERSION_LEN + CRC_LEN {
        return Err(RecordError::Crc);
    }
    let (data, crc) = record.split_at(record.len() - CRC_LEN);
    if CRC32C.checksum(data) != u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]) {
        return Err(RecordError::Crc);
    }
    let version = u16::from_le_bytes([data[0], data[1]]);
    let body = &data[VERSION_LEN..];
    let settings = match version {
        SCHEMA_VERSION => {
            postcard::from_bytes::<Settings>(body).map_err(|_| RecordError::Malformed)?
        }
        schema_v1::VERSION => postcard::from_bytes::<schema_v1::SettingsV1>(body)
            .map_err(|_| RecordError::Malformed)?
            .migrate(),
        other => return Err(RecordError::UnknownVersion(other)),
    };
    settings.validate().map_err(|_| RecordError::Malformed)?;
    Ok((settings, version))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schema::{Calibration, MotorConstants};

    fn full() -> Settings {
        let mut s = Settings::default();
        s.identity.serial = u32::MAX;
        s.identity.name.clear();
        for _ in 0..crate::schema::NAME_LEN {
            s.identity.name.push('x').unwrap();
        }
        for p in s.presets.iter_mut() {
            p.name.clear();
            for _ in 0..crate::schema::PRESET_NAME_LEN {
                p.name.push('y').unwrap();
            }
        }
        s.calibration = Some(Calibration {
            homing_offset_counts: [i32::MIN; 3],
            wrist_zero_counts: [i16::MIN; 3],
            encoder_direction: [-1; 6],
            motors: [MotorConstants {
                torque_constant_nm_per_a: 1.0,
                resistance_ohm: 100.0,
            }; 3],
        });
        s.stream.rate_hz = 10_000;
        s.watchdog.timeout_ms = 10_000;
        s
    }

    #[test]
    fn round_trip_and_the_largest_record_fits() {
        let mut buf = [0u8; MAX_RECORD_LEN];
        let n = encode(&full(), &mut buf).unwrap();
        assert!(n < MAX_RECORD_LEN / 2 + 64, "largest record {n} bytes");
        assert_eq!(decode(&buf[..n]), Ok((full(), SCHEMA_VERSION)));
    }

    #[test]
    fn every_single_bit_flip_is_refused() {
        let mut buf = [0u8; MAX_RECORD_LEN];
        let n = encode(&full(), &mut buf).unwrap();
        for bit in 0..n * 8 {
            let mut r = buf;
            r[bit / 8] ^= 1 << (bit % 8);
            assert_eq!(decode(&r[..n]), Err(RecordError::Crc), "bit {bit}");
        }
        assert_eq!(decode(&buf[..3]), Err(RecordError::Crc));
        assert_eq!(decode(&buf[..n - 1]), Err(RecordError::Crc));
    }

    #[test]
    fn unknown_version_is_named() {
        let mut buf = [0u8; MAX_RECORD_LEN];
        let n = encode_version(3, &full(), &mut buf).unwrap();
        assert_eq!(decode(&buf[..n]), Err(RecordError::UnknownVersion(3)));
        let n = encode_version(0, &full(), &mut buf).unwrap();
        assert_eq!(decode(&buf[..n]), Err(RecordError::UnknownVersion(0)));
    }

    #[test]
    fn a_valid_crc_over_out_of_range_settings_is_malformed() {
        let mut s = full();
        s.watchdog.timeout_ms = 5;
        let mut buf = [0u8; MAX_RECORD_LEN];
        let n = encode(&s, &mut buf).unwrap();
        assert_eq!(decode(&buf[..n]), Err(RecordError::Malformed));
    }

    #[test]
    fn schema_1_migrates_keeping_every_measured_field() {
        let v1 = schema_v1::SettingsV1 {
            identity: full().identity,
            calibration: Some(schema_v1::CalibrationV1 {
                homing_offset_counts: [1, 2, 3],
                wrist_zero_counts: [-4, 5, -6],
                encoder_direction: [1, 1, -1, 1, 1, -1],
            }),
            presets: full().presets,
            stream: full().stream,
        };
        let mut buf = [0u8; MAX_RECORD_LEN];
        let n = encode_version(schema_v1::VERSION, &v1, &mut buf).unwrap();
        let (s, from) = decode(&buf[..n]).unwrap();
        assert_eq!(from, 1);
        assert_eq!(s.identity, v1.identity);
        assert_eq!(s.presets, v1.presets);
        assert_eq!(s.stream, v1.stream);
        assert_eq!(s.watchdog, Settings::default().watchdog);
        let c = s.calibration.unwrap();
        assert_eq!(c.homing_offset_counts, [1, 2, 3]);
        assert_eq!(c.wrist_zero_counts, [-4, 5, -6]);
        assert_eq!(c.encoder_direction, [1, 1, -1, 1, 1, -1]);
        assert_eq!(c.motors, [schema_v1::NOMINAL_MOTOR; 3]);
    }
}
