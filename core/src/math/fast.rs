//! Our own f32 kernels for the Cortex-M4F: single-precision multiply/add polynomials, integer bit
//! manipulation and comparisons only — no f64 (which the M4F's FPU lacks and emulates in software)
//! and no call into libm.
//!
//! - [`reduce`]: range reduction by π/2 (Cody-Waite below 2^16, integer Payne-Hanek above).
//! - [`trig`]: sin, cos and sin_cos sharing one reduction.
//! - [`atan`]: atan2 with octant reduction.
//! - [`sqrt`]: Newton iterations from a bit-pattern estimate (see that module for why not `VSQRT`).
//!
//! The maximum errors quoted on each function are measured by the sweeps in this module's tests
//! against the host's f64 functions (see [`super::sweep`] for the exact inputs).

mod atan;
#[cfg(test)]
mod exhaustive;
mod reduce;
mod sqrt;
mod trig;

use super::Math;

/// Our f32-only kernels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Fast;

impl Math for Fast {
    const NAME: &'static str = "fast";

    /// sin(x). Max abs error 6.4e-8 over |x| ≤ 1e4 (test `sin_error_sweep`; 6.5e-8 over every
    /// float with |x| ≤ 1e4, ignored test `exhaustive_sin_cos_up_to_1e4`), 8.9e-8 over all finite
    /// f32 (test `trig_error_sweep_whole_domain`: large |x| are reduced exactly by Payne-Hanek, so
    /// accuracy does not degrade). Output always in [-1, 1]; 0 for ±∞ and NaN.
    #[inline]
    fn sin(x: f32) -> f32 {
        trig::sin(x)
    }

    /// cos(x). Max abs error 6.3e-8 over |x| ≤ 1e4 (test `cos_error_sweep`; 6.5e-8 over every
    /// float with |x| ≤ 1e4, ignored test `exhaustive_sin_cos_up_to_1e4`), 8.9e-8 over all
    /// finite f32 (test `trig_error_sweep_whole_domain`). Output always in [-1, 1]; 0 for ±∞ and
    /// NaN.
    #[inline]
    fn cos(x: f32) -> f32 {
        trig::cos(x)
    }

    /// (sin x, cos x) with one shared range reduction; bit-identical to (`sin`, `cos`), so the same
    /// errors: max abs 6.4e-8 over |x| ≤ 1e4 (test `sin_cos_error_sweep`). (0, 0) for ±∞ and NaN.
    #[inline]
    fn sin_cos(x: f32) -> (f32, f32) {
        trig::sin_cos(x)
    }

    /// atan2(y, x). Max abs error 1.8e-7 rad and max relative error 1.5e-7 (where the exact result
    /// is a normal f32) over all finite inputs (test `atan2_error_sweep`; for atan2(y, ±1) over
    /// every finite y: 1.8e-7 abs, 1.6e-7 relative, ignored test `exhaustive_atan2_unit_x`); for
    /// small angles (1e-30 ≤ |y/x| ≤ 0.1) max relative error 1.1e-7 (test
    /// `atan2_small_angle_error_sweep`). Zeros, infinities and NaN as in the [`Math::atan2`]
    /// contract (IEEE limits for infinities).
    #[inline]
    fn atan2(y: f32, x: f32) -> f32 {
        atan::atan2(y, x)
    }

    /// √x. Max error 0.5005 ulp for normal and 0.5002 ulp for subnormal x (test `sqrt_error_sweep`;
    /// 0.5005 ulp over every positive float, ignored test `exhaustive_sqrt`):
    /// correctly rounded except within 0.0005 ulp of a rounding midpoint. 0 for x ≤ 0 and NaN,
    /// `f32::MAX` for +∞.
    #[inline]
    fn sqrt(x: f32) -> f32 {
        sqrt::sqrt(x)
    }
}

#[cfg(test)]
mod tests {
    use super::super::sweep::{self, report, TRIG_RANGE};
    use super::*;

