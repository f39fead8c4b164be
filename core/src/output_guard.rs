//! The last line of defence between the controller and the motor drivers.
//!
//! [`OutputGuard`] runs after [`Controller::tick`](crate::controller::Controller::tick) and
//! independently of it: whatever the controller returns, the guard
//! - latches a fault on a driver fault, an encoder glitch, a non-finite controller output or a
//!   streak of overrun ticks, and from then on outputs zero duties with the drivers disabled until
//!   an explicit [`OutputGuard::clear`];
//! - maps any non-finite duty to 0 (raising [`Flags::NON_FINITE_OUTPUT`]);
//! - clamps every duty to the configured maximum (raising [`Flags::OUTPUT_LIMITED`]).
//!
//! [`phase_enable`] turns a guarded duty into what a phase/enable H-bridge (DRV887x class) needs:
//! the phase (direction) pin level and a PWM compare value.
//!
//! Duty convention: a duty `d` in [-1, 1] is the signed fraction of the PWM period the bridge
//! drives; `d ≥ 0` drives the phase pin high ("forward": current from OUT1 to OUT2), `d < 0` low.

use crate::controller::{ParamError, TickOutput};
use crate::flags::Flags;

/// Flags that latch a fault in the guard (outputs held at zero torque until cleared).
pub const LATCHING: Flags = Flags(
    Flags::DRIVER_FAULT.0 | Flags::ENCODER_GLITCH.0 | Flags::NON_FINITE_OUTPUT.0 | Flags::OVERRUN.0,
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

/// The guard's limits.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GuardConfig {
    /// Largest duty magnitude ever written, in (0, 1].
    pub max_duty: f32,
    /// Consecutive overrun ticks that latch [`Flags::OVERRUN`]; at least 1.
    pub max_overrun_streak: u32,
}

impl GuardConfig {
    /// The tighter of a plain duty limit and the duty that produces `max_torque_nm` at stall.
    pub fn with_torque_limit(
        max_duty: f32,
        max_torque_nm: f32,
        motor: &MotorModel,
        max_overrun_streak: u32,
    ) -> Result<Self, ParamError> {
        let torque_duty = motor.duty_for_torque(max_torque_nm)?;
        let config = GuardConfig {
            max_duty: max_duty.min(torque_duty),
            max_overrun_streak,
        };
        config.validate()?;
        Ok(config)
    }

    /// Accept only a finite `max_duty` in (0, 1] and a streak limit of at least 1.
    pub fn validate(&self) -> Result<(), ParamError> {
        if self.max_duty.is_finite()
            && self.max_duty > 0.0
            && self.max_duty <= 1.0
            && self.max_overrun_streak >= 1
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

/// Duty limiter and fault latch. See the module documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct OutputGuard {
    config: GuardConfig,
    latched: Flags,
}

impl OutputGuard {
    /// A guard with no fault latched; an invalid configuration is rejected, never clamped.
    pub fn new(config: GuardConfig) -> Result<Self, ParamError> {
        config.validate()?;
        Ok(OutputGuard {
            config,
            latched: Flags::NONE,
        })
    }

    /// The limits in force.
    pub const fn config(&self) -> &GuardConfig {
        &self.config
    }

    /// The faults latched so far (empty when outputs may be enabled).
    pub const fn latched(&self) -> Flags {
        self.latched
    }

    /// Clear every latched fault (an explicit operator action). A condition still present latches
    /// again on the next [`OutputGuard::apply`].
    pub fn clear(&mut self) {
        self.latched = Flags::NONE;
    }

