//! Round trip of every message kind: each host and device message variant (every request, every
//! error code, every frame-error kind, every surface shape) is encoded, fed byte by byte to a
//! decoder and must come back equal. Coverage is checked with exhaustive `match`es, so a new
//! variant does not compile here until it is added to the list.

use softfinger_mcu_bench::check::Checker;
use softfinger_mcu_bench::link::{feed, frame_of, largest_command, state_sample, typical_command};
use softfinger_protocol::config::{ConfigRefusal, ConfigSection, ConfigValue, StoreStatus};
use softfinger_protocol::info::Text;
use softfinger_protocol::update::{
    BootStateWire, UpdateChunk, UpdatePhase, UpdateRefusal, UpdateStatus,
};
use softfinger_protocol::{
    AckResult, ContactParamsWire, DeviceInfo, DeviceMsg, DeviceStatus, ErrorCode, FieldRange,
    FrameDecoder, FrameErrorKind, HandTarget, HostMsg, LinkCounters, LocalModel, Mode, Request,
    SurfaceKind, SurfaceShape, PROTOCOL_VERSION,
};

const PARAMS: ContactParamsWire = ContactParamsWire {
    fingertip_radius_m: 0.01,
    normal_stiffness: 2_000.0,
    normal_damping: 2.5,
    tangential_stiffness: 1_500.0,
    tangential_damping: 1.5,
    mu_s: 0.8,
    mu_k: 0.6,
    spin_stiffness: 0.01,
    max_force_n: 8.0,
};

const ERROR_CODES: [ErrorCode; 8] = [
    ErrorCode::Unsupported,
    ErrorCode::WrongMode,
    ErrorCode::Faulted,
    ErrorCode::InvalidValue,
    ErrorCode::UnsupportedSurface,
    ErrorCode::StaleSequence,
    ErrorCode::StreamTooFast,
    ErrorCode::Busy,
];

const FRAME_ERRORS: [FrameErrorKind; 5] = [
    FrameErrorKind::Cobs,
    FrameErrorKind::Crc,
    FrameErrorKind::Version,
    FrameErrorKind::Decode,
    FrameErrorKind::Oversized,
];

fn request_index(r: &Request) -> u32 {
    match r {
        Request::GetInfo => 0,
        Request::GetCounters => 1,
        Request::GetContactParams => 2,
        Request::Ping => 3,
        Request::Home => 4,
        Request::Arm => 5,
        Request::Disarm => 6,
        Request::ClearFaults => 7,
        Request::SetContactParams(_) => 8,
        Request::SetLocalModel(m) => match m.shape {
            SurfaceShape::Plane => 9,
            SurfaceShape::Sphere { .. } => 10,
            SurfaceShape::Bowl { .. } => 11,
            SurfaceShape::Cylinder { .. } => 12,
        },
        Request::SetStream { .. } => 13,
        Request::SetWatchdog { .. } => 14,
        Request::DriveHand(_) => 15,
        Request::ReleaseHand => 16,
        Request::GetStatus => 17,
        Request::ConfigGet(_) => 18,
        Request::ConfigSet(_) => 19,
        Request::ConfigSave => 20,
        Request::ConfigReset => 21,
        Request::UpdateBegin { .. } => 22,
        Request::UpdateChunk(_) => 23,
        Request::UpdateFinish => 24,
        Request::UpdateStatus => 25,
        Request::Reboot => 26,
    }
}
const REQUEST_KINDS: u32 = 27;

fn device_index(m: &DeviceMsg) -> u32 {
    match m {
        DeviceMsg::HelloReply { .. } => 0,
        DeviceMsg::Ack { result, .. } => match result {
            AckResult::Ok => 1,
            AckResult::Err(e) => 2 + error_index(*e),
        },
        DeviceMsg::Info { .. } => 10,
        DeviceMsg::Counters { .. } => 11,
        DeviceMsg::ContactParams { .. } => 12,
        DeviceMsg::State(_) => 13,
        DeviceMsg::FrameError { kind, .. } => 14 + frame_error_index(*kind),
        DeviceMsg::Status { .. } => 19,
        DeviceMsg::Rejected { .. } => 20,
        DeviceMsg::Config { .. } => 21,
        DeviceMsg::ConfigRefused { .. } => 22,
        DeviceMsg::Update { .. } => 23,
        DeviceMsg::UpdateRefused { .. } => 24,
    }
}
const DEVICE_KINDS: u32 = 25;

