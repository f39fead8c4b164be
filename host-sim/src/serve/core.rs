//! The device side of the virtual device: the one control pipeline
//! ([`softfinger_core::control::pipeline::Pipeline`]) on the local-model scene, against the plant.
//!
//! [`DeviceCore`] is the seam the server calls: `tick` with the plant (the pipeline reads the
//! plant's raw 16-bit counter values, `Plant::raw_counts`, and its bridge commands drive the
//! plant, `Plant::step_bridges`, with the firmware's board timing and thresholds), `request` for
//! each operator request, `message_received` for each valid message (the communication
//! watchdog's food). [`PipelineCore`] implements it; its mode machine, homing, arming ramp,
//! output guard and fault latch are the pipeline's, the firmware's own. It renders with the
//! contact model the scene names (`model` in its file; [`softfinger_core::contact::parts`]).

use crate::plant::Plant;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::state::ContactState;
use softfinger_core::contact::{Full, Parts};
use softfinger_core::control::controller::ContactStage;
use softfinger_core::control::local_model::{
    LocalModelEnvironment, LocalModelSpec, ModelKind, ModelPose,
};
use softfinger_core::control::pipeline::{Command, CommandError, Pipeline, PipelineConfig};
use softfinger_core::{Fast, Flags, Vec3};
use softfinger_protocol::Mode;

/// The communication watchdog's timeout on the virtual device at start, s. 200 ms: ten times
/// the host library's 20 ms heartbeat (a client that is alive is never near it, even with the
/// OS's scheduling hiccups on a loaded machine), and short enough that a client that dies lets
/// go of the force within 0.2 s + the 20 ms fade, well inside a human's reaction to a runaway
/// force. A client may change it (`SetWatchdog`, 0 turns it off for bench use).
pub const DEFAULT_WATCHDOG_S: f32 = 0.2;

/// What the device did in one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CoreOutput {
    /// Probe position, base frame, m.
    pub probe_m: Vec3,
    /// Probe velocity (the controller's filtered one), base frame, m/s.
    pub probe_vel_m_s: Vec3,
    /// Force rendered, base frame, N.
    pub force_n: Vec3,
    /// Spin torque, N·m.
    pub spin_torque_nm: f32,
    /// Contact state.
    pub contact: ContactState,
    /// Contact point, base frame, m.
    pub contact_point_m: Vec3,
    /// Flags raised (latched included).
    pub flags: Flags,
    /// Mode after the tick.
    pub mode: Mode,
    /// Sequence of the model in force.
    pub model_seq: u32,
    /// Bridges driven this tick.
    pub enable: bool,
}

/// The per-tick device logic the server runs against the plant.
pub trait DeviceCore: Send {
    /// Control rate, Hz.
    fn rate_hz(&self) -> f32;
    /// One control tick: read the plant's counters, run, drive the plant's bridges for a tick.
    fn tick(&mut self, plant: &mut Plant) -> CoreOutput;
    /// An operator command, at a tick boundary.
    fn request(&mut self, command: Command) -> Result<(), CommandError>;
    /// A valid message arrived from some client (the communication watchdog's food).
    fn message_received(&mut self);
    /// The contact parameters in force.
    fn contact_params(&self) -> ContactParams;
    /// The watchdog timeout in force, s (0: off).
    fn watchdog_s(&self) -> f32;
    /// Faults latched until `ClearFaults`.
    fn latched(&self) -> Flags;
    /// The mode now (a command's change shows before the next tick).
    fn mode(&self) -> Mode;
    /// The local model in force.
    fn model(&self) -> LocalModelSpec;
}

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
        scene: &crate::scene::Scene,
        blend_s: f32,
        watchdog_s: f32,
    ) -> Result<Self, super::ServeError> {
        let (contact, model) = scene_model(scene)?;
        let config = PipelineConfig {
            device: softfinger_core::omega_like::OMEGA_LIKE,
            timing: crate::closed_loop::board_timing(scene.rate_hz)?,
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

impl<P: Parts> DeviceCore for PipelineCore<P> {
    fn rate_hz(&self) -> f32 {
        self.pipe.config().timing.control_hz as f32
    }

    fn tick(&mut self, plant: &mut Plant) -> CoreOutput {
        let (_, out, _) = crate::closed_loop::step(&mut self.pipe, plant, |_| {});
        let c = self.pipe.controller();
        CoreOutput {
            probe_m: out.control.probe_m,
            probe_vel_m_s: c.probe_velocity(),
            force_n: out.control.force_n,
            spin_torque_nm: out.control.tau_n_nm,
            contact: out.control.state,
            contact_point_m: c.contact_point_m(),
            flags: out.flags,
            mode: out.mode,
            model_seq: c.contact().model_seq(),
            enable: out.bridges.pwm_enable,
        }
    }

    fn request(&mut self, command: Command) -> Result<(), CommandError> {
        self.pipe.command(command)
    }

    fn message_received(&mut self) {
        self.pipe.note_link_activity();
    }

    fn contact_params(&self) -> ContactParams {
        self.pipe.controller().config().contact
    }

    fn watchdog_s(&self) -> f32 {
        self.pipe.controller().contact().watchdog_s()
    }

    fn latched(&self) -> Flags {
        self.pipe.latched()
    }

    fn mode(&self) -> Mode {
        self.pipe.mode()
    }

    fn model(&self) -> LocalModelSpec {
        *self.pipe.controller().contact().renderer().model()
    }
}

/// The initial model and contact parameters of a scene (plane top; sphere, bowl or cylinder centre
/// in the base frame, as the closed-loop runs place them).
pub fn scene_model(
    scene: &crate::scene::Scene,
) -> Result<(ContactParams, LocalModelSpec), crate::closed_loop::ClosedLoopError> {
    let contact = crate::closed_loop::contact_params(scene)?;
    let top = crate::closed_loop::surface_top_z_m() as f32;
    let (kind, z) = match scene.surface {
        crate::scene::SurfaceSpec::Plane => (ModelKind::Plane, top),
        crate::scene::SurfaceSpec::Sphere { radius_m } => (
            ModelKind::Sphere {
                radius_m: radius_m as f32,
            },
            top - radius_m as f32,
        ),
        // The bowl's centre is its radius above its bottom (the first contact), as in
        // `closed_loop::bowl_config`; the local model checks that it holds the fingertip.
        crate::scene::SurfaceSpec::Bowl { radius_m } => (
            ModelKind::Bowl {
                radius_m: radius_m as f32,
            },
            top + radius_m as f32,
        ),
        // The cylinder's axis (object x, along base x) is its radius below its top.
        crate::scene::SurfaceSpec::Cylinder { radius_m } => (
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
