//! Math backends: the scalar functions every other module calls.
//!
//! All core math is generic over a zero-sized backend type `M: Math`, so the choice is made at compile
//! time with static dispatch and costs nothing at run time, and all backends can be compared in one
//! build (the benchmarks and charts do exactly that).
//!
//! | backend | type | notes |
//! | --- | --- | --- |
//! | libm | [`Libm`] | reference f32 accuracy; `sinf` is slow on a Cortex-M4F (partly f64 inside) |
//! | micromath | [`Micromath`] | small and fast, ~0.002 rad errors on trig, ~5 % on sqrt |
//! | ours | [`Fast`] | f32-only polynomial kernels written for the Cortex-M4F single-precision FPU |
//!
//! Angles are radians. Each implementation documents its measured maximum error.

mod fast;
mod libm_backend;
mod micromath_backend;

pub use fast::Fast;
pub use libm_backend::Libm;
pub use micromath_backend::Micromath;

/// The scalar functions the core needs. Implemented by zero-sized marker types.
///
/// Contract for every implementation: finite input gives finite output (no NaN for finite input);
/// `sqrt` of a negative number returns 0; `atan2(0, 0)` returns 0.
pub trait Math: Copy + Default + 'static {
    /// Short name used in benchmark tables and charts.
    const NAME: &'static str;
    /// sin(x), x in radians.
    fn sin(x: f32) -> f32;
    /// cos(x), x in radians.
    fn cos(x: f32) -> f32;
    /// (sin x, cos x); backends may share the range reduction.
    #[inline]
    fn sin_cos(x: f32) -> (f32, f32) {
        (Self::sin(x), Self::cos(x))
    }
    /// Four-quadrant arctangent of y/x in (-π, π]; `atan2(0, 0) = 0`.
    fn atan2(y: f32, x: f32) -> f32;
    /// Square root; returns 0 for negative input.
    fn sqrt(x: f32) -> f32;
}
