//! The firmware's host link (`softfinger_app::link`, the firmware's no_std, board-independent
//! app, `firmware/app`) compiled for the host: real frames in, the device's frames out, the
//! command queue and the tick's outcomes played by the test.

use softfinger_app::board::CommandSource;
use softfinger_app::persist::{DeviceStore, Persistence};
use softfinger_app::tick::Applied;
use softfinger_app::{link, stream, stream_point};

use link::info::{min_stream_divisor, InfoSource};
use link::session::{CommandSink, LinkConfig, LinkSession};
use link::state::{StateBuilder, TickExtender};
use link::tx::TxRing;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::pipeline::{CheckedCommand, Command, CommandError, CommandKey};
use softfinger_core::omega_like::OMEGA_LIKE;
use softfinger_core::{Flags, Vec3};
use softfinger_protocol::frame::encode_frame_with_version;
use softfinger_protocol::{
    encode_frame, AckResult, ContactParamsWire, ContactState, DeviceMsg, ErrorCode, FrameDecoder,
    FrameErrorKind, HostMsg, LocalModel, Mode, RenderedTick, Request, StateSample, SurfaceKind,
    SurfaceShape, MAX_FRAME_LEN, PROTOCOL_VERSION,
};
use stream::MAX_STREAM_HZ;
use stream_point::StreamPoint;

const RATE_HZ: u32 = 10_000;
const MIN_DIVISOR: u16 = 5;
/// The tick timer's clock of the test sessions (the STM32's 170 MHz).
const TIMER_HZ: u32 = 170_000_000;

/// The tick's command queue, as a list of the commands it was given, checked (`capacity`: how
/// many it takes).
#[derive(Default)]
struct Queue {
    commands: Vec<Command>,
    capacity: usize,
}

impl CommandSink for Queue {
    fn try_submit(&mut self, command: CheckedCommand) -> bool {
        if self.commands.len() >= self.capacity {
            return false;
        }
        self.commands.push(command.command());
        true
    }
}

/// The tick's outcome of a host command: by its key, as the tick reports it.
fn host(c: Command) -> Applied {
    Applied::Link(c.key())
}

fn queue() -> Queue {
    Queue {
        commands: Vec::new(),
        capacity: 4,
    }
}

fn link_config() -> LinkConfig {
    LinkConfig {
        info: InfoSource {
            name: OMEGA_LIKE.name,
            firmware_version: "0.1.0",
            control_rate_hz: RATE_HZ,
            max_force_n: ContactParams::DEFAULT.max_force_n,
            min_stream_divisor: MIN_DIVISOR,
            watchdog_ms: 0,
            reset_cause: "power-on",
        },
        timer_clock_hz: TIMER_HZ,
        contact: ContactParams::DEFAULT,
    }
}

fn session<const TX: usize>() -> LinkSession<TX> {
    LinkSession::new(&link_config())
}

fn frame(msg: &HostMsg) -> Vec<u8> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = encode_frame(msg, &mut buf).unwrap();
    buf[..n].to_vec()
}

fn request(seq: u16, req: Request) -> Vec<u8> {
    frame(&HostMsg::Request { seq, req })
}

fn feed<const TX: usize, S: Persistence>(s: &mut LinkSession<TX, S>, q: &mut Queue, bytes: &[u8]) {
    for &b in bytes {
        s.receive(b, q);
    }
}

/// Ask for the state stream at `divisor` (0: stop it), as request `seq`.
fn set_stream<const TX: usize>(s: &mut LinkSession<TX>, q: &mut Queue, seq: u16, divisor: u16) {
    feed(s, q, &request(seq, Request::SetStream { divisor }));
}

/// The state samples among `msgs`, in order.
fn states(msgs: &[DeviceMsg]) -> Vec<StateSample> {
    msgs.iter()
        .filter_map(|m| match m {
            DeviceMsg::State(st) => Some(*st),
            _ => None,
        })
        .collect()
}

/// Every frame the device queued for the host, decoded.
fn sent<const TX: usize, S: Persistence>(s: &mut LinkSession<TX, S>) -> Vec<DeviceMsg> {
    let mut dec = FrameDecoder::new();
    let mut out = Vec::new();
    while let Some(b) = s.tx().pop() {
        if let Some(m) = dec.push::<DeviceMsg>(b) {
            out.push(m.expect("the device's frames decode"));
        }
    }
    assert_eq!(dec.errors().total(), 0);
    out
}

/// A stream point at `tick`, in rolling contact.
fn point(tick: u32) -> StreamPoint {
    StreamPoint {
        tick,
        rendered: RenderedTick {
            mode: Mode::Armed,
            contact: ContactState::Rolling,
            flags: Flags::OUTPUT_LIMITED,
            probe_m: Vec3::new(0.01, -0.02, 0.13),
            probe_vel_m_s: Vec3::new(0.1, 0.0, -0.05),
            force_n: Vec3::new(0.1, -2.5, 12.0),
            spin_torque_nm: 1.5e-3,
            contact_point_m: Vec3::new(0.01, -0.02, 0.12),
            model_seq: 7,
        },
        max_tick_counts: 3400,
        sum_tick_counts: 5 * 3000,
        ticks: 5,
        overruns: 2,
    }
}

