//! The hardware-independent control law: six encoder counts in, three motor duties out.
//!
//! [`Controller::compute`]: motor angles → delta forward kinematics (probe position) → wrist
//! orientation → contact step (rolling, spin torque, state machine, proxy force) → Jacobian-transpose
//! motor torques → duties. [`Controller::tick`] runs it through an [`OutputGuard`] (fault inputs,
//! encoder checks, the latch, the output limits). The firmware and host-sim run it inside the
//! control pipeline ([`crate::pipeline`]), which calls `compute` and its own guard.
//!
//! Frames: the device **base frame** is the delta's (see [`crate::delta`]); the object (scene) frame
//! is the base frame translated by `object_origin_m` (no rotation), so forces computed in the object
//! frame apply unchanged in the base frame.
//!
//! Safety (through the guard): any fault — driver fault input, encoder glitch, encoder stuck under
//! drive, non-finite output, an overrun streak — is latched: duties are zero and `enable` is false
//! from that tick on, until [`Controller::clear_faults`]. The latching set and the thresholds are
//! defined once, in [`crate::output_guard`] and [`Limits`].

use crate::contact::{ContactInput, ContactOutput};
use crate::contact_state::ContactState;
use crate::device::DeviceParams;
use crate::flags::Flags;
use crate::math::Math;
use crate::output_guard::{GuardConfig, Guarded, OutputGuard};
pub use crate::params::ParamError;
use crate::params::{positive, ContactParams};
use crate::pipeline::passivity::{Passivity, PassivityConfig};
use crate::surface::Plane;
use crate::vec3::Vec3;

pub mod stage;
pub use stage::{ContactStage, Scene};

/// What the firmware (or the host plant) hands the controller each tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TickInput {
    /// Extended 32-bit encoder positions, counts: `[motor0, motor1, motor2, wrist0, wrist1, wrist2]`.
    pub counts: [i32; 6],
    /// The motor drivers' fault input is asserted.
    pub driver_fault: bool,
    /// The previous tick did not finish before this one started.
    pub overrun: bool,
}

/// What the controller hands back.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TickOutput {
    /// Signed PWM duties in [-1, 1] per motor: sign is the direction pin, magnitude the duty.
    pub duties: [f32; 3],
    /// Drive the shared driver-enable pin. False in any fault: outputs at zero torque.
    pub enable: bool,
    /// Flags raised this tick, including the latched fault flags.
    pub flags: Flags,
    /// Probe (fingertip centre) position in the device base frame, m.
    pub probe_m: Vec3,
    /// Force rendered on the user, base frame, N.
    pub force_n: Vec3,
    /// Spin torque about the contact normal, N·m (not displayed by a 3-DoF device; reported).
    pub tau_n_nm: f32,
    /// Contact state after this tick.
    pub state: ContactState,
}

/// Limits and fault thresholds, in physical units so that changing the control rate changes no
/// behaviour; [`Limits::per_tick`] converts them for a rate.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Limits {
    /// Largest |duty| ever output, (0, 1].
    pub max_duty: f32,
    /// Largest motor-side arm torque requested, N·m.
    pub max_arm_torque_nm: f32,
    /// An encoder moving faster than this between two ticks is a glitch, counts/s.
    pub glitch_counts_per_s: f32,
    /// Overrunning ticks for this long in a row latch a fault, s.
    pub overrun_streak_s: f32,
    /// |duty| at or above this, with no count change for `stuck_s`, latches ENCODER_STUCK.
    pub stuck_duty: f32,
    /// Time of drive without motion before ENCODER_STUCK, s.
    pub stuck_s: f32,
    /// Cut-off of the first-order low-pass on the finite-difference velocities, Hz.
    pub velocity_cutoff_hz: f32,
    /// Arm angles outside [min, max] (rad) cannot be reached by the mechanism: the encoders or
    /// their calibration are wrong, so no force is rendered ([`Flags::OUT_OF_RANGE`]).
    pub arm_angle_range_rad: [f32; 2],
}

/// [`Limits`] converted for one control rate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TickLimits {
    /// A count change larger than this in one tick is a glitch: round(glitch_counts_per_s / rate),
    /// at least 1, at most 32 767 (beyond that a 16-bit wrapping difference cannot tell).
    pub max_counts_per_tick: u16,
    /// Consecutive overrun ticks that latch OVERRUN: round(overrun_streak_s · rate), at least 1.
    pub overrun_streak: u32,
    /// Ticks of drive without motion before ENCODER_STUCK: round(stuck_s · rate), at least 1.
    pub stuck_ticks: u32,
}

