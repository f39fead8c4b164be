//! Framing: postcard body + version byte + CRC-32C, COBS-encoded, zero-delimited (see the crate
//! doc). [`encode_frame`] writes one frame; [`FrameDecoder`] takes bytes one at a time and yields
//! a message or a counted [`FrameError`] at each delimiter. Neither allocates nor panics.

use crate::{MAX_BODY_LEN, MAX_FRAME_LEN, PROTOCOL_VERSION};
use crc::{Crc, CRC_32_ISCSI};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// CRC-32C (Castagnoli): better than CRC-32/ISO-HDLC at detecting errors in short frames.
const CRC32C: Crc<u32> = Crc::<u32>::new(&CRC_32_ISCSI);

/// Bytes of CRC at the end of a frame body.
const CRC_LEN: usize = 4;

/// Why a frame could not be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EncodeError {
    /// The message does not fit in [`MAX_BODY_LEN`] (or postcard refused it).
    TooLarge,
}

/// Why a received frame was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FrameErrorKind {
    /// The bytes between two delimiters are not valid COBS.
    Cobs,
    /// The CRC does not match, or the body is too short to hold one (a truncated frame).
    Crc,
    /// The CRC matches but the version byte is not [`PROTOCOL_VERSION`].
    Version,
    /// The body is not a message of the expected type (unknown variant, short, trailing bytes).
    Decode,
    /// More than [`MAX_FRAME_LEN`] bytes before a delimiter; everything up to it was dropped.
    Oversized,
}

/// A rejected frame: the kind, and for [`FrameErrorKind::Version`] the version it carried.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FrameError {
    /// Why.
    pub kind: FrameErrorKind,
    /// The version byte found (0 when the frame never got that far).
    pub version: u8,
}

/// Rejected frames by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FrameErrorCounts {
    /// Invalid COBS.
    pub cobs: u32,
    /// CRC mismatch or too short.
    pub crc: u32,
    /// Wrong version.
    pub version: u32,
    /// Body did not decode.
    pub decode: u32,
    /// Too long.
    pub oversized: u32,
}

impl FrameErrorCounts {
    /// All rejected frames.
    pub fn total(&self) -> u32 {
        self.cobs
            .wrapping_add(self.crc)
            .wrapping_add(self.version)
            .wrapping_add(self.decode)
            .wrapping_add(self.oversized)
    }

    fn count(&mut self, kind: FrameErrorKind) {
        let c = match kind {
            FrameErrorKind::Cobs => &mut self.cobs,
            FrameErrorKind::Crc => &mut self.crc,
            FrameErrorKind::Version => &mut self.version,
            FrameErrorKind::Decode => &mut self.decode,
            FrameErrorKind::Oversized => &mut self.oversized,
        };
        *c = c.wrapping_add(1);
    }
}

/// Write `msg` as one frame into `out`, delimiter included; returns the frame's length.
pub fn encode_frame<T: Serialize>(
    msg: &T,
    out: &mut [u8; MAX_FRAME_LEN],
) -> Result<usize, EncodeError> {
    encode_frame_with_version(msg, PROTOCOL_VERSION, out)
}

/// [`encode_frame`] with any version byte: for tests of version handling, and for a future host
/// that speaks an older version.
pub fn encode_frame_with_version<T: Serialize>(
    msg: &T,
    version: u8,
    out: &mut [u8; MAX_FRAME_LEN],
) -> Result<usize, EncodeError> {
    let mut body = [0u8; MAX_BODY_LEN];
    body[0] = version;
    let n = postcard::to_slice(msg, &mut body[1..MAX_BODY_LEN - CRC_LEN])
        .map_err(|_| EncodeError::TooLarge)?
        .len();
    let end = 1 + n;
    let crc = CRC32C.checksum(&body[..end]);
    body[end..end + CRC_LEN].copy_from_slice(&crc.to_le_bytes());
    let body = &body[..end + CRC_LEN];
    // MAX_BODY_LEN is chosen so the encoding plus the delimiter always fits MAX_FRAME_LEN.
    let len =
        cobs::try_encode(body, &mut out[..MAX_FRAME_LEN - 1]).map_err(|_| EncodeError::TooLarge)?;
    out[len] = 0;
    Ok(len + 1)
}

/// Decode one frame's bytes (without its delimiter), in place.
pub fn decode_frame<T: DeserializeOwned>(encoded: &mut [u8]) -> Result<T, FrameError> {
    let err = |kind, version| FrameError { kind, version };
    let n = cobs::decode_in_place(encoded).map_err(|_| err(FrameErrorKind::Cobs, 0))?;
    let body = encoded.get(..n).ok_or(err(FrameErrorKind::Cobs, 0))?;
    if body.len() < 1 + CRC_LEN {
        return Err(err(FrameErrorKind::Crc, 0));
    }
    let (data, crc) = body.split_at(body.len() - CRC_LEN);
    let got = u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]);
    if CRC32C.checksum(data) != got {
        return Err(err(FrameErrorKind::Crc, 0));
    }
    let version = data[0];
    if version != PROTOCOL_VERSION {
        return Err(err(FrameErrorKind::Version, version));
    }
    match postcard::take_from_bytes::<T>(&data[1..]) {
        Ok((msg, [])) => Ok(msg),
        _ => Err(err(FrameErrorKind::Decode, version)),
    }
}

/// A streaming decoder: feed it bytes as they arrive; at each delimiter it yields a message or a
/// [`FrameError`], which it also counts. Empty frames (two delimiters in a row, used to
/// resynchronise a link) are skipped silently. Its buffer is one fixed [`MAX_FRAME_LEN`] array.
#[derive(Clone, Debug)]
pub struct FrameDecoder {
    buf: [u8; MAX_FRAME_LEN],
    len: usize,
    overflowed: bool,
    frames: u32,
    errors: FrameErrorCounts,
}

impl Default for FrameDecoder {
    fn default() -> Self {
        FrameDecoder::new()
    }
}

impl FrameDecoder {
    /// An empty decoder.
    pub const fn new() -> Self {
        FrameDecoder {
            buf: [0; MAX_FRAME_LEN],
            len: 0,
            overflowed: false,
            frames: 0,
            errors: FrameErrorCounts {
                cobs: 0,
                crc: 0,
                version: 0,
                decode: 0,
                oversized: 0,
            },
        }
    }

    /// Take one byte. Returns `Some` at the end of a non-empty frame.
    pub fn push<T: DeserializeOwned>(&mut self, byte: u8) -> Option<Result<T, FrameError>> {
        if byte != 0 {
            match self.buf.get_mut(self.len) {
                Some(slot) if !self.overflowed => {
                    *slot = byte;
                    self.len += 1;
                }
                _ => self.overflowed = true,
            }
            return None;
        }
        let (len, overflowed) = (self.len, self.overflowed);
        self.len = 0;
        self.overflowed = false;
        let result = if overflowed {
            Err(FrameError {
                kind: FrameErrorKind::Oversized,
                version: 0,
            })
        } else if len == 0 {
            return None;
        } else {
            decode_frame::<T>(&mut self.buf[..len])
        };
        match &result {
            Ok(_) => self.frames = self.frames.wrapping_add(1),
            Err(e) => self.errors.count(e.kind),
        }
        Some(result)
    }

    /// Frames decoded into a message so far.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Rejected frames so far, by kind.
    pub fn errors(&self) -> FrameErrorCounts {
        self.errors
    }
}

#[cfg(test)]
pub(crate) mod tests;
