//! Range reduction by π/2 for the trigonometric kernels, in f32 and integer arithmetic only.
//!
//! Every finite `x` is written as `x = k·π/2 + r` with `k` an integer and `|r| ≲ π/4`; the result
//! is the reduced argument `r` (radians) and the quadrant `k mod 4`.
//!
//! - `|x| < 2^16` (the only range the controller ever uses): three-part Cody-Waite reduction. π/2
//!   is split into `C1 + C2 + C3`, where `C1` and `C2` have 8 significant bits each, so `k·C1` and
//!   `k·C2` are exact for `|k| < 2^16` and the first subtraction is exact (Sterbenz). The error of
//!   `r` is at most about 1 ulp of `r`, plus half an ulp of `k·C3` (≤ 9e-10), plus `|k|·5.4e-15`
//!   (the representation error of the split).
//! - `2^16 ≤ |x| < ∞`: Payne-Hanek reduction in integer arithmetic: the 24-bit significand of `x`
//!   is multiplied by a 96-bit window of the bits of 2/π (`u64` products), which gives
//!   `x·2/π mod 4` with 62 fraction bits (86 when the fraction is tiny). Rare and slower (it calls
//!   the integer routine `__aeabi_l2f` once), but just as accurate.

/// 2/π rounded to f32.
const FRAC_2_PI: f32 = 0.636_619_75;
/// 1.5·2^23: adding it to a float of magnitude < 2^22 rounds that float to an integer, which then
/// sits in the low significand bits of the sum.
const SHIFTER: f32 = 12_582_912.0;
/// π/2 = C1 + C2 + C3 (+5.4e-15). `C1 = 201/128` and `C2 = 254·2^-19` have 8 significant bits.
const C1: f32 = 1.570_312_5;
const C2: f32 = 4.844_665_5e-4;
const C3: f32 = -6.397_578_4e-7;
/// Bit pattern of 2^16: below it the Cody-Waite path is exact (`|k| ≤ 41 722 < 2^16`).
const CODY_WAITE_LIMIT_BITS: u32 = 0x4780_0000;
/// Bit pattern of π/4 rounded to f32 (0.785 398 2, just above π/4): for every smaller |x|,
/// x·2/π rounds to at most 1/2, and so k to 0 (a tie rounds to even).
const QUARTER_PI_BITS: u32 = 0x3f49_0fdb;
/// Bit pattern of +∞ (also the smallest absolute bit pattern of a NaN).
const INF_BITS: u32 = 0x7f80_0000;

/// Reduces `x` (radians) by π/2.
///
/// Returns `Some((r, q))` with `x ≈ k·π/2 + r`, `q = k mod 4` and `|r| ≤ π/4 + 0.002` (the slack
/// comes from rounding `x·2/π` in f32 before rounding to an integer; the polynomials are accurate
/// there too). Returns `None` for ±∞ and NaN.
#[inline(always)]
pub(super) fn reduce_pio2(x: f32) -> Option<(f32, u32)> {
    let ix = x.to_bits() & 0x7fff_ffff;
    if ix < QUARTER_PI_BITS {
        // k = 0: the Cody-Waite path below gives exactly (x + 0, 0) here (x·2/π rounds to 0; its
        // last term, 0·C3, is -0 since C3 < 0, which turns -0 into +0), at a third of the
        // instructions.
        Some((x + 0.0, 0))
    } else if ix < CODY_WAITE_LIMIT_BITS {
        Some(cody_waite(x))
    } else if ix < INF_BITS {
        Some(reduce_large(x))
    } else {
        None
    }
}

/// Three-part Cody-Waite reduction, for |x| < 2^16 (see the module doc).
#[inline(always)]
fn cody_waite(x: f32) -> (f32, u32) {
    let kf = x * FRAC_2_PI + SHIFTER;
    let q = kf.to_bits() & 3;
    let k = kf - SHIFTER;
    (((x - k * C1) - k * C2) - k * C3, q)
}

/// The bits of 2/π after the binary point, preceded by `PAD` zero bits, as big-endian 32-bit words:
/// bit `b_i` of 2/π (weight 2^-i) sits at bit position `i + PAD - 1` counted from the most
/// significant bit of word 0.
const TWO_OVER_PI_BITS: [u32; 9] = [
    0x0051_7CC1,
    0xB727_220A,
    0x94FE_13AB,
    0xE8FA_9A6E,
    0xE06D_B14A,
    0xCC9E_21C8,
    0x20FF_28B1,
    0xD5EF_5DE2,
    0xB0DB_9237,
];
/// Leading zero bits in [`TWO_OVER_PI_BITS`]; enough for the smallest `x` that takes the large
/// path.
const PAD: u32 = 9;
/// π/2·2^-62: converts a fraction of a quarter turn in units of 2^-62 to radians.
const PIO2_2M62: f32 = 3.406_121_7e-19;
/// π/2·2^-86: the same for the extended fraction (units of 2^-86).
const PIO2_2M86: f32 = 2.030_206_7e-26;

