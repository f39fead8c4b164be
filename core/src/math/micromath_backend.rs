//! The micromath backend: fast low-accuracy approximations from the `micromath` crate, wrapped so
//! that they meet the [`Math`] contract.

use super::Math;
use micromath::F32Ext;

/// micromath's approximations. Documented by micromath: sin/cos/atan2 max error 0.002 (atan2
/// 0.162° = 0.0028 rad), sqrt ~5 % average deviation (one bit-pattern step, no Newton iteration).
/// Measured figures are on each function.
///
/// Wrapping (micromath itself returns NaN or out-of-range values in these cases):
/// - sin/cos: micromath's reduction `floor(x/2π)` saturates for |x| ≳ 1.35e10 and the result then
///   grows without bound (up to ∞, NaN for ∞ input); for |x| ≥ 2^33 and non-finite x the wrapper
///   returns 0. (From |x| ≈ 1e6 on micromath's results are already meaningless, since x/2π keeps
///   too few fraction bits, but they stay within [-1, 1].)
/// - atan2: micromath squares its inputs, so |x|, |y| both ≳ 1.8e19 (overflow) or both ≲ 1e-19
///   (underflow to 0/0) give NaN; the wrapper then divides both by max(|x|, |y|) first. Infinities
///   are mapped to the IEEE limits, NaN and (±0, ±0) give 0. For y = -0, x < 0 micromath returns +π
///   (IEEE: -π).
/// - sqrt: x ≤ 0 and NaN give 0 (micromath: NaN for negative x), +∞ gives `f32::MAX`. Subnormal x
///   are NOT fixed: micromath's result is then far too large, by up to a factor 2170 (sqrt(1.4e-45)
///   gives 8.1e-20 instead of 3.7e-23).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Micromath;

/// 2^33: beyond this the wrapper returns 0 for sin/cos (see [`Micromath`]).
const TRIG_LIMIT: f32 = 8_589_934_592.0;
/// With |x| + |y| inside [2^-60, 2^60] micromath's atan2 neither overflows nor underflows to 0/0
/// (the larger magnitude is then in [2^-61, 2^60], its square a normal float).
const ATAN2_SAFE_MIN: f32 = 8.673_617_4e-19;
const ATAN2_SAFE_MAX: f32 = 1.152_921_5e18;

impl Math for Micromath {
    const NAME: &'static str = "micromath";

    /// micromath `sin`. Max abs error 1.1e-3 over |x| ≤ 6.3 (test `trig_error_sweep_one_period`),
    /// 2.3e-3 over |x| ≤ 1e4 (test `sin_error_sweep`: the f32 reduction x/2π adds error as |x|
    /// grows, beyond micromath's documented 0.002); meaningless beyond |x| ≈ 1e6 (see the type's
    /// docs).
    #[inline]
    fn sin(x: f32) -> f32 {
        if x.abs() < TRIG_LIMIT {
            F32Ext::sin(x)
        } else {
            0.0
        }
    }

    /// micromath `cos`. Max abs error 1.1e-3 over |x| ≤ 6.3 (test `trig_error_sweep_one_period`),
    /// 1.9e-3 over |x| ≤ 1e4 (test `cos_error_sweep`). `sin_cos` is (`sin`, `cos`): max 2.3e-3
    /// over |x| ≤ 1e4 (test `sin_cos_error_sweep`).
    #[inline]
    fn cos(x: f32) -> f32 {
        if x.abs() < TRIG_LIMIT {
            F32Ext::cos(x)
        } else {
            0.0
        }
    }

    /// micromath `atan2`. Max abs error 2.8e-3 rad over all finite inputs (test
    /// `atan2_error_sweep`, counting +π and -π as the same angle). Relative error for small
    /// angles: 6.3 % for y > 0, x = 1 (its slope at 0 is 0.937 instead of 1), and 100 % (result 0)
    /// for y < 0 < x with |y/x| ≲ 4e-7 or for |x·y| ≲ 1e-45 (test
    /// `atan2_small_angle_error_sweep`). Unsuitable where relative accuracy near 0 matters (e.g.
    /// `2·atan2(s, w)/s`).
    #[inline]
    fn atan2(y: f32, x: f32) -> f32 {
        // NaN or ∞ in either argument makes the sum fail the range test.
        let sum = x.abs() + y.abs();
        if (ATAN2_SAFE_MIN..=ATAN2_SAFE_MAX).contains(&sum) {
            F32Ext::atan2(y, x)
        } else {
            atan2_edge(y, x)
        }
    }

    /// micromath `sqrt`. Max relative error 6.07 % for normal x (test `sqrt_error_sweep`); for
    /// subnormal x up to a factor 2170 too large (see the type's docs).
    #[inline]
    fn sqrt(x: f32) -> f32 {
        if x > 0.0 {
            if x < f32::INFINITY {
                F32Ext::sqrt(x)
            } else {
                f32::MAX
            }
        } else {
            0.0
        }
    }
}

/// atan2 outside micromath's safe magnitude range, for NaN and for infinities.
#[cold]
#[inline(never)]
fn atan2_edge(y: f32, x: f32) -> f32 {
    let m = x.abs().max(y.abs());
    if y.is_nan() || x.is_nan() || m == 0.0 {
        0.0
    } else if m == f32::INFINITY {
        let squash = |v: f32| {
            let unit = if v.abs() == f32::INFINITY { 1.0 } else { 0.0 };
            if v.is_sign_negative() {
                -unit
            } else {
                unit
            }
        };
        let (sy, sx) = (squash(y), squash(x));
        if sy == 0.0 && sx == 0.0 {
            0.0
        } else {
            F32Ext::atan2(sy, sx)
        }
    } else {
        // One component is now ±1 exactly; the other may underflow to ±0, which is harmless.
        F32Ext::atan2(y / m, x / m)
    }
}

