use super::*;
use crate::info::{DeviceInfo, LinkCounters};
use crate::messages::{AckResult, DeviceMsg, ErrorCode, HostMsg, Request};
use crate::model::{ContactParamsWire, HandTarget, LocalModel, SurfaceKind, SurfaceShape};
use crate::state::{ContactState, Mode, StateSample, TickStatsWire};
use proptest::prelude::*;
use std::vec;
use std::vec::Vec;

fn frame_of<T: Serialize>(msg: &T) -> Vec<u8> {
    let mut out = [0u8; MAX_FRAME_LEN];
    let n = encode_frame(msg, &mut out).expect("fits");
    out[..n].to_vec()
}

fn decode_all<T: DeserializeOwned>(
    dec: &mut FrameDecoder,
    bytes: &[u8],
) -> Vec<Result<T, FrameError>> {
    bytes.iter().filter_map(|b| dec.push::<T>(*b)).collect()
}

/// A sphere model, its material and position each a different value (other tests reuse it).
pub(crate) fn model(seq: u32) -> LocalModel {
    LocalModel {
        seq,
        shape: SurfaceShape::Sphere { radius_m: 0.05 },
        position_m: [0.0, 0.01, -0.02],
        orientation: [1.0, 0.0, 0.0, 0.0],
        stiffness_n_per_m: 2000.0,
        damping_n_s_per_m: 2.0,
        mu_s: 0.8,
        mu_k: 0.6,
        spin_stiffness_nm_per_rad: 0.01,
        max_age_ms: u16::MAX,
    }
}

/// Contact parameters, each field a different value: a golden frame catches two fields swapped.
fn contact_params() -> ContactParamsWire {
    ContactParamsWire {
        fingertip_radius_m: 0.012,
        normal_stiffness: 2500.0,
        normal_damping: 2.5,
        tangential_stiffness: 1100.0,
        tangential_damping: 1.25,
        mu_s: 0.9,
        mu_k: 0.7,
        spin_stiffness: 0.02,
        max_force_n: 11.0,
    }
}

/// The largest message of each direction, every field at its widest encoding.
fn largest_device_msgs() -> Vec<DeviceMsg> {
    let mut name = heapless::String::<24>::new();
    let mut fw = heapless::String::<16>::new();
    for _ in 0..24 {
        name.push('é').ok();
        name.push('x').ok();
    }
    for _ in 0..16 {
        fw.push('9').ok();
    }
    let mut surfaces = heapless::Vec::new();
    for _ in 0..8 {
        surfaces.push(SurfaceKind::Sphere).unwrap();
    }
    let s = StateSample {
        tick: u64::MAX,
        probe_m: [f32::MAX; 3],
        probe_vel_m_s: [f32::MIN; 3],
        force_n: [1.0; 3],
        spin_torque_nm: -1.0,
        contact: ContactState::Sliding,
        contact_point_m: [2.0; 3],
        flags: u32::MAX,
        mode: Mode::Faulted,
        model_seq: u32::MAX,
        tick_stats: TickStatsWire {
            max_duration_ns: u32::MAX,
            mean_duration_ns: u32::MAX,
            overruns: u32::MAX,
        },
        dropped: u32::MAX,
    };
    let c = u32::MAX;
    vec![
        DeviceMsg::State(s),
        DeviceMsg::Info {
            seq: u16::MAX,
            info: DeviceInfo {
                protocol_version: 255,
                name,
                firmware_version: fw,
                virtual_device: true,
                control_rate_hz: u32::MAX,
                max_force_n: 12.0,
                min_stream_divisor: u16::MAX,
                surfaces,
                watchdog_ms: u16::MAX,
                settings_flags: u8::MAX,
                reset_cause: heapless::String::try_from("éééééééé").unwrap(),
            },
        },
        DeviceMsg::Counters {
            seq: u16::MAX,
            counters: LinkCounters {
                rx_frames: c,
                rx_errors: c,
                rx_cobs: c,
                rx_crc: c,
                rx_version: c,
                rx_decode: c,
                rx_oversized: c,
                tx_frames: c,
                tx_dropped: c,
                connections: u16::MAX,
            },
        },
        DeviceMsg::Ack {
            seq: 7,
            result: AckResult::Err(ErrorCode::StaleSequence),
        },
        DeviceMsg::HelloReply {
            version: Some(1),
            device_version: 1,
        },
        DeviceMsg::FrameError {
            kind: FrameErrorKind::Version,
            device_version: 1,
        },
    ]
}