/// 32 bits of [`TWO_OVER_PI_BITS`] starting at bit position `p` (0 beyond the table).
#[inline(always)]
fn window32(p: u32) -> u32 {
    let w = (p / 32) as usize;
    let hi = u64::from(TWO_OVER_PI_BITS.get(w).copied().unwrap_or(0));
    let lo = u64::from(TWO_OVER_PI_BITS.get(w + 1).copied().unwrap_or(0));
    // `p % 32 < 32`, so the shift cannot overflow; the bits shifted out are meant to go.
    ((((hi << 32) | lo) << (p % 32)) >> 32) as u32
}

/// Payne-Hanek reduction for finite `|x| ≥ 2^16` (see the module docs).
#[cold]
#[inline(never)]
fn reduce_large(x: f32) -> (f32, u32) {
    let bits = x.to_bits();
    let biased_exp = (bits >> 23) & 0xff;
    // |x| = m·2^e with e = biased_exp - 150, m a 24-bit integer.
    let m = u64::from((bits & 0x007f_ffff) | 0x0080_0000);
    // Bits b_i of 2/π with i ≤ e - 2 only add multiples of 4 to m·2^e·(2/π); the 96-bit window
    // starts at i = e - 1, i.e. at bit position e - 1 + PAD - 1 = biased_exp - 143 (≥ 0 since
    // biased_exp ≥ 143).
    let p0 = biased_exp.saturating_sub(150 + 2 - PAD);
    let w0 = u64::from(window32(p0));
    let w1 = u64::from(window32(p0 + 32));
    let w2 = u64::from(window32(p0 + 64));
    // m·W mod 2^96 = y mod 4 in fixed point with 94 fraction bits (y = |x|·2/π), in 32-bit words
    // r0 (most significant), r1, r2.
    let p2 = m * w2;
    let t1 = m * w1 + (p2 >> 32);
    let r0 = (m * w0 + (t1 >> 32)) & 0xffff_ffff;
    let r1 = t1 & 0xffff_ffff;
    let r2 = p2 & 0xffff_ffff;
    // Top 64 bits: 2 integer bits (y mod 4) and 62 fraction bits. Round y to the nearest integer k.
    let hi = ((r0 << 32) | r1).wrapping_add(1 << 61);
    let mut q = (hi >> 62) as u32;
    // y - k in units of 2^-62, in [-2^61, 2^61).
    let f = (hi & ((1 << 62) - 1)) as i64 - (1 << 61);
    let mut r = if f.unsigned_abs() >= 1 << 38 {
        f as f32 * PIO2_2M62
    } else {
        // Tiny fraction: append the next 24 bits so r keeps full f32 precision.
        ((f << 24) + (r2 >> 8) as i64) as f32 * PIO2_2M86
    };
    if bits >> 31 != 0 {
        r = -r;
        q = q.wrapping_neg();
    }
    (r, q & 3)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use core::f64::consts::FRAC_PI_2;

    /// Exact `x mod π/2` is not available in f64 for huge `x`, but `sin` and `cos` are (the host
    /// libm reduces exactly), so the reduction is checked through them: sin(x) must equal ±sin(r)
    /// or ±cos(r) as selected by `q`. With `r` exact to about 1 ulp (≤ 6e-8 for |r| ≤ π/4), the
    /// reconstructed value may differ from sin(x) by at most |Δr| ≤ 1e-7 (an ulp argument, not a
    /// margin: measured 5.67e-8 over the inputs of `reduction_matches_host_sin_over_all_exponents`).
    /// The k = 0 shortcut is the Cody-Waite path bit for bit: every 97th bit pattern below the
    /// limit and the 100 000 just below it, both signs (the shortcut's one threshold, just below;
    /// the first pattern at it takes the Cody-Waite path, k = 0 there too, and then k = 1).
    #[test]
    fn small_angles_reduce_exactly_as_cody_waite_does() {
        let below = (0..QUARTER_PI_BITS)
            .step_by(97)
            .chain(QUARTER_PI_BITS - 100_000..QUARTER_PI_BITS);
        for bits in below {
            for x in [f32::from_bits(bits), -f32::from_bits(bits)] {
                let (r, q) = reduce_pio2(x).unwrap();
                let (rc, qc) = cody_waite(x);
                assert_eq!((r.to_bits(), q), (rc.to_bits(), qc), "x = {x:e}");
            }
        }
        assert_eq!(cody_waite(f32::from_bits(QUARTER_PI_BITS)).1, 0);
        let just_over = f32::from_bits(QUARTER_PI_BITS) * 1.001;
        assert_eq!(reduce_pio2(just_over).unwrap().1, 1);
    }

    fn check(x: f32) {
        let Some((r, q)) = reduce_pio2(x) else {
            panic!("finite {x} rejected")
        };
        assert!(q < 4);
        assert!(
            f64::from(r.abs()) <= core::f64::consts::FRAC_PI_4 + 0.002,
            "x={x} r={r}"
        );
        let (s, c) = (f64::from(r).sin(), f64::from(r).cos());
        let rebuilt = match q {
            0 => s,
            1 => c,
            2 => -s,
            _ => -c,
        };
        let want = f64::from(x).sin();
        assert!(
            (rebuilt - want).abs() <= 1e-7,
            "x={x:e} q={q} r={r:e} rebuilt={rebuilt} want={want}"
        );
    }

    #[test]
    fn reduction_matches_host_sin_over_all_exponents() {
        // Every 1021st bit pattern of the positive and negative finite floats, both paths.
        let mut bits = 0u32;
        while bits < INF_BITS {
            check(f32::from_bits(bits));
            check(-f32::from_bits(bits));
            bits += 1021 * 37;
        }
        for x in [
            65_535.996f32,
            65_536.0,
            65_536.01,
            f32::MAX,
            1e10,
            1e20,
            1e30,
        ] {
            check(x);
            check(-x);
        }
    }

    #[test]
    fn large_path_agrees_with_cody_waite_where_both_apply() {
        // The large path is written for |x| ≥ 2^16, the Cody-Waite path is exact up to about 1e5.
        // Where both apply they must describe the same angle: q·π/2 + r equal modulo 2π (they may
        // pick neighbouring k when x·2/π is within rounding of a half-integer). Tolerance: the sum
        // of both reduction errors, each ≤ ulp(π/4) = 6e-8 plus 1.7e-10 (k·5.4e-15 and ulp(k·C3)).
        // Measured 5.96e-8 (one ulp of π/4: one path rounds r differently), 2.0x below.
        let mut x = 65_536.0f32;
        while x < 100_000.0 {
            let (r1, q1) = reduce_large(x);
            let kf = x * FRAC_2_PI + SHIFTER;
            let k = kf - SHIFTER;
            let r2 = ((x - k * C1) - k * C2) - k * C3;
            let q2 = kf.to_bits() & 3;
            let dq = f64::from(q1.wrapping_sub(q2) & 3);
            let d = (f64::from(r1) - f64::from(r2) + dq * FRAC_PI_2).rem_euclid(4.0 * FRAC_PI_2);
            let d = d.min(4.0 * FRAC_PI_2 - d);
            assert!(d <= 1.2e-7, "x={x} ({r1}, {q1}) vs ({r2}, {q2})");
            x += 0.37;
        }
    }

    #[test]
    fn non_finite_is_rejected() {
        assert!(reduce_pio2(f32::NAN).is_none());
        assert!(reduce_pio2(f32::INFINITY).is_none());
        assert!(reduce_pio2(f32::NEG_INFINITY).is_none());
        assert!(reduce_pio2(-f32::NAN).is_none());
    }

    #[test]
    fn near_multiples_of_pio2_the_error_of_r_is_tiny() {
        // Near k·π/2 (k ≠ 0) the reduced argument is tiny. Its absolute error is then bounded by
        // ulp(r) (final rounding) + ulp(k·C3) (rounding of that product, ≤ 9e-10 for |k| < 2^16)
        // + |k|·5.4e-15 (representation error of C1 + C2 + C3): absolute accuracy far beyond what
        // sin/cos need, but not full relative precision of r when |k·C3| ≫ |r|. The exact residual
        // is computed in f64 (error ≤ 1e-12 for these k), which is included in the tolerance.
        // Measured: the error reaches at most 0.55 of this per-input bound (1.8x below it; largest
        // absolute error 2.99e-9).
        for k in (1..41_000i32).step_by(7) {
            let target = f64::from(k) * FRAC_PI_2;
            let x0 = target as f32;
            for d in -8i32..=8 {
                let x = f32::from_bits(x0.to_bits().wrapping_add_signed(d));
                let Some((r, q)) = reduce_pio2(x) else {
                    panic!("finite {x} rejected")
                };
                let exact = f64::from(x) - target;
                assert_eq!(q, (k & 3) as u32, "x={x}");
                let kc3 = f64::from(k) * f64::from(C3);
                let tol = ulp(f64::from(r)) + ulp(kc3) + f64::from(k) * 5.4e-15 + 1e-12;
                assert!(
                    (f64::from(r) - exact).abs() <= tol,
                    "x={x} r={r:e} exact={exact:e}"
                );
            }
        }
    }

    fn ulp(v: f64) -> f64 {
        crate::math::sweep::ulp_of(v)
    }
}
