//! The host link's decoder on the target: every message kind survives a round trip, and bad input
//! of each kind (garbage, truncated, oversized, wrong version, wrong CRC, undecodable body, the
//! committed fuzz corpus) gives the documented, counted error and never panics (a panic would end
//! the run through the panic handler, failing it).
//!
//! Expected kinds follow from the wire format, not from running the decoder on the host: COBS is
//! checked first, then the CRC (a body shorter than the CRC counts as a CRC error), then the
//! version byte, then the postcard body. A CRC-32C detects every error burst of at most 32 bits, so
//! changing any one data byte of a frame is always a CRC error.

use core::hint::black_box as bb;
use softfinger_mcu_bench::check::Checker;
use softfinger_mcu_bench::link::{
    feed, frame_of, largest_command, longest_bad_crc_run, state_sample, typical_command, Frame,
};
use softfinger_protocol::frame::encode_frame_with_version;
use softfinger_protocol::{
    DeviceEndpoint, DeviceMsg, FrameDecoder, FrameErrorCounts, FrameErrorKind, HostMsg,
    LinkCounters, MAX_FRAME_LEN, PROTOCOL_VERSION,
};

mod kinds;

include!(concat!(env!("OUT_DIR"), "/protocol_corpus.rs"));

pub fn checks(c: &mut Checker) {
    c.group("protocol");
    kinds::round_trips(c);
    let (Some(typical), Some(largest)) =
        (frame_of(&typical_command()), frame_of(&largest_command()))
    else {
        c.ok("the sample commands fit a frame", false);
        return;
    };
    let Some(state) = frame_of(&DeviceMsg::State(state_sample())) else {
        c.ok("the state sample fits a frame", false);
        return;
    };
    garbage(c);
    truncated(c, &[typical, largest, state]);
    oversized(c, &typical);
    wrong_version(c);
    wrong_crc(c, &[typical, largest, state]);
    undecodable(c);
    endpoint_answers(c, &typical);
    corpus(c);
}

/// The one error `bytes` (a single frame, delimiter included) gives, checked to be counted once
/// and alone; `None` if it decoded or was counted wrongly.
fn single_error(bytes: &[u8]) -> Option<FrameErrorKind> {
    let mut dec = FrameDecoder::new();
    let kind = match feed::<HostMsg>(&mut dec, bytes)? {
        Ok(_) => return None,
        Err(e) => e.kind,
    };
    let e: FrameErrorCounts = dec.errors();
    let counter = match kind {
        FrameErrorKind::Cobs => e.cobs,
        FrameErrorKind::Crc => e.crc,
        FrameErrorKind::Version => e.version,
        FrameErrorKind::Decode => e.decode,
        FrameErrorKind::Oversized => e.oversized,
    };
    (counter == 1 && e.total() == 1 && dec.frames() == 0).then_some(kind)
}

/// `frame` with its bytes `..keep` and a delimiter.
fn cut(frame: &Frame, keep: usize) -> ([u8; MAX_FRAME_LEN], usize) {
    let mut b = [0u8; MAX_FRAME_LEN];
    b[..keep].copy_from_slice(&frame.bytes[..keep]);
    (b, keep + 1)
}

/// Positions of COBS code bytes in a frame (delimiter excluded): the first byte, then each code
/// byte `code` positions after the previous one.
fn code_positions(frame: &Frame) -> [bool; MAX_FRAME_LEN] {
    let mut is_code = [false; MAX_FRAME_LEN];
    let mut i = 0;
    while i < frame.len - 1 {
        is_code[i] = true;
        i += frame.bytes[i].max(1) as usize;
    }
    is_code
}

/// Known garbage: a code byte promising more bytes than the frame has is a COBS error; a frame
/// that decodes to fewer bytes than a CRC is a CRC error. Then 4 kB of pseudo-random bytes
/// (xorshift32, zero about one byte in 40): each non-empty segment gives exactly one result and the
/// counters add up, in both directions.
fn garbage(c: &mut Checker) {
    c.ok(
        "garbage: code 5 with 1 byte is a COBS error",
        single_error(&[5, 1, 0]) == Some(FrameErrorKind::Cobs),
    );
    c.ok(
        "garbage: code 0xFF alone is a COBS error",
        single_error(&[0xFF, 0]) == Some(FrameErrorKind::Cobs),
    );
    for (name, bytes) in [
        ("empty body", &[1u8, 0][..]),
        ("4-byte body", &[5, 1, 2, 3, 4, 0][..]),
    ] {
        c.ok(name, single_error(bytes) == Some(FrameErrorKind::Crc));
    }
    let mut x = 0x1234_5678u32;
    let mut data = [0u8; 4096];
    for b in data.iter_mut() {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        *b = if x.is_multiple_of(40) {
            0
        } else {
            (x >> 8) as u8 | 1
        };
    }
    let nonempty = frames_in(&data);
    c.ok("garbage: the stream has frames", nonempty > 50);
    c.ok(
        "garbage: host → device results add up",
        counted::<HostMsg>(&data) == Some(nonempty),
    );
    c.ok(
        "garbage: device → host results add up",
        counted::<DeviceMsg>(&data) == Some(nonempty),
    );
}

