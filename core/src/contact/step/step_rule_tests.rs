//! Contact step rules pinned one at a time, each against its closed form: the input range gates,
//! the normal force law (spring, damping sign, zero at zero penetration), the tangential coupling's
//! damping, and the inputs the state machine receives from the step (separation by acceleration,
//! the slip velocity in rolling, the haptic sign rule, the twist threshold). Every threshold is
//! bracketed just below and just above.

use super::*;
use crate::contact::surface::Plane;
use crate::math::Libm;

const DT: f32 = 1e-4; // 10 kHz
const P: ContactParams = ContactParams::DEFAULT;

fn model() -> ContactModel<Libm, Plane> {
    ContactModel::new(P, Plane::default(), Quat::IDENTITY, DT).unwrap()
}

pub(super) fn sample(q: Quat, probe: Vec3, vel: Vec3) -> ContactInput {
    ContactInput {
        q,
        probe_m: probe,
        probe_vel: vel,
    }
}

/// Probe centre `pen_m` below the free position z = ρ (plane z = 0).
pub(super) fn pressed(x: f32, pen_m: f32) -> Vec3 {
    Vec3::new(x, 0.0, P.fingertip_radius_m - pen_m)
}

/// A model in rolling contact at the origin, 1 mm deep, with probe velocity `vel` from the start
/// (so the acceleration the step sees afterwards is zero while `vel` is kept).
fn touching(vel: Vec3) -> ContactModel<Libm, Plane> {
    let mut m = model();
    let o = m.contact_step(&sample(Quat::IDENTITY, pressed(0.0, 0.001), vel));
    assert_eq!(
        (o.state, o.reason),
        (ContactState::Rolling, Reason::MadeContact)
    );
    m
}

#[test]
fn probe_position_gate_is_the_euclidean_norm_against_max_probe_m() {
    for (r, flagged) in [(0.5 * MAX_PROBE_M, false), (MAX_PROBE_M * 1.001, true)] {
        let mut m = model();
        let o = m.contact_step(&sample(Quat::IDENTITY, Vec3::new(r, 0.0, 0.0), Vec3::ZERO));
        assert_eq!(
            o.flags.contains(Flags::OUT_OF_RANGE),
            flagged,
            "|p| = {r} m"
        );
    }
}

#[test]
fn probe_speed_gate_is_the_euclidean_norm_against_max_probe_speed() {
    // 0.5·max is far above 1 m/s and √(2·max) m/s: the gate is max², nothing smaller.
    for (v, flagged) in [
        (0.5 * MAX_PROBE_SPEED_M_S, false),
        (MAX_PROBE_SPEED_M_S * 1.001, true),
    ] {
        let mut m = model();
        let o = m.contact_step(&sample(
            Quat::IDENTITY,
            Vec3::new(0.0, 0.0, 0.05),
            Vec3::new(0.0, v, 0.0),
        ));
        assert_eq!(
            o.flags.contains(Flags::OUT_OF_RANGE),
            flagged,
            "|v| = {v} m/s"
        );
    }
}

/// f_N = K·δ − B·v_n: pressing in (v_n < 0) adds damping force, pulling out removes it.
#[test]
fn normal_damping_opposes_the_normal_velocity() {
    for v_n in [-0.1f32, 0.1] {
        let mut m = touching(Vec3::ZERO);
        let o = m.contact_step(&sample(
            Quat::IDENTITY,
            pressed(0.0, 0.001),
            Vec3::new(0.0, 0.0, v_n),
        ));
        let expected = P.normal_stiffness * 0.001 - P.normal_damping * v_n;
        // f32 arithmetic on O(1) N: measured 2.38e-7 N (2 ulp); bound 3x, 7.2e-7 N.
        assert!(
            (o.force_n.z - expected).abs() < 7.2e-7,
            "v_n {v_n}: {} vs {expected}",
            o.force_n.z
        );
    }
}

/// At exactly zero penetration there is no normal force, however fast the probe moves in.
#[test]
fn zero_penetration_gives_no_normal_force_even_moving_in() {
    let mut m = touching(Vec3::ZERO);
    let surface_touch = Vec3::new(0.0, 0.0, P.fingertip_radius_m);
    assert_eq!(
        Plane::default().penetration::<Libm>(surface_touch, P.fingertip_radius_m),
        0.0
    );
    let o = m.contact_step(&sample(
        Quat::IDENTITY,
        surface_touch,
        Vec3::new(0.0, 0.0, -0.5),
    ));
    assert_eq!(o.force_n.z, 0.0);
    // Just inside, the damping force appears: K·δ + B·0.5.
    let o = m.contact_step(&sample(
        Quat::IDENTITY,
        pressed(0.0, 1e-6),
        Vec3::new(0.0, 0.0, -0.5),
    ));
    assert!(
        o.force_n.z > 0.9 * P.normal_damping * 0.5,
        "{}",
        o.force_n.z
    );
}

