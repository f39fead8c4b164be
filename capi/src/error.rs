//! The C API's error codes: negative, one per [`LinkError`] kind and one per device refusal
//! ([`ErrorCode`], carried as `SF_ERR_REFUSED_BASE - code`), with their text for `sf_strerror`.

use softfinger_host::protocol::ErrorCode;
use softfinger_host::LinkError;
use std::ffi::{c_char, CStr};

/// Success.
pub const SF_OK: i32 = 0;
/// A required pointer argument was null.
pub const SF_ERR_NULL: i32 = -1;
/// The target string is not `tcp:HOST:PORT`, `usb` or `usb:PATH` (or not UTF-8).
pub const SF_ERR_BAD_TARGET: i32 = -2;
/// An argument is out of range or not finite; nothing was sent.
pub const SF_ERR_BAD_VALUE: i32 = -3;
/// The connection could not be opened, or broke.
pub const SF_ERR_IO: i32 = -4;
/// No softfinger USB device found.
pub const SF_ERR_NO_DEVICE: i32 = -5;
/// No answer from the device within the timeout (or homing did not finish in time).
pub const SF_ERR_TIMEOUT: i32 = -6;
/// The device closed the connection.
pub const SF_ERR_DISCONNECTED: i32 = -7;
/// The device answered something unexpected.
pub const SF_ERR_PROTOCOL: i32 = -8;
/// The device speaks another protocol version.
pub const SF_ERR_VERSION: i32 = -9;
/// The device rejected a frame of ours.
pub const SF_ERR_FRAME: i32 = -10;
/// Homing ended in a fault.
pub const SF_ERR_HOMING_FAILED: i32 = -11;
/// A bug in the library (it was caught; the handle may be unusable).
pub const SF_ERR_INTERNAL: i32 = -12;

/// Refusals: `SF_ERR_REFUSED_BASE - code`, the device's error code in wire order.
pub const SF_ERR_REFUSED_BASE: i32 = -100;
/// Refused: the device does not implement the request.
pub const SF_ERR_REFUSED_UNSUPPORTED: i32 = -100;
/// Refused: not allowed in the current mode (e.g. arming before homing).
pub const SF_ERR_REFUSED_WRONG_MODE: i32 = -101;
/// Refused: a latched fault forbids it; `sf_clear` first.
pub const SF_ERR_REFUSED_FAULTED: i32 = -102;
/// Refused: a value is non-finite, out of range or inconsistent; nothing changed.
pub const SF_ERR_REFUSED_INVALID_VALUE: i32 = -103;
/// Refused: the device does not render this surface.
pub const SF_ERR_REFUSED_UNSUPPORTED_SURFACE: i32 = -104;
/// Refused: a local model whose `seq` is not newer than the one in force.
pub const SF_ERR_REFUSED_STALE_SEQUENCE: i32 = -105;
/// Refused: the stream rate is above the device's fastest.
pub const SF_ERR_REFUSED_STREAM_TOO_FAST: i32 = -106;
/// Refused: the device could not queue the request; try again.
pub const SF_ERR_REFUSED_BUSY: i32 = -107;

/// The code of a device refusal.
pub(crate) fn refused(code: ErrorCode) -> i32 {
    SF_ERR_REFUSED_BASE
        - match code {
            ErrorCode::Unsupported => 0,
            ErrorCode::WrongMode => 1,
            ErrorCode::Faulted => 2,
            ErrorCode::InvalidValue => 3,
            ErrorCode::UnsupportedSurface => 4,
            ErrorCode::StaleSequence => 5,
            ErrorCode::StreamTooFast => 6,
            ErrorCode::Busy => 7,
        }
}

