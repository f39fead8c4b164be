//! A fixed cylinder of radius R with its axis along the object frame's x axis through the origin.
//!
//! Contact state: the position x along the axis and the angle α around it, the contact point
//! (x, R·sin α, R·cos α), the normal n = (0, sin α, cos α) (the contact starts at (0, 0, R) with
//! normal +z). Contact frame: x along the axis, y = t = (0, cos α, −sin α), z = n.
//!
//! Rolling (fingertip radius r, ω constant in the object frame over the step, w = ω·T): the centre
//! c = (x, (R + r)·n) moves with ċ = r·ω × n, so α̇ = −r·ω_x/(R + r) (constant) and
//! ẋ = r·(ω_y·cos α − ω_z·sin α). Integrated exactly over the step, with Δα = −r·w_x/(R + r) and
//! α_m the mid-step angle:
//!
//! Δx = r·sinc(Δα/2)·(w_y·cos α_m − w_z·sin α_m),
//!
//! exact for constant ω (no order: a closed form). The relative curvature of eq. (3) depends on the
//! rolling direction β (see [`Cylinder::k_gamma`]).
//!
//! Exactness: x and α are fixed-point sums ([`Fixed`]), Δα is an odd function of w_x, α_m is
//! computed from the integer sum of the step's two ends and Δx is odd in (w_y, w_z): a zero step
//! moves nothing, and any path retraced with the negated steps returns x and α bit for bit.

use super::Surface;
use crate::math::fixed::Fixed;
use crate::math::vec3::Vec3;
use crate::math::Math;

/// A cylinder along the object x axis.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Cylinder {
    /// Cylinder radius R, m.
    pub radius_m: f32,
    /// Position of the contact along the axis, m.
    x: Fixed,
    /// Angle of the contact around the axis, rad (0: on top, normal +z).
    alpha: Fixed,
    /// (sin α, cos α).
    sc: (f32, f32),
    /// (sin α_m, cos α_m) of the last roll (mid-step angle).
    mid_sc: (f32, f32),
    /// Cached contact point, object frame, m.
    point: Vec3,
}

impl Cylinder {
    /// Contact on top, at (0, 0, R), normal +z.
    pub fn new(radius_m: f32) -> Cylinder {
        let mut c = Cylinder {
            radius_m,
            x: Fixed::ZERO,
            alpha: Fixed::ZERO,
            sc: (0.0, 1.0),
            mid_sc: (0.0, 1.0),
            point: Vec3::ZERO,
        };
        c.refresh::<crate::math::Libm>();
        c.mid_sc = c.sc;
        c
    }

    /// The paper's eq. (3) relative curvature for this cylinder: rolling in direction β (eq. 2,
    /// contact moving along (sin β, −cos β) in the contact frame), the cylinder's normal curvature
    /// is cos²β/R (zero along the axis, 1/R across it), so k_γ = 1/r + cos²β/R (1/m). Our update is
    /// the closed form above; it agrees with δs = δξ/k_γ for rolling along (β = ±π/2) and across
    /// (β = 0, π) the axis.
    pub fn k_gamma<M: Math>(&self, r: f32, beta: f32) -> f32 {
        let c = M::cos(beta);
        1.0 / r + c * c / self.radius_m
    }

    /// Angle of the contact around the axis, rad.
    pub fn angle_rad(&self) -> f32 {
        self.alpha.to_f32()
    }

    fn refresh<M: Math>(&mut self) {
        self.sc = M::sin_cos(self.alpha.to_f32());
        let (s, c) = self.sc;
        self.point = Vec3::new(self.x.to_f32(), self.radius_m * s, self.radius_m * c);
    }
}

/// ⌊(a0 + a1)/2⌋ without overflow, symmetric in a0 and a1 (so a step and its reverse share
/// their mid-step angle bit for bit).
#[inline]
fn midpoint(a0: i64, a1: i64) -> i64 {
    (a0 >> 1) + (a1 >> 1) + (a0 & a1 & 1)
}

