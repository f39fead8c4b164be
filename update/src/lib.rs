//! # softfinger-update
//!
//! Firmware updates of a softfinger device over its host link, on embassy-boot's partitions
//! (an *active* slot the application runs from, a *DFU* slot one page larger that receives the new
//! image, a *state* slot recording the bootloader's progress). `#![no_std]`, no allocation: the
//! firmware and the virtual device (`host-sim serve --flash FILE`) run the same code.
//!
//! - [`package`]: the signed update file (`.sfu`) and the version trailer inside an image.
//! - [`session`]: the device's side: begin / chunk (CRC each, resumable) / finish (ed25519 over
//!   the image's SHA-512, then marked for swap); refused while armed.
//! - [`boot`]: after a reset, the bootloader's swap (the same `embassy-boot` code the bootloader
//!   crate runs) and the new image's trial boot: confirmed only after its self-test, else the next
//!   reset rolls back.
//! - [`layout`]: where the slots are on the STM32G474.
//! - [`keys`]: the development public key.
#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]

pub mod boot;
pub mod keys;
pub mod layout;
pub mod package;
pub mod session;

pub use boot::{BootState, SelfTest};
pub use layout::Layout;
pub use package::{ImageTrailer, Package, PackageError};
pub use session::{Slots, Status, UpdateError, UpdateSession, CHUNK_LEN};
