//! A free rigid body held by up to two soft fingertips: one control tick of the whole grasp.
//!
//! Each tick, with the body's state at the start of the tick: each fingertip's contact is stepped
//! ([`FingertipContact::step`]), the wrenches on the body are summed with gravity and the external
//! wrench, and the body is advanced by one semi-implicit Euler step ([`RigidBody::step`]). The
//! wrench on each fingertip is returned for the caller's fingertip dynamics (the hand, or a device).

use crate::contact::{ContactParams, Full, ParamError, Parts, Surface, MAX_DT_S, MIN_DT_S};
use crate::flags::Flags;
use crate::grasp::body::{BodyError, BodyParams, BodyState, RigidBody};
use crate::grasp::fingertip_contact::{ContactReport, Fingertip, FingertipContact, Wrench};
use crate::math::vec3::Vec3;
use crate::math::Math;

/// Why a grasp could not be built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GraspError {
    /// The body was rejected.
    Body(BodyError),
    /// A contact's parameters (index 0 or 1) were rejected.
    Contact(usize, ParamError),
    /// The step period is outside [`MIN_DT_S`]..=[`MAX_DT_S`] or not finite.
    Dt,
    /// Gravity is not finite.
    Gravity,
}

impl core::fmt::Display for GraspError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            GraspError::Body(e) => write!(f, "body: {e}"),
            GraspError::Contact(i, e) => write!(f, "contact {i}: {e}"),
            GraspError::Dt => write!(f, "dt_s must be finite and in [{MIN_DT_S}, {MAX_DT_S}] s"),
            GraspError::Gravity => write!(f, "gravity must be finite"),
        }
    }
}

/// Grasp-level conditions raised in a tick (the contacts' and the body's own [`Flags`] are
/// reported beside them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GraspFlags(pub u8);

impl GraspFlags {
    /// Nothing to report.
    pub const NONE: GraspFlags = GraspFlags(0);
    /// The two fingertips overlap each other (centres closer than the sum of their radii, e.g.
    /// both on the same spot): the second is ignored this tick (its contact breaks).
    pub const COINCIDENT_FINGERTIPS: GraspFlags = GraspFlags(1 << 0);

    /// Whether every flag of `o` is raised.
    pub const fn contains(self, o: GraspFlags) -> bool {
        self.0 & o.0 == o.0
    }
}

/// What one grasp tick produced.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GraspStep {
    /// Each contact's report.
    pub contacts: [ContactReport; 2],
    /// The flags of the body step (a non-finite external wrench, an undone overflow) and of both
    /// contact steps, or-ed.
    pub flags: Flags,
    /// Grasp-level conditions.
    pub grasp_flags: GraspFlags,
}

/// A body and two fingertip contacts on its surface `S` (the body's object frame), each contact
/// the model of parts `P` ([`crate::contact::parts`]; the whole model unless named).
#[derive(Clone, Copy, Debug)]
pub struct Grasp<M: Math, S: Surface, P: Parts = Full> {
    /// The held body.
    pub body: RigidBody,
    contacts: [FingertipContact<M, S, P>; 2],
    gravity_m_s2: Vec3,
    dt_s: f32,
}

impl<M: Math, S: Surface> Grasp<M, S, Full> {
    /// A grasp of a body with `body` parameters starting at `state`, its surface `surface` in the
    /// object frame, each fingertip's contact the whole model with `contacts[i]`, gravity
    /// `gravity_m_s2` (world, m/s²), stepped every `dt_s` seconds. [`Grasp::with_parts`] for
    /// contacts of a reduced model.
    pub fn new(
        body: BodyParams,
        state: BodyState,
        surface: S,
        contacts: [ContactParams; 2],
        gravity_m_s2: Vec3,
        dt_s: f32,
    ) -> Result<Self, GraspError> {
        Self::with_parts(body, state, surface, contacts, gravity_m_s2, dt_s)
    }
}

impl<M: Math, S: Surface, P: Parts> Grasp<M, S, P> {
    /// [`Grasp::new`] with each contact the model of parts `P`.
    pub fn with_parts(
        body: BodyParams,
        state: BodyState,
        surface: S,
        contacts: [ContactParams; 2],
        gravity_m_s2: Vec3,
        dt_s: f32,
    ) -> Result<Self, GraspError> {
        if !(dt_s.is_finite() && (MIN_DT_S..=MAX_DT_S).contains(&dt_s)) {
            return Err(GraspError::Dt);
        }
        if !gravity_m_s2.is_finite() {
            return Err(GraspError::Gravity);
        }
        let body = RigidBody::new(body, state).map_err(GraspError::Body)?;
        let c0 = FingertipContact::with_parts(contacts[0], surface, dt_s)
            .map_err(|e| GraspError::Contact(0, e))?;
        let c1 = FingertipContact::with_parts(contacts[1], surface, dt_s)
            .map_err(|e| GraspError::Contact(1, e))?;
        Ok(Grasp {
            body,
            contacts: [c0, c1],
            gravity_m_s2,
            dt_s,
        })
    }

    /// The contacts.
    pub fn contacts(&self) -> &[FingertipContact<M, S, P>; 2] {
        &self.contacts
    }

    /// The step period, s.
    pub fn dt_s(&self) -> f32 {
        self.dt_s
    }

    /// One tick: the fingertips `tips` (world frame; `None` for a finger not there) and the
    /// external wrench `external` on the body (world frame, moment about the centre of mass).
    /// Never panics; bad input gives the safe results described on [`RigidBody::step`],
    /// [`FingertipContact::step`] and [`GraspFlags`].
    pub fn step(&mut self, tips: [Option<Fingertip>; 2], external: Wrench) -> GraspStep {
        let mut grasp_flags = GraspFlags::NONE;
        let mut tips = tips;
        if let [Some(a), Some(b)] = &tips {
            let r = self.contacts[0].model().params().fingertip_radius_m
                + self.contacts[1].model().params().fingertip_radius_m;
            // False for NaN: a non-finite tip goes on to its contact model, which flags it.
            if (a.pos_m - b.pos_m).norm_squared() < r * r {
                grasp_flags = GraspFlags(grasp_flags.0 | GraspFlags::COINCIDENT_FINGERTIPS.0);
                tips[1] = None;
            }
        }
        let state = self.body.state;
        let r0 = self.contacts[0].step(&state, tips[0].as_ref());
        let r1 = self.contacts[1].step(&state, tips[1].as_ref());
        let m = self.body.params().mass_kg;
        let force = self.gravity_m_s2 * m + r0.on_body.force_n + r1.on_body.force_n;
        let torque = r0.on_body.torque_nm + r1.on_body.torque_nm;
        let (ext_f, ext_t, ext_flags) =
            if external.force_n.is_finite() && external.torque_nm.is_finite() {
                (external.force_n, external.torque_nm, Flags::NONE)
            } else {
                (Vec3::ZERO, Vec3::ZERO, Flags::NON_FINITE_INPUT)
            };
        let body_flags = self
            .body
            .step::<M>(force + ext_f, torque + ext_t, self.dt_s);
        GraspStep {
            contacts: [r0, r1],
            flags: body_flags | ext_flags | r0.output.flags | r1.output.flags,
            grasp_flags,
        }
    }
}
