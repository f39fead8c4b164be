//! The one control pipeline the firmware's interrupt and host-sim's closed loop both run: raw
//! 16-bit timer counts, the driver-fault line and the tick's timing in; bridge commands
//! (phase, compare, enable, sleep), telemetry and tick statistics out.
//!
//! Per tick ([`Pipeline::tick`]):
//!
//! ```text
//! timing stats ─► count extension + glitch check ─► nFAULT (masked asleep / waking)
//!   ─► mode: Homing → homing drive │ Disarmed/Armed → controller (force × arming ramp)
//!   ─► output guard (the one latching set) ─► fault? → Faulted: sleep, zero torque
//!   ─► bridge mapping (reversal without a wrong-direction pulse) ─► telemetry, summary
//! ```
//!
//! The firmware's interrupt is: read the counters, nFAULT and the tick timer → `tick` → write the
//! hardware in the order of [`bridge`]'s contract → hand the telemetry record to a non-blocking
//! log and report whether it was queued ([`Pipeline::telemetry_sent`]). Operator commands go
//! through [`Pipeline::command`] between ticks; a link task also calls
//! [`Pipeline::note_link_activity`] for every message it decodes (the communication watchdog's
//! food).
//!
//! The environment `S` decides the controller's contact stage ([`crate::control::controller::stage`]): a fixed
//! surface (the firmware's plane), or [`crate::control::local_model::LocalModelEnvironment`], the application's
//! local model with the communication watchdog, which also accepts [`Command::SetLocalModel`]
//! and [`Command::SetWatchdog`] (a fixed surface refuses them: [`CommandError::Unsupported`]).
//!
//! Frames: motor counts handed to the controller are *homed*: 0 ↔ the device's zero-count arm
//! angle; wrist counts are relative to the calibration pose held at `Home`.

pub mod board;
pub mod bridge;
pub mod config;
pub mod driver;
pub mod homing;
pub mod link;
pub mod liveness;
pub mod mode;
pub mod output_timing;
pub mod ramp;
pub mod record;
pub mod timing;

use crate::contact::params::ParamsChange;
pub use crate::control::command::{CheckedCommand, Command, CommandError, CommandKey};
pub use board::{BoardTiming, TimingError};
pub use bridge::{BridgeCommands, BridgeMapper};
pub use config::{PipelineConfig, PipelineError};
pub use homing::HomingSpec;
pub use link::{HOST_WATCHDOG_MAX_S, HOST_WATCHDOG_MIN_S, HOST_WATCHDOG_S, LINK_FADE_S};
pub use mode::Mode;
pub use record::PipelineRecord;
pub use timing::TimingSummary;

use crate::contact::state::ContactState;
use crate::contact::surface::Plane;
use crate::control::controller::passivity;
use crate::control::controller::{
    guarded_output, ContactStage, Controller, Environment, TickOutput,
};
use crate::control::output_guard::{GuardConfig, OutputGuard};
use crate::control::telemetry::{Decimator, DropCounter};
use crate::device::channels::{EncoderCounts, CHANNELS, MOTOR, WRIST};
use crate::device::encoder::EncoderBank;
use crate::flags::Flags;
use crate::math::Math;

use driver::DriverPower;
use homing::{ticks_for, Homing, HomingStep};
use link::LinkHold;
use ramp::ArmRamp;
use timing::{TickTiming, TimingVerdict};

/// What the firmware reads from the hardware at the start of a tick.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RawInput {
    /// Raw wrapping 16-bit encoder timer counts, in the channel order of
    /// [`crate::device::channels`] (motors 0-2, then wrist joints 0-2).
    pub counts: [u16; CHANNELS],
    /// The drivers' nFAULT line is asserted (as read; the pipeline masks it while asleep/waking).
    pub driver_fault: bool,
    /// Timer counts from this tick's timer event to the interrupt's first instruction.
    pub start_latency_counts: u32,
    /// Timer counts from the previous tick's timer event to the end of its hardware writes; pass
    /// `u32::MAX` when the tick timer's update flag was set again before they finished.
    pub prev_write_done_counts: u32,
}