#[test]
fn hello_agrees_on_the_version_or_says_which_it_speaks() {
    let (mut s, mut q) = (session::<1024>(), queue());
    feed(
        &mut s,
        &mut q,
        &frame(&HostMsg::Hello {
            min_version: 1,
            max_version: 3,
        }),
    );
    feed(
        &mut s,
        &mut q,
        &frame(&HostMsg::Hello {
            min_version: 2,
            max_version: 3,
        }),
    );
    assert_eq!(
        sent(&mut s),
        vec![
            DeviceMsg::HelloReply {
                version: Some(PROTOCOL_VERSION),
                device_version: 1
            },
            DeviceMsg::HelloReply {
                version: None,
                device_version: 1
            },
        ]
    );
}

#[test]
fn device_info_names_the_device_rate_limits_and_surfaces() {
    let (mut s, mut q) = (session::<1024>(), queue());
    feed(&mut s, &mut q, &request(7, Request::GetInfo));
    let msgs = sent(&mut s);
    let [DeviceMsg::Info { seq: 7, info }] = msgs.as_slice() else {
        panic!("{msgs:?}");
    };
    assert_eq!(info.name.as_str(), OMEGA_LIKE.name);
    assert_eq!(info.firmware_version.as_str(), "0.1.0");
    assert_eq!(info.control_rate_hz, RATE_HZ);
    assert_eq!(info.min_stream_divisor, MIN_DIVISOR);
    assert_eq!(info.max_force_n, ContactParams::DEFAULT.max_force_n);
    assert_eq!(
        info.surfaces.as_slice(),
        &[
            SurfaceKind::Plane,
            SurfaceKind::Sphere,
            SurfaceKind::Bowl,
            SurfaceKind::Cylinder
        ]
    );
    assert_eq!(info.watchdog_ms, 0, "off at power-up (bench mode)");
    assert!(!info.virtual_device);
    assert!(q.commands.is_empty());
}

#[test]
fn a_command_is_acknowledged_with_the_ticks_outcome_not_before() {
    let (mut s, mut q) = (session::<1024>(), queue());
    feed(&mut s, &mut q, &request(1, Request::Home));
    feed(&mut s, &mut q, &request(2, Request::Arm));
    assert_eq!(q.commands, vec![Command::Home, Command::Arm]);
    assert!(
        sent(&mut s).is_empty(),
        "no answer before the tick applied it"
    );
    assert_eq!(s.pending(), 2);
    s.outcome(&host(Command::Home), Ok(()));
    s.outcome(&host(Command::Arm), Err(CommandError::NotHomed));
    assert_eq!(
        sent(&mut s),
        vec![
            DeviceMsg::Ack {
                seq: 1,
                result: AckResult::Ok
            },
            DeviceMsg::Ack {
                seq: 2,
                result: AckResult::Err(ErrorCode::WrongMode)
            },
        ]
    );
    assert_eq!(s.pending(), 0);
}

#[test]
fn another_sources_outcome_answers_nothing() {
    let (mut s, mut q) = (session::<1024>(), queue());
    feed(&mut s, &mut q, &request(5, Request::Disarm));
    // The operator's button pressed Home meanwhile.
    s.outcome(&Applied::Operator(CommandKey::Home), Ok(()));
    assert!(sent(&mut s).is_empty());
    s.outcome(&host(Command::Disarm), Ok(()));
    assert_eq!(
        sent(&mut s),
        vec![DeviceMsg::Ack {
            seq: 5,
            result: AckResult::Ok
        }]
    );
}

#[test]
fn a_full_command_queue_is_answered_busy_and_nothing_is_queued() {
    let (mut s, mut q) = (session::<1024>(), queue());
    q.capacity = 1;
    feed(&mut s, &mut q, &request(1, Request::Home));
    feed(&mut s, &mut q, &request(2, Request::Arm));
    assert_eq!(q.commands, vec![Command::Home]);
    assert_eq!(
        sent(&mut s),
        vec![DeviceMsg::Ack {
            seq: 2,
            result: AckResult::Err(ErrorCode::Busy)
        }]
    );
    // At most MAX_PENDING (4) waiting for outcomes, even when the queue would take more: 4 taken,
    // the 5th busy.
    let (mut s, mut q) = (session::<1024>(), queue());
    q.capacity = 10;
    for seq in 1..=5 {
        feed(&mut s, &mut q, &request(seq, Request::Disarm));
    }
    assert_eq!(q.commands.len(), 4);
    assert_eq!(
        sent(&mut s),
        vec![DeviceMsg::Ack {
            seq: 5,
            result: AckResult::Err(ErrorCode::Busy)
        }]
    );
}

fn sphere_model(seq: u32) -> LocalModel {
    LocalModel {
        seq,
        shape: SurfaceShape::Sphere { radius_m: 0.03 },
        position_m: [0.01, -0.02, -0.19],
        orientation: [0.0, 1.0, 0.0, 0.0],
        stiffness_n_per_m: 900.0,
        damping_n_s_per_m: 1.5,
        mu_s: 0.7,
        mu_k: 0.4,
        spin_stiffness_nm_per_rad: 0.02,
        max_age_ms: 250,
    }
}

