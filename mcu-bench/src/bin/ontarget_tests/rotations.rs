//! Rodrigues' formula (eq. 4) and the quaternion exp/log maps against closed forms.

use crate::accuracy::Accuracy;
use core::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
use core::hint::black_box as bb;
use softfinger_core::{Flags, Quat, Rot3, Vec3};
use softfinger_mcu_bench::check::Checker;

/// 1/√3 correctly rounded: the components of the unit (1, 1, 1) axis.
const INV_SQRT3: f32 = 0.577_350_26;

fn arr(v: Vec3) -> [f32; 3] {
    v.to_array()
}

pub fn checks<M: Accuracy>(c: &mut Checker) {
    rodrigues::<M>(c);
    quat_maps::<M>(c);
    round_trips::<M>(c);
}

/// Rodrigues' formula (eq. 4): quarter and third turns, and a non-unit axis.
fn rodrigues<M: Accuracy>(c: &mut Checker) {
    // 90° about z: R·x = (cos, sin, 0) at π/2 = (0, 1, 0). Each entry is off by at most the sin/cos
    // error, plus 1.2e-7 for the f32 rounding of π/2.
    let (r, f) = Rot3::from_axis_angle::<M>(bb(Vec3::Z), bb(FRAC_PI_2));
    let t = M::TRIG + 1.2e-7;
    c.ok("rodrigues 90 deg about z: no flag", f.is_empty());
    c.close_all(
        "rodrigues 90 deg about z maps x to y",
        &arr(r.apply(Vec3::X)),
        &[0.0, 1.0, 0.0],
        t,
    );
    c.close_all(
        "rodrigues 90 deg about z maps y to -x",
        &arr(r.apply(Vec3::Y)),
        &[-1.0, 0.0, 0.0],
        t,
    );
    c.close_all(
        "rodrigues 90 deg about z keeps z",
        &arr(r.apply(Vec3::Z)),
        &[0.0, 0.0, 1.0],
        t,
    );

    // 120° about (1,1,1)/√3 cycles the axes x → y → z → x. An entry a_i a_j (1 - c) + δ_ij c ± a_k s
    // is off by ≤ (1/3 + 1)·TRIG + 0.58·TRIG < 2·TRIG; 1e-6 covers the f32 rounding of the products
    // and of 2π/3 (about ten operations of ulp ≤ 6e-8).
    let axis = Vec3::new(INV_SQRT3, INV_SQRT3, INV_SQRT3);
    let (r, f) = Rot3::from_axis_angle::<M>(bb(axis), bb(2.0 * PI / 3.0));
    let t = 2.0 * M::TRIG + 1.0e-6;
    c.ok("rodrigues 120 deg about (1,1,1): no flag", f.is_empty());
    c.close_all(
        "rodrigues 120 deg about (1,1,1): x -> y",
        &arr(r.apply(Vec3::X)),
        &[0.0, 1.0, 0.0],
        t,
    );
    c.close_all(
        "rodrigues 120 deg about (1,1,1): y -> z",
        &arr(r.apply(Vec3::Y)),
        &[0.0, 0.0, 1.0],
        t,
    );
    c.close_all(
        "rodrigues 120 deg about (1,1,1): z -> x",
        &arr(r.apply(Vec3::Z)),
        &[1.0, 0.0, 0.0],
        t,
    );

    // A non-unit axis is normalised (√4 = 2, exact in every backend here: micromath's bit trick is
    // exact at powers of four) and flagged.
    let (r, f) = Rot3::from_axis_angle::<M>(bb(Vec3::new(2.0, 0.0, 0.0)), bb(FRAC_PI_2));
    c.ok(
        "rodrigues, axis of length 2: NON_UNIT_QUAT",
        f == Flags::NON_UNIT_QUAT,
    );
    let t = M::TRIG + 1.2e-7;
    c.close_all(
        "rodrigues 90 deg about 2x maps y to z",
        &arr(r.apply(Vec3::Y)),
        &[0.0, 0.0, 1.0],
        t,
    );
}