/// What one tick hands back.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PipelineOutput {
    /// Write these to the bridges (see [`bridge`] for the order).
    pub bridges: BridgeCommands,
    /// Mode after this tick.
    pub mode: Mode,
    /// Flags of this tick, latched faults included.
    pub flags: Flags,
    /// Latched faults (empty unless `mode` is `Faulted`).
    pub latched: Flags,
    /// The controller's view this tick (probe, force actually commanded, contact state; force 0
    /// unless armed) with the guarded duties.
    pub control: TickOutput,
    /// Counts as handed to the controller (homed motors, calibrated wrist).
    pub counts: [i32; CHANNELS],
    /// Gain of the arming ramp applied to the force this tick (0 unless armed).
    pub ramp_gain: f32,
    /// A decimated telemetry record, when this tick is selected.
    pub telemetry: Option<PipelineRecord>,
    /// Tick statistics, once per second.
    pub summary: Option<TimingSummary>,
}

/// The pipeline. `M`: math backend; `S`: the environment (a fixed surface, or
/// [`LocalModelEnvironment`](crate::control::local_model::LocalModelEnvironment) for the application's local model).
#[derive(Clone, Copy, Debug)]
pub struct Pipeline<M: Math, S: Environment = Plane> {
    config: PipelineConfig<S>,
    controller: Controller<M, S>,
    guard: OutputGuard,
    glitch_limit: u16,
    encoders: Option<EncoderBank<6>>,
    extended: [i32; CHANNELS],
    offsets: [i32; CHANNELS],
    homed: bool,
    mode: Mode,
    homing: Homing,
    ramp: ArmRamp,
    driver: DriverPower,
    bridge: BridgeMapper,
    timing: TickTiming,
    decimator: Decimator,
    drops: DropCounter,
    tick: u32,
    /// The probe was in contact with the surface on the last disarmed tick (Arm is refused).
    inside: bool,
    link: LinkHold,
    /// The communication watchdog's timeout a host's `Arm` turns on when it is off, s
    /// ([`HOST_WATCHDOG_S`] unless the stored settings say otherwise: [`Self::set_host_watchdog`]).
    host_watchdog_s: f32,
    /// `COMM_TIMEOUT` of a lost link this tick.
    link_flags: Flags,
}

impl<M: Math, S: Environment> Pipeline<M, S> {
    /// Build a pipeline at power-up (Unhomed, drivers asleep). An invalid configuration is
    /// rejected, never clamped.
    pub fn new(config: PipelineConfig<S>) -> Result<Self, PipelineError> {
        config.validate()?;
        let cc = config.controller_config();
        let mut controller = Controller::new(cc).map_err(PipelineError::Params)?;
        // The passivity observer weighs the forces acting in each interval by this board's
        // sample-to-output delay.
        let delay = output_timing::OutputTiming::planned(&config.timing).delay_ticks();
        controller
            .set_passivity(passivity::PassivityConfig {
                output_delay_ticks: delay.min(1.0),
                // The motor encoders' resolution at the probe: a held probe's count dither is
                // not energy the wall generates.
                position_quantum_m: config.device.params.probe_m_per_motor_count(),
                enabled: S::PASSIVITY_DAMPS,
                ..passivity::PassivityConfig::DEFAULT
            })
            .map_err(PipelineError::Params)?;
        let rate = cc.rate_hz;
        let gc = GuardConfig::from_limits(&config.device.limits, rate);
        let guard = OutputGuard::new(gc).map_err(PipelineError::Params)?;
        let t = config.timing;
        let full_scale = t.pwm_period_counts().min(u32::from(u16::MAX)) as u16;
        Ok(Pipeline {
            controller,
            guard,
            glitch_limit: gc.ticks.max_counts_per_tick,
            encoders: None,
            extended: [0; CHANNELS],
            offsets: [0; CHANNELS],
            homed: false,
            mode: Mode::Unhomed,
            homing: Homing::new(config.device.homing, &config.device.params, rate),
            ramp: ArmRamp::new(ticks_for(config.device.arm_ramp_s, rate)),
            driver: DriverPower::new(ticks_for(config.device.driver_wake_s, rate)),
            bridge: BridgeMapper::new(full_scale),
            timing: TickTiming::new(t.tick_period_counts(), t.pwm_period_counts(), t.control_hz),
            decimator: Decimator::new(t.control_hz, config.log_rate_hz),
            drops: DropCounter::new(),
            tick: 0,
            inside: false,
            link: LinkHold::new(rate),
            host_watchdog_s: HOST_WATCHDOG_S,
            link_flags: Flags::NONE,
            config,
        })
    }

