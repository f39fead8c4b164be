//! Table-driven test of every transition and every non-transition.

use super::*;

#[path = "threshold_tests.rs"]
mod threshold_tests;

const P: StateParams = StateParams {
    mu_s: 0.8,
    mu_k: 0.6,
    k_tau: 4.0,
    radius_m: 0.01,
    roll_eps_m: 1e-9,
    tol: Tolerances {
        normal_accel_tol: 20.0,
        ..Tolerances::DEFAULT
    },
};

/// Pressing with 2 N, at rest, nothing else.
fn pressed() -> StateInputs {
    StateInputs {
        normal_force_n: 2.0,
        gap_m: -0.001,
        time_in_state_s: 1.0,
        ..StateInputs::default()
    }
}

fn x(v: f32) -> Vec3 {
    Vec3::new(v, 0.0, 0.0)
}

use ContactState::{Broken, Rolling, Sliding};

#[test]
fn every_transition_and_non_transition() {
    // (name, from, inputs, expected state, expected reason)
    let cases: &[(&str, ContactState, StateInputs, ContactState, Reason)] = &[
        // --- broken ---
        (
            "broken, no force",
            Broken,
            StateInputs {
                gap_m: 0.01,
                ..Default::default()
            },
            Broken,
            Reason::Kept,
        ),
        (
            "broken, force at ε",
            Broken,
            StateInputs {
                normal_force_n: 0.01,
                ..Default::default()
            },
            Broken,
            Reason::Kept,
        ),
        (
            "broken, force inside the make band",
            Broken,
            StateInputs {
                normal_force_n: 0.04,
                ..Default::default()
            },
            Broken,
            Reason::Kept,
        ),
        (
            "broken, pressed right after a break",
            Broken,
            StateInputs {
                time_in_state_s: 0.001,
                ..pressed()
            },
            Broken,
            Reason::Kept,
        ),
        (
            "broken, pressed",
            Broken,
            pressed(),
            Rolling,
            Reason::MadeContact,
        ),
        // --- rolling ---
        (
            "rolling, inside cone",
            Rolling,
            StateInputs {
                tangential_force_n: x(1.0),
                tangential_accel: x(1.0),
                ..pressed()
            },
            Rolling,
            Reason::Kept,
        ),
        (
            "rolling, f_N=0 and a_N>0",
            Rolling,
            StateInputs {
                normal_accel: 1.0,
                ..Default::default()
            },
            Broken,
            Reason::Separated,
        ),
        (
            "rolling, f_N=0 and gap",
            Rolling,
            StateInputs {
                gap_m: 0.001,
                ..Default::default()
            },
            Broken,
            Reason::Separated,
        ),
        (
            "rolling, f_N=0 but approaching, touching",
            Rolling,
            StateInputs {
                normal_accel: -1.0,
                gap_m: 0.0,
                ..Default::default()
            },
            Rolling,
            Reason::Kept,
        ),
        (
            "rolling, exactly on cone",
            Rolling,
            StateInputs {
                tangential_force_n: x(1.6),
                tangential_accel: x(1.0),
                ..pressed()
            },
            Rolling,
            Reason::Kept,
        ),
        (
            "rolling, inside hysteresis band",
            Rolling,
            StateInputs {
                tangential_force_n: x(1.67),
                tangential_accel: x(1.0),
                ..pressed()
            },
            Rolling,
            Reason::Kept,
        ),
        (
            "rolling, over cone, no rolling",
            Rolling,
            StateInputs {
                tangential_force_n: x(1.7),
                tangential_accel: x(1.0),
                ..pressed()
            },
            Sliding,
            Reason::ConeExceeded,
        ),
        (
            "rolling, over cone, agrees with roll",
            Rolling,
            StateInputs {
                tangential_force_n: x(1.7),
                tangential_accel: x(1.0),
                roll_disp_m: x(1e-5),
                ..pressed()
            },
            Sliding,
            Reason::ConeExceeded,
        ),
        (
            "rolling, over cone, against roll (haptic rule)",
            Rolling,
            StateInputs {
                tangential_force_n: x(-1.7),
                tangential_accel: x(1.0),
                roll_disp_m: x(1e-5),
                ..pressed()
            },
            Rolling,
            Reason::Kept,
        ),
        (
            "rolling, over cone, a_T = 0",
            Rolling,
            StateInputs {
                tangential_force_n: x(1.7),
                ..pressed()
            },
            Rolling,
            Reason::Kept,
        ),
        (
            "rolling, over cone, a_N ≠ 0 (bouncing)",
            Rolling,
            StateInputs {
                tangential_force_n: x(1.7),
                tangential_accel: x(1.0),
                normal_accel: 50.0,
                ..pressed()
            },
            Rolling,
            Reason::Kept,
        ),
        // Δθ_max = f_N·μ_s/(k_τ·r) = 2·0.8/(4·0.01) = 40 rad/s
        (
            "rolling, tilt rate below Δθ_max",
            Rolling,
            StateInputs {
                tilt_rate_sq: 39.0 * 39.0,
                ..pressed()
            },
            Rolling,
            Reason::Kept,
        ),
        (
            "rolling, tilt rate above Δθ_max",
            Rolling,
            StateInputs {
                tilt_rate_sq: 41.0 * 41.0,
                ..pressed()
            },
            Sliding,
            Reason::TwistExceeded,
        ),
        // --- sliding ---
        (
            "sliding, moving",
            Sliding,
            StateInputs {
                tangential_velocity: x(0.05),
                tangential_force_n: x(1.2),
                ..pressed()
            },
            Sliding,
            Reason::Kept,
        ),
        (
            "sliding, stopped inside kinetic cone",
            Sliding,
            StateInputs {
                tangential_velocity: x(0.001),
                tangential_force_n: x(1.1),
                time_in_state_s: 0.5,
                ..pressed()
            },
            Rolling,
            Reason::Stuck,
        ),
        (
            "sliding, stopped but only just started sliding",
            Sliding,
            StateInputs {
                tangential_velocity: x(0.001),
                tangential_force_n: x(1.1),
                time_in_state_s: 0.01,
                ..pressed()
            },
            Sliding,
            Reason::Kept,
        ),
        (
            "sliding, stopped but pushed past kinetic cone",
            Sliding,
            StateInputs {
                tangential_velocity: x(0.001),
                tangential_force_n: x(1.3),
                time_in_state_s: 0.5,
                ..pressed()
            },
            Sliding,
            Reason::Kept,
        ),
        (
            "sliding, stopped, a_N ≠ 0",
            Sliding,
            StateInputs {
                tangential_velocity: x(0.0),
                normal_accel: 50.0,
                time_in_state_s: 0.5,
                ..pressed()
            },
            Sliding,
            Reason::Kept,
        ),
        (
            "sliding, f_N=0 and a_N>0",
            Sliding,
            StateInputs {
                normal_accel: 1.0,
                ..Default::default()
            },
            Broken,
            Reason::Separated,
        ),
        (
            "sliding, f_N=0, touching, at rest",
            Sliding,
            StateInputs::default(),
            Sliding,
            Reason::Kept,
        ),
    ];
    for (name, from, inputs, to, reason) in cases {
        let got = next_state(*from, inputs, &P);
        assert_eq!(got, (*to, *reason), "case '{name}'");
    }
}

