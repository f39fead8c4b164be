//! `host-sim pil --link-check`: the firmware's host link exercised on the emulated board. QEMU's
//! UART0 is a Unix socket; this side connects and sends real frames while the plant runs in lock
//! step: hello, device info, a stream request (one below the minimum divisor, then the minimum),
//! garbage, wrong-CRC, truncated and wrong-version frames, local models the pipeline refuses,
//! the settings store (`link_settings`: a save, the tick meanwhile, read back), arming before
//! homing, home, arm, a save refused while armed, then the local model and the communication
//! watchdog (`link_model`); it decodes the state frames and checks each answer, the link counters, and
//! that the link stays usable after every bad frame.
//!
//! A separate run from the scene runs: the host link owns the board's command queue (the plant's
//! operator is ignored) and the link's timing depends on the host, so this run is not compared
//! with the in-process pipeline and its instruction counts are not budgeted.

pub use super::link_report::LinkReport;

use super::link_client::{frame, Client, LinkError, ANSWER_TIMEOUT};
use super::qemu;
use super::session;
use super::PilError;
use softfinger_protocol::frame::encode_frame_with_version;
use softfinger_protocol::{
    AckResult, DeviceMsg, ErrorCode, FrameErrorKind, HostMsg, LocalModel, Mode, Request,
    StateSample, SurfaceKind, SurfaceShape, MAX_FRAME_LEN, PROTOCOL_VERSION,
};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// The socket QEMU's UART0 listens on, in the run's work directory.
pub const UART_SOCKET: &str = "uart0.sock";

/// Longest wait for homing to finish (about 5.1 s of board time in the default scene: both stops
/// and the range check), wall clock.
const HOMING_TIMEOUT: Duration = Duration::from_secs(120);

/// A ping request with sequence number `seq`.
fn ping(seq: u16) -> HostMsg {
    HostMsg::Request {
        seq,
        req: Request::Ping,
    }
}

/// A frame with its CRC broken (one body byte changed; still valid COBS).
fn wrong_crc_frame() -> Result<Vec<u8>, LinkError> {
    let mut f = frame(&ping(900))?;
    // Byte 3 is inside the body and not zero; flipping bit 6 keeps it non-zero.
    f[3] ^= 0x40;
    Ok(f)
}

/// The frame error the device answers next.
fn frame_error(c: &mut Client) -> Result<FrameErrorKind, LinkError> {
    match c.next(ANSWER_TIMEOUT)? {
        DeviceMsg::FrameError { kind, .. } => Ok(kind),
        other => Err(LinkError::unexpected("a frame error", &other)),
    }
}

/// The conversation; each step's outcome goes into `r`.
fn converse(c: &mut Client, rate_hz: u32, r: &mut LinkReport) -> Result<(), LinkError> {
    let min_divisor = handshake(c, rate_hz, r)?;
    start_stream(c, min_divisor, r)?;
    bad_frames(c, r)?;
    refused_models(c, r)?;
    super::link_settings::check_disarmed(c, rate_hz, r)?;
    let after_update = super::link_settings::check_update(c, rate_hz, r)?;
    let armed = home_and_arm(c, rate_hz, r)?;
    super::link_settings::check_armed(c, r)?;
    super::link_model::check(c, rate_hz, min_divisor, r)?;
    let states = check_state_frames(c, rate_hz, min_divisor, after_update, armed.tick, r);
    check_tick_timing(c, rate_hz, r);
    check_mode_order(c, r);
    final_counters(c, states, r)
}

