//! The device's side of an update: receive an image into the DFU slot in chunks, check it, mark
//! it for the bootloader's swap.
//!
//! ```text
//! Idle --begin(len, signature)--> Receiving{received} --chunk(offset, data, crc)*--> Receiving{len}
//!      --finish()--> Verified (the next reset swaps; see crate::boot)
//! ```
//!
//! - Every call is refused while the device is armed ([`UpdateError::Armed`]).
//! - A chunk's CRC-32C is checked before it is written; a chunk at another offset than the next
//!   expected is refused naming that offset, a chunk already written is acknowledged again (its
//!   acknowledgement was lost). `begin` with the length and signature of the image being received
//!   resumes at the bytes already received (after a disconnect), anything else starts over.
//! - `finish` refuses an image not fully received, then checks the ed25519 signature over the
//!   SHA-512 of the DFU slot's first `len` bytes (embassy-boot's `verify_and_mark_updated`):
//!   only a good one is marked for swap. The active slot is never written here.

use core::cell::RefCell;

use crc::{Crc, CRC_32_ISCSI};
use embassy_boot::{
    AlignedBuffer, BlockingFirmwareUpdater, FirmwareUpdaterConfig, FirmwareUpdaterError,
};
use embassy_embedded_hal::flash::partition::BlockingPartition;
use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embedded_storage::nor_flash::{NorFlash, ReadNorFlash};

use crate::layout::{Layout, PAGE};

/// The longest chunk, bytes (a multiple of the G474's 8-byte write; fits the link's 256-byte frame).
pub const CHUNK_LEN: usize = 128;

const CRC32C: Crc<u32> = Crc::<u32>::new(&CRC_32_ISCSI);

/// CRC-32C of a chunk, as [`UpdateSession::chunk`] expects it.
pub fn chunk_crc(data: &[u8]) -> u32 {
    CRC32C.checksum(data)
}

/// The flash and where the slots are in it.
pub struct Slots<'a, F: NorFlash> {
    flash: &'a Mutex<NoopRawMutex, RefCell<F>>,
    layout: Layout,
}

impl<F: NorFlash> core::fmt::Debug for Slots<'_, F> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Slots")
            .field("layout", &self.layout)
            .finish_non_exhaustive()
    }
}

fn part<'a, F: NorFlash>(
    flash: &'a Mutex<NoopRawMutex, RefCell<F>>,
    r: &core::ops::Range<u32>,
) -> BlockingPartition<'a, NoopRawMutex, F> {
    BlockingPartition::new(flash, r.start, r.end - r.start)
}

impl<'a, F: NorFlash> Slots<'a, F> {
    /// The slots of `layout` in `flash` (offsets from the flash's start).
    pub fn new(flash: &'a Mutex<NoopRawMutex, RefCell<F>>, layout: Layout) -> Self {
        Self { flash, layout }
    }
    /// The layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }
    /// The active slot.
    pub fn active(&self) -> BlockingPartition<'a, NoopRawMutex, F> {
        part(self.flash, &self.layout.active)
    }
    /// The DFU slot.
    pub fn dfu(&self) -> BlockingPartition<'a, NoopRawMutex, F> {
        part(self.flash, &self.layout.dfu)
    }
    /// The state slot.
    pub fn state(&self) -> BlockingPartition<'a, NoopRawMutex, F> {
        part(self.flash, &self.layout.state)
    }
    /// The largest image, bytes: the active slot.
    pub fn max_image_len(&self) -> u32 {
        self.layout.active.end - self.layout.active.start
    }
    /// Read `out.len()` bytes of the active slot from `offset`.
    pub fn read_active(&self, offset: u32, out: &mut [u8]) -> Result<(), UpdateError> {
        self.active()
            .read(offset, out)
            .map_err(|_| UpdateError::Flash)
    }
    pub(crate) fn updater<'b>(
        &self,
        aligned: &'b mut [u8],
    ) -> BlockingFirmwareUpdater<
        'b,
        BlockingPartition<'a, NoopRawMutex, F>,
        BlockingPartition<'a, NoopRawMutex, F>,
    > {
        BlockingFirmwareUpdater::new(
            FirmwareUpdaterConfig {
                dfu: self.dfu(),
                state: self.state(),
            },
            aligned,
        )
    }
}