/// A tangential force held on the static cone boundary with ±2 % noise never leaves rolling: the
/// 5 % hysteresis margin is wider than the noise.
#[test]
fn force_on_the_cone_boundary_does_not_chatter() {
    let mut state = Rolling;
    let mut transitions = 0;
    for k in 0..10_000 {
        let noise = 0.02 * ((k as f32) * 0.7).sin();
        let i = StateInputs {
            tangential_force_n: x(1.6 * (1.0 + noise)),
            tangential_accel: x(0.5),
            ..pressed()
        };
        let (s, r) = next_state(state, &i, &P);
        if r != Reason::Kept {
            transitions += 1;
        }
        state = s;
    }
    assert_eq!(transitions, 0);
}

/// One friction budget: pushing sideways at 80 % of the static cone (1.6 N at 2 N, μ_s = 0.8,
/// beyond the hysteresis-free 0.8² + 0.8² > 1.05²) while twisting at 80 % of τ_max slips; either
/// alone does not. Just inside and just outside the ellipse scaled by 1 + h on the diagonal.
#[test]
fn twisting_while_pushing_sideways_slips_sooner() {
    let p = crate::contact::params::ContactParams::DEFAULT.state_params();
    let cone = p.mu_s * 2.0;
    let tau_max = crate::contact::spin::torsion_limit(p.mu_s, 2.0, 0.005);
    let with = |ft: f32, tau: f32| StateInputs {
        tangential_force_n: x(ft),
        tangential_accel: x(1.0),
        spin_torque_nm: tau,
        torsion_limit_nm: tau_max,
        ..pressed()
    };
    let state = |i: StateInputs| next_state(Rolling, &i, &p).0;
    assert_eq!(state(with(0.8 * cone, 0.0)), Rolling);
    assert_eq!(state(with(0.0, 0.8 * tau_max)), Rolling);
    assert_eq!(state(with(0.8 * cone, 0.8 * tau_max)), Sliding);
    let d = core::f32::consts::FRAC_1_SQRT_2 * (1.0 + p.tol.hysteresis);
    assert_eq!(state(with(0.999 * d * cone, 0.999 * d * tau_max)), Rolling);
    assert_eq!(state(with(1.001 * d * cone, 1.001 * d * tau_max)), Sliding);
    // No torsional budget (τ_max = 0): the friction cone alone, as before.
    let cone_only = |ft: f32| StateInputs {
        torsion_limit_nm: 0.0,
        ..with(ft, 0.01)
    };
    assert_eq!(state(cone_only(0.999 * 1.05 * cone)), Rolling);
    assert_eq!(state(cone_only(1.001 * 1.05 * cone)), Sliding);
}

