//! The local model as the control pipeline's contact stage: [`LocalModelEnvironment`] is what a
//! [`Pipeline`](crate::control::pipeline::Pipeline) is built with, [`LocalModelStage`] what it runs — the
//! [`LocalModelRenderer`] followed by the [`CommWatchdog`]'s gain.
//!
//! Per tick: the renderer steps (switch at the tick boundary, slew or cross-fade, stale fade),
//! then force and spin torque are multiplied by the watchdog's gain. Its flags (MODEL_STALE,
//! MODEL_REJECTED, COMM_TIMEOUT while latched) go out with the contact step's, through the
//! pipeline's one guard and flags path; none of them latches a fault (the force fades instead).
//! The stage steps only while the pipeline runs the controller (Disarmed, Armed): the watchdog
//! and the model's age do not advance while unhomed, homing or faulted, when no force is
//! rendered anyway.
//!
//! Frames: the model poses are in the pipeline's object frame (the base frame translated by the
//! configuration's `object_origin_m`; zero makes it the base frame).

use crate::contact::params::{ContactParams, ParamsChange};
use crate::contact::state::ContactState;
use crate::contact::{ContactInput, ContactOutput, Full, Parts};
use crate::control::command::CommandError;
use crate::control::controller::{ContactStage, Environment};
use crate::control::local_model::pose::ProbeSample;
use crate::control::local_model::renderer::{LocalModelRenderer, RendererConfig};
use crate::control::local_model::spec::{LocalModelSpec, ModelError, MAX_AGE_S};
use crate::control::local_model::watchdog::CommWatchdog;
use crate::math::vec3::Vec3;
use crate::math::Math;
use crate::validate::{Checked, ParamError};
use core::marker::PhantomData;

/// The local-model environment: the initial model, the timing of blends, fades and the watchdog, and
/// the contact model's parts `P` ([`crate::contact::parts`]; the full model unless named).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LocalModelEnvironment<P: Parts = Full> {
    /// The model rendered until the application sends another.
    pub initial: LocalModelSpec,
    /// Blend time of a model switch, s, in [0, 1] (see [`RendererConfig::blend_s`]).
    pub blend_s: f32,
    /// Fade time of a stale model, s, in [0, 1].
    pub stale_fade_s: f32,
    /// Fade time of the force after a communication timeout, s.
    pub watchdog_fade_s: f32,
    /// Communication watchdog timeout at start, s, in [0, 60] (0: off).
    pub watchdog_timeout_s: f32,
    /// The contact model's parts (no data).
    pub parts: PhantomData<P>,
}

impl LocalModelEnvironment {
    /// `initial` with the renderer's default blend and stale fade, a 20 ms watchdog fade and the
    /// watchdog off, rendered with the full contact model.
    pub const fn new(initial: LocalModelSpec) -> LocalModelEnvironment {
        LocalModelEnvironment::with_parts(initial)
    }
}

impl<P: Parts> LocalModelEnvironment<P> {
    /// [`LocalModelEnvironment::new`] with the contact model of parts `P`.
    pub const fn with_parts(initial: LocalModelSpec) -> LocalModelEnvironment<P> {
        LocalModelEnvironment {
            initial,
            blend_s: RendererConfig::DEFAULT.blend_s,
            stale_fade_s: RendererConfig::DEFAULT.stale_fade_s,
            watchdog_fade_s: 0.020,
            watchdog_timeout_s: 0.0,
            parts: PhantomData,
        }
    }
}