/// sin(h)/h for h ≥ 0: 1 − h²/6 below 0.01, where the next term, h⁴/120 < 8.4e-11, is below
/// half an ulp of the result (the two-term and three-term series give the same bits there).
fn sinc<M: Math>(h: f32) -> f32 {
    if h < 0.01 {
        1.0 - h * h * (1.0 / 6.0)
    } else {
        M::sin(h) / h
    }
}

impl Surface for Cylinder {
    #[inline]
    fn curvature(&self) -> f32 {
        1.0 / self.radius_m
    }
    #[inline]
    fn to_contact(&self, v: Vec3) -> Vec3 {
        let (s, c) = self.sc;
        Vec3::new(v.x, v.y * c - v.z * s, v.y * s + v.z * c)
    }
    #[inline]
    fn to_step_contact<M: Math>(&self, v: Vec3) -> Vec3 {
        let (s, c) = self.mid_sc;
        Vec3::new(v.x, v.y * c - v.z * s, v.y * s + v.z * c)
    }
    #[inline]
    fn contact_to_object(&self, v: Vec3) -> Vec3 {
        let (s, c) = self.sc;
        Vec3::new(v.x, v.y * c + v.z * s, -v.y * s + v.z * c)
    }
    /// The closed form of the module doc.
    fn roll<M: Math>(&mut self, w: Vec3, r: f32) -> Vec3 {
        if w.x == 0.0 && w.y == 0.0 && w.z == 0.0 {
            self.mid_sc = self.sc;
            return Vec3::ZERO;
        }
        let before = self.point;
        let d_alpha = Fixed::from_f32(-r * w.x / (self.radius_m + r));
        let a0 = self.alpha.0;
        let a1 = a0.saturating_add(d_alpha.0);
        let mid = Fixed(midpoint(a0, a1));
        self.mid_sc = M::sin_cos(mid.to_f32());
        let (sm, cm) = self.mid_sc;
        let half = Fixed(d_alpha.0.saturating_abs()).to_f32() * 0.5;
        let dx = r * sinc::<M>(half) * (w.y * cm - w.z * sm);
        self.x.add_f32(dx);
        self.alpha = Fixed(a1);
        self.refresh::<M>();
        self.point - before
    }
    #[inline]
    fn contact_point(&self) -> Vec3 {
        self.point
    }
    #[inline]
    fn normal(&self) -> Vec3 {
        Vec3::new(0.0, self.sc.0, self.sc.1)
    }
    /// Put the contact under `c`: x = c_x, α = atan2(c_y, c_z). A centre on the axis keeps α.
    fn place_under<M: Math>(&mut self, c: Vec3) {
        if !c.is_finite() {
            return;
        }
        self.x = Fixed::from_f32(c.x);
        if c.y * c.y + c.z * c.z > 1e-20 {
            self.alpha = Fixed::from_f32(M::atan2(c.y, c.z));
        }
        self.refresh::<M>();
        self.mid_sc = self.sc;
    }
    #[inline]
    fn penetration<M: Math>(&self, c: Vec3, r: f32) -> f32 {
        self.radius_m + r - M::sqrt(c.y * c.y + c.z * c.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Libm;

    /// The branch threshold bracketed: below 0.01 the series, from 0.01 on the backend's sine
    /// (told apart with micromath, whose sine differs from the series there).
    #[test]
    fn sinc_switches_to_the_sine_at_0_01() {
        use crate::math::Micromath;
        let h = 0.01f32;
        let below = h.next_down();
        assert_eq!(sinc::<Micromath>(below), 1.0 - below * below * (1.0 / 6.0));
        assert_eq!(sinc::<Micromath>(h), Micromath::sin(h) / h);
        assert_ne!(Micromath::sin(h) / h, 1.0 - h * h * (1.0 / 6.0));
    }

    /// The midpoint is the floor of the exact mean (i128), at the extremes and for odd pairs.
    #[test]
    fn midpoint_is_the_floor_of_the_mean() {
        let vals = [
            i64::MIN,
            i64::MIN + 1,
            -7,
            -2,
            -1,
            0,
            1,
            2,
            3,
            7,
            i64::MAX - 1,
            i64::MAX,
        ];
        for a in vals {
            for b in vals {
                let exact = (i128::from(a) + i128::from(b)).div_euclid(2);
                assert_eq!(i128::from(midpoint(a, b)), exact, "{a} {b}");
                assert_eq!(midpoint(a, b), midpoint(b, a));
            }
        }
    }

    /// At α ≠ 0 a spin about the object's z axis (not the normal) rolls the contact along the
    /// axis: Δx = −r·w_z·sin α (Δα = 0, sinc(0) = 1), and `roll` returns the contact point's
    /// displacement. Measured 0 for α and Δx; bounds from ulp arguments: 1 ulp of 0.5 (6e-8 rad)
    /// and 1 ulp of 4.8e-4 m (5.8e-11 m). Δy and Δz are exactly 0 (Δα = 0).
    #[test]
    fn a_z_rotation_off_the_top_rolls_along_the_axis() {
        let (big, r, a) = (0.05f32, 0.01f32, 0.5f32);
        let mut c = Cylinder::new(big);
        c.place_under::<Libm>(Vec3::new(0.0, libm::sinf(a), libm::cosf(a)) * (big + r));
        assert!((c.angle_rad() - a).abs() <= 6e-8);
        let before = c.contact_point();
        let d = c.roll::<Libm>(Vec3::new(0.0, 0.0, 0.1), r);
        let expected = -r * 0.1 * libm::sinf(a);
        assert!((d.x - expected).abs() <= 5.8e-11, "{d:?} vs {expected}");
        assert_eq!(d, c.contact_point() - before);
        assert_eq!((d.y, d.z), (0.0, 0.0), "{d:?}");
    }

    /// Placing under a centre sets α = atan2(c_y, c_z), back to 0 on top; a centre within
    /// 1e-10 m of the axis (c_y² + c_z² ≤ 1e-20 m²) keeps α. Bracketed with a centre whose
    /// c_y² + c_z² is exactly 1e-20 in f32 and one a float farther. α measured exact; bound 1 ulp
    /// of 0.5 (6e-8 rad), an ulp argument.
    #[test]
    fn place_under_sets_the_angle_except_on_the_axis() {
        let big = 0.05f32;
        let mut c = Cylinder::new(big);
        c.place_under::<Libm>(Vec3::new(0.0, libm::sinf(0.5), libm::cosf(0.5)) * 0.06);
        assert!((c.angle_rad() - 0.5).abs() <= 6e-8);
        c.place_under::<Libm>(Vec3::new(0.001, 0.0, 0.06));
        assert_eq!(c.angle_rad(), 0.0);
        assert_eq!(c.contact_point(), Vec3::new(0.001, 0.0, big));
        let (y, z) = (f32::from_bits(0x2e9b_7dcb), f32::from_bits(0x2e9b_7f5a));
        assert_eq!(y * y + z * z, 1e-20);
        for (z, moves) in [(z, false), (z.next_up(), true)] {
            let mut c = Cylinder::new(big);
            c.place_under::<Libm>(Vec3::new(0.0, libm::sinf(0.5), libm::cosf(0.5)) * 0.06);
            c.place_under::<Libm>(Vec3::new(0.0, y, z));
            let a = c.angle_rad();
            assert_eq!((a - 0.5).abs() > 0.1, moves, "z {z:e}: α {a}");
        }
    }

    /// sinc(h) = sin(h)/h against f64 on both branches (series below 0.01, the division above) and
    /// at 0. Measured worst relative error 7.8e-8 (f32 rounding); bound 2.4e-7.
    #[test]
    fn sinc_matches_sin_over_h() {
        assert_eq!(sinc::<Libm>(0.0), 1.0);
        let mut worst = 0.0f64;
        for i in 1..=400 {
            let h = i as f32 * 1e-4; // 1e-4 .. 0.04: both branches
            let exact = (h as f64).sin() / h as f64;
            worst = worst.max((sinc::<Libm>(h) as f64 / exact - 1.0).abs());
        }
        std::println!("sinc worst relative error {worst:e}");
        assert!(worst < 2.4e-7, "{worst:e}");
    }
}
