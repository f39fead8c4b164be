//! The contact-stage seam: what the [`Controller`](super::Controller) (and so the
//! [`Pipeline`](crate::control::pipeline::Pipeline)) calls between the kinematics and the Jacobian. One
//! control law runs either stage:
//!
//! - a fixed surface: [`ContactModel`] on a surface chosen at build time (the firmware's plane).
//!   Every [`Surface`] is an [`Environment`] whose stage is that contact model; the trait's methods are
//!   `#[inline]` forwards, so the firmware's tick runs the same instructions as before;
//! - the application's local model: [`LocalModelStage`](crate::control::local_model::LocalModelStage),
//!   the local-model renderer and the communication watchdog.
//!
//! Frames: the stage receives the probe in the environment's object frame (the base frame translated by
//! the configuration's `object_origin_m`) and returns its force, torque and contact point in that
//! frame.

use crate::contact::params::{ContactParams, ParamsChange};
use crate::contact::parts::Parts;
use crate::contact::state::ContactState;
use crate::contact::surface::Surface;
use crate::contact::{ContactInput, ContactModel, ContactOutput};
use crate::control::command::CommandError;
use crate::control::local_model::LocalModelSpec;
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Math;
use crate::validate::{Checked, ParamError};

/// A contact stage: one step per control tick, plus the commands it understands. The commands
/// about the local model and the link answer [`CommandError::Unsupported`] on a fixed surface.
pub trait ContactStage: Copy + core::fmt::Debug {
    /// One control tick. Never panics, never returns a non-finite force for finite input.
    fn step(&mut self, input: &ContactInput) -> ContactOutput;
    /// Break the contact and forget the motion history (after a fault or a re-homing); the
    /// surface (or the local model in force) stays.
    fn restart(&mut self);
    /// New contact parameters (checked where they arrived): the contact restarts, or carries on
    /// when only the material changed and the stage blends it ([`ParamsChange`]); refused ones
    /// change nothing.
    fn set_contact_params(
        &mut self,
        p: &Checked<ContactParams>,
    ) -> Result<ParamsChange, ParamError>;
    /// The contact parameters in force.
    fn params(&self) -> &ContactParams;
    /// Contact state after the last step.
    fn state(&self) -> ContactState;
    /// Contact point on the object after the last step, object frame, m.
    fn contact_point_m(&self) -> Vec3;
    /// Sequence number of the local model in force (0 on a fixed surface).
    #[inline]
    fn model_seq(&self) -> u32 {
        0
    }
    /// Queue a new local model (checked where it arrived) for the next tick boundary.
    #[inline]
    fn set_local_model(&mut self, _spec: &Checked<LocalModelSpec>) -> Result<(), CommandError> {
        Err(CommandError::Unsupported)
    }
    /// A local model was refused before it reached the stage (its own checks): the stage's
    /// refusal flag, as if it had refused it.
    #[inline]
    fn local_model_refused(&mut self) {}
    /// Set the communication watchdog's timeout, s (0: off).
    #[inline]
    fn set_watchdog(&mut self, _timeout_s: f32) -> Result<(), CommandError> {
        Err(CommandError::Unsupported)
    }
    /// The communication watchdog's timeout in force, s (0: off or none).
    #[inline]
    fn watchdog_s(&self) -> f32 {
        0.0
    }
    /// A valid message arrived on the link (feeds the watchdog).
    #[inline]
    fn note_link_activity(&mut self) {}
    /// The operator armed: a latched communication timeout clears if the link is alive.
    #[inline]
    fn rearm(&mut self) {}
}

/// What a controller is built with: the virtual environment the device renders (a fixed
/// surface, or the application's local models), which makes its contact stage.
pub trait Environment: Copy + core::fmt::Debug {
    /// Whether the passivity stage ([`crate::control::controller::passivity`]) adds its damper on this
    /// environment by default (false: it observes only). Its energy balance is taken in the base
    /// frame, where a fixed surface is passive; an environment whose objects move is an active
    /// environment there, and the damper would answer the model's own motion with force steps.
    const PASSIVITY_DAMPS: bool = true;
    /// The stage this environment runs with math backend `M`.
    type Stage<M: Math>: ContactStage;
    /// The stage for contact parameters `contact`, stepped every `dt_s` seconds.
    fn stage<M: Math>(
        &self,
        contact: ContactParams,
        dt_s: f32,
    ) -> Result<Self::Stage<M>, ParamError>;
}

