//! The libm backend: the `libm` crate's f32 functions (ports of musl), wrapped so that they meet
//! the [`Math`] contract for non-finite input.

use super::Math;

/// libm's f32 functions: the accuracy reference among the backends (documented errors ≤ 1 ulp;
/// measured: sin/cos ≤ 0.5 ulp, atan2 ≤ 2 ulp, sqrt correctly rounded). On a
/// Cortex-M4F `sinf`/`cosf` are slow (~1270 instructions: they reduce and evaluate in f64, which
/// the single-precision FPU emulates in software), and `sqrtf` does not use `VSQRT`.
///
/// Wrapping: non-finite input to sin/cos gives 0 (libm gives NaN); NaN input to atan2 gives 0 and
/// `atan2(±0, ±0)` gives 0 (libm gives ±0 or ±π); sqrt of +∞ gives `f32::MAX`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Libm;

impl Math for Libm {
    const NAME: &'static str = "libm";

    /// `libm::sinf`. Max abs error 3.0e-8 over |x| ≤ 1e4 (test `sin_error_sweep`) and over all
    /// finite f32 (test `trig_error_sweep_whole_domain`).
    #[inline]
    fn sin(x: f32) -> f32 {
        if x.is_finite() {
            libm::sinf(x)
        } else {
            0.0
        }
    }

    /// `libm::cosf`. Max abs error 3.0e-8 over |x| ≤ 1e4 (test `cos_error_sweep`) and over all
    /// finite f32 (test `trig_error_sweep_whole_domain`).
    #[inline]
    fn cos(x: f32) -> f32 {
        if x.is_finite() {
            libm::cosf(x)
        } else {
            0.0
        }
    }

    /// `libm::sincosf`. Max abs error 3.0e-8 over |x| ≤ 1e4 (test `sin_cos_error_sweep`).
    #[inline]
    fn sin_cos(x: f32) -> (f32, f32) {
        if x.is_finite() {
            libm::sincosf(x)
        } else {
            (0.0, 0.0)
        }
    }

    /// `libm::atan2f`. Max abs error 2.4e-7 rad, max relative error 1.2e-7 over all finite inputs
    /// (test `atan2_error_sweep`); small angles (1e-30 ≤ |y/x| ≤ 0.1): max relative error 1.1e-7
    /// (test `atan2_small_angle_error_sweep`).
    #[inline]
    fn atan2(y: f32, x: f32) -> f32 {
        if (y == 0.0 && x == 0.0) || y.is_nan() || x.is_nan() {
            0.0
        } else {
            libm::atan2f(y, x)
        }
    }

    /// `libm::sqrtf`. Correctly rounded: max error 0.5 ulp, subnormals included (test
    /// `sqrt_error_sweep`).
    #[inline]
    fn sqrt(x: f32) -> f32 {
        if x > 0.0 {
            libm::sqrtf(x).min(f32::MAX)
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::sweep::{self, report, TRIG_RANGE};
    use super::*;

    // Bounds: libm documents its f32 functions as accurate to within 1 ulp. For sin/cos results
    // in [-1, 1] that is at most 2^-24 = 5.96e-8 absolute (1 ulp of values in [0.5, 1)).
    // Measured by these sweeps: 2.99e-8 for sin, cos and sin_cos, up to 1e4 and over every finite
    // x (half an ulp: correctly rounded on these inputs); the documented 1-ulp bound is 2.0x that.
    const TRIG_BOUND: f64 = 5.97e-8;

    #[test]
    fn sin_error_sweep() {
        let e = sweep::sin_abs::<Libm>(&sweep::trig_samples(TRIG_RANGE));
        report("libm", "sin abs |x|<=1e4", &e);
        assert!(e.max <= TRIG_BOUND, "{e:?}");
    }

    #[test]
    fn cos_error_sweep() {
        let e = sweep::cos_abs::<Libm>(&sweep::trig_samples(TRIG_RANGE));
        report("libm", "cos abs |x|<=1e4", &e);
        assert!(e.max <= TRIG_BOUND, "{e:?}");
    }

    #[test]
    fn sin_cos_error_sweep() {
        let e = sweep::sin_cos_abs::<Libm>(&sweep::trig_samples(TRIG_RANGE));
        report("libm", "sin_cos abs |x|<=1e4", &e);
        assert!(e.max <= TRIG_BOUND, "{e:?}");
    }

    #[test]
    fn trig_error_sweep_whole_domain() {
        let e = sweep::sin_cos_abs::<Libm>(&sweep::trig_samples_whole_domain());
        report("libm", "sin_cos abs, all finite x", &e);
        assert!(e.max <= TRIG_BOUND, "{e:?}");
    }

    /// Bound: ≤ 2 ulp of the result (musl's atan2f is not documented as correctly rounded; its
    /// arctangent core is quoted at < 1 ulp, the quadrant arithmetic adds up to one more rounding).
    /// Absolute: 2 ulp(π) = 4.8e-7; relative: 2·2^-23 = 2.4e-7. Measured 2.42e-7 absolute and
    /// 1.19e-7 relative (2.0x each).
    #[test]
    fn atan2_error_sweep() {
        let (abs, rel) = sweep::atan2_abs_rel::<Libm>(&sweep::atan2_samples());
        report("libm", "atan2 abs", &abs);
        report("libm", "atan2 rel", &rel);
        assert!(abs.max <= 4.8e-7, "{abs:?}");
        assert!(rel.max <= 2.4e-7, "{rel:?}");
    }

    /// Same 2-ulp bound as the whole-domain sweep (2·2^-23 relative). Measured 5.88e-8 (y > 0,
    /// x = 1) and 1.05e-7 (any signs and x): 2.3x.
    #[test]
    fn atan2_small_angle_error_sweep() {
        let (first, all) = sweep::atan2_small_angle_rel::<Libm>();
        report("libm", "atan2 rel, small y/x, y > 0, x = 1", &first);
        report("libm", "atan2 rel, small y/x, any signs", &all);
        assert!(
            first.max <= 2.4e-7 && all.max <= 2.4e-7,
            "{first:?} {all:?}"
        );
    }

    /// Bound: 0.5 ulp — IEEE 754 requires sqrt to be correctly rounded and libm's `sqrtf` is.
    /// Measured 0.5000 ulp in both ranges: an exact property, so no margin.
    #[test]
    fn sqrt_error_sweep() {
        let (normal, sub) = sweep::sqrt_ulp::<Libm>(&sweep::sqrt_samples());
        report("libm", "sqrt ulp, normal x", &normal);
        report("libm", "sqrt ulp, subnormal x", &sub);
        assert!(normal.max <= 0.5 && sub.max <= 0.5, "{normal:?} {sub:?}");
    }
}
