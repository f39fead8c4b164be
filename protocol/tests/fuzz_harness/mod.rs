//! The fuzz harness of the protocol decoder, shared by the `protocol_decode` cargo-fuzz target
//! (`fuzz/fuzz_targets/protocol_decode.rs`) and `tests/fuzz_regression.rs`.
//!
//! Input: any bytes, fed one at a time to a [`FrameDecoder`] for each direction (host → device and
//! device → host). Invariants:
//! - no panic;
//! - every non-empty zero-delimited segment gives exactly one result, and the decoder's counters
//!   add up: decoded frames + rejected frames (all kinds) = non-empty segments;
//! - every decoded message re-encodes to a frame that decodes to a message with the same postcard
//!   bytes (NaN-safe equality), within the frame-size limit.

use serde::de::DeserializeOwned;
use serde::Serialize;
use softfinger_protocol::{encode_frame, DeviceMsg, FrameDecoder, HostMsg, MAX_FRAME_LEN};

/// What one input exercised.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Summary {
    /// Messages decoded (both directions).
    pub decoded: u32,
    /// Frames rejected (both directions).
    pub rejected: u32,
}

fn check_direction<T: DeserializeOwned + Serialize>(data: &[u8]) -> Result<Summary, String> {
    let mut dec = FrameDecoder::new();
    let mut results = 0u32;
    for &b in data {
        if let Some(r) = dec.push::<T>(b) {
            results += 1;
            if let Ok(msg) = r {
                round_trip(&msg)?;
            }
        }
    }
    let segments = data.split(|b| *b == 0).count() - 1;
    let nonempty = data
        .split(|b| *b == 0)
        .take(segments)
        .filter(|s| !s.is_empty())
        .count() as u32;
    if results != nonempty {
        return Err(format!("{results} results for {nonempty} frames"));
    }
    let counted = dec.frames() + dec.errors().total();
    if counted != nonempty {
        return Err(format!("counters say {counted} frames, {nonempty} seen"));
    }
    Ok(Summary {
        decoded: dec.frames(),
        rejected: dec.errors().total(),
    })
}

fn round_trip<T: DeserializeOwned + Serialize>(msg: &T) -> Result<(), String> {
    let mut out = [0u8; MAX_FRAME_LEN];
    let n = encode_frame(msg, &mut out).map_err(|e| format!("re-encode: {e:?}"))?;
    let mut dec = FrameDecoder::new();
    let mut again = None;
    for &b in &out[..n] {
        if let Some(r) = dec.push::<T>(b) {
            again = Some(r.map_err(|e| format!("re-decode: {e:?}"))?);
        }
    }
    let again = again.ok_or("re-encoded frame gave no message")?;
    let a = postcard_bytes(msg)?;
    let b = postcard_bytes(&again)?;
    if a != b {
        return Err("round trip changed the message".into());
    }
    Ok(())
}

fn postcard_bytes<T: Serialize>(msg: &T) -> Result<Vec<u8>, String> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    postcard::to_slice(msg, &mut buf)
        .map(|s| s.to_vec())
        .map_err(|e| format!("postcard: {e}"))
}

/// Run both directions over `data`.
pub fn protocol_decode(data: &[u8]) -> Result<Summary, String> {
    let h = check_direction::<HostMsg>(data)?;
    let d = check_direction::<DeviceMsg>(data)?;
    Ok(Summary {
        decoded: h.decoded + d.decoded,
        rejected: h.rejected + d.rejected,
    })
}
