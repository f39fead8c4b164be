//! The local-model part of `host-sim pil --link-check`, once the board is armed: the firmware
//! renders the model the application sends, and its communication watchdog lets go of the force
//! when the application falls silent. Everything is judged from the board's state stream (the
//! tick's probe position, filtered velocity and force, the flags).
//!
//! 1. A sphere out of the probe's reach: after the blend, no contact and exactly zero force.
//! 2. A plane raised to press 2 mm into the fingertip where the probe is: after the blend, every
//!    sample is in contact, and its normal force is the plane's spring and damper on the probe
//!    state the stream shows, k·(top + r − z) − b·v_z (the local model's passivity stage observes
//!    only, so nothing acts on top).
//! 3. A 50 ms watchdog: while pings arrive back to back for 150 ms no timeout; then silence:
//!    COMM_TIMEOUT latches no earlier than 50 ms after the last state seen before it, stays latched with the mode Armed, and the force is
//!    exactly zero from the fade's length (20 ms) after the first flagged sample; turning the
//!    watchdog off and re-arming clears it.

use super::link_client::{Client, LinkError};
use super::link_report::LinkReport;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::local_model::RendererConfig;
use softfinger_core::Flags;
use softfinger_protocol::{
    AckResult, ContactState, ErrorCode, LocalModel, Mode, Request, StateSample, SurfaceShape,
};

/// The default contact material and fingertip (the firmware's, `config::pipeline_config`).
const CONTACT: ContactParams = ContactParams::DEFAULT;

/// Radius of the out-of-reach sphere, m.
const SPHERE_R_M: f32 = 0.05;

/// Gap between the out-of-reach sphere and the fingertip where the probe was, m: three times the
/// scene's 10 mm press depth, the farthest the hand's target goes past a surface.
const SPHERE_GAP_M: f32 = 0.030;

/// How far the raised plane presses into the fingertip where the probe was, m (4 N at the
/// default 2000 N/m, within the 12 N force limit).
const PLANE_PRESS_M: f32 = 0.002;

/// Largest difference between the stream's normal force and the plane's spring and damper on
/// the streamed probe position and filtered velocity, k·(top + r − z) − b·v_z, on every sample in
/// contact after the raised plane's blend, N. The stream carries the tick's own probe state, and
/// the local model's passivity stage observes only, so the law holds to rounding: measured
/// 1.14e-5 N over 41 samples (scripts/pil --link-check, 10 kHz); the bound is about 3x that. Had
/// the firmware kept the old model (the out-of-reach sphere: no force) the difference would be
/// about k·2 mm = 4 N; with the passivity damper on, up to about 3.5 N.
const PLANE_FORCE_TOL_N: f32 = 3.5e-5;

/// Largest distance of the streamed contact point from the plane's top under the probe, m (the
/// fingertip rolls on a plane, so the contact point stays under the probe up to f32 rounding of
/// positions near 0.16 m). Measured 2.98e-8 and 4.47e-8 m in two runs of scripts/pil
/// --link-check (10 kHz); the bound is about 3x the larger.
const CONTACT_POINT_TOL_M: f32 = 1.5e-7;

/// The communication watchdog's timeout for the test, ms.
const WATCHDOG_MS: u16 = 50;

/// The watchdog the check arms with, ms: long enough for its waits without pings (the firmware
/// turns a 200 ms watchdog on for a host that arms with it off, `Pipeline::link_command`).
pub(super) const HOLD_WATCHDOG_MS: u16 = 5_000;

/// After the first sample flagged COMM_TIMEOUT the force is exactly zero from this long on, s:
/// the watchdog latched at or before that sample, and its gain reaches 0 within the fade
/// (`LocalModelEnvironment::new`: 20 ms, the firmware's). The passivity damper stands aside while the
/// watchdog holds the force down (`Controller::compute`); before it did, this run measured
/// 0.8-2.2 N for 140 ms after the timeout.
fn zero_after_timeout_s() -> f32 {
    use softfinger_core::control::local_model::{LocalModelEnvironment, LocalModelSpec, ModelPose};
    let any = LocalModelSpec::plane(0, ModelPose::at(softfinger_core::Vec3::ZERO), &CONTACT);
    LocalModelEnvironment::new(any).watchdog_fade_s
}

/// Samples looked at after each model switch.
const SAMPLES: usize = 40;

