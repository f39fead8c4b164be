//! The device description answered to `GetInfo`.

use softfinger_protocol::info::Text;
use softfinger_protocol::{DeviceInfo, SurfaceKind, PROTOCOL_VERSION};

/// What the link says about the device.
#[derive(Clone, Copy, Debug)]
pub struct InfoSource {
    /// Device name (`DeviceDefinition::name`); cut to 24 bytes.
    pub name: &'static str,
    /// Firmware version (the crate version); cut to 16 bytes.
    pub firmware_version: &'static str,
    /// Control rate, Hz.
    pub control_rate_hz: u32,
    /// Largest force rendered (the contact parameters' `max_force_n`), N.
    pub max_force_n: f32,
    /// Smallest stream divisor (see [`min_stream_divisor`]).
    pub min_stream_divisor: u16,
    /// Communication watchdog timeout in force, ms (0: off).
    pub watchdog_ms: u16,
    /// Why the MCU last reset (`crate::reset_cause::ResetCause::name`).
    pub reset_cause: &'static str,
}

pub use crate::stream::min_stream_divisor;

/// `s` cut at a character boundary to fit `N` bytes.
pub fn text<const N: usize>(s: &str) -> Text<N> {
    let mut t = Text::new();
    for c in s.chars() {
        if t.push(c).is_err() {
            break;
        }
    }
    t
}

/// The description: the local model's surfaces, the watchdog in force, the settings store's
/// flags (`softfinger_store::boot::FLAG_*`).
pub fn device_info(src: &InfoSource, settings_flags: u8) -> DeviceInfo {
    DeviceInfo {
        protocol_version: PROTOCOL_VERSION,
        name: text(src.name),
        firmware_version: text(src.firmware_version),
        virtual_device: false,
        control_rate_hz: src.control_rate_hz,
        max_force_n: src.max_force_n,
        min_stream_divisor: src.min_stream_divisor,
        // Every kind the local-model renderer draws. Cannot fail: 4 kinds, capacity 8.
        surfaces: heapless::Vec::from_slice(&SurfaceKind::ALL).unwrap_or_default(),
        watchdog_ms: src.watchdog_ms,
        settings_flags,
        reset_cause: text(src.reset_cause),
    }
}