    /// The configuration in force.
    pub fn config(&self) -> &PipelineConfig<S> {
        &self.config
    }

    /// The current mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Replace the passivity stage's parameters (see [`passivity`]); the board's output delay is
    /// the caller's to keep. Invalid values are rejected and the old ones stay.
    pub fn set_passivity(
        &mut self,
        config: passivity::PassivityConfig,
    ) -> Result<(), crate::contact::params::ParamError> {
        self.controller.set_passivity(config)
    }

    /// Latched faults.
    #[must_use]
    pub fn latched(&self) -> Flags {
        self.guard.latched()
    }

    /// True once homing has set the encoder zero (cleared again by faults that make it doubtful).
    pub fn homed(&self) -> bool {
        self.homed
    }

    /// The controller (read-only, for logs and charts).
    pub fn controller(&self) -> &Controller<M, S> {
        &self.controller
    }

    /// Telemetry records dropped since start-up.
    pub fn dropped_total(&self) -> u32 {
        self.drops.total()
    }

    /// Report whether this tick's telemetry record was queued (`false`: dropped, counted and
    /// reported in the next record that gets through).
    pub fn telemetry_sent(&mut self, queued: bool) {
        if queued {
            let _ = self.drops.take_unreported();
        }
        self.drops.note(queued);
    }

    /// A valid message arrived on the link: feeds the communication watchdog of a local-model
    /// environment (nothing on a fixed surface). The link task calls it for every message it decodes.
    pub fn note_link_activity(&mut self) {
        self.controller.contact_mut().note_link_activity();
    }

    /// The timeout a host's `Arm` turns the communication watchdog on with, s.
    pub fn host_watchdog_s(&self) -> f32 {
        self.host_watchdog_s
    }

    /// Set the timeout a host's `Arm` turns the communication watchdog on with (the stored
    /// settings' `watchdog.timeout_ms`, applied at boot), s, in
    /// [[`HOST_WATCHDOG_MIN_S`], [`HOST_WATCHDOG_MAX_S`]]. Anything else is refused and the
    /// timeout in force stays: a host that arms always holds a watchdog.
    pub fn set_host_watchdog(
        &mut self,
        timeout_s: f32,
    ) -> Result<(), crate::contact::params::ParamError> {
        use crate::contact::params::ParamError;
        if !timeout_s.is_finite() {
            return Err(ParamError::NotFinite("host watchdog timeout"));
        }
        if !(HOST_WATCHDOG_MIN_S..=HOST_WATCHDOG_MAX_S).contains(&timeout_s) {
            return Err(ParamError::OutOfRange("host watchdog timeout"));
        }
        self.host_watchdog_s = timeout_s;
        Ok(())
    }

    /// A command that arrived over the host link: link activity, then [`Self::command`] under
    /// the host's rules ([`link`]): an accepted `Arm` turns the communication watchdog on
    /// ([`Self::host_watchdog_s`], [`HOST_WATCHDOG_S`] by default) when it is off and makes the link hold the force; while it does,
    /// `SetWatchdog` cannot turn the watchdog off ([`CommandError::WatchdogRequired`]).
    pub fn link_command(&mut self, command: Command) -> Result<(), CommandError> {
        match command.check() {
            Ok(c) => self.link_apply(&c),
            Err(e) => {
                self.note_link_activity();
                self.refused(&command);
                Err(e)
            }
        }
    }

    /// [`Self::link_command`] for a command checked where it arrived ([`Command::check`]): the
    /// firmware's tick applies a host's commands this way.
    pub fn link_apply(&mut self, command: &CheckedCommand) -> Result<(), CommandError> {
        self.note_link_activity();
        match *command {
            CheckedCommand::Arm => {
                self.apply(command)?;
                self.link.armed_by_host();
                if self.controller.contact().watchdog_s() == 0.0 {
                    // A fixed surface has no watchdog (Unsupported): the link-loss rule still holds.
                    let _ = self
                        .controller
                        .contact_mut()
                        .set_watchdog(self.host_watchdog_s);
                }
                Ok(())
            }
            CheckedCommand::SetWatchdog { timeout_s }
                if self.link.host_armed()
                    && self.mode == Mode::Armed
                    && (timeout_s.is_nan() || timeout_s <= 0.0) =>
            {
                Err(CommandError::WatchdogRequired)
            }
            _ => self.apply(command),
        }
    }

