//! Rotation matrices and Rodrigues' formula (the paper's eq. 4).
//!
//! `Rot3.m[i][j]` is the paper's r_{(i+1)(j+1)}: row i, column j. A matrix `R` describing a body's
//! orientation maps body-frame vectors to the reference frame: `v_ref = R · v_body`.

use crate::flags::Flags;
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Math;

/// A 3×3 rotation matrix, row-major.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Rot3 {
    /// Entries: `m[i][j]` is row i, column j (the paper's r_{(i+1)(j+1)}).
    pub m: [[f32; 3]; 3],
}

impl Default for Rot3 {
    fn default() -> Rot3 {
        Rot3::IDENTITY
    }
}

impl Rot3 {
    /// The identity matrix (no rotation).
    pub const IDENTITY: Rot3 = Rot3 {
        m: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };

    /// Rodrigues' formula, eq. (4): `R(α, γ) = ααᵀ + (I - ααᵀ) cos γ + S(α) sin γ`, a rotation by
    /// `angle` γ (radians, right-hand rule) about the unit `axis` α.
    ///
    /// The axis is normalised first. Zero (or shorter than 1e-15) axis: identity with
    /// [`Flags::ZERO_AXIS`]. NaN or ±inf anywhere: identity with [`Flags::NON_FINITE_INPUT`]. An axis
    /// whose norm is off unity by more than 1e-3 is normalised and flagged [`Flags::NON_UNIT_QUAT`]
    /// (the same tolerance as for quaternions).
    #[must_use]
    pub fn from_axis_angle<M: Math>(axis: Vec3, angle: f32) -> (Rot3, Flags) {
        if !axis.is_finite() || !angle.is_finite() || !axis.norm_squared().is_finite() {
            return (Rot3::IDENTITY, Flags::NON_FINITE_INPUT);
        }
        let n2 = axis.norm_squared();
        if n2 < 1.0e-30 {
            return (Rot3::IDENTITY, Flags::ZERO_AXIS);
        }
        let n = M::sqrt(n2);
        let flags = if (n - 1.0).abs() > crate::math::quat::UNIT_TOLERANCE {
            Flags::NON_UNIT_QUAT
        } else {
            Flags::NONE
        };
        let a = axis * (1.0 / n);
        let (s, c) = M::sin_cos(angle);
        (Rot3::rodrigues_unit(a, s, c), flags)
    }

    /// Rodrigues' formula from a rotation vector w (axis × angle, radians). Zero vector: identity.
    /// Non-finite: identity with [`Flags::NON_FINITE_INPUT`].
    #[must_use]
    pub fn from_rotation_vector<M: Math>(w: Vec3) -> (Rot3, Flags) {
        if !w.is_finite() || !w.norm_squared().is_finite() {
            return (Rot3::IDENTITY, Flags::NON_FINITE_INPUT);
        }
        let angle = w.norm::<M>();
        if angle < 1.0e-15 {
            return (Rot3::IDENTITY, Flags::NONE);
        }
        let a = w * (1.0 / angle);
        let (s, c) = M::sin_cos(angle);
        (Rot3::rodrigues_unit(a, s, c), Flags::NONE)
    }

    /// Eq. (4) with a unit axis and precomputed sin γ, cos γ.
    #[inline]
    fn rodrigues_unit(a: Vec3, s: f32, c: f32) -> Rot3 {
        let t = 1.0 - c;
        // ααᵀ(1 - cos γ) + I cos γ + S(α) sin γ, with S(α) the skew (cross-product) matrix.
        Rot3 {
            m: [
                [
                    a.x * a.x * t + c,
                    a.x * a.y * t - a.z * s,
                    a.x * a.z * t + a.y * s,
                ],
                [
                    a.y * a.x * t + a.z * s,
                    a.y * a.y * t + c,
                    a.y * a.z * t - a.x * s,
                ],
                [
                    a.z * a.x * t - a.y * s,
                    a.z * a.y * t + a.x * s,
                    a.z * a.z * t + c,
                ],
            ],
        }
    }

