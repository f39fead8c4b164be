//! Every threshold of the state machine bracketed just below and just above its value, one rule at a
//! time: each case starts from inputs where every other condition of the rule already holds, so the
//! threshold under test alone decides the transition. "Just" is one part in 10⁴ (or the exact value
//! for the `≥`/`≤` edges), far finer than the factor-of-two spacing of the table in `tests.rs`.
//!
//! Also the torsional friction limit of the spin spring ([`crate::contact::spin`]), the other torque
//! threshold of the contact.

use super::*;
use crate::contact::spin::{torsion_limit, SpinSpring};

/// Just below and just above a threshold value.
const BELOW: f32 = 1.0 - 1e-4;
const ABOVE: f32 = 1.0 + 1e-4;

/// A tangential direction off the axes (unit), so a norm computed from one component fails.
fn along(mag: f32) -> Vec3 {
    Vec3::new(0.6 * mag, -0.8 * mag, 0.0)
}

/// Along x: for the cases exactly at a threshold, where a norm from two components could round
/// to either side.
fn x(mag: f32) -> Vec3 {
    Vec3::new(mag, 0.0, 0.0)
}

use ContactState::{Broken, Rolling, Sliding};

fn check(name: &str, from: ContactState, i: StateInputs, want: (ContactState, Reason)) {
    assert_eq!(next_state(from, &i, &P), want, "{name}: {i:?}");
}

/// One threshold bracketed: `at(BELOW)` must give `want[0]` and `at(ABOVE)` `want[1]`. `below` names
/// the case below; the case above is named with "below" replaced by "above".
fn bracket(
    below: &str,
    from: ContactState,
    at: impl Fn(f32) -> StateInputs,
    want: [(ContactState, Reason); 2],
) {
    check(below, from, at(BELOW), want[0]);
    check(&below.replace("below", "above"), from, at(ABOVE), want[1]);
}

/// Rolling with f_N = 2 N and every condition of the cone rule met except the one a case varies:
/// |f_T| over the hysteresis cone (1.68 N), a_N = 0, slipping at 0.01 m/s, no rolling displacement.
fn over_cone() -> StateInputs {
    StateInputs {
        tangential_force_n: along(1.7),
        tangential_velocity: along(0.01),
        ..pressed()
    }
}

/// Sliding with every condition of the stick rule met except the one a case varies.
fn ready_to_stick() -> StateInputs {
    StateInputs {
        tangential_force_n: along(1.0),
        tangential_velocity: along(0.001),
        time_in_state_s: 0.5,
        ..pressed()
    }
}

const SLIDE: (ContactState, Reason) = (Sliding, Reason::ConeExceeded);
const STAY_ROLLING: (ContactState, Reason) = (Rolling, Reason::Kept);
const STAY_SLIDING: (ContactState, Reason) = (Sliding, Reason::Kept);
const STUCK: (ContactState, Reason) = (Rolling, Reason::Stuck);

#[test]
fn make_force_is_bracketed() {
    let at = |f: f32| StateInputs {
        normal_force_n: f,
        ..pressed()
    };
    check("f_N = f_make", Broken, at(0.05), (Broken, Reason::Kept));
    bracket(
        "f_N below f_make",
        Broken,
        |s| at(0.05 * s),
        [(Broken, Reason::Kept), (Rolling, Reason::MadeContact)],
    );
}

#[test]
fn recontact_dwell_is_bracketed() {
    let at = |t: f32| StateInputs {
        time_in_state_s: t,
        ..pressed()
    };
    check(
        "t below t_broken",
        Broken,
        at(0.002 * BELOW),
        (Broken, Reason::Kept),
    );
    check(
        "t = t_broken",
        Broken,
        at(0.002),
        (Rolling, Reason::MadeContact),
    );
    check(
        "t above t_broken",
        Broken,
        at(0.002 * ABOVE),
        (Rolling, Reason::MadeContact),
    );
}