/// The coupling spring's damper acts on the anchor's velocity relative to the probe: a probe
/// moving at v over a still anchor feels −B_t·v.
#[test]
fn tangential_damping_opposes_the_probe_velocity_over_the_anchor() {
    let v = Vec3::new(0.01, 0.0, 0.0);
    let mut m = touching(v);
    let o = m.contact_step(&sample(Quat::IDENTITY, pressed(0.0, 0.001), v));
    assert_eq!(o.state, ContactState::Rolling);
    let expected = -P.tangential_damping * 0.01;
    // Measured exact (the same f32 product); bound |expected|·ε (1-2 ulp), an ulp argument.
    assert!(
        (o.force_n.x - expected).abs() <= expected.abs() * f32::EPSILON,
        "{} vs {expected}",
        o.force_n.x
    );
}

/// Separation needs f_N ≤ ε_f and, with the gap still within ε_gap, a separating normal
/// acceleration a_N > ε_a: (v − v_prev)/T along +n.
#[test]
fn separation_within_the_gap_tolerance_is_told_by_the_acceleration_sign() {
    let gap = 0.5 * P.tolerances.gap_eps_m;
    for (v_n, separated) in [(0.01f32, true), (-0.01, false)] {
        let mut m = touching(Vec3::ZERO);
        let o = m.contact_step(&sample(
            Quat::IDENTITY,
            pressed(0.0, -gap),
            Vec3::new(0.0, 0.0, v_n),
        ));
        // a_N = ±0.01/1e-4 = ±100 m/s², far beyond ε_a = 0.05 either way.
        let expected = if separated {
            (ContactState::Broken, Reason::Separated)
        } else {
            (ContactState::Rolling, Reason::Kept)
        };
        assert_eq!((o.state, o.reason), expected, "v_n {v_n}");
    }
}

/// Rolling, outside the static cone, at constant velocity (no acceleration): the contact slides
/// only if the probe slips over the rolling fingertip. A probe moving with the anchor (the wrist
/// rolls at the probe's speed, v = ρ·ω) does not slip; a probe moving alone does.
#[test]
fn slip_velocity_in_rolling_is_the_probe_over_the_rolling_anchor() {
    let stick = P.tolerances.stick_speed;
    let v = 3.0 * stick;
    let omega = v / P.fingertip_radius_m; // 0.6 rad/s: tilt rate far below the twist threshold.
                                          // Offset so |f_T| = 1.5·μ_s·f_N (outside the cone with its 5 % hysteresis).
    let f_n = P.normal_stiffness * 0.001;
    let d = 1.5 * P.mu_s * f_n / P.tangential_stiffness;
    for (wrist_rolls, slides) in [(true, false), (false, true)] {
        let mut m = touching(Vec3::new(v, 0.0, 0.0));
        let q = if wrist_rolls {
            Quat::from_axis_angle::<Libm>(Vec3::Y, omega * DT)
        } else {
            Quat::IDENTITY
        };
        let o = m.contact_step(&sample(q, pressed(d, 0.001), Vec3::new(v, 0.0, 0.0)));
        let expected = if slides {
            (ContactState::Sliding, Reason::ConeExceeded)
        } else {
            (ContactState::Rolling, Reason::Kept)
        };
        assert_eq!((o.state, o.reason), expected, "wrist rolls: {wrist_rolls}");
    }
}

/// The haptic sign rule: outside the cone, a rolling contact slides only if its rolling
/// displacement does not oppose the force the user applies (probe − anchor, along +x here).
#[test]
fn haptic_rule_slides_only_when_rolling_agrees_with_the_user_force() {
    let f_n = P.normal_stiffness * 0.001;
    let d = 1.5 * P.mu_s * f_n / P.tangential_stiffness;
    let v = Vec3::new(0.05, 0.0, 0.0); // moving: |v| ≫ v_stick
                                       // About +y the contact rolls towards +x (with the user's force), about −y against it.
    for (angle, slides) in [(1e-4f32, true), (-1e-4, false)] {
        let mut m = touching(v);
        let q = Quat::from_axis_angle::<Libm>(Vec3::Y, angle);
        let o = m.contact_step(&sample(q, pressed(d, 0.001), v));
        assert_slides(&o, slides, &std::format!("roll {angle} rad"));
    }
}

