//! Controller tick: rendering through the device, and every fault ending in the safe state.

use super::*;
use crate::contact::state::ContactState;
use crate::device::DeviceParams;
use crate::math::Libm;

#[path = "report_tests.rs"]
mod report_tests;

fn controller() -> Controller<Libm, Plane> {
    Controller::new(ControllerConfig::default_plane()).unwrap()
}

/// Encoder counts that put the probe at `p` (base frame), with the wrist at `wrist` counts.
fn counts_at(p: Vec3, wrist: [i32; 3]) -> [i32; 6] {
    let c = DeviceParams::OMEGA_LIKE.counts_at::<Libm>(p, wrist);
    c.unwrap_or_else(|| panic!("{p:?} out of reach"))
}

/// The probe height (base frame) at which the fingertip touches the default plane, minus `depth`.
fn touching(depth: f32) -> Vec3 {
    let cfg = ControllerConfig::default_plane();
    cfg.object_origin_m + Vec3::new(0.0, 0.0, cfg.contact.fingertip_radius_m - depth)
}

fn input(counts: [i32; 6]) -> TickInput {
    TickInput {
        counts,
        ..TickInput::default()
    }
}

#[test]
fn free_space_renders_no_force_and_enables_the_drivers() {
    let mut c = controller();
    let out = c.tick(&input(counts_at(touching(-0.02), [0; 3])));
    assert!(out.enable);
    assert_eq!(out.force_n, Vec3::ZERO);
    assert_eq!(out.duties, [0.0; 3]);
    assert_eq!(out.state, ContactState::Broken);
}

/// 1 mm into the 2000 N/m plane: 2 N up. Encoder quantisation moves the probe by up to ~13 µm per
/// count per axis, i.e. up to ±0.05 N; at this pose the error measures 5.73e-4 N: bound 3x,
/// 1.7e-3 N.
#[test]
fn pressing_renders_the_wall_force_through_the_motors() {
    let mut c = controller();
    let counts = counts_at(touching(0.001), [0; 3]);
    let mut out = TickOutput::default();
    for _ in 0..5 {
        out = c.tick(&input(counts));
    }
    assert!(out.enable);
    assert_eq!(out.state, ContactState::Rolling);
    assert!((out.force_n.z - 2.0).abs() < 1.7e-3, "{:?}", out.force_n);
    assert!(
        out.duties.iter().any(|d| d.abs() > 1e-3),
        "{:?}",
        out.duties
    );
    // Virtual work: the duties are torques/(ratio·k_t)·R/V; with the velocity at rest, τ = Jᵀ·F, so
    // pushing the arms by the duties' direction must move the effector along +z (F·δp > 0).
    let dev = DeviceParams::OMEGA_LIKE;
    let (angles, _) = dev.delta.inverse::<Libm>(touching(0.001));
    let k = 1e-4;
    let moved = [
        angles[0] + k * out.duties[0],
        angles[1] + k * out.duties[1],
        angles[2] + k * out.duties[2],
    ];
    let (p0, _) = dev.delta.forward::<Libm>(angles);
    let (p1, _) = dev.delta.forward::<Libm>(moved);
    assert!(
        (p1 - p0).z > 0.0,
        "duties push the effector up into the finger: {:?}",
        p1 - p0
    );
}

#[test]
fn driver_fault_latches_zero_torque_until_cleared() {
    let mut c = controller();
    let counts = counts_at(touching(0.002), [0; 3]);
    c.tick(&input(counts));
    let out = c.tick(&TickInput {
        counts,
        driver_fault: true,
        overrun: false,
    });
    assert!(!out.enable && out.duties == [0.0; 3] && out.force_n == Vec3::ZERO);
    assert!(out.flags.contains(Flags::DRIVER_FAULT));
    // The fault input going away does not re-enable.
    let out = c.tick(&input(counts));
    assert!(!out.enable && out.duties == [0.0; 3]);
    c.clear_faults();
    let out = c.tick(&input(counts));
    assert!(out.enable);
    assert!(!out.flags.intersects(LATCHING));
}

#[test]
fn an_overrun_streak_latches_but_a_shorter_one_does_not() {
    // 1 ms at 10 kHz: 10 overruns in a row latch, 9 do not.
    let n = Limits::OMEGA_LIKE.per_tick(10_000.0).overrun_streak;
    assert_eq!(n, 10);
    let mut c = controller();
    let counts = counts_at(touching(-0.01), [0; 3]);
    let over = TickInput {
        counts,
        overrun: true,
        driver_fault: false,
    };
    for _ in 0..10 {
        for _ in 0..n - 1 {
            let _ = c.tick(&over);
        }
        let out = c.tick(&input(counts));
        assert!(out.enable, "{} in a row are tolerated", n - 1);
    }
    for _ in 0..n - 1 {
        assert!(c.tick(&over).enable);
    }
    let out = c.tick(&over);
    assert!(!out.enable && out.flags.contains(Flags::OVERRUN));
}

#[test]
fn an_encoder_glitch_latches_and_the_limit_itself_does_not() {
    let lim = i32::from(Limits::OMEGA_LIKE.per_tick(10_000.0).max_counts_per_tick);
    for (jump, faulted) in [(lim, false), (lim + 1, true), (-(lim + 1), true)] {
        let mut c = controller();
        let mut counts = counts_at(touching(-0.01), [0; 3]);
        c.tick(&input(counts));
        counts[4] += jump; // a wrist encoder
        let out = c.tick(&input(counts));
        assert_eq!(!out.enable, faulted, "jump {jump}");
        assert_eq!(out.flags.contains(Flags::ENCODER_GLITCH), faulted);
    }
}

