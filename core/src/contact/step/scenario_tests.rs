//! Contact step scenarios that pin what the state machine's table cannot see: the entry actions
//! (placing the contact under the probe, dragging the sliding proxy), the tilt rate the twist
//! threshold receives, the anchor's motion on a curved surface, and what early returns report.

use super::*;
use crate::contact::surface::{Plane, Sphere};
use crate::math::Libm;

const DT: f32 = 1e-4; // 10 kHz

fn plane_model() -> ContactModel<Libm, Plane> {
    ContactModel::new(ContactParams::DEFAULT, Plane::default(), Quat::IDENTITY, DT).unwrap()
}

fn input(q: Quat, x: f32, y: f32, z: f32, vx: f32) -> ContactInput {
    ContactInput {
        q,
        probe_m: Vec3::new(x, y, z),
        probe_vel: Vec3::new(vx, 0.0, 0.0),
    }
}

/// `state()` follows the output's state through touch, slide and lift-off.
#[test]
fn state_accessor_reports_the_state_of_the_last_step() {
    let mut m = plane_model();
    assert_eq!(m.state(), ContactState::Broken);
    let o = m.contact_step(&input(Quat::IDENTITY, 0.0, 0.0, 0.009, 0.0));
    assert_eq!(
        (o.state, m.state()),
        (ContactState::Rolling, ContactState::Rolling)
    );
    let mut x = 0.0;
    for _ in 0..2000 {
        x += 0.05 * DT;
        let o = m.contact_step(&input(Quat::IDENTITY, x, 0.0, 0.009, 0.05));
        assert_eq!(o.state, m.state());
    }
    assert_eq!(m.state(), ContactState::Sliding);
    let o = m.contact_step(&input(Quat::IDENTITY, x, 0.0, 0.02, 0.0));
    assert_eq!(
        (o.state, m.state()),
        (ContactState::Broken, ContactState::Broken)
    );
}

/// Slide 5 mm, stop and ease back 0.3 mm (the spring then leaves the kinetic cone's edge), stick
/// again: the sliding proxy was dragged along (`restart_at`), so once stuck the contact sits under
/// the probe and the spring renders at most the kinetic force, instead of pulling the finger back
/// to where the slide began.
#[test]
fn after_a_slide_the_contact_sticks_under_the_probe() {
    let mut m = plane_model();
    m.contact_step(&input(Quat::IDENTITY, 0.0, 0.0, 0.009, 0.0));
    let v = 0.05;
    let mut x = 0.0f32;
    let mut slid = false;
    while x < 0.005 {
        x += v * DT;
        let o = m.contact_step(&input(Quat::IDENTITY, x, 0.0, 0.009, v));
        slid |= o.state == ContactState::Sliding;
    }
    assert!(slid, "the drag slid");
    x -= 0.0003;
    let mut last = ContactOutput::default();
    for _ in 0..2000 {
        last = m.contact_step(&input(Quat::IDENTITY, x, 0.0, 0.009, 0.0));
    }
    assert_eq!(last.state, ContactState::Rolling, "stuck again");
    // The contact is under the probe (within the kinetic reach μ_k·f_N/K_t = 1.2 mm), not at the
    // start of the slide 5 mm behind.
    assert!(
        (last.object_point_m.x - x).abs() <= 1.2e-3 + 1e-6,
        "contact {:?} probe x {x}",
        last.object_point_m
    );
    // The tangential force is within the kinetic cone μ_k·f_N = 1.2 N (the spring stretched by
    // at most the reach), not K_t·5 mm = 5 N.
    let ft = libm::sqrtf(last.force_n.x * last.force_n.x + last.force_n.y * last.force_n.y);
    assert!(ft <= 1.2 + 1e-3, "tangential force {ft} N");
}

/// On first touch the contact is placed under the probe and the anchor velocity starts from
/// there: the step after the touch renders no damping spike.
#[test]
fn touching_down_places_the_contact_and_starts_the_anchor_at_rest() {
    let mut m = plane_model();
    m.contact_step(&input(Quat::IDENTITY, 0.004, -0.003, 0.02, 0.0));
    let o = m.contact_step(&input(Quat::IDENTITY, 0.004, -0.003, 0.009, 0.0));
    assert_eq!(o.reason, Reason::MadeContact);
    // Measured exact: the contact lands on the probe's x, y and the next step's tangential force
    // is exactly 0.
    assert_eq!(o.object_point_m, Vec3::new(0.004, -0.003, 0.0));
    let o = m.contact_step(&input(Quat::IDENTITY, 0.004, -0.003, 0.009, 0.0));
    assert_eq!(o.state, ContactState::Rolling);
    assert_eq!((o.force_n.x, o.force_n.y), (0.0, 0.0), "{:?}", o.force_n);
}

/// The twist threshold sees the tilt rate from both tilt components: at f_N = 2 N it is
/// f_N·μ_s/(k_τ·r) = 40 rad/s; a step of 41 rad/s about x alone, or about y alone, exceeds it,
/// 39 rad/s does not.
#[test]
fn tilt_rate_about_either_tangent_axis_reaches_the_twist_threshold() {
    for axis in [Vec3::X, Vec3::Y] {
        for (rate, want) in [
            (39.0f32, (ContactState::Rolling, Reason::Kept)),
            (41.0, (ContactState::Sliding, Reason::TwistExceeded)),
        ] {
            let mut m = plane_model();
            m.contact_step(&input(Quat::IDENTITY, 0.0, 0.0, 0.009, 0.0));
            let q = Quat::from_axis_angle::<Libm>(axis, rate * DT);
            let o = m.contact_step(&input(q, 0.0, 0.0, 0.009, 0.0));
            assert_eq!((o.state, o.reason), want, "{axis:?} at {rate} rad/s");
        }
    }
}

