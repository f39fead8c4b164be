//! The grasp tick's own invariants: equal and opposite wrenches, a fingertip that leaves lets go,
//! bad input gives a flagged safe result. The thresholds (lift, twist, both, torsion off) are
//! bracketed with simulated hands in host-sim (`host-sim/tests/grasp_thresholds.rs`).

use super::*;
use crate::contact::surface::Sphere;
use crate::contact::{ContactParams, ContactState};
use crate::flags::Flags;
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Libm;

const R_OBJ: f32 = 0.03;
const R_TIP: f32 = 0.01;

fn grasp() -> Grasp<Libm, Sphere> {
    Grasp::new(
        BodyParams::solid_sphere(0.1, R_OBJ),
        BodyState::default(),
        Sphere::new(R_OBJ),
        [ContactParams::DEFAULT; 2],
        Vec3::new(0.0, 0.0, -9.81),
        1.0e-4,
    )
    .unwrap()
}

/// Fingertips on ±x pressing `pen` metres into the sphere, at rest.
fn tips(pen: f32) -> [Option<Fingertip>; 2] {
    let d = R_OBJ + R_TIP - pen;
    let tip = |x: f32| Fingertip {
        pos_m: Vec3::new(x, 0.0, 0.0),
        vel_m_s: Vec3::ZERO,
        q: Quat::IDENTITY,
    };
    [Some(tip(d)), Some(tip(-d))]
}

#[test]
fn wrenches_on_body_and_fingertip_are_equal_and_opposite() {
    let mut g = grasp();
    let mut worst = 0.0_f32;
    let mut last = GraspStep::default();
    for k in 0..2000 {
        // The fingertips move up and twist, so normal force, tangential load and spin all act.
        let mut t = tips(0.0025);
        let twist = Quat::from_axis_angle::<Libm>(Vec3::X, 2.0e-5 * k as f32);
        for tip in t.iter_mut().flatten() {
            tip.pos_m.z = 1.0e-6 * k as f32;
            tip.vel_m_s.z = 0.01;
            tip.q = twist;
        }
        let x = g.body.state.pos_m;
        last = g.step(t, Wrench::default());
        for (c, tip) in last.contacts.iter().zip(t.iter().flatten()) {
            assert_eq!(c.on_body.force_n, -c.on_fingertip.force_n);
            // Moments about the world origin: body τ + x × F, fingertip τ + p × F; they cancel.
            let m_body = c.on_body.torque_nm + x.cross(c.on_body.force_n);
            let m_tip = c.on_fingertip.torque_nm + tip.pos_m.cross(c.on_fingertip.force_n);
            worst = worst.max((m_body + m_tip).norm::<Libm>());
        }
    }
    // f32 roundoff of moments of ~5 N at 30 mm (0.15 N·m): a few ulps.
    assert!(worst < 1.0e-6, "moment mismatch {worst} N·m");
    for c in &last.contacts {
        assert_eq!(c.output.state, ContactState::Rolling);
        assert!(c.normal_force_n > 4.0, "{}", c.normal_force_n);
        assert!(c.tangential_force_n > 0.0 && c.output.tau_n_nm != 0.0);
    }
}

#[test]
fn fingertips_that_leave_drop_the_body() {
    let mut g = grasp();
    for _ in 0..2000 {
        g.step(tips(0.0025), Wrench::default());
    }
    let z_held = g.body.state.pos_m.z;
    assert!(z_held.abs() < 2.0e-3, "held at {z_held}");
    // The fingers open 5 mm each: no contact, no force, free fall from there.
    let mut max_force = 0.0_f32;
    for _ in 0..1000 {
        let s = g.step(tips(-0.005), Wrench::default());
        for c in &s.contacts {
            max_force = max_force.max(c.on_body.force_n.norm::<Libm>());
        }
    }
    let z = g.body.state.pos_m.z - z_held;
    // 0.1 s of free fall: g·t²/2 = 49 mm (the first ticks still touch while opening).
    assert!(z < -0.04, "fell only {z} m");
    assert_eq!(max_force, 0.0);
    let s = g.step([None, None], Wrench::default());
    assert!(!s.contacts[0].active && s.contacts[0].on_body.force_n == Vec3::ZERO);
}

#[test]
fn coincident_fingertips_are_flagged_and_the_second_ignored() {
    let mut g = grasp();
    let t = tips(0.0025);
    let s = g.step([t[0], t[0]], Wrench::default());
    assert!(s.grasp_flags.contains(GraspFlags::COINCIDENT_FINGERTIPS));
    assert!(!s.contacts[1].active);
    assert!(s.contacts[0].normal_force_n > 0.0);
    // Just apart (centres 2r + 1 µm apart) is not flagged.
    let mut b = t[0].unwrap();
    b.pos_m.z += 2.0 * R_TIP + 1.0e-6;
    let s = g.step([t[0], Some(b)], Wrench::default());
    assert!(!s.grasp_flags.contains(GraspFlags::COINCIDENT_FINGERTIPS));
    let mut b = t[0].unwrap();
    b.pos_m.z += 2.0 * R_TIP - 1.0e-6;
    let s = g.step([t[0], Some(b)], Wrench::default());
    assert!(s.grasp_flags.contains(GraspFlags::COINCIDENT_FINGERTIPS));
}

