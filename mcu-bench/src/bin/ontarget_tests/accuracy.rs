//! The accuracy each math backend is held to on target, from which every closed-form tolerance of
//! the math checks is derived (worst-case propagation of these kernel errors); the same checks'
//! values are held to their golden bits as well (`golden.rs`).

use softfinger_core::{Fast, Libm, Math, Micromath};

/// A backend's kernel accuracy.
pub trait Accuracy: Math {
    /// Largest absolute error of `sin`/`cos`/`sin_cos` for |x| ≤ 2π, inputs exactly representable.
    const TRIG: f32;
    /// Largest absolute error of `atan2`, rad.
    const ATAN2: f32;
    /// Largest relative error of `sqrt`.
    const SQRT_REL: f32;
    /// The golden bits of the math checks' results (`golden.rs`).
    const GOLDEN: &'static [u32];
}

/// libm's f32 functions are within 1 ulp: ≤ 6e-8 on [-1, 1] for sin/cos, ≤ 2.4e-7 near π for atan2,
/// 0.5 ulp (6e-8 relative) for sqrt. The bounds below allow about 2-3 ulps.
impl Accuracy for Libm {
    const TRIG: f32 = 2.0e-7;
    const ATAN2: f32 = 5.0e-7;
    const SQRT_REL: f32 = 2.0e-7;
    const GOLDEN: &'static [u32] = crate::golden::LIBM;
}

/// micromath's documented errors: sin/cos 0.002 (its own tests' MAX_ERROR), atan2 0.1620° =
/// 0.00283 rad. Its sqrt is `(bits + 0x3f80_0000) >> 1` with no Newton step: a chord of √ between
/// powers of four whose worst relative error is 1.5/√2 − 1 = 0.0607 (mantissa → 2); documented as
/// "about 5 % average".
impl Accuracy for Micromath {
    const TRIG: f32 = 0.002;
    const ATAN2: f32 = 0.002_83;
    const SQRT_REL: f32 = 0.0607;
    const GOLDEN: &'static [u32] = crate::golden::MICROMATH;
}

/// Our kernels' measured maximum errors (`core/src/math/mod.rs`, sweeps of a million inputs or more
/// against f64 on the host; the kernels are f32-only and the same instructions run here): trig
/// 6.5e-8 for |x| ≤ 1e4, atan2 1.8e-7 rad, sqrt 0.5005 ulp (≤ 5.97e-8 relative). Bounds about 3x.
impl Accuracy for Fast {
    const TRIG: f32 = 2.0e-7;
    const ATAN2: f32 = 5.4e-7;
    const SQRT_REL: f32 = 1.8e-7;
    const GOLDEN: &'static [u32] = crate::golden::FAST;
}