/// Extended counts wrap like the hardware counters: i32::MAX → i32::MIN is a step of one count,
/// not a glitch (wrapping difference), even after hours of wrist rotation.
#[test]
fn counter_wrap_is_not_a_glitch() {
    let mut c = controller();
    let mut counts = counts_at(touching(-0.01), [0; 3]);
    counts[3] = i32::MAX - 3;
    c.tick(&input(counts));
    for _ in 0..8 {
        counts[3] = counts[3].wrapping_add(1);
        let out = c.tick(&input(counts));
        assert!(out.enable, "{:?}", out.flags);
    }
    assert!(counts[3] < 0, "wrapped");
}

/// A motor encoder that stops counting while its motor is driven hard latches ENCODER_STUCK after
/// `stuck_ticks`. Pressing 6 mm deep asks for 12 N: the current limit gives duties of ~0.36.
#[test]
fn an_encoder_stuck_under_drive_latches() {
    let cfg = ControllerConfig {
        limits: Limits {
            stuck_duty: 0.2,
            // 50 ticks at 10 kHz.
            stuck_s: 0.005,
            ..Limits::OMEGA_LIKE
        },
        ..ControllerConfig::default_plane()
    };
    let mut c: Controller<Libm, Plane> = Controller::new(cfg).unwrap();
    let counts = counts_at(touching(0.006), [0; 3]);
    let first = c.tick(&input(counts));
    assert!(
        first.duties.iter().any(|d| d.abs() >= 0.2),
        "{:?}",
        first.duties
    );
    let mut latched_at = None;
    for k in 0..100 {
        let out = c.tick(&input(counts));
        if !out.enable {
            latched_at = Some(k);
            assert!(out.flags.contains(Flags::ENCODER_STUCK));
            assert_eq!(out.duties, [0.0; 3]);
            break;
        }
    }
    assert!(
        matches!(latched_at, Some(k) if (48..=50).contains(&k)),
        "{latched_at:?}"
    );
}

#[test]
fn invalid_parameter_changes_are_rejected_and_flagged_once() {
    let mut c = controller();
    let counts = counts_at(touching(0.001), [0; 3]);
    c.tick(&input(counts));
    let bad = ContactParams {
        mu_s: f32::NAN,
        ..ContactParams::DEFAULT
    };
    // Refused where it arrives (the pipeline's `Command::check`); the controller flags it.
    assert_eq!(bad.checked().err(), Some(ParamError::NotFinite("mu_s")));
    c.params_refused();
    assert_eq!(c.config().contact, ContactParams::DEFAULT);
    let out = c.tick(&input(counts));
    assert!(out.flags.contains(Flags::PARAM_REJECTED) && out.enable);
    let out = c.tick(&input(counts));
    assert!(!out.flags.contains(Flags::PARAM_REJECTED));
    // A valid change takes effect: a stiffer wall pushes harder.
    let stiff = ContactParams {
        normal_stiffness: 4000.0,
        ..ContactParams::DEFAULT
    };
    assert_eq!(
        c.set_contact_params(&stiff.checked().unwrap()),
        Ok(ParamsChange::Restarted)
    );
    let mut out = TickOutput::default();
    for _ in 0..3 {
        out = c.tick(&input(counts));
    }
    // Encoder quantisation at this pose: measured 1.15e-3 N off 4 N; bound 3x.
    assert!((out.force_n.z - 4.0).abs() < 3.4e-3, "{:?}", out.force_n);
}

#[test]
fn invalid_configurations_are_rejected() {
    let d = ControllerConfig::default_plane();
    assert_eq!(
        Controller::<Libm, Plane>::new(ControllerConfig {
            rate_hz: 50_000.0,
            ..d
        })
        .err(),
        Some(ParamError::OutOfRange("rate_hz"))
    );
    assert_eq!(
        Controller::<Libm, Plane>::new(ControllerConfig {
            limits: Limits {
                max_duty: 1.5,
                ..Limits::OMEGA_LIKE
            },
            ..d
        })
        .err(),
        Some(ParamError::OutOfRange("max_duty"))
    );
    let mut dev = DeviceParams::OMEGA_LIKE;
    dev.supply_v = 0.0;
    assert!(matches!(
        Controller::<Libm, Plane>::new(ControllerConfig { device: dev, ..d }).err(),
        Some(ParamError::Device(_))
    ));
}

/// Absurd counts (the arms far outside their range) give no force and no NaN, only a flag.
#[test]
fn unreachable_kinematics_give_zero_force_and_a_flag() {
    let mut c = controller();
    let out = c.tick(&input([1_000_000, -1_000_000, 5, 0, 0, 0]));
    assert!(
        out.flags
            .intersects(Flags::KINEMATICS_SINGULAR | Flags::OUT_OF_RANGE),
        "{:?}",
        out.flags
    );
    assert_eq!(out.duties, [0.0; 3]);
    assert!(out.probe_m.is_finite());
}

/// The default plane is where the host plant's touch script presses: 10 mm below the workspace
/// centre, so a 10 mm fingertip touches with its centre at the workspace centre.
#[test]
fn default_plane_touches_at_the_workspace_centre() {
    let cfg = ControllerConfig::default_plane();
    let centre = crate::device::delta::DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M;
    let touch_z = cfg.object_origin_m.z + cfg.contact.fingertip_radius_m;
    // Measured exact.
    assert_eq!(
        touch_z, centre.z,
        "touch at z = {touch_z}, centre {}",
        centre.z
    );
}
