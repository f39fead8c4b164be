//! Tests of the output guard: every latching event, every threshold bracketed, the duty limit,
//! the rate conversion of the limits and the phase/enable mapping.
use super::*;
use crate::math::vec3::Vec3;

const TICKS: TickLimits = TickLimits {
    max_counts_per_tick: 10,
    overrun_streak: 3,
    stuck_ticks: 5,
};

fn config() -> GuardConfig {
    GuardConfig {
        max_duty: 0.8,
        stuck_duty: 0.2,
        ticks: TICKS,
    }
}

fn out(duties: [f32; 3]) -> TickOutput {
    TickOutput {
        duties,
        enable: true,
        flags: Flags::NONE,
        probe_m: Vec3::ZERO,
        force_n: Vec3::new(0.5, 0.0, 1.0),
        tau_n_nm: 0.0,
        ..TickOutput::default()
    }
}

fn guard() -> OutputGuard {
    match OutputGuard::new(config()) {
        Ok(g) => g,
        Err(e) => panic!("valid config rejected: {e:?}"),
    }
}

/// Counts that move every tick (so nothing is stuck): `k` on every axis.
fn moving(k: i32) -> [i32; 6] {
    [k; 6]
}

#[test]
fn nominal_duties_pass_unchanged() {
    let mut g = guard();
    let r = g.apply(&moving(0), &out([0.1, -0.5, 0.8]), Flags::NONE, false);
    assert_eq!(r.duties, [0.1, -0.5, 0.8]);
    assert!(r.enable);
    assert!(r.flags.is_empty());
}

#[test]
fn duties_are_clamped_to_the_limit_with_a_flag() {
    let mut g = guard();
    let r = g.apply(&moving(0), &out([1.0, -0.95, 0.3]), Flags::NONE, false);
    assert_eq!(r.duties, [0.8, -0.8, 0.3]);
    assert!(r.enable);
    assert_eq!(r.flags, Flags::OUTPUT_LIMITED);
    assert!(g.latched().is_empty(), "limiting is not a fault");
}

#[test]
fn non_finite_duty_zeroes_everything_and_latches() {
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let mut g = guard();
        let r = g.apply(&moving(0), &out([0.2, bad, 0.3]), Flags::NONE, false);
        assert_eq!(r.duties, [0.0; 3]);
        assert!(!r.enable);
        assert!(r.flags.contains(Flags::NON_FINITE_OUTPUT));
        assert_eq!(g.latched(), Flags::NON_FINITE_OUTPUT);
        // Still latched with a good output next tick.
        let r = g.apply(&moving(1), &out([0.2, 0.2, 0.2]), Flags::NONE, false);
        assert_eq!((r.duties, r.enable), ([0.0; 3], false));
    }
}

#[test]
fn non_finite_reported_force_or_torque_latches() {
    let mut g = guard();
    let mut o = out([0.1; 3]);
    o.force_n.y = f32::NAN;
    assert!(!g.apply(&moving(0), &o, Flags::NONE, false).enable);
    let mut g = guard();
    let mut o = out([0.1; 3]);
    o.tau_n_nm = f32::INFINITY;
    assert!(!g.apply(&moving(0), &o, Flags::NONE, false).enable);
    assert_eq!(g.latched(), Flags::NON_FINITE_OUTPUT);
}

#[test]
fn each_latching_event_disables_until_cleared() {
    for ev in [
        Flags::DRIVER_FAULT,
        Flags::ENCODER_GLITCH,
        Flags::HOMING_FAILED,
    ] {
        let mut g = guard();
        let r = g.apply(&moving(0), &out([0.5; 3]), ev, false);
        assert_eq!((r.duties, r.enable), ([0.0; 3], false));
        assert!(r.flags.contains(ev));
        // The event is gone, the latch is not.
        let r = g.apply(&moving(1), &out([0.5; 3]), Flags::NONE, false);
        assert_eq!((r.duties, r.enable), ([0.0; 3], false));
        assert_eq!(r.flags, ev);
        g.clear();
        let r = g.apply(&moving(2), &out([0.5; 3]), Flags::NONE, false);
        assert_eq!((r.duties, r.enable), ([0.5; 3], true));
    }
}