/// Hello and device info; returns the device's minimum stream divisor.
fn handshake(c: &mut Client, rate_hz: u32, r: &mut LinkReport) -> Result<u16, LinkError> {
    c.send(&HostMsg::Hello {
        min_version: 1,
        max_version: PROTOCOL_VERSION,
    })?;
    let hello = c.next(ANSWER_TIMEOUT)?;
    r.check(
        "hello agrees on the version",
        hello
            == DeviceMsg::HelloReply {
                version: Some(PROTOCOL_VERSION),
                device_version: PROTOCOL_VERSION,
            },
        format!("{hello:?}"),
    );

    let seq = c.request(Request::GetInfo)?;
    match c.next(ANSWER_TIMEOUT)? {
        DeviceMsg::Info { seq: s, info } if s == seq => {
            let ok = info.control_rate_hz == rate_hz
                && !info.virtual_device
                && info.surfaces.as_slice()
                    == [
                        SurfaceKind::Plane,
                        SurfaceKind::Sphere,
                        SurfaceKind::Bowl,
                        SurfaceKind::Cylinder,
                    ]
                && info.watchdog_ms == 0
                && info.min_stream_divisor >= 1
                && !info.name.is_empty()
                && !info.firmware_version.is_empty();
            r.check("device info", ok, format!("{info:?}"));
            Ok(info.min_stream_divisor)
        }
        other => Err(LinkError::unexpected("device info", &other)),
    }
}

/// A stream one below the minimum divisor (refused), then at the minimum (started).
fn start_stream(c: &mut Client, min_divisor: u16, r: &mut LinkReport) -> Result<(), LinkError> {
    let seq = c.request(Request::SetStream {
        divisor: min_divisor - 1,
    })?;
    let too_fast = c.ack(seq)?;
    r.check(
        "a stream below the minimum divisor is refused",
        too_fast == AckResult::Err(ErrorCode::StreamTooFast),
        format!("{too_fast:?}"),
    );
    let seq = c.request(Request::SetStream {
        divisor: min_divisor,
    })?;
    let ok = c.ack(seq)?;
    r.check("the stream starts", ok == AckResult::Ok, format!("{ok:?}"));
    Ok(())
}

/// Bad frames: each answered with its kind, the link usable after each, each counted.
fn bad_frames(c: &mut Client, r: &mut LinkReport) -> Result<(), LinkError> {
    let mut kinds = Vec::new();
    c.send_raw(&[0x05, 0x11, 0x00])?;
    kinds.push(frame_error(c)?);
    c.send_raw(&wrong_crc_frame()?)?;
    kinds.push(frame_error(c)?);
    let whole = frame(&ping(901))?;
    let mut truncated = whole[..whole.len() / 2].to_vec();
    truncated.push(0);
    c.send_raw(&truncated)?;
    kinds.push(frame_error(c)?);
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = encode_frame_with_version(&ping(902), 9, &mut buf).map_err(|_| LinkError::TooLarge)?;
    c.send_raw(&buf[..n])?;
    kinds.push(frame_error(c)?);
    r.check(
        "garbage, wrong-CRC, truncated and wrong-version frames are answered with their kind",
        kinds[1] == FrameErrorKind::Crc
            && kinds[3] == FrameErrorKind::Version
            && kinds[..3].iter().all(|k| {
                matches!(
                    k,
                    FrameErrorKind::Cobs | FrameErrorKind::Crc | FrameErrorKind::Decode
                )
            }),
        format!("{kinds:?}"),
    );
    let seq = c.request(Request::Ping)?;
    let ping = c.ack(seq)?;
    r.check(
        "the link is usable after bad frames",
        ping == AckResult::Ok,
        format!("{ping:?}"),
    );
    let seq = c.request(Request::GetCounters)?;
    match c.next(ANSWER_TIMEOUT)? {
        DeviceMsg::Counters { seq: s, counters } if s == seq => r.check(
            "the device counted each bad frame by kind",
            counters.rx_errors == 4
                && counters.rx_version == 1
                && counters.rx_crc >= 1
                && counters.rx_cobs + counters.rx_crc + counters.rx_decode == 3,
            format!("{counters:?}"),
        ),
        other => return Err(LinkError::unexpected("counters", &other)),
    }
    Ok(())
}

/// Models before homing: refused by the pipeline's validation, with their codes.
fn refused_models(c: &mut Client, r: &mut LinkReport) -> Result<(), LinkError> {
    let initial_seq = super::link_model::model(0, SurfaceShape::Plane, [0.0, 0.0, -0.175]);
    let seq = c.request(Request::SetLocalModel(initial_seq))?;
    let stale = c.ack(seq)?;
    let seq = c.request(Request::SetLocalModel(LocalModel {
        seq: 1,
        orientation: [0.5, 0.0, 0.0, 0.0],
        ..initial_seq
    }))?;
    let bad_pose = c.ack(seq)?;
    r.check(
        "local models the pipeline refuses: the initial model's sequence, a non-unit quaternion",
        stale == AckResult::Err(ErrorCode::StaleSequence)
            && bad_pose == AckResult::Err(ErrorCode::InvalidValue),
        format!("{stale:?} {bad_pose:?}"),
    );
    Ok(())
}

