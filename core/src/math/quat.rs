//! Unit quaternions for orientations and rotation increments.
//!
//! Convention: Hamilton product, scalar first `(w, x, y, z)`. A quaternion `q` describing the
//! orientation of a body maps body-frame vectors to the reference frame: `v_ref = q ⊗ v_body ⊗ q*`,
//! the same rotation as the matrix [`Rot3::from_quat`](crate::math::rot3::Rot3::from_quat).

use crate::flags::Flags;
use crate::math::vec3::Vec3;
use crate::math::Math;
use core::ops::Mul;

/// Below this |v| (sine of half the angle) the log and exp maps use their Taylor series; the
/// neglected terms are below f32 resolution there (relative error < 1e-9).
const SERIES_THRESHOLD: f32 = 1.0e-4;

/// |‖q‖² − 1| up to which [`Quat::unit_checked`] accepts a quaternion as it is. 1.9e-3 keeps
/// |‖q‖ − 1| = |‖q‖² − 1|/(‖q‖ + 1) below [`UNIT_TOLERANCE`].
const NEAR_UNIT_N2: f32 = 1.9e-3;

/// Tolerance on |‖q‖ - 1| before [`Quat::normalized_checked`] raises [`Flags::NON_UNIT_QUAT`].
pub const UNIT_TOLERANCE: f32 = 1.0e-3;

/// A quaternion `w + x i + y j + z k`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Quat {
    /// Scalar part.
    pub w: f32,
    /// i component of the vector part.
    pub x: f32,
    /// j component of the vector part.
    pub y: f32,
    /// k component of the vector part.
    pub z: f32,
}

impl Default for Quat {
    fn default() -> Quat {
        Quat::IDENTITY
    }
}

impl Quat {
    /// The identity rotation `1 + 0 i + 0 j + 0 k`.
    pub const IDENTITY: Quat = Quat::new(1.0, 0.0, 0.0, 0.0);

    /// The quaternion `w + x i + y j + z k`, as given (not normalised).
    #[inline]
    pub const fn new(w: f32, x: f32, y: f32, z: f32) -> Quat {
        Quat { w, x, y, z }
    }
    /// The vector part (x, y, z).
    #[inline]
    pub fn vector(self) -> Vec3 {
        Vec3::new(self.x, self.y, self.z)
    }
    /// Conjugate; the inverse of a unit quaternion.
    #[inline]
    pub fn conjugate(self) -> Quat {
        Quat::new(self.w, -self.x, -self.y, -self.z)
    }
    /// Squared norm ‖q‖² = w² + x² + y² + z² (1 for a unit quaternion).
    #[inline]
    pub fn norm_squared(self) -> f32 {
        self.w * self.w + self.x * self.x + self.y * self.y + self.z * self.z
    }
    /// True when all four components are finite.
    #[inline]
    pub fn is_finite(self) -> bool {
        crate::flags::all_finite(&[self.w, self.x, self.y, self.z])
    }
    #[inline]
    fn scale(self, s: f32) -> Quat {
        Quat::new(self.w * s, self.x * s, self.y * s, self.z * s)
    }

    /// Check a quaternion that should be unit, for callers whose math does not depend on its scale
    /// (the exact method's log map is scale-free). Within the tolerance (|‖q‖ − 1| ≤ 1e-3) it is
    /// returned **unchanged**: rescaling would round every component, and at kHz rates that
    /// rounding noise random-walks into the rolled contact path (measured: 4x the drift over 10⁶
    /// steps at 10 kHz). Outside the tolerance, and for non-finite or zero input, the answer and
    /// flags are those of [`Quat::normalized_checked`]. No square root on the common path.
    #[inline(always)]
    #[must_use]
    pub fn unit_checked<M: Math>(self) -> (Quat, Flags) {
        if self.is_near_unit() {
            return (self, Flags::NONE);
        }
        self.normalized_checked::<M>()
    }

