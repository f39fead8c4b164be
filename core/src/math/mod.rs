//! Math: the small vector and rotation types ([`Vec3`], [`Quat`], [`Rot3`], [`fixed::Fixed`]) and
//! the scalar backends every other module calls.
//!
//! # Backends
//!
//! All core math is generic over a zero-sized backend type `M: Math`, so the choice is made at compile
//! time with static dispatch and costs nothing at run time, and all backends can be compared in one
//! build (the benchmarks and charts do exactly that).
//!
//! | backend | type | notes |
//! | --- | --- | --- |
//! | libm | [`Libm`] | reference f32 accuracy; `sinf` is slow on a Cortex-M4F (partly f64 inside) |
//! | micromath | [`Micromath`] | small and fast, ~0.002 rad errors on trig, ~6 % on sqrt |
//! | ours | [`Fast`] | f32-only polynomial kernels written for the Cortex-M4F single-precision FPU |
//!
//! Angles are radians. Each implementation documents its measured maximum error; the figures come
//! from the sweeps in the backends' tests (`cargo test -p softfinger-core math:: -- --nocapture`
//! prints them), which compare against the host's f64 functions.
//!
//! Measured maximum errors (sweeps of about a million inputs or more per row; details and test names on each
//! function):
//!
//! | kernel | libm | micromath | fast |
//! | --- | --- | --- | --- |
//! | sin, cos, sin_cos, abs, \|x\| ≤ 1e4 | 3.0e-8 | 2.3e-3 | 6.5e-8 |
//! | sin, cos, abs, all finite x | 3.0e-8 | meaningless beyond ~1e6 | 8.9e-8 |
//! | atan2, abs (rad), all finite inputs | 2.4e-7 | 2.8e-3 | 1.8e-7 |
//! | atan2, relative, small angles (y > 0, x = 1) | 5.9e-8 | 6.3e-2 | 5.9e-8 |
//! | sqrt, normal x | 0.5 ulp | 6.1 % | 0.5005 ulp |
//! | sqrt, subnormal x | 0.5 ulp | ×2170 | 0.5002 ulp |

pub mod fixed;
pub mod quat;
pub mod rot3;
pub mod vec3;

mod fast;
mod libm_backend;
mod micromath_backend;

#[cfg(test)]
mod contract_tests;
#[cfg(test)]
mod sweep;

pub use fast::Fast;
pub use libm_backend::Libm;
pub use micromath_backend::Micromath;
pub use quat::Quat;
pub use rot3::Rot3;
pub use vec3::Vec3;

/// The scalar functions the core needs. Implemented by zero-sized marker types.
///
/// Contract for every implementation (checked for all backends by the tests in `contract_tests.rs`):
/// no output is ever NaN or infinite, whatever the input.
/// - `sin`, `cos`, `sin_cos`: output in [-1, 1]; ±∞ and NaN give 0 (callers flag non-finite inputs
///   separately).
/// - `atan2`: output in [-π, π] (π rounded to f32); NaN in either argument gives 0;
///   `atan2(±0, ±0) = 0` for all four sign combinations; infinite arguments give the IEEE 754
///   limits (`atan2(∞, -∞) = 3π/4`, `atan2(1, -∞) = π`, `atan2(-∞, 1) = -π/2`, ...);
///   `atan2(±0, x > 0) = ±0` and `atan2(±0, x < 0) = ±π` (the sign of π may differ between backends).
/// - `sqrt`: output finite and ≥ 0; 0 for x ≤ 0 (including -0 and -∞) and NaN; `f32::MAX` for +∞.
///
/// Accuracy is per backend; each function's doc comment states its measured maximum error.
pub trait Math: Copy + Default + core::fmt::Debug + 'static {
    /// Short name used in benchmark tables and charts.
    const NAME: &'static str;
    /// sin(x), x in radians; 0 for non-finite x.
    fn sin(x: f32) -> f32;
    /// cos(x), x in radians; 0 for non-finite x.
    fn cos(x: f32) -> f32;
    /// (sin x, cos x); backends may share the range reduction. (0, 0) for non-finite x.
    #[inline]
    fn sin_cos(x: f32) -> (f32, f32) {
        (Self::sin(x), Self::cos(x))
    }
    /// Four-quadrant arctangent of y/x in [-π, π]; `atan2(0, 0) = 0`.
    fn atan2(y: f32, x: f32) -> f32;
    /// Square root; returns 0 for negative input and NaN, `f32::MAX` for +∞.
    fn sqrt(x: f32) -> f32;
}