/// A model of the default material, never stale.
pub(super) fn model(seq: u32, shape: SurfaceShape, position_m: [f32; 3]) -> LocalModel {
    LocalModel {
        seq,
        shape,
        position_m,
        orientation: [1.0, 0.0, 0.0, 0.0],
        stiffness_n_per_m: CONTACT.normal_stiffness,
        damping_n_s_per_m: CONTACT.normal_damping,
        mu_s: CONTACT.mu_s,
        mu_k: CONTACT.mu_k,
        spin_stiffness_nm_per_rad: CONTACT.spin_stiffness,
        max_age_ms: 0,
    }
}

/// Send `m`; the ack, then `SAMPLES` states from `settle_ticks` after the first state that
/// followed the ack and names `m` (`model_seq`: the renderer names the incoming model once its
/// weight reaches ½, so its blend is over within `settle_ticks` of that state). The first state
/// after the ack alone is not a bound: the link task can send the ack before stream points the
/// tick queued before it applied the model (host-link commands go through a queue of their own
/// that the tick applies), and a run here started the force check 3 ticks inside the blend
/// (10.2 N of 12 N, weight 0.85).
fn switch_to(
    c: &mut Client,
    m: LocalModel,
    settle_ticks: u64,
) -> Result<(AckResult, Vec<StateSample>), LinkError> {
    let seq = c.request(Request::SetLocalModel(m))?;
    let ack = c.ack(seq)?;
    let seen = c.states.len();
    let first = if ack == AckResult::Ok {
        c.wait_for(|s| s.iter().skip(seen).any(|x| x.model_seq == m.seq))?;
        c.states
            .iter()
            .skip(seen)
            .find(|x| x.model_seq == m.seq)
            .map(|x| x.tick)
            .ok_or(LinkError::NoState)?
    } else {
        c.wait_states(seen + 1)?[seen].tick
    };
    let from = first + settle_ticks;
    c.wait_for(|s| s.iter().filter(|x| x.tick >= from).count() >= SAMPLES)?;
    let after: Vec<StateSample> = c
        .states
        .iter()
        .filter(|x| x.tick >= from)
        .copied()
        .collect();
    Ok((ack, after))
}

fn largest_force(s: &[StateSample]) -> f32 {
    s.iter()
        .flat_map(|x| x.force_n)
        .map(f32::abs)
        .fold(0.0, f32::max)
}

fn dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The checks above; `rate_hz`: the control rate, `divisor`: the stream's.
pub(super) fn check(
    c: &mut Client,
    rate_hz: u32,
    divisor: u16,
    r: &mut LinkReport,
) -> Result<(), LinkError> {
    let stream = u64::from(divisor);
    // The blend of a switch, then one stream period.
    let settle = ticks_at(rate_hz, RendererConfig::DEFAULT.blend_s) + stream;
    sphere_out_of_reach(c, settle, r)?;
    raised_plane(c, settle, r)?;
    let ack = watchdog_fed(c, rate_hz, stream, r)?;
    watchdog_silence(c, rate_hz, ack, r)?;
    watchdog_off_and_rearm(c, r)
}

/// Control ticks in `s` seconds at `rate_hz`, rounded up.
fn ticks_at(rate_hz: u32, s: f32) -> u64 {
    (s * rate_hz as f32).ceil() as u64
}

/// The state flags COMM_TIMEOUT.
fn timed_out(s: &StateSample) -> bool {
    s.flags & Flags::COMM_TIMEOUT.0 != 0
}

/// Check 1: a sphere out of the probe's reach renders no contact and zero force.
fn sphere_out_of_reach(c: &mut Client, settle: u64, r: &mut LinkReport) -> Result<(), LinkError> {
    let radius = CONTACT.fingertip_radius_m;
    let p = c.states.last().ok_or(LinkError::NoState)?.probe_m;
    let centre = [p[0], p[1], p[2] - (SPHERE_R_M + radius + SPHERE_GAP_M)];
    let sphere = model(
        1,
        SurfaceShape::Sphere {
            radius_m: SPHERE_R_M,
        },
        centre,
    );
    let (ack, after) = switch_to(c, sphere, settle)?;
    let nearest = after
        .iter()
        .map(|s| dist(s.probe_m, centre) - SPHERE_R_M - radius)
        .fold(f32::INFINITY, f32::min);
    r.check(
        "a sphere out of reach: no contact, zero force after the blend",
        ack == AckResult::Ok
            && nearest > 0.0
            && after
                .iter()
                .all(|s| s.force_n == [0.0; 3] && s.contact == ContactState::Broken),
        format!(
            "{ack:?}; {} samples, nearest gap {:.4} m, largest force {} N",
            after.len(),
            nearest,
            largest_force(&after)
        ),
    );

    Ok(())
}