    /// `command` was refused by its own checks ([`Command::check`]): the refusal flag the stage
    /// would have raised ([`Flags::PARAM_REJECTED`], [`Flags::MODEL_REJECTED`]) on the next tick.
    pub fn refused(&mut self, command: &Command) {
        match command {
            Command::SetContactParams(_) => self.controller.params_refused(),
            Command::SetLocalModel(_) => self.controller.contact_mut().local_model_refused(),
            _ => {}
        }
    }

    /// The host link was lost (USB bus reset, suspend, DTR dropped, or the host not taking the
    /// device's writes for the firmware's stated time): when a host armed the device, the force
    /// fades to zero within [`LINK_FADE_S`] and `COMM_TIMEOUT` latches until the next `Arm`.
    pub fn link_lost(&mut self) {
        if self.mode == Mode::Armed {
            let _ = self.link.lose();
        }
    }

    /// The thread-mode tasks stopped ([`liveness`]): latch `THREAD_STALLED`, so this tick's
    /// outputs are zero torque with the drivers asleep, before the IWDG resets the MCU.
    pub fn thread_stalled(&mut self) {
        self.guard.latch(Flags::THREAD_STALLED);
    }

    /// A host holds the arming (it armed the device over the link and it is still armed).
    pub fn host_armed(&self) -> bool {
        self.link.host_armed() && self.mode == Mode::Armed
    }

    /// Apply an operator command at a tick boundary: [`Command::check`], then [`Self::apply`].
    pub fn command(&mut self, command: Command) -> Result<(), CommandError> {
        match command.check() {
            Ok(c) => self.apply(&c),
            Err(e) => {
                self.refused(&command);
                Err(e)
            }
        }
    }

    /// Apply a checked command at a tick boundary. See [`Mode`] for the transitions.
    pub fn apply(&mut self, command: &CheckedCommand) -> Result<(), CommandError> {
        match command {
            CheckedCommand::Home => match self.mode {
                Mode::Unhomed | Mode::Disarmed => {
                    // The handle is in the wrist calibration pose now: that is the wrist zero.
                    for i in WRIST {
                        self.offsets[i] = self.extended[i].wrapping_neg();
                    }
                    self.homed = false;
                    self.homing.restart();
                    self.driver.wake();
                    self.mode = Mode::Homing;
                    Ok(())
                }
                Mode::Homing => Err(CommandError::Homing),
                Mode::Armed => Err(CommandError::Armed),
                Mode::Faulted => Err(CommandError::Faulted),
            },
            CheckedCommand::Arm => match self.mode {
                Mode::Disarmed if self.inside => Err(CommandError::InsideSurface),
                Mode::Disarmed => {
                    self.link.armed_locally();
                    self.controller.contact_mut().rearm();
                    self.ramp.restart();
                    self.controller.set_force_scale(0.0);
                    self.mode = Mode::Armed;
                    Ok(())
                }
                Mode::Armed => {
                    // Re-arming clears a latched communication timeout (the force ramps back).
                    self.link.armed_locally();
                    self.controller.contact_mut().rearm();
                    Ok(())
                }
                Mode::Unhomed => Err(CommandError::NotHomed),
                Mode::Homing => Err(CommandError::Homing),
                Mode::Faulted => Err(CommandError::Faulted),
            },
            CheckedCommand::Disarm => {
                match self.mode {
                    Mode::Armed => self.mode = Mode::Disarmed,
                    Mode::Homing => {
                        // An aborted homing leaves nothing awake.
                        self.driver.sleep();
                        self.mode = Mode::Unhomed;
                    }
                    _ => {}
                }
                self.link.released();
                Ok(())
            }
            CheckedCommand::ClearFaults => {
                if self.mode == Mode::Faulted {
                    self.guard.clear();
                    self.controller.restart();
                    self.mode = if self.homed {
                        self.driver.wake();
                        self.inside = true;
                        Mode::Disarmed
                    } else {
                        Mode::Unhomed
                    };
                }
                Ok(())
            }
            CheckedCommand::SetContactParams(p) => {
                let change = self
                    .controller
                    .set_contact_params(p)
                    .map_err(CommandError::InvalidParams)?;
                // A restarted contact starts from zero force: ramp it in again when armed. A
                // blended material carries the contact on.
                if change == ParamsChange::Restarted {
                    self.ramp.restart();
                }
                Ok(())
            }
            CheckedCommand::SetLocalModel(spec) => {
                self.controller.contact_mut().set_local_model(spec)
            }
            CheckedCommand::SetWatchdog { timeout_s } => {
                self.controller.contact_mut().set_watchdog(*timeout_s)
            }
        }
    }

