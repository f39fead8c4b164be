//! The host link's cost on the target: what the firmware's link task pays per frame received and
//! per state sample sent, with `softfinger-protocol` as the firmware uses it (a fixed
//! `FrameDecoder` fed one byte at a time, `encode_frame` into a stack buffer; no allocation).
//!
//! - `protocol_decode_command`: a typical command frame (`SetStream`, 11 bytes on the wire) from
//!   its first byte to the decoded message;
//! - `protocol_decode_largest`: the largest legal host → device frame (a local-model update with
//!   every integer at its maximum, see [`largest_command`]);
//! - `protocol_reject_longest`: the longest byte run the decoder takes (256 bytes of valid COBS)
//!   with a CRC mismatch: the most work one frame can cost;
//! - `protocol_encode_state`: one state-stream message, postcard + CRC-32C + COBS + delimiter.
//!
//! After each measurement the result is checked (the frame decoded to the message sent, the run
//! was rejected for its CRC, the encoded state decodes back), so a figure is never of an error path
//! by accident.

use cortex_m_semihosting::hprintln;
use softfinger_mcu_bench::bench::Bencher;
use softfinger_mcu_bench::link::{
    feed, frame_of, largest_command, longest_bad_crc_run, state_sample, typical_command, Frame,
};
use softfinger_mcu_bench::{bb, bench};
use softfinger_protocol::{
    encode_frame, DeviceMsg, FrameDecoder, FrameErrorKind, HostMsg, MAX_FRAME_LEN,
};

/// All link benchmarks.
pub fn benches(b: &mut Bencher) {
    let (Some(typical), Some(largest)) =
        (frame_of(&typical_command()), frame_of(&largest_command()))
    else {
        hprintln!("ERROR protocol benches: a sample command does not fit a frame");
        b.fail();
        return;
    };
    hprintln!(
        "NOTE protocol frames on the wire: typical command {} bytes, largest command {} bytes",
        typical.len,
        largest.len
    );
    decode(b, "protocol_decode_command", &typical, &typical_command());
    decode(b, "protocol_decode_largest", &largest, &largest_command());
    reject_longest(b);
    encode_state(b);
}

/// Decode `frame` byte by byte; afterwards it must give `expected` and no error.
fn decode(b: &mut Bencher, name: &str, frame: &Frame, expected: &HostMsg) {
    let mut dec = FrameDecoder::new();
    let wire = frame.wire();
    bench!(b, name, _, || feed::<HostMsg>(&mut dec, bb(wire)));
    let got = feed::<HostMsg>(&mut dec, wire);
    if got != Some(Ok(expected.clone())) || dec.errors().total() != 0 {
        hprintln!(
            "ERROR {}: the frame did not decode to the message sent",
            name
        );
        b.fail();
    }
}

/// The longest accepted run with a bad CRC; afterwards it must be counted as a CRC error.
fn reject_longest(b: &mut Bencher) {
    let run = longest_bad_crc_run();
    let mut dec = FrameDecoder::new();
    bench!(b, "protocol_reject_longest", _, || {
        feed::<HostMsg>(&mut dec, bb(&run[..]))
    });
    let before = dec.errors().crc;
    let got = feed::<HostMsg>(&mut dec, &run);
    let crc_error = matches!(got, Some(Err(e)) if e.kind == FrameErrorKind::Crc);
    if !crc_error || dec.errors().crc != before + 1 || dec.frames() != 0 {
        hprintln!("ERROR protocol_reject_longest: expected a counted CRC error");
        b.fail();
    }
}

/// Encode one state sample into a frame; afterwards the frame must decode to the same sample.
fn encode_state(b: &mut Bencher) {
    let msg = DeviceMsg::State(state_sample());
    let mut out = [0u8; MAX_FRAME_LEN];
    bench!(b, "protocol_encode_state", _, || encode_frame(
        bb(&msg),
        &mut out
    ));
    let Ok(n) = encode_frame(&msg, &mut out) else {
        hprintln!("ERROR protocol_encode_state: the sample does not fit a frame");
        b.fail();
        return;
    };
    hprintln!("NOTE protocol state message: {} bytes on the wire", n);
    let mut dec = FrameDecoder::new();
    if feed::<DeviceMsg>(&mut dec, &out[..n]) != Some(Ok(msg)) {
        hprintln!("ERROR protocol_encode_state: the frame does not decode to the sample");
        b.fail();
    }
}
