//! Contact step scenarios with closed-form expectations.

use super::*;
use crate::contact::surface::Plane;
use crate::math::Libm;

#[path = "budget_tests.rs"]
mod budget_tests;
#[path = "scenario_tests.rs"]
mod scenario_tests;
#[path = "step_rule_tests.rs"]
mod step_rule_tests;

const DT: f32 = 1e-4; // 10 kHz

fn model() -> ContactModel<Libm, Plane> {
    ContactModel::new(ContactParams::DEFAULT, Plane::default(), Quat::IDENTITY, DT).unwrap()
}

fn at(x: f32, y: f32, z: f32) -> ContactInput {
    ContactInput {
        q: Quat::IDENTITY,
        probe_m: Vec3::new(x, y, z),
        probe_vel: Vec3::ZERO,
    }
}

/// Asserts whether a step's output is sliding; `case` names the case in the message, with the
/// transition's reason.
fn assert_slides(o: &ContactOutput, slides: bool, case: &str) {
    let sliding = o.state == ContactState::Sliding;
    assert_eq!(sliding, slides, "{case}: {:?}", o.reason);
}

#[test]
fn free_space_renders_nothing() {
    let mut m = model();
    let o = m.contact_step(&at(0.0, 0.0, 0.05));
    assert_eq!(o.state, ContactState::Broken);
    assert_eq!(o.force_n, Vec3::ZERO);
}

/// Pressing 1 mm into a 2000 N/m surface at rest: f_N = 2 N along +z, rolling, no tangential force.
#[test]
fn pressing_gives_the_spring_force_and_rolling() {
    let mut m = model();
    let o = m.contact_step(&at(0.003, -0.002, 0.009));
    assert_eq!(
        (o.state, o.reason),
        (ContactState::Rolling, Reason::MadeContact)
    );
    // Measured 2.38e-7 N (1 ulp of 2 N); bound 3x. The tangential force and the contact point
    // measured exact.
    assert!((o.force_n.z - 2.0).abs() < 7.2e-7, "{:?}", o.force_n);
    assert_eq!((o.force_n.x, o.force_n.y), (0.0, 0.0));
    assert_eq!(o.object_point_m, Vec3::new(0.003, -0.002, 0.0));
}

/// Rolling the fingertip about y by 0.1 rad while the probe stays put moves the anchor by
/// ρ·0.1 = 1 mm along +x, so the coupling spring pulls the probe by K_t·1 mm = 1 N along +x.
#[test]
fn rolling_the_wrist_drags_the_probe_through_the_coupling_spring() {
    let mut m = model();
    m.contact_step(&at(0.0, 0.0, 0.009));
    let steps = 100;
    let mut o = ContactOutput::default();
    for k in 1..=steps {
        let q = Quat::from_axis_angle::<Libm>(Vec3::Y, 0.1 * k as f32 / steps as f32);
        o = m.contact_step(&ContactInput {
            q,
            ..at(0.0, 0.0, 0.009)
        });
        assert_eq!(o.state, ContactState::Rolling, "step {k}");
    }
    // Measured 3.49e-10 m and 7.15e-7 N over the 100 steps; bounds 3x.
    assert!(
        (o.object_point_m.x - 0.001).abs() < 1.05e-9,
        "{:?}",
        o.object_point_m
    );
    // spring 1000 N/m × 1 mm = 1 N, plus damping 1 N·s/m × anchor speed (1 mm / 10 ms = 0.1 m/s).
    assert!((o.force_n.x - 1.1).abs() < 2.2e-6, "{:?}", o.force_n);
    assert!(o.flags.is_empty(), "{:?}", o.flags);
}

