//! What the controller reports and keeps between ticks, against closed forms: the probe velocity
//! filter, the contact point in the base frame, the latched faults, the restart; and the limits'
//! validation bracketed at its edges.

use super::*;

/// α of the velocity filter from its definition: 2π·f_c·T/(1 + 2π·f_c·T).
fn alpha(c: &Controller<Libm, Plane>) -> f32 {
    let wt =
        2.0 * core::f32::consts::PI * c.config().limits.velocity_cutoff_hz / c.config().rate_hz;
    wt / (1.0 + wt)
}

/// One motor count of travel after rest: the filtered velocity is α·Δp/T on that tick and decays
/// by (1 − α) per tick afterwards (v ← v + α·(Δp/T − v)). Δp is read from the ticks' own probe
/// positions. Measured relative error ≤ 9.4e-8 over the five ticks (f32); bound 3e-7.
#[test]
fn probe_velocity_is_the_first_order_filter_of_the_probe_steps() {
    let mut c = controller();
    let c0 = counts_at(touching(-0.005), [0; 3]);
    let mut c1 = c0;
    c1[0] += 1;
    let p0 = (0..3).map(|_| c.tick(&input(c0)).probe_m).last().unwrap();
    assert_eq!(c.probe_velocity(), Vec3::ZERO, "at rest");
    let p1 = c.tick(&input(c1)).probe_m;
    let a = alpha(&c);
    let mut expected = (p1 - p0) * (a * c.config().rate_hz);
    assert!(expected.norm_squared() > 0.0);
    for k in 0..5 {
        let v = c.probe_velocity();
        let err = (v - expected).norm::<Libm>() / expected.norm::<Libm>();
        assert!(err < 3e-7, "tick {k}: {v:?} vs {expected:?}");
        c.tick(&input(c1));
        expected = expected * (1.0 - a);
    }
}

/// The contact point is reported in the base frame: the object-frame point plus the object's
/// origin. Pressed at a probe position, the contact sits under the probe on the plane, z = the
/// plane's height in the base frame. Measured exact; bound |expected|·ε (1-2 ulp), an ulp
/// argument.
#[test]
fn the_contact_point_is_reported_in_the_base_frame() {
    let mut c = controller();
    let counts = counts_at(touching(0.001), [0; 3]);
    let out = c.tick(&input(counts));
    assert_eq!(out.state, ContactState::Rolling);
    let origin = c.config().object_origin_m;
    assert!(
        origin.z.abs() > 0.05,
        "a plane away from the base origin: {origin:?}"
    );
    let expected = Vec3::new(out.probe_m.x, out.probe_m.y, origin.z);
    let cp = c.contact_point_m();
    assert!(
        (cp - expected).norm::<Libm>() <= expected.norm::<Libm>() * f32::EPSILON,
        "{cp:?} vs {expected:?}"
    );
}

#[test]
fn latched_faults_are_reported_until_cleared() {
    let mut c = controller();
    let counts = counts_at(touching(0.002), [0; 3]);
    c.tick(&input(counts));
    assert_eq!(c.latched_faults(), Flags::NONE);
    c.tick(&TickInput {
        counts,
        driver_fault: true,
        overrun: false,
    });
    assert!(c.latched_faults().contains(Flags::DRIVER_FAULT));
    c.tick(&input(counts));
    assert!(c.latched_faults().contains(Flags::DRIVER_FAULT), "latched");
    c.clear_faults();
    assert_eq!(c.latched_faults(), Flags::NONE);
}

