//! Steps beyond the log map's series branch (> 0.39 rad per sample), where each backend's own sqrt
//! and atan2 run, on both sides of the atan2 octant split (rotation angle below and above π/2),
//! against the closed form on the plane over 26 axes. Each backend has its own bound.

use super::*;
use crate::math::Micromath;

/// Worst per-axis error (m) of either path over every axis, for steps of `step` rad.
fn worst<M: Math>(step: f64) -> f64 {
    let mut w = 0.0f64;
    for axis in axes() {
        let inc = UnitQuaternion::from_scaled_axis(axis * step);
        let mut qs = vec![UnitQuaternion::identity()];
        for _ in 0..16 {
            let q = inc * *qs.last().unwrap();
            qs.push(q);
        }
        let (ep, ef) = run::<M>(Method::Exact, &qs);
        w = ep.iter().chain(&ef).fold(w, |a, &b| a.max(b));
    }
    w
}

/// Measured (`cargo test -p softfinger-core --lib large_step -- --nocapture`), worst over the
/// steps 0.6, 1.4 and 2.6 rad: libm 2.68e-8 m, fast 2.68e-8 m (both at 2.6 rad), micromath
/// 1.80e-3 m (at 1.4 rad: its atan2, 2.8e-3 rad, and its 6 % sqrt); bounds about 3x.
#[test]
fn large_steps_follow_the_closed_form_with_each_backends_bound() {
    let mut w = [0.0f64; 3];
    for step in [0.6, 1.4, 2.6] {
        let e = [
            worst::<Libm>(step),
            worst::<Fast>(step),
            worst::<Micromath>(step),
        ];
        std::println!(
            "step {step} rad: libm {:e} m, fast {:e} m, micromath {:e} m",
            e[0],
            e[1],
            e[2]
        );
        for i in 0..3 {
            w[i] = w[i].max(e[i]);
        }
    }
    assert!(w[0] <= 8.0e-8, "libm {:e} m", w[0]);
    assert!(w[1] <= 8.0e-8, "fast {:e} m", w[1]);
    assert!(w[2] <= 5.4e-3, "micromath {:e} m", w[2]);
}