/// Twist threshold through the step: the tilt rate is δξ/T, and rolling → sliding when
/// δξ/T > f_N·μ_s/(k_τ·ρ). Bracketed at 0.95 and 1.05 of the threshold.
#[test]
fn tilt_rate_threshold_is_bracketed_through_the_step() {
    let f_n = P.normal_stiffness * 0.001;
    let rate = f_n * P.mu_s / (P.k_tau * P.fingertip_radius_m); // 40 rad/s
    for (factor, slides) in [(0.95f32, false), (1.05, true)] {
        let mut m = touching(Vec3::ZERO);
        let q = Quat::from_axis_angle::<Libm>(Vec3::Y, factor * rate * DT);
        let o = m.contact_step(&sample(q, pressed(0.0, 0.001), Vec3::ZERO));
        let expected = if slides {
            (ContactState::Sliding, Reason::TwistExceeded)
        } else {
            (ContactState::Rolling, Reason::Kept)
        };
        assert_eq!((o.state, o.reason), expected, "{factor} of the threshold");
    }
}

/// While apart, the model tracks the wrist: touching down after the wrist turned, the contact is
/// placed with the current orientation, so holding still afterwards rolls nothing.
#[test]
fn orientation_is_tracked_while_apart() {
    let mut m = model();
    let far = Vec3::new(0.0, 0.0, 0.05);
    let mut q = Quat::IDENTITY;
    for k in 1..=100 {
        q = Quat::from_axis_angle::<Libm>(Vec3::Y, 0.3 * k as f32 / 100.0);
        let o = m.contact_step(&sample(q, far, Vec3::ZERO));
        assert_eq!(o.state, ContactState::Broken);
    }
    let o = m.contact_step(&sample(q, pressed(0.002, 0.001), Vec3::ZERO));
    assert_eq!(o.reason, Reason::MadeContact);
    let placed = o.object_point_m;
    // Measured exact.
    assert_eq!(placed, Vec3::new(0.002, 0.0, 0.0), "{placed:?}");
    let o = m.contact_step(&sample(q, pressed(0.002, 0.001), Vec3::ZERO));
    assert_eq!(o.object_point_m, placed);
    assert_eq!(o.force_n.x, 0.0);
}

/// A non-finite orientation sample leaves the whole model as it was (the doc's contract), in
/// every state.
#[test]
fn a_bad_orientation_sample_changes_no_state() {
    let bad = Quat {
        w: f32::NAN,
        ..Quat::IDENTITY
    };
    let mut apart = model();
    apart.contact_step(&sample(
        Quat::IDENTITY,
        Vec3::new(0.001, 0.0, 0.05),
        Vec3::ZERO,
    ));
    for mut m in [apart, touching(Vec3::ZERO)] {
        let before = std::format!("{m:?}");
        let o = m.contact_step(&sample(
            bad,
            pressed(0.004, 0.001),
            Vec3::new(0.1, 0.0, 0.0),
        ));
        assert!(o.flags.contains(Flags::NON_FINITE_INPUT));
        assert_eq!(std::format!("{m:?}"), before);
    }
}

/// Twist the pressed fingertip about the normal by `angle` (rad) in steps of 1 mrad, probe still.
fn twisted(angle: f32) -> (ContactModel<Libm, Plane>, Quat, ContactOutput) {
    let mut m = touching(Vec3::ZERO);
    let n = (angle / 1e-3) as usize;
    let mut q = Quat::IDENTITY;
    let mut o = ContactOutput::default();
    for k in 1..=n {
        q = Quat::from_axis_angle::<Libm>(Vec3::Z, angle * k as f32 / n as f32);
        o = m.contact_step(&sample(q, pressed(0.0, 0.001), Vec3::ZERO));
        assert_eq!(o.state, ContactState::Rolling);
    }
    (m, q, o)
}

/// One friction budget in the rolling → sliding rule: the trial spin torque the step hands the
/// state machine is k_z·(elastic twist + this step's spin). With the twist held at 0.6 of the
/// torsional limit, a tangential load of 0.75 of the cone stays inside the static ellipse
/// (0.75² + 0.6² < 1.05²) and 0.9 of it leaves it (0.9² + 0.6² > 1.05²), though both are inside
/// the cone alone.
#[test]
fn twist_held_in_the_spring_shrinks_the_tangential_budget() {
    // τ_max at this normal force: where the torque stops growing under a slow twist.
    let (_, _, o) = twisted(1.0);
    assert!(o.flags.contains(Flags::SPIN_SATURATED), "1 rad saturates");
    let tau_max = o.tau_n_nm.abs();
    let f_n = P.normal_stiffness * 0.001;
    for (load, slides) in [(0.75f32, false), (0.9, true)] {
        let (mut m, q, o) = twisted(0.6 * tau_max / P.spin_stiffness);
        assert!(
            // Measured 1.19e-7 (1 ulp); bound 3x.
            (o.tau_n_nm.abs() / tau_max - 0.6).abs() < 3.6e-7,
            "{}",
            o.tau_n_nm
        );
        let d = load * P.mu_s * f_n / P.tangential_stiffness;
        let v = Vec3::new(0.05, 0.0, 0.0);
        m.contact_step(&sample(q, pressed(0.0, 0.001), v));
        let o = m.contact_step(&sample(q, pressed(d, 0.001), v));
        assert_slides(&o, slides, &std::format!("load {load}"));
    }
}

