//! Local-model switches under a pressed finger, and the watchdog.

use super::BenchConfig;
use crate::{Device, LinkError, Target};
use serde::Serialize;
use softfinger_core::Flags;
use softfinger_protocol::{HandTarget, LocalModel, StateSample, SurfaceShape};
use std::time::{Duration, Instant};

/// Per-tick force changes (every control tick streamed) with the hand pressing the surface.
#[derive(Clone, Debug, Serialize)]
pub struct ModelReport {
    /// Mean |F| while still, N (the contact is real).
    pub mean_force_n: f64,
    /// Largest |ΔF| between consecutive ticks with a still model, N (encoder quantisation and the
    /// hand's motion alone).
    pub max_step_still_n: f64,
    /// Models sent in the 1 kHz stream (plane height ±1 mm at 5 Hz).
    pub stream_updates: u32,
    /// Of those, refused by the device.
    pub stream_refused: u32,
    /// Achieved update rate, Hz.
    pub stream_rate_hz: f64,
    /// The last model sent is the one in force afterwards.
    pub last_applied: bool,
    /// Largest |ΔF| between consecutive ticks during the 1 kHz stream, N.
    pub max_step_stream_n: f64,
    /// 1 mm jumps of the plane sent.
    pub jumps: u32,
    /// The force change one jump asks for (stiffness × 1 mm), N.
    pub jump_force_n: f64,
    /// Largest |ΔF| between consecutive ticks during the jumps, N.
    pub max_step_jumps_n: f64,
    /// Ticks streamed without a gap / all ticks streamed.
    pub ticks_seen: u64,
    pub ticks_missing: u64,
}

/// The watchdog: silence, fade, latch, re-arm.
#[derive(Clone, Debug, Serialize)]
pub struct WatchdogReport {
    pub timeout_ms: u16,
    /// |F| just before the timeout, N.
    pub force_before_n: f64,
    /// From the first tick flagged COMM_TIMEOUT to the first tick with zero force, ms.
    pub fade_ms: f64,
    /// The flag stayed raised and the force zero until re-armed.
    pub latched: bool,
    /// After re-arming (and talking again) the flag cleared and stayed clear, and force is
    /// rendered again (|F| > 0.1 N at some tick; the hand moved while the force was off).
    pub recovered: bool,
}

const STIFFNESS: f32 = 2000.0;

fn plane(seq: u32, z: f64) -> LocalModel {
    LocalModel {
        seq,
        shape: SurfaceShape::Plane,
        position_m: [0.0, 0.0, z as f32],
        orientation: [1.0, 0.0, 0.0, 0.0],
        stiffness_n_per_m: STIFFNESS,
        damping_n_s_per_m: 2.0,
        mu_s: 0.8,
        mu_k: 0.6,
        spin_stiffness_nm_per_rad: 0.01,
        max_age_ms: 0,
    }
}

fn norm(f: [f32; 3]) -> f64 {
    f.iter().map(|v| (*v as f64).powi(2)).sum::<f64>().sqrt()
}

/// The samples queued now, and those arriving within 5 ms (the stream never pauses, so "until
/// the queue is empty" would not end).
fn drain(d: &Device) -> Result<Vec<StateSample>, LinkError> {
    let end = Instant::now() + Duration::from_millis(5);
    let mut v = Vec::new();
    while let Some(left) = end.checked_duration_since(Instant::now()) {
        match d.next_state(left)? {
            Some(s) => v.push(s),
            None => break,
        }
    }
    Ok(v)
}

/// Read samples until one satisfies `done` (at most 30 s of wall time).
fn wait_until(
    d: &Device,
    cfg: &BenchConfig,
    mut done: impl FnMut(&StateSample) -> bool,
) -> Result<StateSample, LinkError> {
    let end = Instant::now() + Duration::from_secs(30);
    while Instant::now() < end {
        cfg.check_stop()?;
        if let Some(s) = d.next_state(Duration::from_millis(100))? {
            if done(&s) {
                return Ok(s);
            }
        }
    }
    Err(LinkError::Timeout)
}

/// Samples up to and including the first that satisfies `done` (at most 30 s of wall time), and
/// whether one did.
fn collect_until(
    d: &Device,
    cfg: &BenchConfig,
    mut done: impl FnMut(&StateSample) -> bool,
) -> Result<(Vec<StateSample>, bool), LinkError> {
    let end = Instant::now() + Duration::from_secs(30);
    let mut v = Vec::new();
    while Instant::now() < end {
        cfg.check_stop()?;
        if let Some(s) = d.next_state(Duration::from_millis(100))? {
            let stop = done(&s);
            v.push(s);
            if stop {
                return Ok((v, true));
            }
        }
    }
    Ok((v, false))
}

