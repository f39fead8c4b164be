//! How far from orthonormal `Rot3::from_axis_angle` is, per math backend, over non-unit axes: the
//! measurement behind the bounds of `from_axis_angle_is_a_finite_rotation_or_identity_with_a_flag`
//! (properties.rs).
//!
//! The error comes from normalising the axis (a sqrt, micromath's is off by up to 6.07 %) and from
//! sin/cos. It depends on the mantissa of |axis|² (the sqrt error), the angle and the direction, so
//! the sweep walks the mantissas of |axis|² over two binades [1, 4) (both exponent parities),
//! eight directions and 29 angles in [-1e4, 1e4], π among them (where the axis term 2aaᵀ is largest).
//!
//! Measured with the full sweep (`SWEEP_STRIDE=131 cargo test -p softfinger-core --test
//! axis_angle_sweep -- --nocapture`, 128 075 norms, 29.7 M rotations per backend): worst entry of
//! |RᵀR − I| is 0.3951 for micromath (|axis|² = 1.99999, angle π, axis along x: sqrt 6.07 % high
//! makes the unit axis 0.943 long, RᵀR = I + 4(m²−1)·aaᵀ), 1.073e-6 for libm and 1.073e-6 for fast
//! (f32 rounding of the nine products).
//! CI runs a coarser sweep (stride 4099, which measures the same worst figures: 1.073e-6 for libm
//! and fast, 0.3949 for micromath) and asserts about 3x the full sweep's: 3.2e-6 and 1.2, the
//! bounds of the property test.

use core::f32::consts::{FRAC_1_SQRT_2, FRAC_PI_3};
use softfinger_core::{Fast, Libm, Math, Micromath, Rot3, Vec3};

/// Largest |RᵀR − I| entry.
pub fn orthonormality_error(r: &Rot3) -> f32 {
    let mut worst = 0.0f32;
    for i in 0..3 {
        for j in 0..3 {
            let d: f32 = (0..3).map(|k| r.m[k][i] * r.m[k][j]).sum();
            let want = if i == j { 1.0 } else { 0.0 };
            worst = worst.max((d - want).abs());
        }
    }
    worst
}

/// Worst orthonormality error of backend `M` over the sweep, taking every `stride`-th mantissa.
fn sweep<M: Math>(stride: u32) -> f32 {
    let dirs = [
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(0.577_350_3, 0.577_350_3, 0.577_350_3),
        Vec3::new(FRAC_1_SQRT_2, -FRAC_1_SQRT_2, 0.0),
        Vec3::new(0.3, 0.4, -0.866_025_4),
        Vec3::new(-0.1, 0.994_987_4, 0.0),
    ];
    let mut angles: Vec<f32> = (0..24).map(|a| -12.0 + a as f32 * FRAC_PI_3).collect();
    angles.extend([
        core::f32::consts::PI,
        -core::f32::consts::PI,
        1e4,
        -9999.0,
        3.0e3,
    ]);
    let one = 1.0f32.to_bits();
    let mut worst = 0.0f32;
    // Mantissas of |axis|² over [1, 4): 2^24 bit patterns.
    for i in (0..1u32 << 24).step_by(stride as usize) {
        let scale = f32::from_bits(one + i).sqrt();
        for d in dirs {
            for &angle in &angles {
                let (r, _) = Rot3::from_axis_angle::<M>(d * scale, angle);
                worst = worst.max(orthonormality_error(&r));
            }
        }
    }
    worst
}

#[test]
fn from_axis_angle_orthonormality_stays_within_the_measured_worst() {
    let stride = std::env::var("SWEEP_STRIDE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4099);
    let (libm, fast, micro) = (
        sweep::<Libm>(stride),
        sweep::<Fast>(stride),
        sweep::<Micromath>(stride),
    );
    println!(
        "orthonormality error, stride {stride}: libm {libm:e}, fast {fast:e}, micromath {micro:e}"
    );
    // About 3x the full sweep's worst figures (module docs).
    assert!(libm <= 3.2e-6, "libm {libm:e}");
    assert!(fast <= 3.2e-6, "fast {fast:e}");
    assert!(micro <= 1.2, "micromath {micro:e}");
}
