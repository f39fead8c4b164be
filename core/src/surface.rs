//! The object surface the fingertip rolls on. Chosen by type (static dispatch), so a sphere-on-plane
//! scene pays only for the plane.
//!
//! Object frame `O`: fixed to the object. Contact frame `C`: origin at the contact point, z along the
//! outward normal (towards the fingertip), x and y tangent. A contact-frame quaternion maps `C`
//! vectors to `O`.

use crate::math::Math;
use crate::quat::Quat;
use crate::vec3::Vec3;

/// A convex object surface with a moving contact frame.
pub trait Surface: Copy + core::fmt::Debug {
    /// Curvature 1/R of the object surface, 1/m (plane: 0).
    fn curvature(&self) -> f32;
    /// Express a rotation increment given in the object frame in the contact frame.
    fn to_contact_frame(&self, dq_object: Quat) -> Quat;
    /// Map a contact-frame vector to the object frame.
    fn contact_to_object(&self, v_contact: Vec3) -> Vec3;
    /// Move the contact point by rolling. `w_contact` is the fingertip's rotation increment
    /// (rad, contact frame: x = δψ, y = δθ, z = δφ) and `fingertip_radius_m` its radius. Returns
    /// the displacement of the contact point on the object (object frame, m).
    fn roll<M: Math>(&mut self, w_contact: Vec3, fingertip_radius_m: f32) -> Vec3;
    /// The contact point on the object, object frame, m.
    fn contact_point(&self) -> Vec3;
    /// The outward unit normal at the contact point, object frame.
    fn normal(&self) -> Vec3;
    /// Put the contact point under a fingertip centred at `center_m` (object frame).
    fn place_under<M: Math>(&mut self, center_m: Vec3);
    /// Penetration depth of a fingertip of radius `r` centred at `center_m` (object frame), m.
    /// Positive when the surfaces overlap.
    fn penetration<M: Math>(&self, center_m: Vec3, r: f32) -> f32;
    /// Split an object-frame vector into its component along the normal and its tangential part.
    #[inline]
    fn split(&self, v: Vec3) -> (f32, Vec3) {
        let n = self.normal();
        let vn = v.dot(n);
        (vn, v - n * vn)
    }
    /// The object-frame vector of length `s` along the normal.
    #[inline]
    fn along_normal(&self, s: f32) -> Vec3 {
        self.normal() * s
    }
}

/// The plane z = 0 of the object frame, normal +z. The contact frame is the object frame
/// translated to the contact point, so no frame conversion is ever computed.
///
/// The contact point is a running sum of tiny steps (6 µm per step at 10 kHz on the paper's
/// scene) onto a position of centimetres, where one f32 ulp is ~1 nm: plain f32 summation lost
/// 1.3 µm over the paper's 1 s at 10 kHz and 3.4 µm at 20 kHz. The sum is therefore compensated
/// (Kahan): `carry` holds the low-order part each addition rounded away.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Plane {
    /// Contact point on the plane, object frame, m (z is always 0).
    pub point: Vec3,
    /// Kahan compensation of `point.x`, `point.y`, m.
    carry: [f32; 2],
}

impl Plane {
    /// A plane touched at `point` (object frame, m; z is ignored).
    pub fn at(point: Vec3) -> Plane {
        Plane {
            point: Vec3::new(point.x, point.y, 0.0),
            carry: [0.0; 2],
        }
    }
}

/// Kahan summation: `sum += x`, keeping the rounding error in `carry`. Rust does not reassociate
/// floating-point arithmetic, so the compensation survives optimisation.
#[inline]
fn kahan_add(sum: &mut f32, carry: &mut f32, x: f32) {
    let y = x - *carry;
    let t = *sum + y;
    *carry = (t - *sum) - y;
    *sum = t;
}