/// Dragging the probe sideways faster than the friction cone allows switches to sliding, and the
/// rendered tangential force is then kinetic friction μ_k·f_N opposing the motion.
#[test]
fn pushing_past_the_cone_slides_with_kinetic_friction() {
    let mut m = model();
    m.contact_step(&at(0.0, 0.0, 0.009)); // f_N = 2 N, cone 1.6 N (× 1.05 hysteresis)
    let v = 0.05; // m/s
    let mut state = ContactState::Rolling;
    let mut o = ContactOutput::default();
    // 600 steps = 3 mm: the spring reaches the cone (1.68 N) after ~1.6 mm.
    for k in 1..600 {
        let x = v * DT * k as f32;
        o = m.contact_step(&ContactInput {
            probe_vel: Vec3::new(v, 0.0, 0.0),
            ..at(x, 0.0, 0.009)
        });
        state = o.state;
    }
    assert_eq!(state, ContactState::Sliding);
    // kinetic friction 0.6·2 N = 1.2 N against +x (speed above the smoothing speed). Measured
    // 2.38e-7 N on both; bounds 3x.
    assert!((o.force_n.x + 1.2).abs() < 7.2e-7, "{:?}", o.force_n);
    assert!((o.force_n.z - 2.0).abs() < 7.2e-7);
}

/// Twisting about the normal winds the spin spring: τn = k_z·φ until the torsional limit.
#[test]
fn twisting_about_the_normal_gives_the_spin_torque_then_saturates() {
    let mut m = model();
    m.contact_step(&at(0.0, 0.0, 0.009)); // f_N = 2 N
    let mut o = ContactOutput::default();
    for k in 1..=100 {
        let q = Quat::from_axis_angle::<Libm>(Vec3::Z, 0.2 * k as f32 / 100.0);
        o = m.contact_step(&ContactInput {
            q,
            ..at(0.0, 0.0, 0.009)
        });
    }
    let tau_max = torsion_limit(0.8, 2.0, 0.005); // 4.7e-3 N·m
    let k_z = 0.01;
    // 0.2 rad × 0.01 = 2e-3 N·m < τ_max: linear. Measured 4.66e-10 N·m, 5.96e-8 rad and, once
    // saturated, 9.31e-10 N·m; bounds 3x.
    assert!(
        (o.tau_n_nm - 0.2 * k_z).abs() < 1.4e-9,
        "τ = {}",
        o.tau_n_nm
    );
    assert!((o.spin_rad - 0.2).abs() < 1.8e-7);
    // The accessors read the same state the output reports.
    assert_eq!(m.spin().accumulated_rad, o.spin_rad);
    assert_eq!(m.spin().elastic_rad, o.spin_rad);
    assert_eq!(m.rolling().surface().contact_point(), o.object_point_m);
    for k in 1..=200 {
        let q = Quat::from_axis_angle::<Libm>(Vec3::Z, 0.2 + 0.8 * k as f32 / 200.0);
        o = m.contact_step(&ContactInput {
            q,
            ..at(0.0, 0.0, 0.009)
        });
    }
    assert!(
        (o.tau_n_nm - tau_max).abs() < 2.8e-9,
        "saturated τ = {} vs {tau_max}",
        o.tau_n_nm
    );
    assert!(o.flags.contains(Flags::SPIN_SATURATED));
}

/// Lifting off breaks the contact and releases everything.
#[test]
fn lifting_off_breaks_contact() {
    let mut m = model();
    m.contact_step(&at(0.0, 0.0, 0.009));
    let o = m.contact_step(&at(0.0, 0.0, 0.0105));
    assert_eq!(
        (o.state, o.reason),
        (ContactState::Broken, Reason::Separated)
    );
    assert_eq!(o.force_n, Vec3::ZERO);
    assert_eq!(o.tau_n_nm, 0.0);
}

/// The force limit holds however deep the probe goes.
#[test]
fn force_is_limited() {
    let mut m = model();
    let o = m.contact_step(&at(0.0, 0.0, -1.0));
    // Measured 5.72e-6 N; bound 3x.
    assert!((o.force_n.norm_squared().sqrt() - 12.0).abs() < 1.7e-5);
    assert!(o.flags.contains(Flags::OUTPUT_LIMITED));
}

