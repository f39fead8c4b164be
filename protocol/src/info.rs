//! What a device says about itself, and its link counters.

use crate::model::SurfaceKind;
use serde::{Deserialize, Serialize};

/// Fixed-capacity text (device name, firmware version).
pub type Text<const N: usize> = heapless::String<N>;

/// The device's description, answered to [`crate::Request::GetInfo`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DeviceInfo {
    /// Protocol version the device speaks.
    pub protocol_version: u8,
    /// Device name.
    pub name: Text<24>,
    /// Firmware (or simulator) version.
    pub firmware_version: Text<16>,
    /// True for the virtual device (host-sim), false for hardware.
    pub virtual_device: bool,
    /// Control rate, Hz.
    pub control_rate_hz: u32,
    /// Largest force the device renders, N.
    pub max_force_n: f32,
    /// Smallest stream divisor accepted (the fastest state stream is rate / this).
    pub min_stream_divisor: u16,
    /// Surfaces it can render.
    pub surfaces: heapless::Vec<SurfaceKind, 8>,
    /// Communication watchdog timeout in force, ms (0: off).
    pub watchdog_ms: u16,
    /// What the boot's load of the settings store found: `softfinger_store::boot::FLAG_*` bits
    /// (0: the settings and a calibration read from the store; see [`settings_flag_names`]).
    pub settings_flags: u8,
    /// Why the device last started (`power-on`, `reset-pin`, `software`, `watchdog`,
    /// `window-watchdog`, `low-power`, `option-bytes`, `unknown`; `virtual` for host-sim).
    pub reset_cause: Text<16>,
}

/// The names of the bits set in a [`DeviceInfo::settings_flags`], lowest bit first.
pub fn settings_flag_names(flags: u8) -> impl Iterator<Item = &'static str> {
    use softfinger_store::boot as b;
    [
        (b::FLAG_DEFAULTS, "defaults"),
        (b::FLAG_ABSENT, "absent"),
        (b::FLAG_CORRUPT, "corrupt"),
        (b::FLAG_UNKNOWN_VERSION, "unknown-version"),
        (b::FLAG_MIGRATED, "migrated"),
        (b::FLAG_FLASH_ERROR, "flash-error"),
        (b::FLAG_NO_CALIBRATION, "no-calibration"),
    ]
    .into_iter()
    .filter(move |(bit, _)| flags & bit != 0)
    .map(|(_, name)| name)
}

/// Link counters over all connections since the device started.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LinkCounters {
    /// Frames received and decoded.
    pub rx_frames: u32,
    /// Frames received and rejected, all kinds (the sum of the five below).
    pub rx_errors: u32,
    /// Rejected: invalid COBS.
    pub rx_cobs: u32,
    /// Rejected: CRC mismatch (or too short to hold one).
    pub rx_crc: u32,
    /// Rejected: unknown protocol version.
    pub rx_version: u32,
    /// Rejected: body did not decode as a message.
    pub rx_decode: u32,
    /// Rejected: longer than the largest frame.
    pub rx_oversized: u32,
    /// Frames sent.
    pub tx_frames: u32,
    /// State samples dropped because a connection's queue was full.
    pub tx_dropped: u32,
    /// Connections open now.
    pub connections: u16,
}

impl LinkCounters {
    /// What was counted since `earlier`: each count's wrapping difference; `connections`, a
    /// level rather than a count, is the one open now.
    pub fn since(&self, earlier: &LinkCounters) -> LinkCounters {
        LinkCounters {
            rx_frames: self.rx_frames.wrapping_sub(earlier.rx_frames),
            rx_errors: self.rx_errors.wrapping_sub(earlier.rx_errors),
            rx_cobs: self.rx_cobs.wrapping_sub(earlier.rx_cobs),
            rx_crc: self.rx_crc.wrapping_sub(earlier.rx_crc),
            rx_version: self.rx_version.wrapping_sub(earlier.rx_version),
            rx_decode: self.rx_decode.wrapping_sub(earlier.rx_decode),
            rx_oversized: self.rx_oversized.wrapping_sub(earlier.rx_oversized),
            tx_frames: self.tx_frames.wrapping_sub(earlier.tx_frames),
            tx_dropped: self.tx_dropped.wrapping_sub(earlier.tx_dropped),
            connections: self.connections,
        }
    }

    /// The counts of two sets of links together (each count's wrapping sum, `connections`
    /// added): a device with several links answers with the sum over them.
    pub fn plus(&self, other: &LinkCounters) -> LinkCounters {
        LinkCounters {
            rx_frames: self.rx_frames.wrapping_add(other.rx_frames),
            rx_errors: self.rx_errors.wrapping_add(other.rx_errors),
            rx_cobs: self.rx_cobs.wrapping_add(other.rx_cobs),
            rx_crc: self.rx_crc.wrapping_add(other.rx_crc),
            rx_version: self.rx_version.wrapping_add(other.rx_version),
            rx_decode: self.rx_decode.wrapping_add(other.rx_decode),
            rx_oversized: self.rx_oversized.wrapping_add(other.rx_oversized),
            tx_frames: self.tx_frames.wrapping_add(other.tx_frames),
            tx_dropped: self.tx_dropped.wrapping_add(other.tx_dropped),
            connections: self.connections.saturating_add(other.connections),
        }
    }
}
