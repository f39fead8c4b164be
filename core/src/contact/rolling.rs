//! Rolling of the fingertip sphere on a surface (Algorithm 1, eqs. 2-3).
//!
//! Each step takes the fingertip orientation sample q (fingertip frame → object frame), forms the
//! increment dq = q ⊗ q_prev* (object frame), decomposes it with the chosen [`Method`], and moves
//! the contact point on both surfaces:
//!
//! - on the object: by the surface's rolling update (plane: r·(δθ, −δψ); curved surfaces: their
//!   closed forms, see [`Surface::roll`]). This equals eq. (2)-(3): direction β = atan2(δθ, δψ) and
//!   length δs = δξ/k_γ, since δs·(sin β, −cos β) = (δθ, −δψ)/k_γ; we skip the atan2/sin/cos.
//! - on the fingertip (fingertip frame): the geometric point q*·(−r·n), for every method.
//!
//! No creep at rest. The increment is computed so that it is exactly antisymmetric in the two
//! samples ([`increment`]): identical samples give exactly zero, and the step back from q to q_prev
//! gives bit for bit the negative of the step forward. The exact method's rotation vector is odd
//! in the increment's vector part; the Euler methods decompose the increment in a canonical sign
//! (see [`Rolling::step`]). The surfaces sum the steps in fixed point, and the spin spring too
//! ([`crate::contact::spin`]), so a fingertip returning to an earlier sample along the same samples returns
//! the contact points and the spin exactly (on curved surfaces, see each surface for what is exact).
//!
//! Before this (Hamilton product and f32 sums) a fingertip held at one tilted orientation walked its
//! contact point 3.7 µm in 10 s at 10 kHz and one dithering between two wrist counts 1.9 µm
//! (`host-sim creep`).

use crate::contact::decompose::{decompose, Angles, Method};
use crate::contact::surface::Surface;
use crate::flags::Flags;
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Math;

/// The relative rotation a ⊗ b* (Hamilton), evaluated so that it is exactly antisymmetric: the
/// scalar part is symmetric in a and b and the vector part odd (each component is a sum of
/// differences of products, u − v with u, v swapped by exchanging a and b, and f32 rounding is
/// odd: fl(v − u) = −fl(u − v)). So `increment(a, a)` has a zero vector part exactly and
/// `increment(b, a)` is the exact conjugate of `increment(a, b)`.
#[inline(always)]
pub fn increment(a: Quat, b: Quat) -> Quat {
    Quat::new(
        (a.w * b.w + a.x * b.x) + (a.y * b.y + a.z * b.z),
        (a.x * b.w - a.w * b.x) + (a.z * b.y - a.y * b.z),
        (a.y * b.w - a.w * b.y) + (a.x * b.z - a.z * b.x),
        (a.z * b.w - a.w * b.z) + (a.y * b.x - a.x * b.y),
    )
}