    /// True when the squared norm is within 1.9e-3 of 1 with finite components: the samples
    /// [`Quat::unit_checked`] leaves as they are.
    #[inline(always)]
    pub fn is_near_unit(self) -> bool {
        let d = self.norm_squared() - 1.0;
        // NaN or inf components make `d` NaN or inf, which fails this test.
        d.abs() <= NEAR_UNIT_N2
    }

    /// Normalise, with a defined answer for every input.
    ///
    /// - non-finite component: identity, [`Flags::NON_FINITE_INPUT`];
    /// - zero (or subnormal-small) norm: identity, [`Flags::ZERO_AXIS`];
    /// - |‖q‖ - 1| > [`UNIT_TOLERANCE`]: normalised, [`Flags::NON_UNIT_QUAT`];
    /// - otherwise normalised silently.
    #[must_use]
    pub fn normalized_checked<M: Math>(self) -> (Quat, Flags) {
        let n2 = self.norm_squared();
        // One test covers every bad component: a NaN or infinite one makes n2 NaN or +inf (a sum
        // of squares has no cancelling term), and n2 also overflows to +inf for huge finite
        // components, treated like non-finite.
        if !n2.is_finite() {
            return (Quat::IDENTITY, Flags::NON_FINITE_INPUT);
        }
        if n2 < 1.0e-30 {
            return (Quat::IDENTITY, Flags::ZERO_AXIS);
        }
        let n = M::sqrt(n2);
        let flags = if (n - 1.0).abs() > UNIT_TOLERANCE {
            Flags::NON_UNIT_QUAT
        } else {
            Flags::NONE
        };
        (self.scale(1.0 / n), flags)
    }

    /// Rotation of `angle` radians about the unit `axis` (right-hand rule). The axis is assumed unit;
    /// use [`Quat::from_rotation_vector`] for an unnormalised input.
    #[inline]
    pub fn from_axis_angle<M: Math>(axis: Vec3, angle: f32) -> Quat {
        let (s, c) = M::sin_cos(0.5 * angle);
        Quat::new(c, axis.x * s, axis.y * s, axis.z * s)
    }

    /// Exponential map: the rotation by |w| radians about w/|w|. Zero vector gives identity.
    /// Non-finite input gives identity and [`Flags::NON_FINITE_INPUT`].
    #[must_use]
    pub fn from_rotation_vector<M: Math>(w: Vec3) -> (Quat, Flags) {
        if !w.is_finite() {
            return (Quat::IDENTITY, Flags::NON_FINITE_INPUT);
        }
        let a2 = w.norm_squared();
        if !a2.is_finite() {
            return (Quat::IDENTITY, Flags::NON_FINITE_INPUT);
        }
        let half = 0.5 * M::sqrt(a2);
        if half < SERIES_THRESHOLD {
            // sin(h)/|w| = (1/2)(1 - h²/6); cos(h) = 1 - h²/2.
            let s = 0.5 * (1.0 - half * half / 6.0);
            return (
                Quat::new(1.0 - 0.5 * half * half, w.x * s, w.y * s, w.z * s),
                Flags::NONE,
            );
        }
        let (s, c) = M::sin_cos(half);
        let k = s / (2.0 * half);
        (Quat::new(c, w.x * k, w.y * k, w.z * k), Flags::NONE)
    }

