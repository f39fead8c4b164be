//! # softfinger-protocol
//!
//! The link between a softfinger device (or the virtual device of `host-sim serve`) and the
//! applications that use it. `#![no_std]`, no allocation, no panic on any input: the same code runs
//! in the firmware's low-priority link task, in host-sim and in the host library.
//!
//! ## Wire format
//!
//! Every message travels in one frame:
//!
//! ```text
//! COBS( version:u8 | postcard(message) | crc32c(version | postcard(message)):u32 LE ) | 0x00
//! ```
//!
//! - COBS removes every zero byte from the frame, so `0x00` marks its end and a receiver
//!   resynchronises at the next zero after any corruption.
//! - The version byte is [`PROTOCOL_VERSION`]; a frame of another version is counted and answered
//!   ([`DeviceMsg::FrameError`]) without decoding its body.
//! - The CRC is CRC-32C (Castagnoli) over the version byte and the postcard body.
//! - A frame is at most [`MAX_FRAME_LEN`] bytes on the wire, delimiter included, so the decoder's
//!   buffer is a fixed array (see [`frame::FrameDecoder`]).
//!
//! ## Conversation
//!
//! The host sends [`HostMsg`]s, the device answers with [`DeviceMsg`]s. Each [`HostMsg::Request`]
//! carries a sequence number echoed by exactly one reply (an [`DeviceMsg::Ack`], or the data asked
//! for). The state stream ([`DeviceMsg::State`]) flows without being asked once a divisor is set
//! ([`Request::SetStream`]). A host starts with [`HostMsg::Hello`] to agree on the version.
//!
//! Units are SI (m, s, N, N·m, rad) unless a name says otherwise; vectors are in the device base
//! frame (see `softfinger_core::device::delta`).
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_debug_implementations)]

#[cfg(test)]
extern crate std;

pub mod config;
pub mod convert;
pub mod endpoint;
pub mod flag_names;
pub mod frame;
pub mod info;
pub mod messages;
pub mod model;
pub mod rendered;
pub mod state;
pub mod status;
pub mod update;

pub use endpoint::DeviceEndpoint;
pub use frame::{encode_frame, FrameDecoder, FrameError, FrameErrorCounts, FrameErrorKind};
pub use info::{DeviceInfo, LinkCounters};
pub use messages::{AckResult, DeviceMsg, ErrorCode, HostMsg, Request};
pub use model::{ContactParamsWire, HandTarget, LocalModel, SurfaceKind, SurfaceShape};
pub use rendered::RenderedTick;
pub use state::{ContactState, Mode, StateSample, TickStatsWire};
pub use status::{DeviceStatus, FieldRange};

/// The protocol version this crate speaks. A change of any message layout increments it.
///
/// Extended compatibly within version 1: bowl and cylinder local models were appended to
/// [`SurfaceKind`] and [`SurfaceShape`] (postcard encodes the variant index, so every earlier
/// message encodes as before). A peer built before that decodes a message carrying a new kind
/// (a model, or a device info listing one) as a counted decode error, never as another kind.
/// Likewise appended: [`Request::GetStatus`] with its answer [`DeviceMsg::Status`], and
/// [`DeviceMsg::Rejected`] (a refusal naming the field and its range); a device built before them
/// answers `GetStatus` with a decode [`DeviceMsg::FrameError`], one built with them that does not
/// implement it with `Unsupported`.
pub const PROTOCOL_VERSION: u8 = 1;

/// Largest frame on the wire, delimiter included, bytes.
pub const MAX_FRAME_LEN: usize = 256;

/// Largest decoded frame body (version byte + postcard message + 4 CRC bytes), bytes. COBS adds at
/// most one byte per 254 plus one, and the delimiter one more, so a body of this size always fits
/// in [`MAX_FRAME_LEN`].
pub const MAX_BODY_LEN: usize = MAX_FRAME_LEN - 2 - MAX_FRAME_LEN.div_ceil(254);
