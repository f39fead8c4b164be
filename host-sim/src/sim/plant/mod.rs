//! A software plant of the Omega-like device and the user's hand, for closed-loop runs of the
//! controller on the host.
//!
//! The plant is coupled to the control pipeline exactly as the MCU is: **wrapping 16-bit timer
//! counts out ([`Plant::raw_counts`]), bridge commands in ([`Plant::step_bridges`])**: phase
//! pins, PWM compares (preloaded: acting from the next PWM period boundary), enable and sleep,
//! with the board timing the firmware uses. It shares only `DeviceParams` and that timing with the
//! pipeline; its kinematics, dynamics and numbers are its own, in f64.
//!
//! Per control tick the host runs:
//!
//! ```text
//! let raw = plant.raw_counts();            // sampled at t_k
//! let out = pipeline.tick(&RawInput { counts: raw, .. });
//! plant.step_bridges(&out.bridges, &timing); // written at t_k; compares act from t_k + T_pwm
//! ```
//!
//! The plant's own unit tests also drive it with plain duties ([`Plant::step`]), which act one
//! tick late through [`pwm::OutputLatch`].
//!
//! Model, per sub-step h = dt / `substeps` (semi-implicit Euler for the mechanics, exact
//! exponential for the winding current with the velocity held):
//! - [`motor`]: duty (quantised to the PWM timer) × supply voltage into L·di/dt = V − R·i −
//!   k_e·ω_motor, current limit, torque ratio·k_t·i at the arm, viscous plus smoothed Coulomb
//!   friction;
//! - [`mechanism`]: f64 delta kinematics; [`dynamics`]: (I_a + m·JᵀJ)·θ̈ = Q − m·Jᵀ·a_b;
//! - [`hand`]: the user's hand, a mass on the handle pulled by a spring-damper towards a
//!   scripted reference; the passive wrist follows the script's angles;
//! - [`encoder`]: angles to extended counts; mechanical stops at the arm limits.

pub mod dynamics;
pub mod encoder;
pub mod hand;
pub mod linalg;
pub mod mechanism;
pub mod motor;
pub mod params;
pub mod pwm;
pub mod timing;

use softfinger_core::control::pipeline::{BoardTiming, BridgeCommands};
use softfinger_core::device::{DeviceParamError, DeviceParams};

pub use hand::{HandRef, HandScript, ScriptError};
#[allow(unused_imports)] // the rest of the public script API, for the CLI
pub use hand::{Phase, TouchScript, Waypoint};
pub use params::{PlantParamError, PlantParams};
pub use pwm::DriveCommand;

use dynamics::Inertia;
use mechanism::{Kinematics, Mechanism, V3};
use motor::Motor;
use pwm::{BridgeStage, OutputLatch};

/// Why a plant could not be built.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum PlantError {
    /// The device definition was rejected.
    #[error("device parameters: {0}")]
    Device(DeviceParamError),
    /// A plant parameter was rejected.
    #[error("plant parameters: {0}")]
    Params(PlantParamError),
    /// The hand script was rejected.
    #[error("hand script: {0}")]
    Script(ScriptError),
    /// The script's start position is out of the linkage's reach or outside the arm stops.
    #[error("the script's start position is out of the linkage's reach or outside the arm stops")]
    StartOutOfReach,
}

/// Everything the plant knows at one instant, for charts and checks. Frame `B`, SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlantTruth {
    pub time_s: f64,
    pub arm_angles_rad: [f64; 3],
    pub arm_velocities_rad_s: [f64; 3],
    pub motor_currents_a: [f64; 3],
    pub effector_position_m: [f64; 3],
    pub effector_velocity_m_s: [f64; 3],
    /// Force the hand applies to the handle, N.
    pub hand_force_n: [f64; 3],
    /// The hand's scripted reference (position, velocity, wrist angles, phase).
    pub hand_reference: HandRef,
    /// The drive command applied during the last tick.
    pub applied: DriveCommand,
    /// Sub-steps at which the linkage would have left its assemblable set (state held instead).
    pub jam_events: u64,
    /// Non-finite duties received (applied as 0, as the firmware's conversion does).
    pub non_finite_duties: u64,
    /// Time each bridge drove with the phase opposite to its compare's (bridge commands only), s.
    pub wrong_direction_s: [f64; 3],
    /// Phase pin changes while enabled (bridge commands only).
    pub reversals: u64,
}