/// A restart forgets the velocity history and breaks the contact: a jump of the probe across a
/// restart (a re-homing) is no velocity, and the contact is made afresh where the probe is.
#[test]
fn a_restart_forgets_the_velocity_and_the_contact() {
    let mut c = controller();
    let here = counts_at(touching(0.001), [0; 3]);
    let there = counts_at(touching(0.001) + Vec3::new(0.002, 0.0, 0.0), [0; 3]);
    for _ in 0..3 {
        c.tick(&input(here));
    }
    c.restart();
    let out = c.tick(&input(there));
    assert_eq!(c.probe_velocity(), Vec3::ZERO);
    assert_eq!(out.state, ContactState::Rolling);
    // Measured exactly 0.
    assert_eq!(
        out.force_n.x, 0.0,
        "no drag from the old anchor: {:?}",
        out.force_n
    );
    // Without the restart the same jump is a velocity and drags the old anchor.
    let mut c = controller();
    for _ in 0..3 {
        c.tick(&input(here));
    }
    let out = c.tick(&input(there));
    assert!(c.probe_velocity().x > 1.0, "{:?}", c.probe_velocity());
    assert!(
        out.force_n.x.abs() > 0.5 || out.state != ContactState::Rolling,
        "{out:?}"
    );
}

/// max_duty ∈ (0, 1]: 1 is allowed, the next float above it is not.
#[test]
fn max_duty_is_allowed_up_to_one_exactly() {
    for (d, ok) in [(1.0f32, true), (1.0f32.next_up(), false)] {
        let l = Limits {
            max_duty: d,
            ..Limits::OMEGA_LIKE
        };
        assert_eq!(l.validate().is_ok(), ok, "max_duty {d}");
    }
}

/// Either end of the arm-angle range non-finite is rejected as such (not as an empty range).
#[test]
fn a_non_finite_arm_angle_bound_is_rejected() {
    for range in [
        [f32::NAN, 2.1],
        [-1.05, f32::NAN],
        [-1.05, f32::INFINITY],
        [f32::NEG_INFINITY, 2.1],
    ] {
        let l = Limits {
            arm_angle_range_rad: range,
            ..Limits::OMEGA_LIKE
        };
        assert_eq!(
            l.validate(),
            Err(ParamError::NotFinite("arm_angle_range_rad")),
            "{range:?}"
        );
    }
    assert_eq!(Limits::OMEGA_LIKE.validate(), Ok(()));
}

/// Pressed 1 mm (a force is rendered when the kinematics is trusted) with the arm-angle range
/// ending one float below the largest arm angle of the pose: OUT_OF_RANGE alone (the kinematics
/// itself solves) gives no force and zero duties; with the range ending at that angle (inclusive)
/// the force is rendered.
#[test]
fn an_arm_angle_out_of_range_alone_untrusts_the_kinematics() {
    let counts = counts_at(touching(0.001), [0; 3]);
    let dev = DeviceParams::OMEGA_LIKE;
    let top = (0..3)
        .map(|i| dev.motor_counts_to_arm_angle_rad(counts[i]))
        .fold(f32::NEG_INFINITY, f32::max);
    for (hi, trusted) in [(top.next_down(), false), (top, true)] {
        let mut cfg = ControllerConfig::default_plane();
        cfg.limits.arm_angle_range_rad = [-1.05, hi];
        let mut c: Controller<Libm, Plane> = Controller::new(cfg).unwrap();
        let out = (0..3).map(|_| c.tick(&input(counts))).last().unwrap();
        assert!(
            !out.flags.contains(Flags::KINEMATICS_SINGULAR),
            "{:?}",
            out.flags
        );
        assert_eq!(
            out.flags.contains(Flags::OUT_OF_RANGE),
            !trusted,
            "{:?}",
            out.flags
        );
        if trusted {
            assert!(out.force_n.z > 1.5, "{:?}", out.force_n);
        } else {
            assert_eq!(out.force_n, Vec3::ZERO);
            assert_eq!(out.duties, [0.0; 3]);
        }
    }
}

