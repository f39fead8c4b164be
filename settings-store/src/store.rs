//! The settings in flash: one record under one key of a `sequential-storage` map, so a save
//! appends the new record and a later load finds the newest whole one. A power cut during a save
//! leaves the previous record readable (its item and ours are CRC-checked; a torn item is
//! skipped and repaired away on the next operation), so a load returns the old or the new settings.
//!
//! Loading never fails: absent, corrupt or unknown-version records give the defaults and a
//! [`LoadStatus`] saying which; [`Loaded::may_arm`] is what the arm check reads.

use core::ops::Range;

use embedded_storage_async::nor_flash::NorFlash;
use sequential_storage::cache::{Cache, Uncached};
use sequential_storage::map::{MapConfig, MapConfigError, MapStorage};

use crate::record::{self, RecordError, MAX_RECORD_LEN};
use crate::schema::{FieldError, Settings, SCHEMA_VERSION};

/// The map key of the settings record.
const SETTINGS_KEY: u8 = 1;

/// The working buffer: the key, the largest record, and room for the flash word alignment.
const BUF_LEN: usize = MAX_RECORD_LEN + 16;

/// What a load found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LoadStatus {
    /// A record of the current schema, read.
    Read,
    /// A record of an earlier schema, read and migrated (saving writes it in the current schema).
    Migrated {
        /// The schema version read.
        from: u16,
    },
    /// No record: a new device or an erased store. Defaults.
    Absent,
    /// A record that does not pass its CRC or does not decode, or a store the storage layer
    /// could not repair. Defaults.
    Corrupt,
    /// A record of a schema this build does not know (written by a newer firmware). Defaults.
    UnknownVersion(u16),
    /// The flash could not be read. Defaults.
    FlashError,
}

impl LoadStatus {
    /// True when the settings came from the store (read or migrated), false when they are the defaults.
    pub fn from_store(self) -> bool {
        matches!(self, LoadStatus::Read | LoadStatus::Migrated { .. })
    }
}

/// The settings the device runs on after a load, and where they came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Loaded {
    /// The settings (the defaults unless [`LoadStatus::from_store`]).
    pub settings: Settings,
    /// What the load found.
    pub status: LoadStatus,
}

impl Loaded {
    /// True only when the calibration was read from the store.
    pub fn may_arm(&self) -> bool {
        self.status.from_store() && self.settings.calibration.is_some()
    }
}

/// Why a save was refused or failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SaveError {
    /// The device is armed: the store is written only while disarmed.
    Armed,
    /// A field is out of range; nothing written.
    Invalid(FieldError),
    /// The storage layer failed (flash error, full, corrupt); the previous record is still the
    /// one a load finds.
    Storage,
}

/// The settings store over a flash region (`range`, whole pages, at least two).
pub struct Store<F: NorFlash> {
    map: MapStorage<u8, F, Cache<Uncached, Uncached, Uncached, u8>>,
    buf: [u8; BUF_LEN],
}

impl<F: NorFlash> core::fmt::Debug for Store<F> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Store").finish_non_exhaustive()
    }
}

impl<F: NorFlash> Store<F> {
    /// A store in `range` of `flash`; refused when the range is not whole pages or under two.
    pub fn new(flash: F, range: Range<u32>) -> Result<Self, MapConfigError> {
        let config = MapConfig::<F>::try_new(range)?;
        Ok(Self {
            map: MapStorage::new(flash, config, Cache::new_uncached()),
            buf: [0; BUF_LEN],
        })
    }

    /// Give the flash back.
    pub fn into_flash(self) -> F {
        self.map.destroy().0
    }

    /// Read the settings (see [`LoadStatus`]); never fails.
    pub async fn load(&mut self) -> Loaded {
        let status = match self
            .map
            .fetch_item::<&[u8]>(&mut self.buf, &SETTINGS_KEY)
            .await
        {
            Ok(None) => LoadStatus::Absent,
            Ok(Some(bytes)) => match record::decode(bytes) {
                Ok((settings, version)) => {
                    let status = if version == SCHEMA_VERSION {
                        LoadStatus::Read
                    } else {
                        LoadStatus::Migrated { from: version }
                    };
                    return Loaded { settings, status };
                }
                Err(RecordError::UnknownVersion(v)) => LoadStatus::UnknownVersion(v),
                Err(_) => LoadStatus::Corrupt,
            },
            Err(sequential_storage::Error::Storage { .. }) => LoadStatus::FlashError,
            Err(_) => LoadStatus::Corrupt,
        };
        Loaded {
            settings: Settings::default(),
            status,
        }
    }

    /// Write `settings` as the new record. Refused while `armed` (never call it from the tick:
    /// it erases flash pages, milliseconds each) or when a field is out of range.
    pub async fn save(&mut self, settings: &Settings, armed: bool) -> Result<(), SaveError> {
        if armed {
            return Err(SaveError::Armed);
        }
        settings.validate().map_err(SaveError::Invalid)?;
        let mut rec = [0u8; MAX_RECORD_LEN];
        let n = record::encode(settings, &mut rec).map_err(|_| SaveError::Storage)?;
        self.map
            .store_item::<&[u8]>(&mut self.buf, &SETTINGS_KEY, &&rec[..n])
            .await
            .map_err(|_| SaveError::Storage)
    }

    /// Write a record of any schema version (tests of migration and of unknown versions).
    #[doc(hidden)]
    pub async fn save_raw_record(&mut self, rec: &[u8]) -> Result<(), SaveError> {
        self.map
            .store_item::<&[u8]>(&mut self.buf, &SETTINGS_KEY, &rec)
            .await
            .map_err(|_| SaveError::Storage)
    }

    /// Erase the whole region (a factory reset of the store: the next load is [`LoadStatus::Absent`]).
    pub async fn erase(&mut self, armed: bool) -> Result<(), SaveError> {
        if armed {
            return Err(SaveError::Armed);
        }
        self.map.erase_all().await.map_err(|_| SaveError::Storage)
    }
}

/// Blocking wrappers for hosts and start-up code without an executor (the flash futures complete
/// without waiting).
impl<F: NorFlash> Store<F> {
    /// [`Self::load`], blocking.
    pub fn load_blocking(&mut self) -> Loaded {
        embassy_futures::block_on(self.load())
    }
    /// [`Self::save`], blocking.
    pub fn save_blocking(&mut self, settings: &Settings, armed: bool) -> Result<(), SaveError> {
        embassy_futures::block_on(self.save(settings, armed))
    }
    /// [`Self::erase`], blocking.
    pub fn erase_blocking(&mut self, armed: bool) -> Result<(), SaveError> {
        embassy_futures::block_on(self.erase(armed))
    }
}
