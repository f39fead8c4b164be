//! The settings and update messages: they round-trip through a frame, the largest of each fits
//! one, and appending them left every earlier message's encoding as it was.

use softfinger_protocol::config::{ConfigRefusal, ConfigSection, ConfigValue, StoreStatus};
use softfinger_protocol::update::{
    BootStateWire, UpdateChunk, UpdatePhase, UpdateRefusal, UpdateStatus, UPDATE_CHUNK_LEN,
};
use softfinger_protocol::{
    encode_frame, DeviceMsg, FrameDecoder, FrameErrorKind, HostMsg, Request, MAX_FRAME_LEN,
};
use softfinger_store::{Calibration, MotorConstants, Settings};

fn round_trip_host(m: HostMsg) -> usize {
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = encode_frame(&m, &mut buf).expect("fits a frame");
    let mut d = FrameDecoder::new();
    let mut got = None;
    for b in &buf[..n] {
        if let Some(r) = d.push::<HostMsg>(*b) {
            got = Some(r.unwrap());
        }
    }
    assert_eq!(got.unwrap(), m);
    n
}

fn round_trip_device(m: DeviceMsg) -> usize {
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = encode_frame(&m, &mut buf).expect("fits a frame");
    let mut d = FrameDecoder::new();
    let mut got = None;
    for b in &buf[..n] {
        if let Some(r) = d.push::<DeviceMsg>(*b) {
            got = Some(r.unwrap());
        }
    }
    assert_eq!(got.unwrap(), m);
    n
}

fn full_settings() -> Settings {
    let mut s = Settings::default();
    s.identity.serial = u32::MAX;
    while s.identity.name.push('n').is_ok() {}
    for p in s.presets.iter_mut() {
        p.name.clear();
        while p.name.push('p').is_ok() {}
    }
    s.calibration = Some(Calibration {
        homing_offset_counts: [i32::MIN; 3],
        wrist_zero_counts: [i16::MIN; 3],
        encoder_direction: [-1; 6],
        motors: [MotorConstants {
            torque_constant_nm_per_a: 1.0,
            resistance_ohm: 100.0,
        }; 3],
    });
    s
}

#[test]
fn the_largest_config_messages_fit_a_frame() {
    let s = full_settings();
    let values = [
        ConfigValue::Identity(s.identity.clone()),
        ConfigValue::Calibration(s.calibration.clone()),
        ConfigValue::Preset {
            index: 3,
            preset: s.presets[3].clone(),
        },
        ConfigValue::Stream(s.stream),
        ConfigValue::Watchdog(s.watchdog),
        ConfigValue::Status {
            store: StoreStatus::UnknownVersion(u16::MAX),
            schema_version: 2,
            may_arm: false,
            unsaved: true,
        },
    ];
    for v in values {
        round_trip_host(HostMsg::Request {
            seq: u16::MAX,
            req: Request::ConfigSet(v.clone()),
        });
        round_trip_device(DeviceMsg::Config {
            seq: u16::MAX,
            value: v,
        });
    }
    for sec in [
        ConfigSection::Status,
        ConfigSection::Preset(3),
        ConfigSection::Watchdog,
    ] {
        round_trip_host(HostMsg::Request {
            seq: 1,
            req: Request::ConfigGet(sec),
        });
    }
    let long = "k".repeat(100);
    let r = ConfigRefusal::new(&long, &long);
    assert_eq!((r.key.len(), r.reason.len()), (48, 80), "cut to fit");
    round_trip_device(DeviceMsg::ConfigRefused {
        seq: u16::MAX,
        refusal: r,
    });
}

#[test]
fn the_largest_update_messages_fit_a_frame() {
    let data = heapless::Vec::from_slice(&[0u8; UPDATE_CHUNK_LEN]).unwrap();
    let n = round_trip_host(HostMsg::Request {
        seq: u16::MAX,
        req: Request::UpdateChunk(UpdateChunk {
            offset: u32::MAX,
            crc: u32::MAX,
            data,
        }),
    });
    assert!(n <= MAX_FRAME_LEN, "{n}");
    let sig = heapless::Vec::from_slice(&[0xFFu8; 64]).unwrap();
    round_trip_host(HostMsg::Request {
        seq: 9,
        req: Request::UpdateBegin {
            len: u32::MAX,
            signature: sig,
        },
    });
    for req in [
        Request::UpdateFinish,
        Request::UpdateStatus,
        Request::Reboot,
        Request::ConfigSave,
        Request::ConfigReset,
    ] {
        round_trip_host(HostMsg::Request { seq: 2, req });
    }
    let mut version = heapless::String::new();
    while version.push('9').is_ok() {}
    round_trip_device(DeviceMsg::Update {
        seq: 3,
        status: UpdateStatus {
            phase: UpdatePhase::Receiving {
                len: u32::MAX,
                received: u32::MAX,
            },
            boot: BootStateWire::Trial,
            version,
        },
    });
    round_trip_device(DeviceMsg::UpdateRefused {
        seq: 4,
        refusal: UpdateRefusal::Truncated {
            received: 1,
            len: 2,
        },
    });
}

#[test]
fn appended_variants_keep_the_earlier_encodings() {
    // postcard encodes a variant by its index: the earlier last variants keep theirs.
    let mut buf = [0u8; 64];
    let m = DeviceMsg::FrameError {
        kind: FrameErrorKind::Crc,
        device_version: 1,
    };
    assert_eq!(
        postcard::to_slice(&m, &mut buf).unwrap()[0],
        6,
        "FrameError is still variant 6"
    );
    let r = HostMsg::Request {
        seq: 0,
        req: Request::ReleaseHand,
    };
    assert_eq!(
        postcard::to_slice(&r, &mut buf).unwrap()[..3],
        [1, 0, 13],
        "ReleaseHand is still variant 13"
    );
}
