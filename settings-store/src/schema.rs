//! The settings the device keeps across power-off: schema version [`SCHEMA_VERSION`].
//!
//! Units are SI unless a field's name says otherwise (`_counts`: encoder counts, `_ms`: ms, `_hz`: Hz).
//! Every field has a dotted path, the one `softfinger config get --json` prints and `config set`
//! takes (`identity.name`, `presets.0.stiffness_n_per_m`, `stream.rate_hz`, ...); [`Settings::validate`]
//! names the path of the first field out of range.

use heapless::String;
use serde::{Deserialize, Serialize};

/// The schema version written by this build. Version 1 is migrated on load (see [`crate::schema_v1`]).
pub const SCHEMA_VERSION: u16 = 2;

/// Longest device name, bytes of UTF-8.
pub const NAME_LEN: usize = 24;
/// Longest preset name, bytes of UTF-8.
pub const PRESET_NAME_LEN: usize = 16;
/// Number of contact-parameter presets kept.
pub const PRESETS: usize = 4;

/// Everything the store keeps, in one record (so a save replaces all of it or none of it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Settings {
    /// Who the device is.
    pub identity: Identity,
    /// What homing and the bench measured; `None` until the device has been calibrated and saved.
    /// The device never arms on a calibration it did not read (see [`crate::Loaded::may_arm`]).
    pub calibration: Option<Calibration>,
    /// Contact-parameter presets an application can select by index.
    pub presets: [ContactPreset; PRESETS],
    /// State-stream defaults applied at boot (`softfinger_app::boot_defaults`).
    pub stream: StreamDefaults,
    /// Communication-watchdog defaults applied at boot (`softfinger_app::boot_defaults`).
    pub watchdog: WatchdogDefaults,
}

/// The device's identity.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Identity {
    /// Serial number given by the maker; 0 = not set.
    pub serial: u32,
    /// A name the user gives the device (UTF-8, at most [`NAME_LEN`] bytes).
    pub name: String<NAME_LEN>,
}

/// Calibration of one device.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Calibration {
    /// Homing's result: offsets added to the extended motor counts to get homed counts, counts
    /// (`softfinger_core::control::pipeline::HomingStep::Done`).
    pub homing_offset_counts: [i32; 3],
    /// The wrist encoders' counts in the wrist calibration pose, counts.
    pub wrist_zero_counts: [i16; 3],
    /// Encoder directions `[motor0, motor1, motor2, wrist0, wrist1, wrist2]`: +1 or -1.
    pub encoder_direction: [i8; 6],
    /// Per-motor constants.
    pub motors: [MotorConstants; 3],
}

/// Constants of one motor, as measured on the bench.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MotorConstants {
    /// Torque constant, N·m/A, in (0, 1].
    pub torque_constant_nm_per_a: f32,
    /// Winding resistance, Ω, in (0, 100].
    pub resistance_ohm: f32,
}

/// One contact-parameter preset (the soft finger's contact with a surface).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ContactPreset {
    /// A label (UTF-8, at most [`PRESET_NAME_LEN`] bytes).
    pub name: String<PRESET_NAME_LEN>,
    /// Normal stiffness, N/m, in (0, 20 000].
    pub stiffness_n_per_m: f32,
    /// Normal damping, N·s/m, in [0, 50].
    pub damping_n_s_per_m: f32,
    /// Coulomb friction coefficient, in [0, 2].
    pub friction: f32,
    /// Spin (torsional) stiffness k_z, N·m/rad, in [0, 1].
    pub spin_stiffness_nm_per_rad: f32,
}

/// State-stream defaults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StreamDefaults {
    /// Stream rate the link starts with at boot, before any `SetStream`, Hz; 0 = off, else in
    /// [1, 10 000] (the device rounds it to a divisor of its control rate, at most its fastest
    /// stream: 2 kHz on the firmware).
    pub rate_hz: u16,
}

/// Communication-watchdog defaults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct WatchdogDefaults {
    /// The timeout a host's `Arm` turns the communication watchdog on with, ms, in
    /// [10, 10 000]; 0 = the firmware's built-in 200 ms (a host that arms always holds a
    /// watchdog; a device armed from its button, with no host, has none).
    pub timeout_ms: u16,
}