#[cfg(test)]
mod tests {
    use super::super::sweep::{self, report, TRIG_RANGE};
    use super::*;

    #[test]
    fn safe_range_constants_are_powers_of_two() {
        assert_eq!(TRIG_LIMIT, f32::from_bits((127 + 33) << 23));
        assert_eq!(ATAN2_SAFE_MIN, f32::from_bits((127 - 60) << 23));
        assert_eq!(ATAN2_SAFE_MAX, f32::from_bits((127 + 60) << 23));
    }

    /// micromath documents 0.002 for sin/cos; that is the error of its approximation after an exact
    /// reduction, checked here over one period and a bit more. Measured 1.09e-3: the bound is the
    /// crate's documented figure (1.8x), not a margin over the measurement.
    #[test]
    fn trig_error_sweep_one_period() {
        let xs = sweep::trig_samples(6.3);
        let e = sweep::sin_cos_abs::<Micromath>(&xs);
        report("micromath", "sin_cos abs |x|<=6.3", &e);
        assert!(e.max <= 2e-3, "{e:?}");
    }

    /// Over |x| ≤ 1e4 the f32 reduction x·(1/2π) adds up to half an ulp of x/2π (6.1e-5 turns =
    /// 3.8e-4 rad at |x| = 1e4) plus the 2^-25 relative error of the f32 constant times x
    /// (3e-4 rad): bound 0.002 + 7e-4. Measured 2.32e-3 (sin, sin_cos) and 1.86e-3 (cos): this
    /// bound is the documented figure plus the worst-case reduction error, not a margin.
    const TRIG_BOUND: f64 = 2.7e-3;

    #[test]
    fn sin_error_sweep() {
        let e = sweep::sin_abs::<Micromath>(&sweep::trig_samples(TRIG_RANGE));
        report("micromath", "sin abs |x|<=1e4", &e);
        assert!(e.max <= TRIG_BOUND, "{e:?}");
    }

    #[test]
    fn cos_error_sweep() {
        let e = sweep::cos_abs::<Micromath>(&sweep::trig_samples(TRIG_RANGE));
        report("micromath", "cos abs |x|<=1e4", &e);
        assert!(e.max <= TRIG_BOUND, "{e:?}");
    }

    #[test]
    fn sin_cos_error_sweep() {
        let e = sweep::sin_cos_abs::<Micromath>(&sweep::trig_samples(TRIG_RANGE));
        report("micromath", "sin_cos abs |x|<=1e4", &e);
        assert!(e.max <= TRIG_BOUND, "{e:?}");
    }

    /// Bound: micromath documents 0.1620° = 2.83e-3 rad for its normalized atan2. Measured
    /// 2.828e-3 rad: the sweep reaches the documented figure, which is asserted as it stands.
    #[test]
    fn atan2_error_sweep() {
        let (abs, rel) = sweep::atan2_abs_rel::<Micromath>(&sweep::atan2_samples());
        report("micromath", "atan2 abs", &abs);
        report("micromath", "atan2 rel", &rel);
        assert!(abs.max <= 2.83e-3, "{abs:?}");
    }

    /// micromath's first-octant formula tends to (π/2)·0.596227·t for small t = y/x, i.e. a
    /// relative error of 1 - 0.93655 = 6.35 % for small angles (bound 6.4 %; measured 6.345 %, the
    /// closed-form limit, so no margin): unusable for
    /// `2·atan2(s, w)/s`.
    #[test]
    fn atan2_small_angle_error_sweep() {
        let (first, all) = sweep::atan2_small_angle_rel::<Micromath>();
        report("micromath", "atan2 rel, small y/x, y > 0, x = 1", &first);
        report("micromath", "atan2 rel, small y/x, any signs", &all);
        assert!(first.max <= 0.064, "{first:?}");
        // For y < 0 < x micromath forms 4 + n (n ≈ -0.6·|y/x|) in f32 before subtracting 4, so
        // angles below ulp(4)/2·π/2 ≈ 3.7e-7 rad come out as 0; and 0.596·|x·y| underflows to 0
        // for |x·y| ≲ 1e-45. Both give 0 instead of a tiny angle: 100 % relative error (more
        // than 100 % would mean a wrong sign or quadrant).
        assert!(all.max <= 1.0, "{all:?}");
    }

    /// Bound for normal x: the bit-pattern estimate is linear in the significand between powers of
    /// two; for x = 4^k·(1 + f), f in [0, 1), it returns 2^k·(1 + f/2), whose relative error
    /// 1.5/√2 - 1 = 6.07 % is reached as x → 2·4^k; so 6.1 %. Measured 6.066 %, the closed-form
    /// limit (and 2171 for subnormal x, the limit below).
    #[test]
    fn sqrt_error_sweep() {
        let (normal, sub) = sweep::sqrt_rel::<Micromath>(&sweep::sqrt_samples());
        report("micromath", "sqrt rel, normal x", &normal);
        report("micromath", "sqrt rel, subnormal x", &sub);
        assert!(normal.max <= 0.061, "{normal:?}");
        // Subnormal x: micromath's result never drops below 1.5·2^-64 (bits (1 + 0x3f80_0000) >> 1
        // for the smallest subnormal 2^-149), against √(2^-149) = 2^-74.5: a ratio of
        // 1.5·2^10.5 = 2172, i.e. a relative error of 2171, reached at x = 2^-149.
        assert!(sub.max <= 2172.0, "{sub:?}");
    }
}
