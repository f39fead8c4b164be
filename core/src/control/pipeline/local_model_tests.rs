//! The pipeline on the local-model scene: model switches at 1 kHz without a force step, the
//! communication watchdog's fade and latch through the pipeline, a stale model's fade, and the
//! fixed scene refusing the local-model commands. Closed loop against the independent arm model
//! of the pipeline tests, with a hand holding the handle.

use super::*;
use crate::contact::params::ContactParams;
use crate::control::controller::passivity;
use crate::control::local_model::{
    LocalModelEnvironment, LocalModelSpec, ModelError, ModelKind, ModelPose,
};

const HOLD: [f64; 3] = [0.5, 0.55, 0.45];

/// The probe position with the arms at `HOLD`.
fn probe_at_hold() -> Vec3 {
    let (p, f) = OMEGA_LIKE
        .params
        .delta
        .forward::<Libm>(HOLD.map(|t| t as f32));
    assert!(f.is_empty());
    p
}

/// A plane `depth_m` into the fingertip held at `HOLD` (base frame), sequence `seq`.
fn plane(seq: u32, depth_m: f32) -> LocalModelSpec {
    let r = ContactParams::DEFAULT.fingertip_radius_m;
    let z = probe_at_hold().z - r + depth_m;
    LocalModelSpec::plane(
        seq,
        ModelPose::at(Vec3::new(0.0, 0.0, z)),
        &ContactParams::DEFAULT,
    )
}

/// A sphere whose top is `depth_m` into the fingertip held at `HOLD`.
fn sphere(seq: u32, depth_m: f32, radius_m: f32) -> LocalModelSpec {
    let r = ContactParams::DEFAULT.fingertip_radius_m;
    let top = probe_at_hold() - Vec3::new(0.0, 0.0, r - depth_m);
    LocalModelSpec {
        kind: ModelKind::Sphere { radius_m },
        pose: ModelPose::at(top - Vec3::new(0.0, 0.0, radius_m)),
        ..plane(seq, depth_m)
    }
}

fn scene_pipeline(scene: LocalModelEnvironment) -> Pipeline<Libm, LocalModelEnvironment> {
    let cfg = PipelineConfig {
        device: OMEGA_LIKE,
        timing: BoardTiming::STM32G474_10KHZ,
        contact: ContactParams::DEFAULT,
        surface: scene,
        object_origin_m: Vec3::ZERO,
        log_rate_hz: 0,
    };
    Pipeline::new(cfg).unwrap_or_else(|e| panic!("{e:?}"))
}

/// Homed, the hand holding the handle at `HOLD`, armed and past the arming ramp (0.5 s).
fn armed(scene: LocalModelEnvironment) -> (Pipeline<Libm, LocalModelEnvironment>, Arms) {
    let mut p = scene_pipeline(scene);
    let mut arms = Arms::new(0.3);
    let _ = home(&mut p, &mut arms);
    // Arm with the handle lifted out of the surface (arms 0.05 rad up), then press in.
    arms.hand = Some(HOLD.map(|t| t - 0.05));
    for _ in 0..5_000 {
        let out = tick(&mut p, &mut arms, |_| {});
        assert_eq!(out.control.force_n, Vec3::ZERO, "disarmed: no force");
    }
    assert_eq!(p.command(Command::Arm), Ok(()));
    arms.hand = Some(HOLD);
    for _ in 0..6_000 {
        let out = tick(&mut p, &mut arms, |_| {});
        assert_eq!(out.mode, Mode::Armed);
    }
    (p, arms)
}

/// Run 0.2 s of 1 kHz model updates alternating between a plane 1 mm and 4 mm into the
/// fingertip (pose slews), every 20 ms switching to a sphere and back (cross-fades); returns
/// the largest force change in one tick and the smallest and largest force seen.
fn switching(blend_s: f32) -> (f32, f32, f32) {
    let scene = LocalModelEnvironment {
        blend_s,
        ..LocalModelEnvironment::new(plane(1, 0.001))
    };
    let (mut p, mut arms) = armed(scene);
    // The passivity stage observes only on a local model, by default (see the test's doc).
    assert!(!p.controller().passivity().config().enabled);
    let mut prev = tick(&mut p, &mut arms, |_| {}).control.force_n;
    let (mut max_step, mut lo, mut hi) = (0.0f32, f32::MAX, 0.0f32);
    let mut seq = 1;
    for k in 0..2_000u32 {
        if k % 10 == 0 {
            seq += 1;
            let depth = if (k / 10) % 2 == 0 { 0.004 } else { 0.001 };
            let m = if (k / 200) % 2 == 1 && k % 200 < 100 {
                sphere(seq, depth, 0.05)
            } else {
                plane(seq, depth)
            };
            p.note_link_activity();
            assert_eq!(p.command(Command::SetLocalModel(m)), Ok(()));
        }
        let out = tick(&mut p, &mut arms, |_| {});
        assert_eq!(out.mode, Mode::Armed);
        let f = out.control.force_n;
        max_step = max_step.max((f - prev).norm::<Libm>());
        let n = f.norm::<Libm>();
        (lo, hi) = (lo.min(n), hi.max(n));
        prev = f;
    }
    (max_step, lo, hi)
}