/// Separation needs f_N ≤ ε_f and (a_N > ε_a or gap > ε_gap); each part alone, from both states.
#[test]
fn separation_thresholds_are_bracketed() {
    let lifted = |f: f32, a: f32, gap: f32| StateInputs {
        normal_force_n: f,
        normal_accel: a,
        gap_m: gap,
        ..StateInputs::default()
    };
    for from in [Rolling, Sliding] {
        let kept = (from, Reason::Kept);
        let broken = (Broken, Reason::Separated);
        // The force, with a clear separating acceleration.
        check("f_N = ε_f, a_N > 0", from, lifted(0.01, 1.0, 0.0), broken);
        bracket(
            "f_N below ε_f",
            from,
            |s| lifted(0.01 * s, 1.0, 0.0),
            [broken, kept],
        );
        // The separating acceleration alone (touching: gap 0).
        check("a_N = ε_a", from, lifted(0.0, 0.05, 0.0), kept);
        bracket(
            "a_N below ε_a",
            from,
            |s| lifted(0.0, 0.05 * s, 0.0),
            [kept, broken],
        );
        // The gap alone (no acceleration).
        check("gap = ε_gap", from, lifted(0.0, 0.0, 1e-4), kept);
        bracket(
            "gap below ε_gap",
            from,
            |s| lifted(0.0, 0.0, 1e-4 * s),
            [kept, broken],
        );
    }
}

/// In rolling, a force at or below ε_f (touching, not separating) keeps rolling whatever else
/// happens: even a tilt rate far above any twist threshold.
#[test]
fn rolling_without_force_keeps_rolling_at_the_force_threshold() {
    let at = |f: f32| StateInputs {
        normal_force_n: f,
        gap_m: 0.0,
        tilt_rate_sq: 1e12,
        ..StateInputs::default()
    };
    check("f_N = ε_f", Rolling, at(0.01), STAY_ROLLING);
    check("f_N below ε_f", Rolling, at(0.01 * BELOW), STAY_ROLLING);
    // Just above ε_f the twist threshold f_N·μ_s/(k_τ·r) ≈ 0.2 rad/s is exceeded.
    check(
        "f_N above ε_f",
        Rolling,
        at(0.01 * ABOVE),
        (Sliding, Reason::TwistExceeded),
    );
}

/// The static cone with its hysteresis margin: |f_T| > μ_s·f_N·(1 + h) = 0.8·2·1.05 = 1.68 N.
#[test]
fn hysteresis_cone_is_bracketed() {
    let cone = 0.8 * 2.0 * 1.05;
    let at = |ft: f32| StateInputs {
        tangential_force_n: along(ft),
        ..over_cone()
    };
    bracket(
        "|f_T| below the cone",
        Rolling,
        |s| at(cone * s),
        [STAY_ROLLING, SLIDE],
    );
    // The plain static cone μ_s·f_N = 1.6 N is inside the margin.
    check(
        "|f_T| just over μ_s·f_N",
        Rolling,
        at(1.6 * ABOVE),
        STAY_ROLLING,
    );
    // The cone scales with f_N: at 4 N it is 3.36 N.
    let at4 = |ft: f32| StateInputs {
        normal_force_n: 4.0,
        tangential_force_n: along(ft),
        ..over_cone()
    };
    check("4 N, below", Rolling, at4(2.0 * cone * BELOW), STAY_ROLLING);
    check("4 N, above", Rolling, at4(2.0 * cone * ABOVE), SLIDE);
}

/// |a_N| ≤ tol_a counts as a_N = 0; the cone rule needs it, in both signs.
#[test]
fn normal_acceleration_tolerance_is_bracketed_for_the_cone_rule() {
    for sign in [1.0f32, -1.0] {
        let at = |a: f32| StateInputs {
            normal_accel: sign * a,
            ..over_cone()
        };
        check("|a_N| = tol_a", Rolling, at(20.0), SLIDE);
        bracket(
            "|a_N| below tol_a",
            Rolling,
            |s| at(20.0 * s),
            [SLIDE, STAY_ROLLING],
        );
    }
}

/// Rolling → sliding by slip speed alone (a_T = 0): a probe dragged at constant speed.
#[test]
fn slip_speed_alone_takes_rolling_to_sliding_bracketed() {
    let at = |v: Vec3| StateInputs {
        tangential_velocity: v,
        tangential_accel: Vec3::ZERO,
        ..over_cone()
    };
    check("|v_T| = v_stick", Rolling, at(x(0.002)), STAY_ROLLING);
    bracket(
        "|v_T| below v_stick",
        Rolling,
        |s| at(along(0.002 * s)),
        [STAY_ROLLING, SLIDE],
    );
}

/// Rolling → sliding by tangential acceleration alone (v_T = 0).
#[test]
fn tangential_acceleration_alone_takes_rolling_to_sliding_bracketed() {
    let at = |a: Vec3| StateInputs {
        tangential_velocity: Vec3::ZERO,
        tangential_accel: a,
        ..over_cone()
    };
    check("|a_T| = ε_a", Rolling, at(x(0.05)), STAY_ROLLING);
    bracket(
        "|a_T| below ε_a",
        Rolling,
        |s| at(along(0.05 * s)),
        [STAY_ROLLING, SLIDE],
    );
}

