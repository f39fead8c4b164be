//! Pipeline tests: every mode transition, homing against a simple independent arm model, faults,
//! thresholds bracketed through the raw inputs, bridges, telemetry, and a property test that no
//! input sequence gives a panic, NaN or force outside `Armed`.

extern crate std;

use super::*;
use crate::math::vec3::Vec3;
use crate::omega_like::OMEGA_LIKE;
use crate::Libm;
use proptest::prelude::*;
use std::vec::Vec;

const RATE: u32 = 10_000;
const FULL_SCALE: u16 = BoardTiming::STM32G474_10KHZ.pwm_period_counts() as u16;

fn pipeline_with(plane_z_m: f32) -> Pipeline<Libm> {
    let cfg = PipelineConfig::plane(OMEGA_LIKE, BoardTiming::STM32G474_10KHZ, plane_z_m);
    match Pipeline::new(cfg) {
        Ok(p) => p,
        Err(e) => panic!("{e:?}"),
    }
}

/// The plane 0.3 m below the base: the probe is in free space everywhere it goes here.
fn pipeline() -> Pipeline<Libm> {
    pipeline_with(-0.3)
}

/// Three independent arms (no linkage): inertia, gravity pulling θ up (arm down), the upper stop
/// at −40° as a stiff spring-damper, the motor as a quasi-static DC motor on the averaged bridge
/// voltage, and an optional "hand" spring holding each arm at a reference angle. Independent of
/// the pipeline's code apart from the device constants.
struct Arms {
    theta: [f64; 3],
    omega: [f64; 3],
    hand: Option<[f64; 3]>,
    start_counts: [i64; 3],
    counter_start: u16,
    wrist: [i64; 3],
}

impl Arms {
    const INERTIA: f64 = 4.2e-4;
    const GRAVITY_NM: f64 = 0.06;
    const STOP_RAD: f64 = -40.0 * core::f64::consts::PI / 180.0;
    const LOWER_STOP_RAD: f64 = 105.0 * core::f64::consts::PI / 180.0;
    const STOP_K: f64 = 100.0;
    const STOP_C: f64 = 0.3;
    const HAND_K: f64 = 50.0;
    const HAND_C: f64 = 0.5;

    fn new(theta0: f64) -> Self {
        let mut a = Arms {
            theta: [theta0, theta0 + 0.05, theta0 - 0.05],
            omega: [0.0; 3],
            hand: None,
            start_counts: [0; 3],
            counter_start: 40_000,
            wrist: [0; 3],
        };
        a.start_counts = a.theta.map(Self::counts_of);
        a
    }

    fn rad_per_count() -> f64 {
        f64::from(OMEGA_LIKE.params.arm_rad_per_motor_count())
    }

    fn counts_of(theta: f64) -> i64 {
        (theta / Self::rad_per_count()).round() as i64
    }

    /// The hardware counters: 16-bit, wrapping, starting at `counter_start` at power-up.
    fn raw(&self) -> [u16; 6] {
        let m = |i: usize| {
            (i64::from(self.counter_start) + Self::counts_of(self.theta[i]) - self.start_counts[i])
                .rem_euclid(65_536) as u16
        };
        let w =
            |i: usize| (i64::from(self.counter_start) + self.wrist[i]).rem_euclid(65_536) as u16;
        [m(0), m(1), m(2), w(0), w(1), w(2)]
    }

    fn step(&mut self, b: &BridgeCommands) {
        let d = b.duties(FULL_SCALE);
        let m = OMEGA_LIKE.params.motor;
        let (kt, ke, r, n) = (
            f64::from(m.torque_constant_nm_per_a),
            f64::from(m.back_emf_v_s_per_rad),
            f64::from(m.resistance_ohm),
            f64::from(m.capstan_ratio),
        );
        let v = f64::from(OMEGA_LIKE.params.supply_v);
        let imax = f64::from(m.max_current_a);
        let h = 1.0 / f64::from(RATE) / 10.0;
        for _ in 0..10 {
            for i in 0..3 {
                let current = if b.pwm_enable && b.driver_awake {
                    ((f64::from(d[i]) * v - ke * n * self.omega[i]) / r).clamp(-imax, imax)
                } else {
                    0.0
                };
                let mut tau = n * kt * current + Self::GRAVITY_NM - 1e-3 * self.omega[i];
                if self.theta[i] < Self::STOP_RAD {
                    tau += (Self::STOP_K * (Self::STOP_RAD - self.theta[i])
                        - Self::STOP_C * self.omega[i])
                        .max(0.0);
                }
                if self.theta[i] > Self::LOWER_STOP_RAD {
                    tau -= (Self::STOP_K * (self.theta[i] - Self::LOWER_STOP_RAD)
                        + Self::STOP_C * self.omega[i])
                        .max(0.0);
                }
                if let Some(r) = self.hand {
                    tau += -Self::HAND_K * (self.theta[i] - r[i]) - Self::HAND_C * self.omega[i];
                }
                self.omega[i] += tau / Self::INERTIA * h;
                self.theta[i] += self.omega[i] * h;
            }
        }
    }
}