/// The frames a decoder sees in `data`: its non-empty runs that a 0x00 delimiter ends (a run
/// without one is still incomplete).
fn frames_in(data: &[u8]) -> u32 {
    let mut run = 0usize;
    let mut frames = 0u32;
    for &b in data {
        if b != 0 {
            run += 1;
        } else if core::mem::take(&mut run) > 0 {
            frames += 1;
        }
    }
    frames
}

/// Feed `data`; the number of results if it equals decoded + rejected frames and every decoded
/// message round-trips, else `None`.
fn counted<T>(data: &[u8]) -> Option<u32>
where
    T: serde::Serialize + serde::de::DeserializeOwned + PartialEq,
{
    let mut dec = FrameDecoder::new();
    let mut results = 0u32;
    for &b in data {
        if let Some(r) = dec.push::<T>(bb(b)) {
            results += 1;
            if let Ok(msg) = r {
                if !same_encoding(&msg) {
                    return None;
                }
            }
        }
    }
    (dec.frames() + dec.errors().total() == results).then_some(results)
}

/// `msg` re-encoded, decoded and encoded again gives the same frame (NaN-safe: bytes, not values).
fn same_encoding<T>(msg: &T) -> bool
where
    T: serde::Serialize + serde::de::DeserializeOwned,
{
    let Some(a) = frame_of(msg) else {
        return false;
    };
    let mut dec = FrameDecoder::new();
    let Some(Ok(again)) = feed::<T>(&mut dec, a.wire()) else {
        return false;
    };
    frame_of(&again).is_some_and(|b| a.wire() == b.wire())
}

/// Every proper prefix of a frame (as if the link dropped its tail) is a COBS or a CRC error,
/// counted once.
fn truncated(c: &mut Checker, frames: &[Frame]) {
    for f in frames {
        let all = (1..f.len - 1).all(|keep| {
            let (b, n) = cut(f, keep);
            matches!(
                single_error(&b[..n]),
                Some(FrameErrorKind::Cobs | FrameErrorKind::Crc)
            )
        });
        c.ok("truncated: every prefix is a COBS or CRC error", all);
    }
}

/// The decoder buffers at most MAX_FRAME_LEN bytes: one more is an oversized frame (and the
/// decoder then takes the next frame normally), exactly that many is decoded (here a CRC error).
fn oversized(c: &mut Checker, typical: &Frame) {
    let run = longest_bad_crc_run();
    c.ok(
        "oversized: MAX_FRAME_LEN bytes are decoded",
        single_error(&run) == Some(FrameErrorKind::Crc),
    );
    let mut over = [0x11u8; MAX_FRAME_LEN + 2];
    over[MAX_FRAME_LEN + 1] = 0;
    c.ok(
        "oversized: MAX_FRAME_LEN + 1 bytes are an oversized frame",
        single_error(&over) == Some(FrameErrorKind::Oversized),
    );
    let mut dec = FrameDecoder::new();
    let first = feed::<HostMsg>(&mut dec, &[0x22u8; 1000]);
    let end = feed::<HostMsg>(&mut dec, &[0]);
    let next = feed::<HostMsg>(&mut dec, typical.wire());
    c.ok(
        "oversized: 1000 bytes, one error, then the next frame decodes",
        first.is_none()
            && matches!(end, Some(Err(e)) if e.kind == FrameErrorKind::Oversized)
            && next == Some(Ok(typical_command()))
            && dec.errors().oversized == 1
            && dec.frames() == 1,
    );
}

/// A valid frame of another version is a version error carrying that version; this version decodes.
fn wrong_version(c: &mut Checker) {
    for v in [0u8, PROTOCOL_VERSION + 1, 0xFF] {
        let mut b = [0u8; MAX_FRAME_LEN];
        let Ok(n) = encode_frame_with_version(&typical_command(), v, &mut b) else {
            c.ok_at("wrong version: encodes", v as f32, false);
            continue;
        };
        let mut dec = FrameDecoder::new();
        let got = feed::<HostMsg>(&mut dec, &b[..n]);
        c.ok_at(
            "wrong version: counted, version reported",
            v as f32,
            matches!(got, Some(Err(e)) if e.kind == FrameErrorKind::Version && e.version == v)
                && dec.errors().version == 1
                && dec.errors().total() == 1,
        );
    }
    let mut b = [0u8; MAX_FRAME_LEN];
    let ok =
        encode_frame_with_version(&typical_command(), PROTOCOL_VERSION, &mut b).is_ok_and(|n| {
            feed::<HostMsg>(&mut FrameDecoder::new(), &b[..n]).is_some_and(|r| r.is_ok())
        });
    c.ok("wrong version: PROTOCOL_VERSION decodes", ok);
}