fn error_index(e: ErrorCode) -> u32 {
    match e {
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

fn frame_error_index(k: FrameErrorKind) -> u32 {
    match k {
        FrameErrorKind::Cobs => 0,
        FrameErrorKind::Crc => 1,
        FrameErrorKind::Version => 2,
        FrameErrorKind::Decode => 3,
        FrameErrorKind::Oversized => 4,
    }
}

/// Encode, decode byte by byte, compare.
fn round_trip<T>(msg: &T) -> bool
where
    T: serde::Serialize + serde::de::DeserializeOwned + PartialEq + Clone,
{
    let Some(f) = frame_of(msg) else {
        return false;
    };
    let one_delimiter = f.wire().iter().filter(|b| **b == 0).count() == 1;
    let mut dec = FrameDecoder::new();
    one_delimiter && feed::<T>(&mut dec, f.wire()) == Some(Ok(msg.clone())) && dec.frames() == 1
}

fn plane_model() -> LocalModel {
    LocalModel {
        seq: 3,
        shape: SurfaceShape::Plane,
        position_m: [0.0, 0.0, 0.15],
        orientation: [1.0, 0.0, 0.0, 0.0],
        stiffness_n_per_m: 2_000.0,
        damping_n_s_per_m: 2.5,
        mu_s: 0.8,
        mu_k: 0.6,
        spin_stiffness_nm_per_rad: 0.01,
        max_age_ms: 0,
    }
}

pub fn round_trips(c: &mut Checker) {
    host_messages(c);
    device_messages(c);
}

fn host_messages(c: &mut Checker) {
    let requests = [
        Request::GetInfo,
        Request::GetCounters,
        Request::GetContactParams,
        Request::Ping,
        Request::Home,
        Request::Arm,
        Request::Disarm,
        Request::ClearFaults,
        Request::SetContactParams(PARAMS),
        Request::SetLocalModel(plane_model()),
        Request::SetLocalModel(LocalModel {
            seq: 4,
            shape: SurfaceShape::Bowl { radius_m: 0.05 },
            ..plane_model()
        }),
        Request::SetLocalModel(LocalModel {
            seq: 5,
            shape: SurfaceShape::Cylinder { radius_m: 0.03 },
            ..plane_model()
        }),
        Request::SetWatchdog { timeout_ms: 250 },
        Request::DriveHand(HandTarget {
            position_m: [0.01, -0.02, 0.15],
            wrist_rad: [0.1, -0.2, 0.3],
        }),
        Request::ReleaseHand,
        Request::GetStatus,
        Request::ConfigGet(ConfigSection::Stream),
        Request::ConfigSet(ConfigValue::Status {
            store: StoreStatus::Absent,
            schema_version: 2,
            may_arm: false,
            unsaved: true,
        }),
        Request::ConfigSave,
        Request::ConfigReset,
        Request::UpdateBegin {
            len: 100_000,
            signature: heapless::Vec::from_slice(&[0xA5; 64]).unwrap_or_default(),
        },
        Request::UpdateChunk(UpdateChunk {
            offset: 128,
            crc: 0x1234_5678,
            data: heapless::Vec::from_slice(&[0x5A; 128]).unwrap_or_default(),
        }),
        Request::UpdateFinish,
        Request::UpdateStatus,
        Request::Reboot,
    ];
    let mut seen = 0u32;
    let extra = [typical_command(), largest_command()];
    for (i, req) in requests.into_iter().enumerate() {
        seen |= 1 << request_index(&req);
        let msg = HostMsg::Request {
            seq: i as u16 * 4099,
            req,
        };
        c.ok_at("round trip: host request", i as f32, round_trip(&msg));
    }
    for msg in extra {
        if let HostMsg::Request { req, .. } = &msg {
            seen |= 1 << request_index(req);
        }
        c.ok("round trip: sample command", round_trip(&msg));
    }
    c.ok(
        "round trip: every request kind",
        seen == (1 << REQUEST_KINDS) - 1,
    );
    let hello = HostMsg::Hello {
        min_version: 1,
        max_version: 255,
    };
    c.ok("round trip: hello", round_trip(&hello));
}

fn device_messages(c: &mut Checker) {
    let mut name: Text<24> = Text::new();
    let mut version: Text<16> = Text::new();
    let mut surfaces = heapless::Vec::new();
    let filled = name.push_str("softfinger bench é").is_ok()
        && version.push_str("0.1.0").is_ok()
        && surfaces.push(SurfaceKind::Plane).is_ok()
        && surfaces.push(SurfaceKind::Sphere).is_ok()
        && surfaces.push(SurfaceKind::Bowl).is_ok()
        && surfaces.push(SurfaceKind::Cylinder).is_ok();
    let mut reset_cause = heapless::String::new();
    let filled = filled && reset_cause.push_str("watchdog").is_ok();
    c.ok("round trip: info fields fit", filled);
    let info = DeviceInfo {
        protocol_version: PROTOCOL_VERSION,
        name,
        firmware_version: version,
        virtual_device: false,
        control_rate_hz: 10_000,
        max_force_n: 8.0,
        min_stream_divisor: 10,
        surfaces,
        watchdog_ms: 100,
        settings_flags: 0x41,
        reset_cause,
    };
    let counters = LinkCounters {
        rx_frames: 1_000_000,
        rx_errors: 5,
        rx_cobs: 1,
        rx_crc: 1,
        rx_version: 1,
        rx_decode: 1,
        rx_oversized: 1,
        tx_frames: 70_000,
        tx_dropped: 3,
        connections: 2,
    };
    let mut msgs: heapless::Vec<DeviceMsg, 32> = heapless::Vec::new();
    let mut all = msgs
        .push(DeviceMsg::HelloReply {
            version: Some(PROTOCOL_VERSION),
            device_version: PROTOCOL_VERSION,
        })
        .is_ok();
    all &= msgs
        .push(DeviceMsg::Ack {
            seq: 1,
            result: AckResult::Ok,
        })
        .is_ok();
    for (i, e) in ERROR_CODES.into_iter().enumerate() {
        let seq = 2 + i as u16;
        all &= msgs
            .push(DeviceMsg::Ack {
                seq,
                result: AckResult::Err(e),
            })
            .is_ok();
    }
    all &= msgs.push(DeviceMsg::Info { seq: 20, info }).is_ok();
    all &= msgs.push(DeviceMsg::Counters { seq: 21, counters }).is_ok();
    all &= msgs
        .push(DeviceMsg::ContactParams {
            seq: 22,
            params: PARAMS,
        })
        .is_ok();
    all &= msgs.push(DeviceMsg::State(state_sample())).is_ok();
    for kind in FRAME_ERRORS {
        all &= msgs
            .push(DeviceMsg::FrameError {
                kind,
                device_version: PROTOCOL_VERSION,
            })
            .is_ok();
    }
    let status = DeviceStatus {
        tick: 1 << 40,
        mode: Mode::Armed,
        flags: 1 << 24,
        latched: 1 << 10,
        model: plane_model(),
    };
    all &= msgs.push(DeviceMsg::Status { seq: 23, status }).is_ok();
    all &= msgs
        .push(DeviceMsg::Rejected {
            seq: 24,
            code: ErrorCode::InvalidValue,
            field: FieldRange::new("normal_stiffness", 0.0, false, 1.0e7),
        })
        .is_ok();
    all &= msgs
        .push(DeviceMsg::Config {
            seq: 25,
            value: ConfigValue::Status {
                store: StoreStatus::Corrupt,
                schema_version: 2,
                may_arm: false,
                unsaved: false,
            },
        })
        .is_ok();
    all &= msgs
        .push(DeviceMsg::ConfigRefused {
            seq: 26,
            refusal: ConfigRefusal::new("presets.2.friction", "disarm first"),
        })
        .is_ok();
    all &= msgs
        .push(DeviceMsg::Update {
            seq: 27,
            status: UpdateStatus {
                phase: UpdatePhase::Receiving {
                    len: 100_000,
                    received: 4_096,
                },
                boot: BootStateWire::Trial,
                version: heapless::String::new(),
            },
        })
        .is_ok();
    all &= msgs
        .push(DeviceMsg::UpdateRefused {
            seq: 28,
            refusal: UpdateRefusal::Armed,
        })
        .is_ok();
    c.ok("round trip: device message list fits", all);
    let mut seen = 0u32;
    for (i, msg) in msgs.iter().enumerate() {
        seen |= 1 << device_index(msg);
        c.ok_at("round trip: device message", i as f32, round_trip(msg));
    }
    c.ok(
        "round trip: every device kind",
        seen == (1 << DEVICE_KINDS) - 1,
    );
    let refused = DeviceMsg::HelloReply {
        version: None,
        device_version: PROTOCOL_VERSION,
    };
    c.ok("round trip: refused hello", round_trip(&refused));
}