/// The haptic rule: a force against the rolling displacement keeps rolling, unless the
/// displacement is below roll_eps (no rolling this step) or the force agrees with it.
#[test]
fn haptic_rule_is_bracketed() {
    let against = |d: Vec3| StateInputs {
        tangential_force_n: x(1.7),
        roll_disp_m: d,
        ..over_cone()
    };
    check("|d_roll| = roll_eps", Rolling, against(x(-1e-9)), SLIDE);
    let tilted = |d: f32| Vec3::new(-0.6 * d, 0.8 * d, 0.0);
    bracket(
        "|d_roll| below roll_eps",
        Rolling,
        |s| against(tilted(1e-9 * s)),
        [SLIDE, STAY_ROLLING],
    );
    // f_T·d_roll = 0 (rolling across the force) counts as agreeing; slightly against does not.
    // f_T = (1.5, −1, 0) N (|f_T| = 1.80 N, over the cone) and d_roll = (u, 1.5·u + δ, 0): the
    // dot product is exactly −δ in f32 (u = 2⁻¹⁷ m).
    let u = 1.0 / 131_072.0;
    let across = |delta: f32| StateInputs {
        tangential_force_n: Vec3::new(1.5, -1.0, 0.0),
        roll_disp_m: Vec3::new(u, 1.5 * u + delta, 0.0),
        ..over_cone()
    };
    check("f_T·d_roll = 0", Rolling, across(0.0), SLIDE);
    check(
        "f_T·d_roll just below 0",
        Rolling,
        across(1e-9),
        STAY_ROLLING,
    );
    check("f_T·d_roll just above 0", Rolling, across(-1e-9), SLIDE);
}

/// The twist threshold Δθ > f_N·μ_s/(k_τ·r): 40 rad/s at 2 N, 80 rad/s at 4 N, alone (no
/// tangential force or motion).
#[test]
fn twist_threshold_is_bracketed() {
    for (f_n, limit) in [(2.0f32, 40.0f32), (4.0, 80.0)] {
        let at = |rate: f32| StateInputs {
            normal_force_n: f_n,
            tilt_rate_sq: rate * rate,
            ..pressed()
        };
        bracket(
            "Δθ below Δθ_max",
            Rolling,
            |s| at(limit * s),
            [STAY_ROLLING, (Sliding, Reason::TwistExceeded)],
        );
    }
    // The rule holds whatever the normal acceleration (it does not need a_N = 0).
    let bouncing = StateInputs {
        normal_accel: 50.0,
        tilt_rate_sq: 41.0 * 41.0,
        ..pressed()
    };
    check(
        "Δθ above, a_N ≠ 0",
        Rolling,
        bouncing,
        (Sliding, Reason::TwistExceeded),
    );
}

/// Sliding → rolling: each of its five conditions bracketed alone.
#[test]
fn stick_rule_thresholds_are_bracketed() {
    // The kinetic cone μ_k·f_N = 1.2 N.
    let force = |ft: f32| StateInputs {
        tangential_force_n: along(ft),
        ..ready_to_stick()
    };
    bracket(
        "|f_T| below μ_k·f_N",
        Sliding,
        |s| force(1.2 * s),
        [STUCK, STAY_SLIDING],
    );
    // Slip speed v_stick.
    let speed = |v: Vec3| StateInputs {
        tangential_velocity: v,
        ..ready_to_stick()
    };
    check("|v_T| = v_stick", Sliding, speed(x(0.002)), STUCK);
    bracket(
        "|v_T| below v_stick",
        Sliding,
        |s| speed(along(0.002 * s)),
        [STUCK, STAY_SLIDING],
    );
    // Dwell t_slide.
    let dwell = |t: f32| StateInputs {
        time_in_state_s: t,
        ..ready_to_stick()
    };
    check(
        "t below t_slide",
        Sliding,
        dwell(0.02 * BELOW),
        STAY_SLIDING,
    );
    check("t = t_slide", Sliding, dwell(0.02), STUCK);
    check("t above t_slide", Sliding, dwell(0.02 * ABOVE), STUCK);
    // Normal acceleration tolerance, both signs.
    for sign in [1.0f32, -1.0] {
        let acc = |a: f32| StateInputs {
            normal_accel: sign * a,
            ..ready_to_stick()
        };
        check("|a_N| = tol_a", Sliding, acc(20.0), STUCK);
        check(
            "|a_N| above tol_a",
            Sliding,
            acc(20.0 * ABOVE),
            STAY_SLIDING,
        );
    }
    // Normal force ε_f (touching, not separating: no gap, no acceleration; no tangential force
    // so the kinetic cone does not decide).
    let normal = |f: f32| StateInputs {
        normal_force_n: f,
        gap_m: 0.0,
        tangential_force_n: Vec3::ZERO,
        ..ready_to_stick()
    };
    check("f_N = ε_f", Sliding, normal(0.01), STAY_SLIDING);
    check("f_N above ε_f", Sliding, normal(0.01 * ABOVE), STUCK);
}

