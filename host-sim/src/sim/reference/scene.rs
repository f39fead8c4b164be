//! Input sequences for the rolling reference: orientation samples of the finger sphere and the
//! piecewise-constant angular velocities they imply.
//!
//! Orientations are unit quaternions (Hamilton, scalar first) mapping the fingertip frame (the
//! sphere's) to the object frame (the plane's; the frames table in `softfinger_core`). Between two samples the angular velocity is constant: the body rate over `[t_k, t_{k+1}]`
//! is `ω_b = log(q_k⁻¹ q_{k+1}) / dt` (rotation vector of the body-fixed increment), and the same angular
//! velocity in the fixed frame is `ω_O = log(q_{k+1} q_k⁻¹) / dt = R_k ω_b`. A constant body rate is also
//! constant in the fixed frame during the interval (`R(t) = R_k exp(t[ω_b]) = exp(t[R_k ω_b]) R_k`), so
//! "constant angular velocity between samples" means the same thing in either frame.

use nalgebra::{UnitQuaternion, Vector3};

/// Sphere radius of the paper's §3.1 scene (m).
pub const PAPER_RADIUS_M: f64 = 0.010;
/// Sampling period of the paper's scene (s).
pub const PAPER_DT_S: f64 = 0.01;
/// Duration of the paper's scene (s).
pub const PAPER_DURATION_S: f64 = 1.0;
/// Per-sample body-fixed Euler increments of the paper's scene (rad): `[δφ about z, δθ about y, δψ about x]`.
pub const PAPER_INCREMENTS_ZYX: [f64; 3] = [0.05, 0.02, 0.03];

/// A sampled orientation sequence with its sampling period and sphere radius.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Orientation samples `q_0 … q_N` (fingertip → object frame).
    pub samples: Vec<UnitQuaternion<f64>>,
    /// Sampling period (s).
    pub dt: f64,
    /// Sphere radius (m).
    pub radius: f64,
}

/// Rotation vector (axis·angle, rad, angle in `[0, π]`) of `q`, accurate for tiny angles: uses
/// `2·atan2(|v|, |w|)` rather than `2·acos(w)`, whose error grows like `ε/θ`.
pub fn rotation_vector(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    let (w, v) = if q.w < 0.0 {
        (-q.w, -q.imag())
    } else {
        (q.w, q.imag())
    };
    let n = v.norm();
    if n == 0.0 {
        return Vector3::zeros();
    }
    let angle = 2.0 * n.atan2(w);
    v * (angle / n)
}

/// The paper's per-sample body-fixed increment `Δq = Rz(δφ) ⊗ Ry(δθ) ⊗ Rx(δψ)`.
pub fn paper_increment() -> UnitQuaternion<f64> {
    let [phi, theta, psi] = PAPER_INCREMENTS_ZYX;
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), phi)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), theta)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), psi)
}

/// The paper's constant body angular velocity `log(Δq) / 10 ms` (rad/s, body frame).
pub fn paper_body_rate() -> Vector3<f64> {
    rotation_vector(&paper_increment()) / PAPER_DT_S
}

/// Samples of a constant body rate `omega_body` (rad/s) from `q0`, at `rate_hz` for `duration_s`:
/// `q_k = q0 ⊗ exp(omega_body · k/rate_hz)`, `k = 0 … round(rate_hz·duration_s)`. Each sample is computed
/// directly (no accumulated products), so consecutive samples differ by exactly the same body increment up
/// to round-off.
pub fn constant_body_rate_samples(
    q0: &UnitQuaternion<f64>,
    omega_body: &Vector3<f64>,
    rate_hz: f64,
    duration_s: f64,
) -> Vec<UnitQuaternion<f64>> {
    let n = (rate_hz * duration_s).round().max(0.0) as usize;
    (0..=n)
        .map(|k| q0 * UnitQuaternion::from_scaled_axis(omega_body * (k as f64 / rate_hz)))
        .collect()
}

/// The paper's §3.1 scene: radius 10 mm, 10 ms sampling, 1 s (101 samples), `q_0 = 1`,
/// `q_{k+1} = q_k ⊗ Rz(0.05) ⊗ Ry(0.02) ⊗ Rx(0.03)`.
pub fn paper_scene() -> Scene {
    paper_scene_at_rate(1.0 / PAPER_DT_S)
}

/// The paper's motion (same body angular velocity, same 1 s, `q_0 = 1`) sampled at `rate_hz`
/// (e.g. 100, 1000, 4000, 10 000, 20 000 Hz); the per-sample increment is `exp(ω_body / rate_hz)`.
pub fn paper_scene_at_rate(rate_hz: f64) -> Scene {
    Scene {
        samples: constant_body_rate_samples(
            &UnitQuaternion::identity(),
            &paper_body_rate(),
            rate_hz,
            PAPER_DURATION_S,
        ),
        dt: 1.0 / rate_hz,
        radius: PAPER_RADIUS_M,
    }
}

