//! Square root in f32 without the FPU's `VSQRT`, which is not reachable from stable, safe
//! `no_std` Rust 1.95 on `thumbv7em-none-eabihf`: `f32::sqrt` is std-only, `core::f32::math::sqrt`
//! is unstable (`core_float_math`; on nightly it compiles to a single `vsqrt.f32`),
//! `core::intrinsics::sqrtf32` is unstable, `libm::sqrtf` has no ARM arch path and runs an integer
//! fixed-point routine (table + Goldschmidt iterations), and inline assembly needs `unsafe`.
//!
//! Method: bit-pattern estimate of 1/√x (magic constant 0x5f375a86, ≤ 3.5 % error), two Newton
//! steps for 1/√x (error ≤ 5e-6), `s = x·y`, and one Newton step for √x whose residual `x - s²` is
//! computed exactly with a Dekker split of `s`, so the result is correctly rounded except within a
//! tiny distance of a rounding midpoint.

/// 2^-100 and 2^124: inside [2^-100, 2^124) no intermediate overflows, and the residual
/// `x - s²` (≈ x·2^-24) stays a normal float with full precision.
const FAST_MIN: f32 = 7.888_609e-31;
const FAST_MAX: f32 = 2.126_764_8e37;
/// 2^50 and 2^-25: exact scalings for the tiny range (sqrt(x·2^50) = sqrt(x)·2^25); they map the
/// smallest subnormal 2^-149 to 2^-99, inside the fast range.
const TWO_P50: f32 = 1.125_899_9e15;
const TWO_M25: f32 = 2.980_232_2e-8;
/// 2^-24 and 2^12: exact scalings for the huge range.
const TWO_M24: f32 = 5.960_464_5e-8;
const TWO_P12: f32 = 4096.0;

/// √x for x in [2^-100, 2^124).
#[inline(always)]
fn sqrt_normal(x: f32) -> f32 {
    let mut y = f32::from_bits(0x5f37_5a86_u32.wrapping_sub(x.to_bits() >> 1));
    let hx = 0.5 * x;
    y = y * (1.5 - (hx * y) * y);
    y = y * (1.5 - (hx * y) * y);
    let s = x * y;
    // s = s_hi + s_lo with s_hi holding the top 12 significand bits: every product below is exact.
    let s_hi = f32::from_bits(s.to_bits() & 0xffff_f000);
    let s_lo = s - s_hi;
    let residual = ((x - s_hi * s_hi) - 2.0 * s_hi * s_lo) - s_lo * s_lo;
    s + (0.5 * y) * residual
}

/// √x; 0 for x ≤ 0 and NaN, `f32::MAX` for +∞.
#[inline]
pub(super) fn sqrt(x: f32) -> f32 {
    if (FAST_MIN..FAST_MAX).contains(&x) {
        sqrt_normal(x)
    } else {
        sqrt_edge(x)
    }
}

/// Everything outside [2^-100, 2^124): scaled by an even power of two into range, or a defined
/// value.
#[cold]
#[inline(never)]
fn sqrt_edge(x: f32) -> f32 {
    if x > 0.0 && x < FAST_MIN {
        sqrt_normal(x * TWO_P50) * TWO_M25
    } else if (FAST_MAX..f32::INFINITY).contains(&x) {
        sqrt_normal(x * TWO_M24) * TWO_P12
    } else if x == f32::INFINITY {
        f32::MAX
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaling_constants_are_the_powers_of_two_they_claim() {
        assert_eq!(FAST_MIN, f32::from_bits((127 - 100) << 23));
        assert_eq!(FAST_MAX, f32::from_bits((127 + 124) << 23));
        assert_eq!(TWO_P50, f32::from_bits((127 + 50) << 23));
        assert_eq!(TWO_M25, f32::from_bits((127 - 25) << 23));
        assert_eq!(TWO_M24, f32::from_bits((127 - 24) << 23));
        assert_eq!(TWO_P12, f32::from_bits((127 + 12) << 23));
    }

    #[test]
    fn perfect_squares_are_exact() {
        // Correct rounding implies exact results for squares of 12-bit integers and their binary
        // scalings, including subnormal and huge ones.
        for n in 1u32..4096 {
            let r = n as f32;
            // 1, 2^-70 (squares near the subnormal boundary), 2^-74 (subnormal squares), 2^51
            // (squares up to 2^126, the huge range).
            for scale_exp in [0i32, -70, -74, 51] {
                let scale = f32::from_bits(((127 + scale_exp) as u32) << 23);
                let s = r * scale;
                assert_eq!(sqrt(s * s), s, "n={n} scale={scale:e}");
            }
        }
    }
}