fn host_msgs() -> Vec<HostMsg> {
    let req = |seq, req| HostMsg::Request { seq, req };
    vec![
        HostMsg::Hello {
            min_version: 1,
            max_version: 3,
        },
        req(1, Request::GetInfo),
        req(2, Request::GetCounters),
        req(2, Request::GetContactParams),
        req(3, Request::Ping),
        req(4, Request::Home),
        req(5, Request::Arm),
        req(6, Request::Disarm),
        req(7, Request::ClearFaults),
        req(8, Request::SetContactParams(contact_params())),
        req(u16::MAX, Request::SetLocalModel(model(u32::MAX))),
        req(10, Request::SetStream { divisor: 10 }),
        req(11, Request::SetWatchdog { timeout_ms: 100 }),
        req(
            12,
            Request::DriveHand(HandTarget {
                position_m: [0.0, 0.0, 0.1],
                wrist_rad: [0.1, 0.2, 0.3],
            }),
        ),
        req(13, Request::ReleaseHand),
    ]
}

#[test]
fn every_message_round_trips_and_the_largest_fit() {
    let mut dec = FrameDecoder::new();
    for m in largest_device_msgs() {
        let f = frame_of(&m);
        assert!(f.len() <= MAX_FRAME_LEN);
        assert_eq!(f.iter().filter(|b| **b == 0).count(), 1, "one delimiter");
        let got = decode_all::<DeviceMsg>(&mut dec, &f);
        assert_eq!(got, vec![Ok(m)]);
    }
    let mut dec = FrameDecoder::new();
    for m in host_msgs() {
        let got = decode_all::<HostMsg>(&mut dec, &frame_of(&m));
        assert_eq!(got, vec![Ok(m)]);
    }
    assert_eq!(dec.frames() as usize, host_msgs().len());
    assert_eq!(dec.errors(), FrameErrorCounts::default());
}

#[test]
fn a_message_over_the_body_limit_is_refused() {
    // A slice of n f32 is 1 length byte + 4n bytes; with the version byte and the CRC the body
    // is 4n + 6: n = 61 gives 250 <= MAX_BODY_LEN (252), n = 62 gives 254 > 252.
    let mut out = [0u8; MAX_FRAME_LEN];
    let fits = [1.0f32; 61];
    assert!(encode_frame(&&fits[..], &mut out).is_ok());
    let big = [1.0f32; 62];
    assert_eq!(
        encode_frame(&&big[..], &mut out),
        Err(EncodeError::TooLarge)
    );
}

/// Each kind of bad input is rejected, counted under its own kind, and the next good frame still
/// decodes.
#[test]
fn bad_frames_are_counted_by_kind_and_the_stream_goes_on() {
    let good = frame_of(&HostMsg::Request {
        seq: 9,
        req: Request::Ping,
    });
    // Wrong CRC: flip one bit of a body byte (COBS-encoded bytes stay non-zero).
    let mut wrong_crc = good.clone();
    wrong_crc[3] ^= 0x01;
    assert_ne!(wrong_crc[3], 0);
    // Truncated: the first half of a frame, then its delimiter (its COBS code now points past
    // the end, so it fails as COBS).
    let mut truncated = good[..good.len() / 2].to_vec();
    truncated.push(0);
    // Wrong version with a valid CRC.
    let mut out = [0u8; MAX_FRAME_LEN];
    let n = encode_frame_with_version(
        &HostMsg::Request {
            seq: 1,
            req: Request::Ping,
        },
        2,
        &mut out,
    )
    .unwrap();
    let wrong_version = out[..n].to_vec();
    // Valid framing, body of another type: a variant index no HostMsg has.
    let undecodable = frame_of(&(200u8, 1u8));
    // Trailing bytes after a valid message.
    let trailing = frame_of(&(
        HostMsg::Request {
            seq: 1,
            req: Request::Ping,
        },
        5u8,
    ));
    // Oversized: 300 non-zero bytes.
    let mut oversized = vec![0x55u8; 300];
    oversized.push(0);
    // COBS code pointing past the end.
    let bad_cobs = vec![0x09u8, 0x01, 0x02, 0x00];

    let mut dec = FrameDecoder::new();
    let mut stream = Vec::new();
    for f in [
        &wrong_crc,
        &truncated,
        &wrong_version,
        &undecodable,
        &trailing,
        &oversized,
        &bad_cobs,
    ] {
        stream.extend_from_slice(f);
    }
    stream.extend_from_slice(&[0, 0, 0]); // empty frames: skipped
    stream.extend_from_slice(&good);
    let got = decode_all::<HostMsg>(&mut dec, &stream);
    let kinds: Vec<_> = got
        .iter()
        .map(|r| r.as_ref().err().map(|e| e.kind))
        .collect();
    use FrameErrorKind::*;
    assert_eq!(
        kinds,
        vec![
            Some(Crc),
            Some(Cobs),
            Some(Version),
            Some(Decode),
            Some(Decode),
            Some(Oversized),
            Some(Cobs),
            None
        ]
    );
    assert_eq!(got[2].as_ref().unwrap_err().version, 2);
    assert_eq!(
        got[7],
        Ok(HostMsg::Request {
            seq: 9,
            req: Request::Ping
        })
    );
    let e = dec.errors();
    assert_eq!(
        (e.cobs, e.crc, e.version, e.decode, e.oversized),
        (2, 1, 1, 2, 1)
    );
    assert_eq!(e.total(), 7);
    assert_eq!(dec.frames(), 1);
}