/// Arming before homing (refused), home, arm, then a few samples while armed (the force ramps
/// in over 0.5 s); returns the first armed state.
fn home_and_arm(
    c: &mut Client,
    rate_hz: u32,
    r: &mut LinkReport,
) -> Result<StateSample, LinkError> {
    let seq = c.request(Request::Arm)?;
    let early = c.ack(seq)?;
    r.check(
        "arming before homing is refused by the pipeline",
        early == AckResult::Err(ErrorCode::WrongMode),
        format!("{early:?}"),
    );
    let seq = c.request(Request::Home)?;
    let home = c.ack(seq)?;
    r.check("home accepted", home == AckResult::Ok, format!("{home:?}"));
    let homed = c.wait_mode(Mode::Disarmed, HOMING_TIMEOUT);
    r.check(
        "homing finished (a disarmed state)",
        homed.is_ok(),
        format!("{homed:?}"),
    );
    homed?;
    // A host that arms holds the force by its link: with the watchdog off the firmware would turn
    // a 200 ms one on; this check's waits send nothing, so it arms with a long one.
    let seq = c.request(Request::SetWatchdog {
        timeout_ms: super::link_model::HOLD_WATCHDOG_MS,
    })?;
    let hold = c.ack(seq)?;
    r.check(
        "a long watchdog before arming",
        hold == AckResult::Ok,
        format!("{hold:?}"),
    );
    let seq = c.request(Request::Arm)?;
    let arm = c.ack(seq)?;
    r.check("arm accepted", arm == AckResult::Ok, format!("{arm:?}"));
    let armed = c.wait_mode(Mode::Armed, ANSWER_TIMEOUT)?;
    let ramped = armed.tick + u64::from(rate_hz) * 6 / 10;
    c.wait_for(|s| s.last().is_some_and(|x| x.tick >= ramped))?;
    Ok(armed)
}

/// Every multiple of the divisor from `from_tick` (after the update) to the last sample: no gap,
/// nothing dropped, finite values, the stream running by `armed_tick`; returns the number of
/// those states.
fn check_state_frames(
    c: &Client,
    rate_hz: u32,
    min_divisor: u16,
    from_tick: u64,
    armed_tick: u64,
    r: &mut LinkReport,
) -> usize {
    // From the end of the update on (the update blocks the link task and loses samples: its own
    // check counts them, `link_settings::check_update`).
    let since: Vec<&StateSample> = c.states.iter().filter(|s| s.tick >= from_tick).collect();
    let ticks: Vec<u64> = since.iter().map(|s| s.tick).collect();
    let gap_at: Vec<u64> = ticks
        .windows(2)
        .filter(|w| w[1] != w[0] + u64::from(min_divisor))
        .map(|w| w[0])
        .collect();
    let gaps = gap_at.len();
    let dropped = since
        .last()
        .zip(since.first())
        .map_or(0, |(b, a)| b.dropped.saturating_sub(a.dropped));
    let finite = since.iter().all(|s| {
        s.probe_m
            .iter()
            .chain(&s.probe_vel_m_s)
            .chain(&s.force_n)
            .chain(&s.contact_point_m)
            .chain(std::iter::once(&s.spin_torque_nm))
            .all(|v| v.is_finite())
    });
    let seconds = ticks
        .last()
        .zip(ticks.first())
        .map_or(0.0, |(b, a)| (b - a) as f64 / f64::from(rate_hz));
    r.check(
        "state frames after the update (homing, arming, the models): every tick on the divisor, no gap, none dropped, finite values",
        gaps == 0 && dropped == 0 && finite && ticks.first() <= Some(&armed_tick),
        format!(
            "{} states over {seconds:.2} s of board time ({:.0} Hz), ticks {:?}..{:?}, gaps {gaps}, \
             dropped {dropped}, first gaps after ticks {:?}",
            ticks.len(),
            (ticks.len().saturating_sub(1)) as f64 / seconds.max(1e-9),
            ticks.first(),
            ticks.last(),
            &gap_at[..gap_at.len().min(5)]
        ),
    );
    ticks.len()
}