/// Why an update step was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum UpdateError {
    /// The device is armed: disarm first.
    Armed,
    /// No update begun (or it was abandoned after an error): begin again.
    NotReceiving,
    /// An empty image.
    Empty,
    /// The image is larger than the active slot.
    TooLarge {
        /// Bytes offered.
        len: u32,
        /// The slot, bytes.
        max: u32,
    },
    /// A chunk at another offset than the next expected one.
    OutOfOrder {
        /// The next offset expected.
        expected: u32,
    },
    /// A chunk whose CRC does not match its data (not written).
    ChunkCrc {
        /// The chunk's offset.
        offset: u32,
    },
    /// A chunk empty, longer than [`CHUNK_LEN`], past the image's end, or not a multiple of 8
    /// bytes without being the last.
    ChunkLen {
        /// The chunk's offset.
        offset: u32,
    },
    /// `finish` before every byte arrived.
    Truncated {
        /// Bytes received.
        received: u32,
        /// The image's length.
        len: u32,
    },
    /// The signature does not verify against the device's public key: the image is not marked.
    BadSignature,
    /// The running image is on trial (just swapped in, not yet confirmed by its self-test).
    TrialNotConfirmed,
    /// The flash failed; the update is abandoned.
    Flash,
}

impl core::fmt::Display for UpdateError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            UpdateError::Armed => write!(f, "refused while armed: disarm first"),
            UpdateError::NotReceiving => write!(f, "no update in progress: begin first"),
            UpdateError::Empty => write!(f, "the image is empty"),
            UpdateError::TooLarge { len, max } => {
                write!(f, "the image is {len} bytes, the slot {max}")
            }
            UpdateError::OutOfOrder { expected } => {
                write!(f, "chunk out of order: expected offset {expected}")
            }
            UpdateError::ChunkCrc { offset } => {
                write!(f, "chunk at {offset}: CRC mismatch, not written")
            }
            UpdateError::ChunkLen { offset } => write!(f, "chunk at {offset}: bad length"),
            UpdateError::Truncated { received, len } => {
                write!(f, "image truncated: {received} of {len} bytes received")
            }
            UpdateError::BadSignature => {
                write!(f, "signature does not verify against the device's key")
            }
            UpdateError::TrialNotConfirmed => {
                write!(
                    f,
                    "the running image has not passed its self-test yet (trial boot)"
                )
            }
            UpdateError::Flash => write!(f, "flash error; update abandoned"),
        }
    }
}

/// Where an update stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Status {
    /// Nothing in progress.
    Idle,
    /// Receiving.
    Receiving {
        /// The image's length, bytes.
        len: u32,
        /// Bytes received and written.
        received: u32,
    },
    /// Received, signature good, marked: the next reset swaps it in.
    Verified,
}

/// The update state machine (RAM only: a reset abandons a transfer, never the running image).
#[derive(Debug)]
pub struct UpdateSession {
    status: Status,
    signature: [u8; 64],
}

impl Default for UpdateSession {
    fn default() -> Self {
        Self::new()
    }
}

fn map_err(e: FirmwareUpdaterError) -> UpdateError {
    match e {
        FirmwareUpdaterError::BadState => UpdateError::TrialNotConfirmed,
        FirmwareUpdaterError::Signature(_) => UpdateError::BadSignature,
        FirmwareUpdaterError::Flash(_) => UpdateError::Flash,
    }
}

impl UpdateSession {
    /// Idle.
    pub const fn new() -> Self {
        Self {
            status: Status::Idle,
            signature: [0; 64],
        }
    }