impl Limits {
    /// The Omega-like device's limits (named by [`crate::devices::OMEGA_LIKE`]).
    ///
    /// - duty ≤ 0.9: leaves bootstrap and current-sense margin on the bridge;
    /// - glitch: 2 M counts/s, three times the motor's no-load speed at 24 V (24 V / k_e =
    ///   1026 rad/s = 669 k counts/s with 4096 counts per turn): 200 counts per tick at 10 kHz,
    ///   100 at 20 kHz;
    /// - overrun streak: 1 ms (10 ticks at 10 kHz, 20 at 20 kHz);
    /// - stuck: 20 % duty for 0.2 s without a single count: a hand holding the handle still
    ///   against that drive still moves it by more than a count (physiological tremor). The duty
    ///   threshold must lie below the largest duty at stall, R·i_max/V = 2.18·4/24 = 0.363: a
    ///   frozen encoder reads zero velocity, so its motor gets no back-EMF feed-forward and its
    ///   duty never exceeds that. At the 12 N force limit the duties of the touch scene reach
    ///   about 0.24.
    pub const OMEGA_LIKE: Limits = Limits {
        max_duty: 0.9,
        max_arm_torque_nm: 2.0,
        glitch_counts_per_s: 2.0e6,
        overrun_streak_s: 1.0e-3,
        stuck_duty: 0.2,
        stuck_s: 0.2,
        velocity_cutoff_hz: 300.0,
        // The Omega-like linkage needs −31° … 94° over its workspace (see `crate::delta`); the
        // range allows margin for the workspace's edge.
        arm_angle_range_rad: [-1.05, 2.1],
    };

    /// Check every field.
    pub fn validate(&self) -> Result<(), ParamError> {
        positive("max_duty", self.max_duty)?;
        if self.max_duty > 1.0 {
            return Err(ParamError::OutOfRange("max_duty"));
        }
        positive("max_arm_torque_nm", self.max_arm_torque_nm)?;
        positive("glitch_counts_per_s", self.glitch_counts_per_s)?;
        positive("overrun_streak_s", self.overrun_streak_s)?;
        positive("stuck_duty", self.stuck_duty)?;
        positive("stuck_s", self.stuck_s)?;
        positive("velocity_cutoff_hz", self.velocity_cutoff_hz)?;
        let [lo, hi] = self.arm_angle_range_rad;
        if !lo.is_finite() || !hi.is_finite() {
            return Err(ParamError::NotFinite("arm_angle_range_rad"));
        }
        if lo >= hi {
            return Err(ParamError::OutOfRange("arm_angle_range_rad"));
        }
        Ok(())
    }

    /// The thresholds in ticks at `rate_hz` (see [`TickLimits`] for the rounding).
    pub fn per_tick(&self, rate_hz: f32) -> TickLimits {
        let glitch = round_at_least_one(self.glitch_counts_per_s / rate_hz).min(32_767);
        TickLimits {
            max_counts_per_tick: glitch as u16,
            overrun_streak: round_at_least_one(self.overrun_streak_s * rate_hz),
            stuck_ticks: round_at_least_one(self.stuck_s * rate_hz),
        }
    }
}

/// Round a non-negative value to the nearest integer, at least 1, saturating; NaN → 1.
fn round_at_least_one(x: f32) -> u32 {
    let r = x + 0.5;
    if r.is_nan() || r < 1.0 {
        1
    } else if r >= u32::MAX as f32 {
        u32::MAX
    } else {
        r as u32
    }
}

/// Everything the controller needs to know about the device and the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ControllerConfig<S: Scene = Plane> {
    /// Control rate, Hz (1 kHz to 40 kHz).
    pub rate_hz: f32,
    /// The device: kinematics, motors, encoders.
    pub device: DeviceParams,
    /// The contact model.
    pub contact: ContactParams,
    /// The scene: a fixed surface, or the local model (see [`stage`]).
    pub surface: S,
    /// Origin of the object frame in the device base frame, m.
    pub object_origin_m: Vec3,
    /// Limits and fault thresholds.
    pub limits: Limits,
}

