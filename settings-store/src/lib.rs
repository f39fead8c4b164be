//! # softfinger-store
//!
//! The settings a softfinger device keeps across power-off (identity, calibration, contact
//! presets, stream and watchdog defaults), on NOR flash, power-fail safe. `#![no_std]`, no
//! allocation, no panic on any flash contents: the same code runs in the firmware (over the G474's
//! flash, in a region the application never executes from) and in `host-sim serve --flash FILE`
//! (over [`flash_model::G474Flash`] backed by a file).
//!
//! - [`schema`]: the settings and their ranges; [`schema_v1`]: the previous schema and its migration.
//! - [`record`]: one record = version, postcard, CRC-32C.
//! - [`store`]: load (never fails: defaults and a flag) and save (refused while armed) on a
//!   `sequential-storage` map.
//! - [`boot`]: the firmware's boot-time load: settings or defaults, device-info flags, the arm gate.
//! - [`flash_model`] (feature `std`): the G474 flash with power cuts, RAM- or file-backed.
#![no_std]
#![deny(missing_docs)]

pub mod boot;
#[cfg(feature = "std")]
pub mod flash_model;
pub mod record;
pub mod schema;
pub mod schema_v1;
pub mod store;

pub use boot::{load_at_boot, load_at_boot_blocking, BootLoad};
pub use schema::{
    Calibration, ContactPreset, FieldError, Identity, MotorConstants, Settings, StreamDefaults,
    WatchdogDefaults, SCHEMA_VERSION,
};
pub use store::{LoadStatus, Loaded, SaveError, Store};
