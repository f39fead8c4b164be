//! Rolling of the fingertip sphere on a surface (Algorithm 1, eqs. 2-3).
//!
//! Each step takes the fingertip orientation sample q (fingertip frame → object frame), forms the
//! increment dq = q ⊗ q_prev* (object frame), expresses it in the contact frame, decomposes it with
//! the chosen [`Method`], and moves the contact point on both surfaces:
//!
//! - on the object: by the surface's rolling update (plane: ρ·(δθ, −δψ); sphere: rotation of the
//!   contact frame, see [`Surface::roll`]). This equals eq. (2)-(3): direction β = atan2(δθ, δψ) and
//!   length δs = δξ/k_γ, since δs·(sin β, −cos β) = (δθ, −δψ)/k_γ; we skip the atan2/sin/cos.
//! - on the fingertip (fingertip frame): for [`Method::Exact`], the exact geometric point
//!   q*·(−ρ·n); for the Euler methods, the paper's dead reckoning (move by the same arc, mapped with
//!   the orientation at the start of the step, back onto the sphere).

use crate::decompose::{decompose, Angles, Method};
use crate::flags::Flags;
use crate::math::Math;
use crate::quat::Quat;
use crate::surface::Surface;
use crate::vec3::Vec3;

/// Eq. (2)-(3): rolling direction β = atan2(δθ, δψ) (rad, from the contact frame's x axis... i.e.
/// the γ plane is the plane x = 0 rotated by β) and path length δs = √(δθ² + δψ²)/k_γ (m).
pub fn direction_and_length<M: Math>(a: Angles, k_gamma: f32) -> (f32, f32) {
    let xi = M::sqrt(a.theta * a.theta + a.psi * a.psi);
    (M::atan2(a.theta, a.psi), xi / k_gamma)
}

/// Relative curvature k_γ = 1/R₁ + 1/R₂ (1/m) of the fingertip (radius `r`) on a surface of
/// curvature `surface_curvature` (1/R₂; plane 0).
#[inline]
pub fn relative_curvature(r: f32, surface_curvature: f32) -> f32 {
    1.0 / r + surface_curvature
}

/// The rolling state of one contact.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Rolling<S: Surface> {
    /// The object surface and its contact point.
    pub surface: S,
    /// Fingertip sphere radius ρ, m.
    pub radius_m: f32,
    /// The Euler methods' dead-reckoned contact point on the fingertip, fingertip frame, m. Unused
    /// by the exact method, whose point follows from the orientation (see [`Rolling::finger_point`]).
    dead_reckoned: Vec3,
    /// The previous orientation sample (fingertip → object), unit.
    pub q_prev: Quat,
    /// Decomposition method.
    pub method: Method,
}

/// What one rolling step produced.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RollStep {
    /// The decomposed increment (contact frame), rad. Zero when the step failed.
    pub angles: Angles,
    /// Displacement of the contact point on the object this step, object frame, m.
    pub object_disp_m: Vec3,
    /// Flags raised (non-finite/non-unit input, singular decomposition, ...).
    pub flags: Flags,
}

impl<S: Surface> Rolling<S> {
    /// Start a contact with the fingertip at orientation `q0` (assumed unit) touching `surface` at its
    /// current contact point.
    pub fn new(surface: S, radius_m: f32, q0: Quat, method: Method) -> Self {
        let mut r = Rolling {
            surface,
            radius_m,
            dead_reckoned: Vec3::ZERO,
            q_prev: q0,
            method,
        };
        r.dead_reckoned = r.exact_finger_point(q0);
        r
    }

    /// The contact point on the fingertip, fingertip frame, m (|p| = ρ). For the exact method it is
    /// computed here from the last orientation (so a control tick that does not need it does not
    /// pay for it); for the Euler methods it is the dead-reckoned point.
    pub fn finger_point(&self) -> Vec3 {
        match self.method {
            Method::Exact => {
                // q_prev is within 1e-3 of unit norm but not normalised (see `step`).
                let (q, _) = self.q_prev.normalized_checked::<crate::math::Fast>();
                self.exact_finger_point(q)
            }
            Method::Rpy | Method::PaperVerbatim => self.dead_reckoned,
        }
    }

    /// The exact contact point on the fingertip for orientation q: q*·(−ρ·n).
    #[inline]
    fn exact_finger_point(&self, q: Quat) -> Vec3 {
        q.conjugate().rotate(self.surface.normal() * -self.radius_m)
    }

    /// Restart the contact at orientation `q` (after a break or a slide): the contact on the
    /// fingertip is recomputed from the geometry.
    pub fn restart(&mut self, q: Quat) {
        self.q_prev = q;
        self.dead_reckoned = self.exact_finger_point(q);
    }

    /// One step with the new orientation sample `q` (fingertip → object; normalised here).
    ///
    /// Bad samples (non-finite, zero) leave the state unchanged and are flagged; a sample off unit
    /// norm by more than 1e-3 is normalised, used and flagged. A failed decomposition (paper's
    /// singularity) moves nothing but still advances `q_prev`, and is flagged.
    #[inline(always)]
    pub fn step<M: Math>(&mut self, q: Quat) -> RollStep {
        // The exact method's log map is scale-free: a near-unit sample is used as it is (see
        // `Quat::unit_checked`). The Euler methods build a rotation matrix, which is not.
        let (q, qflags) = match self.method {
            Method::Exact => q.unit_checked::<M>(),
            Method::Rpy | Method::PaperVerbatim => q.normalized_checked::<M>(),
        };
        if qflags.intersects(Flags::NON_FINITE_INPUT | Flags::ZERO_AXIS) {
            return RollStep {
                flags: qflags,
                ..RollStep::default()
            };
        }
        let dq = self.surface.to_contact_frame(q * self.q_prev.conjugate());
        // q and q_prev are finite unit quaternions here, so dq is finite: the exact method skips
        // `decompose`'s own finiteness check.
        let (angles, dflags) = match self.method {
            Method::Exact => (crate::decompose::exact::<M>(dq), Flags::NONE),
            m => decompose::<M>(m, dq),
        };
        let flags = qflags | dflags;
        let w = Vec3::new(angles.psi, angles.theta, angles.phi);

        let object_disp_m = self.surface.roll::<M>(w, self.radius_m);

        if self.method != Method::Exact {
            // The same arc on the fingertip, mapped with the start-of-step orientation.
            let k_gamma = relative_curvature(self.radius_m, self.surface.curvature());
            let d_contact = Vec3::new(angles.theta, -angles.psi, 0.0) * (1.0 / k_gamma);
            let d_object = self.surface.contact_to_object(d_contact);
            let p = self.dead_reckoned + self.q_prev.conjugate().rotate(d_object);
            let n = p.norm::<M>();
            self.dead_reckoned = if n > 0.5 * self.radius_m && n.is_finite() {
                p * (self.radius_m / n)
            } else {
                self.exact_finger_point(q)
            };
        }
        self.q_prev = q;
        RollStep {
            angles,
            object_disp_m,
            flags,
        }
    }
}

#[cfg(test)]
mod tests;