    /// One tick. Never panics; any fault gives zero torque at once. The same as
    /// [`Self::tick_outputs`] then [`Self::tick_telemetry`].
    pub fn tick(&mut self, raw: &RawInput) -> PipelineOutput {
        let mut out = self.tick_outputs(raw);
        self.tick_telemetry(&mut out, raw);
        out
    }

    /// The tick up to its outputs: everything but the telemetry record and the timing summary
    /// (`None` here). The firmware writes the bridge commands between this and
    /// [`Self::tick_telemetry`], which must follow once per tick (it ends the tick), so the
    /// compares wait for nothing the hardware does not need. Never panics. Inlined into its one
    /// caller, so the output is built in place (not copied out) as when the tick was one function.
    #[inline(always)]
    pub fn tick_outputs(&mut self, raw: &RawInput) -> PipelineOutput {
        let verdict = self
            .timing
            .record(raw.start_latency_counts, raw.prev_write_done_counts);
        let mut events = self.extend_counts(raw.counts);
        // Ready at the start of this tick: the whole wake time is masked and disabled.
        let ready = self.driver.ready();
        if self.driver.tick(raw.driver_fault) {
            events |= Flags::DRIVER_FAULT;
        }
        let counts = self.homed_counts();
        // Only homing moves the offsets within a tick (`HomingStep::Done`).
        let was_homing = self.mode == Mode::Homing;
        let (out, drive, gain) = self.control(counts, ready);
        let g = self
            .guard
            // The count extension above already checked every channel's step against the same
            // limit (`glitch_limit`), every tick: its ENCODER_GLITCH is in `events`.
            .apply_extension_checked(&self.extended, &out, events, verdict.overrun);
        if !self.guard.latched().is_empty() && self.mode != Mode::Faulted {
            self.enter_fault();
        }
        let drive = drive && g.enable && ready && self.driver.awake();
        let bridges = self.bridges(if drive { g.duties } else { [0.0; 3] }, drive, verdict);
        let mut control = guarded_output(out, &g);
        if !drive {
            control.duties = [0.0; 3];
            control.enable = false;
        }
        PipelineOutput {
            bridges: bridges.0,
            mode: self.mode,
            flags: g.flags | bridges.1 | self.link_flags,
            latched: self.guard.latched(),
            control,
            // After the mode's work: on the tick homing ends these are already the homed counts.
            counts: if was_homing {
                self.homed_counts()
            } else {
                counts
            },
            ramp_gain: if self.mode == Mode::Armed { gain } else { 0.0 },
            telemetry: None,
            summary: None,
        }
    }

    /// The end of the tick [`Self::tick_outputs`] began: its decimated telemetry record and the
    /// timing summary when due, filled into `out` (with the same `raw`).
    #[inline(always)]
    pub fn tick_telemetry(&mut self, out: &mut PipelineOutput, raw: &RawInput) {
        out.telemetry = self.record(&out.control, &out.counts, &out.bridges, out.flags, raw);
        self.tick = self.tick.wrapping_add(1);
        out.summary = self.timing.take_summary_if_due(self.drops.total());
    }

    /// Count extension with the glitch check; the first tick's reading is position 0.
    #[must_use]
    fn extend_counts(&mut self, raw: [u16; CHANNELS]) -> Flags {
        match &mut self.encoders {
            Some(bank) => bank.update_into(raw, &mut self.extended),
            None => {
                self.encoders = Some(EncoderBank::new(raw, self.glitch_limit));
                self.extended = [0; CHANNELS];
                Flags::NONE
            }
        }
    }