/// The device and the user's hand, simulated.
#[derive(Clone, Debug)]
pub struct Plant {
    device: DeviceParams,
    params: PlantParams,
    script: HandScript,
    mechanism: Mechanism,
    motor: Motor,
    inertia: Inertia,
    latch: OutputLatch,
    bridge: BridgeStage,
    applied: DriveCommand,
    /// The plant's parameters as built (the hand comes back from here after a release).
    built_params: PlantParams,
    /// Extended counts at power-up: the hardware counters read 0 there.
    counter_origin: [i32; 6],
    time_s: f64,
    theta: [f64; 3],
    omega: [f64; 3],
    current: [f64; 3],
    kin: Kinematics,
    hand_reference: HandRef,
    hand_force: [f64; 3],
    jam_events: u64,
    non_finite_duties: u64,
}

impl Plant {
    /// A plant at rest with the effector at the script's start position, currents zero and the
    /// output latch holding zero duty.
    pub fn new(
        device: DeviceParams,
        params: PlantParams,
        script: HandScript,
    ) -> Result<Plant, PlantError> {
        device.validate().map_err(PlantError::Device)?;
        params.validate().map_err(PlantError::Params)?;
        script.validate().map_err(PlantError::Script)?;
        let mechanism = Mechanism::new(&device.delta);
        let start = script.sample(0.0);
        let theta = mechanism
            .inverse(V3::from(start.position_m))
            .ok_or(PlantError::StartOutOfReach)?;
        let [lo, hi] = params.arm_limits_rad;
        if theta.iter().any(|&t| t < lo || t > hi) {
            return Err(PlantError::StartOutOfReach);
        }
        let kin = mechanism
            .kinematics(theta)
            .ok_or(PlantError::StartOutOfReach)?;
        let motor = Motor::new(&device, &params);
        let inertia = Inertia {
            axis_kg_m2: params.arm_inertia_kg_m2
                + motor.ratio() * motor.ratio() * params.rotor_inertia_kg_m2,
            translating_kg: params.effector_mass_kg + params.hand_mass_kg,
        };
        let mut plant = Plant {
            device,
            params,
            script,
            mechanism,
            motor,
            inertia,
            latch: OutputLatch::new(),
            bridge: BridgeStage::default(),
            applied: DriveCommand::IDLE,
            built_params: params,
            counter_origin: [0; 6],
            time_s: 0.0,
            theta,
            omega: [0.0; 3],
            current: [0.0; 3],
            kin,
            hand_reference: start,
            hand_force: [0.0; 3],
            jam_events: 0,
            non_finite_duties: 0,
        };
        plant.refresh_hand();
        plant.counter_origin = plant.counts();
        Ok(plant)
    }

    /// The six 16-bit hardware counters as the firmware reads them: they read 0 at power-up (the
    /// plant's construction) wherever the arms were, count with the motion and wrap.
    pub fn raw_counts(&self) -> [u16; 6] {
        self.raw_counts_inner()
    }

    /// Keep the hardware counters of `previous` running: a plant rebuilt where `previous` was
    /// (a new hand script) then reads the same raw counts, as the same hardware would.
    pub fn continue_counters_from(&mut self, previous: &Plant) {
        self.counter_origin = previous.counter_origin;
    }

    fn raw_counts_inner(&self) -> [u16; 6] {
        let c = self.counts();
        std::array::from_fn(|i| c[i].wrapping_sub(self.counter_origin[i]) as u16)
    }

    /// Advance one control tick driven by bridge commands written at the tick's start: phase,
    /// enable and sleep act at once, the compares from the first PWM period boundary of the tick
    /// (`timing`'s PWM period; at the tick's end when the tick is one PWM period).
    pub fn step_bridges(&mut self, commands: &BridgeCommands, timing: &BoardTiming) {
        self.step_bridges_loading_after(commands, timing, 1);
    }