impl<P: Parts> Environment for LocalModelEnvironment<P> {
    /// Observe only: the application moves and switches its model, work the base-frame observer
    /// would count as energy the wall puts into the hand. Measured on host-sim's virtual device
    /// (`serve::core` test `a_moving_local_model_steps_the_force_with_the_damper_on`): a plane
    /// moving ±1 mm at 5 Hz under a pressing hand steps the force by up to 2.35 N per tick with
    /// the damper, 0.119 N without.
    const PASSIVITY_DAMPS: bool = false;
    type Stage<M: Math> = LocalModelStage<M, P>;
    fn stage<M: Math>(
        &self,
        contact: ContactParams,
        dt_s: f32,
    ) -> Result<Self::Stage<M>, ParamError> {
        let rate_hz = 1.0 / dt_s;
        let config = RendererConfig {
            rate_hz,
            blend_s: self.blend_s,
            stale_fade_s: self.stale_fade_s,
        };
        let renderer =
            LocalModelRenderer::new(config, contact, self.initial).map_err(|e| match e {
                ModelError::Params(p) => p,
                _ => ParamError::OutOfRange("local model"),
            })?;
        crate::validate::positive("watchdog_fade_s", self.watchdog_fade_s)?;
        let mut stage = LocalModelStage {
            renderer,
            watchdog: CommWatchdog::new(rate_hz, self.watchdog_fade_s),
            watchdog_s: 0.0,
            state: ContactState::Broken,
            point_m: Vec3::ZERO,
            seq: self.initial.seq,
        };
        stage
            .set_watchdog(self.watchdog_timeout_s)
            .map_err(|_| ParamError::OutOfRange("watchdog_timeout_s"))?;
        Ok(stage)
    }
}

/// The local-model renderer and the communication watchdog as a contact stage.
#[derive(Clone, Copy, Debug)]
pub struct LocalModelStage<M: Math, P: Parts = Full> {
    renderer: LocalModelRenderer<M, P>,
    watchdog: CommWatchdog,
    watchdog_s: f32,
    state: ContactState,
    point_m: Vec3,
    seq: u32,
}

impl<M: Math, P: Parts> LocalModelStage<M, P> {
    /// The renderer (read-only, for logs).
    pub fn renderer(&self) -> &LocalModelRenderer<M, P> {
        &self.renderer
    }

    /// The watchdog (read-only, for logs).
    pub fn watchdog(&self) -> &CommWatchdog {
        &self.watchdog
    }
}

impl<M: Math, P: Parts> ContactStage for LocalModelStage<M, P> {
    fn step(&mut self, input: &ContactInput) -> ContactOutput {
        let r = self.renderer.step(&ProbeSample {
            q: input.q,
            probe_m: input.probe_m,
            probe_vel: input.probe_vel,
        });
        let (gain, wflags) = self.watchdog.tick();
        self.state = r.state;
        self.point_m = r.contact_point_m;
        self.seq = r.model_seq;
        ContactOutput {
            force_n: r.force_n * gain,
            tau_n_nm: r.tau_n_nm * gain,
            state: r.state,
            object_point_m: r.contact_point_m,
            flags: r.flags | wflags,
            ..ContactOutput::default()
        }
    }

    fn restart(&mut self) {
        self.renderer.restart();
        self.state = ContactState::Broken;
    }

    fn set_contact_params(
        &mut self,
        p: &Checked<ContactParams>,
    ) -> Result<ParamsChange, ParamError> {
        let change = self.renderer.set_base_params(p).map_err(|e| match e {
            ModelError::Params(p) => p,
            _ => ParamError::OutOfRange("contact params"),
        })?;
        if change == ParamsChange::Restarted {
            self.state = ContactState::Broken;
        }
        Ok(change)
    }

    fn params(&self) -> &ContactParams {
        self.renderer.base_params()
    }

    fn state(&self) -> ContactState {
        self.state
    }

    fn contact_point_m(&self) -> Vec3 {
        self.point_m
    }

    fn model_seq(&self) -> u32 {
        self.seq
    }

    fn set_local_model(&mut self, spec: &Checked<LocalModelSpec>) -> Result<(), CommandError> {
        self.renderer
            .accept_checked(spec)
            .map_err(CommandError::InvalidModel)
    }

    fn local_model_refused(&mut self) {
        self.renderer.refused();
    }

    fn set_watchdog(&mut self, timeout_s: f32) -> Result<(), CommandError> {
        if !(0.0..=MAX_AGE_S).contains(&timeout_s) {
            return Err(CommandError::InvalidParams(ParamError::OutOfRange(
                "watchdog_timeout_s",
            )));
        }
        self.watchdog
            .set_timeout(timeout_s, self.renderer.config().rate_hz);
        self.watchdog_s = if self.watchdog.enabled() {
            timeout_s
        } else {
            0.0
        };
        Ok(())
    }

    fn watchdog_s(&self) -> f32 {
        self.watchdog_s
    }

    fn note_link_activity(&mut self) {
        self.watchdog.feed();
    }

    fn rearm(&mut self) {
        self.watchdog.rearm();
    }
}