/// Check 2: a plane pressing into the fingertip is named by the stream, its contact point under
/// the probe, and its force the spring-damper law on the streamed probe state.
fn raised_plane(c: &mut Client, settle: u64, r: &mut LinkReport) -> Result<(), LinkError> {
    let radius = CONTACT.fingertip_radius_m;
    let z = c.states.last().ok_or(LinkError::NoState)?.probe_m[2];
    let top = z - radius + PLANE_PRESS_M;
    let plane = model(2, SurfaceShape::Plane, [0.0, 0.0, top]);
    let (ack, after) = switch_to(c, plane, settle)?;
    let (k, b) = (CONTACT.normal_stiffness, CONTACT.normal_damping);
    // The spring-damper law on the stream's own probe position and filtered velocity, within the
    // force limit.
    let law = |s: &StateSample| {
        (k * (top + radius - s.probe_m[2]) - b * s.probe_vel_m_s[2]).clamp(0.0, CONTACT.max_force_n)
    };
    let errors: Vec<f32> = after.iter().map(|s| s.force_n[2] - law(s)).collect();
    let worst = errors.iter().fold(0.0f32, |m, e| m.max(e.abs()));
    let pressing = after
        .iter()
        .all(|s| top + radius - s.probe_m[2] > 0.0 && s.contact != ContactState::Broken);
    // The model in force is the plane (sequence 2), and the contact point is on its top under
    // the probe.
    let on_plane = after.iter().all(|s| {
        s.model_seq == 2
            && (s.contact_point_m[2] - top).abs() <= CONTACT_POINT_TOL_M
            && (s.contact_point_m[0] - s.probe_m[0]).abs() <= CONTACT_POINT_TOL_M
            && (s.contact_point_m[1] - s.probe_m[1]).abs() <= CONTACT_POINT_TOL_M
    });
    let off = after.iter().fold(0.0f32, |m, s| {
        m.max((s.contact_point_m[2] - top).abs())
            .max((s.contact_point_m[0] - s.probe_m[0]).abs())
            .max((s.contact_point_m[1] - s.probe_m[1]).abs())
    });
    r.check(
        "a raised plane: the stream names it and puts the contact point on its top under the probe",
        on_plane && !after.is_empty(),
        format!(
            "largest offset {off:.3e} m (bound {CONTACT_POINT_TOL_M}); (model_seq, contact point, \
             probe) first {:?}",
            after
                .first()
                .map(|s| (s.model_seq, s.contact_point_m, s.probe_m))
        ),
    );
    r.check(
        "a raised plane: in contact; the normal force is the plane's spring and damper on the streamed probe state",
        ack == AckResult::Ok && pressing && !after.is_empty() && worst <= PLANE_FORCE_TOL_N,
        format!(
            "{ack:?}; {} samples in contact: {pressing}; largest |Fz - min(k·pen - b·vz, F_max)| {worst:.3e} N \
             (bound {PLANE_FORCE_TOL_N}); (tick, Fz, error, vz) {:?}",
            after.len(),
            after
                .iter()
                .zip(&errors)
                .map(|(s, e)| (s.tick, s.force_n[2], *e, s.probe_vel_m_s[2]))
                .collect::<Vec<_>>()
        ),
    );

    Ok(())
}

/// Check 3, first part: set the watchdog, then pings back to back must keep it from firing;
/// returns the watchdog request's acknowledgement.
fn watchdog_fed(
    c: &mut Client,
    rate_hz: u32,
    stream: u64,
    r: &mut LinkReport,
) -> Result<AckResult, LinkError> {
    let seq = c.request(Request::SetWatchdog {
        timeout_ms: WATCHDOG_MS,
    })?;
    let ack = c.ack(seq)?;
    // Pings back to back (each answered) for three timeouts of board time: every valid frame
    // feeds the watchdog, so it must not fire.
    let fed_from = c.states.last().ok_or(LinkError::NoState)?.tick + stream;
    let fed_until = fed_from + 3 * ticks_at(rate_hz, f32::from(WATCHDOG_MS) * 1e-3);
    let mut pings = 0u32;
    while c.states.last().is_none_or(|s| s.tick < fed_until) {
        let seq = c.request(Request::Ping)?;
        if c.ack(seq)? != AckResult::Ok {
            return Err(LinkError::PingRefused);
        }
        pings += 1;
    }
    let fed: Vec<&StateSample> = c
        .states
        .iter()
        .filter(|s| (fed_from..fed_until).contains(&s.tick))
        .collect();
    r.check(
        "link activity feeds the watchdog: no timeout while pings arrive",
        !fed.is_empty() && !fed.iter().any(|s| timed_out(s)),
        format!(
            "{pings} pings; {} samples from tick {fed_from} to {fed_until}, flagged: {}",
            fed.len(),
            fed.iter().filter(|s| timed_out(s)).count()
        ),
    );
    Ok(ack)
}

