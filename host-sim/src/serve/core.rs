//! The device side of the virtual device: the one control pipeline
//! ([`softfinger_core::control::pipeline::Pipeline`]) on the local-model scene, against the plant.
//!
//! [`PipelineCore`] is what the device loop calls: `tick` with the plant (the pipeline reads the
//! plant's raw 16-bit counter values, `Plant::raw_counts`, and its bridge commands drive the
//! plant, `Plant::step_bridges`, with the firmware's board timing and thresholds), `request` for
//! each operator request, `message_received` for each valid message (the communication
//! watchdog's food). Its mode machine, homing, arming ramp, output guard and fault latch are the
//! pipeline's, the firmware's own. It renders with the contact model the scene names (`model` in
//! its file; [`softfinger_core::contact::parts`]), a type parameter: the server picks it once,
//! at start.

use crate::sim::plant::Plant;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::{Full, Parts};
use softfinger_core::control::controller::ContactStage;
use softfinger_core::control::local_model::{
    LocalModelEnvironment, LocalModelSpec, ModelKind, ModelPose,
};
use softfinger_core::control::pipeline::{
    Command, CommandError, Pipeline, PipelineConfig, PipelineOutput,
};
use softfinger_core::{Fast, Flags, Vec3};
use softfinger_protocol::{Mode, RenderedTick};

/// The communication watchdog's timeout on the virtual device at start, s. 200 ms: ten times
/// the host library's 20 ms heartbeat (a client that is alive is never near it, even with the
/// OS's scheduling hiccups on a loaded machine), and short enough that a client that dies lets
/// go of the force within 0.2 s + the 20 ms fade, well inside a human's reaction to a runaway
/// force. A client may change it (`SetWatchdog`, 0 turns it off for bench use).
pub const DEFAULT_WATCHDOG_S: f32 = 0.2;

/// The virtual device's core: the pipeline on the local-model scene, with the contact model of
/// parts `P`.
#[derive(Debug)]
pub struct PipelineCore<P: Parts = Full> {
    pipe: Pipeline<Fast, LocalModelEnvironment<P>>,
}

impl<P: Parts> PipelineCore<P> {
    /// The pipeline for `scene` (its control rate on the firmware's board timing, its contact
    /// parameters, its surface as the initial local model), blending model switches over
    /// `blend_s`, with the watchdog at `watchdog_s` (0: off). Unhomed.
    pub fn new(
        scene: &crate::sim::scene::Scene,
        blend_s: f32,
        watchdog_s: f32,
    ) -> Result<Self, super::ServeError> {
        let (contact, model) = scene_model(scene)?;
        let config = PipelineConfig {
            device: softfinger_core::omega_like::OMEGA_LIKE,
            timing: crate::sim::closed_loop::board_timing(scene.rate_hz)?,
            contact,
            surface: LocalModelEnvironment {
                blend_s,
                watchdog_timeout_s: watchdog_s,
                ..LocalModelEnvironment::<P>::with_parts(model)
            },
            // Model poses are in the base frame.
            object_origin_m: Vec3::ZERO,
            log_rate_hz: 0,
        };
        // The passivity stage observes only, as on the firmware: the local-model scene's
        // default (`LocalModelEnvironment::PASSIVITY_DAMPS`, with the measurement behind it).
        let pipe = Pipeline::new(config)?;
        Ok(PipelineCore { pipe })
    }

    /// The pipeline (read-only).
    pub fn pipeline(&self) -> &Pipeline<Fast, LocalModelEnvironment<P>> {
        &self.pipe
    }

    /// The pipeline, for the operator's session at start (`--auto-arm`).
    pub fn pipeline_mut(&mut self) -> &mut Pipeline<Fast, LocalModelEnvironment<P>> {
        &mut self.pipe
    }

    /// The name of the contact model it renders with ([`Parts::NAME`]).
    pub fn contact_model(&self) -> &'static str {
        P::NAME
    }
}

impl<P: Parts> PipelineCore<P> {
    /// Control rate, Hz.
    pub fn rate_hz(&self) -> f32 {
        self.pipe.config().timing.control_hz as f32
    }

    /// One control tick: read the plant's counters, run, drive the plant's bridges for a tick.
    /// What it rendered, as the stream reports it: [`RenderedTick::of`] with [`Self::pipeline`].
    pub fn tick(&mut self, plant: &mut Plant) -> PipelineOutput {
        let (_, out, _) = crate::sim::closed_loop::step(&mut self.pipe, plant, |_| {});
        out
    }

    /// What the last tick, which returned `out`, rendered (the stream's fields).
    pub fn rendered(&self, out: &PipelineOutput) -> RenderedTick {
        RenderedTick::of(&self.pipe, out)
    }

    /// A client's command, at a tick boundary, under the host link's rules as on the firmware
    /// (`Pipeline::link_command`: a client's `Arm` turns the host watchdog on when it is off, and
    /// that client cannot turn it off while the device stays armed).
    pub fn request(&mut self, command: Command) -> Result<(), CommandError> {
        self.pipe.link_command(command)
    }

    /// A valid message arrived from some client (the communication watchdog's food).
    pub fn message_received(&mut self) {
        self.pipe.note_link_activity();
    }

    /// The contact parameters in force.
    pub fn contact_params(&self) -> ContactParams {
        self.pipe.controller().config().contact
    }

    /// The watchdog timeout in force, s (0: off).
    pub fn watchdog_s(&self) -> f32 {
        self.pipe.controller().contact().watchdog_s()
    }

    /// Faults latched until `ClearFaults`.
    pub fn latched(&self) -> Flags {
        self.pipe.latched()
    }

    /// The mode now (a command's change shows before the next tick).
    pub fn mode(&self) -> Mode {
        self.pipe.mode()
    }

    /// The local model in force.
    pub fn model(&self) -> LocalModelSpec {
        *self.pipe.controller().contact().renderer().model()
    }
}

/// The initial model and contact parameters of a scene (plane top; sphere, bowl or cylinder centre
/// in the base frame, as the closed-loop runs place them).
pub fn scene_model(
    scene: &crate::sim::scene::Scene,
) -> Result<(ContactParams, LocalModelSpec), crate::sim::closed_loop::ClosedLoopError> {
    let contact = crate::sim::closed_loop::contact_params(scene)?;
    let top = crate::sim::closed_loop::surface_top_z_m() as f32;
    let (kind, z) = match scene.surface {
        crate::sim::scene::SurfaceSpec::Plane => (ModelKind::Plane, top),
        crate::sim::scene::SurfaceSpec::Sphere { radius_m } => (
            ModelKind::Sphere {
                radius_m: radius_m as f32,
            },
            top - radius_m as f32,
        ),
        // The bowl's centre is its radius above its bottom (the first contact), as in
        // `closed_loop::bowl_config`; the local model checks that it holds the fingertip.
        crate::sim::scene::SurfaceSpec::Bowl { radius_m } => (
            ModelKind::Bowl {
                radius_m: radius_m as f32,
            },
            top + radius_m as f32,
        ),
        // The cylinder's axis (object x, along base x) is its radius below its top.
        crate::sim::scene::SurfaceSpec::Cylinder { radius_m } => (
            ModelKind::Cylinder {
                radius_m: radius_m as f32,
            },
            top - radius_m as f32,
        ),
    };
    let spec = LocalModelSpec {
        kind,
        ..LocalModelSpec::plane(0, ModelPose::at(Vec3::new(0.0, 0.0, z)), &contact)
    };
    Ok((contact, spec))
}

#[cfg(test)]
#[path = "core_tests.rs"]
mod tests;
