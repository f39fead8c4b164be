//! The pose of a model's object frame in the device base frame, and the probe sample moved into
//! it.
//!
//! A pose `(o, R)` maps object-frame points to the base frame: `p_B = o + R·p_O`. The probe goes
//! the other way: `p_O = Rᵀ·(p_B − o)`, velocities `v_O = Rᵀ·v_B`, the fingertip orientation
//! `q_O = R* · q_B` (fingertip frame → object frame). Forces come back as `F_B = R·F_O`.

use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Math;

/// Pose of an object frame in the base frame.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ModelPose {
    /// Origin of the object frame, base frame, m.
    pub position_m: Vec3,
    /// Unit quaternion mapping object-frame vectors to the base frame.
    pub orientation: Quat,
}

impl ModelPose {
    /// The base frame itself.
    pub const IDENTITY: ModelPose = ModelPose {
        position_m: Vec3::ZERO,
        orientation: Quat::IDENTITY,
    };

    /// A pose translated only.
    pub const fn at(position_m: Vec3) -> ModelPose {
        ModelPose {
            position_m,
            orientation: Quat::IDENTITY,
        }
    }

    /// A base-frame point in the object frame.
    #[inline]
    pub fn point_to_object(&self, p_base: Vec3) -> Vec3 {
        self.orientation
            .conjugate()
            .rotate(p_base - self.position_m)
    }

    /// A base-frame vector (velocity) in the object frame.
    #[inline]
    pub fn vector_to_object(&self, v_base: Vec3) -> Vec3 {
        self.orientation.conjugate().rotate(v_base)
    }

    /// An object-frame point in the base frame.
    #[inline]
    pub fn point_to_base(&self, p_object: Vec3) -> Vec3 {
        self.position_m + self.orientation.rotate(p_object)
    }

    /// An object-frame vector (force) in the base frame.
    #[inline]
    pub fn vector_to_base(&self, v_object: Vec3) -> Vec3 {
        self.orientation.rotate(v_object)
    }

    /// The pose a fraction `s` ∈ [0, 1] of the way from `self` to `to`: positions interpolated
    /// linearly, orientations by normalised linear interpolation along the shorter arc.
    pub fn interpolate<M: Math>(&self, to: &ModelPose, s: f32) -> ModelPose {
        let (a, mut b) = (self.orientation, to.orientation);
        if a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z < 0.0 {
            b = Quat::new(-b.w, -b.x, -b.y, -b.z);
        }
        let lerp = |x: f32, y: f32| x + (y - x) * s;
        let q = Quat::new(
            lerp(a.w, b.w),
            lerp(a.x, b.x),
            lerp(a.y, b.y),
            lerp(a.z, b.z),
        );
        let (q, _) = q.normalized_checked::<M>();
        ModelPose {
            position_m: self.position_m + (to.position_m - self.position_m) * s,
            orientation: q,
        }
    }
}

/// One probe sample in the base frame, as the pipeline has it each tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ProbeSample {
    /// Fingertip orientation, fingertip frame → base frame.
    pub q: Quat,
    /// Probe (fingertip centre), base frame, m.
    pub probe_m: Vec3,
    /// Probe velocity, base frame, m/s.
    pub probe_vel: Vec3,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Libm;

    /// Round trips through a rotated, translated frame, against the rotation written out by hand:
    /// 90° about z maps object x to base y. Squared distances measured 1.78e-14, 1.42e-14,
    /// 7.1e-15 and 1.42e-14; bounds 3x.
    #[test]
    fn transforms_match_a_hand_written_rotation() {
        let h = core::f32::consts::FRAC_1_SQRT_2;
        let pose = ModelPose {
            position_m: Vec3::new(0.1, 0.2, 0.3),
            orientation: Quat::new(h, 0.0, 0.0, h),
        };
        let p = pose.point_to_base(Vec3::new(1.0, 0.0, 0.0));
        assert!(
            (p - Vec3::new(0.1, 1.2, 0.3)).norm_squared() < 5.3e-14,
            "{p:?}"
        );
        let back = pose.point_to_object(p);
        assert!((back - Vec3::X).norm_squared() < 4.3e-14);
        let f = pose.vector_to_base(Vec3::new(0.0, 1.0, 0.0));
        assert!((f - Vec3::new(-1.0, 0.0, 0.0)).norm_squared() < 2.1e-14);
        assert!((pose.vector_to_object(f) - Vec3::Y).norm_squared() < 4.3e-14);
    }

    /// Measured: the middle position exact, its scalar part 5.96e-8 off cos(π/8), the end point
    /// 2.84e-14 m² off; bounds 3x.
    #[test]
    fn interpolation_ends_and_middle() {
        let h = core::f32::consts::FRAC_1_SQRT_2;
        let a = ModelPose::IDENTITY;
        let b = ModelPose {
            position_m: Vec3::new(0.0, 0.0, 0.02),
            // −q of 90° about z: the same rotation, the shorter arc must still be taken.
            orientation: Quat::new(-h, 0.0, 0.0, -h),
        };
        let m = a.interpolate::<Libm>(&b, 0.5);
        assert_eq!(m.position_m.z, 0.01);
        // Halfway along the arc: 45° about z.
        let c = libm::cosf(core::f32::consts::FRAC_PI_8);
        assert!(
            (m.orientation.w.abs() - c).abs() < 1.8e-7,
            "{:?}",
            m.orientation
        );
        let e = a.interpolate::<Libm>(&b, 1.0);
        assert!((e.point_to_base(Vec3::X) - Vec3::new(0.0, 1.0, 0.02)).norm_squared() < 8.5e-14);
    }
}