/// One closed-loop tick with an optional input edit.
fn tick<S: Environment>(
    p: &mut Pipeline<Libm, S>,
    arms: &mut Arms,
    edit: impl FnOnce(&mut RawInput),
) -> PipelineOutput {
    let mut raw = RawInput {
        counts: arms.raw(),
        ..RawInput::default()
    };
    edit(&mut raw);
    let out = p.tick(&raw);
    arms.step(&out.bridges);
    out
}

/// Home from arms hanging at 0.3 rad; returns the ticks homing took.
fn home<S: Environment>(p: &mut Pipeline<Libm, S>, arms: &mut Arms) -> u32 {
    let _ = tick(p, arms, |_| {});
    assert_eq!(p.command(Command::Home), Ok(()));
    for k in 1..60_000 {
        let out = tick(p, arms, |_| {});
        assert!(
            out.control.force_n == Vec3::ZERO && out.latched.is_empty(),
            "{out:?}"
        );
        if out.mode == Mode::Disarmed {
            // The tick homing ends reports the counts from the new zero already.
            assert_eq!(out.counts, p.homed_counts());
            // One disarmed tick looks at the contact (Arm is refused until one has).
            let _ = tick(p, arms, |_| {});
            return k;
        }
        assert_eq!(out.mode, Mode::Homing);
    }
    panic!("homing did not finish");
}

/// Off: asleep, disabled, compare 0 (the phase pins do not matter then).
fn is_off(b: &BridgeCommands) -> bool {
    !b.driver_awake && !b.pwm_enable && b.compare == [0; 3]
}

fn homed() -> (Pipeline<Libm>, Arms) {
    let mut p = pipeline();
    let mut arms = Arms::new(0.3);
    let _ = home(&mut p, &mut arms);
    (p, arms)
}

#[test]
fn power_up_is_unhomed_asleep_and_refuses_to_arm() {
    let mut p = pipeline();
    for _ in 0..100 {
        let out = p.tick(&RawInput::default());
        assert_eq!(out.mode, Mode::Unhomed);
        assert!(is_off(&out.bridges), "{:?}", out.bridges);
        assert_eq!(out.control.force_n, Vec3::ZERO);
    }
    assert_eq!(p.command(Command::Arm), Err(CommandError::NotHomed));
    assert_eq!(p.mode(), Mode::Unhomed);
}

#[test]
fn homing_finds_the_stop_and_sets_the_zero() {
    let mut p = pipeline();
    let mut arms = Arms::new(0.3);
    let ticks = home(&mut p, &mut arms);
    // ~1.5 rad down to the far stops at 1 rad/s, 2.5 rad up to the reference stops, a 0.1 s
    // stall time at each, ~0.7 rad back to the park angle and its 0.1 s settling, the 2 ms
    // wake: measured 52 436 ticks.
    assert!((45_000..60_000).contains(&ticks), "{ticks}");
    assert!(p.homed());
    // Parked near 0 rad: measured 4.7e-3 rad at worst; bound 3x, 0.014 rad.
    for t in arms.theta {
        assert!(t.abs() < 0.014, "{t}");
    }
    // The homed count of each arm equals its true angle within the stop's compliance under the
    // homing torque: (0.15 − 0.06) N·m / 100 N·m/rad = 0.9 mrad = 7 counts, plus 1 count of
    // quantisation.
    let out = tick(&mut p, &mut arms, |_| {});
    for i in 0..3 {
        let truth = Arms::counts_of(arms.theta[i]);
        let err = i64::from(out.counts[i]) - truth;
        assert!(
            err.abs() <= 10,
            "arm {i}: homed {} vs true {truth}",
            out.counts[i]
        );
    }
}