/// The tolerances' validation: each field is named when NaN, negative or above its largest value;
/// the hysteresis must stay below 1 and f_make at or above ε_f, both bracketed.
#[test]
fn tolerances_are_validated_field_by_field() {
    use crate::contact::params::ParamError::{Negative, NotFinite, OutOfRange};
    type Field = fn(&mut Tolerances) -> &mut f32;
    let d = Tolerances::DEFAULT;
    assert_eq!(d.validate(), Ok(()));
    let fields: [(&str, Field); 9] = [
        ("force_eps_n", |t| &mut t.force_eps_n),
        ("accel_eps", |t| &mut t.accel_eps),
        ("normal_accel_tol", |t| &mut t.normal_accel_tol),
        ("gap_eps_m", |t| &mut t.gap_eps_m),
        ("stick_speed", |t| &mut t.stick_speed),
        ("hysteresis", |t| &mut t.hysteresis),
        ("make_force_n", |t| &mut t.make_force_n),
        ("min_slide_s", |t| &mut t.min_slide_s),
        ("min_broken_s", |t| &mut t.min_broken_s),
    ];
    for (name, field) in fields {
        let with = |v: f32| {
            let mut t = d;
            *field(&mut t) = v;
            t.validate()
        };
        assert_eq!(with(f32::NAN), Err(NotFinite(name)));
        assert_eq!(with(-1e-6), Err(Negative(name)));
        let max = *field(&mut { Tolerances::MAX });
        assert_eq!(with(max * 1.001), Err(OutOfRange(name)), "{name}");
        if !matches!(name, "force_eps_n" | "hysteresis") {
            assert_eq!(with(max), Ok(()), "{name} at its largest value");
        }
    }
    let hysteresis = |h: f32| Tolerances { hysteresis: h, ..d }.validate();
    assert_eq!(hysteresis(1.0_f32.next_down()), Ok(()));
    assert_eq!(hysteresis(1.0), Err(OutOfRange("hysteresis")));
    let make = |f: f32| {
        let t = Tolerances {
            make_force_n: f,
            ..d
        };
        t.validate()
    };
    assert_eq!(make(d.force_eps_n), Ok(()));
    assert_eq!(
        make(d.force_eps_n.next_down()),
        Err(OutOfRange("make_force_n"))
    );
}