impl ControllerConfig<Plane> {
    /// The Omega-like device ([`DeviceParams::OMEGA_LIKE`], [`Limits::OMEGA_LIKE`]) with the
    /// default scene: a plane 10 mm below the centre of the device's workspace, so the 10 mm
    /// fingertip touches it with its centre at the workspace centre, at 10 kHz.
    pub fn default_plane() -> Self {
        ControllerConfig {
            rate_hz: 10_000.0,
            device: DeviceParams::OMEGA_LIKE,
            contact: ContactParams::DEFAULT,
            surface: Plane::default(),
            object_origin_m: crate::delta::DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M
                - Vec3::new(0.0, 0.0, 0.010),
            limits: Limits::OMEGA_LIKE,
        }
    }
}

impl<S: Scene> ControllerConfig<S> {
    /// Check every part.
    pub fn validate(&self) -> Result<(), ParamError> {
        positive("rate_hz", self.rate_hz)?;
        if !(1_000.0..=40_000.0).contains(&self.rate_hz) {
            return Err(ParamError::OutOfRange("rate_hz"));
        }
        self.device.validate().map_err(ParamError::Device)?;
        self.contact.validate()?;
        self.limits.validate()?;
        if !self.object_origin_m.is_finite() {
            return Err(ParamError::NotFinite("object_origin_m"));
        }
        Ok(())
    }
}

/// The controller with its state. `M`: math backend; `S`: the scene (a fixed surface or the
/// local model), whose [`ContactStage`] the control law calls.
///
/// [`Controller::compute`] is the control law alone (no fault latch); [`Controller::tick`] runs it
/// through the controller's own [`OutputGuard`], the one implementation of the latching set and
/// its thresholds, for callers that use the controller without the
/// [`Pipeline`](crate::pipeline::Pipeline) (which has its own guard instance and calls `compute`).
#[derive(Clone, Copy, Debug)]
pub struct Controller<M: Math, S: Scene = Plane> {
    config: ControllerConfig<S>,
    contact: S::Stage<M>,
    guard: OutputGuard,
    dt_s: f32,
    /// Low-pass coefficient α of the velocity filters: v ← v + α·(v_raw − v).
    alpha: f32,
    started: bool,
    prev_probe: Vec3,
    probe_vel: Vec3,
    prev_angles: [f32; 3],
    arm_vel: [f32; 3],
    force_scale: f32,
    pending: Flags,
    /// The passivity observer and controller (on by default).
    passivity: Passivity,
}

/// Faults that latch: the outputs stay at zero torque until an explicit clear (one set, defined
/// with the guard that enforces it).
pub use crate::output_guard::LATCHING;

impl<M: Math, S: Scene> Controller<M, S> {
    /// Build a controller; an invalid configuration is rejected, never clamped.
    pub fn new(config: ControllerConfig<S>) -> Result<Self, ParamError> {
        config.validate()?;
        let dt_s = 1.0 / config.rate_hz;
        let contact = config.surface.stage::<M>(config.contact, dt_s)?;
        let guard = OutputGuard::new(GuardConfig::from_limits(&config.limits, config.rate_hz))?;
        // α = 1 − exp(−2π·f_c·T) ≈ 2π·f_c·T/(1 + 2π·f_c·T) (bilinear-free, no exp on the MCU).
        let wt = 2.0 * core::f32::consts::PI * config.limits.velocity_cutoff_hz * dt_s;
        Ok(Controller {
            config,
            contact,
            guard,
            dt_s,
            alpha: wt / (1.0 + wt),
            started: false,
            prev_probe: Vec3::ZERO,
            probe_vel: Vec3::ZERO,
            prev_angles: [0.0; 3],
            arm_vel: [0.0; 3],
            force_scale: 1.0,
            pending: Flags::NONE,
            passivity: Passivity::new(
                PassivityConfig {
                    enabled: S::PASSIVITY_DAMPS,
                    ..PassivityConfig::DEFAULT
                },
                dt_s,
                stored_spring(&config.contact),
                config.contact.max_force_n,
            )?,
        })
    }

    /// The configuration in force.
    pub fn config(&self) -> &ControllerConfig<S> {
        &self.config
    }

    /// The contact stage (read-only view for logs and charts).
    pub fn contact(&self) -> &S::Stage<M> {
        &self.contact
    }

    /// The contact stage, for the commands it understands (local model, watchdog, link).
    pub fn contact_mut(&mut self) -> &mut S::Stage<M> {
        &mut self.contact
    }