/// Largest |ΔF| between consecutive ticks, ticks seen and ticks missing.
fn max_step(samples: &[StateSample]) -> (f64, u64, u64) {
    let (mut m, mut missing) = (0.0f64, 0u64);
    for w in samples.windows(2) {
        if w[1].tick == w[0].tick + 1 {
            let d = [0, 1, 2].map(|k| w[1].force_n[k] - w[0].force_n[k]);
            m = m.max(norm(d));
        } else {
            missing += w[1].tick.saturating_sub(w[0].tick + 1);
        }
    }
    (m, samples.len() as u64, missing)
}

/// Press, arm, switch models, then the watchdog.
pub fn run(
    target: &Target,
    rate: u32,
    cfg: &BenchConfig,
) -> Result<(ModelReport, WatchdogReport), LinkError> {
    let mut d = Device::connect(target)?;
    d.set_timeout(Duration::from_secs(3));
    let watchdog_before = d.info()?.watchdog_ms;
    let top = host_sim::sim::closed_loop::surface_top_z_m();
    let c = softfinger_core::device::delta::DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M;
    let _ = d.disarm();
    d.clear_faults()?;
    d.home()?;
    // The hand presses the fingertip (10 mm) 3 mm into the plane.
    d.drive_hand(HandTarget {
        position_m: [c.x, c.y, (top + 0.010 - 0.003) as f32],
        wrist_rad: [0.0; 3],
    })?;
    d.set_stream(1)?;
    // Homing against the plant first (the hand lets go meanwhile).
    wait_until(&d, cfg, |s| s.mode == softfinger_protocol::Mode::Disarmed)?;
    // Wait in device time (a loaded or unoptimised host runs the device slower than real time):
    // the hand's move (at most 2 s) is over and the handle has settled (it sags below the
    // target under gravity; the hand's grasp is a spring), then 0.5 s armed.
    let t0 = d
        .next_state(Duration::from_secs(5))?
        .ok_or(LinkError::Timeout)?
        .tick;
    let first = wait_until(&d, cfg, |s| {
        s.tick >= t0 + 5 * rate as u64 / 2 && norm(s.probe_vel_m_s) < 0.005
    })?;
    let mut seq = arm_from_above(&mut d, cfg, first.model_seq, top)?;
    // Past the pipeline's 0.5 s arming ramp.
    let armed_at = first.tick;
    wait_until(&d, cfg, |s| s.tick >= armed_at + rate as u64)?;
    drain(&d)?;

    cfg.sleep(Duration::from_secs_f64(cfg.model_s))?;
    let still = drain(&d)?;
    let mean_force_n =
        still.iter().map(|s| norm(s.force_n)).sum::<f64>() / still.len().max(1) as f64;
    let (max_step_still_n, mut seen, mut missing) = max_step(&still);

    let n = (cfg.model_s * 1000.0) as u32;
    let (mut refused, t0) = (0u32, Instant::now());
    for k in 0..n {
        cfg.check_stop()?;
        let t = k as f64 * 1e-3;
        seq = seq.wrapping_add(1);
        let z = top + 0.001 * (2.0 * std::f64::consts::PI * 5.0 * t).sin();
        if d.set_local_model(plane(seq, z)).is_err() {
            refused += 1;
        }
        let next = t0 + Duration::from_secs_f64(t + 1e-3);
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
    }
    let stream_rate_hz = n as f64 / t0.elapsed().as_secs_f64();
    let last = seq;
    let (mut streamed, last_applied) = collect_until(&d, cfg, |s| s.model_seq == last)?;
    streamed.extend(drain(&d)?);
    let (max_step_stream_n, s2, m2) = max_step(&streamed);

    let jumps = (cfg.model_s * 10.0) as u32;
    for j in 0..jumps {
        seq = seq.wrapping_add(1);
        d.set_local_model(plane(seq, top + if j % 2 == 0 { 0.001 } else { 0.0 }))?;
        cfg.sleep(Duration::from_millis(100))?;
    }
    let last = seq;
    let (mut jumped, _) = collect_until(&d, cfg, |s| s.model_seq == last)?;
    jumped.extend(drain(&d)?);
    let (max_step_jumps_n, s3, m3) = max_step(&jumped);
    seen += s2 + s3;
    missing += m2 + m3;

    let watchdog = watchdog(&mut d, cfg, rate, seq, top)?;
    let _ = d.set_watchdog_ms(watchdog_before);
    let _ = d.disarm();
    let _ = d.release_hand();
    let _ = d.set_stream(0);
    Ok((
        ModelReport {
            mean_force_n,
            max_step_still_n,
            stream_updates: n,
            stream_refused: refused,
            stream_rate_hz,
            last_applied,
            max_step_stream_n,
            jumps,
            jump_force_n: STIFFNESS as f64 * 0.001,
            max_step_jumps_n,
            ticks_seen: seen,
            ticks_missing: missing,
        },
        watchdog,
    ))
}