impl Surface for Plane {
    #[inline]
    fn curvature(&self) -> f32 {
        0.0
    }
    #[inline]
    fn to_contact_frame(&self, dq_object: Quat) -> Quat {
        dq_object
    }
    #[inline]
    fn contact_to_object(&self, v_contact: Vec3) -> Vec3 {
        v_contact
    }
    /// Eqs. (2)-(3) for k_γ = 1/ρ: the contact point moves by ρ·(δθ, −δψ). For the rotation vector
    /// of a constant-angular-velocity step this is the exact sphere-on-plane rolling displacement.
    #[inline]
    fn roll<M: Math>(&mut self, w: Vec3, rho: f32) -> Vec3 {
        let d = Vec3::new(rho * w.y, -rho * w.x, 0.0);
        kahan_add(&mut self.point.x, &mut self.carry[0], d.x);
        kahan_add(&mut self.point.y, &mut self.carry[1], d.y);
        d
    }
    #[inline]
    fn contact_point(&self) -> Vec3 {
        self.point
    }
    #[inline]
    fn normal(&self) -> Vec3 {
        Vec3::Z
    }
    #[inline]
    fn place_under<M: Math>(&mut self, c: Vec3) {
        *self = Plane::at(c);
    }
    #[inline]
    fn penetration<M: Math>(&self, c: Vec3, r: f32) -> f32 {
        r - c.z
    }
    /// The normal is +z: no products with 0 and 1 (IEEE arithmetic cannot drop them itself).
    #[inline]
    fn split(&self, v: Vec3) -> (f32, Vec3) {
        (v.z, Vec3::new(v.x, v.y, 0.0))
    }
    #[inline]
    fn along_normal(&self, s: f32) -> Vec3 {
        Vec3::new(0.0, 0.0, s)
    }
}

/// A fixed sphere of radius `radius_m` centred at the object-frame origin (e.g. a large ball the
/// fingertip explores). The contact frame is carried along the surface as the fingertip rolls.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sphere {
    /// Object sphere radius, m.
    pub radius_m: f32,
    /// Contact frame → object frame. Its z axis is the outward normal at the contact point.
    pub frame: Quat,
}

impl Sphere {
    /// Contact at the north pole (normal +z).
    pub fn new(radius_m: f32) -> Sphere {
        Sphere {
            radius_m,
            frame: Quat::IDENTITY,
        }
    }
}