/// The canonical sign of a rotation increment's vector part: true when its first non-zero
/// component (x, then y, then z) is negative. The Euler methods decompose the canonical one of
/// dq and dq* and negate, so their angles are exactly odd too.
#[inline]
fn negative_canonical(v: Vec3) -> bool {
    if v.x != 0.0 {
        v.x < 0.0
    } else if v.y != 0.0 {
        v.y < 0.0
    } else {
        v.z < 0.0
    }
}

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
    pub(crate) surface: S,
    /// Fingertip sphere radius ρ, m.
    pub(crate) radius_m: f32,
    /// The previous orientation sample (fingertip → object), unit.
    pub(crate) q_prev: Quat,
    /// Decomposition method.
    pub(crate) method: Method,
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
        Rolling {
            surface,
            radius_m,
            q_prev: q0,
            method,
        }
    }

    /// The object surface, with the contact point on it.
    #[must_use]
    pub fn surface(&self) -> &S {
        &self.surface
    }

    /// Fingertip sphere radius ρ, m.
    #[must_use]
    pub fn radius_m(&self) -> f32 {
        self.radius_m
    }

    /// The previous orientation sample (fingertip → object), unit.
    #[must_use]
    pub fn q_prev(&self) -> Quat {
        self.q_prev
    }

    /// The decomposition method.
    #[must_use]
    pub fn method(&self) -> Method {
        self.method
    }

    /// The contact point on the fingertip, fingertip frame, m (|p| = ρ): q*·(−ρ·n), computed here
    /// from the last orientation (so a control tick that does not need it does not pay for it).
    ///
    /// The Euler methods used to dead-reckon this point (the paper's "same arc on the fingertip");
    /// a dead-reckoned sum cannot return exactly when the fingertip returns, and the geometric
    /// point is what it approximates.
    pub fn finger_point(&self) -> Vec3 {
        // q_prev is within 1e-3 of unit norm but not normalised (see `step`).
        let (q, _) = self.q_prev.normalized_checked::<crate::math::Fast>();
        q.conjugate().rotate(self.surface.normal() * -self.radius_m)
    }

    /// Restart the contact at orientation `q` (after a break or a slide).
    pub fn restart(&mut self, q: Quat) {
        self.q_prev = q;
    }

    /// The Euler methods' angles of the object-frame increment `dq`: decomposed in the contact
    /// frame, in the canonical sign (see [`negative_canonical`]).
    #[must_use]
    fn euler_angles<M: Math>(&self, dq: Quat) -> (Angles, Flags) {
        let v = dq.vector();
        let neg = negative_canonical(v);
        let v = if neg { -v } else { v };
        let vc = self.surface.to_contact(v);
        let (a, f) = decompose::<M>(self.method, Quat::new(dq.w, vc.x, vc.y, vc.z));
        if neg {
            (
                Angles {
                    phi: -a.phi,
                    theta: -a.theta,
                    psi: -a.psi,
                },
                f,
            )
        } else {
            (a, f)
        }
    }

    /// One step with the new orientation sample `q` (fingertip → object; normalised here).
    ///
    /// Bad samples (non-finite, zero) leave the state unchanged and are flagged; a sample off unit
    /// norm by more than 1e-3 is normalised, used and flagged. A failed decomposition (paper's
    /// singularity) moves nothing but still advances `q_prev`, and is flagged.
    #[inline(always)]
    pub fn step<M: Math>(&mut self, q: Quat) -> RollStep {
        self.step_parts::<M, true>(q)
    }

    /// [`Rolling::step`] when `ROLL`; otherwise the same increment and angles (in the contact
    /// frame at the contact point) with the contact point left where it is: the spin of a model
    /// without rolling ([`crate::contact::parts::WithSpin`]).
    #[inline(always)]
    pub fn step_parts<M: Math, const ROLL: bool>(&mut self, q: Quat) -> RollStep {
        // The exact method's log map is scale-free: a near-unit sample is used as it is (see
        // `Quat::unit_checked`). The Euler methods build a rotation matrix, which is not.
        // The near-unit sample of the exact method is the common path: it stays in registers,
        // and only the rescaling path goes through `normalized_checked`'s result in memory.
        let (q, qflags) = if self.method == Method::Exact && q.is_near_unit() {
            (q, Flags::NONE)
        } else {
            let (n, f) = q.normalized_checked::<M>();
            (Quat::new(n.w, n.x, n.y, n.z), f)
        };
        if qflags.intersects(Flags::NON_FINITE_INPUT | Flags::ZERO_AXIS) {
            return RollStep {
                flags: qflags,
                ..RollStep::default()
            };
        }
        let dq = increment(q, self.q_prev);
        let (angles, object_disp_m, dflags) = match self.method {
            Method::Exact => {
                // q and q_prev are finite unit quaternions here, so dq is finite: the exact
                // method skips `decompose`'s own finiteness check. The rotation vector is taken
                // in the object frame (odd in dq's vector part), the surface rolls by it, and the
                // angles are its components in the contact frame over the step.
                let w = dq.to_rotation_vector::<M>();
                let (d, wc) = if ROLL {
                    let d = self.surface.roll::<M>(w, self.radius_m);
                    (d, self.surface.to_step_contact::<M>(w))
                } else {
                    (Vec3::ZERO, self.surface.to_contact(w))
                };
                let a = Angles {
                    phi: wc.z,
                    theta: wc.y,
                    psi: wc.x,
                };
                (a, d, Flags::NONE)
            }
            _ => {
                let (a, f) = self.euler_angles::<M>(dq);
                if !ROLL {
                    return self.advance(q, a, Vec3::ZERO, qflags | f);
                }
                let w = self
                    .surface
                    .contact_to_object(Vec3::new(a.psi, a.theta, a.phi));
                (a, self.surface.roll::<M>(w, self.radius_m), f)
            }
        };
        self.advance(q, angles, object_disp_m, qflags | dflags)
    }

    /// Take `q` as the previous sample and report the step.
    #[inline(always)]
    fn advance(&mut self, q: Quat, angles: Angles, object_disp_m: Vec3, flags: Flags) -> RollStep {
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