    fn homed_counts(&self) -> [i32; CHANNELS] {
        core::array::from_fn(|i| self.extended[i].wrapping_add(self.offsets[i]))
    }

    /// The mode's control law: (output for the guard, whether the bridges may drive, ramp gain).
    fn control(&mut self, counts: [i32; CHANNELS], ready: bool) -> (TickOutput, bool, f32) {
        let idle = TickOutput {
            enable: false,
            ..TickOutput::default()
        };
        self.link_flags = Flags::NONE;
        match self.mode {
            Mode::Unhomed | Mode::Faulted => (idle, false, 0.0),
            Mode::Homing => {
                if !ready {
                    return (idle, false, 0.0);
                }
                let motors = MOTOR.map(|i| self.extended[i]);
                match self.homing.tick(motors, &self.config.device.params) {
                    HomingStep::Drive(duties) => (
                        TickOutput {
                            duties,
                            enable: true,
                            ..TickOutput::default()
                        },
                        true,
                        0.0,
                    ),
                    HomingStep::Done(offsets) => {
                        for (k, i) in MOTOR.into_iter().enumerate() {
                            self.offsets[i] = offsets[k];
                        }
                        self.homed = true;
                        self.controller.restart();
                        // Unknown until a disarmed tick has looked: no Arm before then.
                        self.inside = true;
                        self.mode = Mode::Disarmed;
                        (idle, false, 0.0)
                    }
                    HomingStep::Failed => {
                        self.guard.latch(Flags::HOMING_FAILED);
                        (idle, false, 0.0)
                    }
                }
            }
            Mode::Disarmed => {
                self.controller.set_force_scale(0.0);
                let mut out = self.controller.compute(&counts);
                out.enable = false;
                self.inside = out.state != ContactState::Broken;
                (out, false, 0.0)
            }
            Mode::Armed => {
                let (link_gain, link_flags) = self.link.tick();
                self.link_flags = link_flags;
                let gain = self.ramp.next_gain() * link_gain;
                self.controller.set_force_scale(gain);
                (self.controller.compute(&counts), true, gain)
            }
        }
    }

    /// Latch: zero torque now, drivers to sleep; a fault that makes the zero doubtful un-homes.
    fn enter_fault(&mut self) {
        let latched = self.guard.latched();
        if self.mode == Mode::Homing
            || latched.intersects(Flags::ENCODER_GLITCH | Flags::HOMING_FAILED)
        {
            self.homed = false;
        }
        self.mode = Mode::Faulted;
        self.driver.sleep();
        self.link.released();
    }

    #[must_use]
    fn bridges(
        &mut self,
        duties: [f32; 3],
        drive: bool,
        verdict: TimingVerdict,
    ) -> (BridgeCommands, Flags) {
        let on_time = !(verdict.late_write || verdict.overrun);
        let (phase_forward, compare, flags) = self.bridge.map(duties, on_time);
        (
            BridgeCommands {
                phase_forward,
                compare,
                pwm_enable: drive,
                driver_awake: self.driver.awake(),
            },
            flags,
        )
    }

    fn record(
        &mut self,
        control: &TickOutput,
        counts: &[i32; CHANNELS],
        bridges: &BridgeCommands,
        flags: Flags,
        raw: &RawInput,
    ) -> Option<PipelineRecord> {
        if !self.decimator.tick() {
            return None;
        }
        let named = EncoderCounts::from(*counts);
        let signed = |i: usize| {
            let c = bridges.compare[i].min(i16::MAX as u16) as i16;
            if bridges.phase_forward[i] {
                c
            } else {
                -c
            }
        };
        Some(PipelineRecord {
            tick: self.tick,
            mode: self.mode,
            state: control.state,
            flags,
            motor_counts: named.motor,
            wrist_counts: named.wrist.map(|c| c as i16),
            force_mn: record::force_mn(control.force_n),
            compare: [signed(0), signed(1), signed(2)],
            latency_counts: record::sat_u16(raw.start_latency_counts),
            write_counts: record::sat_u16(raw.prev_write_done_counts),
            dropped_before: record::sat_u16(self.drops.unreported()),
        })
    }
}

#[cfg(test)]
mod tests;