/// Within the re-contact dwell (t_broken after a break) the state stays broken, but a probe pressed
/// back in beyond the make force by the spring alone (K·δ > f_make) gets the normal force: the
/// dwell holds back friction, rolling and spin, never the wall. Bracketed at 0.99 and 1.01 of
/// f_make/K; a pressing velocity that lifts K·δ − B·v_n above f_make while K·δ is below it renders
/// nothing (the gate is the spring, so velocity noise on a hovering probe does not count).
#[test]
fn wall_stays_solid_through_the_recontact_dwell() {
    let k = P.normal_stiffness;
    let make = P.tolerances.make_force_n;
    let lifted = || {
        let mut m = touching(Vec3::ZERO);
        let o = m.contact_step(&sample(Quat::IDENTITY, pressed(0.0, -0.001), Vec3::ZERO));
        assert_eq!(o.state, ContactState::Broken, "{o:?}");
        assert_eq!(o.force_n, Vec3::ZERO);
        m
    };
    // Just above the make force, one tick (0.1 ms < t_broken) after the break.
    let depth = 1.01 * make / k;
    let mut m = lifted();
    let o = m.contact_step(&sample(Quat::IDENTITY, pressed(0.0, depth), Vec3::ZERO));
    assert_eq!((o.state, o.reason), (ContactState::Broken, Reason::Kept));
    assert_eq!((o.force_n.x, o.force_n.y, o.tau_n_nm), (0.0, 0.0, 0.0));
    // K·δ exactly (no velocity, no damping); 1 ulp-level rounding of the product.
    assert!((o.force_n.z - k * depth).abs() <= 1e-6 * k * depth, "{o:?}");
    // Just below: nothing, also when pressing in fast enough that K·δ − B·v_n exceeds f_make.
    let depth = 0.99 * make / k;
    let v_in = -2.0 * make / P.normal_damping;
    for vel in [Vec3::ZERO, Vec3::new(0.0, 0.0, v_in)] {
        let mut m = lifted();
        let o = m.contact_step(&sample(Quat::IDENTITY, pressed(0.0, depth), vel));
        assert_eq!(o.state, ContactState::Broken, "{o:?}");
        assert_eq!(o.force_n, Vec3::ZERO, "v = {vel:?}");
    }
}

/// The dwell's force gate is open strictly above f_make, as the make rule itself: at K·δ = f_make
/// exactly nothing, one ulp of depth deeper the normal force. Exact in f32 with K = 2¹¹ N/m,
/// f_make = 2⁻⁴ N and δ = 2⁻¹⁵ m (ρ − δ and ρ − (ρ − δ) are exact: same binade, Sterbenz).
#[test]
fn dwell_force_gate_is_strict_at_the_make_force() {
    let mut p = P;
    p.normal_stiffness = 2048.0;
    p.tolerances.make_force_n = 0.0625;
    let depth = 1.0 / 32_768.0;
    assert_eq!(p.normal_stiffness * depth, p.tolerances.make_force_n);
    for (z, expect_force) in [
        (p.fingertip_radius_m - depth, false),
        (libm::nextafterf(p.fingertip_radius_m - depth, 0.0), true),
    ] {
        let mut m =
            ContactModel::<Libm, Plane>::new(p, Plane::default(), Quat::IDENTITY, DT).unwrap();
        let at = |z: f32| sample(Quat::IDENTITY, Vec3::new(0.0, 0.0, z), Vec3::ZERO);
        let o = m.contact_step(&at(p.fingertip_radius_m - 0.001));
        assert_eq!(o.state, ContactState::Rolling, "{o:?}");
        let o = m.contact_step(&at(p.fingertip_radius_m + 0.001));
        assert_eq!(o.state, ContactState::Broken, "{o:?}");
        let o = m.contact_step(&at(z));
        assert_eq!(o.state, ContactState::Broken, "{o:?}");
        assert_eq!(o.force_n.z > 0.0, expect_force, "z = {z}: {o:?}");
    }
}