/// Arm angles inside the allowed range (widened here to ±3.1 rad) whose elbows cannot meet (no
/// forward-kinematics solution): KINEMATICS_SINGULAR alone gives no force and zero duties, and
/// the contact stage is not stepped with that pose: a rolling contact is reported as it was and
/// goes on rolling when the kinematics solves again.
#[test]
fn singular_kinematics_alone_untrusts_the_kinematics() {
    let dev = DeviceParams::OMEGA_LIKE;
    let per = dev.arm_rad_per_motor_count();
    let count = |a: f32| libm::roundf((a - dev.arm_angle_at_zero_count_rad) / per) as i32;
    // The first pose of a coarse grid over the range that has no solution.
    let grid = |i: i32| -3.0 + 0.5 * i as f32;
    let mut found = None;
    'search: for i in 0..13 {
        for j in 0..13 {
            for k in 0..13 {
                let a = [grid(i), grid(j), grid(k)];
                let (_, f) = dev.delta.forward::<Libm>(a);
                if f.contains(Flags::KINEMATICS_SINGULAR) {
                    found = Some([count(a[0]), count(a[1]), count(a[2]), 0, 0, 0]);
                    break 'search;
                }
            }
        }
    }
    let counts = found.expect("a pose without a solution inside the range");
    let mut cfg = ControllerConfig::default_plane();
    cfg.limits.arm_angle_range_rad = [-3.1, 3.1];
    let mut c: Controller<Libm, Plane> = Controller::new(cfg).unwrap();
    let pressed = counts_at(touching(0.001), [0; 3]);
    assert_eq!(c.tick(&input(pressed)).state, ContactState::Rolling);
    let out = c.tick(&input(counts));
    assert_eq!(
        out.state,
        ContactState::Rolling,
        "the contact stage was not stepped"
    );
    assert!(
        out.flags.contains(Flags::KINEMATICS_SINGULAR),
        "{:?}",
        out.flags
    );
    assert!(!out.flags.contains(Flags::OUT_OF_RANGE), "{:?}", out.flags);
    assert_eq!(out.force_n, Vec3::ZERO);
    assert_eq!(out.duties, [0.0; 3]);
    assert_eq!(c.tick(&input(pressed)).state, ContactState::Rolling);
}

/// The joint-torque limit, bracketed at the pose's own largest torque: a limit equal to it
/// raises no OUTPUT_LIMITED (only a torque above the limit is limited), one float below it does.
/// The torques are recomputed from the tick's force and pose with the same kinematics.
#[test]
fn the_joint_torque_limit_is_bracketed_at_the_largest_torque() {
    let counts = counts_at(touching(0.001), [0; 3]);
    let dev = DeviceParams::OMEGA_LIKE;
    let mut c = controller();
    let out = (0..3).map(|_| c.tick(&input(counts))).last().unwrap();
    assert!(
        !out.flags.contains(Flags::OUTPUT_LIMITED),
        "{:?}",
        out.flags
    );
    let angles = [0, 1, 2].map(|i| dev.motor_counts_to_arm_angle_rad(counts[i]));
    let (pose, _) = dev.delta.pose::<Libm>(angles);
    let (torques, f) = dev.delta.torques_at(&pose, out.force_n);
    assert!(f.is_empty());
    let top = torques.iter().fold(0.0f32, |m, t| m.max(t.abs()));
    assert!(top > 0.0);
    for (limit, limited) in [(top, false), (top.next_down(), true)] {
        let mut cfg = ControllerConfig::default_plane();
        cfg.limits.max_arm_torque_nm = limit;
        let mut c: Controller<Libm, Plane> = Controller::new(cfg).unwrap();
        let o = (0..3).map(|_| c.tick(&input(counts))).last().unwrap();
        assert_eq!(o.force_n, out.force_n, "the same force at the same pose");
        assert_eq!(
            o.flags.contains(Flags::OUTPUT_LIMITED),
            limited,
            "limit {limit}"
        );
    }
}

/// The spin torque is reported through the guard and scaled by the arming ramp like the force:
/// twisting the pressed wrist gives τn ≠ 0, and at force scale 0.5 exactly half of it.
#[test]
fn the_spin_torque_is_reported_and_scaled_by_the_arming_ramp() {
    let pressed = counts_at(touching(0.001), [0; 3]);
    let run = |scale: f32| {
        let mut c = controller();
        c.set_force_scale(scale);
        let mut out = c.tick(&input(pressed));
        for w in 1..=20 {
            // A wrist twist of `w` counts on the first wrist axis.
            let mut counts = pressed;
            counts[3] = w;
            out = c.tick(&input(counts));
        }
        out
    };
    let (full, half) = (run(1.0), run(0.5));
    assert_eq!(full.state, ContactState::Rolling);
    assert!(full.tau_n_nm.abs() > 1e-5, "{full:?}");
    assert_eq!(half.tau_n_nm, 0.5 * full.tau_n_nm);
}

