//! The device side of the virtual device: what runs every control tick, behind one trait.
//!
//! [`DeviceCore`] is the seam: the server calls `tick` with the plant's encoder counts and
//! `request` for each operator request, and nothing else. [`LocalModelCore`] implements it with
//! core parts (delta kinematics, [`LocalModelRenderer`], [`CommWatchdog`], Jacobian-transpose
//! torques, duty limits, a mode machine). The shared control pipeline
//! (`softfinger_core::pipeline`) renders one surface fixed at build time; once its contact step
//! can be the renderer, a `DeviceCore` over `Pipeline` (raw counts from `Plant::raw_counts`,
//! bridge commands to `Plant::step_bridges`) replaces this one without touching the server.
//!
//! Safety as on the device: no force before homing and arming; force ramps in on arming; any
//! latching fault (encoder glitch, non-finite output) gives zero duties with the drivers disabled
//! at once, until cleared, and clearing leads to `Disarmed`, never `Armed`.

use softfinger_core::contact_state::ContactState;
use softfinger_core::device::DeviceParams;
use softfinger_core::local_model::{
    CommWatchdog, LocalModelRenderer, LocalModelSpec, ModelError, ProbeSample, Ramp, RendererConfig,
};
use softfinger_core::params::ContactParams;
use softfinger_core::{Fast, Flags, Vec3};
use softfinger_protocol::{AckResult, ErrorCode, Mode};

/// What the device did in one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CoreOutput {
    /// Signed duties for the three motors, [-1, 1].
    pub duties: [f32; 3],
    /// Drivers enabled.
    pub enable: bool,
    /// Probe position, base frame, m.
    pub probe_m: Vec3,
    /// Probe velocity, base frame, m/s.
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
}

/// An operator request the core handles (the link's requests minus the ones about the link).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CoreRequest {
    Home,
    Arm,
    Disarm,
    ClearFaults,
    SetContactParams(ContactParams),
    SetLocalModel(LocalModelSpec),
    SetWatchdog { timeout_s: f32 },
}

/// The per-tick device logic the server runs against the plant.
pub trait DeviceCore: Send {
    /// Control rate, Hz.
    fn rate_hz(&self) -> f32;
    /// One control tick with the extended encoder counts.
    fn tick(&mut self, counts: [i32; 6]) -> CoreOutput;
    /// An operator request, at a tick boundary.
    fn request(&mut self, req: CoreRequest) -> AckResult;
    /// A valid message arrived from some client (the communication watchdog's food).
    fn message_received(&mut self);
    /// The contact parameters in force.
    fn contact_params(&self) -> ContactParams;
    /// The watchdog timeout in force, s (0: off).
    fn watchdog_s(&self) -> f32;
}

/// Timing constants of the mode machine.
const HOMING_S: f32 = 0.05;
const ARM_RAMP_S: f32 = 0.1;
const WATCHDOG_FADE_S: f32 = 0.02;

/// The virtual device's core: see the module doc.
#[derive(Debug)]
pub struct LocalModelCore {
    device: DeviceParams,
    rate_hz: f32,
    renderer: LocalModelRenderer<Fast>,
    watchdog: CommWatchdog,
    watchdog_s: f32,
    arm: Ramp,
    mode: Mode,
    homing_ticks: u32,
    latched: Flags,
    max_counts_per_tick: u32,
    max_duty: f32,
    alpha: f32,
    prev: Option<Prev>,
}

/// The previous tick's measurements, for the velocity filters and the glitch check.
#[derive(Clone, Copy, Debug)]
struct Prev {
    counts: [i32; 6],
    probe_m: Vec3,
    probe_vel: Vec3,
    angles: [f32; 3],
    arm_vel: [f32; 3],
}

impl LocalModelCore {
    /// A core at `rate_hz` rendering `initial`, unhomed.
    pub fn new(
        device: DeviceParams,
        rate_hz: f32,
        contact: ContactParams,
        initial: LocalModelSpec,
        blend_s: f32,
    ) -> Result<Self, String> {
        let config = RendererConfig {
            rate_hz,
            blend_s,
            ..RendererConfig::DEFAULT
        };
        let renderer = LocalModelRenderer::new(config, contact, initial)
            .map_err(|e| format!("initial local model: {e:?}"))?;
        let limits = softfinger_core::devices::OMEGA_LIKE.limits;
        // Velocity low-pass as the controller's: α = ωT/(1 + ωT).
        let wt = 2.0 * std::f32::consts::PI * limits.velocity_cutoff_hz / rate_hz;
        Ok(LocalModelCore {
            device,
            rate_hz,
            renderer,
            watchdog: CommWatchdog::new(rate_hz, WATCHDOG_FADE_S),
            watchdog_s: 0.0,
            arm: Ramp::new(0.0, ARM_RAMP_S, rate_hz),
            mode: Mode::Unhomed,
            homing_ticks: 0,
            latched: Flags::NONE,
            max_counts_per_tick: limits.per_tick(rate_hz).max_counts_per_tick as u32,
            max_duty: limits.max_duty,
            alpha: wt / (1.0 + wt),
            prev: None,
        })
    }

