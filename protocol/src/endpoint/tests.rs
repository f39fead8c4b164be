use super::*;
use crate::frame::{encode_frame_with_version, FrameErrorKind};
use std::vec;
use std::vec::Vec;

fn frame(msg: &HostMsg) -> Vec<u8> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = crate::encode_frame(msg, &mut buf).unwrap();
    buf[..n].to_vec()
}

/// Feed `bytes`; the requests handed to the control side and the messages sent back.
fn feed(ep: &mut DeviceEndpoint, bytes: &[u8]) -> (Vec<(u16, Request)>, Vec<DeviceMsg>) {
    let mut wire = Vec::new();
    let mut reqs = Vec::new();
    for &b in bytes {
        let mut send = |f: &[u8]| {
            wire.extend_from_slice(f);
            true
        };
        if let Some(r) = ep.receive(b, &mut send) {
            reqs.push(r);
        }
    }
    (reqs, decode_all(&wire))
}

fn decode_all(wire: &[u8]) -> Vec<DeviceMsg> {
    let mut dec = FrameDecoder::new();
    wire.iter()
        .filter_map(|b| dec.push::<DeviceMsg>(*b))
        .map(|r| r.unwrap())
        .collect()
}

#[test]
fn link_messages_are_answered_here_and_requests_passed_on() {
    let mut ep = DeviceEndpoint::new(2);
    let mut bytes = frame(&HostMsg::Hello {
        min_version: 1,
        max_version: 4,
    });
    bytes.extend(frame(&HostMsg::Request {
        seq: 1,
        req: Request::Arm,
    }));
    bytes.extend(frame(&HostMsg::Request {
        seq: 2,
        req: Request::SetStream { divisor: 1 },
    }));
    bytes.extend(frame(&HostMsg::Request {
        seq: 3,
        req: Request::SetStream { divisor: 2 },
    }));
    bytes.extend(frame(&HostMsg::Request {
        seq: 4,
        req: Request::GetCounters,
    }));
    let (reqs, sent) = feed(&mut ep, &bytes);
    assert_eq!(reqs, vec![(1, Request::Arm)]);
    assert_eq!(ep.divisor(), 2);
    assert_eq!(
        sent[..3],
        [
            DeviceMsg::HelloReply {
                version: Some(1),
                device_version: 1
            },
            DeviceMsg::Ack {
                seq: 2,
                result: AckResult::Err(ErrorCode::StreamTooFast)
            },
            DeviceMsg::Ack {
                seq: 3,
                result: AckResult::Ok
            },
        ]
    );
    match &sent[3] {
        DeviceMsg::Counters { seq: 4, counters } => {
            assert_eq!(
                (counters.rx_frames, counters.rx_errors, counters.tx_frames),
                (5, 0, 3)
            );
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_frames_are_answered_and_counted() {
    let mut ep = DeviceEndpoint::new(1);
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = encode_frame_with_version(
        &HostMsg::Request {
            seq: 1,
            req: Request::Ping,
        },
        7,
        &mut buf,
    )
    .unwrap();
    let mut bytes = buf[..n].to_vec();
    bytes.extend([0x55u8; 300]);
    bytes.push(0);
    bytes.extend(frame(&HostMsg::Request {
        seq: 9,
        req: Request::Ping,
    }));
    let (reqs, sent) = feed(&mut ep, &bytes);
    assert_eq!(reqs, vec![(9, Request::Ping)]);
    let kinds: Vec<_> = sent
        .iter()
        .map(|m| match m {
            DeviceMsg::FrameError { kind, .. } => *kind,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(
        kinds,
        vec![FrameErrorKind::Version, FrameErrorKind::Oversized]
    );
    let c = ep.counters();
    assert_eq!(
        (c.rx_version, c.rx_oversized, c.rx_errors, c.rx_frames),
        (1, 1, 2, 1)
    );
}

/// Every `divisor`-th tick is sent; a full queue drops the sample and the next one says so.
#[test]
fn the_stream_follows_the_divisor_and_counts_drops() {
    let mut ep = DeviceEndpoint::new(1);
    feed(
        &mut ep,
        &frame(&HostMsg::Request {
            seq: 1,
            req: Request::SetStream { divisor: 10 },
        }),
    );
    let mut wire = Vec::new();
    for tick in 0..50u64 {
        let full = tick == 20;
        let mut send = |f: &[u8]| {
            if full {
                return false;
            }
            wire.extend_from_slice(f);
            true
        };
        ep.offer_state(
            &StateSample {
                tick,
                ..StateSample::default()
            },
            &mut send,
        );
    }
    let got: Vec<(u64, u32)> = decode_all(&wire)
        .into_iter()
        .map(|m| match m {
            DeviceMsg::State(s) => (s.tick, s.dropped),
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(got, vec![(0, 0), (10, 0), (30, 1), (40, 1)]);
    assert_eq!(ep.counters().tx_dropped, 1);
}

/// One link of several hands `GetCounters` on (the device answers with the sum over its links)
/// and answers hello and the stream divisor itself, as a lone link does.
#[test]
fn one_of_several_links_hands_the_counters_on() {
    let mut ep = DeviceEndpoint::one_of_several(1);
    let mut bytes = frame(&HostMsg::Hello {
        min_version: 1,
        max_version: 1,
    });
    bytes.extend(frame(&HostMsg::Request {
        seq: 1,
        req: Request::GetCounters,
    }));
    bytes.extend(frame(&HostMsg::Request {
        seq: 2,
        req: Request::SetStream { divisor: 1 },
    }));
    let (reqs, sent) = feed(&mut ep, &bytes);
    assert_eq!(reqs, vec![(1, Request::GetCounters)]);
    assert_eq!(ep.divisor(), 1);
    assert_eq!(
        sent,
        vec![
            DeviceMsg::HelloReply {
                version: Some(1),
                device_version: 1
            },
            DeviceMsg::Ack {
                seq: 2,
                result: AckResult::Ok
            },
        ]
    );
    let c = ep.counters();
    assert_eq!((c.rx_frames, c.tx_frames, c.connections), (3, 2, 1));
    let both = c.plus(&c);
    assert_eq!(
        (both.rx_frames, both.tx_frames, both.connections),
        (6, 4, 2)
    );
}
