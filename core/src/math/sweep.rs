//! Test support: dense input sweeps and error measurement of a [`Math`] backend against the host's
//! f64 functions (glibc's `sin`, `cos`, `atan2`, `sqrt`: correctly reduced for every f64 and far
//! more accurate than any f32 result, so their error is negligible in every figure below).
//!
//! Each backend's tests call these sweeps and assert the measured maximum against a stated bound;
//! the figures quoted in the backends' doc comments come from these sweeps
//! (`cargo test -p softfinger-core math:: -- --nocapture` prints them).

extern crate std;

use super::Math;
use core::f64::consts::{FRAC_PI_2, PI};
use std::vec::Vec;

/// The range of angles the trigonometric accuracy targets refer to: |x| ≤ 1e4 rad.
pub const TRIG_RANGE: f32 = 1.0e4;

/// Bit pattern of +∞.
const INF_BITS: u32 = 0x7f80_0000;

/// The largest error seen and the input that produced it.
#[derive(Clone, Copy, Debug, Default)]
pub struct MaxErr {
    /// Largest error (absolute, relative or in ulps, as the sweep says).
    pub max: f64,
    /// First argument of the worst case.
    pub at_x: f32,
    /// Second argument of the worst case (atan2's x; 0 otherwise).
    pub at_x2: f32,
}

impl MaxErr {
    fn record(&mut self, err: f64, x: f32, x2: f32) {
        // NaN errors are recorded as infinite so they can never pass a bound.
        let err = if err.is_nan() { f64::INFINITY } else { err };
        if err > self.max {
            *self = Self {
                max: err,
                at_x: x,
                at_x2: x2,
            };
        }
    }
}

/// ulp of an f32 of magnitude |v| (2^-149 for the subnormal range).
pub fn ulp_of(v: f64) -> f64 {
    let exp = ((v.to_bits() >> 52) & 0x7ff) as i32 - 1023; // floor(log2 |v|) for normal f64
    2f64.powi(exp.max(-126) - 23)
}

/// Non-negative floats from `lo` to `hi` (inclusive ends) stepping the bit pattern by `stride`.
pub fn bit_stride(lo: f32, hi: f32, stride: u32) -> impl Iterator<Item = f32> {
    let (lo, hi) = (lo.to_bits(), hi.to_bits());
    (lo..=hi)
        .step_by(stride as usize)
        .chain(core::iter::once(hi))
        .map(f32::from_bits)
}

/// `n` points linearly spaced over [lo, hi] (computed in f64, rounded to f32).
pub fn linear(lo: f64, hi: f64, n: u32) -> impl Iterator<Item = f32> {
    (0..n).map(move |i| (lo + (hi - lo) * f64::from(i) / f64::from(n - 1)) as f32)
}

/// Deterministic xorshift32 bit patterns of finite floats (any sign and exponent).
pub fn random_finite(n: usize, seed: u32) -> impl Iterator<Item = f32> {
    let mut s = seed | 1;
    core::iter::repeat_with(move || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        s
    })
    .filter(|b| b & INF_BITS != INF_BITS)
    .take(n)
    .map(f32::from_bits)
}

/// Inputs for sin/cos over |x| ≤ `limit`: every 4093rd positive float and its negative, 250 000
/// evenly spaced points, and the 9 floats nearest each multiple of π/2 (where the reduced argument
/// is tiny and reduction errors would show). About 830 000 inputs for `limit` = 1e4.
pub fn trig_samples(limit: f32) -> Vec<f32> {
    let mut v: Vec<f32> = bit_stride(0.0, limit, 4093).flat_map(|x| [x, -x]).collect();
    v.extend(linear(-f64::from(limit), f64::from(limit), 250_000));
    let kmax = (f64::from(limit) / FRAC_PI_2) as i32;
    for k in -kmax..=kmax {
        let x0 = (f64::from(k) * FRAC_PI_2) as f32;
        for d in -4i32..=4 {
            v.push(f32::from_bits(x0.to_bits().wrapping_add_signed(d)));
        }
    }
    v.retain(|x| x.abs() <= limit);
    v
}

/// Inputs for sin/cos over every finite float: every 8191st bit pattern, both signs.
pub fn trig_samples_whole_domain() -> Vec<f32> {
    bit_stride(0.0, f32::MAX, 8191)
        .flat_map(|x| [x, -x])
        .collect()
}

/// Max absolute error of `M::sin` over `xs`.
pub fn sin_abs<M: Math>(xs: &[f32]) -> MaxErr {
    let mut e = MaxErr::default();
    for &x in xs {
        e.record((f64::from(M::sin(x)) - f64::from(x).sin()).abs(), x, 0.0);
    }
    e
}

/// Max absolute error of `M::cos` over `xs`.
pub fn cos_abs<M: Math>(xs: &[f32]) -> MaxErr {
    let mut e = MaxErr::default();
    for &x in xs {
        e.record((f64::from(M::cos(x)) - f64::from(x).cos()).abs(), x, 0.0);
    }
    e
}

/// Max absolute error of both components of `M::sin_cos` over `xs`.
pub fn sin_cos_abs<M: Math>(xs: &[f32]) -> MaxErr {
    let mut e = MaxErr::default();
    for &x in xs {
        let (s, c) = M::sin_cos(x);
        let xd = f64::from(x);
        e.record((f64::from(s) - xd.sin()).abs(), x, 0.0);
        e.record((f64::from(c) - xd.cos()).abs(), x, 0.0);
    }
    e
}