#[test]
fn local_model_and_watchdog_go_to_the_pipeline_the_simulated_hand_is_unsupported() {
    let (mut s, mut q) = (session::<1024>(), queue());
    let model = sphere_model(1);
    feed(&mut s, &mut q, &request(1, Request::SetLocalModel(model)));
    feed(
        &mut s,
        &mut q,
        &request(2, Request::SetWatchdog { timeout_ms: 150 }),
    );
    feed(&mut s, &mut q, &request(3, Request::ReleaseHand));
    // The protocol's conversion (`LocalModel::spec`, tested in the protocol crate).
    let want = model.spec();
    assert_eq!(
        q.commands,
        vec![
            Command::SetLocalModel(want),
            Command::SetWatchdog { timeout_s: 0.15 }
        ]
    );
    assert_eq!(
        sent(&mut s),
        vec![DeviceMsg::Ack {
            seq: 3,
            result: AckResult::Err(ErrorCode::Unsupported)
        }],
        "only the hand is answered before the tick applies the others"
    );
    s.outcome(
        &host(Command::SetLocalModel(want)),
        Err(CommandError::InvalidModel(
            softfinger_core::control::local_model::ModelError::StaleSequence,
        )),
    );
    s.outcome(&host(Command::SetWatchdog { timeout_s: 0.15 }), Ok(()));
    assert_eq!(
        sent(&mut s),
        vec![
            DeviceMsg::Ack {
                seq: 1,
                result: AckResult::Err(ErrorCode::StaleSequence)
            },
            DeviceMsg::Ack {
                seq: 2,
                result: AckResult::Ok
            },
        ]
    );
    // The device info reports the watchdog the tick accepted.
    feed(&mut s, &mut q, &request(4, Request::GetInfo));
    let msgs = sent(&mut s);
    let [DeviceMsg::Info { info, .. }] = msgs.as_slice() else {
        panic!("{msgs:?}");
    };
    assert_eq!(info.watchdog_ms, 150);
}

#[test]
fn a_refused_watchdog_leaves_the_reported_one() {
    let (mut s, mut q) = (session::<1024>(), queue());
    feed(
        &mut s,
        &mut q,
        &request(1, Request::SetWatchdog { timeout_ms: 65_000 }),
    );
    assert_eq!(q.commands, vec![Command::SetWatchdog { timeout_s: 65.0 }]);
    s.outcome(
        &host(Command::SetWatchdog { timeout_s: 65.0 }),
        Err(CommandError::InvalidParams(
            softfinger_core::contact::params::ParamError::OutOfRange("watchdog_timeout_s"),
        )),
    );
    feed(&mut s, &mut q, &request(2, Request::GetInfo));
    let msgs = sent(&mut s);
    let [DeviceMsg::Ack { seq: 1, result }, DeviceMsg::Info { info, .. }] = msgs.as_slice() else {
        panic!("{msgs:?}");
    };
    assert_eq!(*result, AckResult::Err(ErrorCode::InvalidValue));
    assert_eq!(info.watchdog_ms, 0);
}

/// Every shape and field maps as host-sim's virtual device maps it.
/// The communication watchdog's food: true for every frame that decodes (link-level messages
/// included), false for every byte that does not end one and for a rejected frame.
#[test]
fn every_valid_frame_and_only_a_valid_frame_feeds_the_watchdog() {
    let (mut s, mut q) = (session::<1024>(), queue());
    let count = |s: &mut LinkSession<1024>, q: &mut Queue, bytes: &[u8]| {
        bytes.iter().filter(|&&b| s.receive(b, q)).count()
    };
    let hello = frame(&HostMsg::Hello {
        min_version: 1,
        max_version: PROTOCOL_VERSION,
    });
    assert_eq!(count(&mut s, &mut q, &hello), 1);
    assert_eq!(count(&mut s, &mut q, &request(1, Request::GetCounters)), 1);
    assert_eq!(count(&mut s, &mut q, &request(2, Request::Ping)), 1);
    assert_eq!(count(&mut s, &mut q, &request(3, Request::Home)), 1);
    let mut bad = request(4, Request::Ping);
    bad[3] ^= 0x40;
    assert_eq!(count(&mut s, &mut q, &bad), 0, "a wrong CRC is no food");
    assert_eq!(count(&mut s, &mut q, &[0x05, 0x11, 0x00]), 0, "garbage");
    // An empty frame (a resynchronising delimiter) is no frame.
    assert_eq!(count(&mut s, &mut q, &[0]), 0);
    assert_eq!(count(&mut s, &mut q, &request(5, Request::Ping)), 1);
}