    /// Guard one controller output.
    ///
    /// - `events`: conditions the firmware observed this tick (e.g. [`Flags::DRIVER_FAULT`] when
    ///   the nFAULT line is asserted, [`Flags::ENCODER_GLITCH`] from the encoder bank).
    /// - `overrun_streak`: consecutive overrun ticks so far; reaching `max_overrun_streak` latches
    ///   [`Flags::OVERRUN`].
    pub fn apply(&mut self, out: &TickOutput, events: Flags, overrun_streak: u32) -> Guarded {
        let mut flags = out.flags | events;
        let finite_duties = out.duties.map(|d| if d.is_finite() { d } else { 0.0 });
        let reported_finite = out.force_n.x.is_finite()
            && out.force_n.y.is_finite()
            && out.force_n.z.is_finite()
            && out.tau_n_nm.is_finite();
        if finite_duties != out.duties || !reported_finite {
            // `!=` is also true for any NaN in `out.duties`, since NaN != 0.0.
            flags |= Flags::NON_FINITE_OUTPUT;
        }
        if overrun_streak >= self.config.max_overrun_streak {
            flags |= Flags::OVERRUN;
        }
        self.latched |= Flags(flags.0 & LATCHING.0);
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
/// 100 % duty. Magnitudes above 1 saturate at `full_scale`; a non-finite duty gives compare 0.
#[inline]
pub fn phase_enable(duty: f32, full_scale: u32) -> PhaseEnable {
    if !duty.is_finite() {
        return PhaseEnable {
            forward: true,
            compare: 0,
        };
    }
    let magnitude = duty.abs().min(1.0);
    // f32 has a 24-bit mantissa; timer full scales are ≤ 16 bits in practice, so the product is
    // exact to well under one count. `as` saturates, and the min() keeps the bound for any input.
    let compare = ((magnitude * full_scale as f32 + 0.5) as u32).min(full_scale);
    PhaseEnable {
        forward: duty >= 0.0,
        compare,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vec3::Vec3;

    fn config() -> GuardConfig {
        GuardConfig {
            max_duty: 0.8,
            max_overrun_streak: 3,
        }
    }

    fn out(duties: [f32; 3]) -> TickOutput {
        TickOutput {
            duties,
            enable: true,
            flags: Flags::NONE,
            probe_m: Vec3::ZERO,
            force_n: Vec3::new(0.5, 0.0, 1.0),
            tau_n_nm: 0.0,
            ..TickOutput::default()
        }
    }

    fn guard() -> OutputGuard {
        match OutputGuard::new(config()) {
            Ok(g) => g,
            Err(e) => panic!("valid config rejected: {e:?}"),
        }
    }

    #[test]
    fn nominal_duties_pass_unchanged() {
        let mut g = guard();
        let r = g.apply(&out([0.1, -0.5, 0.8]), Flags::NONE, 0);
        assert_eq!(r.duties, [0.1, -0.5, 0.8]);
        assert!(r.enable);
        assert!(r.flags.is_empty());
    }

    #[test]
    fn duties_are_clamped_to_the_limit_with_a_flag() {
        let mut g = guard();
        let r = g.apply(&out([1.0, -0.95, 0.3]), Flags::NONE, 0);
        assert_eq!(r.duties, [0.8, -0.8, 0.3]);
        assert!(r.enable);
        assert_eq!(r.flags, Flags::OUTPUT_LIMITED);
        assert!(g.latched().is_empty(), "limiting is not a fault");
    }

    #[test]
    fn non_finite_duty_zeroes_everything_and_latches() {
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let mut g = guard();
            let r = g.apply(&out([0.2, bad, 0.3]), Flags::NONE, 0);
            assert_eq!(r.duties, [0.0; 3]);
            assert!(!r.enable);
            assert!(r.flags.contains(Flags::NON_FINITE_OUTPUT));
            assert_eq!(g.latched(), Flags::NON_FINITE_OUTPUT);
            // Still latched with a good output next tick.
            let r = g.apply(&out([0.2, 0.2, 0.2]), Flags::NONE, 0);
            assert_eq!((r.duties, r.enable), ([0.0; 3], false));
        }
    }

    #[test]
    fn non_finite_reported_force_or_torque_latches() {
        let mut g = guard();
        let mut o = out([0.1; 3]);
        o.force_n.y = f32::NAN;
        assert!(!g.apply(&o, Flags::NONE, 0).enable);
        let mut g = guard();
        let mut o = out([0.1; 3]);
        o.tau_n_nm = f32::INFINITY;
        assert!(!g.apply(&o, Flags::NONE, 0).enable);
        assert_eq!(g.latched(), Flags::NON_FINITE_OUTPUT);
    }

    #[test]
    fn each_latching_event_disables_until_cleared() {
        for ev in [Flags::DRIVER_FAULT, Flags::ENCODER_GLITCH] {
            let mut g = guard();
            let r = g.apply(&out([0.5; 3]), ev, 0);
            assert_eq!((r.duties, r.enable), ([0.0; 3], false));
            assert!(r.flags.contains(ev));
            // The event is gone, the latch is not.
            let r = g.apply(&out([0.5; 3]), Flags::NONE, 0);
            assert_eq!((r.duties, r.enable), ([0.0; 3], false));
            assert_eq!(r.flags, ev);
            g.clear();
            let r = g.apply(&out([0.5; 3]), Flags::NONE, 0);
            assert_eq!((r.duties, r.enable), ([0.5; 3], true));
        }
    }

    #[test]
    fn latching_flags_reported_by_the_controller_also_latch() {
        let mut g = guard();
        let mut o = out([0.5; 3]);
        o.flags = Flags::DRIVER_FAULT | Flags::SPIN_SATURATED;
        g.apply(&o, Flags::NONE, 0);
        assert_eq!(g.latched(), Flags::DRIVER_FAULT, "only fault flags latch");
    }

    #[test]
    fn overrun_streak_latches_at_the_limit_only() {
        let mut g = guard();
        assert!(g.apply(&out([0.5; 3]), Flags::NONE, 2).enable);
        let r = g.apply(&out([0.5; 3]), Flags::NONE, 3);
        assert!(!r.enable);
        assert_eq!(g.latched(), Flags::OVERRUN);
    }

    #[test]
    fn condition_still_present_relatches_after_clear() {
        let mut g = guard();
        g.apply(&out([0.5; 3]), Flags::DRIVER_FAULT, 0);
        g.clear();
        let r = g.apply(&out([0.5; 3]), Flags::DRIVER_FAULT, 0);
        assert!(!r.enable);
        assert_eq!(g.latched(), Flags::DRIVER_FAULT);
    }

    #[test]
    fn controller_disable_gives_zero_without_latching() {
        let mut g = guard();
        let mut o = out([0.5; 3]);
        o.enable = false;
        let r = g.apply(&o, Flags::NONE, 0);
        assert_eq!((r.duties, r.enable), ([0.0; 3], false));
        assert!(g.latched().is_empty());
    }

    #[test]
    fn invalid_configs_are_rejected() {
        for max_duty in [0.0, -0.1, 1.01, f32::NAN, f32::INFINITY] {
            let c = GuardConfig {
                max_duty,
                max_overrun_streak: 3,
            };
            assert_eq!(
                OutputGuard::new(c).err(),
                Some(ParamError::OutOfRange("guard_config")),
                "{max_duty}"
            );
        }
        let c = GuardConfig {
            max_duty: 0.5,
            max_overrun_streak: 0,
        };
        assert_eq!(
            OutputGuard::new(c).err(),
            Some(ParamError::OutOfRange("guard_config"))
        );
        assert!(OutputGuard::new(GuardConfig {
            max_duty: 1.0,
            max_overrun_streak: 1
        })
        .is_ok());
    }

    #[test]
    fn torque_limit_becomes_a_duty_limit() {
        // kt = 0.02 N·m/A, R = 2 Ω, V = 24 V: 0.1 N·m needs 5 A, i.e. 10 V, i.e. duty 10/24.
        let m = MotorModel {
            kt_nm_per_a: 0.02,
            r_ohm: 2.0,
            v_supply: 24.0,
        };
        let d = m.duty_for_torque(0.1).unwrap_or(f32::NAN);
        // Tolerance: a few f32 ulps of the 0.4167 result (three roundings).
        assert!((d - 10.0 / 24.0).abs() < 1e-6, "{d}");
        let c = GuardConfig::with_torque_limit(0.9, 0.1, &m, 5);
        assert_eq!(c.map(|c| c.max_duty), Ok(d));
        // A loose torque limit leaves the duty limit in force.
        let c = GuardConfig::with_torque_limit(0.3, 0.1, &m, 5);
        assert_eq!(c.map(|c| c.max_duty), Ok(0.3));
        // Beyond stall at full duty the torque limit saturates at duty 1.
        assert_eq!(m.duty_for_torque(10.0), Ok(1.0));
        assert_eq!(
            m.duty_for_torque(-0.1),
            Err(ParamError::OutOfRange("motor_model_or_torque"))
        );
        assert_eq!(
            m.duty_for_torque(f32::NAN),
            Err(ParamError::OutOfRange("motor_model_or_torque"))
        );
        let bad = MotorModel { r_ohm: 0.0, ..m };
        assert_eq!(
            bad.duty_for_torque(0.1),
            Err(ParamError::OutOfRange("motor_model_or_torque"))
        );
        // A zero torque limit gives a zero duty limit, which the guard rejects.
        assert_eq!(
            GuardConfig::with_torque_limit(0.9, 0.0, &m, 5),
            Err(ParamError::OutOfRange("guard_config"))
        );
    }

    #[test]
    fn phase_enable_maps_sign_and_magnitude() {
        assert_eq!(
            phase_enable(0.5, 6800),
            PhaseEnable {
                forward: true,
                compare: 3400
            }
        );
        assert_eq!(
            phase_enable(-0.25, 6800),
            PhaseEnable {
                forward: false,
                compare: 1700
            }
        );
        assert_eq!(
            phase_enable(0.0, 6800),
            PhaseEnable {
                forward: true,
                compare: 0
            }
        );
        assert_eq!(
            phase_enable(1.0, 6800),
            PhaseEnable {
                forward: true,
                compare: 6800
            }
        );
        assert_eq!(
            phase_enable(-1.0, 6800),
            PhaseEnable {
                forward: false,
                compare: 6800
            }
        );
        // Out of range saturates; non-finite is off.
        assert_eq!(phase_enable(-3.0, 6800).compare, 6800);
        assert_eq!(
            phase_enable(f32::NAN, 6800),
            PhaseEnable {
                forward: true,
                compare: 0
            }
        );
        assert_eq!(phase_enable(f32::NEG_INFINITY, 6800).compare, 0);
        // Rounds to nearest: 0.1 · 6800 = 680 exactly; 1/6800 of full scale is one count.
        assert_eq!(phase_enable(0.1, 6800).compare, 680);
        assert_eq!(phase_enable(1.0 / 6800.0, 6800).compare, 1);
        assert_eq!(phase_enable(0.4 / 6800.0, 6800).compare, 0);
    }

    #[test]
    fn phase_enable_compare_never_exceeds_full_scale() {
        // Every duty step of 1/65536 across [-1, 1] against a 16-bit full scale.
        for k in -65_536i32..=65_536 {
            let d = k as f32 / 65_536.0;
            let p = phase_enable(d, 65_535);
            assert!(p.compare <= 65_535);
            // Independent expectation: |k|·65535/65536 rounded, computed in integers. Tolerance of
            // one count: the f32 product can land on the other side of a .5 rounding boundary.
            let expect = ((k.unsigned_abs() as u64 * 65_535 * 2 + 65_536) / (2 * 65_536)) as u32;
            assert!(
                p.compare.abs_diff(expect) <= 1,
                "k={k}: {} vs {expect}",
                p.compare
            );
        }
    }
}