    /// The filtered probe velocity of the last tick, base frame, m/s.
    pub fn probe_velocity(&self) -> Vec3 {
        self.probe_vel
    }

    /// The contact point after the last tick, base frame, m.
    pub fn contact_point_m(&self) -> Vec3 {
        self.contact.contact_point_m() + self.config.object_origin_m
    }

    /// Latched faults of [`Self::tick`]'s guard (empty when the outputs are allowed).
    #[must_use]
    pub fn latched_faults(&self) -> Flags {
        self.guard.latched()
    }

    /// Clear latched faults (an explicit operator action). The next tick starts afresh: no velocity
    /// history, contact broken.
    pub fn clear_faults(&mut self) {
        self.guard.clear();
        self.restart();
    }

    /// Forget the velocity history and break the contact (after a fault, a re-homing, an arming).
    pub fn restart(&mut self) {
        self.started = false;
        self.passivity.restart();
        self.contact.restart();
    }

    /// The passivity stage (read-only, for logs and charts).
    pub fn passivity(&self) -> &Passivity {
        &self.passivity
    }

    /// Replace the passivity stage's parameters (its history restarts). Invalid values are
    /// rejected and the old ones stay.
    pub fn set_passivity(&mut self, config: PassivityConfig) -> Result<(), ParamError> {
        let c = &self.config.contact;
        self.passivity = Passivity::new(config, self.dt_s, stored_spring(c), c.max_force_n)?;
        Ok(())
    }

    /// Scale the rendered force by `scale` in [0, 1] (the arming ramp). Out-of-range or NaN
    /// values are clamped to [0, 1] (NaN → 0).
    pub fn set_force_scale(&mut self, scale: f32) {
        self.force_scale = if scale >= 1.0 {
            1.0
        } else if scale > 0.0 {
            scale
        } else {
            0.0
        };
    }

    /// Change the contact parameters at run time. Invalid values are rejected (the old ones stay)
    /// and [`Flags::PARAM_REJECTED`] is raised on the next tick. A valid change restarts the contact.
    pub fn set_contact_params(&mut self, p: ContactParams) -> Result<(), ParamError> {
        match self.contact.set_contact_params(p) {
            Ok(()) => {
                self.config.contact = p;
                self.passivity.set_contact(stored_spring(&p), p.max_force_n);
                self.passivity.restart();
                Ok(())
            }
            Err(e) => {
                self.pending |= Flags::PARAM_REJECTED;
                Err(e)
            }
        }
    }

    /// One control tick through the controller's guard. Never panics; any fault gives zero duties
    /// and `enable = false`, latched until [`Self::clear_faults`].
    pub fn tick(&mut self, input: &TickInput) -> TickOutput {
        let raw = self.compute(&input.counts);
        let events = if input.driver_fault {
            Flags::DRIVER_FAULT
        } else {
            Flags::NONE
        };
        let g = self.guard.apply(&input.counts, &raw, events, input.overrun);
        guarded_output(raw, &g)
    }

