//! The firmware's boot-time load, independent of the board: open the store on a flash region,
//! load it, and say what the device must report and whether it may arm.
//!
//! [`load_at_boot`] never fails and never panics: a region the map cannot use (not whole pages,
//! under two pages) or a flash that cannot be read gives the defaults with
//! [`LoadStatus::FlashError`], like an absent, corrupt or unknown-version record gives them with
//! its own status. [`BootLoad::flags`] is the bit set for device info, [`BootLoad::notice`] the
//! line for the log, and [`BootLoad::arm_refusal`] why arming is refused (none when the
//! calibration was read from the store).

use core::ops::Range;

use embedded_storage_async::nor_flash::NorFlash;

use crate::schema::Settings;
use crate::store::{LoadStatus, Loaded, Store};

/// Device-info flag: the settings in force are the defaults (nothing usable was read).
pub const FLAG_DEFAULTS: u8 = 1 << 0;
/// Device-info flag: the store was erased or never written.
pub const FLAG_ABSENT: u8 = 1 << 1;
/// Device-info flag: the record failed its CRC or did not decode.
pub const FLAG_CORRUPT: u8 = 1 << 2;
/// Device-info flag: the record is of a schema this firmware does not know.
pub const FLAG_UNKNOWN_VERSION: u8 = 1 << 3;
/// Device-info flag: the record was of an earlier schema and was migrated (not yet re-saved).
pub const FLAG_MIGRATED: u8 = 1 << 4;
/// Device-info flag: the flash region could not be opened or read.
pub const FLAG_FLASH_ERROR: u8 = 1 << 5;
/// Device-info flag: no calibration read from the store (the settings in force have none).
pub const FLAG_NO_CALIBRATION: u8 = 1 << 6;

/// What the boot-time load gives the firmware.
#[derive(Clone, Debug, PartialEq)]
pub struct BootLoad {
    /// The settings to run on and what the load found.
    pub loaded: Loaded,
}

impl BootLoad {
    /// The settings to run on.
    pub fn settings(&self) -> &Settings {
        &self.loaded.settings
    }

    /// What the load found.
    pub fn status(&self) -> LoadStatus {
        self.loaded.status
    }

    /// True only for a calibration read from the store.
    pub fn may_arm(&self) -> bool {
        self.loaded.may_arm()
    }

    /// The device-info flags (`FLAG_*`); 0 for a current-schema record with a calibration.
    pub fn flags(&self) -> u8 {
        let mut f = match self.loaded.status {
            LoadStatus::Read => 0,
            LoadStatus::Migrated { .. } => FLAG_MIGRATED,
            LoadStatus::Absent => FLAG_DEFAULTS | FLAG_ABSENT,
            LoadStatus::Corrupt => FLAG_DEFAULTS | FLAG_CORRUPT,
            LoadStatus::UnknownVersion(_) => FLAG_DEFAULTS | FLAG_UNKNOWN_VERSION,
            LoadStatus::FlashError => FLAG_DEFAULTS | FLAG_FLASH_ERROR,
        };
        if !self.may_arm() {
            f |= FLAG_NO_CALIBRATION;
        }
        f
    }

    /// The log line for this load.
    pub fn notice(&self) -> &'static str {
        match self.loaded.status {
            LoadStatus::Read => "settings: read from the store",
            LoadStatus::Migrated { .. } => {
                "settings: read from an earlier schema and migrated (save to keep them in the current one)"
            }
            LoadStatus::Absent => "settings: store empty, running on the defaults",
            LoadStatus::Corrupt => "settings: store corrupt, running on the defaults",
            LoadStatus::UnknownVersion(_) => {
                "settings: store written by a newer firmware (unknown schema), running on the defaults"
            }
            LoadStatus::FlashError => "settings: store unreadable, running on the defaults",
        }
    }

    /// Why the device refuses to arm, or `None` when it may.
    pub fn arm_refusal(&self) -> Option<&'static str> {
        if self.may_arm() {
            None
        } else if self.loaded.status.from_store() {
            Some("no calibration in the store: home and save the calibration first")
        } else {
            Some("the calibration could not be read from the store (see the settings flag)")
        }
    }
}

/// Load the store in `region` of `flash` at boot; never fails (see the module doc).
pub async fn load_at_boot<F: NorFlash>(flash: &mut F, region: Range<u32>) -> BootLoad {
    let loaded = match Store::new(flash, region) {
        Ok(mut store) => store.load().await,
        Err(_) => Loaded {
            settings: Settings::default(),
            status: LoadStatus::FlashError,
        },
    };
    BootLoad { loaded }
}

/// [`load_at_boot`] for start-up code without an executor (the flash futures complete without
/// waiting).
pub fn load_at_boot_blocking<F: NorFlash>(flash: &mut F, region: Range<u32>) -> BootLoad {
    embassy_futures::block_on(load_at_boot(flash, region))
}
