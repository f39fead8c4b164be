//! [`LocalModelRenderer`]: renders the local model in force and switches to a new one at a tick
//! boundary without a force step.
//!
//! - **Accepting** ([`LocalModelRenderer::accept`]): a model newer than the last accepted one and
//!   valid is queued (the latest wins); anything else is refused with a [`ModelError`] and
//!   [`Flags::MODEL_REJECTED`] on the next tick. Nothing changes mid-tick. The checks that need
//!   only the model run where it arrives ([`LocalModelSpec::checked`]; the firmware's link task,
//!   in thread mode); [`LocalModelRenderer::accept_checked`], in the tick, checks the rest: the
//!   sequence number and the fit ([`LocalModelSpec::fits`]).
//! - **Switching** (at the start of [`LocalModelRenderer::step`]):
//!   - same surface (kind and size), new pose (a moving object, the usual 100 Hz–1 kHz stream):
//!     the surface *slews* from where it is now to the new pose over `blend_s` (positions linear,
//!     orientations by normalised lerp). A new material (stiffness, damping, friction, spin
//!     stiffness) *blends* over the same time, field by field, in the same contact model. The
//!     contact model, its contact state and contact points carry on: the state is consistent by
//!     construction, and the tick steps one contact model.
//!   - another kind or size: a second contact model starts on the new surface and the
//!     force *cross-fades* from the old to the new over `blend_s`. The reported contact state and
//!     point are the old model's until the new one's weight reaches ½. Further different models
//!     wait (the latest wins) until the cross-fade ends; pose updates of the incoming model slew.
//!
//!   Either way the force changes by at most `|ΔF|·dt/blend_s` per tick from the switch itself.
//! - **Staleness**: a model declaring a maximum age (`max_age_s > 0`) is stale that long after it
//!   was received unless a newer one arrived: [`Flags::MODEL_STALE`] is raised and the force and
//!   torque fade to zero over `stale_fade_s`; a fresh model brings them back over the same time.
//!
//! The object may move, but the damping acts on the probe's velocity (relative to the base, not to
//! the moving surface): a 1 kHz stream gives no surface velocity to difference.

use crate::contact::params::{ContactParams, Material};
use crate::contact::state::ContactState;
use crate::contact::{ContactInput, ContactModel, ContactOutput, Full, Parts};
use crate::control::local_model::pose::{ModelPose, ProbeSample};
use crate::control::local_model::ramp::Ramp;
use crate::control::local_model::spec::{is_newer, LocalModelSpec, ModelError};
use crate::control::local_model::surface::ModelSurface;
use crate::flags::Flags;
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Math;
use crate::validate::{Checked, ParamError};

pub use crate::contact::params::ParamsChange;

/// Timing of the renderer.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RendererConfig {
    /// Control rate, Hz (1 kHz to 40 kHz).
    pub rate_hz: f32,
    /// Time over which a new model replaces the old one (slew or cross-fade), s, in [0, 1].
    /// 0 switches in one tick.
    pub blend_s: f32,
    /// Time a stale model's force takes to fade to zero, and to come back, s, in [0, 1].
    pub stale_fade_s: f32,
}

impl RendererConfig {
    /// 10 kHz, 2 ms blend (two updates of a 1 kHz stream), 20 ms stale fade.
    pub const DEFAULT: RendererConfig = RendererConfig {
        rate_hz: 10_000.0,
        blend_s: 0.002,
        stale_fade_s: 0.020,
    };

    /// Check every field.
    pub fn validate(&self) -> Result<(), ParamError> {
        crate::validate::positive("rate_hz", self.rate_hz)?;
        if !(1_000.0..=40_000.0).contains(&self.rate_hz) {
            return Err(ParamError::OutOfRange("rate_hz"));
        }
        crate::validate::non_negative("blend_s", self.blend_s)?;
        crate::validate::at_most("blend_s", self.blend_s, 1.0)?;
        crate::validate::non_negative("stale_fade_s", self.stale_fade_s)?;
        crate::validate::at_most("stale_fade_s", self.stale_fade_s, 1.0)
    }
}

