//! The libm backend: correctly rounded-ish f32 functions from the `libm` crate.

use super::Math;

/// libm's f32 functions. Reference accuracy (errors ≤ 1 ulp); on a Cortex-M4F `sinf`/`cosf` are slow
/// (~1270 instructions, they use f64 internally).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Libm;

impl Math for Libm {
    const NAME: &'static str = "libm";
    #[inline]
    fn sin(x: f32) -> f32 {
        libm::sinf(x)
    }
    #[inline]
    fn cos(x: f32) -> f32 {
        libm::cosf(x)
    }
    #[inline]
    fn sin_cos(x: f32) -> (f32, f32) {
        libm::sincosf(x)
    }
    #[inline]
    fn atan2(y: f32, x: f32) -> f32 {
        libm::atan2f(y, x)
    }
    #[inline]
    fn sqrt(x: f32) -> f32 {
        if x > 0.0 {
            libm::sqrtf(x)
        } else {
            0.0
        }
    }
}