/// The frame-length limit, just below and just above: 256 non-zero bytes are buffered (and then
/// fail as a frame), 257 are oversized.
#[test]
fn oversize_threshold_is_exact() {
    let mut dec = FrameDecoder::new();
    let mut at_limit = vec![0x01u8; MAX_FRAME_LEN];
    at_limit.push(0);
    let r = decode_all::<HostMsg>(&mut dec, &at_limit);
    assert_ne!(r[0].as_ref().unwrap_err().kind, FrameErrorKind::Oversized);
    let mut over = vec![0x01u8; MAX_FRAME_LEN + 1];
    over.push(0);
    let r = decode_all::<HostMsg>(&mut dec, &over);
    assert_eq!(r[0].as_ref().unwrap_err().kind, FrameErrorKind::Oversized);
}

proptest! {
    /// Any byte sequence: no panic, and every non-empty delimited segment gives exactly one result
    /// that is either a message or a counted error.
    #[test]
    fn any_bytes_decode_or_count(bytes in proptest::collection::vec(any::<u8>(), 0..2000)) {
        let mut dec = FrameDecoder::new();
        let results = decode_all::<HostMsg>(&mut dec, &bytes);
        let segments = bytes.split(|b| *b == 0).count() - 1;
        let nonempty = bytes
            .split(|b| *b == 0)
            .take(segments)
            .filter(|s| !s.is_empty())
            .count();
        prop_assert_eq!(results.len(), nonempty);
        prop_assert_eq!(dec.frames() + dec.errors().total(), nonempty as u32);
        let oks = results.iter().filter(|r| r.is_ok()).count() as u32;
        prop_assert_eq!(oks, dec.frames());
    }

    /// A valid frame with one byte changed never decodes into a different message.
    #[test]
    fn one_corrupted_byte_never_yields_another_message(
        i in 0usize..64, x in 1u8..=255, seq in any::<u16>(), mseq in any::<u32>()
    ) {
        let msg = HostMsg::Request { seq, req: Request::SetLocalModel(model(mseq)) };
        let mut f = frame_of(&msg);
        let i = i % (f.len() - 1);
        f[i] ^= x;
        let mut dec = FrameDecoder::new();
        for m in decode_all::<HostMsg>(&mut dec, &f).into_iter().flatten() {
            prop_assert_eq!(m, msg.clone());
        }
    }

    /// Frames split at arbitrary points and interleaved with garbage resynchronise at the next
    /// delimiter: the good frames after the garbage all decode.
    #[test]
    fn resynchronises_after_garbage(garbage in proptest::collection::vec(any::<u8>(), 0..600), n in 1usize..5) {
        let mut stream = garbage.clone();
        stream.push(0);
        for k in 0..n {
            stream.extend_from_slice(&frame_of(&HostMsg::Request { seq: k as u16, req: Request::Ping }));
        }
        let mut dec = FrameDecoder::new();
        let results = decode_all::<HostMsg>(&mut dec, &stream);
        let tail: Vec<_> = results[results.len() - n..].to_vec();
        for (k, r) in tail.into_iter().enumerate() {
            prop_assert_eq!(r, Ok(HostMsg::Request { seq: k as u16, req: Request::Ping }));
        }
    }
}

mod golden;
