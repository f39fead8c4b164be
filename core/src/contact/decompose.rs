//! Decomposition of a relative rotation increment into (δφ about z, δθ about y, δψ about x).
//!
//! The increment is expressed in the **contact frame**: z is the contact normal, x and y span the
//! tangent plane. δφ is the spin about the normal (drives the torsional torque, eq. 1); δθ and δψ are
//! the tilts about y and x (drive rolling, eqs. 2-3). Angles are radians, right-hand rule.
//!
//! Three methods, selectable at run time with [`Method`]:
//!
//! | method | what it computes | fails where |
//! | --- | --- | --- |
//! | [`Method::PaperVerbatim`] | eqs. (5)-(7) exactly as printed | sin δθ = 0 (δθ = 0 ± kπ): every pure spin, no motion at all; and its φ, ψ are *direction* angles, so a tiny tilt about y gives δφ ≈ π/2 (a large spurious spin) |
//! | [`Method::Rpy`] | Z-Y-X roll-pitch-yaw: R = Rz(δφ)·Ry(δθ)·Rx(δψ) | pole at δθ = ±π/2 (never reached by a per-step increment at kHz rates; guarded and flagged) |
//! | [`Method::Exact`] | rotation vector (log map) w: (δψ, δθ, δφ) = (w_x, w_y, w_z) | nowhere on [0, π] |
//!
//! The rotation vector is the right quantity for rolling: with the angular velocity constant between
//! two samples, the sphere-on-plane contact moves by exactly ρ·(w_y, −w_x). Z-Y-X angles differ from it
//! at second order (terms like δφ·δθ/2), which accumulates over many steps.

use crate::flags::Flags;
use crate::math::quat::Quat;
use crate::math::rot3::Rot3;
use crate::math::Math;

/// Which decomposition to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Method {
    /// The paper's eqs. (5)-(7) as printed (a Z-Y-Z-style split). Kept to document its failure.
    PaperVerbatim,
    /// Z-Y-X roll-pitch-yaw angles, as the paper's text describes.
    Rpy,
    /// The rotation vector of the increment (log map).
    Exact,
}

impl Method {
    /// All methods, in a stable order (for tables and sweeps).
    pub const ALL: [Method; 3] = [Method::PaperVerbatim, Method::Rpy, Method::Exact];

    /// The name used on the command line and in files.
    pub const fn name(self) -> &'static str {
        match self {
            Method::PaperVerbatim => "paper-verbatim",
            Method::Rpy => "rpy",
            Method::Exact => "exact",
        }
    }

    /// Parse a name as produced by [`Method::name`].
    pub fn from_name(s: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == s)
    }
}

/// The three angles of a rotation increment, radians, in the contact frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Angles {
    /// δφ: spin about z, the contact normal.
    pub phi: f32,
    /// δθ: about y.
    pub theta: f32,
    /// δψ: about x.
    pub psi: f32,
}

impl Angles {
    /// No rotation: all three angles zero.
    pub const ZERO: Angles = Angles {
        phi: 0.0,
        theta: 0.0,
        psi: 0.0,
    };
}

/// Below this value of sin δθ = √(r13² + r23²) the paper's eqs. (6)-(7) divide by (numerically) zero.
/// 1e-6 is about 8 ulps of 1.0 in f32: smaller values are indistinguishable from the rounding noise
/// of a pure spin, so the direction angles they would produce are meaningless.
pub const PAPER_SINGULAR_SIN: f32 = 1.0e-6;

/// The RPY pole guard: when cos δθ = √(r11² + r21²) is below this, δφ and δψ are no longer separable
/// (their error grows like ε_f32/cos δθ ≈ 1e-3 rad here), so the pole branch is used and flagged.
pub const RPY_POLE_COS: f32 = 1.0e-4;

