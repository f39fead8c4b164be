//! Nothing emits NaN: bad inputs give the documented safe value and a flag, and every backend keeps
//! the trait's contract (finite in, finite out) at the extremes of the f32 range.

use crate::accuracy::Accuracy;
use core::hint::black_box as bb;
use softfinger_core::{Flags, Quat, Rot3, Vec3};
use softfinger_mcu_bench::check::Checker;

pub fn checks<M: Accuracy>(c: &mut Checker) {
    // The Math contract: finite input gives finite output, even at the ends of the range.
    for x in [
        1.0e30f32,
        -1.0e30,
        f32::MAX,
        1.0e-30,
        f32::MIN_POSITIVE,
        1.0e-45,
    ] {
        let (s, co) = M::sin_cos(bb(x));
        c.ok_at("finite in, finite out: sin", x, M::sin(bb(x)).is_finite());
        c.ok_at("finite in, finite out: cos", x, M::cos(bb(x)).is_finite());
        c.ok_at(
            "finite in, finite out: sin_cos",
            x,
            s.is_finite() && co.is_finite(),
        );
        c.ok_at(
            "finite in, finite out: atan2(x, 1)",
            x,
            M::atan2(bb(x), bb(1.0)).is_finite(),
        );
        c.ok_at(
            "finite in, finite out: atan2(1, x)",
            x,
            M::atan2(bb(1.0), bb(x)).is_finite(),
        );
        c.ok_at(
            "finite in, finite out: sqrt(|x|)",
            x,
            M::sqrt(bb(x.abs())).is_finite(),
        );
    }

    let nan = f32::NAN;
    let inf = f32::INFINITY;
    let (r, f) = Rot3::from_axis_angle::<M>(bb(Vec3::new(nan, 0.0, 1.0)), bb(1.0));
    c.ok(
        "rodrigues, NaN axis: identity, NON_FINITE_INPUT",
        r == Rot3::IDENTITY && f == Flags::NON_FINITE_INPUT,
    );
    let (r, f) = Rot3::from_axis_angle::<M>(bb(Vec3::Z), bb(inf));
    c.ok(
        "rodrigues, inf angle: identity, NON_FINITE_INPUT",
        r == Rot3::IDENTITY && f == Flags::NON_FINITE_INPUT,
    );
    let (r, f) = Rot3::from_axis_angle::<M>(bb(Vec3::new(3e38, 3e38, 0.0)), bb(1.0));
    c.ok(
        "rodrigues, axis norm overflows: identity, NON_FINITE_INPUT",
        r == Rot3::IDENTITY && f == Flags::NON_FINITE_INPUT,
    );
    let (r, f) = Rot3::from_axis_angle::<M>(bb(Vec3::ZERO), bb(1.0));
    c.ok(
        "rodrigues, zero axis: identity, ZERO_AXIS",
        r == Rot3::IDENTITY && f == Flags::ZERO_AXIS,
    );
    let (r, f) = Rot3::from_rotation_vector::<M>(bb(Vec3::new(0.0, inf, 0.0)));
    c.ok(
        "rotation vector inf: identity, NON_FINITE_INPUT",
        r == Rot3::IDENTITY && f == Flags::NON_FINITE_INPUT,
    );

    let (q, f) = Quat::from_rotation_vector::<M>(bb(Vec3::new(nan, 0.0, 0.0)));
    c.ok(
        "quat exp, NaN: identity, NON_FINITE_INPUT",
        q == Quat::IDENTITY && f == Flags::NON_FINITE_INPUT,
    );
    let (q, f) = Quat::new(3e38, 3e38, 0.0, 0.0).normalized_checked::<M>();
    c.ok(
        "normalize, norm overflows: identity, NON_FINITE_INPUT",
        q == Quat::IDENTITY && f == Flags::NON_FINITE_INPUT,
    );
    let (q, f) = bb(Quat::new(0.0, 0.0, 0.0, 0.0)).normalized_checked::<M>();
    c.ok(
        "normalize, zero: identity, ZERO_AXIS",
        q == Quat::IDENTITY && f == Flags::ZERO_AXIS,
    );
    let (q, f) = bb(Quat::new(2.0, 0.0, 0.0, 0.0)).normalized_checked::<M>();
    // √4 is exact in every backend (powers of four), so the result is exactly the identity.
    c.ok(
        "normalize, norm 2: identity, NON_UNIT_QUAT",
        q == Quat::IDENTITY && f == Flags::NON_UNIT_QUAT,
    );
}