/// The passivity observer starts from the energy stored in the stiffest spring of the contact:
/// E = −|F|²/(2·max(K_n, K_t)) on the first tick it sees a force (no motion yet). Measured exact;
/// bound 2 ulp (2.4e-7 relative), an ulp argument.
#[test]
fn the_passivity_observer_starts_from_the_stiffest_springs_energy() {
    let mut c = controller();
    let out = c.tick(&input(counts_at(touching(0.001), [0; 3])));
    assert!(out.force_n.z > 1.5);
    let p = &c.config().contact;
    let k = p.normal_stiffness.max(p.tangential_stiffness);
    let expected = -0.5 * out.force_n.norm_squared() / k;
    let e = c.passivity().energy_j();
    assert!((e / expected - 1.0).abs() < 2.4e-7, "{e} vs {expected}");
}

/// The arm velocities are the same first-order filter of the arm-angle steps, and they feed the
/// back-EMF term of the duties: in free space (no force, so no torque), one count of motor 0
/// gives duty₀ = k_e·N·v/V with v = α·Δθ/T on that tick and (1 − α)·v the next, and the other
/// motors stay at 0. Measured relative error 0 (the same f32 operations); bound 3.6e-7, three
/// ulps, so a reordering of the arithmetic does not fail it while a wrong filter does.
#[test]
fn arm_velocities_filter_the_angle_steps_into_the_back_emf_duty() {
    let dev = DeviceParams::OMEGA_LIKE;
    let mut c = controller();
    let c0 = counts_at(touching(-0.005), [0; 3]);
    let mut c1 = c0;
    c1[0] += 1;
    for _ in 0..3 {
        c.tick(&input(c0));
    }
    let a = alpha(&c);
    let dtheta =
        dev.motor_counts_to_arm_angle_rad(c1[0]) - dev.motor_counts_to_arm_angle_rad(c0[0]);
    let m = &dev.motor;
    let mut v = a * dtheta * c.config().rate_hz;
    for k in 0..2 {
        let out = c.tick(&input(c1));
        assert_eq!(out.force_n, Vec3::ZERO);
        let expected = m.back_emf_v_s_per_rad * m.capstan_ratio * v / dev.supply_v;
        let err = (out.duties[0] / expected - 1.0).abs();
        assert!(
            err < 3.6e-7,
            "tick {k}: {} vs {expected} ({err:e})",
            out.duties[0]
        );
        assert_eq!([out.duties[1], out.duties[2]], [0.0; 2]);
        v *= 1.0 - a;
    }
}

/// A fault zeroes the reported spin torque with the force: twisted and pressed (τn ≠ 0), the tick
/// with nFAULT reports τn = 0, and so does every tick until the faults are cleared.
#[test]
fn a_fault_zeroes_the_reported_spin_torque() {
    let pressed = counts_at(touching(0.001), [0; 3]);
    let mut c = controller();
    c.tick(&input(pressed));
    let mut twisted = pressed;
    let mut out = TickOutput::default();
    for w in 1..=20 {
        twisted[3] = w;
        out = c.tick(&input(twisted));
    }
    assert!(out.tau_n_nm.abs() > 1e-5, "{out:?}");
    let out = c.tick(&TickInput {
        counts: twisted,
        driver_fault: true,
        overrun: false,
    });
    assert!(!out.enable);
    assert_eq!((out.force_n, out.tau_n_nm), (Vec3::ZERO, 0.0));
    assert_eq!(c.tick(&input(twisted)).tau_n_nm, 0.0);
}