/// Decompose the unit-quaternion increment `dq` (contact frame) with `method`.
///
/// `dq` must be finite; a non-finite `dq` returns zero angles and [`Flags::NON_FINITE_INPUT`]. The
/// caller normalises (see [`Quat::normalized_checked`]); a finite `dq` so far from unit that the
/// angles would overflow returns zero angles and [`Flags::NON_UNIT_QUAT`].
#[must_use]
pub fn decompose<M: Math>(method: Method, dq: Quat) -> (Angles, Flags) {
    if !dq.is_finite() {
        return (Angles::ZERO, Flags::NON_FINITE_INPUT);
    }
    let (a, f) = match method {
        Method::PaperVerbatim => paper_verbatim::<M>(&Rot3::from_quat(dq)),
        Method::Rpy => rpy::<M>(&Rot3::from_quat(dq)),
        Method::Exact => (exact::<M>(dq), Flags::NONE),
    };
    // A finite but far-from-unit dq (the caller skipped the normalisation) can overflow the
    // matrix entries to ±inf and the angles to NaN: zero angles and a flag instead.
    if a.phi.is_finite() && a.theta.is_finite() && a.psi.is_finite() {
        (a, f)
    } else {
        (Angles::ZERO, f | Flags::NON_UNIT_QUAT)
    }
}

/// Eqs. (5)-(7) exactly as printed:
///
/// δθ = atan2(√(r13² + r23²), r33), δψ = atan2(r31/sin δθ, r32/sin δθ),
/// δφ = atan2(r13/sin δθ, −r23/sin δθ).
///
/// At sin δθ < [`PAPER_SINGULAR_SIN`] the divisions are undefined: returns zero angles and
/// [`Flags::SINGULAR`] instead of NaN.
#[must_use]
pub fn paper_verbatim<M: Math>(r: &Rot3) -> (Angles, Flags) {
    let m = &r.m;
    let (r13, r23, r33, r31, r32) = (m[0][2], m[1][2], m[2][2], m[2][0], m[2][1]);
    let s = M::sqrt(r13 * r13 + r23 * r23);
    if s < PAPER_SINGULAR_SIN || !s.is_finite() {
        return (Angles::ZERO, Flags::SINGULAR);
    }
    let theta = M::atan2(s, r33);
    // sin δθ equals s here (δθ in [0, π], so its sine is non-negative).
    let psi = M::atan2(r31 / s, r32 / s);
    let phi = M::atan2(r13 / s, -r23 / s);
    (Angles { phi, theta, psi }, Flags::NONE)
}

/// Z-Y-X roll-pitch-yaw: R = Rz(δφ)·Ry(δθ)·Rx(δψ), δθ ∈ [−π/2, π/2].
///
/// δθ = atan2(−r31, √(r11² + r21²)), δφ = atan2(r21, r11), δψ = atan2(r32, r33).
/// At the pole (cos δθ < [`RPY_POLE_COS`]) only δφ − δψ (or δφ + δψ) is defined: returns δφ = 0,
/// δψ = atan2(−r23, r22), and [`Flags::GIMBAL_LOCK`].
#[must_use]
pub fn rpy<M: Math>(r: &Rot3) -> (Angles, Flags) {
    let m = &r.m;
    let c = M::sqrt(m[0][0] * m[0][0] + m[1][0] * m[1][0]);
    let theta = M::atan2(-m[2][0], c);
    if c < RPY_POLE_COS {
        let psi = M::atan2(-m[1][2], m[1][1]);
        return (
            Angles {
                phi: 0.0,
                theta,
                psi,
            },
            Flags::GIMBAL_LOCK,
        );
    }
    let phi = M::atan2(m[1][0], m[0][0]);
    let psi = M::atan2(m[2][1], m[2][2]);
    (Angles { phi, theta, psi }, Flags::NONE)
}

/// The rotation vector w = log(dq): (δψ, δθ, δφ) = (w_x, w_y, w_z). Well conditioned on [0, π].
#[inline]
pub fn exact<M: Math>(dq: Quat) -> Angles {
    let w = dq.to_rotation_vector::<M>();
    Angles {
        phi: w.z,
        theta: w.y,
        psi: w.x,
    }
}

#[cfg(test)]
mod tests;