/// The plane models' forces differ by |ΔF| = 2 N/mm · 3 mm = 6 N at the held probe; a 2 ms blend
/// at 10 kHz moves at most |ΔF|·dt/blend = 6 N · 0.05 = 0.3 N per tick, plus the encoder
/// quantisation's 75 mN (see `arming_while_pressing_ramps_the_force_in_without_a_step`): bound
/// 0.375 N. Measured largest step 0.306 N (force range 2.2–5.5 N). A switch in one tick (blend
/// 0) steps by several newtons: the test can fail.
///
/// The passivity stage observes only, the local-model scene's default
/// (`LocalModelEnvironment::PASSIVITY_DAMPS`): a surface oscillating by 3 mm at 500 Hz is an active
/// environment, the observer sees the energy it puts into the hand, and its damper then steps
/// the force (measured 2.8 N with it on). Rendering moving local models passively needs the
/// model's motion in the observer's energy balance; not done.
#[test]
fn model_switches_at_1khz_make_no_force_step() {
    let (step, lo, hi) = switching(0.002);
    std::println!("blend 2 ms: largest step {step} N, force {lo}..{hi} N");
    assert!(
        hi - lo > 2.0,
        "the models render different forces: {lo}..{hi}"
    );
    assert!(step <= 0.375, "largest step {step} N");
    let (jump, lo0, hi0) = switching(0.0);
    std::println!("blend 0: largest step {jump} N, force {lo0}..{hi0} N");
    assert!(jump > 3.0 * 0.375, "an unblended switch steps: {jump} N");
}

/// Watchdog 10 ms (100 ticks) through the pipeline: link activity every 5 ms keeps it quiet for
/// 0.5 s; then silent, no flag at 99 ticks, COMM_TIMEOUT at 100, the force fades to zero within
/// the 20 ms fade (200 ticks; not at 199 while the hand presses); activity alone does not clear
/// it, `Arm` (re-arming while armed) does and the force returns.
#[test]
fn the_watchdog_fades_within_its_bound_and_latches_until_rearmed() {
    let (mut p, mut arms) = armed(LocalModelEnvironment::new(plane(1, 0.003)));
    assert_eq!(p.command(Command::SetWatchdog { timeout_s: 0.010 }), Ok(()));
    for k in 0..5_000 {
        if k % 50 == 0 {
            p.note_link_activity();
        }
        let out = tick(&mut p, &mut arms, |_| {});
        assert!(!out.flags.contains(Flags::COMM_TIMEOUT), "tick {k}");
    }
    p.note_link_activity();
    for _ in 0..99 {
        let out = tick(&mut p, &mut arms, |_| {});
        assert!(!out.flags.contains(Flags::COMM_TIMEOUT));
    }
    let out = tick(&mut p, &mut arms, |_| {});
    assert!(out.flags.contains(Flags::COMM_TIMEOUT));
    assert_eq!(out.mode, Mode::Armed, "a timeout fades, it is not a fault");
    let f0 = out.control.force_n.norm::<Libm>();
    assert!(f0 > 3.0, "{f0}");
    for _ in 0..198 {
        let out = tick(&mut p, &mut arms, |_| {});
        assert!(out.control.force_n.norm::<Libm>() > 0.0);
    }
    let out = tick(&mut p, &mut arms, |_| {});
    assert_eq!(out.control.force_n, Vec3::ZERO, "faded within 200 ticks");
    p.note_link_activity();
    let out = tick(&mut p, &mut arms, |_| {});
    assert!(
        out.flags.contains(Flags::COMM_TIMEOUT),
        "latched until re-armed"
    );
    p.note_link_activity();
    assert_eq!(p.command(Command::Arm), Ok(()));
    let mut out = tick(&mut p, &mut arms, |_| {});
    assert!(!out.flags.contains(Flags::COMM_TIMEOUT));
    for _ in 0..50 {
        p.note_link_activity();
        out = tick(&mut p, &mut arms, |_| {});
    }
    assert!(out.control.force_n.norm::<Libm>() > 0.5);
    assert_eq!(
        p.command(Command::SetWatchdog { timeout_s: 60.01 }),
        Err(CommandError::InvalidParams(
            crate::contact::params::ParamError::OutOfRange("watchdog_timeout_s")
        ))
    );
    assert_eq!(p.command(Command::SetWatchdog { timeout_s: 60.0 }), Ok(()));
}

