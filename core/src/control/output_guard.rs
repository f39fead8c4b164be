//! The last line of defence between the control law and the motor drivers, and the ONE place
//! where faults latch.
//!
//! [`OutputGuard`] runs after the control law ([`Controller::compute`]) and independently of it:
//! whatever the control law returns, the guard
//! - latches [`LATCHING`] faults: a driver fault or encoder glitch reported as an event, an encoder
//!   step beyond the glitch limit, a motor encoder that does not move while its duty is at or above
//!   the stuck duty for the stuck time, a non-finite output, a streak of overrun ticks, a failed
//!   homing; from then on it outputs zero duties with the drivers disabled until an explicit
//!   [`OutputGuard::clear`];
//! - maps any non-finite duty to 0 (raising [`Flags::NON_FINITE_OUTPUT`]);
//! - clamps every duty to the configured maximum (raising [`Flags::OUTPUT_LIMITED`]).
//!
//! Its thresholds come from [`Limits`] (physical units) converted for the control rate by
//! [`Limits::per_tick`], so the controller, the pipeline and the firmware share one definition.
//!
//! [`phase_enable`] turns a guarded duty into what a phase/enable H-bridge (DRV887x class) needs:
//! the phase (direction) pin level and a PWM compare value.
//!
//! Duty convention: a duty `d` in [-1, 1] is the signed fraction of the PWM period the bridge
//! drives; `d ≥ 0` drives the phase pin high ("forward": current from OUT1 to OUT2), `d < 0` low.
//!
//! [`Controller::compute`]: crate::control::controller::Controller::compute

use crate::control::controller::config::{Limits, TickLimits};
use crate::control::controller::tick::TickOutput;
use crate::device::channels::{CHANNELS, MOTOR};
use crate::flags::{all_finite, Flags};
use crate::validate::ParamError;

/// Faults that latch (outputs held at zero torque until cleared). The one latching set: the
/// controller, the pipeline, the firmware's LED and log all use this.
pub const LATCHING: Flags = Flags(
    Flags::DRIVER_FAULT.0
        | Flags::ENCODER_GLITCH.0
        | Flags::ENCODER_STUCK.0
        | Flags::NON_FINITE_OUTPUT.0
        | Flags::OVERRUN.0
        | Flags::HOMING_FAILED.0
        | Flags::THREAD_STALLED.0,
);

/// A brushed DC motor seen from its driver, to express a torque limit as a duty limit.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MotorModel {
    /// Torque constant, N·m/A.
    pub kt_nm_per_a: f32,
    /// Terminal resistance, Ω.
    pub r_ohm: f32,
    /// Bridge supply voltage, V.
    pub v_supply: f32,
}

impl MotorModel {
    /// The duty whose stall current produces `torque_nm`: `d = τ·R / (kt·V)`, in [0, 1].
    ///
    /// At stall the winding current is `d·V/R`, so this bounds the torque a duty can produce when
    /// the motor is held (the haptic case: the user pushes against the device). Any invalid model
    /// or torque (non-finite, non-positive constants, negative torque) is rejected.
    pub fn duty_for_torque(&self, torque_nm: f32) -> Result<f32, ParamError> {
        let ok = |x: f32| x.is_finite() && x > 0.0;
        let torque_ok = torque_nm.is_finite() && torque_nm >= 0.0;
        if !(ok(self.kt_nm_per_a) && ok(self.r_ohm) && ok(self.v_supply) && torque_ok) {
            return Err(ParamError::OutOfRange("motor_model_or_torque"));
        }
        let d = torque_nm * self.r_ohm / (self.kt_nm_per_a * self.v_supply);
        // The quotient of finite positives can still overflow to +inf; min() keeps it at 1.
        Ok(if d.is_finite() { d.min(1.0) } else { 1.0 })
    }
}

/// The guard's limits, per tick.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GuardConfig {
    /// Largest duty magnitude ever written, in (0, 1].
    pub max_duty: f32,
    /// |duty| at or above this without motion counts towards ENCODER_STUCK.
    pub stuck_duty: f32,
    /// Thresholds in ticks (glitch step, overrun streak, stuck time).
    pub ticks: TickLimits,
}

impl GuardConfig {
    /// The guard for `limits` at `rate_hz`.
    pub fn from_limits(limits: &Limits, rate_hz: f32) -> Self {
        GuardConfig {
            max_duty: limits.max_duty,
            stuck_duty: limits.stuck_duty,
            ticks: limits.per_tick(rate_hz),
        }
    }