/// What one tick rendered. Vectors in the base frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RenderOutput {
    /// Force on the probe, N (blended, faded).
    pub force_n: Vec3,
    /// Spin torque about the contact normal, N·m.
    pub tau_n_nm: f32,
    /// Contact state (see the module doc for a cross-fade).
    pub state: ContactState,
    /// Contact point on the object, m.
    pub contact_point_m: Vec3,
    /// Sequence number of the model in force (the incoming one once its weight reaches ½).
    pub model_seq: u32,
    /// The contact steps' flags, plus MODEL_STALE / MODEL_REJECTED.
    pub flags: Flags,
}

/// One model being rendered: its spec, its surface's current pose and material, and its contact
/// model.
#[derive(Clone, Copy, Debug)]
struct Slot<M: Math, P: Parts> {
    spec: LocalModelSpec,
    pose: ModelPose,
    slew_from: ModelPose,
    slew: Ramp,
    /// The material the contact model renders now, and where a material blend started.
    material: Material,
    blend_from: Material,
    blend: Ramp,
    contact: ContactModel<M, ModelSurface, P>,
}

/// A contact step's result moved to the base frame.
#[derive(Clone, Copy, Debug)]
struct SlotOutput {
    force_n: Vec3,
    point_m: Vec3,
    out: ContactOutput,
}

impl<M: Math, P: Parts> Slot<M, P> {
    /// A slot rendering `spec` (checked, and fitting `base`: [`LocalModelSpec::validate`]) on
    /// `base` (valid) at the renderer's rate (validated with its configuration).
    fn new(
        spec: &Checked<LocalModelSpec>,
        base: &ContactParams,
        cfg: &RendererConfig,
    ) -> Result<Self, ModelError> {
        let material = spec.material();
        // Valid: a valid base with a checked material.
        let params = Checked::assume_checked(spec.contact_params(base));
        let contact = ContactModel::with_checked_parts(
            &params,
            ModelSurface::of(spec.kind),
            Quat::IDENTITY,
            1.0 / cfg.rate_hz,
        )
        .map_err(ModelError::Params)?;
        Ok(Slot {
            spec: **spec,
            pose: spec.pose,
            slew_from: spec.pose,
            slew: Ramp::new(1.0, cfg.blend_s, cfg.rate_hz),
            material,
            blend_from: material,
            blend: Ramp::new(1.0, cfg.blend_s, cfg.rate_hz),
            contact,
        })
    }

    /// Same surface, new pose and perhaps material: slew from where the surface is now, blend
    /// from the material rendered now.
    fn retarget(&mut self, spec: &LocalModelSpec) {
        if spec.pose != self.spec.pose {
            self.slew_from = self.pose;
            self.slew.set(0.0);
        }
        if !spec.same_material_as(&self.spec) {
            self.blend_from = self.material;
            self.blend.set(0.0);
        }
        self.spec = *spec;
    }

    fn step(&mut self, s: &ProbeSample) -> SlotOutput {
        if self.slew.value() < 1.0 {
            let k = self.slew.advance(1.0);
            self.pose = self.slew_from.interpolate::<M>(&self.spec.pose, k);
        } else {
            self.pose = self.spec.pose;
        }
        if self.blend.value() < 1.0 {
            let k = self.blend.advance(1.0);
            let to = self.spec.material();
            self.material = if k >= 1.0 {
                to
            } else {
                self.blend_from.lerp(&to, k)
            };
            self.contact.take_material(&self.material);
        }
        let pose = self.pose;
        let out = self.contact.contact_step(&ContactInput {
            q: pose.orientation.conjugate() * s.q,
            probe_m: pose.point_to_object(s.probe_m),
            probe_vel: pose.vector_to_object(s.probe_vel),
        });
        SlotOutput {
            force_n: pose.vector_to_base(out.force_n),
            point_m: pose.point_to_base(out.object_point_m),
            out,
        }
    }
}

/// Renders the local model in force with the contact model of parts `P`
/// ([`crate::contact::parts`]); see the module doc.
#[derive(Clone, Copy, Debug)]
pub struct LocalModelRenderer<M: Math, P: Parts = Full> {
    config: RendererConfig,
    base: ContactParams,
    active: Slot<M, P>,
    incoming: Option<Slot<M, P>>,
    weight: Ramp,
    pending: Option<Checked<LocalModelSpec>>,
    latest_seq: u32,
    age_ticks: u32,
    max_age_ticks: u32,
    stale_gain: Ramp,
    pending_flags: Flags,
}