    /// Kinematics and filtered velocities from the counts.
    fn measure(
        &mut self,
        counts: [i32; 6],
    ) -> (
        softfinger_core::delta::DeltaPose,
        ProbeSample,
        [f32; 3],
        Flags,
    ) {
        let dev = &self.device;
        let angles = [0, 1, 2].map(|i| dev.motor_counts_to_arm_angle_rad(counts[i]));
        let wrist = [3, 4, 5].map(|i| dev.wrist_counts_to_angle_rad(counts[i]));
        let (pose, flags) = dev.delta.pose::<Fast>(angles);
        let p = pose.effector_m;
        let prev = self.prev.unwrap_or(Prev {
            counts,
            probe_m: p,
            probe_vel: Vec3::ZERO,
            angles,
            arm_vel: [0.0; 3],
        });
        let glitch = counts
            .iter()
            .zip(prev.counts)
            .any(|(a, b)| a.wrapping_sub(b).unsigned_abs() > self.max_counts_per_tick);
        if glitch {
            self.latched |= Flags::ENCODER_GLITCH;
        }
        let probe_vel =
            prev.probe_vel + ((p - prev.probe_m) * self.rate_hz - prev.probe_vel) * self.alpha;
        let arm_vel = [0, 1, 2].map(|i| {
            prev.arm_vel[i]
                + ((angles[i] - prev.angles[i]) * self.rate_hz - prev.arm_vel[i]) * self.alpha
        });
        self.prev = Some(Prev {
            counts,
            probe_m: p,
            probe_vel,
            angles,
            arm_vel,
        });
        let sample = ProbeSample {
            q: DeviceParams::wrist_orientation::<Fast>(wrist),
            probe_m: p,
            probe_vel,
        };
        (pose, sample, arm_vel, flags)
    }

    /// The mode machine's part of the tick: homing completes, faults latch the mode.
    fn advance_mode(&mut self) {
        if !self.latched.is_empty() {
            self.mode = Mode::Faulted;
        } else if self.mode == Mode::Homing {
            self.homing_ticks = self.homing_ticks.saturating_sub(1);
            if self.homing_ticks == 0 {
                self.mode = Mode::Disarmed;
            }
        }
    }

    /// Force → duties, with the limits; a non-finite duty latches a fault.
    fn duties(
        &mut self,
        pose: &softfinger_core::delta::DeltaPose,
        force: Vec3,
        arm_vel: [f32; 3],
    ) -> ([f32; 3], Flags) {
        let (torques, mut flags) = self.device.delta.torques_at(pose, force);
        let max_t = softfinger_core::devices::OMEGA_LIKE
            .limits
            .max_arm_torque_nm;
        let mut duties = [0.0f32; 3];
        for i in 0..3 {
            let t = torques[i].clamp(-max_t, max_t);
            let (d, f) = self.device.arm_torque_to_duty_checked(t, arm_vel[i]);
            flags |= f & Flags::OUTPUT_LIMITED;
            if !d.is_finite() {
                self.latched |= Flags::NON_FINITE_OUTPUT;
            }
            duties[i] = if d.is_finite() {
                d.clamp(-self.max_duty, self.max_duty)
            } else {
                0.0
            };
        }
        (duties, flags)
    }
}

impl DeviceCore for LocalModelCore {
    fn rate_hz(&self) -> f32 {
        self.rate_hz
    }

