//! Exactly reversible accumulation: a running sum of f32 increments kept in fixed point.
//!
//! A contact point or a spin angle is a sum of tiny increments, one per tick. Summed in f32 (even
//! with Kahan compensation), `(s + d) − d` is not `s`: a fingertip dithering between two encoder
//! counts walks its contact point away one rounding at a time. Here the sum is an `i64` in units of
//! 2⁻⁴⁴ (5.7e-14 m for lengths, range ±5.2e5 m; the spin spring scales its angles by 2⁻⁸ first,
//! see [`crate::contact::spin`]). Each increment is
//! truncated once to that unit, by a rounding that is odd (`trunc(−x) = −trunc(x)`), and integer
//! addition is exact and associative, so:
//!
//! - a zero increment leaves the sum bit for bit unchanged;
//! - an increment followed by its exact negative returns the sum bit for bit;
//! - any sequence of increments followed by their negatives in any order returns it too.
//!
//! The price is one truncation of less than one unit (5.7e-14) per increment, independent of the
//! size of the sum, where f32 rounds to half an ulp of the sum (4.7e-10 m at 1 cm).
//!
//! Conversion to f32 (for output) is correctly rounded up to one ulp: the high and low 32-bit
//! halves are converted separately (two single-instruction conversions on the Cortex-M4F) and added.

/// 2⁴⁴: fixed-point units per unit of the quantity (m or rad).
const SCALE: f32 = 17_592_186_044_416.0;
/// 2⁻⁴⁴.
const INV_SCALE: f32 = 1.0 / SCALE;
/// 2⁻¹² = 2³²·2⁻⁴⁴: the weight of the high half.
const HIGH_WEIGHT: f32 = 1.0 / 4096.0;
/// The largest f32 below 2³¹: up to this |x·2⁴⁴| (|x| < 1.2e-4) an increment converts through i32
/// (one instruction on the M4F); the conversion tells the larger ones apart by its saturation.
#[cfg(test)]
const I32_FAST: f32 = 2_147_483_520.0;

/// 2⁶³: beyond it `from_f32` saturates (through the general conversion).
const TWO_63: f32 = 9_223_372_036_854_775_808.0;
/// 2³².
const TWO_32: f32 = 4_294_967_296.0;

/// A whole `a` in [2³¹ − 128, 2⁶³) as i64, exactly (equal to `a as i64`): hi = ⌊a/2³²⌋ < 2³¹ has at
/// most 24 significant bits (so `hi as f32` is exact), and lo = a − hi·2³² in [0, 2³²) is a
/// multiple of ulp(a) ≥ 2⁸ (or a itself when hi = 0), so it has at most 24 significant bits too
/// and the f32 subtraction is exact. Two VCVT.U32 on the M4F where `as i64` calls __aeabi_f2lz.
#[inline]
fn split_whole(a: f32) -> i64 {
    let hi = (a * (1.0 / TWO_32)) as u32;
    let lo = (a - hi as f32 * TWO_32) as u32;
    (((hi as u64) << 32) | lo as u64) as i64
}

/// A quantity (m or rad) held as an integer number of 2⁻⁴⁴ units.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Fixed(pub i64);

impl Fixed {
    /// Zero.
    pub const ZERO: Fixed = Fixed(0);

    /// `x` truncated to a whole number of units (towards zero). Odd: `from_f32(−x) == −from_f32(x)`
    /// bit for bit. NaN gives zero; beyond ±5.2e5 saturates. (Truncation rather than rounding to
    /// nearest saves instructions on the M4F; its bias, below one unit = 5.7e-14 per increment, is
    /// 5.7e-8 after 10⁶ increments.)
    #[inline]
    pub fn from_f32(x: f32) -> Fixed {
        let s = x * SCALE; // exact: a power of two
                           // `as` truncates towards zero (odd) and saturates; NaN becomes 0. Only |s| ≥ 2³¹ saturates
                           // (to i32::MIN or i32::MAX), which one unsigned comparison of i + 2³¹ + 1 tells apart
                           // (they become 1 and 0), with no float comparison.
        let i = s as i32;
        if (i as u32).wrapping_add(0x8000_0001) >= 2 {
            Fixed(i as i64)
        } else {
            Fixed::from_large(s)
        }
    }

    /// [`Fixed::from_f32`], except that ±inf gives zero too (as NaN does): for increments that
    /// must not move a sum unless finite, with no separate finiteness test on the common path.
    #[inline]
    pub fn from_finite_f32(x: f32) -> Fixed {
        let s = x * SCALE;
        let i = s as i32;
        if (i as u32).wrapping_add(0x8000_0001) >= 2 {
            Fixed(i as i64)
        } else if x.abs() == f32::INFINITY {
            Fixed::ZERO
        } else {
            Fixed::from_large(s)
        }
    }

    /// `s` (units; |s| ≥ 2³¹ − 128 or NaN) truncated towards zero.
    #[inline]
    fn from_large(s: f32) -> Fixed {
        let a = s.abs();
        if a < TWO_63 {
            // |s| ≥ 2³¹ − 128 is a whole number: its two 32-bit halves convert exactly with one
            // unsigned conversion each (no 64-bit libcall), see [`split_whole`].
            let m = split_whole(a);
            Fixed(if s < 0.0 { -m } else { m })
        } else {
            Fixed(s as i64)
        }
    }

