//! The hardware-independent control law: six encoder counts in, three motor duties out.
//!
//! [`Controller::compute`]: motor angles → delta forward kinematics (probe position) → wrist
//! orientation → contact step (rolling, spin torque, state machine, proxy force) → Jacobian-transpose
//! motor torques → duties. [`Controller::tick`] runs it through an [`OutputGuard`] (fault inputs,
//! encoder checks, the latch, the output limits). The firmware and host-sim run it inside the
//! control pipeline ([`crate::control::pipeline`]), which calls `compute` and its own guard.
//!
//! Frames: the device **base frame** is the delta's (see [`crate::device::delta`]); the object frame
//! is the base frame translated by `object_origin_m` (no rotation), so forces computed in the object
//! frame apply unchanged in the base frame.
//!
//! Safety (through the guard): any fault — driver fault input, encoder glitch, encoder stuck under
//! drive, non-finite output, an overrun streak — is latched: duties are zero and `enable` is false
//! from that tick on, until [`Controller::clear_faults`]. The latching set and the thresholds are
//! defined once, in [`crate::control::output_guard`] and [`Limits`].

use crate::contact::params::{ContactParams, ParamsChange};
use crate::contact::surface::Plane;
use crate::contact::{ContactInput, ContactOutput};
use crate::control::controller::passivity::{Passivity, PassivityConfig};
use crate::control::output_guard::{GuardConfig, Guarded, OutputGuard};
use crate::device::channels::{EncoderCounts, CHANNELS};
use crate::device::delta::DeltaPose;
use crate::device::DeviceParams;
use crate::flags::Flags;
use crate::math::quat::Quat;
use crate::math::vec3::Vec3;
use crate::math::Math;
use crate::validate::Checked;
pub use crate::validate::ParamError;

pub mod config;
pub mod passivity;
pub mod stage;
pub mod tick;
pub use config::{ControllerConfig, Limits, TickLimits};
pub use stage::{ContactStage, Environment, WithParts};
pub use tick::{TickInput, TickOutput};

/// The controller with its state. `M`: math backend; `S`: the environment (a fixed surface or the
/// local model), whose [`ContactStage`] the control law calls.
///
/// [`Controller::compute`] is the control law alone (no fault latch); [`Controller::tick`] runs it
/// through the controller's own [`OutputGuard`], the one implementation of the latching set and
/// its thresholds, for callers that use the controller without the
/// [`Pipeline`](crate::control::pipeline::Pipeline) (which has its own guard instance and calls `compute`).
#[derive(Clone, Copy, Debug)]
pub struct Controller<M: Math, S: Environment = Plane> {
    config: ControllerConfig<S>,
    contact: S::Stage<M>,
    guard: OutputGuard,
    dt_s: f32,
    /// Low-pass coefficient α of the velocity filters: v ← v + α·(v_raw − v).
    alpha: f32,
    /// False until the first tick: the velocity filters start from that tick's position.
    started: bool,
    /// The previous tick's probe position, object frame, m.
    prev_probe: Vec3,
    /// Filtered probe velocity, object frame, m/s.
    probe_vel: Vec3,
    /// The previous tick's arm angles, rad.
    prev_angles: [f32; 3],
    /// Filtered arm angular velocities, rad/s (the back-EMF feed-forward).
    arm_vel: [f32; 3],
    /// Scale on every rendered force, 0..=1 (the arming ramp).
    force_scale: f32,
    /// Flags raised between ticks, reported with the next one.
    pending: Flags,
    /// The passivity observer and controller (on by default).
    passivity: Passivity,
    /// The device's arm angle per extended motor count, rad/count
    /// ([`DeviceParams::arm_rad_per_motor_count`], computed once: the device never changes).
    arm_rad_per_count: f32,
    /// The device's wrist angle per count, rad/count ([`DeviceParams::wrist_rad_per_count`]).
    wrist_rad_per_count: f32,
}

/// Faults that latch: the outputs stay at zero torque until an explicit clear (one set, defined
/// with the guard that enforces it).
pub use crate::control::output_guard::LATCHING;

impl<M: Math, S: Environment> Controller<M, S> {
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
            arm_rad_per_count: config.device.arm_rad_per_motor_count(),
            wrist_rad_per_count: config.device.wrist_rad_per_count(),
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

    /// Change the contact parameters at run time (checked where they arrived: [`ContactParams::checked`]).
    /// A refusal keeps the old ones and raises [`Flags::PARAM_REJECTED`] on the next tick. A
    /// change restarts the contact, or blends the material in when nothing else changed (the
    /// stage's [`ParamsChange`]).
    pub fn set_contact_params(
        &mut self,
        p: &Checked<ContactParams>,
    ) -> Result<ParamsChange, ParamError> {
        match self.contact.set_contact_params(p) {
            Ok(change) => {
                // A blend changed the material only: five fields, not a copy of the whole.
                match change {
                    ParamsChange::Blended => self.config.contact.take_material_of(p),
                    ParamsChange::Restarted => self.config.contact = **p,
                }
                self.passivity.set_contact(stored_spring(p), p.max_force_n);
                self.passivity.restart();
                Ok(change)
            }
            Err(e) => {
                self.params_refused();
                Err(e)
            }
        }
    }

