//! Firmware updates over the link (`softfinger-update` on the device).
//!
//! The host sends [`crate::Request::UpdateBegin`] (image length and signature), then the image in
//! [`crate::Request::UpdateChunk`]s of at most [`UPDATE_CHUNK_LEN`] bytes from the offset the
//! device answered (0, or where an interrupted transfer stopped), then
//! [`crate::Request::UpdateFinish`] (the device checks the signature and marks the image), then
//! [`crate::Request::Reboot`]: the bootloader swaps the image in, the image's self-test confirms
//! it or the next reset rolls it back.

use heapless::Vec;
use serde::{Deserialize, Serialize};

/// The longest chunk, bytes (`softfinger_update::CHUNK_LEN`).
pub const UPDATE_CHUNK_LEN: usize = 128;

/// Where an update stands on the device.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum UpdatePhase {
    /// Nothing in progress.
    Idle,
    /// Receiving: `received` of `len` bytes written.
    Receiving {
        /// The image's length.
        len: u32,
        /// Bytes received.
        received: u32,
    },
    /// Signature good, marked: a reboot swaps it in.
    Verified,
}

/// The running image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BootStateWire {
    /// Confirmed.
    Normal,
    /// Swapped in, awaiting its self-test.
    Trial,
    /// The previous update failed its self-test and was swapped back.
    RolledBack,
}

/// Answer to the update requests.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct UpdateStatus {
    /// The transfer.
    pub phase: UpdatePhase,
    /// The running image's state.
    pub boot: BootStateWire,
    /// The running image's version (its trailer), empty if unknown.
    pub version: heapless::String<23>,
}

/// Why an update request was refused (`softfinger_update::UpdateError` on the wire).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum UpdateRefusal {
    /// Armed: disarm first.
    Armed,
    /// No update begun.
    NotReceiving,
    /// An empty image.
    Empty,
    /// Larger than the slot.
    TooLarge {
        /// Offered.
        len: u32,
        /// The slot.
        max: u32,
    },
    /// A chunk at the wrong offset.
    OutOfOrder {
        /// The next offset expected.
        expected: u32,
    },
    /// A chunk whose CRC did not match.
    ChunkCrc {
        /// Its offset.
        offset: u32,
    },
    /// A chunk of a bad length.
    ChunkLen {
        /// Its offset.
        offset: u32,
    },
    /// Finished before every byte arrived.
    Truncated {
        /// Received.
        received: u32,
        /// Expected.
        len: u32,
    },
    /// The signature does not verify against the device's key.
    BadSignature,
    /// The running image is on trial.
    TrialNotConfirmed,
    /// The flash failed.
    Flash,
    /// The signature field is not 64 bytes.
    BadSignatureLength,
}

/// A chunk of the image.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct UpdateChunk {
    /// Offset in the image, bytes.
    pub offset: u32,
    /// CRC-32C of `data`.
    pub crc: u32,
    /// The bytes.
    pub data: Vec<u8, UPDATE_CHUNK_LEN>,
}