/// The passivity damper (off by default on a local model; an application may turn it on) stands
/// aside while the watchdog holds the force down: a
/// model switch 7 mm up pushes the probe (energy the observer counts as generated, so its damper
/// acts), the hand swings the handle, and after a 10 ms timeout the force is exactly zero from
/// the end of the 20 ms fade on (300 ticks after the last message), every tick. On the emulated
/// board the damper kept pushing on the moving probe after the timeout (`scripts/pil
/// --link-check` measured 0.8-2.2 N for 140 ms after the timeout); this arm model does not
/// reproduce that motion, so here the test guards the contract rather than the failure.
#[test]
fn after_a_timeout_no_force_even_while_the_hand_moves() {
    let (mut p, mut arms) = armed(LocalModelEnvironment::new(plane(1, 0.003)));
    let damping = passivity::PassivityConfig {
        enabled: true,
        ..*p.controller().passivity().config()
    };
    assert_eq!(p.set_passivity(damping), Ok(()));
    assert_eq!(p.command(Command::SetLocalModel(plane(2, 0.010))), Ok(()));
    assert_eq!(p.command(Command::SetWatchdog { timeout_s: 0.010 }), Ok(()));
    let mut forced_while_moving = 0;
    for k in 0..3_000 {
        // The hand swings the handle between two poses every 10 ms.
        arms.hand = Some(if (k / 30) % 2 == 0 {
            HOLD
        } else {
            [0.42, 0.62, 0.5]
        });
        let out = tick(&mut p, &mut arms, |_| {});
        if k < 100 && out.control.force_n != Vec3::ZERO {
            forced_while_moving += 1;
        }
        if k >= 300 {
            assert_eq!(out.control.force_n, Vec3::ZERO, "tick {k}");
            assert!(out.flags.contains(Flags::COMM_TIMEOUT));
        }
    }
    assert!(
        forced_while_moving > 0,
        "the plane pressed before the timeout"
    );
}

/// A model declaring 5 ms of age (50 ticks) raises MODEL_STALE at tick 51 (not 50) and its force
/// fades to zero over the 20 ms stale fade (200 ticks); a fresh model brings it back.
#[test]
fn a_stale_model_fades() {
    let (mut p, mut arms) = armed(LocalModelEnvironment::new(plane(1, 0.003)));
    let aging = LocalModelSpec {
        max_age_s: 0.005,
        ..plane(2, 0.003)
    };
    assert_eq!(p.command(Command::SetLocalModel(aging)), Ok(()));
    for _ in 0..50 {
        let out = tick(&mut p, &mut arms, |_| {});
        assert!(!out.flags.contains(Flags::MODEL_STALE));
    }
    let out = tick(&mut p, &mut arms, |_| {});
    assert!(out.flags.contains(Flags::MODEL_STALE));
    assert!(out.control.force_n.norm::<Libm>() > 3.0);
    let mut out = out;
    for _ in 0..200 {
        out = tick(&mut p, &mut arms, |_| {});
    }
    assert_eq!(out.control.force_n, Vec3::ZERO);
    assert_eq!(p.command(Command::SetLocalModel(plane(3, 0.003))), Ok(()));
    for _ in 0..300 {
        out = tick(&mut p, &mut arms, |_| {});
    }
    assert!(!out.flags.contains(Flags::MODEL_STALE));
    assert!(out.control.force_n.norm::<Libm>() > 3.0);
    assert_eq!(p.controller().contact().model_seq(), 3);
    // An old sequence number is refused, typed, and flagged on the next tick.
    assert_eq!(
        p.command(Command::SetLocalModel(plane(3, 0.003))),
        Err(CommandError::InvalidModel(ModelError::StaleSequence))
    );
    assert!(tick(&mut p, &mut arms, |_| {})
        .flags
        .contains(Flags::MODEL_REJECTED));
}

/// No force before homing and arming on the local-model scene either; models are accepted
/// meanwhile.
#[test]
fn the_local_model_renders_only_when_armed() {
    let mut p = scene_pipeline(LocalModelEnvironment::new(plane(1, 0.003)));
    let mut arms = Arms::new(0.3);
    assert_eq!(p.command(Command::SetLocalModel(plane(2, 0.003))), Ok(()));
    assert_eq!(p.command(Command::Arm), Err(CommandError::NotHomed));
    let _ = home(&mut p, &mut arms);
    arms.hand = Some(HOLD);
    for _ in 0..2_000 {
        let out = tick(&mut p, &mut arms, |_| {});
        assert_eq!(out.control.force_n, Vec3::ZERO);
        assert!(!out.bridges.pwm_enable);
    }
}