/// A field out of range: its dotted path and why.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FieldError {
    /// The field's dotted path, as `config get --json` prints it.
    pub key: &'static str,
    /// Why it was refused, one short phrase.
    pub reason: &'static str,
}

impl core::fmt::Display for FieldError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{}: {}", self.key, self.reason)
    }
}

/// Check `lo <= v <= hi` (or `lo < v` when `open_low`), finite.
fn range(key: &'static str, v: f32, lo: f32, hi: f32, open_low: bool) -> Result<(), FieldError> {
    if !v.is_finite() {
        return Err(FieldError {
            key,
            reason: "not a finite number",
        });
    }
    let low_ok = if open_low { v > lo } else { v >= lo };
    if !low_ok || v > hi {
        return Err(FieldError {
            key,
            reason: if open_low {
                "out of range (must be above the low limit and at most the high limit)"
            } else {
                "out of range"
            },
        });
    }
    Ok(())
}

const MOTOR_KEYS: [[&str; 2]; 3] = [
    [
        "calibration.motors.0.torque_constant_nm_per_a",
        "calibration.motors.0.resistance_ohm",
    ],
    [
        "calibration.motors.1.torque_constant_nm_per_a",
        "calibration.motors.1.resistance_ohm",
    ],
    [
        "calibration.motors.2.torque_constant_nm_per_a",
        "calibration.motors.2.resistance_ohm",
    ],
];
const PRESET_KEYS: [[&str; 4]; PRESETS] = [
    [
        "presets.0.stiffness_n_per_m",
        "presets.0.damping_n_s_per_m",
        "presets.0.friction",
        "presets.0.spin_stiffness_nm_per_rad",
    ],
    [
        "presets.1.stiffness_n_per_m",
        "presets.1.damping_n_s_per_m",
        "presets.1.friction",
        "presets.1.spin_stiffness_nm_per_rad",
    ],
    [
        "presets.2.stiffness_n_per_m",
        "presets.2.damping_n_s_per_m",
        "presets.2.friction",
        "presets.2.spin_stiffness_nm_per_rad",
    ],
    [
        "presets.3.stiffness_n_per_m",
        "presets.3.damping_n_s_per_m",
        "presets.3.friction",
        "presets.3.spin_stiffness_nm_per_rad",
    ],
];

impl Settings {
    /// Check every field; the first out of range is named.
    pub fn validate(&self) -> Result<(), FieldError> {
        if let Some(cal) = &self.calibration {
            for (i, d) in cal.encoder_direction.iter().enumerate() {
                if *d != 1 && *d != -1 {
                    const KEYS: [&str; 6] = [
                        "calibration.encoder_direction.0",
                        "calibration.encoder_direction.1",
                        "calibration.encoder_direction.2",
                        "calibration.encoder_direction.3",
                        "calibration.encoder_direction.4",
                        "calibration.encoder_direction.5",
                    ];
                    return Err(FieldError {
                        key: KEYS[i],
                        reason: "must be 1 or -1",
                    });
                }
            }
            for (m, keys) in cal.motors.iter().zip(MOTOR_KEYS.iter()) {
                range(keys[0], m.torque_constant_nm_per_a, 0.0, 1.0, true)?;
                range(keys[1], m.resistance_ohm, 0.0, 100.0, true)?;
            }
        }
        for (p, keys) in self.presets.iter().zip(PRESET_KEYS.iter()) {
            range(keys[0], p.stiffness_n_per_m, 0.0, 20_000.0, true)?;
            range(keys[1], p.damping_n_s_per_m, 0.0, 50.0, false)?;
            range(keys[2], p.friction, 0.0, 2.0, false)?;
            range(keys[3], p.spin_stiffness_nm_per_rad, 0.0, 1.0, false)?;
        }
        if self.stream.rate_hz > 10_000 {
            return Err(FieldError {
                key: "stream.rate_hz",
                reason: "out of range (0 = off, else 1..=10000)",
            });
        }
        let w = self.watchdog.timeout_ms;
        if w != 0 && !(10..=10_000).contains(&w) {
            return Err(FieldError {
                key: "watchdog.timeout_ms",
                reason: "out of range (0 = off, else 10..=10000)",
            });
        }
        Ok(())
    }
}