/// The tick's timing, as the board measured it: a mean within the longest, both within the
/// control period (no overrun on this scene).
fn check_tick_timing(c: &Client, rate_hz: u32, r: &mut LinkReport) {
    let period_ns = 1e9 / f64::from(rate_hz);
    let timed = c.states.iter().filter(|s| s.mode == Mode::Armed).all(|s| {
        let t = s.tick_stats;
        t.mean_duration_ns > 0
            && t.mean_duration_ns <= t.max_duration_ns
            && f64::from(t.max_duration_ns) < period_ns
            && t.overruns == 0
    });
    let longest = c
        .states
        .iter()
        .map(|s| s.tick_stats.max_duration_ns)
        .max()
        .unwrap_or(0);
    r.check(
        "tick statistics in every armed sample: 0 < mean <= max < one period, no overrun",
        timed,
        format!("longest tick {longest} ns of {period_ns:.0} ns"),
    );
}

/// The modes in the order the stream showed them (repeats removed), and no force before armed.
fn check_mode_order(c: &Client, r: &mut LinkReport) {
    let mut modes: Vec<Mode> = c.states.iter().map(|s| s.mode).collect();
    modes.dedup();
    let unarmed_force = c
        .states
        .iter()
        .filter(|s| s.mode != Mode::Armed)
        .map(|s| s.force_n.iter().map(|f| f.abs()).fold(0.0f32, f32::max))
        .fold(0.0f32, f32::max);
    r.check(
        "the stream shows unhomed, homing, disarmed, armed in order, and no force before armed",
        modes == [Mode::Unhomed, Mode::Homing, Mode::Disarmed, Mode::Armed] && unarmed_force == 0.0,
        format!("{modes:?}, largest force before armed {unarmed_force} N"),
    );
}

/// The device's counters at the end: no new errors, at least `states` frames sent.
fn final_counters(c: &mut Client, states: usize, r: &mut LinkReport) -> Result<(), LinkError> {
    let seq = c.request(Request::GetCounters)?;
    match c.next(ANSWER_TIMEOUT)? {
        DeviceMsg::Counters { seq: s, counters } if s == seq => {
            r.check(
                "final counters: errors unchanged, frames sent",
                counters.rx_errors == 4 && counters.tx_frames >= states as u32,
                format!("{counters:?}"),
            );
            r.counters = Some(counters);
        }
        other => return Err(LinkError::unexpected("counters", &other)),
    }
    Ok(())
}

/// Run the board with its host link on a socket in `dir` and the conversation against it.
pub fn run(
    qemu_exe: &str,
    elf: &Path,
    dir: &Path,
    limit: Duration,
    plant: crate::sim::plant::Plant,
    s: &session::Settings,
) -> Result<(session::Trace, LinkReport), PilError> {
    let sock = dir.join(UART_SOCKET);
    let serial = format!("unix:{},server=on,wait=off", sock.display());
    let mut emu = qemu::Emulator::start_with_serial(qemu_exe, elf, dir, limit, &serial)?;
    let stop = AtomicBool::new(false);
    let rate_hz = s.rate_hz();
    let (trace, report) = std::thread::scope(|scope| {
        let client = scope.spawn(|| {
            let mut report = LinkReport::default();
            let result = Client::connect(&sock).and_then(|mut c| {
                let r = converse(&mut c, rate_hz, &mut report);
                report.states = c.states.len() as u32;
                report.rx_errors_here = c.decoder.errors().total();
                r
            });
            if let Err(e) = result {
                report.check("conversation completed", false, e.to_string());
            }
            stop.store(true, Ordering::Relaxed);
            report
        });
        let trace = session::run_with_link(&mut emu, plant, s, true, &stop);
        // The board stopped (or failed): make sure the client does not wait on.
        stop.store(true, Ordering::Relaxed);
        (trace, client.join())
    });
    let status = emu.finish();
    let trace = trace?;
    let report = report.map_err(|_| PilError::ClientPanicked)?;
    status?;
    Ok((trace, report))
}