#[test]
fn non_finite_input_gives_a_finite_flagged_result() {
    let mut g = grasp();
    let mut t = tips(0.0025);
    t[0].as_mut().unwrap().pos_m.x = f32::NAN;
    t[1].as_mut().unwrap().q = Quat::new(f32::INFINITY, 0.0, 0.0, 0.0);
    let bad = Wrench {
        force_n: Vec3::new(0.0, f32::NAN, 0.0),
        torque_nm: Vec3::ZERO,
    };
    for _ in 0..100 {
        let s = g.step(t, bad);
        assert!(s.flags.contains(Flags::NON_FINITE_INPUT));
        for c in &s.contacts {
            assert!(c.on_body.force_n.is_finite() && c.on_body.torque_nm.is_finite());
        }
    }
    let st = g.body.state;
    assert!(st.pos_m.is_finite() && st.vel_m_s.is_finite() && st.q.is_finite());
}

#[test]
fn bad_construction_is_named() {
    let body = BodyParams::solid_sphere(0.0, R_OBJ);
    let e = Grasp::<Libm, Sphere>::new(
        body,
        BodyState::default(),
        Sphere::new(R_OBJ),
        [ContactParams::DEFAULT; 2],
        Vec3::ZERO,
        1.0e-4,
    )
    .unwrap_err();
    assert_eq!(e, GraspError::Body(BodyError::NotPositive("mass_kg")));
    let mut p = ContactParams::DEFAULT;
    p.mu_s = f32::NAN;
    let e = Grasp::<Libm, Sphere>::new(
        BodyParams::solid_sphere(0.1, R_OBJ),
        BodyState::default(),
        Sphere::new(R_OBJ),
        [ContactParams::DEFAULT, p],
        Vec3::ZERO,
        1.0e-4,
    )
    .unwrap_err();
    assert!(matches!(e, GraspError::Contact(1, _)));
    for dt in [0.0, f32::NAN, 2.0] {
        let e = Grasp::<Libm, Sphere>::new(
            BodyParams::solid_sphere(0.1, R_OBJ),
            BodyState::default(),
            Sphere::new(R_OBJ),
            [ContactParams::DEFAULT; 2],
            Vec3::ZERO,
            dt,
        )
        .unwrap_err();
        assert_eq!(e, GraspError::Dt);
    }
}

/// The twisting, lifting pinch of the first test for 500 ticks with contacts of parts `P`: the
/// largest |τn| of either contact (N·m) and the body's last state.
fn twisted_with<P: crate::contact::Parts>() -> (f32, BodyState) {
    let mut g = Grasp::<Libm, Sphere, P>::with_parts(
        BodyParams::solid_sphere(0.1, R_OBJ),
        BodyState::default(),
        Sphere::new(R_OBJ),
        [ContactParams::DEFAULT; 2],
        Vec3::new(0.0, 0.0, -9.81),
        1.0e-4,
    )
    .unwrap();
    let mut tau = 0.0_f32;
    for k in 0..500 {
        let mut t = tips(0.0025);
        let twist = Quat::from_axis_angle::<Libm>(Vec3::X, 2.0e-5 * k as f32);
        for tip in t.iter_mut().flatten() {
            tip.q = twist;
        }
        let s = g.step(t, Wrench::default());
        for c in &s.contacts {
            tau = tau.max(c.output.tau_n_nm.abs());
        }
    }
    (tau, g.body.state)
}

/// The contacts' parts are a compile-time choice of the grasp: the whole model by default
/// (`Grasp::new` is `with_parts::<Full>`, bit for bit), and a choice without the spin renders
/// no spin torque while the fingertips twist, one with it does.
#[test]
fn a_grasp_runs_the_contact_parts_it_names() {
    use crate::contact::{Full, PointFriction, RollingOnly, WithRolling, WithSpin};
    let mut g = grasp();
    for k in 0..500 {
        let mut t = tips(0.0025);
        let twist = Quat::from_axis_angle::<Libm>(Vec3::X, 2.0e-5 * k as f32);
        for tip in t.iter_mut().flatten() {
            tip.q = twist;
        }
        g.step(t, Wrench::default());
    }
    let (full_tau, full_state) = twisted_with::<Full>();
    assert_eq!(full_state, g.body.state, "new is with_parts::<Full>");
    assert!(
        full_tau > 1.0e-5,
        "the twist loads the spin spring: {full_tau}"
    );
    assert_eq!(twisted_with::<PointFriction>().0, 0.0);
    assert_eq!(twisted_with::<RollingOnly>().0, 0.0);
    // Inside the limits the limit surface does not act: the spin parts give the full torque.
    for tau in [
        twisted_with::<WithSpin>().0,
        twisted_with::<WithRolling>().0,
    ] {
        assert!(
            (tau - full_tau).abs() <= 1.0e-3 * full_tau,
            "{tau} {full_tau}"
        );
    }
}
