//! Messages and frames of the host link (`softfinger-protocol`) shared by the link benchmarks and
//! the on-target protocol tests: a typical command, the largest legal host → device frame, a state
//! sample, and the longest byte run the decoder's buffer takes. Everything is built on the stack,
//! as the firmware's link task does (no allocation).

use softfinger_protocol::{
    encode_frame, HostMsg, LocalModel, Mode, Request, StateSample, SurfaceShape, TickStatsWire,
    MAX_FRAME_LEN,
};
use softfinger_protocol::{ContactState, FrameDecoder, FrameError};

/// A frame on the wire: the bytes and how many of them are used (delimiter included).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub bytes: [u8; MAX_FRAME_LEN],
    pub len: usize,
}

impl Frame {
    /// The used bytes, delimiter included.
    pub fn wire(&self) -> &[u8] {
        &self.bytes[..self.len]
    }
}

/// `msg` encoded as one frame; `None` if it does not fit.
pub fn frame_of<T: serde::Serialize>(msg: &T) -> Option<Frame> {
    let mut bytes = [0u8; MAX_FRAME_LEN];
    let len = encode_frame(msg, &mut bytes).ok()?;
    Some(Frame { bytes, len })
}

/// Feed `bytes` to `dec` one at a time (as a UART or USB task does) and return the last result.
pub fn feed<T: serde::de::DeserializeOwned>(
    dec: &mut FrameDecoder,
    bytes: &[u8],
) -> Option<Result<T, FrameError>> {
    let mut last = None;
    for &b in bytes {
        if let Some(r) = dec.push::<T>(b) {
            last = Some(r);
        }
    }
    last
}

/// A typical command: start the state stream at 1/10 of the control rate (1 kHz at 10 kHz).
pub fn typical_command() -> HostMsg {
    HostMsg::Request {
        seq: 7,
        req: Request::SetStream { divisor: 10 },
    }
}

/// The largest legal host → device message. postcard writes f32 as 4 fixed bytes and integers as
/// varints (u16 ≤ 3 bytes, u32 ≤ 5), so the longest encoding is the message with the most fields
/// and every integer at its maximum: a local-model update (12 f32, 3 integers; the next longest,
/// `SetContactParams`, has 9 f32 and 1 integer) of a sphere (the shape with a size), sequence
/// numbers and maximum age all at their type's maximum: 66 postcard bytes, 71 with the version
/// byte and CRC, 73 on the wire.
pub fn largest_command() -> HostMsg {
    HostMsg::Request {
        seq: u16::MAX,
        req: Request::SetLocalModel(LocalModel {
            seq: u32::MAX,
            shape: SurfaceShape::Sphere { radius_m: 0.05 },
            position_m: [0.012, -0.034, 0.158],
            orientation: [0.877_582_6, 0.128_129_8, 0.256_259_6, 0.384_389_4],
            stiffness_n_per_m: 2_000.0,
            damping_n_s_per_m: 2.5,
            mu_s: 0.8,
            mu_k: 0.6,
            spin_stiffness_nm_per_rad: 0.01,
            max_age_ms: u16::MAX,
        }),
    }
}

/// A state sample as the device streams it while pressing a plane: mid-run tick, non-round values
/// in every field.
pub fn state_sample() -> StateSample {
    StateSample {
        tick: 1_234_567,
        probe_m: [0.0012, -0.0034, 0.1489],
        probe_vel_m_s: [0.021, -0.004, 0.0003],
        force_n: [0.17, -0.05, 2.01],
        spin_torque_nm: 4.7e-4,
        contact: ContactState::Rolling,
        contact_point_m: [0.0012, -0.0034, 0.139],
        flags: 0,
        mode: Mode::Armed,
        model_seq: 42,
        tick_stats: TickStatsWire {
            max_duration_ns: 18_250,
            mean_duration_ns: 16_900,
            overruns: 0,
        },
        dropped: 0,
    }
}

/// The longest run of bytes the decoder buffers ([`MAX_FRAME_LEN`], every one non-zero) that is
/// valid COBS: 16 blocks of a code byte 16 and 15 data bytes, which decode to a 255-byte body whose
/// CRC does not match. This is the most work the decoder does for one frame (COBS over 256 bytes,
/// CRC-32C over 251). Followed by the delimiter (index [`MAX_FRAME_LEN`]).
pub fn longest_bad_crc_run() -> [u8; MAX_FRAME_LEN + 1] {
    let mut run = [0u8; MAX_FRAME_LEN + 1];
    for (i, b) in run.iter_mut().take(MAX_FRAME_LEN).enumerate() {
        *b = if i % 16 == 0 { 16 } else { (i % 251) as u8 + 1 };
    }
    run
}