/// The code of a failed exchange.
pub(crate) fn code_of(e: &LinkError) -> i32 {
    match e {
        LinkError::Io(_) => SF_ERR_IO,
        LinkError::BadTarget(_) => SF_ERR_BAD_TARGET,
        LinkError::NoDevice => SF_ERR_NO_DEVICE,
        LinkError::Timeout => SF_ERR_TIMEOUT,
        LinkError::Disconnected => SF_ERR_DISCONNECTED,
        LinkError::Refused(c) | LinkError::Rejected { code: c, .. } => refused(*c),
        LinkError::Frame(_) => SF_ERR_FRAME,
        LinkError::Version { .. } => SF_ERR_VERSION,
        LinkError::Protocol(_) | LinkError::Context(_) => SF_ERR_PROTOCOL,
        LinkError::HomingFailed => SF_ERR_HOMING_FAILED,
    }
}

/// The text of `code`.
pub(crate) fn text(code: i32) -> &'static CStr {
    match code {
        SF_OK => c"ok",
        SF_ERR_NULL => c"a required pointer argument is null",
        SF_ERR_BAD_TARGET => c"bad target (use tcp:HOST:PORT, usb, or usb:/dev/ttyACM0)",
        SF_ERR_BAD_VALUE => c"an argument is out of range or not finite",
        SF_ERR_IO => c"the connection could not be opened, or broke",
        SF_ERR_NO_DEVICE => c"no softfinger USB device found",
        SF_ERR_TIMEOUT => c"no answer from the device in time",
        SF_ERR_DISCONNECTED => c"the device closed the connection",
        SF_ERR_PROTOCOL => c"the device answered something unexpected",
        SF_ERR_VERSION => c"the device speaks another protocol version",
        SF_ERR_FRAME => c"the device rejected our frame",
        SF_ERR_HOMING_FAILED => c"homing failed: the device faulted",
        SF_ERR_INTERNAL => c"internal error in the softfinger library",
        SF_ERR_REFUSED_UNSUPPORTED => c"the device refused: Unsupported (not implemented)",
        SF_ERR_REFUSED_WRONG_MODE => {
            c"the device refused: WrongMode (not in this mode; home first?)"
        }
        SF_ERR_REFUSED_FAULTED => c"the device refused: Faulted (clear faults first)",
        SF_ERR_REFUSED_INVALID_VALUE => {
            c"the device refused: InvalidValue (out of range or inconsistent)"
        }
        SF_ERR_REFUSED_UNSUPPORTED_SURFACE => c"the device refused: UnsupportedSurface",
        SF_ERR_REFUSED_STALE_SEQUENCE => {
            c"the device refused: StaleSequence (seq not newer than the model in force)"
        }
        SF_ERR_REFUSED_STREAM_TOO_FAST => {
            c"the device refused: StreamTooFast (rate above the device's fastest)"
        }
        SF_ERR_REFUSED_BUSY => c"the device refused: Busy (try again)",
        _ => c"unknown softfinger error code",
    }
}

/// `text` as a C pointer (static, never freed).
pub(crate) fn text_ptr(code: i32) -> *const c_char {
    text(code).as_ptr()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every refusal has its own code and text; codes outside the table say so.
    #[test]
    fn every_code_has_its_own_text() {
        let all = [
            ErrorCode::Unsupported,
            ErrorCode::WrongMode,
            ErrorCode::Faulted,
            ErrorCode::InvalidValue,
            ErrorCode::UnsupportedSurface,
            ErrorCode::StaleSequence,
            ErrorCode::StreamTooFast,
            ErrorCode::Busy,
        ];
        let mut seen = std::collections::HashSet::new();
        for (i, c) in all.iter().enumerate() {
            let code = refused(*c);
            assert_eq!(code, SF_ERR_REFUSED_BASE - i as i32);
            let t = text(code).to_str().unwrap();
            assert!(t.contains(&format!("{c:?}")), "{code}: {t}");
            assert!(seen.insert(t));
        }
        for code in SF_ERR_INTERNAL..=SF_OK {
            assert!(seen.insert(text(code).to_str().unwrap()), "{code}");
        }
        let unknown = text(-99).to_str().unwrap();
        assert!(unknown.contains("unknown"));
        assert_eq!(text(SF_ERR_REFUSED_BASE - 8).to_str().unwrap(), unknown);
        assert_eq!(text(1).to_str().unwrap(), unknown);
    }
}