    /// The same rotation as a unit quaternion: Rodrigues' formula in quaternion form (no trig).
    /// With q = (cos γ/2, α sin γ/2) this equals [`Rot3::from_axis_angle`]`(α, γ)` exactly in real
    /// arithmetic.
    #[inline]
    pub fn from_quat(q: Quat) -> Rot3 {
        let (w, x, y, z) = (q.w, q.x, q.y, q.z);
        let (xx, yy, zz) = (x * x, y * y, z * z);
        let (xy, xz, yz) = (x * y, x * z, y * z);
        let (wx, wy, wz) = (w * x, w * y, w * z);
        Rot3 {
            m: [
                [1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz), 2.0 * (xz + wy)],
                [2.0 * (xy + wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx)],
                [2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (xx + yy)],
            ],
        }
    }

    /// Matrix product `self · o`.
    pub fn mul(&self, o: &Rot3) -> Rot3 {
        let mut r = [[0.0f32; 3]; 3];
        for (i, row) in r.iter_mut().enumerate() {
            for (j, cell) in row.iter_mut().enumerate() {
                *cell =
                    self.m[i][0] * o.m[0][j] + self.m[i][1] * o.m[1][j] + self.m[i][2] * o.m[2][j];
            }
        }
        Rot3 { m: r }
    }

    /// Transpose (the inverse of a rotation).
    pub fn transpose(&self) -> Rot3 {
        let m = &self.m;
        Rot3 {
            m: [
                [m[0][0], m[1][0], m[2][0]],
                [m[0][1], m[1][1], m[2][1]],
                [m[0][2], m[1][2], m[2][2]],
            ],
        }
    }

    /// `self · v`.
    #[inline]
    pub fn apply(&self, v: Vec3) -> Vec3 {
        let m = &self.m;
        Vec3::new(
            m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Libm;
    use nalgebra::{Rotation3, Unit, Vector3};

    fn max_abs_diff(a: &Rot3, b: &Rotation3<f64>) -> f64 {
        let mut d = 0.0f64;
        for i in 0..3 {
            for j in 0..3 {
                d = d.max((a.m[i][j] as f64 - b[(i, j)]).abs());
            }
        }
        d
    }

    /// Rodrigues (eq. 4) against nalgebra's f64 `Rotation3::from_axis_angle`, swept over 26 axis
    /// directions and angles from 1e-7 to π. Tolerance 1e-6 per element: the f32 inputs carry
    /// 6e-8 relative rounding and the formula sums three terms of size ≤ 1, each rounded once,
    /// so a few ulps of 1.0 (1.2e-7 each) is the floor; 1e-6 leaves ~8 ulps.
    #[test]
    fn rodrigues_matches_nalgebra_over_axes_and_angles() {
        let mut worst = 0.0f64;
        for ix in -1..=1 {
            for iy in -1..=1 {
                for iz in -1..=1 {
                    if ix == 0 && iy == 0 && iz == 0 {
                        continue;
                    }
                    let a = Vector3::new(ix as f64, iy as f64, iz as f64).normalize();
                    for k in 0..=70 {
                        // 1e-7 .. π, log-spaced
                        let angle = 1e-7f64 * (core::f64::consts::PI / 1e-7).powf(k as f64 / 70.0);
                        let axis = Vec3::new(a.x as f32, a.y as f32, a.z as f32);
                        let (r, f) = Rot3::from_axis_angle::<Libm>(axis, angle as f32);
                        assert!(f.is_empty());
                        let reference = Rotation3::from_axis_angle(&Unit::new_normalize(a), angle);
                        worst = worst.max(max_abs_diff(&r, &reference));
                    }
                }
            }
        }
        // Measured 1.99e-7; bound 3x.
        assert!(worst < 6e-7, "worst element error {worst:e}");
    }

    #[test]
    fn from_quat_is_rodrigues_in_quaternion_form() {
        let axis = Vec3::new(0.2, 0.3, -0.9);
        let axis = axis * (1.0 / axis.norm::<Libm>());
        for &angle in &[1e-6f32, 0.02, 0.7, 2.0, 3.1] {
            let (r1, _) = Rot3::from_axis_angle::<Libm>(axis, angle);
            let r2 = Rot3::from_quat(Quat::from_axis_angle::<Libm>(axis, angle));
            for i in 0..3 {
                for j in 0..3 {
                    // Measured 1.79e-7; bound 3x.
                    assert!((r1.m[i][j] - r2.m[i][j]).abs() < 5.4e-7, "angle {angle}");
                }
            }
        }
    }

    #[test]
    fn bad_axes_give_identity_and_a_flag() {
        assert_eq!(
            Rot3::from_axis_angle::<Libm>(Vec3::ZERO, 1.0),
            (Rot3::IDENTITY, Flags::ZERO_AXIS)
        );
        assert_eq!(
            Rot3::from_axis_angle::<Libm>(Vec3::new(f32::NAN, 0.0, 1.0), 1.0),
            (Rot3::IDENTITY, Flags::NON_FINITE_INPUT)
        );
        assert_eq!(
            Rot3::from_axis_angle::<Libm>(Vec3::X, f32::INFINITY),
            (Rot3::IDENTITY, Flags::NON_FINITE_INPUT)
        );
        let (r, f) = Rot3::from_axis_angle::<Libm>(Vec3::new(0.0, 0.0, 5.0), 0.5);
        assert_eq!(f, Flags::NON_UNIT_QUAT);
        assert!(r.m[2][2] == 1.0);
    }
}
