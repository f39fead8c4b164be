//! The messages: host → device ([`HostMsg`]) and device → host ([`DeviceMsg`]).

use crate::frame::FrameErrorKind;
use crate::info::{DeviceInfo, LinkCounters};
use crate::model::{ContactParamsWire, HandTarget, LocalModel};
use crate::state::StateSample;
use crate::status::{DeviceStatus, FieldRange};
use crate::PROTOCOL_VERSION;
use serde::{Deserialize, Serialize};

/// A message from the host (application) to the device.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum HostMsg {
    /// Version negotiation: the host speaks every version in `min_version..=max_version`. The
    /// device answers [`DeviceMsg::HelloReply`].
    Hello {
        /// Oldest version the host speaks.
        min_version: u8,
        /// Newest version the host speaks.
        max_version: u8,
    },
    /// A request; answered by exactly one reply carrying `seq`.
    Request {
        /// Chosen by the host, echoed in the reply.
        seq: u16,
        /// What to do.
        req: Request,
    },
}

/// What the host asks for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Request {
    /// Answered by [`DeviceMsg::Info`].
    GetInfo,
    /// Answered by [`DeviceMsg::Counters`].
    GetCounters,
    /// Answered by [`DeviceMsg::ContactParams`].
    GetContactParams,
    /// Does nothing but answer [`AckResult::Ok`] (round-trip measurements, keep-alive).
    Ping,
    /// Find the encoders' reference; afterwards the device is disarmed.
    Home,
    /// Start rendering force (ramped in). Needs homing; also re-arms the watchdog.
    Arm,
    /// Stop rendering force.
    Disarm,
    /// Clear latched faults (the device is then disarmed, never armed).
    ClearFaults,
    /// Replace the contact parameters.
    SetContactParams(ContactParamsWire),
    /// Replace the local model (blended in at a tick boundary).
    SetLocalModel(LocalModel),
    /// Stream one [`StateSample`] every `divisor` control ticks on this connection; 0 stops it.
    SetStream {
        /// Control ticks per sample (at least [`DeviceInfo::min_stream_divisor`]), or 0.
        divisor: u16,
    },
    /// Communication watchdog: no message for `timeout_ms` fades the force to zero and latches
    /// `COMM_TIMEOUT` until re-armed. 0 turns it off.
    SetWatchdog {
        /// Timeout, ms (0: off).
        timeout_ms: u16,
    },
    /// Virtual device: the simulated hand holds this target instead of following its script.
    DriveHand(HandTarget),
    /// Virtual device: the simulated hand follows the scene's script again.
    ReleaseHand,
    /// Answered by [`DeviceMsg::Status`] (appended, see [`crate::PROTOCOL_VERSION`]).
    GetStatus,
    // Appended (compatible within version 1): persistent settings and updates.
    /// Read a settings section: [`DeviceMsg::Config`].
    ConfigGet(crate::config::ConfigSection),
    /// Change a section of the settings in force (not saved): [`AckResult::Ok`] or
    /// [`DeviceMsg::ConfigRefused`].
    ConfigSet(crate::config::ConfigValue),
    /// Write the settings in force to flash (disarmed only): Ok or [`DeviceMsg::ConfigRefused`].
    ConfigSave,
    /// Erase the store and put the defaults in force (disarmed only).
    ConfigReset,
    /// Begin or resume an update: [`DeviceMsg::Update`] (its phase tells the offset to send from)
    /// or [`DeviceMsg::UpdateRefused`].
    UpdateBegin {
        /// The image's length, bytes.
        len: u32,
        /// Its ed25519 signature (64 bytes).
        signature: heapless::Vec<u8, 64>,
    },
    /// A chunk of the image: [`DeviceMsg::Update`] or [`DeviceMsg::UpdateRefused`].
    UpdateChunk(crate::update::UpdateChunk),
    /// Check the signature and mark the image: [`DeviceMsg::Update`] or [`DeviceMsg::UpdateRefused`].
    UpdateFinish,
    /// [`DeviceMsg::Update`].
    UpdateStatus,
    /// Reset the device (disarmed only): an image marked by `UpdateFinish` is swapped in.
    /// Acknowledged before the reset.
    Reboot,
}