/// The axis-angle quaternion, and the log and exp maps at known rotations.
fn quat_maps<M: Accuracy>(c: &mut Checker) {
    // Quaternion of 90° about z is (cos π/4, 0, 0, sin π/4); its rotation of x is y.
    let q = Quat::from_axis_angle::<M>(bb(Vec3::Z), bb(FRAC_PI_2));
    let s = core::f32::consts::FRAC_1_SQRT_2;
    let t = M::TRIG + 1.2e-7;
    c.close_all(
        "quat 90 deg about z",
        &[q.w, q.x, q.y, q.z],
        &[s, 0.0, 0.0, s],
        t,
    );
    // rotate() has no trig: each output component is off by ≤ ~4·(component error) via the two cross
    // products (|u|, |w| ≤ 1).
    c.close_all(
        "quat 90 deg about z rotates x to y",
        &arr(q.rotate(Vec3::X)),
        &[0.0, 1.0, 0.0],
        4.0 * t,
    );

    // Log map. For a rotation of angle θ the result is v·2·atan2(|v|, w)/|v|. The atan2 error gives
    // ≤ 2·ATAN2 per component (|v_i|/|v| ≤ 1). |v| comes from sqrt with relative error ε ≤ SQRT_REL;
    // the log-derivative of atan2(s, w)/s in s lies in [-1, 0] (sin x cos x ≤ x), so that moves the
    // result by ≤ θ·SQRT_REL. Plus 1e-6 for f32 rounding.
    let log_tol = |theta: f32| 2.0 * M::ATAN2 + theta * M::SQRT_REL + 1.0e-6;
    // 90° about z: (cos π/4, 0, 0, sin π/4) → (0, 0, π/2).
    let q = Quat::new(s, 0.0, 0.0, s);
    let w = bb(q).to_rotation_vector::<M>();
    c.close_all(
        "log(90 deg about z) = (0, 0, pi/2)",
        &arr(w),
        &[0.0, 0.0, FRAC_PI_2],
        log_tol(FRAC_PI_2),
    );
    // (1/2, -1/2, 1/2, -1/2) = (cos 60°, sin 60°·(-1, 1, -1)/√3): 120° about (-1, 1, -1)/√3.
    let w = bb(Quat::new(0.5, -0.5, 0.5, -0.5)).to_rotation_vector::<M>();
    let k = 2.0 * PI / 3.0 * INV_SQRT3;
    c.close_all(
        "log(120 deg about (-1,1,-1))",
        &arr(w),
        &[-k, k, -k],
        log_tol(2.0 * PI / 3.0),
    );
    // q and -q are the same rotation; the log map takes the w >= 0 hemisphere, exactly.
    c.ok(
        "log(q) == log(-q) exactly",
        bb(Quat::new(-0.5, 0.5, -0.5, 0.5)).to_rotation_vector::<M>() == w,
    );

    // Exp map: (0, 0, π/2) → (cos π/4, 0, 0, sin π/4). The half angle h comes from sqrt((π/2)²), off
    // by ≤ h·SQRT_REL rad, which moves cos h and sin h by at most that; plus the kernels' TRIG.
    let (q, f) = Quat::from_rotation_vector::<M>(bb(Vec3::new(0.0, 0.0, FRAC_PI_2)));
    let t = M::TRIG + M::SQRT_REL * FRAC_PI_4 + 2.0e-7;
    c.ok("exp(0, 0, pi/2): no flag", f.is_empty());
    c.close_all(
        "exp(0, 0, pi/2)",
        &[q.w, q.x, q.y, q.z],
        &[s, 0.0, 0.0, s],
        t,
    );
}

/// Round trips of the exp and log maps, and the matrix of a quaternion against Rodrigues.
fn round_trips<M: Accuracy>(c: &mut Checker) {
    // Round trips log(exp(w)) = w from tiny (series branch) to near π. exp puts each quaternion
    // component within TRIG + (θ/2)·SQRT_REL (as above); the log map's sensitivity to a component is
    // ≤ 2; then the log map's own error. Total 2·TRIG + 2·ATAN2 + 2θ·SQRT_REL, and 1e-6·(1 + θ) of
    // f32 rounding (near π the axis is carried by components of size ~1).
    let dir = Vec3::new(0.3, -0.5, 0.8) * (1.0 / 0.989_949_5); // |(0.3, -0.5, 0.8)| = 0.9899495
    const CASES: [(f32, &str); 5] = [
        (1.0e-5, "log(exp(w)) = w, |w| = 1e-5"),
        (0.06, "log(exp(w)) = w, |w| = 0.06"),
        (1.0, "log(exp(w)) = w, |w| = 1"),
        (2.5, "log(exp(w)) = w, |w| = 2.5"),
        (3.1, "log(exp(w)) = w, |w| = 3.1"),
    ];
    for (theta, name) in CASES {
        let w = dir * theta;
        let (q, _) = Quat::from_rotation_vector::<M>(bb(w));
        let back = bb(q).to_rotation_vector::<M>();
        let t = 2.0 * M::TRIG + 2.0 * M::ATAN2 + 2.0 * theta * M::SQRT_REL + 1.0e-6 * (1.0 + theta);
        // Near θ = π an error in the angle can cross π, and the log map (angle in [0, π]) then
        // returns the same rotation's other representative, w − 2π·w/|w|: accept either.
        let other = dir * (theta - 2.0 * PI);
        c.close_all_either(name, &arr(back), &arr(w), &arr(other), t);
    }

    // from_quat and from_axis_angle describe the same rotation: compare R·v for v = (1, 2, 3)
    // (|v| = 3.74; both sides within ~2·TRIG per entry, three entries per component).
    let axis = Vec3::new(0.267_261_24, 0.534_522_5, 0.801_783_7);
    let (r1, _) = Rot3::from_axis_angle::<M>(bb(axis), bb(1.0));
    let r2 = Rot3::from_quat(Quat::from_axis_angle::<M>(axis, 1.0));
    let v = Vec3::new(1.0, 2.0, 3.0);
    c.close_all(
        "Rot3::from_quat agrees with Rodrigues",
        &arr(r1.apply(v)),
        &arr(r2.apply(v)),
        3.0 * 3.74 * 2.0 * M::TRIG + 4.0e-6,
    );
}