/// The spin spring saturates when |φ_el| exceeds τ_max/k_z, in both directions, and the limit
/// τ_max = (3π/16)·μ·f_N·a is zero at and below f_N = 0. The torques measured exact; the limit
/// too, asserted within |τ|·ε (1-2 ulp, an ulp argument) of its closed form.
#[test]
fn torsion_limit_is_bracketed() {
    let (k_z, tau_max) = (0.05f32, 1e-3f32);
    let limit = tau_max / k_z; // 0.02 rad
    for sign in [1.0f32, -1.0] {
        let mut s = SpinSpring::default();
        let (tau, sat) = s.update(sign * limit * BELOW, k_z, tau_max);
        assert!(!sat, "below the limit ({sign})");
        assert_eq!(tau, sign * k_z * limit * BELOW);
        let mut s = SpinSpring::default();
        let (tau, sat) = s.update(sign * limit * ABOVE, k_z, tau_max);
        assert!(sat, "above the limit ({sign})");
        assert_eq!(s.elastic_rad, sign * limit);
        assert_eq!(tau, sign * tau_max, "clamped torque {tau}");
        assert_eq!(s.accumulated_rad, sign * limit * ABOVE);
    }
    assert_eq!(torsion_limit(0.8, 0.0, 0.005), 0.0);
    assert_eq!(torsion_limit(0.8, -1e-30, 0.005), 0.0);
    let t = torsion_limit(0.8, 1e-3, 0.005);
    let want = 3.0 * core::f32::consts::PI / 16.0 * 0.8 * 1e-3 * 0.005;
    assert!((t - want).abs() <= want * f32::EPSILON, "{t} vs {want}");
}

/// The names written to files and logs.
#[test]
fn state_names_are_the_file_and_log_names() {
    assert_eq!(
        [Broken.name(), Rolling.name(), Sliding.name()],
        ["broken", "rolling", "sliding"]
    );
}

/// Parameters whose thresholds are exact in binary, so a case can sit exactly on the boundary
/// (f_N = 2 N): static cone μ_s·f_N·(1 + h) = 0.5·2·1.25 = 1.25 N, kinetic cone μ_k·f_N = 0.5 N,
/// twist threshold f_N·μ_s/(k_τ·r) = 1/(2·0.5) = 1 rad/s.
const EXACT: StateParams = StateParams {
    mu_s: 0.5,
    mu_k: 0.25,
    k_tau: 2.0,
    radius_m: 0.5,
    tol: Tolerances {
        hysteresis: 0.25,
        ..P.tol
    },
    ..P
};

/// Exactly on each strict inequality: the rule does not fire (`>`, not `≥`; `≤`, not `<`).
#[test]
fn exactly_on_the_cone_twist_and_kinetic_thresholds() {
    let ask = |from, i: StateInputs| next_state(from, &i, &EXACT);
    let on_cone = StateInputs {
        tangential_force_n: x(1.25),
        ..over_cone()
    };
    assert_eq!(ask(Rolling, on_cone), STAY_ROLLING, "|f_T| = cone");
    let on_twist = StateInputs {
        tilt_rate_sq: 1.0,
        ..pressed()
    };
    assert_eq!(ask(Rolling, on_twist), STAY_ROLLING, "Δθ = Δθ_max");
    let over_twist = StateInputs {
        tilt_rate_sq: 1.0 + 1e-6,
        ..pressed()
    };
    assert_eq!(ask(Rolling, over_twist), (Sliding, Reason::TwistExceeded));
    let on_kinetic = StateInputs {
        tangential_force_n: x(0.5),
        ..ready_to_stick()
    };
    assert_eq!(ask(Sliding, on_kinetic), STUCK, "|f_T| = μ_k·f_N");
}