    /// Logarithm map: the rotation vector (axis × angle, angle in [0, π]) of a unit quaternion.
    ///
    /// Well conditioned over the whole range: angle = 2·atan2(|v|, |w|) never loses precision near
    /// 0 or π, and q and -q give the same answer. Input is assumed finite.
    ///
    /// Fast path for angles up to 2·atan(0.2) = 0.39 rad: a degree-5 series in u = |v|²/w², no
    /// square root and no arctangent. Derivation: docs/design.md#rotation-vector-fast-path.
    #[inline(always)]
    pub fn to_rotation_vector<M: Math>(self) -> Vec3 {
        // The series needs no hemisphere: (−v)·(2/(−w))·P = v·(2/w)·P bit for bit (negation is
        // exact and u is even in w), so −q gives the same answer without a sign flip.
        let v = self.vector();
        let s2 = v.norm_squared();
        let w2 = self.w * self.w;
        if s2 <= 0.04 * w2 && self.w != 0.0 {
            let inv_w = 1.0 / self.w;
            let u = s2 * inv_w * inv_w;
            let p = 1.0
                + u * (-1.0 / 3.0
                    + u * (1.0 / 5.0 + u * (-1.0 / 7.0 + u * (1.0 / 9.0 - u * (1.0 / 11.0)))));
            return v * (2.0 * inv_w * p);
        }
        // Take the hemisphere w >= 0 so the angle is in [0, π].
        let q = if self.w < 0.0 { self.scale(-1.0) } else { self };
        let v = q.vector();
        let s = M::sqrt(s2);
        let k = if s < SERIES_THRESHOLD {
            // 2·atan2(s, w)/s = (2/w)(1 - s²/(3w²) + ...); w ≈ 1 here.
            2.0 / q.w
        } else {
            2.0 * M::atan2(s, q.w) / s
        };
        v * k
    }

    /// Rotate a vector: `q ⊗ v ⊗ q*` for a unit quaternion.
    #[inline]
    pub fn rotate(self, v: Vec3) -> Vec3 {
        // v' = v + 2w (u × v) + 2 u × (u × v), u the vector part.
        let u = self.vector();
        let t = u.cross(v) * 2.0;
        v + t * self.w + u.cross(t)
    }
}