#[test]
fn non_finite_inputs_give_zero_force_and_a_flag() {
    let mut m = model();
    m.contact_step(&at(0.0, 0.0, 0.009));
    for bad in [
        at(f32::NAN, 0.0, 0.009),
        ContactInput {
            probe_vel: Vec3::new(0.0, f32::INFINITY, 0.0),
            ..at(0.0, 0.0, 0.009)
        },
        ContactInput {
            q: Quat::new(f32::NAN, 0.0, 0.0, 0.0),
            ..at(0.0, 0.0, 0.009)
        },
    ] {
        let o = m.contact_step(&bad);
        assert_eq!(o.force_n, Vec3::ZERO);
        assert!(o.flags.contains(Flags::NON_FINITE_INPUT));
        assert_eq!(o.state, ContactState::Rolling, "state kept");
    }
}

#[test]
fn invalid_parameters_are_rejected() {
    let bad = ContactParams {
        mu_k: 2.0,
        ..ContactParams::DEFAULT
    };
    assert_eq!(
        ContactModel::<Libm, Plane>::new(bad, Plane::default(), Quat::IDENTITY, DT).err(),
        Some(ParamError::KineticAboveStatic)
    );
    assert_eq!(
        ContactModel::<Libm, Plane>::new(
            ContactParams::DEFAULT,
            Plane::default(),
            Quat::IDENTITY,
            0.0
        )
        .err(),
        Some(ParamError::NotPositive("dt_s"))
    );
}

/// No creep at rest, in the full contact step, for every method, backend and surface: the probe
/// pressed 1 mm and held still at a tilted, twisted orientation for 200 000 ticks (20 s at 10 kHz):
/// the contact point, spin and rendered force stay bit for bit what they were after the press
/// (on main the anchor walked 65 µm in 10⁶ ticks and the tangential force grew to 0.065 N). Then
/// one wrist count of dither about a tangent axis and about the normal: every even tick the
/// outputs are back exactly (the plane with every method, the curved surfaces with the exact one).
#[test]
fn a_pressed_and_held_finger_does_not_creep() {
    use crate::contact::decompose::Method;
    use crate::contact::surface::{Bowl, Cylinder, Sphere, Surface};
    use crate::math::{Fast, Micromath};

    fn check<M: Math, S: Surface>(surface: S, method: Method) {
        let params = ContactParams {
            method,
            ..ContactParams::DEFAULT
        };
        let q = Quat::from_rotation_vector::<Libm>(Vec3::new(0.3, -0.2, 0.1)).0;
        let mut m = ContactModel::<M, S>::new(params, surface, q, DT).unwrap();
        let n = surface.normal();
        let probe = surface.contact_point() + n * (params.fingertip_radius_m - 0.001);
        let input = |q| ContactInput {
            q,
            probe_m: probe,
            probe_vel: Vec3::ZERO,
        };
        for _ in 0..5 {
            let _ = m.contact_step(&input(q));
        }
        let first = m.contact_step(&input(q));
        assert_eq!(first.state, ContactState::Rolling);
        for k in 0..200_000 {
            let o = m.contact_step(&input(q));
            assert_eq!(
                (o.force_n, o.spin_rad, o.object_point_m),
                (first.force_n, first.spin_rad, first.object_point_m),
                "{method:?} {} tick {k}",
                M::NAME
            );
        }
        if method == Method::PaperVerbatim {
            // Its printed equations turn a one-count tilt into a spin of about π/2 per tick: the
            // twist threshold makes it slide, which moves the anchor by friction, not creep.
            return;
        }
        let count = core::f32::consts::TAU / 4096.0;
        let tilt = q * Quat::from_axis_angle::<Libm>(Vec3::X, count);
        let twist = q * Quat::from_axis_angle::<Libm>(Vec3::Z, count);
        let mut moved = false;
        for k in 0..20_000 {
            let o = m.contact_step(&input([tilt, q, twist, q][k % 4]));
            assert_eq!(o.state, ContactState::Rolling);
            if k % 2 == 1 {
                assert_eq!(
                    (o.spin_rad, o.object_point_m, o.tau_n_nm),
                    (first.spin_rad, first.object_point_m, first.tau_n_nm),
                    "{method:?} {} dither {k}",
                    M::NAME
                );
                assert_eq!(m.rolling.finger_point(), {
                    let mut r = m.rolling;
                    r.q_prev = q;
                    r.finger_point()
                });
            } else {
                moved |= o.object_point_m != first.object_point_m || o.spin_rad != first.spin_rad;
            }
        }
        assert!(moved, "the dither moves the contact in between");
    }
    for method in Method::ALL {
        check::<Libm, _>(Plane::default(), method);
        check::<Micromath, _>(Plane::default(), method);
        check::<Fast, _>(Plane::default(), method);
    }
    check::<Fast, _>(Sphere::new(0.05), Method::Exact);
    check::<Libm, _>(Bowl::new(0.05), Method::Exact);
    check::<Micromath, _>(Cylinder::new(0.05), Method::Exact);
}