    /// The value as f32 (within one f32 ulp). Odd: `Fixed(−v).to_f32() == −Fixed(v).to_f32()`.
    ///
    /// v = hi·2³² + lo with lo the low 32 bits read as signed, so both halves convert with one
    /// signed conversion each, a small v (hi = 0) converts exactly once, and the split of −v is
    /// the negated split of v.
    #[inline]
    pub fn to_f32(self) -> f32 {
        let lo = self.0 as i32;
        let hi = (self.0.wrapping_sub(lo as i64) >> 32) as i32;
        hi as f32 * HIGH_WEIGHT + lo as f32 * INV_SCALE
    }

    /// Add an f32 increment (truncated once, see [`Fixed::from_f32`]). The sum wraps only beyond
    /// ±5.2e5, far outside any workspace.
    #[inline]
    pub fn add_f32(&mut self, d: f32) {
        self.0 = self.0.wrapping_add(Fixed::from_f32(d).0);
    }

    /// [`Fixed::add_f32`] of a finite increment; a non-finite one adds nothing (see
    /// [`Fixed::from_finite_f32`]).
    #[inline]
    pub fn add_finite_f32(&mut self, d: f32) {
        self.0 = self.0.wrapping_add(Fixed::from_finite_f32(d).0);
    }

    /// `self − other` (wrapping, see [`Fixed::add_f32`]).
    #[inline]
    pub fn minus(self, other: Fixed) -> Fixed {
        Fixed(self.0.wrapping_sub(other.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Round trip through the conversion: within half a unit plus one f32 ulp of the value
    /// (independent reference: the f64 value of the integer). Both bounds are rounding arguments,
    /// not margins: measured at most 0.59 of the first (3.4e-14 m) and exact for the second.
    #[test]
    fn conversions_round_to_the_unit_and_back_to_f32() {
        for &x in &[
            0.0f32, 1e-12, -1e-12, 3.7e-9, 6.1e-6, -6.1e-6, 0.01, -0.0234, 1.5, -100.0, 5.0e5,
        ] {
            let f = Fixed::from_f32(x);
            let as64 = f.0 as f64 / 2f64.powi(44);
            assert!(
                (as64 - x as f64).abs() <= 1.0 / 2f64.powi(44) + (x as f64).abs() * 1e-15,
                "{x}"
            );
            let back = f.to_f32();
            assert!(
                (back as f64 - as64).abs() <= (as64.abs() * f32::EPSILON as f64).max(1e-45),
                "{x}: {back} vs {as64}"
            );
            assert_eq!(Fixed::from_f32(-x).0, -f.0, "odd rounding at {x}");
            assert_eq!(Fixed(-f.0).to_f32(), -back, "odd conversion at {x}");
        }
        assert_eq!(Fixed::from_f32(f32::NAN), Fixed::ZERO);
        for x in [
            0.0f32,
            1e-12,
            -3.7e-9,
            6.1e-6,
            -0.0234,
            1.5,
            5.0e5,
            -1e30,
            f32::MAX,
        ] {
            assert_eq!(Fixed::from_finite_f32(x), Fixed::from_f32(x), "{x}");
        }
        for x in [f32::INFINITY, f32::NEG_INFINITY, f32::NAN] {
            assert_eq!(Fixed::from_finite_f32(x), Fixed::ZERO, "{x}");
        }
        assert_eq!(Fixed::from_f32(f32::INFINITY).0, i64::MAX);
        assert_eq!(Fixed::from_f32(f32::NEG_INFINITY).0, i64::MIN);
    }

    /// The two-halves conversion equals the general one (`s as i64`, i.e. __aeabi_f2lz on the M4F)
    /// bit for bit: on both sides of each boundary (2³¹ − 128, 2³¹, 2³², 2⁶³ units), on every 61st
    /// f32 bit pattern from 1 to 2⁶⁴ units (about 8.8 million values), on every power of two in
    /// that range, on their negatives, and on infinities and NaN.
    #[test]
    fn fast_conversions_equal_the_general_one() {
        let general = |x: f32| {
            let s = x * SCALE;
            s as i64
        };
        let check = |x: f32| {
            assert_eq!(Fixed::from_f32(x).0, general(x), "{x:e}");
            assert_eq!(Fixed::from_f32(-x).0, general(-x), "-{x:e}");
        };
        for &s in &[I32_FAST, 2_147_483_648.0f32, TWO_32, TWO_63, 1.0] {
            let b = s.to_bits();
            for bits in b.saturating_sub(3)..=b + 3 {
                check(f32::from_bits(bits) / SCALE);
            }
        }
        let (lo, hi) = ((1.0f32 / SCALE).to_bits(), (TWO_63 * 2.0 / SCALE).to_bits());
        let mut bits = lo;
        while bits <= hi {
            check(f32::from_bits(bits));
            bits += 61;
        }
        let mut e = lo;
        while e <= hi {
            check(f32::from_bits(e));
            e += 1 << 23;
        }
        for x in [
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MAX,
            f32::MIN_POSITIVE,
            0.0,
        ] {
            check(x);
        }
    }

    /// A million pseudo-random increments, then the same increments negated in reverse order:
    /// the sum returns bit for bit, where an f32 sum does not.
    #[test]
    fn increments_and_their_negatives_return_exactly() {
        let mut s = Fixed::from_f32(0.0123);
        let start = s;
        let mut f = 0.0123f32;
        let mut x = 0x2545_f491u32;
        let mut incs = [0.0f32; 1000];
        for _ in 0..1000 {
            for d in incs.iter_mut() {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                *d = (x as f32 / u32::MAX as f32 - 0.5) * 1.2e-5;
                s.add_f32(*d);
                f += *d;
            }
            for d in incs.iter().rev() {
                s.add_f32(-*d);
                f -= *d;
            }
        }
        assert_eq!(s, start);
        // The f32 sum drifted (this is what the fixed-point sum is for).
        assert_ne!(f, 0.0123f32);
    }
}