    fn tick(&mut self, counts: [i32; 6]) -> CoreOutput {
        let (pose, sample, arm_vel, kflags) = self.measure(counts);
        let r = self.renderer.step(&sample);
        let (wd_gain, wd_flags) = self.watchdog.tick();
        self.advance_mode();
        let armed = self.mode == Mode::Armed;
        let gain = self.arm.advance(if armed { 1.0 } else { 0.0 }) * wd_gain;
        let force = r.force_n * gain;
        let trusted = !kflags.intersects(Flags::KINEMATICS_SINGULAR | Flags::NON_FINITE_INPUT);
        let (mut duties, dflags) = if armed && trusted {
            self.duties(&pose, force, arm_vel)
        } else {
            ([0.0; 3], Flags::NONE)
        };
        let faulted = !self.latched.is_empty();
        if faulted {
            duties = [0.0; 3];
            self.mode = Mode::Faulted;
        }
        let rendered = armed && trusted && !faulted;
        CoreOutput {
            duties,
            enable: rendered,
            probe_m: sample.probe_m,
            probe_vel_m_s: sample.probe_vel,
            force_n: if rendered { force } else { Vec3::ZERO },
            spin_torque_nm: if rendered { r.tau_n_nm * gain } else { 0.0 },
            contact: r.state,
            contact_point_m: r.contact_point_m,
            flags: r.flags | kflags | dflags | wd_flags | self.latched,
            mode: self.mode,
            model_seq: r.model_seq,
        }
    }

    fn request(&mut self, req: CoreRequest) -> AckResult {
        let err = AckResult::Err;
        match req {
            CoreRequest::Home => match self.mode {
                Mode::Faulted => err(ErrorCode::Faulted),
                Mode::Armed => err(ErrorCode::WrongMode),
                _ => {
                    self.mode = Mode::Homing;
                    self.homing_ticks = (HOMING_S * self.rate_hz) as u32;
                    AckResult::Ok
                }
            },
            CoreRequest::Arm => match self.mode {
                Mode::Faulted => err(ErrorCode::Faulted),
                Mode::Unhomed | Mode::Homing => err(ErrorCode::WrongMode),
                Mode::Disarmed | Mode::Armed => {
                    self.watchdog.feed();
                    self.watchdog.rearm();
                    self.mode = Mode::Armed;
                    AckResult::Ok
                }
            },
            CoreRequest::Disarm => {
                if self.mode == Mode::Armed {
                    self.mode = Mode::Disarmed;
                    self.arm.set(0.0);
                }
                AckResult::Ok
            }
            CoreRequest::ClearFaults => {
                self.latched = Flags::NONE;
                self.prev = None;
                if self.mode == Mode::Faulted {
                    self.mode = Mode::Disarmed;
                }
                AckResult::Ok
            }
            CoreRequest::SetContactParams(p) => {
                if self.mode == Mode::Armed {
                    return err(ErrorCode::WrongMode);
                }
                match self.renderer.set_base_params(p) {
                    Ok(()) => AckResult::Ok,
                    Err(_) => err(ErrorCode::InvalidValue),
                }
            }
            CoreRequest::SetLocalModel(spec) => match self.renderer.accept(spec) {
                Ok(()) => AckResult::Ok,
                Err(ModelError::StaleSequence) => err(ErrorCode::StaleSequence),
                Err(_) => err(ErrorCode::InvalidValue),
            },
            CoreRequest::SetWatchdog { timeout_s } => {
                if !(0.0..=60.0).contains(&timeout_s) {
                    return err(ErrorCode::InvalidValue);
                }
                self.watchdog.set_timeout(timeout_s, self.rate_hz);
                self.watchdog_s = timeout_s;
                AckResult::Ok
            }
        }
    }

    fn message_received(&mut self) {
        self.watchdog.feed();
    }

    fn contact_params(&self) -> ContactParams {
        *self.renderer.base_params()
    }

    fn watchdog_s(&self) -> f32 {
        self.watchdog_s
    }
}

/// The initial model and contact parameters of a scene (plane top or sphere centre in the base
/// frame, as the closed-loop runs place them).
pub fn scene_model(scene: &crate::scene::Scene) -> Result<(ContactParams, LocalModelSpec), String> {
    let contact = crate::closed_loop::contact_params(scene)?;
    let top = crate::closed_loop::surface_top_z_m() as f32;
    let (kind, z) = match scene.surface {
        crate::scene::SurfaceSpec::Plane => (softfinger_core::local_model::ModelKind::Plane, top),
        crate::scene::SurfaceSpec::Sphere { radius_m } => (
            softfinger_core::local_model::ModelKind::Sphere {
                radius_m: radius_m as f32,
            },
            top - radius_m as f32,
        ),
        other => {
            return Err(format!(
                "scene '{}': the virtual device renders plane and sphere local models, not a {}",
                scene.name,
                other.kind()
            ))
        }
    };
    let spec = LocalModelSpec {
        kind,
        ..LocalModelSpec::plane(
            0,
            softfinger_core::local_model::ModelPose::at(Vec3::new(0.0, 0.0, z)),
            &contact,
        )
    };
    Ok((contact, spec))
}

#[cfg(test)]
#[path = "core_tests.rs"]
mod tests;