    /// This config with the duty limit tightened to the duty that produces `max_torque_nm` at
    /// stall (see [`MotorModel::duty_for_torque`]).
    pub fn with_torque_limit(
        self,
        max_torque_nm: f32,
        motor: &MotorModel,
    ) -> Result<Self, ParamError> {
        let torque_duty = motor.duty_for_torque(max_torque_nm)?;
        let config = GuardConfig {
            max_duty: self.max_duty.min(torque_duty),
            ..self
        };
        config.validate()?;
        Ok(config)
    }

    /// Accept only a finite `max_duty` in (0, 1], a finite positive stuck duty and non-zero tick
    /// thresholds.
    pub fn validate(&self) -> Result<(), ParamError> {
        let t = &self.ticks;
        if self.max_duty.is_finite()
            && self.max_duty > 0.0
            && self.max_duty <= 1.0
            && self.stuck_duty.is_finite()
            && self.stuck_duty > 0.0
            && t.max_counts_per_tick >= 1
            && t.overrun_streak >= 1
            && t.stuck_ticks >= 1
        {
            Ok(())
        } else {
            Err(ParamError::OutOfRange("guard_config"))
        }
    }
}

/// What the guard lets through to the hardware this tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Guarded {
    /// Duties to write, each finite and within ±`max_duty` (all 0 when disabled).
    pub duties: [f32; 3],
    /// Drive the shared driver-enable pin.
    pub enable: bool,
    /// Controller flags, this tick's events and guard flags, plus every latched fault.
    pub flags: Flags,
}

/// Duty limiter, fault checks and the fault latch. See the module documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct OutputGuard {
    config: GuardConfig,
    /// Faults latched so far: any of them holds the outputs at zero.
    latched: Flags,
    /// False until the first tick (no previous counts to compare with).
    started: bool,
    /// The previous tick's extended counts, for the glitch check.
    prev_counts: [i32; CHANNELS],
    /// Consecutive overrun ticks.
    overruns: u32,
    /// Consecutive ticks of drive without a count, per motor.
    stuck: [u32; 3],
}

impl OutputGuard {
    /// A guard with no fault latched; an invalid configuration is rejected, never clamped.
    pub fn new(config: GuardConfig) -> Result<Self, ParamError> {
        config.validate()?;
        Ok(OutputGuard {
            config,
            latched: Flags::NONE,
            started: false,
            prev_counts: [0; CHANNELS],
            overruns: 0,
            stuck: [0; 3],
        })
    }

    /// The limits in force.
    pub const fn config(&self) -> &GuardConfig {
        &self.config
    }

    /// The faults latched so far (empty when outputs may be enabled).
    #[must_use]
    pub const fn latched(&self) -> Flags {
        self.latched
    }

    /// Clear every latched fault and the streak and stuck counters (an explicit operator action);
    /// count steps are checked again from the second tick after. A condition still present latches
    /// again.
    pub fn clear(&mut self) {
        self.latched = Flags::NONE;
        self.started = false;
        self.overruns = 0;
        self.stuck = [0; 3];
    }

    /// Latch `faults` now (e.g. a failed homing); only [`LATCHING`] flags are kept.
    pub fn latch(&mut self, faults: Flags) {
        self.latched |= faults & LATCHING;
    }

    /// Guard one output of the control law.
    ///
    /// - `counts`: the encoder positions of this tick in one continuous frame (extended counts;
    ///   motors first), for the glitch and stuck checks;
    /// - `events`: conditions observed this tick (e.g. [`Flags::DRIVER_FAULT`] when nFAULT counts,
    ///   [`Flags::ENCODER_GLITCH`] from the count extension);
    /// - `overrun`: this tick follows an overrun; `overrun_streak` of them in a row latch
    ///   [`Flags::OVERRUN`].
    pub fn apply(
        &mut self,
        counts: &[i32; CHANNELS],
        out: &TickOutput,
        events: Flags,
        overrun: bool,
    ) -> Guarded {
        self.guard::<true>(counts, out, events, overrun)
    }

