//! Schema version 1, as the first builds wrote it, and its migration to the current schema.
//!
//! Version 1 had no watchdog defaults and no per-motor constants in the calibration. Migration
//! keeps every measured field and fills the two new ones with the defaults: the watchdog at
//! [`Settings::default`]'s timeout, the motor constants at [`NOMINAL_MOTOR`] (the datasheet values of
//! the device's motors), so a migrated calibration still arms.

use serde::{Deserialize, Serialize};

use crate::schema::{
    Calibration, ContactPreset, Identity, MotorConstants, Settings, StreamDefaults, PRESETS,
};

/// The schema version this module reads.
pub const VERSION: u16 = 1;

/// The motor constants a calibration from schema 1 is given: the datasheet values.
pub const NOMINAL_MOTOR: MotorConstants = MotorConstants {
    torque_constant_nm_per_a: 0.0302,
    resistance_ohm: 1.16,
};

/// Schema 1's record.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SettingsV1 {
    /// As in schema 2.
    pub identity: Identity,
    /// Schema 1's calibration (no motor constants).
    pub calibration: Option<CalibrationV1>,
    /// As in schema 2.
    pub presets: [ContactPreset; PRESETS],
    /// As in schema 2.
    pub stream: StreamDefaults,
}

/// Schema 1's calibration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CalibrationV1 {
    /// Homing's offsets, counts.
    pub homing_offset_counts: [i32; 3],
    /// Wrist zero, counts.
    pub wrist_zero_counts: [i16; 3],
    /// Encoder directions, +1 or -1.
    pub encoder_direction: [i8; 6],
}

impl SettingsV1 {
    /// The same settings in the current schema.
    pub fn migrate(self) -> Settings {
        Settings {
            identity: self.identity,
            calibration: self.calibration.map(|c| Calibration {
                homing_offset_counts: c.homing_offset_counts,
                wrist_zero_counts: c.wrist_zero_counts,
                encoder_direction: c.encoder_direction,
                motors: [NOMINAL_MOTOR; 3],
            }),
            presets: self.presets,
            stream: self.stream,
            watchdog: Settings::default().watchdog,
        }
    }
}
