//! What can go wrong talking to a device.

use softfinger_protocol::{ErrorCode, FieldRange, FrameErrorKind};
use std::fmt;

/// A failed exchange with the device.
#[derive(Debug)]
pub enum LinkError {
    /// The connection could not be opened, or broke.
    Io(std::io::Error),
    /// The target string is not understood.
    BadTarget(String),
    /// No USB device found.
    NoDevice,
    /// No answer within the timeout.
    Timeout,
    /// The connection closed.
    Disconnected,
    /// The device refused the request.
    Refused(ErrorCode),
    /// The device refused the request for one value: which field, and the range it accepts.
    Rejected {
        /// The error code.
        code: ErrorCode,
        /// The field and its range.
        field: FieldRange,
    },
    /// The device rejected our frame.
    Frame(FrameErrorKind),
    /// The device speaks another protocol version.
    Version {
        /// The device's version.
        device: u8,
    },
    /// The device answered something unexpected.
    Protocol(String),
    /// An error with what was being done.
    Context(String),
    /// Homing ended in a fault (see [`crate::Device::home_and_wait`]).
    HomingFailed,
}

impl fmt::Display for LinkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LinkError::Io(e) => write!(f, "connection: {e}"),
            LinkError::BadTarget(t) => write!(
                f,
                "cannot understand '{t}' (use tcp:HOST:PORT, usb, or usb:/dev/ttyACM0)"
            ),
            LinkError::NoDevice => write!(f, "no softfinger USB device found"),
            LinkError::Timeout => write!(f, "no answer from the device"),
            LinkError::Disconnected => write!(f, "the device closed the connection"),
            LinkError::Refused(c) => write!(f, "the device refused: {c:?}"),
            LinkError::Rejected { code, field } => write!(
                f,
                "the device refused ({code:?}): {} must be within {}",
                field.field,
                range_text(field)
            ),
            LinkError::Frame(k) => write!(f, "the device rejected our frame: {k:?}"),
            LinkError::Version { device } => write!(
                f,
                "the device speaks protocol version {device}, this tool {}",
                softfinger_protocol::PROTOCOL_VERSION
            ),
            LinkError::Protocol(m) => write!(f, "unexpected answer: {m}"),
            LinkError::Context(m) => write!(f, "{m}"),
            LinkError::HomingFailed => write!(f, "homing failed: the device faulted"),
        }
    }
}

impl std::error::Error for LinkError {}

/// `[min, max]`, or `(min, max]` when `min` itself is refused.
pub fn range_text(r: &FieldRange) -> String {
    format!(
        "{}{}, {}]",
        if r.min_exclusive { "(" } else { "[" },
        r.min,
        r.max
    )
}

impl From<std::io::Error> for LinkError {
    fn from(e: std::io::Error) -> Self {
        LinkError::Io(e)
    }
}