    /// [`Self::apply`] without its own glitch check, for a caller whose `events` already carry
    /// [`Flags::ENCODER_GLITCH`] from a count extension (`device::encoder::EncoderBank`) with the
    /// same limit (`ticks.max_counts_per_tick`, counts per tick) that is fed every tick `counts`
    /// come from: the extension's per-tick difference of a channel is exactly the difference of
    /// its extended counts, so the guard's check would find nothing the extension has not
    /// already flagged (the pipeline's case; it saves six comparisons before the compare
    /// writes). The stuck check, the latching and the duty limit are [`Self::apply`]'s.
    pub fn apply_extension_checked(
        &mut self,
        counts: &[i32; CHANNELS],
        out: &TickOutput,
        events: Flags,
        overrun: bool,
    ) -> Guarded {
        self.guard::<false>(counts, out, events, overrun)
    }

    #[inline(always)]
    fn guard<const CHECK_GLITCH: bool>(
        &mut self,
        counts: &[i32; CHANNELS],
        out: &TickOutput,
        events: Flags,
        overrun: bool,
    ) -> Guarded {
        let mut flags = out.flags | events;
        let t = self.config.ticks;
        self.overruns = if overrun {
            self.overruns.saturating_add(1)
        } else {
            0
        };
        if self.overruns >= t.overrun_streak {
            flags |= Flags::OVERRUN;
        }
        let [d0, d1, d2] = out.duties;
        let f = out.force_n;
        let finite_duties = if all_finite(&[d0, d1, d2, f.x, f.y, f.z, out.tau_n_nm]) {
            out.duties
        } else {
            flags |= Flags::NON_FINITE_OUTPUT;
            out.duties.map(|d| if d.is_finite() { d } else { 0.0 })
        };
        if self.started {
            if CHECK_GLITCH {
                let max = u32::from(t.max_counts_per_tick);
                for (now, before) in counts.iter().zip(self.prev_counts.iter()) {
                    if now.wrapping_sub(*before).unsigned_abs() > max {
                        flags |= Flags::ENCODER_GLITCH;
                    }
                }
            }
            for (k, stuck) in self.stuck.iter_mut().enumerate() {
                let i = MOTOR[k];
                let moved = counts[i] != self.prev_counts[i];
                *stuck = if out.enable && finite_duties[k].abs() >= self.config.stuck_duty && !moved
                {
                    stuck.saturating_add(1)
                } else {
                    0
                };
                if *stuck >= t.stuck_ticks {
                    flags |= Flags::ENCODER_STUCK;
                }
            }
        }
        self.started = true;
        self.prev_counts = *counts;
        self.latched |= flags & LATCHING;
        flags |= self.latched;

        if !self.latched.is_empty() || !out.enable {
            return Guarded {
                duties: [0.0; 3],
                enable: false,
                flags,
            };
        }
        let max = self.config.max_duty;
        // Not `f32::clamp`: its min > max assertion would link the float formatting machinery
        // (~17 KB) into the firmware for the panic message. `max` is validated in (0, 1].
        let duties = finite_duties.map(|d| {
            if d > max {
                max
            } else if d < -max {
                -max
            } else {
                d
            }
        });
        if duties != finite_duties {
            flags |= Flags::OUTPUT_LIMITED;
        }
        Guarded {
            duties,
            enable: true,
            flags,
        }
    }
}

/// One phase/enable bridge command.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PhaseEnable {
    /// Phase pin level: true (high) for `duty ≥ 0`.
    pub forward: bool,
    /// PWM compare value in [0, `full_scale`]: `round(|duty| · full_scale)`.
    pub compare: u32,
}

/// Map a duty in [-1, 1] to a phase level and compare value; `full_scale` is the compare value for
/// 100 % duty (at most 65 535: a 16-bit compare register). Magnitudes above 1 saturate at
/// `full_scale`; a non-finite duty gives compare 0. Stateless: the pipeline's
/// [`BridgeMapper`](crate::control::pipeline::BridgeMapper) adds the reversal sequencing on top of the same
/// rounding ([`duty_to_compare`](crate::control::pipeline::bridge::duty_to_compare)).
#[inline]
pub fn phase_enable(duty: f32, full_scale: u32) -> PhaseEnable {
    let fs = full_scale.min(u32::from(u16::MAX)) as u16;
    PhaseEnable {
        forward: !duty.is_finite() || duty >= 0.0,
        compare: u32::from(crate::control::pipeline::bridge::duty_to_compare(duty, fs)),
    }
}

#[cfg(test)]
mod tests;
