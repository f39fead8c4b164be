//! Faults end in the documented safe state: the closed-loop campaign (`host-sim faults`) run
//! in-process, plus controller fault sequences the core's unit tests do not cover (the firmware's
//! CountExtender and the controller together over a 32-bit wrap, faults while sliding, a fault
//! that clears and comes back, invalid parameter changes of every field kind).

use host_sim::faults::{campaign_report, closed_loop::scene_config};
use host_sim::plant::TouchScript;
use softfinger_core::contact_state::ContactState;
use softfinger_core::controller::{
    Controller, ControllerConfig, ParamError, TickInput, TickOutput, LATCHING,
};
use softfinger_core::encoder::EncoderBank;
use softfinger_core::params::ContactParams;
use softfinger_core::surface::Plane;
use softfinger_core::{Fast, Flags, Libm, Vec3};

#[test]
fn every_campaign_scenario_survives_without_nan() {
    let r = campaign_report().expect("scenarios set up");
    assert!(r.injected >= 8, "{} scenarios", r.injected);
    let failed: Vec<_> = r
        .scenarios
        .iter()
        .filter(|o| !o.survived)
        .map(|o| format!("{}: {}", o.name, o.detail))
        .collect();
    assert!(failed.is_empty(), "{failed:#?}");
    assert_eq!(r.survived, r.injected);
    assert_eq!(r.nan_outputs, 0);
    // The rescale to the limit rounds in f32: a few ulps above is the limit itself.
    assert!(r.max_force_n <= r.force_limit_n * (1.0 + 1e-6));
    assert!(r.max_plant_force_n <= r.plant_force_limit_n);
}

#[test]
fn the_cli_knows_the_faults_and_soak_commands() {
    // Help exits 0; the campaign itself is checked above through the library function.
    assert_eq!(host_sim::cli::run(["host-sim", "faults", "--help"]), 0);
    assert_eq!(host_sim::cli::run(["host-sim", "soak", "--help"]), 0);
    assert_eq!(host_sim::cli::run(["host-sim", "soak", "--ticks", "x"]), 2);
}

/// The controller of the touch scene.
fn controller() -> Controller<Libm, Plane> {
    Controller::new(scene_config(&TouchScript::default())).expect("valid")
}

/// Motor counts that put the probe `depth` m into the scene's plane at the workspace centre.
fn pressed_counts(depth: f32) -> [i32; 3] {
    let cfg = scene_config(&TouchScript::default());
    let dev = cfg.device;
    let p = cfg.object_origin_m + Vec3::new(0.0, 0.0, cfg.contact.fingertip_radius_m - depth);
    let (a, f) = dev.delta.inverse::<Libm>(p);
    assert!(f.is_empty());
    let step = dev.arm_rad_per_motor_count();
    a.map(|x| libm::roundf((x - dev.arm_angle_at_zero_count_rad) / step) as i32)
}

fn tick(c: &mut Controller<Libm, Plane>, counts: [i32; 6]) -> TickOutput {
    c.tick(&TickInput {
        counts,
        ..TickInput::default()
    })
}

fn safe(out: &TickOutput) -> bool {
    !out.enable && out.duties == [0.0; 3] && out.force_n == Vec3::ZERO
}