/// Check 3, second part: silence latches COMM_TIMEOUT after the timeout and fades the force to
/// zero; `ack`: the watchdog request's acknowledgement.
fn watchdog_silence(
    c: &mut Client,
    rate_hz: u32,
    ack: AckResult,
    r: &mut LinkReport,
) -> Result<(), LinkError> {
    // Silence from here: wait for the timeout, then for the fade to end.
    let before = c.states.last().ok_or(LinkError::NoState)?.tick;
    c.wait_for(|s| s.iter().any(timed_out))?;
    let t1 = c
        .states
        .iter()
        .find(|s| timed_out(s))
        .map(|s| s.tick)
        .ok_or(LinkError::NoTimeout)?;
    let faded = t1 + ticks_at(rate_hz, zero_after_timeout_s());
    c.wait_for(|s| s.iter().filter(|x| x.tick >= faded).count() >= 3)?;
    let later: Vec<&StateSample> = c.states.iter().filter(|s| s.tick >= t1).collect();
    let prior = c
        .states
        .iter()
        .rev()
        .find(|s| s.tick < t1)
        .map(|s| s.force_n);
    let pressing_before = prior.is_some_and(|f| f[2] > 0.0);
    let latched = later.iter().all(|s| timed_out(s) && s.mode == Mode::Armed);
    let zero = later
        .iter()
        .filter(|s| s.tick >= faded)
        .all(|s| s.force_n == [0.0; 3]);
    let timeout_ticks = ticks_at(rate_hz, f32::from(WATCHDOG_MS) * 1e-3);
    r.check(
        "silence: COMM_TIMEOUT latches after the timeout, the force goes to zero and stays there",
        ack == AckResult::Ok && t1 >= before + timeout_ticks && pressing_before && latched && zero,
        format!(
            "{ack:?}; last state before the request at tick {before}, timeout flagged at {t1} \
             (>= {}), force before {prior:?}, latched and armed after: {latched}, zero from \
             tick {faded}: {zero}; (tick, F, flags) {:?}",
            before + timeout_ticks,
            later
                .iter()
                .map(|s| (s.tick, s.force_n, s.flags))
                .collect::<Vec<_>>()
        ),
    );

    Ok(())
}

/// Check 3, last part: the watchdog cannot be turned off while the host keeps the device armed;
/// a long one, re-armed: the latch clears and the force returns.
fn watchdog_off_and_rearm(c: &mut Client, r: &mut LinkReport) -> Result<(), LinkError> {
    // Watchdog off (itself a message): refused while this host holds the device armed
    // (`CommandError::WatchdogRequired`, on the wire InvalidValue).
    let seq = c.request(Request::SetWatchdog { timeout_ms: 0 })?;
    let off = c.ack(seq)?;
    let seq = c.request(Request::SetWatchdog {
        timeout_ms: HOLD_WATCHDOG_MS,
    })?;
    let long = c.ack(seq)?;
    let seq = c.request(Request::Arm)?;
    let rearm = c.ack(seq)?;
    let seen = c.states.len();
    c.wait_for(|s| {
        s[seen..]
            .iter()
            .any(|x| !timed_out(x) && x.force_n[2] > 0.0)
    })?;
    r.check(
        "watchdog off refused while host-armed; a long one and re-armed: the latch clears, the force returns",
        off == AckResult::Err(ErrorCode::InvalidValue)
            && long == AckResult::Ok
            && rearm == AckResult::Ok,
        format!("{off:?} {long:?} {rearm:?}"),
    );
    Ok(())
}

/// Bounds of the checks above that do not depend on a run.
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_raised_plane_tells_the_new_model_from_the_old() {
        // Keeping the old plane would be PLANE_PRESS_M deeper or shallower: k·2 mm = 4 N, far
        // outside the bound; the raised plane's own force stays under the force limit.
        let k = CONTACT.normal_stiffness;
        assert!(k * PLANE_PRESS_M > 10.0 * PLANE_FORCE_TOL_N);
        assert!(k * PLANE_PRESS_M < CONTACT.max_force_n);
    }
}