impl Surface for Sphere {
    #[inline]
    fn curvature(&self) -> f32 {
        1.0 / self.radius_m
    }
    #[inline]
    fn to_contact_frame(&self, dq: Quat) -> Quat {
        self.frame.conjugate() * dq * self.frame
    }
    #[inline]
    fn contact_to_object(&self, v: Vec3) -> Vec3 {
        self.frame.rotate(v)
    }
    /// A fingertip of radius r rolling with rotation increment w on a sphere of radius R: the
    /// normal rotates about w by κ·|w|, κ = r/(R + r). Exact for constant angular velocity over the
    /// step (the centre moves on the sphere of radius R + r with velocity r·ω × n); its tangential
    /// part is the paper's arc δs = δξ/k_γ with k_γ = 1/r + 1/R. Here the whole contact frame is
    /// rotated, which keeps its tangent axes transported with the contact.
    fn roll<M: Math>(&mut self, w: Vec3, r: f32) -> Vec3 {
        let before = self.contact_point();
        let kappa = r / (self.radius_m + r);
        let (dq, _) = Quat::from_rotation_vector::<M>(w * kappa);
        // Rotation given in the contact frame: right-multiply.
        let f = self.frame * dq;
        let (f, _) = f.normalized_checked::<M>();
        self.frame = f;
        self.contact_point() - before
    }
    #[inline]
    fn contact_point(&self) -> Vec3 {
        self.normal() * self.radius_m
    }
    #[inline]
    fn normal(&self) -> Vec3 {
        self.frame.rotate(Vec3::Z)
    }
    /// Rotate the contact frame by the shortest arc that brings its normal to the direction of
    /// `c`. A centre at the object's origin (no direction) leaves the frame unchanged.
    fn place_under<M: Math>(&mut self, c: Vec3) {
        let d2 = c.norm_squared();
        if d2.is_nan() || d2 <= 1e-20 || !d2.is_finite() {
            return;
        }
        let target = c * (1.0 / M::sqrt(d2));
        let n = self.normal();
        // Shortest-arc quaternion from n to target: (1 + n·t, n × t), normalised.
        let q = Quat::new(1.0 + n.dot(target), 0.0, 0.0, 0.0);
        let v = n.cross(target);
        let q = Quat::new(q.w, v.x, v.y, v.z);
        let (q, flags) = q.normalized_checked::<M>();
        if flags.is_empty() || flags == crate::flags::Flags::NON_UNIT_QUAT {
            let (f, _) = (q * self.frame).normalized_checked::<M>();
            self.frame = f;
        }
    }
    #[inline]
    fn penetration<M: Math>(&self, c: Vec3, r: f32) -> f32 {
        self.radius_m + r - c.norm::<M>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Libm;

    /// 100 000 steps of 1e-7 m onto 0.01 m. Near 0.01 m an f32 ulp is 9.3e-10 m, so each plain
    /// addition of 1e-7 m (107.4 ulps) rounds the same way by ~0.4 ulp: a bias that sums to
    /// ~4e-5 m over the run. Kahan keeps the sum within a few ulps (bound 4e-9 m).
    #[test]
    fn plane_accumulates_without_rounding_drift() {
        let mut p = Plane::at(Vec3::new(0.01, -0.02, 0.0));
        let w = Vec3::new(-1e-5 / 3.0, 1e-5 / 3.0, 0.0);
        for _ in 0..100_000 {
            p.roll::<Libm>(w, 0.03);
        }
        // Exact: 0.01 + 1e5·1e-7 = 0.02, −0.02 + 0.01 = −0.01 (1e-5/3·0.03 = 1e-7 per step).
        assert!((p.point.x as f64 - 0.02).abs() < 4e-9, "{}", p.point.x);
        assert!((p.point.y as f64 + 0.01).abs() < 4e-9, "{}", p.point.y);
    }

    #[test]
    fn plane_roll_is_rho_times_wy_minus_wx() {
        let mut p = Plane::default();
        p.roll::<Libm>(Vec3::new(0.03, 0.02, 0.05), 0.01);
        assert!((p.point.x - 0.0002).abs() < 1e-9 && (p.point.y + 0.0003).abs() < 1e-9);
        assert_eq!(p.point.z, 0.0);
    }

    /// A fingertip (r) rolled about a fixed tangent axis on a sphere (R): the contact point travels
    /// along a great circle by an arc R·κ·angle, κ = r/(R + r), i.e. angle/k_γ with k_γ = 1/r + 1/R.
    #[test]
    fn sphere_roll_moves_the_contact_by_the_paper_arc() {
        let (r, big) = (0.01f32, 0.1f32);
        let mut s = Sphere::new(big);
        let steps = 1000;
        let w = Vec3::new(0.0, 0.001, 0.0); // about y: contact moves towards +x
        for _ in 0..steps {
            s.roll::<Libm>(w, r);
        }
        let total = 0.001 * steps as f32;
        let k_gamma = 1.0 / r + 1.0 / big;
        let arc = total / k_gamma;
        let n = s.normal();
        let got_arc = big * libm::atan2f(n.x, n.z);
        // f32 accumulation over 1000 quaternion products: ~1000·6e-8 relative ≈ 6e-5 of the arc.
        assert!((got_arc - arc).abs() < 1e-4 * arc, "arc {got_arc} vs {arc}");
        assert!(n.y.abs() < 1e-6);
    }

    #[test]
    fn penetration_and_placement() {
        let p = Plane::default();
        assert!((p.penetration::<Libm>(Vec3::new(1.0, 2.0, 0.009), 0.01) - 0.001).abs() < 1e-7);
        let mut s = Sphere::new(0.1);
        s.place_under::<Libm>(Vec3::new(0.0, 0.11, 0.0));
        assert!((s.normal() - Vec3::Y).norm_squared() < 1e-10);
        // R + r − |c| = 0.1 + 0.01 − 0.105 = +0.005 m (overlapping): two-sided, so a sign error fails.
        let pen = s.penetration::<Libm>(Vec3::new(0.0, 0.105, 0.0), 0.01);
        assert!((pen - 0.005).abs() < 1e-7, "penetration {pen}");
        s.place_under::<Libm>(Vec3::ZERO);
        assert!(
            (s.normal() - Vec3::Y).norm_squared() < 1e-10,
            "no direction: unchanged"
        );
    }
}
