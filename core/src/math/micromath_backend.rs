//! The micromath backend: fast approximations from the `micromath` crate.

use super::Math;
use micromath::F32Ext;

/// micromath's approximations. Documented errors: sin/cos/atan2 about 0.002 rad; sqrt about 5 %
/// average deviation (no Newton step). Measured figures are in this module's tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Micromath;

impl Math for Micromath {
    const NAME: &'static str = "micromath";
    #[inline]
    fn sin(x: f32) -> f32 {
        F32Ext::sin(x)
    }
    #[inline]
    fn cos(x: f32) -> f32 {
        F32Ext::cos(x)
    }
    #[inline]
    fn atan2(y: f32, x: f32) -> f32 {
        if y == 0.0 && x == 0.0 {
            0.0
        } else {
            F32Ext::atan2(y, x)
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