/// An early return (a non-finite sample) still reports the spin accumulated so far.
#[test]
fn a_rejected_sample_reports_the_accumulated_spin() {
    let mut m = plane_model();
    m.contact_step(&input(Quat::IDENTITY, 0.0, 0.0, 0.009, 0.0));
    let q = Quat::from_axis_angle::<Libm>(Vec3::Z, 0.01);
    let o = m.contact_step(&input(q, 0.0, 0.0, 0.009, 0.0));
    // Measured exact; bound 1 ulp of 0.01 (9.3e-10 rad), an ulp argument.
    assert!((o.spin_rad - 0.01).abs() <= 9.3e-10, "{}", o.spin_rad);
    let bad = m.contact_step(&input(q, f32::NAN, 0.0, 0.009, 0.0));
    assert!(bad.flags.contains(Flags::NON_FINITE_INPUT));
    assert_eq!(bad.spin_rad, o.spin_rad);
    assert_eq!(bad.state, ContactState::Rolling);
}

/// An early return reports the contact point where it is, not the origin.
#[test]
fn a_rejected_sample_reports_the_current_contact_point() {
    let mut m = plane_model();
    let o = m.contact_step(&input(Quat::IDENTITY, 0.004, -0.003, 0.009, 0.0));
    // Measured exact.
    assert_eq!(o.object_point_m, Vec3::new(0.004, -0.003, 0.0));
    let bad = m.contact_step(&input(Quat::IDENTITY, f32::INFINITY, 0.0, 0.009, 0.0));
    assert!(bad.flags.contains(Flags::NON_FINITE_INPUT));
    assert_eq!(bad.object_point_m, o.object_point_m);
}

/// A non-finite orientation while apart is flagged and changes nothing.
#[test]
fn a_non_finite_orientation_while_apart_is_flagged() {
    let mut m = plane_model();
    m.contact_step(&input(Quat::IDENTITY, 0.0, 0.0, 0.05, 0.0));
    let nan = Quat::new(f32::NAN, 0.0, 0.0, 0.0);
    let o = m.contact_step(&input(nan, 0.0, 0.0, 0.05, 0.0));
    assert!(o.flags.contains(Flags::NON_FINITE_INPUT), "{:?}", o.flags);
    assert_eq!((o.state, o.force_n), (ContactState::Broken, Vec3::ZERO));
    assert_eq!(m.rolling.q_prev, Quat::IDENTITY);
}

/// Rolling on a sphere (R = 50 mm) with the probe held still: the anchor (fingertip centre implied
/// by rolling) is at (R + ρ)·n, and the coupling renders K_t·(anchor − probe) + b_t·(anchor
/// velocity), tangential parts, computed here from the surface's contact frame after each step.
#[test]
fn rolling_on_a_sphere_couples_through_the_anchor_at_r_plus_rho() {
    let (big, rho) = (0.05f32, 0.01f32);
    let p = ContactParams::DEFAULT;
    let mut m = ContactModel::<Libm, Sphere>::new(p, Sphere::new(big), Quat::IDENTITY, DT).unwrap();
    let probe = Vec3::new(0.0, 0.0, big + rho - 0.001);
    let still = |q: Quat| ContactInput {
        q,
        probe_m: probe,
        probe_vel: Vec3::ZERO,
    };
    m.contact_step(&still(Quat::IDENTITY));
    let anchor = |m: &ContactModel<Libm, Sphere>| m.rolling.surface.normal() * (big + rho);
    let mut prev = anchor(&m);
    for k in 1..=20 {
        // 2 rad/s about y: the contact rolls towards +x.
        let q = Quat::from_axis_angle::<Libm>(Vec3::Y, 2.0 * DT * k as f32);
        let o = m.contact_step(&still(q));
        assert_eq!(o.state, ContactState::Rolling, "step {k}");
        let a = anchor(&m);
        let f = (a - probe) * p.tangential_stiffness + (a - prev) * (p.tangential_damping / DT);
        let n = m.rolling.surface.normal();
        let want = f - n * f.dot(n);
        let got = o.force_n - n * o.force_n.dot(n);
        assert!(
            // Measured 1.59e-14 N² over the 20 steps; bound 3x.
            (got - want).norm_squared() < 4.8e-14,
            "step {k}: {got:?} vs {want:?}"
        );
        prev = a;
    }
}

/// The force limit is a ceiling: however deep the probe, |F| (in f64 from the f32 components)
/// never exceeds max_force_n, and the rescale lands within a few ulps below it.
#[test]
fn limited_force_never_exceeds_the_limit() {
    for depth in [0.01f32, 0.1, 1.0, 7.3] {
        let mut m = plane_model();
        let o = m.contact_step(&input(Quat::IDENTITY, 0.001, -0.002, 0.01 - depth, 0.0));
        assert!(o.flags.contains(Flags::OUTPUT_LIMITED), "depth {depth}");
        let f = o.force_n;
        let n = ((f.x as f64).powi(2) + (f.y as f64).powi(2) + (f.z as f64).powi(2)).sqrt();
        assert!(n <= 12.0, "depth {depth}: |F| = {n}");
        assert!(n >= 12.0 * (1.0 - 1e-6), "depth {depth}: |F| = {n}");
    }
}