    /// Where it stands.
    pub fn status(&self) -> Status {
        self.status
    }

    /// Begin (or resume) receiving an image of `len` bytes signed `signature`; returns the offset
    /// to send from (0, or the bytes already received when resuming). Erases the DFU slot on a
    /// new image.
    pub fn begin<F: NorFlash>(
        &mut self,
        slots: &Slots<'_, F>,
        len: u32,
        signature: &[u8; 64],
        armed: bool,
    ) -> Result<u32, UpdateError> {
        if armed {
            return Err(UpdateError::Armed);
        }
        if len == 0 {
            return Err(UpdateError::Empty);
        }
        let max = slots.max_image_len();
        if len > max {
            return Err(UpdateError::TooLarge { len, max });
        }
        if let Status::Receiving { len: l, received } = self.status {
            if l == len && self.signature == *signature {
                return Ok(received);
            }
        }
        self.status = Status::Idle;
        let mut aligned = AlignedBuffer([0u8; 8]);
        slots
            .updater(&mut aligned.0)
            .prepare_update()
            .map_err(map_err)?;
        self.signature = *signature;
        self.status = Status::Receiving { len, received: 0 };
        Ok(0)
    }

    /// Write the chunk `data` at `offset` after checking `crc` (CRC-32C of `data`); returns the
    /// bytes received so far.
    pub fn chunk<F: NorFlash>(
        &mut self,
        slots: &Slots<'_, F>,
        offset: u32,
        data: &[u8],
        crc: u32,
        armed: bool,
    ) -> Result<u32, UpdateError> {
        if armed {
            return Err(UpdateError::Armed);
        }
        let Status::Receiving { len, received } = self.status else {
            return Err(UpdateError::NotReceiving);
        };
        if chunk_crc(data) != crc {
            return Err(UpdateError::ChunkCrc { offset });
        }
        let n = data.len() as u32;
        if data.is_empty() || data.len() > CHUNK_LEN || offset.saturating_add(n) > len {
            return Err(UpdateError::ChunkLen { offset });
        }
        if offset + n <= received {
            return Ok(received); // a resend of a chunk already written
        }
        if offset != received {
            return Err(UpdateError::OutOfOrder { expected: received });
        }
        let last = offset + n == len;
        if !last && !n.is_multiple_of(8) {
            return Err(UpdateError::ChunkLen { offset });
        }
        let mut buf = [0xFFu8; CHUNK_LEN];
        buf[..data.len()].copy_from_slice(data);
        let padded = data.len().div_ceil(8) * 8;
        if slots.dfu().write(offset, &buf[..padded]).is_err() {
            self.status = Status::Idle;
            return Err(UpdateError::Flash);
        }
        self.status = Status::Receiving {
            len,
            received: received + n,
        };
        Ok(received + n)
    }

    /// Check the received image's signature against `public_key` and mark it for swap.
    pub fn finish<F: NorFlash>(
        &mut self,
        slots: &Slots<'_, F>,
        public_key: &[u8; 32],
        armed: bool,
    ) -> Result<(), UpdateError> {
        if armed {
            return Err(UpdateError::Armed);
        }
        let Status::Receiving { len, received } = self.status else {
            return Err(UpdateError::NotReceiving);
        };
        if received != len {
            return Err(UpdateError::Truncated { received, len });
        }
        let mut aligned = AlignedBuffer([0u8; 8]);
        let r =
            slots
                .updater(&mut aligned.0)
                .verify_and_mark_updated(public_key, &self.signature, len);
        match r {
            Ok(()) => {
                self.status = Status::Verified;
                Ok(())
            }
            Err(e) => {
                self.status = Status::Idle;
                Err(map_err(e))
            }
        }
    }
}

/// One page, for callers sizing buffers.
pub const PAGE_LEN: usize = PAGE as usize;