#[test]
fn latching_set_includes_stuck_and_homing() {
    for f in [
        Flags::DRIVER_FAULT,
        Flags::ENCODER_GLITCH,
        Flags::ENCODER_STUCK,
        Flags::NON_FINITE_OUTPUT,
        Flags::OVERRUN,
        Flags::HOMING_FAILED,
        Flags::THREAD_STALLED,
    ] {
        assert!(LATCHING.contains(f));
    }
    assert!(!LATCHING.intersects(Flags::OUTPUT_LIMITED | Flags::PARAM_REJECTED));
}

#[test]
fn latching_flags_reported_by_the_controller_also_latch() {
    let mut g = guard();
    let mut o = out([0.5; 3]);
    o.flags = Flags::DRIVER_FAULT | Flags::SPIN_SATURATED;
    let _ = g.apply(&moving(0), &o, Flags::NONE, false);
    assert_eq!(g.latched(), Flags::DRIVER_FAULT, "only fault flags latch");
    let mut g = guard();
    g.latch(Flags::HOMING_FAILED | Flags::OUTPUT_LIMITED);
    assert_eq!(g.latched(), Flags::HOMING_FAILED);
}

#[test]
fn overrun_streak_latches_at_the_limit_only() {
    let mut g = guard();
    // Two in a row (one below the limit of 3), then a break: nothing.
    for k in 0..2 {
        assert!(
            g.apply(&moving(k), &out([0.5; 3]), Flags::NONE, true)
                .enable
        );
    }
    assert!(
        g.apply(&moving(2), &out([0.5; 3]), Flags::NONE, false)
            .enable
    );
    for k in 3..5 {
        assert!(
            g.apply(&moving(k), &out([0.5; 3]), Flags::NONE, true)
                .enable
        );
    }
    let r = g.apply(&moving(5), &out([0.5; 3]), Flags::NONE, true);
    assert!(!r.enable);
    assert_eq!(g.latched(), Flags::OVERRUN);
}

#[test]
fn glitch_threshold_is_bracketed() {
    let mut g = guard();
    let _ = g.apply(&[0; 6], &out([0.0; 3]), Flags::NONE, false);
    // Exactly 10 counts in a tick (the limit) on a wrist axis: plausible.
    let r = g.apply(&[0, 0, 0, 0, 10, 0], &out([0.0; 3]), Flags::NONE, false);
    assert!(r.enable);
    // 11: a glitch.
    let r = g.apply(&[0, 0, 0, 0, 21, 0], &out([0.0; 3]), Flags::NONE, false);
    assert!(!r.enable);
    assert_eq!(g.latched(), Flags::ENCODER_GLITCH);
    // The first tick after a clear has no predecessor to compare with.
    g.clear();
    assert!(
        g.apply(&[5000; 6], &out([0.0; 3]), Flags::NONE, false)
            .enable
    );
}

#[test]
fn stuck_needs_the_duty_and_the_time() {
    let still = [7; 6];
    // Duty 0.2 (the threshold) for 5 ticks after the first: stuck on the 5th.
    let mut g = guard();
    let _ = g.apply(&still, &out([0.2, 0.0, 0.0]), Flags::NONE, false);
    for _ in 0..4 {
        assert!(
            g.apply(&still, &out([0.2, 0.0, 0.0]), Flags::NONE, false)
                .enable
        );
    }
    assert!(
        !g.apply(&still, &out([0.2, 0.0, 0.0]), Flags::NONE, false)
            .enable
    );
    assert_eq!(g.latched(), Flags::ENCODER_STUCK);
    // Just below the duty: never.
    let mut g = guard();
    for _ in 0..100 {
        assert!(
            g.apply(&still, &out([0.0, -0.199, 0.0]), Flags::NONE, false)
                .enable
        );
    }
    // One count of motion resets the time.
    let mut g = guard();
    for k in 0..100 {
        let c = [0, 0, k / 4, 0, 0, 0];
        assert!(
            g.apply(&c, &out([0.0, 0.0, 0.5]), Flags::NONE, false)
                .enable
        );
    }
    // Disabled outputs do not count as drive.
    let mut g = guard();
    let mut o = out([0.5; 3]);
    o.enable = false;
    for _ in 0..100 {
        let _ = g.apply(&still, &o, Flags::NONE, false);
    }
    assert!(g.latched().is_empty());
}

#[test]
fn condition_still_present_relatches_after_clear() {
    let mut g = guard();
    let _ = g.apply(&moving(0), &out([0.5; 3]), Flags::DRIVER_FAULT, false);
    g.clear();
    let r = g.apply(&moving(1), &out([0.5; 3]), Flags::DRIVER_FAULT, false);
    assert!(!r.enable);
    assert_eq!(g.latched(), Flags::DRIVER_FAULT);
}