    /// [`Self::step_bridges`] with the compares loaded at the start of PWM period
    /// `pwm_periods` of the tick (≥ 1; 1 is the first boundary): a write that missed the first
    /// boundary acts from a later one. At or beyond the tick's end the compares load at its end.
    pub fn step_bridges_loading_after(
        &mut self,
        commands: &BridgeCommands,
        timing: &BoardTiming,
        pwm_periods: u32,
    ) {
        let dt = 1.0 / f64::from(timing.control_hz.max(1));
        let pwm_s = f64::from(pwm_periods.max(1)) / f64::from(timing.pwm_hz.max(1));
        let full_scale = timing.pwm_period_counts().min(u32::from(u16::MAX)) as u16;
        self.bridge.write(commands);
        let n = self.params.substeps;
        let h = dt / n as f64;
        // The boundary, in sub-steps from the tick's start; the sub-step it falls inside is split
        // there (a small tolerance for rounding: a boundary within 1e-9 of a sub-step's edge is
        // that edge).
        let at = pwm_s / h;
        let t0 = self.time_s;
        let mut loaded = false;
        for k in 0..n {
            let start = f64::from(k);
            let mut pieces = [(start, 1.0), (0.0, 0.0)];
            if !loaded && at <= start + 1e-9 {
                self.bridge.load();
                loaded = true;
            } else if !loaded && at < start + 1.0 - 1e-9 {
                pieces = [(start, at - start), (at, start + 1.0 - at)];
            }
            for (i, (from, length)) in pieces.into_iter().enumerate() {
                if length <= 0.0 {
                    continue;
                }
                if i == 1 {
                    self.bridge.load();
                    loaded = true;
                }
                self.applied = self.bridge.applied(full_scale);
                self.bridge.note(length * h);
                self.time_s = t0 + from * h;
                self.substep(length * h);
            }
        }
        if !loaded {
            self.bridge.load();
        }
        self.time_s = t0 + dt;
        self.refresh_hand();
    }

    /// The user takes the handle again (after [`Self::release_hand`]).
    pub fn grasp_hand(&mut self) {
        let b = self.built_params;
        self.params.hand_mass_kg = b.hand_mass_kg;
        self.params.hand_stiffness_n_per_m = b.hand_stiffness_n_per_m;
        self.params.hand_damping_n_s_per_m = b.hand_damping_n_s_per_m;
        self.inertia.translating_kg = self.params.effector_mass_kg + self.params.hand_mass_kg;
        self.refresh_hand();
    }

    /// Encoder counts now: `[motor0, motor1, motor2, wrist0, wrist1, wrist2]`, extended i32 as
    /// the firmware hands them to the controller.
    pub fn counts(&self) -> [i32; 6] {
        let d = &self.device;
        let tau = std::f64::consts::TAU;
        let arm_step = tau / (d.motor_encoder_counts_per_rev as f64 * d.motor.capstan_ratio as f64);
        let wrist_step = tau / d.wrist_encoder_counts_per_rev as f64;
        let zero = d.arm_angle_at_zero_count_rad as f64;
        let w = self.hand_reference.wrist_rad;
        [
            encoder::quantize(self.theta[0] - zero, arm_step),
            encoder::quantize(self.theta[1] - zero, arm_step),
            encoder::quantize(self.theta[2] - zero, arm_step),
            encoder::quantize(w[0], wrist_step),
            encoder::quantize(w[1], wrist_step),
            encoder::quantize(w[2], wrist_step),
        ]
    }

    /// Advance one control tick of `dt_tick_s` seconds with the drive enabled. `duties` are the
    /// controller's output this tick; they take effect during the next tick.
    pub fn step(&mut self, duties: [f32; 3], dt_tick_s: f64) {
        self.step_with_enable(duties, true, dt_tick_s);
    }

    /// [`Self::step`] with the H-bridge enable pin (false: windings open). The enable is delayed
    /// with the duties.
    ///
    /// # Panics
    /// If `dt_tick_s` is not finite and positive (a bug in the caller, not a plant state).
    pub fn step_with_enable(&mut self, duties: [f32; 3], enable: bool, dt_tick_s: f64) {
        assert!(
            dt_tick_s.is_finite() && dt_tick_s > 0.0,
            "tick period must be finite and positive, got {dt_tick_s}"
        );
        self.non_finite_duties += duties.iter().filter(|d| !d.is_finite()).count() as u64;
        let command = DriveCommand::quantized(&self.device, duties, enable);
        self.applied = self.latch.shift(command);
        let n = self.params.substeps;
        let h = dt_tick_s / n as f64;
        let t0 = self.time_s;
        for k in 0..n {
            self.time_s = t0 + k as f64 * h;
            self.substep(h);
        }
        self.time_s = t0 + dt_tick_s;
        self.refresh_hand();
    }

