//! The [`Math`] contract (see the trait docs), checked for every backend on special values, on one
//! float from every input class, and on random bit patterns over the whole finite range.

extern crate std;

use super::sweep::random_finite;
use super::{Fast, Libm, Math, Micromath};
use core::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
use std::vec::Vec;

/// One float of each class, both signs: zero, smallest and largest subnormal, smallest normal,
/// small, around 1, large, largest finite, and powers of ten across the range.
fn finite_classes() -> Vec<f32> {
    let mut v = std::vec![
        0.0,
        f32::from_bits(1),
        f32::from_bits(0x007f_ffff),
        f32::MIN_POSITIVE,
        1e-30,
        1e-7,
        0.5,
        1.0,
        FRAC_PI_4,
        FRAC_PI_2,
        PI,
        1e4,
        65_536.0,
        1e10,
        1e30,
        f32::MAX,
    ];
    let mut p = 1e-38f32;
    while p < 1e38 {
        v.push(p);
        p *= 10.0;
    }
    let neg: Vec<f32> = v.iter().map(|x| -x).collect();
    v.extend(neg);
    v
}

/// Every NaN and infinity the checks feed in (quiet and signalling-pattern NaNs of both signs).
fn non_finite() -> [f32; 6] {
    [
        f32::NAN,
        -f32::NAN,
        f32::from_bits(0x7f80_0001),
        f32::from_bits(0xffc0_1234),
        f32::INFINITY,
        f32::NEG_INFINITY,
    ]
}

fn check_trig<M: Math>() {
    let mut xs = finite_classes();
    xs.extend(random_finite(50_000, 0x5eed_0001));
    for x in xs {
        let (s, c) = M::sin_cos(x);
        for v in [M::sin(x), M::cos(x), s, c] {
            assert!(
                v.is_finite() && v.abs() <= 1.0,
                "{}: x={x:e} gave {v}",
                M::NAME
            );
        }
    }
    for x in non_finite() {
        assert_eq!(M::sin(x), 0.0, "{}: sin({x})", M::NAME);
        assert_eq!(M::cos(x), 0.0, "{}: cos({x})", M::NAME);
        assert_eq!(M::sin_cos(x), (0.0, 0.0), "{}: sin_cos({x})", M::NAME);
    }
}

fn check_atan2<M: Math>() {
    let classes = finite_classes();
    let mut pairs: Vec<(f32, f32)> = classes
        .iter()
        .flat_map(|&y| classes.iter().map(move |&x| (y, x)))
        .collect();
    pairs.extend(random_finite(50_000, 0x5eed_0002).zip(random_finite(50_000, 0x5eed_0003)));
    for (y, x) in pairs {
        let a = M::atan2(y, x);
        assert!(
            a.is_finite() && a.abs() <= PI,
            "{}: atan2({y:e}, {x:e}) = {a}",
            M::NAME
        );
    }
    // NaN anywhere gives 0.
    for n in non_finite().into_iter().filter(|v| v.is_nan()) {
        for other in [0.0, 1.0, -1.0, f32::INFINITY, f32::NAN] {
            assert_eq!(M::atan2(n, other), 0.0, "{}: atan2({n}, {other})", M::NAME);
            assert_eq!(M::atan2(other, n), 0.0, "{}: atan2({other}, {n})", M::NAME);
        }
    }
    // All four signed-zero pairs give 0.
    for (y, x) in [(0.0, 0.0), (-0.0, 0.0), (0.0, -0.0), (-0.0, -0.0)] {
        assert_eq!(M::atan2(y, x), 0.0, "{}: atan2({y}, {x})", M::NAME);
    }
    // Signed zero y with nonzero x: 0 towards +x, π (either sign) towards -x.
    for x in [1.0f32, 1e-40, 1e30] {
        assert_eq!(M::atan2(0.0, x), 0.0, "{}", M::NAME);
        assert_eq!(M::atan2(-0.0, x), 0.0, "{}", M::NAME);
        assert_eq!(M::atan2(0.0, -x), PI, "{}", M::NAME);
        assert_eq!(M::atan2(-0.0, -x).abs(), PI, "{}", M::NAME);
    }
    // Infinities: the IEEE 754 limits, to within 1 ulp(π) = 2.4e-7, an ulp argument. Measured:
    // libm 1.19e-7 (π/2 one ulp low), fast and micromath exact (their wrappers return the limits).
    let inf = f32::INFINITY;
    let tol = 2.4e-7;
    let cases = [
        ((inf, inf), FRAC_PI_4),
        ((inf, -inf), 3.0 * FRAC_PI_4),
        ((-inf, inf), -FRAC_PI_4),
        ((-inf, -inf), -3.0 * FRAC_PI_4),
        ((inf, 1.0), FRAC_PI_2),
        ((-inf, -1e30), -FRAC_PI_2),
        ((1.0, inf), 0.0),
        ((1.0, -inf), PI),
        ((-1.0, -inf), -PI),
        ((0.0, inf), 0.0),
    ];
    for ((y, x), want) in cases {
        let a = M::atan2(y, x);
        // Distance modulo 2π: micromath gives +π where IEEE gives -π (the contract allows it).
        let d = (a - want).abs();
        let d = d.min((2.0 * PI - d).abs());
        assert!(d <= tol, "{}: atan2({y}, {x}) = {a}, want {want}", M::NAME);
    }
}

fn check_sqrt<M: Math>() {
    let mut xs = finite_classes();
    xs.extend(random_finite(50_000, 0x5eed_0004));
    for x in xs {
        let r = M::sqrt(x);
        assert!(r.is_finite() && r >= 0.0, "{}: sqrt({x:e}) = {r}", M::NAME);
        if x <= 0.0 {
            assert_eq!(r, 0.0, "{}: sqrt({x:e})", M::NAME);
        }
    }
    for x in non_finite() {
        let want = if x == f32::INFINITY { f32::MAX } else { 0.0 };
        assert_eq!(M::sqrt(x), want, "{}: sqrt({x})", M::NAME);
    }
}

#[test]
fn fast_meets_the_contract() {
    check_trig::<Fast>();
    check_atan2::<Fast>();
    check_sqrt::<Fast>();
}

#[test]
fn libm_meets_the_contract() {
    check_trig::<Libm>();
    check_atan2::<Libm>();
    check_sqrt::<Libm>();
}

#[test]
fn micromath_meets_the_contract() {
    check_trig::<Micromath>();
    check_atan2::<Micromath>();
    check_sqrt::<Micromath>();
}

/// IEEE sign conventions that Fast and Libm follow exactly (micromath returns +π for y = -0).
#[test]
fn fast_and_libm_give_minus_pi_for_minus_zero_over_negative_x() {
    assert_eq!(Fast::atan2(-0.0, -1.0), -PI);
    assert_eq!(Libm::atan2(-0.0, -1.0), -PI);
    assert_eq!(Fast::atan2(-0.0, 1.0).to_bits(), (-0.0f32).to_bits());
}