/// Ticks in `s` seconds at `rate_hz`, rounded up; 0 for 0.
fn ticks_of(s: f32, rate_hz: f32) -> u32 {
    let t = libm::ceilf(s * rate_hz);
    if t.is_finite() && t > 0.0 {
        if t >= u32::MAX as f32 {
            u32::MAX
        } else {
            t as u32
        }
    } else {
        0
    }
}

impl<M: Math, P: Parts> LocalModelRenderer<M, P> {
    /// A renderer of `initial`; `base` supplies what a model does not carry (fingertip radius,
    /// tangential coupling, force limit, state tolerances).
    pub fn new(
        config: RendererConfig,
        base: ContactParams,
        initial: LocalModelSpec,
    ) -> Result<Self, ModelError> {
        config.validate().map_err(ModelError::Params)?;
        base.validate().map_err(ModelError::Params)?;
        let initial = initial.checked()?;
        initial.fits(&base)?;
        Ok(LocalModelRenderer {
            config,
            base,
            active: Slot::new(&initial, &base, &config)?,
            incoming: None,
            weight: Ramp::new(0.0, config.blend_s, config.rate_hz),
            pending: None,
            latest_seq: initial.seq,
            age_ticks: 0,
            max_age_ticks: ticks_of(initial.max_age_s, config.rate_hz),
            stale_gain: Ramp::new(1.0, config.stale_fade_s, config.rate_hz),
            pending_flags: Flags::NONE,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &RendererConfig {
        &self.config
    }

    /// The contact parameters models are completed with.
    pub fn base_params(&self) -> &ContactParams {
        &self.base
    }

    /// Replace the parameters models are completed with; the model in force takes their material
    /// (stiffness, damping, friction, spin stiffness) too.
    ///
    /// - Only the material differs from the parameters in force: the material blends in over
    ///   `blend_s` in the contact model in force, whose contact state carries on
    ///   ([`ParamsChange::Blended`]), as for a model with another material.
    /// - Anything else differs (fingertip, coupling, patch, limits, tolerances): the model in
    ///   force restarts, its contact state too ([`ParamsChange::Restarted`]), so callers ramp
    ///   the force in again.
    pub fn set_base_params(
        &mut self,
        base: &Checked<ContactParams>,
    ) -> Result<ParamsChange, ModelError> {
        let base: &ContactParams = base;
        let with_base = |spec: &LocalModelSpec| LocalModelSpec {
            stiffness_n_per_m: base.normal_stiffness,
            damping_n_s_per_m: base.normal_damping,
            mu_s: base.mu_s,
            mu_k: base.mu_k,
            spin_stiffness_nm_per_rad: base.spin_stiffness,
            ..*spec
        };
        let spec = with_base(&self.active.spec);
        // The material is the checked base's, the rest was checked when the model was accepted.
        spec.fits(base)?;
        if base.same_but_material(&self.base) {
            // Only the material differs: five fields, not a copy of the whole parameters.
            self.base.take_material_of(base);
            self.active.retarget(&spec);
            if let Some(inc) = &mut self.incoming {
                let s = with_base(&inc.spec);
                inc.retarget(&s);
            }
            return Ok(ParamsChange::Blended);
        }
        let slot = Slot::new(&Checked::assume_checked(spec), base, &self.config)?;
        self.base = *base;
        self.active = slot;
        self.incoming = None;
        Ok(ParamsChange::Restarted)
    }

    /// Break the contact: the model in force starts again untouched (a queued model stays queued,
    /// a cross-fade in progress is completed at once, the age and staleness carry on).
    pub fn restart(&mut self) {
        // Every model in force was checked when it was accepted.
        let spec = Checked::assume_checked(*self.model());
        if let Ok(slot) = Slot::new(&spec, &self.base, &self.config) {
            self.active = slot;
            self.incoming = None;
        }
    }

    /// The highest sequence number accepted so far.
    pub fn latest_seq(&self) -> u32 {
        self.latest_seq
    }

    /// The model in force (the one rendered with weight ≥ ½).
    pub fn model(&self) -> &LocalModelSpec {
        match &self.incoming {
            Some(inc) if self.weight.value() >= 0.5 => &inc.spec,
            _ => &self.active.spec,
        }
    }

    /// Queue a model for the next tick boundary (see the module doc): [`LocalModelSpec::checked`]
    /// then [`Self::accept_checked`].
    pub fn accept(&mut self, spec: LocalModelSpec) -> Result<(), ModelError> {
        match spec.checked() {
            Ok(spec) => self.accept_checked(&spec),
            Err(e) => Err(self.rejected(e)),
        }
    }

    /// Queue a checked model: what is left of its validation is the tick's share, its sequence
    /// number and [`LocalModelSpec::fits`].
    pub fn accept_checked(&mut self, spec: &Checked<LocalModelSpec>) -> Result<(), ModelError> {
        if !is_newer(spec.seq, self.latest_seq) {
            return Err(self.rejected(ModelError::StaleSequence));
        }
        if let Err(e) = spec.fits(&self.base) {
            return Err(self.rejected(e));
        }
        self.latest_seq = spec.seq;
        self.age_ticks = 0;
        self.max_age_ticks = ticks_of(spec.max_age_s, self.config.rate_hz);
        self.pending = Some(*spec);
        Ok(())
    }

    /// A model was refused (here or where it arrived): [`Flags::MODEL_REJECTED`] on the next
    /// tick.
    pub fn refused(&mut self) {
        self.pending_flags |= Flags::MODEL_REJECTED;
    }

    /// [`Self::refused`], returning `e`.
    pub fn rejected(&mut self, e: ModelError) -> ModelError {
        self.refused();
        e
    }

    /// Start rendering the queued model, if it can start now.
    fn apply_pending(&mut self) {
        // Borrowed, not copied: the spec is copied once, into the slot that renders it.
        let Some(spec) = &self.pending else { return };
        match &mut self.incoming {
            Some(inc) if spec.same_surface_as(&inc.spec) => inc.retarget(spec),
            Some(_) => return, // a cross-fade is running: wait for its end
            None if spec.same_surface_as(&self.active.spec) => self.active.retarget(spec),
            None => match Slot::new(spec, &self.base, &self.config) {
                Ok(slot) => {
                    self.incoming = Some(slot);
                    self.weight.set(0.0);
                }
                // Checked on acceptance; kept for safety: the model in force stays.
                Err(_) => self.pending_flags |= Flags::MODEL_REJECTED,
            },
        }
        self.pending = None;
    }

    /// One control tick with the probe sample in the base frame.
    pub fn step(&mut self, sample: &ProbeSample) -> RenderOutput {
        let mut flags = self.pending_flags;
        self.pending_flags = Flags::NONE;
        self.apply_pending();

        let a = self.active.step(sample);
        flags |= a.out.flags;
        let mut out = RenderOutput {
            force_n: a.force_n,
            tau_n_nm: a.out.tau_n_nm,
            state: a.out.state,
            contact_point_m: a.point_m,
            model_seq: self.active.spec.seq,
            flags,
        };
        if let Some(mut inc) = self.incoming.take() {
            let b = inc.step(sample);
            let w = self.weight.advance(1.0);
            out.force_n = a.force_n * (1.0 - w) + b.force_n * w;
            out.tau_n_nm = a.out.tau_n_nm * (1.0 - w) + b.out.tau_n_nm * w;
            out.flags |= b.out.flags;
            if w >= 0.5 {
                out.state = b.out.state;
                out.contact_point_m = b.point_m;
                out.model_seq = inc.spec.seq;
            }
            if w >= 1.0 {
                self.active = inc;
            } else {
                self.incoming = Some(inc);
            }
        }
        self.fade_if_stale(&mut out);
        out
    }

    /// Age the model; fade force and torque while it is stale.
    fn fade_if_stale(&mut self, out: &mut RenderOutput) {
        self.age_ticks = self.age_ticks.saturating_add(1);
        let stale = self.max_age_ticks != 0 && self.age_ticks > self.max_age_ticks;
        let g = self.stale_gain.advance(if stale { 0.0 } else { 1.0 });
        if stale {
            out.flags |= Flags::MODEL_STALE;
        }
        out.force_n = out.force_n * g;
        out.tau_n_nm *= g;
    }
}

#[cfg(test)]
mod tests;
