//! Spherical objects: a [`Sphere`] (the fingertip outside it) and a [`Bowl`] (a concave spherical
//! shell, the fingertip inside it), both centred at the object frame's origin.
//!
//! Rolling (fingertip radius r, object radius R, ω constant over the step, w = ω·T): the fingertip
//! centre stays on the sphere of radius R ± r about the origin, and the normal n obeys
//! ṅ = ±κ·ω × n with κ = r/(R + r) outside and κ = r/(R − r) inside (sign − inside: the centre is
//! on the other side of the contact). So over the step n rotates about w by ±κ·|w|: exact for
//! constant ω. The relative curvature of eq. (3) is k_γ = 1/r + 1/R outside and 1/r − 1/R inside;
//! the tangential arc R·κ·|w_t| equals |w_t|/k_γ in both cases.
//!
//! The contact frame (a quaternion, contact → object) is rotated by the same rotation, which
//! transports its tangent axes with the contact.
//!
//! Exactness: a zero rotation vector leaves the frame bit for bit; a step whose rotation vector is
//! the exact negative of the previous one (a fingertip dithering between two samples) restores the
//! previous frame bit for bit (one step is remembered). A longer path retraced returns within f32
//! rounding of the frame products (see the tests), since rotations of a unit vector in finite
//! precision are not exactly invertible.

use super::Surface;
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Math;

/// The state shared by [`Sphere`] and [`Bowl`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
struct SphericalContact {
    /// Contact frame → object frame; its z axis is the normal towards the fingertip.
    frame: Quat,
    /// The frame before the last roll, and that roll's rotation vector (object frame, rad).
    prev_frame: Quat,
    last_w: Vec3,
}

impl SphericalContact {
    const START: SphericalContact = SphericalContact {
        frame: Quat::IDENTITY,
        prev_frame: Quat::IDENTITY,
        last_w: Vec3::ZERO,
    };

    /// Rotate the frame by the object-frame rotation vector `w·k`. A zero `w` is skipped; the
    /// negative of the last `w` restores the frame before it.
    fn rotate<M: Math>(&mut self, w: Vec3, k: f32) {
        if w.x == 0.0 && w.y == 0.0 && w.z == 0.0 {
            return;
        }
        let undo = w.x == -self.last_w.x && w.y == -self.last_w.y && w.z == -self.last_w.z;
        let before = self.frame;
        if undo {
            self.frame = self.prev_frame;
        } else {
            let (dq, _) = Quat::from_rotation_vector::<M>(w * k);
            let (f, _) = (dq * self.frame).normalized_checked::<M>();
            self.frame = f;
        }
        self.prev_frame = before;
        self.last_w = w;
    }

    /// The frame midway through the last roll: the normalised sum of the two ends, symmetric in
    /// them. The end is the start turned by dq = (cos θ/2, u·sin θ/2) (θ the frame's turn in the
    /// step), so a + b = (1 + dq)·a ∝ (cos θ/4, u·sin θ/4)·a, the frame turned by θ/2 along the
    /// step's own path, for any θ < 2π. No sign flip: a flip would take the shorter arc, which for
    /// θ > π (a bowl barely larger than the fingertip turns its frame by r/(R − r) times the
    /// step) is not the path the contact took.
    fn mid_frame<M: Math>(&self) -> Quat {
        let (a, b) = (self.prev_frame, self.frame);
        let m = Quat::new(a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z);
        let (m, _) = m.normalized_checked::<M>();
        m
    }

    fn normal(&self) -> Vec3 {
        self.frame.rotate(Vec3::Z)
    }

    /// Rotate the frame by the shortest arc that brings its normal to `target` (unit).
    fn turn_normal_to<M: Math>(&mut self, target: Vec3) {
        let n = self.normal();
        let v = n.cross(target);
        let q = Quat::new(1.0 + n.dot(target), v.x, v.y, v.z);
        let (q, flags) = q.normalized_checked::<M>();
        if flags.is_empty() || flags == crate::flags::Flags::NON_UNIT_QUAT {
            let (f, _) = (q * self.frame).normalized_checked::<M>();
            self.frame = f;
        }
        self.prev_frame = self.frame;
        self.last_w = Vec3::ZERO;
    }
}

/// The unit direction of `c`, or `None` for a centre at the origin (or non-finite).
fn direction<M: Math>(c: Vec3) -> Option<Vec3> {
    let d2 = c.norm_squared();
    if d2.is_nan() || d2 <= 1e-20 || !d2.is_finite() {
        return None;
    }
    Some(c * (1.0 / M::sqrt(d2)))
}