#[test]
fn controller_disable_gives_zero_without_latching() {
    let mut g = guard();
    let mut o = out([0.5; 3]);
    o.enable = false;
    let r = g.apply(&moving(0), &o, Flags::NONE, false);
    assert_eq!((r.duties, r.enable), ([0.0; 3], false));
    assert!(g.latched().is_empty());
}

#[test]
fn invalid_configs_are_rejected() {
    for max_duty in [0.0, -0.1, 1.01, f32::NAN, f32::INFINITY] {
        let c = GuardConfig {
            max_duty,
            ..config()
        };
        assert_eq!(
            OutputGuard::new(c).err(),
            Some(ParamError::OutOfRange("guard_config")),
            "{max_duty}"
        );
    }
    for ticks in [
        TickLimits {
            max_counts_per_tick: 0,
            ..TICKS
        },
        TickLimits {
            overrun_streak: 0,
            ..TICKS
        },
        TickLimits {
            stuck_ticks: 0,
            ..TICKS
        },
    ] {
        let c = GuardConfig { ticks, ..config() };
        assert!(OutputGuard::new(c).is_err());
    }
    for stuck_duty in [0.0, f32::NAN] {
        assert!(OutputGuard::new(GuardConfig {
            stuck_duty,
            ..config()
        })
        .is_err());
    }
    assert!(OutputGuard::new(GuardConfig {
        max_duty: 1.0,
        ticks: TickLimits {
            max_counts_per_tick: 1,
            overrun_streak: 1,
            stuck_ticks: 1
        },
        ..config()
    })
    .is_ok());
}

#[test]
fn limits_convert_for_the_rate_without_changing_behaviour() {
    let l = Limits::OMEGA_LIKE;
    let t10 = l.per_tick(10_000.0);
    let t20 = l.per_tick(20_000.0);
    assert_eq!(
        t10,
        TickLimits {
            max_counts_per_tick: 200,
            overrun_streak: 10,
            stuck_ticks: 2000
        }
    );
    assert_eq!(
        t20,
        TickLimits {
            max_counts_per_tick: 100,
            overrun_streak: 20,
            stuck_ticks: 4000
        }
    );
    // The same speed, time and duration at either rate.
    assert_eq!(
        f32::from(t10.max_counts_per_tick) * 10_000.0,
        l.glitch_counts_per_s
    );
    assert_eq!(
        f32::from(t20.max_counts_per_tick) * 20_000.0,
        l.glitch_counts_per_s
    );
    // Saturation and the floor of one tick.
    let big = Limits {
        glitch_counts_per_s: 1e12,
        overrun_streak_s: 1e-9,
        ..l
    };
    let t = big.per_tick(1_000.0);
    assert_eq!((t.max_counts_per_tick, t.overrun_streak), (32_767, 1));
    let g = GuardConfig::from_limits(&l, 10_000.0);
    assert_eq!((g.max_duty, g.stuck_duty, g.ticks), (0.9, 0.2, t10));
}

#[test]
fn torque_limit_becomes_a_duty_limit() {
    // kt = 0.02 N·m/A, R = 2 Ω, V = 24 V: 0.1 N·m needs 5 A, i.e. 10 V, i.e. duty 10/24.
    let m = MotorModel {
        kt_nm_per_a: 0.02,
        r_ohm: 2.0,
        v_supply: 24.0,
    };
    let d = m.duty_for_torque(0.1).unwrap_or(f32::NAN);
    // Three roundings of the 0.4167 result: measured 2.98e-8 (1 ulp); bound 3x.
    assert!((d - 10.0 / 24.0).abs() < 9e-8, "{d}");
    let c = GuardConfig {
        max_duty: 0.9,
        ..config()
    }
    .with_torque_limit(0.1, &m);
    assert_eq!(c.map(|c| c.max_duty), Ok(d));
    // A loose torque limit leaves the duty limit in force.
    let c = GuardConfig {
        max_duty: 0.3,
        ..config()
    }
    .with_torque_limit(0.1, &m);
    assert_eq!(c.map(|c| c.max_duty), Ok(0.3));
    // Beyond stall at full duty the torque limit saturates at duty 1.
    assert_eq!(m.duty_for_torque(10.0), Ok(1.0));
    assert_eq!(
        m.duty_for_torque(-0.1),
        Err(ParamError::OutOfRange("motor_model_or_torque"))
    );
    assert_eq!(
        m.duty_for_torque(f32::NAN),
        Err(ParamError::OutOfRange("motor_model_or_torque"))
    );
    let bad = MotorModel { r_ohm: 0.0, ..m };
    assert_eq!(
        bad.duty_for_torque(0.1),
        Err(ParamError::OutOfRange("motor_model_or_torque"))
    );
    // A zero torque limit gives a zero duty limit, which the guard rejects.
    assert_eq!(
        config().with_torque_limit(0.0, &m),
        Err(ParamError::OutOfRange("guard_config"))
    );
}