#[test]
fn contact_parameters_change_only_when_the_tick_accepts_them() {
    let (mut s, mut q) = (session::<1024>(), queue());
    let mut wire = ContactParamsWire::of(&ContactParams::DEFAULT);
    wire.normal_stiffness = 1234.0;
    feed(&mut s, &mut q, &request(1, Request::SetContactParams(wire)));
    let [Command::SetContactParams(p)] = q.commands.as_slice() else {
        panic!("{:?}", q.commands);
    };
    let p = *p;
    assert_eq!(
        p,
        ContactParams {
            normal_stiffness: 1234.0,
            ..ContactParams::DEFAULT
        }
    );
    // Still the old ones until the outcome.
    feed(&mut s, &mut q, &request(2, Request::GetContactParams));
    s.outcome(&host(Command::SetContactParams(p)), Ok(()));
    feed(&mut s, &mut q, &request(3, Request::GetContactParams));
    let msgs = sent(&mut s);
    assert_eq!(
        reported_stiffness(&msgs),
        vec![ContactParams::DEFAULT.normal_stiffness, 1234.0]
    );
    assert!(msgs.contains(&DeviceMsg::Ack {
        seq: 1,
        result: AckResult::Ok
    }));
}

#[test]
fn the_tick_reports_a_command_by_its_key_and_an_operator_preset_whole() {
    let checked = |c: Command| c.check().unwrap_or(CheckedCommand::Home);
    let preset = ContactParams {
        normal_stiffness: 5000.0,
        ..ContactParams::DEFAULT
    };
    let params = checked(Command::SetContactParams(preset));
    assert!(matches!(
        Applied::of(CommandSource::Operator, &params),
        Applied::OperatorParams(p) if p == preset
    ));
    assert!(matches!(
        Applied::of(CommandSource::Host, &params),
        Applied::Link(CommandKey::SetContactParams)
    ));
    assert!(matches!(
        Applied::of(CommandSource::Operator, &CheckedCommand::Arm),
        Applied::Operator(CommandKey::Arm)
    ));
    assert!(matches!(
        Applied::of(CommandSource::Host, &CheckedCommand::Disarm),
        Applied::Link(CommandKey::Disarm)
    ));
}

#[test]
fn an_operator_preset_changes_the_reported_parameters_only_when_the_tick_accepts_it() {
    let (mut s, mut q) = (session::<1024>(), queue());
    let preset = ContactParams {
        normal_stiffness: 5000.0,
        ..ContactParams::DEFAULT
    };
    s.outcome(
        &Applied::OperatorParams(preset),
        Err(CommandError::InvalidParams(
            softfinger_core::contact::params::ParamError::NotFinite("mu_s"),
        )),
    );
    feed(&mut s, &mut q, &request(1, Request::GetContactParams));
    s.outcome(&Applied::OperatorParams(preset), Ok(()));
    feed(&mut s, &mut q, &request(2, Request::GetContactParams));
    assert_eq!(
        reported_stiffness(&sent(&mut s)),
        vec![ContactParams::DEFAULT.normal_stiffness, 5000.0]
    );
}

/// The normal stiffness of each contact-parameter report among `msgs`, in order.
fn reported_stiffness(msgs: &[DeviceMsg]) -> Vec<f32> {
    msgs.iter()
        .filter_map(|m| match m {
            DeviceMsg::ContactParams { params, .. } => Some(params.normal_stiffness),
            _ => None,
        })
        .collect()
}

#[test]
fn bad_frames_are_counted_by_kind_answered_and_the_link_stays_usable() {
    let (mut s, mut q) = (session::<4096>(), queue());
    // Garbage: a 0x00-delimited run that is not COBS (a code byte pointing past the end).
    feed(&mut s, &mut q, &[0x05, 0x11, 0x00]);
    // Wrong CRC: a valid frame with one body byte changed (COBS re-encoded by flipping a
    // non-zero byte to another non-zero value keeps the framing).
    let mut bad_crc = request(1, Request::Ping);
    bad_crc[3] ^= 0x40;
    assert_ne!(bad_crc[3], 0);
    feed(&mut s, &mut q, &bad_crc);
    // Truncated: the first half of a frame, then the delimiter.
    let good = request(2, Request::Ping);
    let mut truncated = good[..good.len() / 2].to_vec();
    truncated.push(0);
    feed(&mut s, &mut q, &truncated);
    // Another protocol version.
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = encode_frame_with_version(
        &HostMsg::Request {
            seq: 3,
            req: Request::Ping,
        },
        9,
        &mut buf,
    )
    .unwrap();
    feed(&mut s, &mut q, &buf[..n]);
    // Oversized: more bytes than a frame holds before the delimiter.
    let mut long = vec![0x01; MAX_FRAME_LEN + 10];
    long.push(0);
    feed(&mut s, &mut q, &long);
    // Still usable.
    feed(&mut s, &mut q, &request(4, Request::Ping));
    feed(&mut s, &mut q, &request(5, Request::GetCounters));
    let msgs = sent(&mut s);
    let kinds: Vec<FrameErrorKind> = msgs
        .iter()
        .filter_map(|m| match m {
            DeviceMsg::FrameError {
                kind,
                device_version: 1,
            } => Some(*kind),
            _ => None,
        })
        .collect();
    assert_eq!(kinds.len(), 5, "{msgs:?}");
    assert!(kinds.contains(&FrameErrorKind::Crc));
    assert!(kinds.contains(&FrameErrorKind::Version));
    assert!(kinds.contains(&FrameErrorKind::Oversized));
    assert!(msgs.contains(&DeviceMsg::Ack {
        seq: 4,
        result: AckResult::Ok
    }));
    let Some(DeviceMsg::Counters { seq: 5, counters }) = msgs.last() else {
        panic!("{msgs:?}");
    };
    assert_eq!(counters.rx_errors, 5);
    assert_eq!(counters.rx_version, 1);
    assert_eq!(counters.rx_oversized, 1);
    assert_eq!(counters.rx_cobs + counters.rx_crc + counters.rx_decode, 3);
    assert_eq!(counters.rx_frames, 2, "the ping and the counters request");
    assert_eq!(s.counters().rx_errors, 5);
}