/// The wake time counts from the nSLEEP edge: the tick after `Home` writes nSLEEP high (the
/// edge), then 2 ms at 10 kHz = 20 full ticks awake, disabled, nFAULT ignored; the 22nd tick
/// after `Home` is the first whose nFAULT counts and the first that may drive.
#[test]
fn wake_time_masks_nfault_and_holds_the_bridges_off_for_2_ms_after_the_nsleep_edge() {
    let mut p = pipeline();
    let mut arms = Arms::new(0.3);
    let _ = tick(&mut p, &mut arms, |r| r.driver_fault = true);
    assert_eq!(p.command(Command::Home), Ok(()));
    for k in 0..21 {
        let out = tick(&mut p, &mut arms, |r| r.driver_fault = true);
        assert!(
            out.bridges.driver_awake && !out.bridges.pwm_enable,
            "tick {k}"
        );
        assert!(out.latched.is_empty(), "tick {k}");
    }
    // The 22nd tick: nFAULT counts.
    let out = tick(&mut p, &mut arms, |r| r.driver_fault = true);
    assert_eq!(out.mode, Mode::Faulted);
    assert!(out.latched.contains(Flags::DRIVER_FAULT));
    assert!(is_off(&out.bridges), "{:?}", out.bridges);
    // Without the fault the 22nd tick drives, the 21st does not.
    let mut p = pipeline();
    let mut arms = Arms::new(0.3);
    let _ = tick(&mut p, &mut arms, |_| {});
    let _ = p.command(Command::Home);
    for _ in 0..21 {
        assert!(!tick(&mut p, &mut arms, |_| {}).bridges.pwm_enable);
    }
    assert!(tick(&mut p, &mut arms, |_| {}).bridges.pwm_enable);
}

#[test]
fn nfault_while_asleep_never_latches() {
    let mut p = pipeline();
    for _ in 0..1000 {
        let out = p.tick(&RawInput {
            driver_fault: true,
            ..RawInput::default()
        });
        assert!(out.latched.is_empty() && out.mode == Mode::Unhomed);
    }
}

#[test]
fn homing_with_a_dead_encoder_fails_and_latches() {
    let mut p = pipeline();
    let _ = p.tick(&RawInput::default());
    assert_eq!(p.command(Command::Home), Ok(()));
    let mut faulted_at = None;
    for k in 0..5_000 {
        // The counters never move.
        let out = p.tick(&RawInput::default());
        if out.mode == Mode::Faulted {
            faulted_at = Some(k);
            assert!(out.latched.contains(Flags::HOMING_FAILED));
            assert!(is_off(&out.bridges), "{:?}", out.bridges);
            break;
        }
    }
    // The nSLEEP edge tick and 20 wake ticks, then 1000 ticks (0.1 s) without motion at the
    // "far stop" and 1000 more at the "reference stop": no travel, no zero.
    assert_eq!(faulted_at, Some(21 + 2000 - 1));
    assert!(!p.homed());
    assert_eq!(p.command(Command::Arm), Err(CommandError::Faulted));
    assert_eq!(p.command(Command::ClearFaults), Ok(()));
    assert_eq!(
        p.mode(),
        Mode::Unhomed,
        "not homed: clear leads back to Unhomed"
    );
}