/// Hours of wrist motion through the firmware's path: 16-bit hardware counters → EncoderBank →
/// controller. Wrist joint 0 turns continuously at 1999 counts per tick (the fastest motion the
/// glitch limit of 2000 allows), so the 16-bit counters wrap every 33 ticks and the 32-bit
/// extended position wraps after 2³¹/1999 ≈ 1.07 M ticks; at a hand's 1 rev/s (0.41 counts per
/// tick) the same wrap takes 145 h. Meanwhile the motors swing ±300 counts around a press. No
/// glitch, no fault, at any tick; the extended position equals the true motion modulo 2³².
#[test]
fn counter_wraps_through_the_count_extender_never_fault_the_controller() {
    let mut c = controller();
    let base = pressed_counts(0.001);
    let start_raw: [u16; 6] = [65_000, 12, 40_000, 65_535, 0, 7];
    let mut bank = EncoderBank::new(start_raw, 2000);
    let step = 1999i64;
    let ticks = (1i64 << 31) / step + 20_000;
    let mut wrapped = false;
    for k in 1..=ticks {
        // True motion since the start, counts.
        let swing = ((k % 1200) - 600).abs() - 300; // triangle, ±300 counts, 1 count per tick
        let truth: [i64; 6] = [swing, -swing, swing / 2, k * step, 0, -(k % 50)];
        let raw: [u16; 6] =
            std::array::from_fn(|i| (i64::from(start_raw[i]) + truth[i]).rem_euclid(65_536) as u16);
        let (pos, flags) = bank.update(raw);
        assert!(flags.is_empty(), "tick {k}: extender flagged {flags:?}");
        for i in 0..6 {
            assert_eq!(pos[i], truth[i] as i32, "tick {k} axis {i}");
        }
        let counts = [
            base[0] + pos[0],
            base[1] + pos[1],
            base[2] + pos[2],
            pos[3],
            pos[4],
            pos[5],
        ];
        wrapped |= pos[3] < 0;
        let out = tick(&mut c, counts);
        assert!(
            out.enable && !out.flags.intersects(LATCHING),
            "tick {k}: {:?}",
            out.flags
        );
    }
    assert!(wrapped, "the 32-bit position must have wrapped");
}

/// A driver fault while the finger is dragged across the surface (not only while pressing still):
/// zero torque at once, latched after the input clears, and a clear with the fault still
/// asserted latches again on that tick.
#[test]
fn driver_fault_while_dragging_latches_and_relatches_if_still_present() {
    let mut c = controller();
    let m = pressed_counts(0.002);
    let mut counts = [m[0], m[1], m[2], 0, 0, 0];
    let mut out = tick(&mut c, counts);
    for _ in 0..100 {
        counts[1] += 2;
        counts[2] -= 2;
        counts[3] += 1;
        out = tick(&mut c, counts);
    }
    assert!(
        out.state != ContactState::Broken && out.force_n.norm_squared() > 0.0,
        "{out:?}"
    );
    let faulted = c.tick(&TickInput {
        counts,
        driver_fault: true,
        overrun: false,
    });
    assert!(safe(&faulted) && faulted.flags.contains(Flags::DRIVER_FAULT));
    assert!(
        safe(&tick(&mut c, counts)),
        "still latched after the input cleared"
    );
    c.clear_faults();
    let again = c.tick(&TickInput {
        counts,
        driver_fault: true,
        overrun: false,
    });
    assert!(safe(&again), "a fault still present latches again");
    c.clear_faults();
    assert!(tick(&mut c, counts).enable);
}

/// An overrun streak during contact, the streak counter reset by one good tick, and the exact
/// threshold: `overrun_streak − 1` in a row never latches, `overrun_streak` does.
#[test]
fn overrun_streak_threshold_is_exact_during_contact() {
    let mut c = controller();
    let n = c
        .config()
        .limits
        .per_tick(c.config().rate_hz)
        .overrun_streak;
    let m = pressed_counts(0.002);
    let counts = [m[0], m[1], m[2], 0, 0, 0];
    tick(&mut c, counts);
    let over = TickInput {
        counts,
        driver_fault: false,
        overrun: true,
    };
    for _ in 0..50 {
        for _ in 0..n - 1 {
            assert!(c.tick(&over).enable);
        }
        let out = tick(&mut c, counts);
        assert!(out.enable && out.state != ContactState::Broken);
    }
    for i in 0..n {
        let out = c.tick(&over);
        assert_eq!(out.enable, i + 1 < n, "overrun {} of {n}", i + 1);
    }
    assert!(c.latched_faults().contains(Flags::OVERRUN));
}