#[test]
fn the_stream_follows_the_divisor_and_refuses_one_below_the_minimum() {
    let (mut s, mut q) = (session::<4096>(), queue());
    set_stream(&mut s, &mut q, 1, MIN_DIVISOR - 1);
    set_stream(&mut s, &mut q, 2, 2 * MIN_DIVISOR);
    // The tick streams the multiples of the divisor: 0, 10, 20.
    for i in 0..3 {
        s.stream(&point(i * 2 * u32::from(MIN_DIVISOR)));
    }
    let msgs = sent(&mut s);
    assert_eq!(
        &msgs[..2],
        &[
            DeviceMsg::Ack {
                seq: 1,
                result: AckResult::Err(ErrorCode::StreamTooFast)
            },
            DeviceMsg::Ack {
                seq: 2,
                result: AckResult::Ok
            },
        ]
    );
    let ticks: Vec<u64> = states(&msgs).iter().map(|st| st.tick).collect();
    assert_eq!(ticks, vec![0, 10, 20]);
    assert_eq!(s.stream_divisor(), 2 * MIN_DIVISOR, "handed to the tick");
    let DeviceMsg::State(st) = &msgs[2] else {
        panic!()
    };
    assert_eq!(st.mode, Mode::Armed);
    assert_eq!(st.contact, ContactState::Rolling);
    assert_eq!(st.flags, Flags::OUTPUT_LIMITED.0);
    assert_eq!(st.force_n, [0.1, -2.5, 12.0]);
    assert_eq!(st.dropped, 0);
    // Divisor 0 stops it.
    set_stream(&mut s, &mut q, 3, 0);
    s.stream(&point(30));
    assert_eq!(
        sent(&mut s),
        vec![DeviceMsg::Ack {
            seq: 3,
            result: AckResult::Ok
        }]
    );
    assert_eq!(s.stream_divisor(), 0);
}

#[test]
fn a_sample_carries_every_field_of_the_point_timing_in_ns() {
    let mut b = StateBuilder::new(TIMER_HZ);
    let st = b.sample(&point(40));
    let p = point(40).rendered;
    assert_eq!(st.tick, 40);
    assert_eq!(st.probe_m, p.probe_m.to_array());
    assert_eq!(st.probe_vel_m_s, p.probe_vel_m_s.to_array());
    assert_eq!(st.force_n, p.force_n.to_array());
    assert_eq!(st.spin_torque_nm, p.spin_torque_nm);
    assert_eq!(st.contact, ContactState::Rolling);
    assert_eq!(st.contact_point_m, p.contact_point_m.to_array());
    assert_eq!(st.flags, Flags::OUTPUT_LIMITED.0);
    assert_eq!(st.mode, Mode::Armed);
    assert_eq!(st.model_seq, 7);
    // 3400 counts at 170 MHz = 20 000 ns; the mean 3000 counts = 17 647.06 ns (truncated).
    assert_eq!(st.tick_stats.max_duration_ns, 20_000);
    assert_eq!(st.tick_stats.mean_duration_ns, 17_647);
    assert_eq!(st.tick_stats.overruns, 2);
    // No tick since the previous point: a mean of 0, not a division by zero.
    let idle = b.sample(&StreamPoint {
        ticks: 0,
        sum_tick_counts: 0,
        ..point(45)
    });
    assert_eq!(idle.tick_stats.mean_duration_ns, 0);
}