    /// Contact parameters were refused where they arrived: [`Flags::PARAM_REJECTED`] on the next
    /// tick, as for a refusal here.
    pub fn params_refused(&mut self) {
        self.pending |= Flags::PARAM_REJECTED;
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
    pub fn compute(&mut self, counts: &[i32; CHANNELS]) -> TickOutput {
        let mut flags = self.pending;
        self.pending = Flags::NONE;

        // Kinematics.
        let dev = &self.config.device;
        let named = EncoderCounts::from(*counts);
        // `DeviceParams::motor_counts_to_arm_angle_rad` and `wrist_counts_to_angle_rad` with
        // their scales computed once (the same operations, so the same bits).
        let (k_arm, k_wrist) = (self.arm_rad_per_count, self.wrist_rad_per_count);
        let angles = named
            .motor
            .map(|c| dev.arm_angle_at_zero_count_rad + c as f32 * k_arm);
        let wrist = named.wrist.map(|c| c as f32 * k_wrist);
        let (pose, mut kflags) = dev.delta.pose::<M>(angles);
        let [lo, hi] = self.config.limits.arm_angle_range_rad;
        if angles.iter().any(|a| !(lo..=hi).contains(a)) {
            kflags |= Flags::OUT_OF_RANGE;
        }
        flags |= kflags;
        let q = DeviceParams::wrist_orientation::<M>(wrist);
        let probe_dev = pose.effector_m;

        // Velocities: filtered finite differences.
        self.update_velocities(probe_dev, angles);

        // Contact: only with trustworthy kinematics, otherwise no force this tick.
        let trusted = !kflags
            .intersects(Flags::KINEMATICS_SINGULAR | Flags::NON_FINITE_INPUT | Flags::OUT_OF_RANGE);
        let (contact, force_n) = self.contact_force(trusted, q, probe_dev);
        flags |= contact.flags;

        // Motor torques and duties.
        let duties = self.duties(trusted, &pose, force_n, &mut flags);
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

    /// Velocity stage: low-pass filtered finite differences of the probe position (base frame,
    /// m) and the arm angles (rad); the first tick after a restart starts them at zero.
    #[inline(always)]
    fn update_velocities(&mut self, probe_dev: Vec3, angles: [f32; 3]) {
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
    }

    /// Contact stage: the contact step (only with `trusted` kinematics; otherwise no force this
    /// tick), the arming ramp's scale and the passivity observer. Returns the contact's output
    /// and the force to render (base frame, N).
    #[inline(always)]
    fn contact_force(&mut self, trusted: bool, q: Quat, probe_dev: Vec3) -> (ContactOutput, Vec3) {
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
        (contact, force_n)
    }

    /// Drive stage: Jacobian-transpose arm torques for `force_n` (base frame, N), limited to
    /// the limits' torque, then duties with back-EMF feed-forward. Untrusted kinematics give
    /// zero duties; the stage's flags are added to `flags`.
    #[inline(always)]
    fn duties(
        &self,
        trusted: bool,
        pose: &DeltaPose,
        force_n: Vec3,
        flags: &mut Flags,
    ) -> [f32; 3] {
        let dev = &self.config.device;
        let max_arm_torque_nm = self.config.limits.max_arm_torque_nm;
        let (torques, jflags) = dev.delta.torques_at(pose, force_n);
        *flags |= jflags;
        let mut duties = [0.0f32; 3];
        for i in 0..3 {
            let mut t = if !trusted || jflags.intersects(Flags::KINEMATICS_SINGULAR) {
                0.0
            } else {
                torques[i]
            };
            if t.abs() > max_arm_torque_nm {
                t = libm::copysignf(max_arm_torque_nm, t);
                *flags |= Flags::OUTPUT_LIMITED;
            }
            // Untrusted kinematics: the velocities are as wrong as the angles, so no back-EMF
            // feed-forward either: zero duty.
            let (mut d, dflags) = if trusted {
                dev.arm_torque_to_duty_checked(t, self.arm_vel[i])
            } else {
                (0.0, Flags::NONE)
            };
            *flags |= dflags & Flags::OUTPUT_LIMITED;
            if !d.is_finite() {
                d = 0.0;
                *flags |= Flags::NON_FINITE_OUTPUT;
            }
            duties[i] = d;
        }
        duties
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