/// The passivity stage's default follows the scene: the fixed plane's damps, the local model's
/// observes only (`Environment::PASSIVITY_DAMPS`).
#[test]
fn passivity_damps_on_a_fixed_scene_and_observes_on_a_local_model() {
    let local = scene_pipeline(LocalModelEnvironment::new(plane(1, 0.001)));
    assert!(!local.controller().passivity().config().enabled);
    let (fixed, _) = homed();
    assert!(fixed.controller().passivity().config().enabled);
}

/// The fixed (plane) scene refuses the local-model commands with a typed error and changes
/// nothing.
#[test]
fn the_fixed_scene_refuses_local_model_commands() {
    let (mut p, mut arms) = homed();
    let before = *p.controller().config();
    assert_eq!(
        p.command(Command::SetLocalModel(plane(2, 0.003))),
        Err(CommandError::Unsupported)
    );
    assert_eq!(
        p.command(Command::SetWatchdog { timeout_s: 0.01 }),
        Err(CommandError::Unsupported)
    );
    p.note_link_activity();
    let out = tick(&mut p, &mut arms, |_| {});
    assert_eq!(out.mode, Mode::Disarmed);
    assert!(!out
        .flags
        .intersects(Flags::MODEL_REJECTED | Flags::COMM_TIMEOUT));
    assert_eq!(*p.controller().config(), before);
}

/// The bowl and the cylinder render through the pipeline: each placed 3 mm into the held
/// fingertip pushes it out (up, +z) as the plane does (2 N/mm · 3 mm = 6 N less the arms'
/// yield: the plane measures 4.7 N here; a curved surface a little less).
#[test]
fn bowls_and_cylinders_render() {
    let r = ContactParams::DEFAULT.fingertip_radius_m;
    let bottom = probe_at_hold() - Vec3::new(0.0, 0.0, r - 0.003);
    let big = 0.05;
    let bowl = LocalModelSpec {
        kind: ModelKind::Bowl { radius_m: big },
        pose: ModelPose::at(bottom + Vec3::new(0.0, 0.0, big)),
        ..plane(2, 0.003)
    };
    let cylinder = LocalModelSpec {
        kind: ModelKind::Cylinder { radius_m: big },
        pose: ModelPose::at(bottom - Vec3::new(0.0, 0.0, big)),
        ..plane(3, 0.003)
    };
    for m in [bowl, cylinder] {
        let (mut p, mut arms) = armed(LocalModelEnvironment::new(plane(1, 0.0005)));
        assert_eq!(p.command(Command::SetLocalModel(m)), Ok(()));
        let mut out = tick(&mut p, &mut arms, |_| {});
        for _ in 0..2_000 {
            out = tick(&mut p, &mut arms, |_| {});
        }
        let f = out.control.force_n;
        assert!(f.z > 3.0 && f.z < 6.0, "{:?}: {f:?}", m.kind);
        assert_eq!(p.controller().contact().model_seq(), m.seq);
        assert!(out.latched.is_empty());
    }
}

/// A host's Arm turns the communication watchdog on (0.2 s) when it was off, and while that host
/// keeps the device armed it cannot turn it off; after Disarm it can.
#[test]
fn a_host_arm_turns_the_watchdog_on_and_keeps_it_on() {
    let mut p = scene_pipeline(LocalModelEnvironment::new(plane(1, 0.003)));
    let mut arms = Arms::new(0.3);
    let _ = home(&mut p, &mut arms);
    arms.hand = Some(HOLD.map(|t| t - 0.05));
    for _ in 0..100 {
        let _ = tick(&mut p, &mut arms, |_| {});
    }
    assert_eq!(p.controller().contact().watchdog_s(), 0.0);
    assert_eq!(p.link_command(Command::Arm), Ok(()));
    assert_eq!(p.controller().contact().watchdog_s(), HOST_WATCHDOG_S);
    assert_eq!(
        p.link_command(Command::SetWatchdog { timeout_s: 0.0 }),
        Err(CommandError::WatchdogRequired)
    );
    assert_eq!(
        p.link_command(Command::SetWatchdog { timeout_s: 0.5 }),
        Ok(())
    );
    assert_eq!(p.link_command(Command::Disarm), Ok(()));
    assert_eq!(
        p.link_command(Command::SetWatchdog { timeout_s: 0.0 }),
        Ok(())
    );
}