fn preset(name: &str, k: f32, b: f32, mu: f32, kz: f32) -> ContactPreset {
    let mut n = String::new();
    // Every default name is shorter than PRESET_NAME_LEN.
    let _ = n.push_str(name);
    ContactPreset {
        name: n,
        stiffness_n_per_m: k,
        damping_n_s_per_m: b,
        friction: mu,
        spin_stiffness_nm_per_rad: kz,
    }
}

impl Default for Settings {
    /// What a device without a readable store runs on: no serial, no name, no calibration, the
    /// default presets, the stream off and the host watchdog at 200 ms.
    fn default() -> Self {
        Self {
            identity: Identity {
                serial: 0,
                name: String::new(),
            },
            calibration: None,
            presets: [
                preset("soft", 500.0, 1.0, 0.8, 0.002),
                preset("medium", 2000.0, 2.0, 0.6, 0.005),
                preset("hard", 8000.0, 5.0, 0.5, 0.01),
                preset("slippery", 2000.0, 2.0, 0.1, 0.001),
            ],
            stream: StreamDefaults { rate_hz: 0 },
            watchdog: WatchdogDefaults { timeout_ms: 200 },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn calibrated() -> Settings {
        let motor = MotorConstants {
            torque_constant_nm_per_a: 0.03,
            resistance_ohm: 1.2,
        };
        Settings {
            calibration: Some(Calibration {
                homing_offset_counts: [10, -20, 30],
                wrist_zero_counts: [1, 2, 3],
                encoder_direction: [1, -1, 1, 1, -1, 1],
                motors: [motor; 3],
            }),
            ..Settings::default()
        }
    }

    #[test]
    fn defaults_are_valid() {
        assert_eq!(Settings::default().validate(), Ok(()));
        assert_eq!(calibrated().validate(), Ok(()));
    }

    #[test]
    fn stiffness_limits_just_inside_and_outside() {
        let mut s = Settings::default();
        s.presets[2].stiffness_n_per_m = 20_000.0;
        assert_eq!(s.validate(), Ok(()));
        s.presets[2].stiffness_n_per_m = 20_000.002;
        assert_eq!(s.validate().unwrap_err().key, "presets.2.stiffness_n_per_m");
        s.presets[2].stiffness_n_per_m = 0.0;
        assert_eq!(s.validate().unwrap_err().key, "presets.2.stiffness_n_per_m");
        s.presets[2].stiffness_n_per_m = f32::MIN_POSITIVE;
        assert_eq!(s.validate(), Ok(()));
        s.presets[2].stiffness_n_per_m = f32::NAN;
        assert_eq!(s.validate().unwrap_err().reason, "not a finite number");
    }

    #[test]
    fn watchdog_and_stream_limits() {
        let mut s = Settings::default();
        for (w, ok) in [
            (0, true),
            (9, false),
            (10, true),
            (10_000, true),
            (10_001, false),
        ] {
            s.watchdog.timeout_ms = w;
            assert_eq!(s.validate().is_ok(), ok, "watchdog {w}");
        }
        s.watchdog.timeout_ms = 200;
        for (r, ok) in [(0, true), (10_000, true), (10_001, false)] {
            s.stream.rate_hz = r;
            assert_eq!(s.validate().is_ok(), ok, "rate {r}");
        }
    }

    #[test]
    fn calibration_fields_named() {
        let mut s = calibrated();
        s.calibration.as_mut().unwrap().encoder_direction[4] = 0;
        assert_eq!(
            s.validate().unwrap_err().key,
            "calibration.encoder_direction.4"
        );
        let mut s = calibrated();
        s.calibration.as_mut().unwrap().motors[1].resistance_ohm = 100.0;
        assert_eq!(s.validate(), Ok(()));
        s.calibration.as_mut().unwrap().motors[1].resistance_ohm = 100.01;
        assert_eq!(
            s.validate().unwrap_err().key,
            "calibration.motors.1.resistance_ohm"
        );
    }
}
