//! Exhaustive checks of [`Fast`] over every float of a range: too slow for the default test run
//! (6.5 CPU-minutes in release for the three), so ignored. Run with
//! `cargo test --release -p softfinger-core exhaustive -- --ignored --nocapture`.
//!
//! Last measured: sin_cos 6.46e-8 abs over every |x| ≤ 1e4; sqrt 0.5005 ulp over every positive
//! float; atan2(y, ±1) 1.79e-7 abs and 1.58e-7 relative over every finite y.

use super::super::sweep::{report, ulp_of, MaxErr};
use super::super::Math;
use super::Fast;

/// Every float x with |x| ≤ 1e4 (2.35e9 values): sin and cos within the 2e-7 target (3.1x the
/// measured 6.46e-8).
#[test]
#[ignore = "exhaustive: minutes in release"]
fn exhaustive_sin_cos_up_to_1e4() {
    let mut e = MaxErr::default();
    let end = 1.0e4f32.to_bits();
    for bits in 0..=end {
        for x in [f32::from_bits(bits), -f32::from_bits(bits)] {
            let (s, c) = Fast::sin_cos(x);
            let xd = f64::from(x);
            e = worse(e, (f64::from(s) - xd.sin()).abs(), x);
            e = worse(e, (f64::from(c) - xd.cos()).abs(), x);
        }
    }
    report("fast", "sin_cos abs, every |x|<=1e4", &e);
    assert!(e.max <= 2e-7, "{e:?}");
}

/// Every positive float (normal and subnormal): within 0.501 ulp (measured 0.5005 ulp; the bound
/// is on the excess over correct rounding, 2x the measured 5e-4 ulp: see `sqrt_error_sweep`).
#[test]
#[ignore = "exhaustive: about a minute in release"]
fn exhaustive_sqrt() {
    let mut e = MaxErr::default();
    for bits in 1..0x7f80_0000u32 {
        let x = f32::from_bits(bits);
        let want = f64::from(x).sqrt();
        e = worse(e, (f64::from(Fast::sqrt(x)) - want).abs() / ulp_of(want), x);
    }
    report("fast", "sqrt ulp, every positive x", &e);
    assert!(e.max <= 0.501, "{e:?}");
}

/// atan2(y, ±1) for every finite y of both signs: crosses all three octant formulas. Measured
/// 1.79e-7 rad absolute and 1.58e-7 relative; bounds 3x: 5.4e-7 and 4.8e-7.
#[test]
#[ignore = "exhaustive: minutes in release"]
fn exhaustive_atan2_unit_x() {
    let (mut abs, mut rel) = (MaxErr::default(), MaxErr::default());
    for bits in 0..0x7f80_0000u32 {
        for y in [f32::from_bits(bits), -f32::from_bits(bits)] {
            for x in [1.0f32, -1.0] {
                let want = f64::from(y).atan2(f64::from(x));
                let err = (f64::from(Fast::atan2(y, x)) - want).abs();
                abs = worse(abs, err, y);
                if want.abs() >= f64::from(f32::MIN_POSITIVE) {
                    rel = worse(rel, err / want.abs(), y);
                }
            }
        }
    }
    report("fast", "atan2(y, ±1) abs, every y", &abs);
    report("fast", "atan2(y, ±1) rel, every y", &rel);
    assert!(abs.max <= 5.4e-7 && rel.max <= 4.8e-7, "{abs:?} {rel:?}");
}

fn worse(e: MaxErr, err: f64, x: f32) -> MaxErr {
    if err > e.max || err.is_nan() {
        MaxErr {
            max: if err.is_nan() { f64::INFINITY } else { err },
            at_x: x,
            at_x2: 0.0,
        }
    } else {
        e
    }
}