/// Why a request was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ErrorCode {
    /// This device does not implement the request.
    Unsupported,
    /// Not allowed in the current mode (e.g. arming before homing, or while faulted).
    WrongMode,
    /// A latched fault forbids it; clear faults first.
    Faulted,
    /// A value is non-finite, out of range or inconsistent; nothing changed.
    InvalidValue,
    /// The surface kind is not one the device renders.
    UnsupportedSurface,
    /// A local model whose sequence number is not newer than the one in force.
    StaleSequence,
    /// The stream divisor is below the device's minimum.
    StreamTooFast,
    /// The device could not queue the request; try again.
    Busy,
}

/// The answer to a command.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum AckResult {
    /// Done (or, for a local model, accepted and applied from the next tick boundary).
    Ok,
    /// Refused, nothing changed.
    Err(ErrorCode),
}

/// A message from the device to the host.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DeviceMsg {
    /// Answer to [`HostMsg::Hello`]: the version both speak, or `None` (the device's own
    /// version is then in `device_version`).
    HelloReply {
        /// The agreed version, if any.
        version: Option<u8>,
        /// The device's version.
        device_version: u8,
    },
    /// Answer to a command.
    Ack {
        /// The request's sequence number.
        seq: u16,
        /// What happened.
        result: AckResult,
    },
    /// Answer to [`Request::GetInfo`].
    Info {
        /// The request's sequence number.
        seq: u16,
        /// The description.
        info: DeviceInfo,
    },
    /// Answer to [`Request::GetCounters`].
    Counters {
        /// The request's sequence number.
        seq: u16,
        /// Counters over all connections.
        counters: LinkCounters,
    },
    /// Answer to [`Request::GetContactParams`].
    ContactParams {
        /// The request's sequence number.
        seq: u16,
        /// The parameters in force.
        params: ContactParamsWire,
    },
    /// A state sample of the stream.
    State(StateSample),
    /// A received frame was rejected (it has no sequence number to answer): what was wrong, and
    /// the device's version (useful after [`FrameErrorKind::Version`]).
    FrameError {
        /// Why.
        kind: FrameErrorKind,
        /// The device's protocol version.
        device_version: u8,
    },
    /// Answer to [`Request::GetStatus`] (appended).
    Status {
        /// The request's sequence number.
        seq: u16,
        /// Mode, flags and the model in force.
        status: DeviceStatus,
    },
    /// Answer to a command refused for one value: the [`Ack`](DeviceMsg::Ack) error `code`
    /// (usually [`ErrorCode::InvalidValue`]) with the field and the range it accepts. Nothing
    /// changed (appended).
    Rejected {
        /// The request's sequence number.
        seq: u16,
        /// Why.
        code: ErrorCode,
        /// Which value, and what it may be.
        field: FieldRange,
    },
    // Appended (compatible within version 1): persistent settings and updates.
    /// Answer to [`Request::ConfigGet`].
    Config {
        /// The request's sequence number.
        seq: u16,
        /// The section.
        value: crate::config::ConfigValue,
    },
    /// A configuration request refused, naming the key and the reason.
    ConfigRefused {
        /// The request's sequence number.
        seq: u16,
        /// What and why.
        refusal: crate::config::ConfigRefusal,
    },
    /// Answer to the update requests.
    Update {
        /// The request's sequence number.
        seq: u16,
        /// Where it stands.
        status: crate::update::UpdateStatus,
    },
    /// An update request refused.
    UpdateRefused {
        /// The request's sequence number.
        seq: u16,
        /// Why.
        refusal: crate::update::UpdateRefusal,
    },
}

impl DeviceMsg {
    /// The device's answer to a [`HostMsg::Hello`] offering `min_version ..= max_version`: the
    /// agreed version is [`PROTOCOL_VERSION`] if the range holds it, none otherwise; either way
    /// the device says which version it speaks.
    pub const fn hello_reply(min_version: u8, max_version: u8) -> DeviceMsg {
        let ok = min_version <= PROTOCOL_VERSION && PROTOCOL_VERSION <= max_version;
        DeviceMsg::HelloReply {
            version: if ok { Some(PROTOCOL_VERSION) } else { None },
            device_version: PROTOCOL_VERSION,
        }
    }
}