#[test]
fn every_command_in_every_mode() {
    use CommandError as E;
    let (mut p, mut arms) = homed();
    // Disarmed.
    assert_eq!(p.mode(), Mode::Disarmed);
    assert_eq!(p.command(Command::Disarm), Ok(()));
    assert_eq!(p.command(Command::ClearFaults), Ok(()));
    assert_eq!(p.mode(), Mode::Disarmed);
    assert_eq!(p.command(Command::Arm), Ok(()));
    // Armed.
    assert_eq!(p.mode(), Mode::Armed);
    assert_eq!(p.command(Command::Arm), Ok(()));
    assert_eq!(p.command(Command::Home), Err(E::Armed));
    assert_eq!(p.command(Command::ClearFaults), Ok(()));
    assert_eq!(p.mode(), Mode::Armed);
    assert_eq!(p.command(Command::Disarm), Ok(()));
    assert_eq!(p.mode(), Mode::Disarmed);
    // Re-homing from Disarmed.
    assert_eq!(p.command(Command::Home), Ok(()));
    assert_eq!(p.mode(), Mode::Homing);
    assert!(!p.homed());
    assert_eq!(p.command(Command::Home), Err(E::Homing));
    assert_eq!(p.command(Command::Arm), Err(E::Homing));
    assert_eq!(p.command(Command::ClearFaults), Ok(()));
    assert_eq!(p.mode(), Mode::Homing);
    // Abort.
    assert_eq!(p.command(Command::Disarm), Ok(()));
    assert_eq!(p.mode(), Mode::Unhomed);
    assert_eq!(p.command(Command::Arm), Err(E::NotHomed));
    // Let the arms fall to their lower stops, home again from there, then a fault while armed.
    for _ in 0..20_000 {
        assert_eq!(tick(&mut p, &mut arms, |_| {}).mode, Mode::Unhomed);
    }
    let _ = home(&mut p, &mut arms);
    assert_eq!(p.command(Command::Arm), Ok(()));
    let out = tick(&mut p, &mut arms, |r| r.driver_fault = true);
    assert_eq!(out.mode, Mode::Faulted);
    assert_eq!(p.command(Command::Arm), Err(E::Faulted));
    assert_eq!(p.command(Command::Home), Err(E::Faulted));
    assert_eq!(p.command(Command::Disarm), Ok(()));
    assert_eq!(p.mode(), Mode::Faulted);
    // Clear: homed, so Disarmed — never straight to Armed — and the drivers wake again.
    assert_eq!(p.command(Command::ClearFaults), Ok(()));
    assert_eq!(p.mode(), Mode::Disarmed);
    let out = tick(&mut p, &mut arms, |_| {});
    assert!(out.bridges.driver_awake && !out.bridges.pwm_enable);
    assert_eq!(out.mode, Mode::Disarmed);
    // Parameters: rejected ones change nothing and raise the flag once.
    let bad = crate::contact::params::ContactParams {
        mu_s: f32::NAN,
        ..crate::contact::params::ContactParams::DEFAULT
    };
    assert!(matches!(
        p.command(Command::SetContactParams(bad)),
        Err(E::InvalidParams(_))
    ));
    assert!(tick(&mut p, &mut arms, |_| {})
        .flags
        .contains(Flags::PARAM_REJECTED));
    assert!(!tick(&mut p, &mut arms, |_| {})
        .flags
        .contains(Flags::PARAM_REJECTED));
    let stiff = crate::contact::params::ContactParams {
        normal_stiffness: 3000.0,
        ..crate::contact::params::ContactParams::DEFAULT
    };
    assert_eq!(p.command(Command::SetContactParams(stiff)), Ok(()));
    assert_eq!(p.controller().config().contact.normal_stiffness, 3000.0);
}

/// The probe position of arm angles, and a pipeline whose plane sits `depth_m` above it (the
/// fingertip pressed `depth_m` into the surface).
fn pressing(theta: [f64; 3], depth_m: f32) -> Pipeline<Libm> {
    pressing_with(theta, depth_m, OMEGA_LIKE.arm_ramp_s)
}

fn pressing_with(theta: [f64; 3], depth_m: f32, ramp_s: f32) -> Pipeline<Libm> {
    let angles = theta.map(|t| t as f32);
    let (p, f) = OMEGA_LIKE.params.delta.forward::<Libm>(angles);
    assert!(f.is_empty());
    let r = crate::contact::params::ContactParams::DEFAULT.fingertip_radius_m;
    let mut cfg =
        PipelineConfig::plane(OMEGA_LIKE, BoardTiming::STM32G474_10KHZ, p.z - r + depth_m);
    cfg.device.arm_ramp_s = ramp_s;
    Pipeline::new(cfg).unwrap_or_else(|e| panic!("{e:?}"))
}

/// The firmware's split tick (outputs, the hardware writes, then telemetry) is the tick: two
/// pipelines, one ticked whole and one split, give identical outputs, records and summaries every
/// tick through homing, arming and 1.1 s of pressing (records every 100 ticks, a summary at 1 s).
#[test]
fn the_split_tick_is_the_tick() {
    let hold = [0.5, 0.55, 0.45];
    let (mut whole, mut split) = (pressing(hold, 0.003), pressing(hold, 0.003));
    let (mut arms_w, mut arms_s) = (Arms::new(0.3), Arms::new(0.3));
    let _ = home(&mut whole, &mut arms_w);
    let _ = home(&mut split, &mut arms_s);
    arms_w.hand = Some(hold);
    arms_s.hand = Some(hold);
    assert_eq!(whole.command(Command::Arm), Ok(()));
    assert_eq!(split.command(Command::Arm), Ok(()));
    let (mut records, mut summaries) = (0, 0);
    for k in 0..11_000u32 {
        let raw = |arms: &Arms| RawInput {
            counts: arms.raw(),
            start_latency_counts: k % 50,
            prev_write_done_counts: 3_000 + k % 500,
            ..RawInput::default()
        };
        let (rw, rs) = (raw(&arms_w), raw(&arms_s));
        let w = whole.tick(&rw);
        arms_w.step(&w.bridges);
        let mut s = split.tick_outputs(&rs);
        assert_eq!((s.telemetry, s.summary), (None, None));
        arms_s.step(&s.bridges);
        split.tick_telemetry(&mut s, &rs);
        assert_eq!(w, s, "tick {k}");
        records += usize::from(w.telemetry.is_some());
        summaries += usize::from(w.summary.is_some());
    }
    assert_eq!(
        (records, summaries),
        (110, 1),
        "the run covers records and a summary"
    );
    assert!(whole.controller().contact().state() != crate::contact::state::ContactState::Broken);
}