/// (y, x) pairs for atan2:
/// - 100 000 angles evenly spaced over [-π, π] on circles of radius 1, 1e-20, 1e20, 1e-41
///   (subnormal components) and 3e38;
/// - small ratios: every 8009th positive float t ≤ 1 in the eight sign/order combinations
///   (±t, ±1), (±1, ±t) — this covers angles from 1e-45 rad up and every octant boundary;
/// - 200 000 random finite bit-pattern pairs (any magnitudes, ratios that under- and overflow).
///
/// About 1.8 million pairs.
pub fn atan2_samples() -> Vec<(f32, f32)> {
    let mut v = Vec::new();
    for radius in [1.0, 1e-20, 1e20, 1e-41, 3e38] {
        for i in 0..100_000 {
            let th = -PI + 2.0 * PI * f64::from(i) / 99_999.0;
            v.push(((radius * th.sin()) as f32, (radius * th.cos()) as f32));
        }
    }
    for t in bit_stride(f32::from_bits(1), 1.0, 8009) {
        for (a, b) in [(t, 1.0), (1.0, t)] {
            for (sy, sx) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                v.push((sy * a, sx * b));
            }
        }
    }
    let ys: Vec<f32> = random_finite(200_000, 0x1234_5678).collect();
    v.extend(ys.into_iter().zip(random_finite(200_000, 0x9abc_def1)));
    v
}

/// Max absolute error (rad) and max relative error of `M::atan2` over `pairs`.
///
/// The error is the angular distance modulo 2π, so that +π and -π count as the same angle
/// (micromath returns +π-ish values for y slightly below 0 and x < 0, where the exact result is
/// near -π; for the other backends this makes no difference). The relative error is taken where the
/// exact result is a normal f32 (≥ 2^-126): below, no f32 result can carry relative precision.
pub fn atan2_abs_rel<M: Math>(pairs: &[(f32, f32)]) -> (MaxErr, MaxErr) {
    let (mut abs, mut rel) = (MaxErr::default(), MaxErr::default());
    for &(y, x) in pairs {
        let want = f64::from(y).atan2(f64::from(x));
        let d = (f64::from(M::atan2(y, x)) - want).abs();
        let err = d.min((2.0 * PI - d).abs());
        abs.record(err, y, x);
        if want.abs() >= f64::from(f32::MIN_POSITIVE) {
            rel.record(err / want.abs(), y, x);
        }
    }
    (abs, rel)
}

/// Max relative error of `M::atan2` for small angles, the case of `2·atan2(s, w)/s` in the rolling
/// code: y/x from 1e-30 to 0.1 (every 8009th float ratio t, as (t·x, x) for x in {1, 0.37, 1e-10,
/// 1e10}). Returns the maximum over y > 0, x = 1 (the rolling code's case: x is the scalar part of
/// a unit quaternion, ≈ 1) and over all four sign combinations and all x.
pub fn atan2_small_angle_rel<M: Math>() -> (MaxErr, MaxErr) {
    let (mut first, mut all) = (MaxErr::default(), MaxErr::default());
    for t in bit_stride(1e-30, 0.1, 8009) {
        for x in [1.0f32, 0.37, 1e-10, 1e10] {
            for (sy, sx) in [(1.0f32, 1.0f32), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
                let (y, x) = (sy * t * x, sx * x);
                let want = f64::from(y).atan2(f64::from(x));
                let d = (f64::from(M::atan2(y, x)) - want).abs();
                let rel = d.min((2.0 * PI - d).abs()) / want.abs();
                all.record(rel, y, x);
                if y > 0.0 && x == 1.0 {
                    first.record(rel, y, x);
                }
            }
        }
    }
    (first, all)
}

/// Inputs for sqrt (about 1.8 million): every 13th float in [1, 4) (two binades: the kernels treat x and 4x alike up to
/// exact scaling), every 4099th positive float over the whole finite range, every 97th subnormal
/// and the 64 smallest subnormals.
pub fn sqrt_samples() -> Vec<f32> {
    let mut v: Vec<f32> = bit_stride(1.0, 4.0, 13).collect();
    v.extend(bit_stride(0.0, f32::MAX, 4099));
    v.extend(bit_stride(0.0, f32::MIN_POSITIVE, 97));
    v.extend((1..=64).map(f32::from_bits));
    v
}

/// Max error of `M::sqrt` over `xs` in ulps of the exact result, for normal inputs and for
/// subnormal inputs separately.
pub fn sqrt_ulp<M: Math>(xs: &[f32]) -> (MaxErr, MaxErr) {
    let (mut normal, mut sub) = (MaxErr::default(), MaxErr::default());
    for &x in xs {
        let want = f64::from(x).sqrt();
        let err = (f64::from(M::sqrt(x)) - want).abs() / ulp_of(want);
        if x >= f32::MIN_POSITIVE {
            normal.record(err, x, 0.0);
        } else {
            sub.record(err, x, 0.0);
        }
    }
    (normal, sub)
}

/// Max relative error of `M::sqrt` over `xs`, for normal and subnormal inputs separately
/// (x = 0 is skipped: its result must be exactly 0 and is checked by the contract tests).
pub fn sqrt_rel<M: Math>(xs: &[f32]) -> (MaxErr, MaxErr) {
    let (mut normal, mut sub) = (MaxErr::default(), MaxErr::default());
    for &x in xs.iter().filter(|x| **x > 0.0) {
        let want = f64::from(x).sqrt();
        let err = (f64::from(M::sqrt(x)) - want).abs() / want;
        if x >= f32::MIN_POSITIVE {
            normal.record(err, x, 0.0);
        } else {
            sub.record(err, x, 0.0);
        }
    }
    (normal, sub)
}

/// Prints one measured figure (visible with `--nocapture`).
pub fn report(backend: &str, what: &str, e: &MaxErr) {
    std::println!(
        "{backend:>9} {what:<34} max {:.3e} at ({:e}, {:e})",
        e.max,
        e.at_x,
        e.at_x2
    );
}