/// A fixed surface is an environment: the contact model on it.
impl<S: Surface> Environment for S {
    type Stage<M: Math> = ContactModel<M, S>;
    #[inline]
    fn stage<M: Math>(
        &self,
        contact: ContactParams,
        dt_s: f32,
    ) -> Result<Self::Stage<M>, ParamError> {
        ContactModel::new(contact, *self, Quat::IDENTITY, dt_s)
    }
}

/// A fixed surface `S` rendered with a reduced contact model `P` (the parts a scene names, see
/// [`crate::contact::parts`]); a bare surface renders the whole model.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WithParts<S: Surface, P: Parts> {
    /// The surface.
    pub surface: S,
    _p: core::marker::PhantomData<P>,
}

impl<S: Surface, P: Parts> WithParts<S, P> {
    /// `surface` rendered with the parts `P`.
    pub fn new(surface: S) -> Self {
        WithParts {
            surface,
            _p: core::marker::PhantomData,
        }
    }
}

impl<S: Surface, P: Parts> Environment for WithParts<S, P> {
    type Stage<M: Math> = ContactModel<M, S, P>;
    #[inline]
    fn stage<M: Math>(
        &self,
        contact: ContactParams,
        dt_s: f32,
    ) -> Result<Self::Stage<M>, ParamError> {
        ContactModel::with_parts(contact, self.surface, Quat::IDENTITY, dt_s)
    }
}

impl<M: Math, S: Surface, P: Parts> ContactStage for ContactModel<M, S, P> {
    #[inline(always)]
    fn step(&mut self, input: &ContactInput) -> ContactOutput {
        self.contact_step(input)
    }
    fn restart(&mut self) {
        // The surface keeps its geometry; its contact point is placed again at the next touch.
        if let Ok(c) = ContactModel::with_parts(
            *self.params(),
            self.rolling.surface,
            Quat::IDENTITY,
            self.dt_s(),
        ) {
            *self = c;
        }
    }
    fn set_contact_params(
        &mut self,
        p: &Checked<ContactParams>,
    ) -> Result<ParamsChange, ParamError> {
        *self =
            ContactModel::with_checked_parts(p, self.rolling.surface, Quat::IDENTITY, self.dt_s())?;
        Ok(ParamsChange::Restarted)
    }
    #[inline]
    fn params(&self) -> &ContactParams {
        ContactModel::params(self)
    }
    #[inline]
    fn state(&self) -> ContactState {
        ContactModel::state(self)
    }
    #[inline]
    fn contact_point_m(&self) -> Vec3 {
        self.rolling.surface.contact_point()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::state::Reason;
    use crate::contact::surface::Plane;
    use crate::math::Libm;

    fn stage() -> ContactModel<Libm, Plane> {
        Plane::default()
            .stage::<Libm>(ContactParams::DEFAULT, 1e-4)
            .unwrap()
    }

    fn pressed(x: f32) -> ContactInput {
        ContactInput {
            q: Quat::IDENTITY,
            probe_m: Vec3::new(x, 0.0, ContactParams::DEFAULT.fingertip_radius_m - 0.001),
            probe_vel: Vec3::ZERO,
        }
    }

    /// A fixed surface's stage reports the contact model's state and contact point, has no local
    /// model (sequence 0) and no watchdog (0 s), and refuses the local-model commands.
    #[test]
    fn a_fixed_scene_forwards_to_its_contact_model() {
        let mut s = stage();
        let o = ContactStage::step(&mut s, &pressed(0.002));
        assert_eq!(ContactStage::state(&s), ContactState::Rolling);
        assert_eq!(ContactStage::state(&s), o.state);
        assert_eq!(s.contact_point_m(), Vec3::new(0.002, 0.0, 0.0));
        assert_eq!(s.model_seq(), 0);
        assert_eq!(s.watchdog_s(), 0.0);
        assert_eq!(s.set_watchdog(0.1), Err(CommandError::Unsupported));
        assert_eq!(s.watchdog_s(), 0.0);
    }

    /// A restart breaks the contact (the next press makes it afresh where the probe is), and keeps
    /// the parameters.
    #[test]
    fn a_restart_breaks_the_contact_and_keeps_the_parameters() {
        let mut s = stage();
        ContactStage::step(&mut s, &pressed(0.0));
        ContactStage::restart(&mut s);
        assert_eq!(ContactStage::state(&s), ContactState::Broken);
        assert_eq!(ContactStage::params(&s), &ContactParams::DEFAULT);
        let o = ContactStage::step(&mut s, &pressed(0.003));
        assert_eq!(
            (o.state, o.reason),
            (ContactState::Rolling, Reason::MadeContact)
        );
        assert_eq!(s.contact_point_m(), Vec3::new(0.003, 0.0, 0.0));
    }
}