/// Arm is refused while the probe is inside the surface. The hand holds the probe 0.40 mm below
/// its pose (measured: the arms sag against gravity), so a plane put 0.3 mm below the pose is
/// 0.1 mm in (refused: the contact is made 25 um in, at the default 2 N/mm wall's 0.05 N make
/// force) and one 0.6 mm below is 0.2 mm out (arms); held 3 mm in is refused. Lifted out, the
/// same pipeline arms.
#[test]
fn arm_is_refused_inside_the_surface_and_accepted_just_outside() {
    let hold = [0.5, 0.55, 0.45];
    for (depth, refused) in [(0.003, true), (-0.000_3, true), (-0.000_6, false)] {
        let mut p = pressing(hold, depth);
        let mut arms = Arms::new(0.3);
        let _ = home(&mut p, &mut arms);
        arms.hand = Some(hold);
        for _ in 0..5_000 {
            let out = tick(&mut p, &mut arms, |_| {});
            assert_eq!(out.control.force_n, Vec3::ZERO, "disarmed: no force");
        }
        let want = if refused {
            Err(CommandError::InsideSurface)
        } else {
            Ok(())
        };
        assert_eq!(p.command(Command::Arm), want, "depth {depth}");
        assert_eq!(
            tick(&mut p, &mut arms, |_| {}).mode == Mode::Armed,
            !refused
        );
        // Over the link the same rule holds.
        if refused {
            assert_eq!(p.link_command(Command::Arm), want);
            // Lift the handle 5 mm (arms 0.05 rad up) out of the surface: then it arms.
            arms.hand = Some(hold.map(|t| t - 0.05));
            for _ in 0..5_000 {
                let _ = tick(&mut p, &mut arms, |_| {});
            }
            assert_eq!(p.command(Command::Arm), Ok(()), "depth {depth}, lifted");
        }
    }
}

/// Armed above the surface and then pressed in, the force ramps from the surface: no step.
#[test]
fn arming_above_and_pressing_in_renders_from_the_surface_without_a_step() {
    let hold = [0.5, 0.55, 0.45];
    let mut p = pressing(hold, 0.003);
    let mut arms = Arms::new(0.3);
    let _ = home(&mut p, &mut arms);
    arms.hand = Some(hold.map(|t| t - 0.05));
    for _ in 0..5_000 {
        let _ = tick(&mut p, &mut arms, |_| {});
    }
    assert_eq!(p.command(Command::Arm), Ok(()));
    arms.hand = Some(hold);
    let (mut prev, mut max_step, mut last) = (0.0f32, 0.0f32, 0.0f32);
    for _ in 0..10_000 {
        let out = tick(&mut p, &mut arms, |_| {});
        assert_eq!(out.mode, Mode::Armed);
        let f = out.control.force_n.norm::<Libm>();
        max_step = max_step.max((f - prev).abs());
        prev = f;
        last = f;
    }
    // 3 mm into the 2 N/mm wall, the arms yielding against the hand (the earlier arming-inside
    // test measured 4.68 N here).
    assert!(last > 3.0, "force after pressing in: {last}");
    // Steps: one encoder count is 26 mN of wall and ~41 mN of damping (see the ramp test's
    // derivation in git history); the approach adds the wall's rise per tick.
    assert!(max_step < 0.3, "largest force step {max_step} N");
}

#[test]
fn a_fault_zeroes_the_outputs_in_the_same_tick_and_sleeps_the_drivers() {
    let hold = [0.5, 0.55, 0.45];
    let mut p = pressing(hold, 0.003);
    let mut arms = Arms::new(0.3);
    let _ = home(&mut p, &mut arms);
    arms.hand = Some(hold);
    let _ = p.command(Command::Arm);
    for _ in 0..6_000 {
        let out = tick(&mut p, &mut arms, |_| {});
        assert!(out.bridges.pwm_enable);
    }
    let out = tick(&mut p, &mut arms, |r| r.driver_fault = true);
    assert_eq!(out.mode, Mode::Faulted);
    assert!(is_off(&out.bridges), "{:?}", out.bridges);
    assert_eq!(out.control.force_n, Vec3::ZERO);
    assert!(p.homed(), "a driver fault does not lose the zero");
}