/// The remembered patch radius and torsion limit equal a fresh evaluation bit for bit, for a
/// force that repeats, changes, returns, crosses zero (both signed zeros), is NaN or infinite.
#[test]
fn remembered_patch_equals_a_fresh_evaluation() {
    let mut m = model();
    let p = ContactParams::DEFAULT;
    let fresh = |f_n: f32| {
        let a = patch_radius(f_n, p.patch_radius_m, p.patch_ref_force_n, p.patch_exponent);
        (a, torsion_limit(p.mu_s, f_n, a))
    };
    let forces = [
        0.0f32,
        2.0,
        2.0,
        1.999_999_9,
        2.0,
        0.0,
        -0.0,
        0.5,
        f32::NAN,
        0.5,
        f32::NAN,
        f32::INFINITY,
        -1.0,
        7.3,
        7.3,
        1e-30,
        1e-30,
        0.0,
    ];
    for f_n in forces {
        let (a, t) = m.patch_at(f_n);
        let (a0, t0) = fresh(f_n);
        assert_eq!(
            (a.to_bits(), t.to_bits()),
            (a0.to_bits(), t0.to_bits()),
            "f_N = {f_n}"
        );
    }
}

/// The output guard: a force just within the limit passes untouched, one just above is rescaled
/// below it (checked in f64) along the same direction, and a non-finite force or torque gives zero
/// force (a non-finite torque zero torque) with its flag, also when the force is over the limit.
#[test]
fn the_output_guard_limits_the_force_and_stops_non_finite_output() {
    let max = 12.0f32;
    let dir = Vec3::new(0.6, 0.0, 0.8);
    let guard = |f: Vec3, t: f32| {
        let mut fl = Flags::NONE;
        let (f, t) = guard_output::<Libm>(f, t, max, &mut fl);
        (f, t, fl)
    };
    let (f, t, fl) = guard(dir * (max * (1.0 - 1e-6)), 0.002);
    assert_eq!((f, t, fl), (dir * (max * (1.0 - 1e-6)), 0.002, Flags::NONE));
    let (f, t, fl) = guard(dir * (max * (1.0 + 1e-6)), -0.002);
    assert_eq!((t, fl), (-0.002, Flags::OUTPUT_LIMITED));
    let n = ((f.x as f64).powi(2) + (f.y as f64).powi(2) + (f.z as f64).powi(2)).sqrt();
    assert!(n <= max as f64 && n > max as f64 * (1.0 - 1e-6), "{n}");
    // The direction: measured exact; bound 1 ulp of 0.75 (6e-8), an ulp argument.
    assert!((f.x / f.z - 0.75).abs() <= 6e-8, "{f:?}");
    for (force, tau, tau_out) in [
        (Vec3::new(f32::NAN, 0.0, 1.0), 0.001, 0.001),
        (Vec3::new(0.0, f32::INFINITY, 1.0), 0.001, 0.001),
        (Vec3::new(0.0, 0.0, 1.0), f32::INFINITY, 0.0),
        (Vec3::new(0.0, 0.0, 1.0), f32::NAN, 0.0),
        (dir * (2.0 * max), f32::NAN, 0.0),
    ] {
        let (f, t, fl) = guard(force, tau);
        assert_eq!(
            (f, t, fl),
            (Vec3::ZERO, tau_out, Flags::NON_FINITE_OUTPUT),
            "{force:?} {tau}"
        );
    }
}