/// Arm with the fingertip pressed in: the device refuses to arm with the probe inside the surface
/// (the force would push it out over the arming ramp), so the plane is first put 10 mm lower (the
/// hand presses 3 mm in and the handle sags below that under gravity, 0.7 mm on the virtual
/// device), the device armed there, and the plane then moved back to `top_z_m` (the 2 ms pose
/// blend) to press.
/// Returns the sequence number of the last model sent.
fn arm_from_above(
    d: &mut Device,
    cfg: &BenchConfig,
    last_seq: u32,
    top_z_m: f64,
) -> Result<u32, LinkError> {
    let below = last_seq.wrapping_add(1);
    d.set_local_model(plane(below, top_z_m - 0.010))?;
    let seen = wait_until(d, cfg, |s| s.model_seq == below)?;
    // Past the pose blend (2 ms by default): 200 ticks, 10-20 ms of device time.
    wait_until(d, cfg, |s| s.tick >= seen.tick + 200)?;
    d.arm()?;
    let back = below.wrapping_add(1);
    d.set_local_model(plane(back, top_z_m))?;
    Ok(back)
}

fn watchdog(
    d: &mut Device,
    cfg: &BenchConfig,
    rate: u32,
    last_seq: u32,
    top_z_m: f64,
) -> Result<WatchdogReport, LinkError> {
    let timeout_ms = cfg.watchdog_ms;
    d.set_watchdog_ms(timeout_ms)?;
    // Silence: no heartbeat either.
    d.set_heartbeat(false);
    // Silence: samples until the force has been zero for the timeout again, in device time.
    let mut zero_since = None;
    let (quiet, _) = collect_until(d, cfg, |s| {
        if norm(s.force_n) != 0.0 || s.flags & Flags::COMM_TIMEOUT.0 == 0 {
            zero_since = None;
            return false;
        }
        let t0 = *zero_since.get_or_insert(s.tick);
        s.tick >= t0 + timeout_ms as u64 * rate as u64 / 1000
    })?;
    let flagged = |s: &StateSample| s.flags & Flags::COMM_TIMEOUT.0 != 0;
    let first = quiet.iter().position(flagged);
    let zero = first.and_then(|i| {
        quiet[i..]
            .iter()
            .position(|s| norm(s.force_n) == 0.0)
            .map(|j| i + j)
    });
    let force_before_n = first
        .filter(|i| *i > 0)
        .map_or(0.0, |i| norm(quiet[i - 1].force_n));
    let fade_ms = match (first, zero) {
        (Some(i), Some(j)) => (quiet[j].tick - quiet[i].tick) as f64 * 1e3 / rate as f64,
        _ => f64::NAN,
    };
    let latched = zero.is_some_and(|j| {
        quiet[j..]
            .iter()
            .all(|s| flagged(s) && norm(s.force_n) == 0.0)
    });
    // Re-arm, and keep talking (the watchdog is still on): a ping every 20 ms until force is
    // rendered again (the handle bounces after the pause, so any tick), then 100 ms more.
    d.set_heartbeat(true);
    arm_from_above(d, cfg, last_seq, top_z_m)?;
    let flagged_now = |s: &StateSample| s.flags & Flags::COMM_TIMEOUT.0 != 0;
    let rendering = |s: &StateSample| {
        !flagged_now(s) && s.mode == softfinger_protocol::Mode::Armed && norm(s.force_n) > 0.1
    };
    let end = Instant::now() + Duration::from_secs(30);
    let mut after = Vec::new();
    while Instant::now() < end && !after.iter().any(rendering) {
        cfg.check_stop()?;
        d.ping()?;
        after.extend(drain(d)?);
        std::thread::sleep(Duration::from_millis(15));
    }
    for _ in 0..5 {
        d.ping()?;
        std::thread::sleep(Duration::from_millis(20));
    }
    after.extend(drain(d)?);
    let recovered = after.iter().any(rendering) && after.last().is_some_and(|s| !flagged_now(s));
    Ok(WatchdogReport {
        timeout_ms,
        force_before_n,
        fade_ms,
        latched,
        recovered,
    })
}
