//! The object surface the fingertip rolls on. Chosen by type (static dispatch), so a scene pays only
//! for its own surface: [`Plane`], [`Sphere`], [`Bowl`] (the fingertip inside a spherical shell)
//! and [`Cylinder`].
//!
//! Frames (the crate's frames table, [`crate`]): the object frame `O` is fixed to the object; the
//! contact frame `C` has its origin at the contact point, z along the normal pointing towards the
//! fingertip, x and y tangent.
//!
//! Rolling (no slip, fingertip sphere of radius r): with the fingertip's angular velocity ω constant
//! in the object frame over a step (rotation vector w = ω·T), the fingertip centre c moves with
//! ċ = r·ω × n and stays on the surface offset by r. Each surface integrates this in closed form
//! (see its [`Surface::roll`]). Every rolling state is a fixed-point sum ([`crate::math::fixed::Fixed`])
//! wherever the surface allows it, so a zero increment moves nothing and a step back by the exact
//! negative increment returns the contact bit for bit (see each type for what is exact).

mod cylinder;
mod spherical;
#[cfg(test)]
mod tests;

pub use cylinder::Cylinder;
pub use spherical::{Bowl, Sphere};

use crate::math::fixed::Fixed;
use crate::math::vec3::Vec3;
use crate::math::Math;

/// An object surface with a moving contact frame.
pub trait Surface: Copy + core::fmt::Debug {
    /// Signed normal curvature of the object surface across the rolling direction of largest
    /// curvature, 1/m: plane 0, sphere 1/R, bowl −1/R (concave), cylinder 1/R (across its axis).
    fn curvature(&self) -> f32;
    /// Express an object-frame vector in the contact frame.
    fn to_contact(&self, v_object: Vec3) -> Vec3;
    /// Express an object-frame vector in the contact frame midway through the last
    /// [`Surface::roll`] (symmetric in the step's two ends, so a step back gives the exact negative
    /// of the step forward). Plane: the contact frame itself.
    #[inline]
    fn to_step_contact<M: Math>(&self, v_object: Vec3) -> Vec3 {
        self.to_contact(v_object)
    }
    /// Map a contact-frame vector to the object frame.
    fn contact_to_object(&self, v_contact: Vec3) -> Vec3;
    /// Move the contact by rolling. `w_object` is the fingertip's rotation vector over the step
    /// (rad, object frame; constant angular velocity over the step) and `fingertip_radius_m` its
    /// radius r. Returns the displacement of the contact point on the object (object frame, m).
    fn roll<M: Math>(&mut self, w_object: Vec3, fingertip_radius_m: f32) -> Vec3;
    /// The contact point on the object, object frame, m.
    fn contact_point(&self) -> Vec3;
    /// The unit normal at the contact point, towards the fingertip, object frame.
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
    /// The force `f_n`·`normal` + `f_t` (N, object frame) for a tangential `f_t` (one of
    /// [`Surface::split`]'s tangential parts) and the unit `normal` this surface had when both
    /// were taken (a restart may have moved the contact since).
    #[inline]
    fn normal_plus_tangential(&self, normal: Vec3, f_n: f32, f_t: Vec3) -> Vec3 {
        normal * f_n + f_t
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
/// The contact point is a fixed-point sum of the rolling steps ([`Fixed`], 2⁻⁴⁴ m): a zero step
/// moves nothing and any path retraced with the negated steps returns bit for bit. (An f32 sum,
/// even Kahan-compensated, walked 3.7 µm in 10 s at 10 kHz of identical samples: `host-sim creep`.)
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Plane {
    /// Contact point on the plane, object frame, m (z is always 0). Read-only: a cache of `sum`.
    pub point: Vec3,
    /// The contact point's x, y as fixed-point sums.
    sum: [Fixed; 2],
}

impl Plane {
    /// A plane touched at `point` (object frame, m; z is ignored).
    pub fn at(point: Vec3) -> Plane {
        let sum = [Fixed::from_f32(point.x), Fixed::from_f32(point.y)];
        Plane {
            point: Vec3::new(sum[0].to_f32(), sum[1].to_f32(), 0.0),
            sum,
        }
    }
}

impl Surface for Plane {
    #[inline]
    fn curvature(&self) -> f32 {
        0.0
    }
    #[inline]
    fn to_contact(&self, v: Vec3) -> Vec3 {
        v
    }
    #[inline]
    fn contact_to_object(&self, v_contact: Vec3) -> Vec3 {
        v_contact
    }
    /// Eqs. (2)-(3) for k_γ = 1/r: the contact point moves by r·(w_y, −w_x). For the rotation
    /// vector of a constant-angular-velocity step this is the exact sphere-on-plane rolling
    /// displacement.
    #[inline]
    fn roll<M: Math>(&mut self, w: Vec3, rho: f32) -> Vec3 {
        let d = Vec3::new(rho * w.y, -rho * w.x, 0.0);
        self.sum[0].add_f32(d.x);
        self.sum[1].add_f32(d.y);
        self.point = Vec3::new(self.sum[0].to_f32(), self.sum[1].to_f32(), 0.0);
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
    /// The normal is always +z and a tangential part has z = 0: (f_t.x, f_t.y, f_n), with no
    /// products with 0 and 1 and no sums with 0 (a zero component of `f_t` keeps its sign).
    #[inline]
    fn normal_plus_tangential(&self, _normal: Vec3, f_n: f32, f_t: Vec3) -> Vec3 {
        Vec3::new(f_t.x, f_t.y, f_n)
    }
}