/// The tick's side (`firmware/src/stream.rs`), the only test that sets the divisor (a static).
#[test]
fn the_tick_streams_the_multiples_of_the_divisor_with_the_timing_between() {
    use stream::{set_divisor, StreamTap};
    let mut tap = StreamTap::default();
    let run = |tap: &mut StreamTap, ticks: u32| {
        let mut points = Vec::new();
        for i in 0..ticks {
            if tap.due() {
                let mut p = StreamPoint::default();
                tap.stamp(&mut p);
                points.push(p);
            }
            // Tick durations 100, 101, ... counts; every seventh one overran.
            tap.account(100 + i, i % 7 == 6);
        }
        points
    };
    // No divisor: nothing, whatever the tick.
    set_divisor(0);
    assert!(run(&mut tap, 12).is_empty());
    // Divisor 5 from tick 12: the next multiple is 15.
    set_divisor(5);
    let points = run(&mut tap, 13);
    let ticks: Vec<u32> = points.iter().map(|p| p.tick).collect();
    assert_eq!(ticks, vec![15, 20]);
    // Between 15 and 20 the tick accounted the durations of ticks 15..=19 of this run's
    // numbering: i = 3..=7, 103..=107 counts; i = 6 overran (the 2nd overrun since start-up,
    // after the first run's i = 6).
    let p = &points[1];
    assert_eq!((p.ticks, p.max_tick_counts), (5, 107));
    assert_eq!(p.sum_tick_counts, 103 + 104 + 105 + 106 + 107);
    assert_eq!(p.overruns, 2);
    // The first point holds everything since start-up: 12 + 3 ticks.
    assert_eq!(points[0].ticks, 15);
    set_divisor(0);
    assert!(run(&mut tap, 10).is_empty());
}

#[test]
fn points_the_tick_could_not_queue_are_counted_as_dropped() {
    let (mut s, mut q) = (session::<4096>(), queue());
    set_stream(&mut s, &mut q, 1, MIN_DIVISOR);
    let d = u32::from(MIN_DIVISOR);
    // Points 0, 5, then 20: the tick lost 10 and 15.
    for t in [0, d, 4 * d] {
        s.stream(&point(t));
    }
    let dropped: Vec<u32> = states(&sent(&mut s)).iter().map(|st| st.dropped).collect();
    assert_eq!(dropped, vec![0, 0, 2]);
}

#[test]
fn a_host_that_stops_reading_loses_samples_counted_never_blocks() {
    // Room for about two state frames.
    let (mut s, mut q) = (session::<200>(), queue());
    set_stream(&mut s, &mut q, 1, MIN_DIVISOR);
    assert_eq!(sent(&mut s).len(), 1);
    let d = u32::from(MIN_DIVISOR);
    for i in 0..10 {
        s.stream(&point(i * d));
    }
    let got = states(&sent(&mut s));
    assert!(!got.is_empty() && got.len() < 10, "{}", got.len());
    let lost = 10 - got.len() as u32;
    assert_eq!(s.counters().tx_dropped, lost);
    // The host reads again: the next sample reports the samples it lost.
    s.stream(&point(10 * d));
    let Some(DeviceMsg::State(next)) = sent(&mut s).pop() else {
        panic!()
    };
    assert_eq!(next.dropped, lost);
}

#[test]
fn ticks_extend_past_the_32_bit_wrap() {
    let mut t = TickExtender::default();
    assert_eq!(t.extend(u32::MAX - 99), u64::from(u32::MAX - 99));
    assert_eq!(t.extend(0), 1 << 32);
    assert_eq!(t.extend(100), (1 << 32) + 100);
}

#[test]
fn the_minimum_divisor_keeps_the_stream_at_or_below_its_fastest_rate() {
    assert_eq!(MAX_STREAM_HZ, 2_000);
    assert_eq!(min_stream_divisor(10_000), 5);
    assert_eq!(min_stream_divisor(20_000), 10);
    // Just above a multiple: the next divisor (10 001 / 5 would be 2 000.2 Hz).
    assert_eq!(min_stream_divisor(10_001), 6);
    assert_eq!(min_stream_divisor(2_000), 1);
    assert_eq!(min_stream_divisor(1_000), 1);
    assert_eq!(min_stream_divisor(0), 1);
}

#[test]
fn the_transmit_ring_takes_whole_frames_or_nothing() {
    let mut r = TxRing::<8>::new();
    assert!(r.push_frame(&[1, 2, 3, 4, 5]));
    assert!(!r.push_frame(&[6, 7, 8, 9]), "4 bytes into 3 free");
    assert_eq!(r.len(), 5);
    assert!(r.push_frame(&[6, 7, 8]), "3 bytes into 3 free");
    let mut out = [0u8; 16];
    assert_eq!(r.pop_into(&mut out), 8);
    assert_eq!(&out[..8], &[1, 2, 3, 4, 5, 6, 7, 8]);
    assert!(r.is_empty());
}

// ---- The device's flash behind the link (softfinger_app::persist), on the G474 flash model ----

use softfinger_protocol::config::{ConfigSection, ConfigValue, StoreStatus};
use softfinger_store::boot::{FLAG_ABSENT, FLAG_CORRUPT, FLAG_DEFAULTS, FLAG_NO_CALIBRATION};
use softfinger_store::flash_model::{G474Flash, PAGE_SIZE};
use softfinger_update::layout::{G474, G474_FLASH_LEN};

type Flash = G474Flash;

fn blank_flash() -> Flash {
    G474Flash::new(G474_FLASH_LEN as usize / PAGE_SIZE)
}

/// A session on a board with `flash` (booted: the store loaded).
fn stored_session(flash: Flash) -> LinkSession<1024, DeviceStore<Flash>> {
    LinkSession::with_store(&link_config(), DeviceStore::boot(flash, G474, "0.1.0"))
}