    /// Target from the design brief: 2e-7 absolute over |x| ≤ 1e4 (≈ 3.4 ulp at 1.0). The expected
    /// figure is ~1 ulp(0.5..1) = 6e-8 from the polynomial plus ~1 ulp(r)·|derivative| from the
    /// reduction. Measured by these sweeps: sin 6.34e-8, cos 6.27e-8, sin_cos 6.34e-8 (bound 3.2x);
    /// 8.86e-8 over every finite x (2.3x).
    const TRIG_BOUND: f64 = 2e-7;

    #[test]
    fn sin_error_sweep() {
        let e = sweep::sin_abs::<Fast>(&sweep::trig_samples(TRIG_RANGE));
        report("fast", "sin abs |x|<=1e4", &e);
        assert!(e.max <= TRIG_BOUND, "{e:?}");
    }

    #[test]
    fn cos_error_sweep() {
        let e = sweep::cos_abs::<Fast>(&sweep::trig_samples(TRIG_RANGE));
        report("fast", "cos abs |x|<=1e4", &e);
        assert!(e.max <= TRIG_BOUND, "{e:?}");
    }

    #[test]
    fn sin_cos_error_sweep() {
        let e = sweep::sin_cos_abs::<Fast>(&sweep::trig_samples(TRIG_RANGE));
        report("fast", "sin_cos abs |x|<=1e4", &e);
        assert!(e.max <= TRIG_BOUND, "{e:?}");
    }

    /// Same bound beyond 1e4: the Payne-Hanek path reduces exactly, so nothing degrades.
    #[test]
    fn trig_error_sweep_whole_domain() {
        let xs = sweep::trig_samples_whole_domain();
        let e = sweep::sin_cos_abs::<Fast>(&xs);
        report("fast", "sin_cos abs, all finite x", &e);
        assert!(e.max <= TRIG_BOUND, "{e:?}");
    }

    /// Targets from the design brief: 1e-6 rad absolute and 1e-6 relative. Expected: ~2 ulp of the
    /// result (division, polynomial, final addition). Measured 1.77e-7 rad absolute and 1.51e-7
    /// relative over these 1.8 million pairs; bounds 3x: 5.3e-7 and 4.5e-7.
    #[test]
    fn atan2_error_sweep() {
        let (abs, rel) = sweep::atan2_abs_rel::<Fast>(&sweep::atan2_samples());
        report("fast", "atan2 abs", &abs);
        report("fast", "atan2 rel", &rel);
        assert!(abs.max <= 5.3e-7, "{abs:?}");
        assert!(rel.max <= 4.5e-7, "{rel:?}");
    }

    /// Target from the design brief: 1e-6 relative for small angles (for y/x ≥ 1e-30 the result
    /// is `atan(t)` evaluated directly, ~1 ulp). Measured 5.88e-8 (y > 0, x = 1) and 1.05e-7 (any
    /// signs and x); bounds 3x: 1.8e-7 and 3.2e-7.
    #[test]
    fn atan2_small_angle_error_sweep() {
        let (first, all) = sweep::atan2_small_angle_rel::<Fast>();
        report("fast", "atan2 rel, small y/x, y > 0, x = 1", &first);
        report("fast", "atan2 rel, small y/x, any signs", &all);
        assert!(
            first.max <= 1.8e-7 && all.max <= 3.2e-7,
            "{first:?} {all:?}"
        );
    }

    /// Target from the design brief: ≤ 2 ulp. Expected: 0.5 ulp (final rounding) plus the
    /// second-order term of the last Newton step, (4.6e-6)²/2 relative ≈ 2e-4 ulp, since the
    /// residual is exact. Measured 0.5005 ulp (normal x) and 0.5002 ulp (subnormal x). No f32
    /// result is closer than 0.5 ulp in general, so the bound is on the excess over a correctly
    /// rounded result: measured 5e-4 ulp, asserted 1e-3 ulp (2x), i.e. 0.501 ulp, in both ranges.
    #[test]
    fn sqrt_error_sweep() {
        let (normal, sub) = sweep::sqrt_ulp::<Fast>(&sweep::sqrt_samples());
        report("fast", "sqrt ulp, normal x", &normal);
        report("fast", "sqrt ulp, subnormal x", &sub);
        assert!(normal.max <= 0.501, "{normal:?}");
        assert!(sub.max <= 0.501, "{sub:?}");
    }
}