#[test]
fn glitch_threshold_bracketed_through_raw_counts_and_it_unhomes() {
    for (jump, glitch) in [(200u16, false), (201, true)] {
        let (mut p, arms) = homed();
        let base = arms.raw();
        let _ = p.tick(&RawInput {
            counts: base,
            ..RawInput::default()
        });
        let mut c = base;
        c[4] = c[4].wrapping_add(jump); // a wrist counter
        let out = p.tick(&RawInput {
            counts: c,
            ..RawInput::default()
        });
        assert_eq!(
            out.latched.contains(Flags::ENCODER_GLITCH),
            glitch,
            "{jump}"
        );
        assert_eq!(p.homed(), !glitch);
        if glitch {
            assert_eq!(p.command(Command::ClearFaults), Ok(()));
            assert_eq!(p.mode(), Mode::Unhomed);
        }
    }
}

#[test]
fn glitch_threshold_is_the_same_speed_at_20_khz() {
    let cfg = PipelineConfig::plane(OMEGA_LIKE, BoardTiming::STM32G474_20KHZ, 0.0);
    for (jump, glitch) in [(100u16, false), (101, true)] {
        let mut p: Pipeline<Libm> = Pipeline::new(cfg).unwrap_or_else(|e| panic!("{e:?}"));
        let _ = p.tick(&RawInput::default());
        let out = p.tick(&RawInput {
            counts: [jump, 0, 0, 0, 0, 0],
            ..RawInput::default()
        });
        assert_eq!(
            out.latched.contains(Flags::ENCODER_GLITCH),
            glitch,
            "{jump}"
        );
    }
}

#[test]
fn overrun_streak_bracketed_through_write_times() {
    let tick_counts = BoardTiming::STM32G474_10KHZ.tick_period_counts();
    for (n, latches) in [(9u32, false), (10, true)] {
        let mut p = pipeline();
        let _ = p.tick(&RawInput::default());
        let mut last = None;
        for _ in 0..n {
            last = Some(p.tick(&RawInput {
                prev_write_done_counts: tick_counts,
                ..RawInput::default()
            }));
        }
        let out = last.unwrap_or_else(|| panic!("no tick"));
        assert_eq!(out.latched.contains(Flags::OVERRUN), latches, "{n}");
        // One count less is not an overrun at all.
        let mut p = pipeline();
        for _ in 0..=n {
            let out = p.tick(&RawInput {
                prev_write_done_counts: tick_counts - 1,
                ..RawInput::default()
            });
            assert!(out.latched.is_empty());
        }
    }
}

#[test]
fn telemetry_is_decimated_and_drops_are_counted_and_reported() {
    let mut p = pipeline();
    let mut records = Vec::new();
    for k in 0..1000u32 {
        let out = p.tick(&RawInput {
            start_latency_counts: 70_000,
            ..RawInput::default()
        });
        if let Some(r) = out.telemetry {
            records.push((k, r));
            // Drop every other record.
            p.telemetry_sent(records.len() % 2 == 0);
        }
    }
    // 100 Hz of 10 kHz: ticks 99, 199, ...
    assert_eq!(records.len(), 10);
    assert_eq!(records[0].0, 99);
    assert_eq!(records[0].1.tick, 99);
    assert_eq!(records[0].1.latency_counts, u16::MAX, "saturates");
    // Record 1 (queued) reports the drop of record 0; record 2 (dropped) reports none.
    assert_eq!(records[1].1.dropped_before, 1);
    assert_eq!(records[2].1.dropped_before, 0);
    assert_eq!(records[3].1.dropped_before, 1);
    assert_eq!(p.dropped_total(), 5);
}

#[test]
fn timing_summary_once_per_second() {
    let mut p = pipeline();
    let mut summaries = Vec::new();
    for k in 0..25_000u32 {
        let out = p.tick(&RawInput {
            start_latency_counts: k % 7,
            prev_write_done_counts: 3_000,
            ..RawInput::default()
        });
        if let Some(s) = out.summary {
            summaries.push((k, s));
        }
    }
    assert_eq!(summaries.len(), 2);
    assert_eq!(summaries[0].0, 9_999);
    let s = summaries[1].1;
    assert_eq!(
        (s.ticks, s.max_latency_counts, s.max_write_counts),
        (10_000, 6, 3_000)
    );
    assert_eq!((s.overruns, s.late_writes), (0, 0));
}