macro_rules! spherical_common {
    () => {
        #[inline]
        fn to_contact(&self, v: Vec3) -> Vec3 {
            self.c.frame.conjugate().rotate(v)
        }
        #[inline]
        fn to_step_contact<M: Math>(&self, v: Vec3) -> Vec3 {
            self.c.mid_frame::<M>().conjugate().rotate(v)
        }
        #[inline]
        fn contact_to_object(&self, v: Vec3) -> Vec3 {
            self.c.frame.rotate(v)
        }
        #[inline]
        fn normal(&self) -> Vec3 {
            self.c.normal()
        }
    };
}

/// A fixed sphere of radius `radius_m` centred at the object-frame origin; the contact starts at
/// (0, 0, R) with the normal +z.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sphere {
    /// Object sphere radius R, m.
    pub radius_m: f32,
    c: SphericalContact,
}

impl Sphere {
    /// Contact at the north pole (normal +z).
    pub fn new(radius_m: f32) -> Sphere {
        Sphere {
            radius_m,
            c: SphericalContact::START,
        }
    }

    /// Contact frame → object frame.
    pub fn frame(&self) -> Quat {
        self.c.frame
    }
}

impl Surface for Sphere {
    spherical_common!();
    #[inline]
    fn curvature(&self) -> f32 {
        1.0 / self.radius_m
    }
    /// The normal rotates about w by κ·|w|, κ = r/(R + r) (see the module doc).
    fn roll<M: Math>(&mut self, w: Vec3, r: f32) -> Vec3 {
        let before = self.contact_point();
        self.c.rotate::<M>(w, r / (self.radius_m + r));
        self.contact_point() - before
    }
    #[inline]
    fn contact_point(&self) -> Vec3 {
        self.normal() * self.radius_m
    }
    /// Turn the normal towards `c`. A centre at the origin leaves the frame unchanged.
    fn place_under<M: Math>(&mut self, c: Vec3) {
        if let Some(t) = direction::<M>(c) {
            self.c.turn_normal_to::<M>(t);
        }
    }
    #[inline]
    fn penetration<M: Math>(&self, c: Vec3, r: f32) -> f32 {
        self.radius_m + r - c.norm::<M>()
    }
}

/// A concave spherical shell (a bowl) of inner radius `radius_m` centred at the object-frame
/// origin, the fingertip inside it (r < R). The contact starts at (0, 0, −R) with the normal +z
/// (towards the centre, i.e. towards the fingertip).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Bowl {
    /// Inner radius R of the bowl, m (larger than the fingertip's).
    pub radius_m: f32,
    c: SphericalContact,
}

impl Bowl {
    /// Contact at the bottom (0, 0, −R), normal +z.
    pub fn new(radius_m: f32) -> Bowl {
        Bowl {
            radius_m,
            c: SphericalContact::START,
        }
    }

    /// Contact frame → object frame.
    pub fn frame(&self) -> Quat {
        self.c.frame
    }
}

impl Surface for Bowl {
    spherical_common!();
    /// Concave: −1/R.
    #[inline]
    fn curvature(&self) -> f32 {
        -1.0 / self.radius_m
    }
    /// The normal rotates about w by −κ·|w|, κ = r/(R − r) (see the module doc). A fingertip as
    /// large as the bowl (R ≤ r) cannot roll in it: nothing moves.
    fn roll<M: Math>(&mut self, w: Vec3, r: f32) -> Vec3 {
        let gap = self.radius_m - r;
        if gap <= 0.0 {
            return Vec3::ZERO;
        }
        let before = self.contact_point();
        self.c.rotate::<M>(w, -r / gap);
        self.contact_point() - before
    }
    #[inline]
    fn contact_point(&self) -> Vec3 {
        self.normal() * -self.radius_m
    }
    /// Turn the normal towards the centre as seen from the fingertip: n = −c/|c|. A centre at the
    /// origin leaves the frame unchanged.
    fn place_under<M: Math>(&mut self, c: Vec3) {
        if let Some(t) = direction::<M>(c) {
            self.c.turn_normal_to::<M>(-t);
        }
    }
    /// The fingertip overlaps the shell when its centre is farther than R − r from the origin.
    #[inline]
    fn penetration<M: Math>(&self, c: Vec3, r: f32) -> f32 {
        c.norm::<M>() - (self.radius_m - r)
    }
}