/// A glitch on each encoder in turn, in both directions, mid-contact: latched on that tick.
#[test]
fn a_glitch_on_any_encoder_latches_on_its_tick() {
    let lim = i32::from(
        ControllerConfig::default_plane()
            .limits
            .per_tick(10_000.0)
            .max_counts_per_tick,
    );
    for axis in 0..6 {
        for sign in [1, -1] {
            let mut c = controller();
            let m = pressed_counts(0.002);
            let mut counts = [m[0], m[1], m[2], 10, -10, 5];
            assert!(tick(&mut c, counts).enable);
            counts[axis] = counts[axis].wrapping_add(sign * (lim + 1));
            let out = tick(&mut c, counts);
            assert!(
                safe(&out) && out.flags.contains(Flags::ENCODER_GLITCH),
                "axis {axis} sign {sign}: {out:?}"
            );
        }
    }
}

/// An encoder stuck while its motor is driven, with the default limits: the frozen motor's duty
/// at a deep press stays above `stuck_duty`, and ENCODER_STUCK latches after `stuck_ticks`.
#[test]
fn a_stuck_encoder_under_drive_latches_with_the_default_limits() {
    let mut c: Controller<Fast, Plane> =
        Controller::new(scene_config(&TouchScript::default())).expect("valid");
    let lim = c.config().limits;
    let m = pressed_counts(0.006); // 12 N asked (the force limit)
    let counts = [m[0], m[1], m[2], 0, 0, 0];
    let first = c.tick(&TickInput {
        counts,
        ..TickInput::default()
    });
    assert!(
        first.duties.iter().any(|d| d.abs() >= lim.stuck_duty),
        "{:?}",
        first.duties
    );
    let mut latched_at = None;
    for k in 1..=lim.per_tick(10_000.0).stuck_ticks + 5 {
        let out = c.tick(&TickInput {
            counts,
            ..TickInput::default()
        });
        if !out.enable {
            assert!(out.flags.contains(Flags::ENCODER_STUCK) && out.duties == [0.0; 3]);
            latched_at = Some(k);
            break;
        }
    }
    assert_eq!(latched_at, Some(lim.per_tick(10_000.0).stuck_ticks));
}

/// Run-time parameter changes with invalid values of every kind, while pressing: each rejected
/// with the field named, flagged once, the old parameters and the rendered force kept.
#[test]
fn invalid_run_time_parameters_are_rejected_and_the_force_is_kept() {
    let mut c = controller();
    let m = pressed_counts(0.001);
    let counts = [m[0], m[1], m[2], 0, 0, 0];
    let mut out = tick(&mut c, counts);
    for _ in 0..5 {
        out = tick(&mut c, counts);
    }
    let force = out.force_n;
    let d = ContactParams::DEFAULT;
    let cases = [
        (
            ContactParams {
                normal_stiffness: f32::NAN,
                ..d
            },
            ParamError::NotFinite("normal_stiffness"),
        ),
        (
            ContactParams {
                normal_stiffness: f32::INFINITY,
                ..d
            },
            ParamError::NotFinite("normal_stiffness"),
        ),
        (
            ContactParams {
                normal_stiffness: 1e30,
                ..d
            },
            ParamError::OutOfRange("normal_stiffness"),
        ),
        (
            ContactParams {
                max_force_n: -1.0,
                ..d
            },
            ParamError::NotPositive("max_force_n"),
        ),
        (
            ContactParams {
                fingertip_radius_m: 1e-9,
                ..d
            },
            ParamError::OutOfRange("fingertip_radius_m"),
        ),
        (
            ContactParams { mu_k: 2.0, ..d },
            ParamError::KineticAboveStatic,
        ),
    ];
    let before = *c.config();
    for (p, e) in cases {
        assert_eq!(c.set_contact_params(p), Err(e));
        let o = tick(&mut c, counts);
        assert!(o.flags.contains(Flags::PARAM_REJECTED) && o.enable, "{o:?}");
        // Same counts, same parameters: the same force (2 N at 1 mm; quantisation aside).
        assert_eq!(o.force_n, force);
        assert!(!tick(&mut c, counts).flags.contains(Flags::PARAM_REJECTED));
    }
    assert_eq!(*c.config(), before);
}