#[test]
fn invalid_configurations_are_rejected() {
    let good = PipelineConfig::plane(OMEGA_LIKE, BoardTiming::STM32G474_10KHZ, 0.0);
    let mut bad = good;
    bad.timing.pwm_hz = 25_000;
    assert_eq!(
        Pipeline::<Libm>::new(bad).err(),
        Some(PipelineError::Timing(TimingError::PwmNotMultipleOfControl))
    );
    let mut bad = good;
    bad.device.arm_ramp_s = -1.0;
    assert!(matches!(
        Pipeline::<Libm>::new(bad).err(),
        Some(PipelineError::Params(_))
    ));
    let mut bad = good;
    bad.object_origin_m.x = f32::NAN;
    assert!(matches!(
        Pipeline::<Libm>::new(bad).err(),
        Some(PipelineError::Params(_))
    ));
}

#[derive(Clone, Debug)]
enum Step {
    Tick([u16; 6], bool, u32, u32),
    Cmd(u8),
}

fn step() -> impl Strategy<Value = Step> {
    prop_oneof![
        8 => (any::<[u16; 6]>(), any::<bool>(), any::<u32>(), any::<u32>())
            .prop_map(|(c, f, l, w)| Step::Tick(c, f, l, w)),
        1 => (0u8..5).prop_map(Step::Cmd),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Any raw input and command sequence: no panic, no NaN, compare within full scale, drive only
    /// in Homing or Armed, force only in Armed, a latched fault always means Faulted, asleep and
    /// disabled.
    #[test]
    fn no_input_sequence_breaks_the_invariants(steps in proptest::collection::vec(step(), 1..400)) {
        let mut p = pipeline();
        let mut counts = [0u16; 6];
        for s in steps {
            match s {
                Step::Cmd(c) => {
                    let cmd = match c {
                        0 => Command::Home,
                        1 => Command::Arm,
                        2 => Command::Disarm,
                        3 => Command::ClearFaults,
                        _ => Command::SetContactParams(crate::contact::params::ContactParams::DEFAULT),
                    };
                    let _ = p.command(cmd);
                }
                Step::Tick(c, fault, lat, wr) => {
                    // Mostly small motions, sometimes anything.
                    for (x, y) in counts.iter_mut().zip(c) {
                        *x = if y % 4 == 0 { y } else { x.wrapping_add(y % 64).wrapping_sub(32) };
                    }
                    let out = p.tick(&RawInput {
                        counts,
                        driver_fault: fault,
                        start_latency_counts: lat % 40_000,
                        prev_write_done_counts: wr % 40_000,
                    });
                    let c = out.control;
                    prop_assert!(c.force_n.is_finite() && c.probe_m.is_finite() && c.tau_n_nm.is_finite());
                    prop_assert!(c.duties.iter().all(|d| d.is_finite() && d.abs() <= 0.9));
                    prop_assert!(out.bridges.compare.iter().all(|&x| x <= FULL_SCALE));
                    if out.bridges.pwm_enable {
                        prop_assert!(matches!(out.mode, Mode::Homing | Mode::Armed));
                        prop_assert!(out.bridges.driver_awake);
                    } else {
                        prop_assert_eq!(out.bridges.compare, [0; 3]);
                    }
                    if out.mode != Mode::Armed {
                        prop_assert_eq!(c.force_n, Vec3::ZERO);
                    }
                    if !out.latched.is_empty() {
                        prop_assert_eq!(out.mode, Mode::Faulted);
                        prop_assert!(is_off(&out.bridges), "{:?}", out.bridges);
                    }
                }
            }
        }
    }
}

#[path = "local_model_tests.rs"]
mod local_model_tests;

/// The pipeline's passivity stage knows the motor encoders' resolution at the probe (so a held
/// probe's count dither is not taken for generated energy), and the board's output delay.
#[test]
fn passivity_stage_gets_the_device_quantum() {
    let pipe = pipeline();
    let c = pipe.controller().passivity().config();
    let q = OMEGA_LIKE.params.probe_m_per_motor_count();
    assert_eq!(c.position_quantum_m, q);
    assert!(q > 0.0);
}

/// Homed, armed above the surface of `pressing(hold, 0.003)` by `arm`, then pressed in for 1 s.
fn armed_pressing(
    arm: impl FnOnce(&mut Pipeline<Libm>) -> Result<(), CommandError>,
) -> (Pipeline<Libm>, Arms) {
    let hold = [0.5, 0.55, 0.45];
    let mut p = pressing(hold, 0.003);
    let mut arms = Arms::new(0.3);
    let _ = home(&mut p, &mut arms);
    arms.hand = Some(hold.map(|t| t - 0.05));
    for _ in 0..5_000 {
        let _ = tick(&mut p, &mut arms, |_| {});
    }
    assert_eq!(arm(&mut p), Ok(()));
    arms.hand = Some(hold);
    for _ in 0..10_000 {
        let _ = tick(&mut p, &mut arms, |_| {});
    }
    (p, arms)
}

/// A host that armed the device and then lost the link: the force reaches zero on the 200th
/// tick at 10 kHz (20 ms), not the 199th, with COMM_TIMEOUT from the first tick; it stays at
/// zero (latched) until re-armed; then it comes back.
#[test]
fn a_lost_link_fades_the_force_within_20_ms_and_latches_until_rearmed() {
    let (mut p, mut arms) = armed_pressing(|p| p.link_command(Command::Arm));
    assert!(p.host_armed());
    let before = tick(&mut p, &mut arms, |_| {});
    assert!(before.control.force_n.norm::<Libm>() > 3.0);
    p.link_lost();
    let mut zero_at = None;
    for k in 1..=2_000u32 {
        let out = tick(&mut p, &mut arms, |_| {});
        assert!(out.flags.contains(Flags::COMM_TIMEOUT), "tick {k}");
        assert_eq!(out.mode, Mode::Armed);
        if k == 199 {
            assert!(out.control.force_n != Vec3::ZERO, "zero before 20 ms");
        }
        if out.control.force_n == Vec3::ZERO && zero_at.is_none() {
            zero_at = Some(k);
        }
        if zero_at.is_some() {
            assert_eq!(out.control.force_n, Vec3::ZERO, "latched at {k}");
        }
    }
    assert_eq!(zero_at, Some(200));
    assert_eq!(p.link_command(Command::Arm), Ok(()));
    let mut last = tick(&mut p, &mut arms, |_| {});
    for _ in 0..1_000 {
        last = tick(&mut p, &mut arms, |_| {});
    }
    assert!(!last.flags.contains(Flags::COMM_TIMEOUT));
    assert!(last.control.force_n.norm::<Libm>() > 3.0);
}

/// Armed from the button (no host), a lost link does not take the force away.
#[test]
fn a_lost_link_leaves_a_locally_armed_device_alone() {
    let (mut p, mut arms) = armed_pressing(|p| p.command(Command::Arm));
    assert!(!p.host_armed());
    p.link_lost();
    for _ in 0..1_000 {
        let out = tick(&mut p, &mut arms, |_| {});
        assert!(!out.flags.contains(Flags::COMM_TIMEOUT));
    }
    assert!(
        tick(&mut p, &mut arms, |_| {})
            .control
            .force_n
            .norm::<Libm>()
            > 3.0
    );
}

/// The motor supply switched off (the E-stop) while armed: the drivers' undervoltage lockout
/// holds nFAULT low; DRIVER_FAULT latches on that tick with the outputs off, and ClearFaults
/// while the supply is still off latches it again the first tick the drivers are awake and
/// past their wake time, never arming.
#[test]
fn motor_supply_lost_latches_with_the_outputs_off_and_stays_latched_while_off() {
    let (mut p, mut arms) = armed_pressing(|p| p.command(Command::Arm));
    let out = tick(&mut p, &mut arms, |r| r.driver_fault = true);
    assert_eq!(out.mode, Mode::Faulted);
    assert!(out.latched.contains(Flags::DRIVER_FAULT));
    assert!(is_off(&out.bridges));
    assert_eq!(p.command(Command::ClearFaults), Ok(()));
    let mut relatched = None;
    for k in 1..=100u32 {
        let out = tick(&mut p, &mut arms, |r| r.driver_fault = true);
        assert!(!out.bridges.pwm_enable, "tick {k}");
        if out.mode == Mode::Faulted {
            relatched = Some(k);
            break;
        }
    }
    // The edge tick, 20 wake ticks, then the 22nd counts.
    assert_eq!(relatched, Some(22));
    assert_eq!(p.command(Command::Arm), Err(CommandError::Faulted));
}

/// Disarm while homing puts the drivers back to sleep at once.
#[test]
fn disarm_during_homing_sleeps_the_drivers() {
    let mut p = pipeline();
    let mut arms = Arms::new(0.3);
    let _ = tick(&mut p, &mut arms, |_| {});
    assert_eq!(p.command(Command::Home), Ok(()));
    for _ in 0..100 {
        assert!(tick(&mut p, &mut arms, |_| {}).bridges.driver_awake);
    }
    assert_eq!(p.command(Command::Disarm), Ok(()));
    let out = tick(&mut p, &mut arms, |_| {});
    assert_eq!(out.mode, Mode::Unhomed);
    assert!(is_off(&out.bridges), "{:?}", out.bridges);
}