    /// One integration sub-step of `h` seconds from `self.time_s`.
    fn substep(&mut self, h: f64) {
        let p = self.params;
        self.refresh_hand();
        // Currents over the sub-step, with the arm velocity held (exact RL response).
        for i in 0..3 {
            self.current[i] = self.motor.current_step(
                self.current[i],
                self.applied.duties[i],
                self.applied.enable,
                self.omega[i],
                h,
            );
        }
        let g = V3::from(p.gravity_m_s2);
        let effector_force = V3::from(self.hand_force) + g * p.effector_mass_kg;
        let external = self.kin.joint_torques(effector_force);
        let mut q = [0.0; 3];
        for i in 0..3 {
            q[i] = self.motor.arm_torque(self.current[i])
                - self.motor.friction_torque(self.omega[i])
                + self.stop_torque(self.theta[i], self.omega[i])
                + p.arm_mass_moment_kg_m * g.dot(self.kin.du[i])
                + external[i];
        }
        let acc = dynamics::arm_accelerations(
            &self.kin,
            self.mechanism.upper_arm_m(),
            self.omega,
            &self.inertia,
            q,
        );
        let Some(acc) = acc else {
            self.jam();
            return;
        };
        let mut omega = self.omega;
        let mut theta = self.theta;
        for i in 0..3 {
            omega[i] += acc[i] * h;
            theta[i] += omega[i] * h;
        }
        match self.mechanism.kinematics(theta) {
            Some(kin) => {
                self.kin = kin;
                self.theta = theta;
                self.omega = omega;
            }
            None => self.jam(),
        }
    }

    /// The linkage would leave its assemblable set: hold the configuration, stop the arms.
    fn jam(&mut self) {
        self.omega = [0.0; 3];
        self.jam_events += 1;
    }

    /// Mechanical stop torque on one arm: a spring-damper while in contact that never pulls.
    fn stop_torque(&self, theta: f64, omega: f64) -> f64 {
        let p = &self.params;
        let [lo, hi] = p.arm_limits_rad;
        let (k, c) = (p.stop_stiffness_nm_per_rad, p.stop_damping_nm_s_per_rad);
        if theta > hi {
            -(k * (theta - hi) + c * omega).max(0.0)
        } else if theta < lo {
            (k * (lo - theta) - c * omega).max(0.0)
        } else {
            0.0
        }
    }

    /// Hand reference and grasp force at the current time and state.
    fn refresh_hand(&mut self) {
        self.hand_reference = self.script.sample(self.time_s);
        let v = self.kin.velocity(self.omega);
        self.hand_force = hand::grasp_force(
            self.params.hand_stiffness_n_per_m,
            self.params.hand_damping_n_s_per_m,
            &self.hand_reference,
            self.kin.p.into(),
            v.into(),
        );
    }

    /// The user lets go of the handle: from now on no hand mass, grasp stiffness or damping.
    pub fn release_hand(&mut self) {
        self.params = self.params.without_hand();
        self.inertia.translating_kg = self.params.effector_mass_kg + self.params.hand_mass_kg;
        self.refresh_hand();
    }

    /// Play the hand's script again from its start, keeping the mechanical state (for soak runs
    /// that repeat a script whose end returns to its start). Simulated time restarts at 0.
    pub fn restart_script(&mut self) {
        self.time_s = 0.0;
        self.refresh_hand();
    }

    /// Simulated time, s.
    pub fn time_s(&self) -> f64 {
        self.time_s
    }

    /// True effector (handle centre) position, frame `B`, m.
    pub fn effector_position_m(&self) -> [f64; 3] {
        self.kin.p.into()
    }

    /// True effector velocity, frame `B`, m/s.
    pub fn effector_velocity_m_s(&self) -> [f64; 3] {
        self.kin.velocity(self.omega).into()
    }

    /// Force the hand applies to the handle, frame `B`, N.
    pub fn hand_force_n(&self) -> [f64; 3] {
        self.hand_force
    }

    /// True wrist joint angles (the script's), rad.
    pub fn wrist_angles_rad(&self) -> [f64; 3] {
        self.hand_reference.wrist_rad
    }

    /// The hand script being played.
    pub fn script(&self) -> &HandScript {
        &self.script
    }

    /// Kinetic energy of arms, rotors, effector and hand, J.
    pub fn kinetic_energy_j(&self) -> f64 {
        self.inertia.kinetic_energy(&self.kin, self.omega)
    }

    /// Everything at once.
    pub fn truth(&self) -> PlantTruth {
        PlantTruth {
            time_s: self.time_s,
            arm_angles_rad: self.theta,
            arm_velocities_rad_s: self.omega,
            motor_currents_a: self.current,
            effector_position_m: self.effector_position_m(),
            effector_velocity_m_s: self.effector_velocity_m_s(),
            hand_force_n: self.hand_force,
            hand_reference: self.hand_reference,
            applied: self.applied,
            jam_events: self.jam_events,
            non_finite_duties: self.non_finite_duties,
            wrong_direction_s: self.bridge.wrong_direction_s,
            reversals: self.bridge.reversals,
        }
    }
}

#[cfg(test)]
mod tests;
