//! Settings over the link: get, set, save and reset the device's persistent settings
//! (`softfinger-store`), one section per message (a whole [`softfinger_store::Settings`] does not
//! fit one frame).
//!
//! The device keeps the settings it runs on in RAM; [`crate::Request::ConfigSet`] changes a
//! section there (validated as a whole: a refusal names the field's dotted path and why),
//! [`crate::Request::ConfigSave`] writes them to flash (only while disarmed),
//! [`crate::Request::ConfigReset`] erases the store and puts the defaults in force.

use heapless::String;
use serde::{Deserialize, Serialize};
pub use softfinger_store::{
    Calibration, ContactPreset, Identity, StreamDefaults, WatchdogDefaults,
};

/// Which section to read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ConfigSection {
    /// Where the settings came from ([`ConfigValue::Status`]).
    Status,
    /// [`ConfigValue::Identity`].
    Identity,
    /// [`ConfigValue::Calibration`].
    Calibration,
    /// [`ConfigValue::Preset`] with this index (0..`softfinger_store::schema::PRESETS`).
    Preset(u8),
    /// [`ConfigValue::Stream`].
    Stream,
    /// [`ConfigValue::Watchdog`].
    Watchdog,
}

/// What the boot's load of the store found (`softfinger_store::LoadStatus` on the wire).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StoreStatus {
    /// Read.
    Read,
    /// Read from an earlier schema and migrated.
    Migrated {
        /// The schema version read.
        from: u16,
    },
    /// No settings stored: defaults.
    Absent,
    /// Unreadable: defaults.
    Corrupt,
    /// Written by a newer firmware: defaults.
    UnknownVersion(u16),
    /// The flash failed: defaults.
    FlashError,
}

impl From<softfinger_store::LoadStatus> for StoreStatus {
    fn from(s: softfinger_store::LoadStatus) -> Self {
        use softfinger_store::LoadStatus as L;
        match s {
            L::Read => StoreStatus::Read,
            L::Migrated { from } => StoreStatus::Migrated { from },
            L::Absent => StoreStatus::Absent,
            L::Corrupt => StoreStatus::Corrupt,
            L::UnknownVersion(v) => StoreStatus::UnknownVersion(v),
            L::FlashError => StoreStatus::FlashError,
        }
    }
}

/// One section's value.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ConfigValue {
    /// Read-only: what the boot's load found, whether the store lets the device arm, whether
    /// the settings in force differ from the stored ones.
    Status {
        /// The load's result.
        store: StoreStatus,
        /// The schema version this firmware writes.
        schema_version: u16,
        /// The store's arm check: false while the store holds settings the device could not
        /// read (corrupt, unknown schema, flash error) until they are saved over or erased.
        may_arm: bool,
        /// Settings changed since the last save or load.
        unsaved: bool,
    },
    /// The identity.
    Identity(Identity),
    /// The calibration, `None` when there is none.
    Calibration(Option<Calibration>),
    /// A contact preset.
    Preset {
        /// Its index.
        index: u8,
        /// Its value.
        preset: ContactPreset,
    },
    /// The stream defaults.
    Stream(StreamDefaults),
    /// The watchdog defaults.
    Watchdog(WatchdogDefaults),
}

/// Why a configuration request was refused: the field's dotted path (or the section) and why.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ConfigRefusal {
    /// The dotted path (`presets.2.friction`), or the section (`calibration`), or `store`.
    pub key: String<48>,
    /// Why, one phrase.
    pub reason: String<80>,
}

impl ConfigRefusal {
    /// A refusal; key and reason are cut to fit.
    pub fn new(key: &str, reason: &str) -> Self {
        Self {
            key: truncated(key),
            reason: truncated(reason),
        }
    }
}

fn truncated<const N: usize>(s: &str) -> String<N> {
    let mut out = String::new();
    for c in s.chars() {
        if out.push(c).is_err() {
            break;
        }
    }
    out
}