/// The stored host watchdog (`watchdog.timeout_ms`, applied at boot) is what a host's Arm turns
/// on; its limits are taken just inside and refused just outside, and a refusal keeps the
/// timeout in force.
#[test]
fn a_host_arm_turns_on_the_stored_watchdog_timeout() {
    let mut p = scene_pipeline(LocalModelEnvironment::new(plane(1, 0.003)));
    assert_eq!(p.host_watchdog_s(), HOST_WATCHDOG_S);
    for bad in [0.0099, 10.01, 0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert!(p.set_host_watchdog(bad).is_err(), "{bad} taken");
        assert_eq!(p.host_watchdog_s(), HOST_WATCHDOG_S);
    }
    assert_eq!(p.set_host_watchdog(HOST_WATCHDOG_MIN_S), Ok(()));
    assert_eq!(p.set_host_watchdog(HOST_WATCHDOG_MAX_S), Ok(()));
    assert_eq!(p.set_host_watchdog(0.05), Ok(()));
    let mut arms = Arms::new(0.3);
    let _ = home(&mut p, &mut arms);
    arms.hand = Some(HOLD.map(|t| t - 0.05));
    for _ in 0..100 {
        let _ = tick(&mut p, &mut arms, |_| {});
    }
    assert_eq!(p.link_command(Command::Arm), Ok(()));
    assert_eq!(p.controller().contact().watchdog_s(), 0.05);
}

/// A stiffness change while armed and pressing (`SetContactParams`, material only): the contact
/// carries on (rolling on every tick), the force moves to the new spring over the blend without
/// a step or a dip, and the arming ramp does not start again. A change of anything else (here
/// the force limit) restarts the contact and ramps the force in again from zero.
///
/// The plane 2 mm into the fingertip held by the hand: 3.30 N, then 0.8 of the stiffness, where
/// the hand settles at 2.78 N. A step is bounded by the blend's share of the change,
/// |ΔF|·dt/blend = |ΔF|·0.05, plus the encoder quantisation's 75 mN (`switching`'s bound):
/// measured 0.077 N of 0.101 N. The force never fell below 0.955 of its final value (bound 0.9;
/// a restart gives 0); after the restart it is 0 and ramps in.
#[test]
fn a_material_change_while_armed_blends_and_anything_else_restarts() {
    let (mut p, mut arms) = armed(LocalModelEnvironment::new(plane(1, 0.002)));
    let before = tick(&mut p, &mut arms, |_| {});
    assert_eq!(before.control.state, ContactState::Rolling);
    let f0 = before.control.force_n.norm::<Libm>();
    let softer = ContactParams {
        normal_stiffness: 0.8 * ContactParams::DEFAULT.normal_stiffness,
        ..ContactParams::DEFAULT
    };
    assert_eq!(p.command(Command::SetContactParams(softer)), Ok(()));
    let (mut prev, mut max_step, mut lo) = (before.control.force_n, 0.0f32, f32::MAX);
    for _ in 0..100 {
        let out = tick(&mut p, &mut arms, |_| {});
        assert_eq!(
            out.control.state,
            ContactState::Rolling,
            "the contact carries on"
        );
        assert_eq!(out.ramp_gain, 1.0, "no new arming ramp");
        max_step = max_step.max((out.control.force_n - prev).norm::<Libm>());
        lo = lo.min(out.control.force_n.norm::<Libm>());
        prev = out.control.force_n;
    }
    let f1 = prev.norm::<Libm>();
    assert!(
        f1 < 0.95 * f0 && f1 > 0.8 * f0,
        "the softer spring: {f0} N -> {f1} N"
    );
    let bound = (f0 - f1) * 0.05 + 0.075;
    assert!(max_step < bound, "largest step {max_step} (bound {bound})");
    // The hand settles on the softer spring with a small undershoot; a restart would give 0.
    assert!(lo > 0.9 * f1, "no dip: {lo} N");
    assert_eq!(p.controller().config().contact, softer);
    assert_eq!(
        *p.controller().contact().params(),
        softer,
        "the renderer's base"
    );

    // The force limit is not material: the contact restarts and the force ramps in again.
    let limited = ContactParams {
        max_force_n: 30.0,
        ..softer
    };
    assert_eq!(p.command(Command::SetContactParams(limited)), Ok(()));
    let out = tick(&mut p, &mut arms, |_| {});
    assert!(out.ramp_gain < 0.01, "ramping in again: {}", out.ramp_gain);
    assert!(
        out.control.force_n.norm::<Libm>() < 0.1,
        "{:?}",
        out.control.force_n
    );
}