/// One request's answers.
fn ask<S: Persistence>(
    s: &mut LinkSession<1024, S>,
    q: &mut Queue,
    seq: u16,
    req: Request,
) -> Vec<DeviceMsg> {
    feed(s, q, &request(seq, req));
    sent(s)
}

fn info_of(msgs: &[DeviceMsg]) -> softfinger_protocol::DeviceInfo {
    match msgs {
        [DeviceMsg::Info { info, .. }] => info.clone(),
        other => panic!("expected the device info, got {other:?}"),
    }
}

#[test]
fn settings_saved_over_the_link_are_read_at_the_next_boot() {
    let mut q = queue();
    let mut s = stored_session(blank_flash());
    let info = info_of(&ask(&mut s, &mut q, 1, Request::GetInfo));
    assert_eq!(
        info.settings_flags,
        FLAG_DEFAULTS | FLAG_ABSENT | FLAG_NO_CALIBRATION
    );
    assert_eq!(info.reset_cause.as_str(), "power-on");
    let mut identity = softfinger_store::Settings::default().identity;
    identity.name = heapless::String::try_from("bench-a").unwrap();
    let r = ask(
        &mut s,
        &mut q,
        2,
        Request::ConfigSet(ConfigValue::Identity(identity.clone())),
    );
    assert!(
        matches!(
            r[..],
            [DeviceMsg::Ack {
                seq: 2,
                result: AckResult::Ok
            }]
        ),
        "{r:?}"
    );
    let r = ask(&mut s, &mut q, 3, Request::ConfigSave);
    assert!(
        matches!(
            r[..],
            [DeviceMsg::Ack {
                seq: 3,
                result: AckResult::Ok
            }]
        ),
        "{r:?}"
    );
    // A power cycle: a new store on the same flash.
    let flash = s.into_store().into_flash();
    let mut s = stored_session(flash);
    let r = ask(
        &mut s,
        &mut q,
        4,
        Request::ConfigGet(ConfigSection::Identity),
    );
    assert!(
        matches!(&r[..], [DeviceMsg::Config { value: ConfigValue::Identity(i), .. }] if *i == identity),
        "{r:?}"
    );
    let r = ask(&mut s, &mut q, 5, Request::ConfigGet(ConfigSection::Status));
    assert!(
        matches!(
            &r[..],
            [DeviceMsg::Config {
                value: ConfigValue::Status {
                    store: StoreStatus::Read,
                    unsaved: false,
                    may_arm: true,
                    ..
                },
                ..
            }]
        ),
        "{r:?}"
    );
    // Read, but no calibration stored yet; the device calls itself by the saved name.
    let info = info_of(&ask(&mut s, &mut q, 6, Request::GetInfo));
    assert_eq!(info.settings_flags, FLAG_NO_CALIBRATION);
    assert_eq!(info.name.as_str(), "bench-a");
    // None of it went to the tick.
    assert!(q.commands.is_empty());
}

/// The answer is one `Ack` of `Ok`.
fn assert_acked(r: &[DeviceMsg]) {
    assert!(
        matches!(
            r,
            [DeviceMsg::Ack {
                result: AckResult::Ok,
                ..
            }]
        ),
        "{r:?}"
    );
}

/// The stored watchdog and stream defaults act from the next boot: the session starts its
/// stream at `stream.rate_hz` and the pipeline's host watchdog is `watchdog.timeout_ms`.
#[test]
fn stored_watchdog_and_stream_defaults_apply_at_the_next_boot() {
    use softfinger_app::boot_defaults::BootDefaults;
    use softfinger_store::schema::{StreamDefaults, WatchdogDefaults};
    let mut q = queue();
    let mut s = stored_session(blank_flash());
    assert_eq!(s.stream_divisor(), 0);
    for (seq, value) in [
        (1, ConfigValue::Stream(StreamDefaults { rate_hz: 1000 })),
        (
            2,
            ConfigValue::Watchdog(WatchdogDefaults { timeout_ms: 50 }),
        ),
    ] {
        let r = ask(&mut s, &mut q, seq, Request::ConfigSet(value));
        assert_acked(&r);
    }
    // Set, not yet booted with: nothing changes now.
    assert_eq!(s.stream_divisor(), 0);
    assert_acked(&ask(&mut s, &mut q, 3, Request::ConfigSave));
    assert_eq!(s.stream_divisor(), 0);
    // A power cycle.
    let flash = s.into_store().into_flash();
    let s = stored_session(flash);
    assert_eq!(s.stream_divisor(), (RATE_HZ / 1000) as u16);
    let defaults = s.into_store().boot_defaults();
    assert_eq!(
        defaults,
        BootDefaults {
            host_watchdog_s: Some(0.05),
            stream_rate_hz: 1000
        }
    );
    let mut pipeline =
        softfinger_app::tick::TickPipeline::new(softfinger_app::config::pipeline_config())
            .expect("the firmware's configuration");
    assert_eq!(pipeline.host_watchdog_s(), 0.2);
    assert_eq!(defaults.apply(&mut pipeline), Ok(()));
    assert_eq!(pipeline.host_watchdog_s(), 0.05);
    // A board without a store: the built-in ones.
    assert_eq!(session::<1024>().stream_divisor(), 0);
}