impl Mul for Quat {
    type Output = Quat;
    /// Hamilton product `self ⊗ o`: apply `o` first, then `self`.
    #[inline]
    fn mul(self, o: Quat) -> Quat {
        Quat::new(
            self.w * o.w - self.x * o.x - self.y * o.y - self.z * o.z,
            self.w * o.x + self.x * o.w + self.y * o.z - self.z * o.y,
            self.w * o.y - self.x * o.z + self.y * o.w + self.z * o.x,
            self.w * o.z + self.x * o.y - self.y * o.x + self.z * o.w,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Libm;

    #[test]
    fn log_of_exp_round_trips_over_the_whole_angle_range() {
        let axis = Vec3::new(0.3, -0.5, 0.8);
        let axis = axis * (1.0 / axis.norm::<Libm>());
        for &angle in &[
            0.0f32,
            1e-7,
            1e-5,
            1e-3,
            0.1,
            1.0,
            2.5,
            3.1,
            core::f32::consts::PI - 1e-4,
        ] {
            let (q, f) = Quat::from_rotation_vector::<Libm>(axis * angle);
            assert!(f.is_empty());
            let w = q.to_rotation_vector::<Libm>();
            let err = (w - axis * angle).norm::<Libm>();
            // f32 quaternion components carry ~6e-8 absolute error; 2·atan2 doubles it, and near π
            // the axis direction is set by components of size ~1: an f32 floor of a few 1e-7. The
            // worst error measured is 0.165 of 4e-7·(1 + angle) (2.73e-7 rad); asserted is that
            // model scaled to 3x the measurement.
            assert!(err <= 2e-7 + 2e-7 * angle, "angle {angle}: err {err}");
        }
    }

    #[test]
    fn normalized_checked_flags_every_bad_input() {
        let (q, f) = Quat::new(f32::NAN, 0.0, 0.0, 0.0).normalized_checked::<Libm>();
        assert_eq!((q, f), (Quat::IDENTITY, Flags::NON_FINITE_INPUT));
        let (q, f) = Quat::new(0.0, 0.0, 0.0, 0.0).normalized_checked::<Libm>();
        assert_eq!((q, f), (Quat::IDENTITY, Flags::ZERO_AXIS));
        let (q, f) = Quat::new(2.0, 0.0, 0.0, 0.0).normalized_checked::<Libm>();
        assert_eq!((q, f), (Quat::IDENTITY, Flags::NON_UNIT_QUAT));
        let (q, f) = Quat::new(1.0005, 0.0, 0.0, 0.0).normalized_checked::<Libm>();
        assert_eq!((q, f), (Quat::IDENTITY, Flags::NONE));
        let (_, f) = Quat::new(3e38, 3e38, 0.0, 0.0).normalized_checked::<Libm>();
        assert_eq!(f, Flags::NON_FINITE_INPUT);
    }

    /// The fast log path (angles ≤ 0.39 rad) against nalgebra f64 over a dense sweep of angles and
    /// axes, including scaled (non-unit) inputs: 2e-7 absolute + 3e-7 relative, the same f32
    /// budget as the atan2 path (the series itself is exact to 3.2e-10 relative).
    #[test]
    fn fast_log_path_matches_nalgebra_and_is_scale_free() {
        use nalgebra::{Unit, UnitQuaternion, Vector3};
        for k in 0..2000 {
            let angle = 0.39 * (k as f64 / 2000.0);
            let a = Vector3::new(
                (k as f64 * 0.37).sin(),
                (k as f64 * 0.11).cos(),
                0.3 + (k as f64 * 0.05).sin(),
            );
            let q64 = UnitQuaternion::from_axis_angle(&Unit::new_normalize(a), angle);
            let w_ref = q64.scaled_axis();
            for scale in [1.0f32, 1.0009, 0.7] {
                let q = Quat::new(
                    q64.w as f32 * scale,
                    q64.i as f32 * scale,
                    q64.j as f32 * scale,
                    q64.k as f32 * scale,
                );
                let w = q.to_rotation_vector::<Libm>();
                // −q is the same rotation: the same answer bit for bit (no hemisphere flip on
                // this path; see `to_rotation_vector`).
                let wn = q.scale(-1.0).to_rotation_vector::<Libm>();
                assert_eq!(
                    wn.to_array().map(f32::to_bits),
                    w.to_array().map(f32::to_bits)
                );
                let err = ((w.x as f64 - w_ref.x).powi(2)
                    + (w.y as f64 - w_ref.y).powi(2)
                    + (w.z as f64 - w_ref.z).powi(2))
                .sqrt();
                // Measured: at most 0.225 of 2e-7 + 3e-7·angle (6.9e-8 rad); asserted is that
                // model scaled to 3x the measurement.
                assert!(
                    err <= 1.35e-7 + 2.03e-7 * angle,
                    "angle {angle} scale {scale}: {err:e}"
                );
            }
        }
    }

    /// `unit_checked` leaves near-unit quaternions bit for bit as they are, and otherwise answers
    /// like `normalized_checked`.
    #[test]
    fn unit_checked_leaves_near_unit_input_alone() {
        for k in 0..1000 {
            let e = -9.4e-4 + 1.88e-3 * k as f32 / 1000.0;
            let q = Quat::new(
                0.5 * (1.0 + e),
                0.5 * (1.0 + e),
                -0.5 * (1.0 + e),
                0.5 * (1.0 + e),
            );
            assert_eq!(q.unit_checked::<Libm>(), (q, Flags::NONE), "e {e}");
        }
        for q in [
            Quat::new(2.0, 0.0, 0.0, 0.0),
            Quat::new(f32::NAN, 0.0, 0.0, 0.0),
            Quat::new(0.0, 0.0, 0.0, 0.0),
        ] {
            assert_eq!(q.unit_checked::<Libm>(), q.normalized_checked::<Libm>());
        }
    }

    #[test]
    fn rotate_matches_the_right_hand_rule() {
        let q = Quat::from_axis_angle::<Libm>(Vec3::Z, core::f32::consts::FRAC_PI_2);
        let v = q.rotate(Vec3::X);
        // Measured 7.1e-15 (squared); bound 3x.
        assert!((v - Vec3::Y).norm_squared() < 2.1e-14, "{v:?}");
    }
}