/// Body-fixed increments `log(q_k⁻¹ q_{k+1})` (rad, body frame at `t_k`), one per interval.
pub fn body_increments(samples: &[UnitQuaternion<f64>]) -> Vec<Vector3<f64>> {
    samples
        .windows(2)
        .map(|w| rotation_vector(&(w[0].inverse() * w[1])))
        .collect()
}

/// Fixed-frame increments `log(q_{k+1} q_k⁻¹)` (rad, object frame), one per interval.
pub fn object_increments(samples: &[UnitQuaternion<f64>]) -> Vec<Vector3<f64>> {
    samples
        .windows(2)
        .map(|w| rotation_vector(&(w[1] * w[0].inverse())))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_vector_matches_nalgebra_and_is_accurate_when_tiny() {
        for v in [
            Vector3::new(0.3, -0.2, 0.1),
            Vector3::new(-2.0, 1.0, 0.5),
            Vector3::new(1e-9, 2e-9, -3e-9),
        ] {
            let q = UnitQuaternion::from_scaled_axis(v);
            // Relative accuracy of a few ulp even for 1e-9 rad (acos would give only ~1e-7 relative
            // there). Measured: the round trip returns these three vectors exactly (0). The bound is
            // 4 ulp of |v| rather than equality because the round trip goes through sin, cos and atan2,
            // which come from the platform's libm (faithful, not bit-identical across platforms).
            let ulps = 4.0 * f64::EPSILON * v.norm();
            assert!((rotation_vector(&q) - v).norm() <= ulps);
            // -q is the same rotation (measured 0 as well).
            let qn = UnitQuaternion::new_unchecked(-q.into_inner());
            assert!((rotation_vector(&qn) - v).norm() <= ulps);
        }
        assert_eq!(
            rotation_vector(&UnitQuaternion::identity()),
            Vector3::zeros()
        );
    }

    #[test]
    fn paper_increment_is_body_fixed_zyx() {
        // nalgebra's from_euler_angles(roll, pitch, yaw) = Rz(yaw)·Ry(pitch)·Rx(roll): the same product.
        // Measured 6.9e-18 rad apart; bound 3×.
        let q = UnitQuaternion::from_euler_angles(0.03, 0.02, 0.05);
        assert!(paper_increment().angle_to(&q) < 2.1e-17);
        // Its Z-Y-X decomposition returns the increments: measured 1 ulp off each (3.5e-18, 3.5e-18,
        // 6.9e-18 rad); bounds 3 ulp.
        let (r, p, y) = paper_increment().euler_angles();
        assert!((r - 0.03).abs() < 1e-17 && (p - 0.02).abs() < 1e-17 && (y - 0.05).abs() < 2.1e-17);
    }

    #[test]
    fn paper_scene_is_repeated_body_increment() {
        // q_{k+1} = q_k ⊗ Δq by repeated products must equal the directly computed samples; rounding of
        // 100 products accumulates to at most ~100·ε ≈ 2e-14 rad; measured 1.45e-15 rad; bound 3×.
        let s = paper_scene();
        assert_eq!(s.samples.len(), 101);
        assert_eq!(s.dt, 0.01);
        assert_eq!(s.radius, 0.01);
        let mut q = UnitQuaternion::identity();
        for sample in &s.samples {
            assert!(sample.angle_to(&q) < 4.4e-15);
            q *= paper_increment();
        }
    }

    #[test]
    fn other_rates_keep_the_body_rate() {
        for (rate, bound) in [(1000.0, 3.7e-12), (4000.0, 3e-11), (20_000.0, 1.5e-10)] {
            let s = paper_scene_at_rate(rate);
            assert_eq!(s.samples.len(), rate as usize + 1);
            let inc = body_increments(&s.samples);
            // Every body increment is ω_body/rate. The samples and their product carry ~ε absolute
            // round-off each, i.e. ~1e-16·rate ≈ 2e-12 rad/s per rounding at 20 kHz. Measured worst
            // (several roundings) 1.25e-12, 9.9e-12 and 4.9e-11 rad/s at 1, 4 and 20 kHz; bounds 3×.
            for d in &inc {
                assert!((d * rate - paper_body_rate()).norm() < bound, "{rate} Hz");
            }
            // The final orientation is the same for every rate (same motion over 1 s): measured
            // 3.5e-18 rad apart at each rate; bound 3×.
            let end = s.samples.last().unwrap();
            let end_100 = paper_scene().samples.last().copied().unwrap();
            assert!(end.angle_to(&end_100) < 1e-17);
        }
    }

    #[test]
    fn object_increment_is_body_increment_rotated() {
        let s = paper_scene();
        let b = body_increments(&s.samples);
        let o = object_increments(&s.samples);
        // Measured 2.4e-16 at worst (2 ulp of the unit quaternions); bound 3×.
        for k in 0..b.len() {
            assert!((s.samples[k] * b[k] - o[k]).norm() < 7.3e-16);
        }
    }
}