#[test]
fn phase_enable_maps_sign_and_magnitude() {
    assert_eq!(
        phase_enable(0.5, 6800),
        PhaseEnable {
            forward: true,
            compare: 3400
        }
    );
    assert_eq!(
        phase_enable(-0.25, 6800),
        PhaseEnable {
            forward: false,
            compare: 1700
        }
    );
    assert_eq!(
        phase_enable(0.0, 6800),
        PhaseEnable {
            forward: true,
            compare: 0
        }
    );
    assert_eq!(
        phase_enable(1.0, 6800),
        PhaseEnable {
            forward: true,
            compare: 6800
        }
    );
    assert_eq!(
        phase_enable(-1.0, 6800),
        PhaseEnable {
            forward: false,
            compare: 6800
        }
    );
    // Out of range saturates; non-finite is off.
    assert_eq!(phase_enable(-3.0, 6800).compare, 6800);
    assert_eq!(
        phase_enable(f32::NAN, 6800),
        PhaseEnable {
            forward: true,
            compare: 0
        }
    );
    assert_eq!(phase_enable(f32::NEG_INFINITY, 6800).compare, 0);
    // Rounds to nearest: 0.1 · 6800 = 680 exactly; 1/6800 of full scale is one count.
    assert_eq!(phase_enable(0.1, 6800).compare, 680);
    assert_eq!(phase_enable(1.0 / 6800.0, 6800).compare, 1);
    assert_eq!(phase_enable(0.4 / 6800.0, 6800).compare, 0);
}

#[test]
fn phase_enable_compare_never_exceeds_full_scale() {
    // Every duty step of 1/65536 across [-1, 1] against a 16-bit full scale.
    for k in -65_536i32..=65_536 {
        let d = k as f32 / 65_536.0;
        let p = phase_enable(d, 65_535);
        assert!(p.compare <= 65_535);
        // Independent expectation: |k|·65535/65536 rounded, computed in integers. Tolerance of
        // one count: the f32 product can land on the other side of a .5 rounding boundary.
        let expect = ((k.unsigned_abs() as u64 * 65_535 * 2 + 65_536) / (2 * 65_536)) as u32;
        assert!(
            p.compare.abs_diff(expect) <= 1,
            "k={k}: {} vs {expect}",
            p.compare
        );
    }
}

/// `apply_extension_checked` with the count extension's flags in `events` gives exactly what
/// `apply` gives: a sequence of raw 16-bit readings with steps below, at and above the glitch
/// limit (10 counts), wrapping round the counter, through one extension bank per guard.
#[test]
fn extension_checked_guard_matches_the_full_guard_when_fed_by_the_extension() {
    use crate::device::encoder::EncoderBank;
    let steps: [i32; 12] = [0, 3, -10, 10, 11, -11, 0, 40_000, -7, 2, -30_000, 1];
    let first = [65_530u16, 0, 5, 32_767, 32_768, 100];
    let mut bank = EncoderBank::new(first, TICKS.max_counts_per_tick);
    let (mut full, mut checked) = (guard(), guard());
    let mut raw = first;
    let mut extended = [0i32; 6];
    for (k, step) in steps.iter().enumerate() {
        for (i, r) in raw.iter_mut().enumerate() {
            // Even channels move by `step` counts, odd ones by half of it.
            let s = if i % 2 == 0 { *step } else { *step / 2 };
            *r = r.wrapping_add(s as u16);
        }
        let events = bank.update_into(raw, &mut extended);
        let o = out([0.3, -0.1, 0.0]);
        let a = full.apply(&extended, &o, events, false);
        let b = checked.apply_extension_checked(&extended, &o, events, false);
        assert_eq!(a, b, "tick {k}");
        assert_eq!(full.latched(), checked.latched(), "tick {k}");
    }
    assert!(full.latched().contains(Flags::ENCODER_GLITCH));
}