/// Any one data byte changed (to another non-zero value) is a CRC error; any one code byte changed
/// is a COBS or a CRC error. Every position of each frame.
fn wrong_crc(c: &mut Checker, frames: &[Frame]) {
    for f in frames {
        let is_code = code_positions(f);
        let (mut data_ok, mut code_ok) = (true, true);
        for i in 0..f.len - 1 {
            let mut b = f.bytes;
            b[i] = if b[i] == 1 { 2 } else { b[i] ^ 1 };
            let got = single_error(&b[..f.len]);
            if is_code[i] {
                code_ok &= matches!(got, Some(FrameErrorKind::Cobs | FrameErrorKind::Crc));
            } else {
                data_ok &= got == Some(FrameErrorKind::Crc);
            }
        }
        c.ok("wrong CRC: every data byte changed is a CRC error", data_ok);
        c.ok(
            "wrong CRC: every code byte changed is a COBS or CRC error",
            code_ok,
        );
    }
}

/// A frame with a good CRC and version whose body is not a host message: an unknown variant
/// index (HostMsg has 2), and a message followed by a trailing byte.
fn undecodable(c: &mut Checker) {
    let unknown = frame_of(&9u8);
    c.ok(
        "undecodable: unknown variant is a decode error",
        unknown.is_some_and(|f| single_error(f.wire()) == Some(FrameErrorKind::Decode)),
    );
    let trailing = frame_of(&(typical_command(), 1u8));
    c.ok(
        "undecodable: trailing byte is a decode error",
        trailing.is_some_and(|f| single_error(f.wire()) == Some(FrameErrorKind::Decode)),
    );
}

/// The firmware's path: a `DeviceEndpoint` answers one bad frame of each kind with a
/// `FrameError` of that kind, stays usable (a good request is answered), and its counters say so.
fn endpoint_answers(c: &mut Checker, typical: &Frame) {
    let mut ep = DeviceEndpoint::new(1);
    let mut over = [0x33u8; MAX_FRAME_LEN + 2];
    over[MAX_FRAME_LEN + 1] = 0;
    let version = {
        let mut b = [0u8; MAX_FRAME_LEN];
        let n = encode_frame_with_version(&typical_command(), 2, &mut b).unwrap_or(0);
        (b, n)
    };
    let decode = frame_of(&9u8);
    let mut replies: [Option<DeviceMsg>; 8] = Default::default();
    let mut n_replies = 0usize;
    let mut send = |bytes: &[u8]| {
        let mut dec = FrameDecoder::new();
        if let (Some(Ok(m)), Some(slot)) = (
            feed::<DeviceMsg>(&mut dec, bytes),
            replies.get_mut(n_replies),
        ) {
            *slot = Some(m);
        }
        n_replies += 1;
        true
    };
    let inputs: [&[u8]; 6] = [
        &[5, 1, 0],
        &[5, 1, 2, 3, 4, 0],
        &version.0[..version.1],
        decode.as_ref().map_or(&[][..], |f| f.wire()),
        &over,
        typical.wire(),
    ];
    for bytes in inputs {
        for &b in bytes {
            let _ = ep.receive(b, &mut send);
        }
    }
    let kinds = [
        FrameErrorKind::Cobs,
        FrameErrorKind::Crc,
        FrameErrorKind::Version,
        FrameErrorKind::Decode,
        FrameErrorKind::Oversized,
    ];
    let answered = kinds.iter().zip(&replies).all(|(k, r)| {
        matches!(r, Some(DeviceMsg::FrameError { kind, device_version })
            if kind == k && *device_version == PROTOCOL_VERSION)
    });
    c.ok("endpoint: each bad frame answered with its kind", answered);
    c.ok(
        "endpoint: the good request after them is answered",
        n_replies == 6 && matches!(replies[5], Some(DeviceMsg::Ack { seq: 7, .. })),
    );
    let k: LinkCounters = ep.counters();
    c.ok(
        "endpoint: counters",
        k.rx_cobs == 1
            && k.rx_crc == 1
            && k.rx_version == 1
            && k.rx_decode == 1
            && k.rx_oversized == 1
            && k.rx_errors == 5
            && k.rx_frames == 1
            && k.tx_frames == 6,
    );
}

/// The committed fuzz corpus: in both directions, one result per non-empty segment, counters add
/// up, decoded messages round-trip.
fn corpus(c: &mut Checker) {
    c.ok("corpus: embedded", CORPUS.len() >= 10);
    for (name, data) in CORPUS {
        let nonempty = frames_in(data);
        let host = counted::<HostMsg>(data) == Some(nonempty);
        let device = counted::<DeviceMsg>(data) == Some(nonempty);
        if !(host && device) {
            cortex_m_semihosting::hprintln!("corpus file {} failed", name);
        }
        c.ok(
            "corpus: results add up, messages round-trip",
            host && device,
        );
    }
}