    /// The control law alone: counts (homed, extended) in, duties out, no fault latch. A
    /// non-finite duty is replaced by zero and reported as [`Flags::NON_FINITE_OUTPUT`]; a
    /// non-finite force or torque is passed on for the guard, which flags and latches it (and then
    /// reports zero); duties are not limited here beyond the device's ±1 (the guard limits them).
    /// Use it only through a guard ([`Self::tick`] or the pipeline).
    pub fn compute(&mut self, counts: &[i32; 6]) -> TickOutput {
        let mut flags = self.pending;
        self.pending = Flags::NONE;
        let lim = self.config.limits;
        let dev = self.config.device;

        // Kinematics.
        let mut angles = [0.0f32; 3];
        for (a, c) in angles.iter_mut().zip(counts.iter()) {
            *a = dev.motor_counts_to_arm_angle_rad(*c);
        }
        let wrist = [
            dev.wrist_counts_to_angle_rad(counts[3]),
            dev.wrist_counts_to_angle_rad(counts[4]),
            dev.wrist_counts_to_angle_rad(counts[5]),
        ];
        let (pose, mut kflags) = dev.delta.pose::<M>(angles);
        let probe_dev = pose.effector_m;
        let [lo, hi] = lim.arm_angle_range_rad;
        if angles.iter().any(|a| !(lo..=hi).contains(a)) {
            kflags |= Flags::OUT_OF_RANGE;
        }
        flags |= kflags;
        let q = DeviceParams::wrist_orientation::<M>(wrist);

        // Velocities: filtered finite differences.
        let inv_dt = self.config.rate_hz;
        if !self.started {
            self.prev_probe = probe_dev;
            self.prev_angles = angles;
            self.probe_vel = Vec3::ZERO;
            self.arm_vel = [0.0; 3];
        }
        self.started = true;
        self.probe_vel += ((probe_dev - self.prev_probe) * inv_dt - self.probe_vel) * self.alpha;
        for ((v, a), a_prev) in self.arm_vel.iter_mut().zip(angles).zip(self.prev_angles) {
            *v += ((a - a_prev) * inv_dt - *v) * self.alpha;
        }
        self.prev_probe = probe_dev;
        self.prev_angles = angles;

        // Contact: only with trustworthy kinematics, otherwise no force this tick.
        let trusted = !kflags
            .intersects(Flags::KINEMATICS_SINGULAR | Flags::NON_FINITE_INPUT | Flags::OUT_OF_RANGE);
        let contact = if !trusted {
            ContactOutput {
                state: self.contact.state(),
                ..ContactOutput::default()
            }
        } else {
            self.contact.step(&ContactInput {
                q,
                probe_m: probe_dev - self.config.object_origin_m,
                probe_vel: self.probe_vel,
            })
        };
        flags |= contact.flags;
        let force_n = contact.force_n * self.force_scale;
        // Passivity: observe the energy into the user, damp it away when it turns positive. The
        // arming ramp scales a stored force up in place (a deliberate, bounded energy source):
        // the observer starts when the ramp is done.
        // While the communication watchdog holds the force down (COMM_TIMEOUT) the observer
        // stands aside too: its damper would keep pushing on a moving probe after the
        // application fell silent, and the watchdog's fade must end at zero force.
        let held_down = contact.flags.intersects(Flags::COMM_TIMEOUT);
        let force_n = if trusted && self.force_scale >= 1.0 && !held_down {
            self.passivity
                .step(force_n, probe_dev, self.probe_vel)
                .force_n
        } else {
            self.passivity.restart();
            force_n
        };

        // Motor torques and duties.
        let (torques, jflags) = dev.delta.torques_at(&pose, force_n);
        flags |= jflags;
        let mut duties = [0.0f32; 3];
        for i in 0..3 {
            let mut t = if !trusted || jflags.intersects(Flags::KINEMATICS_SINGULAR) {
                0.0
            } else {
                torques[i]
            };
            if t.abs() > lim.max_arm_torque_nm {
                t = libm::copysignf(lim.max_arm_torque_nm, t);
                flags |= Flags::OUTPUT_LIMITED;
            }
            // Untrusted kinematics: the velocities are as wrong as the angles, so no back-EMF
            // feed-forward either: zero duty.
            let (mut d, dflags) = if trusted {
                dev.arm_torque_to_duty_checked(t, self.arm_vel[i])
            } else {
                (0.0, Flags::NONE)
            };
            flags |= dflags & Flags::OUTPUT_LIMITED;
            if !d.is_finite() {
                d = 0.0;
                flags |= Flags::NON_FINITE_OUTPUT;
            }
            duties[i] = d;
        }
        let probe_m = if probe_dev.is_finite() {
            probe_dev
        } else {
            Vec3::ZERO
        };
        TickOutput {
            duties,
            enable: true,
            flags,
            probe_m,
            force_n,
            tau_n_nm: contact.tau_n_nm * self.force_scale,
            state: contact.state,
        }
    }
}

/// The stiffest spring of a contact (normal or tangential), N/m: the passivity observer's
/// estimate of the energy a rendered force holds (|F|²/(2K) is least for the stiffest).
fn stored_spring(c: &ContactParams) -> f32 {
    c.normal_stiffness.max(c.tangential_stiffness)
}

/// The controller's raw output after a guard: the guard's duties, enable and flags; force and
/// torque zero whenever the guard disabled the outputs.
pub fn guarded_output(raw: TickOutput, g: &Guarded) -> TickOutput {
    TickOutput {
        duties: g.duties,
        enable: g.enable,
        flags: g.flags,
        force_n: if g.enable { raw.force_n } else { Vec3::ZERO },
        tau_n_nm: if g.enable { raw.tau_n_nm } else { 0.0 },
        ..raw
    }
}

#[cfg(test)]
mod tests;
