//! Our own f32 kernels for the Cortex-M4F (placeholder: delegates to libm until the kernels land).

use super::Math;

/// Our f32-only kernels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Fast;

impl Math for Fast {
    const NAME: &'static str = "fast";
    #[inline]
    fn sin(x: f32) -> f32 {
        libm::sinf(x)
    }
    #[inline]
    fn cos(x: f32) -> f32 {
        libm::cosf(x)
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