#[test]
fn a_store_it_cannot_read_refuses_to_arm_until_reset() {
    let mut flash = blank_flash();
    {
        // A record that fails its CRC.
        let mut st = softfinger_store::Store::new(&mut flash, G474.store.clone()).unwrap();
        let mut rec = vec![0xFFu8, 0x7F];
        rec.extend_from_slice(&[1, 2, 3, 4, 5, 6]);
        embassy_futures::block_on(st.save_raw_record(&rec)).unwrap();
    }
    let mut q = queue();
    let mut s = stored_session(flash);
    let info = info_of(&ask(&mut s, &mut q, 1, Request::GetInfo));
    assert_ne!(
        info.settings_flags & FLAG_CORRUPT,
        0,
        "{:#x}",
        info.settings_flags
    );
    let r = ask(&mut s, &mut q, 2, Request::Arm);
    assert!(
        matches!(
            r[..],
            [DeviceMsg::Ack {
                seq: 2,
                result: AckResult::Err(ErrorCode::WrongMode)
            }]
        ),
        "{r:?}"
    );
    assert!(
        q.commands.is_empty(),
        "refused before the tick: {:?}",
        q.commands
    );
    // Erased: the defaults, and arming goes to the tick again.
    let r = ask(&mut s, &mut q, 3, Request::ConfigReset);
    assert!(
        matches!(
            r[..],
            [DeviceMsg::Ack {
                seq: 3,
                result: AckResult::Ok
            }]
        ),
        "{r:?}"
    );
    assert!(
        ask(&mut s, &mut q, 4, Request::Arm).is_empty(),
        "acknowledged by the tick's outcome"
    );
    assert_eq!(q.commands, vec![Command::Arm]);
}

#[test]
fn a_reboot_is_answered_then_requested_once() {
    let mut q = queue();
    let mut s = stored_session(blank_flash());
    assert!(!s.take_reset_request());
    let r = ask(&mut s, &mut q, 9, Request::Reboot);
    assert!(
        matches!(
            r[..],
            [DeviceMsg::Ack {
                seq: 9,
                result: AckResult::Ok
            }]
        ),
        "{r:?}"
    );
    assert!(s.take_reset_request());
    assert!(!s.take_reset_request());
}

#[test]
fn a_board_without_a_store_refuses_settings_naming_why() {
    let mut q = queue();
    let mut s = session::<1024>();
    let r = ask(&mut s, &mut q, 1, Request::ConfigSave);
    match &r[..] {
        [DeviceMsg::ConfigRefused { seq: 1, refusal }] => {
            assert_eq!(refusal.key.as_str(), "store");
            assert!(refusal.reason.contains("no settings store"), "{refusal:?}");
        }
        other => panic!("{other:?}"),
    }
    let r = ask(&mut s, &mut q, 2, Request::Reboot);
    assert!(
        matches!(
            r[..],
            [DeviceMsg::Ack {
                seq: 2,
                result: AckResult::Err(ErrorCode::Unsupported)
            }]
        ),
        "{r:?}"
    );
}

// ---- The scripted application session of the processor-in-the-loop run ----

use softfinger_app::scripted_app::{
    ScriptedApp, AMPLITUDE_M, PARAMS_EVERY, SOFT_STIFFNESS_FRACTION,
};

#[test]
fn the_scripted_application_moves_the_plane_within_its_amplitude_and_changes_params_every_hundredth(
) {
    let mut app = ScriptedApp::new(ContactParams::DEFAULT);
    let top = softfinger_app::config::INITIAL_PLANE_TOP_M.z;
    let (mut last_seq, mut lowest, mut highest) = (0, f32::MAX, f32::MIN);
    for n in 1..=1000u32 {
        match app.next_command() {
            Command::SetContactParams(p) => {
                assert_eq!(n % PARAMS_EVERY, 0, "update {n}");
                let soft = (n / PARAMS_EVERY) % 2 == 1;
                let want = ContactParams::DEFAULT.normal_stiffness
                    * if soft { SOFT_STIFFNESS_FRACTION } else { 1.0 };
                assert_eq!(p.normal_stiffness, want);
                assert!(p.validate().is_ok());
            }
            Command::SetLocalModel(m) => {
                assert_ne!(n % PARAMS_EVERY, 0, "update {n}");
                assert!(m.seq > last_seq);
                last_seq = m.seq;
                let dz = m.pose.position_m.z - top;
                lowest = lowest.min(dz);
                highest = highest.max(dz);
            }
            other => panic!("{other:?}"),
        }
    }
    // The whole wave (its turning points fall on parameter updates: one step short), no further.
    for extreme in [highest, -lowest] {
        assert!(
            (0.98 * AMPLITUDE_M..=AMPLITUDE_M).contains(&extreme),
            "{lowest} {highest}"
        );
    }
    assert_eq!(ScriptedApp::update_period_ticks(20_000), 20);
    assert_eq!(ScriptedApp::stream_divisor(10_000), 5);
}
