//! Duty → phase/enable bridge commands for DRV887x-class drivers (PH/EN mode), with direction
//! reversal that never drives the old magnitude in the new direction.
//!
//! A duty `d` in [-1, 1] becomes a phase pin level (`d ≥ 0`: forward, phase high) and a PWM
//! compare value `round(|d| · full_scale)`. The PWM compare is preloaded (see
//! [`super::board`]): it takes effect at the next PWM period start, while the phase pin switches
//! when written. Flipping the phase together with a new compare would drive the *old* magnitude
//! in the *new* direction until the period ends. So a reversal takes two ticks:
//!
//! 1. the tick that first asks for the other direction writes compare 0 with the old phase;
//! 2. the next tick flips the phase and writes the new compare, but only if compare 0 is known to
//!    be in effect: the previous tick wrote 0 and its writes finished before the next PWM period
//!    started (`last_write_on_time`); otherwise it holds compare 0 one more tick.
//!
//! Cost: one tick of zero drive on that motor per reversal (100 µs at 10 kHz).
//!
//! # Ordering contract for the firmware's writes (each tick, after `Pipeline::tick`)
//!
//! 1. If `pwm_enable` is false: disable the outputs first (EN low / TIM1 MOE off).
//! 2. Phase pins.
//! 3. Compare registers (preloaded), **after** the phase pins: a PWM period boundary falling
//!    between the two writes then loads the old compare, which is 0 whenever the phase changed.
//! 4. If `pwm_enable` is true: enable the outputs.
//! 5. nSLEEP = `driver_awake` (after step 1 when going to sleep).
//!
//! All writes of a tick must finish before the tick's first PWM period ends; the firmware reports
//! the timer count at the end of its writes (`RawInput::prev_write_done_counts`), and a late write
//! makes the mapper hold reversals one tick longer.

use crate::flags::Flags;

/// What the bridges get this tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BridgeCommands {
    /// Phase pin per motor: true (high) drives forward (positive duty).
    pub phase_forward: [bool; 3],
    /// PWM compare per motor, 0 ..= full scale (the PWM period in timer counts).
    pub compare: [u16; 3],
    /// Bridge outputs enabled (EN / TIM1 MOE). False: zero torque, outputs off.
    pub pwm_enable: bool,
    /// Drivers awake (nSLEEP high). False only at power-up and after a fault.
    pub driver_awake: bool,
}

impl BridgeCommands {
    /// Everything off: asleep, disabled, compare 0, phase forward (the power-up state).
    pub const OFF: BridgeCommands = BridgeCommands {
        phase_forward: [true; 3],
        compare: [0; 3],
        pwm_enable: false,
        driver_awake: false,
    };

    /// The signed duty these commands drive, per motor (0 when disabled or asleep).
    pub fn duties(&self, full_scale: u16) -> [f32; 3] {
        let mut d = [0.0f32; 3];
        if !(self.pwm_enable && self.driver_awake) || full_scale == 0 {
            return d;
        }
        for ((d, c), f) in d.iter_mut().zip(self.compare).zip(self.phase_forward) {
            let m = f32::from(c) / f32::from(full_scale);
            *d = if f { m } else { -m };
        }
        d
    }
}

/// Round `|duty| · full_scale` to a compare value; non-finite gives 0, beyond ±1 saturates.
#[inline]
pub fn duty_to_compare(duty: f32, full_scale: u16) -> u16 {
    if !duty.is_finite() {
        return 0;
    }
    let fs = f32::from(full_scale);
    // No clamp of |duty| to 1 first: `as` saturates, and for |duty| >= 1 the product rounds to at
    // least `full_scale`, so the integer min alone gives the bound, and the same value (a float
    // `min` is a library call on the Cortex-M4, about 10 instructions).
    ((duty.abs() * fs + 0.5) as u16).min(full_scale)
}

/// Stateful duty → bridge mapping (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BridgeMapper {
    full_scale: u16,
    phase: [bool; 3],
    wrote_zero: [bool; 3],
}

impl BridgeMapper {
    /// A mapper for a PWM whose 100 % compare is `full_scale`; phase forward, compare 0.
    pub const fn new(full_scale: u16) -> Self {
        BridgeMapper {
            full_scale,
            phase: [true; 3],
            wrote_zero: [true; 3],
        }
    }

    /// The compare value of 100 % duty.
    pub const fn full_scale(&self) -> u16 {
        self.full_scale
    }

    /// Map this tick's duties. `last_write_on_time`: the previous tick's writes finished within its
    /// first PWM period. Returns phases, compares and [`Flags::OUTPUT_LIMITED`] when a reversal
    /// was held at zero this tick.
    #[must_use]
    pub fn map(
        &mut self,
        duties: [f32; 3],
        last_write_on_time: bool,
    ) -> ([bool; 3], [u16; 3], Flags) {
        let mut compare = [0u16; 3];
        let mut flags = Flags::NONE;
        for i in 0..3 {
            let want = duty_to_compare(duties[i], self.full_scale);
            // NaN maps to compare 0 above, so its direction does not matter.
            let forward = duties[i] >= 0.0 || duties[i].is_nan();
            if want != 0 && forward != self.phase[i] {
                if self.wrote_zero[i] && last_write_on_time {
                    self.phase[i] = forward;
                    compare[i] = want;
                } else {
                    flags |= Flags::OUTPUT_LIMITED;
                }
            } else {
                compare[i] = want;
            }
            self.wrote_zero[i] = compare[i] == 0;
        }
        (self.phase, compare, flags)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compare_rounds_and_saturates() {
        assert_eq!(duty_to_compare(0.5, 8500), 4250);
        assert_eq!(duty_to_compare(-0.25, 8500), 2125);
        assert_eq!(duty_to_compare(1.0, 8500), 8500);
        assert_eq!(duty_to_compare(-7.0, 8500), 8500);
        // The saturation's edge, just below and just above 100 %.
        assert_eq!(duty_to_compare(0.9999, 8500), 8499);
        assert_eq!(duty_to_compare(-1.0001, 8500), 8500);
        assert_eq!(duty_to_compare(1.0e30, 8500), 8500);
        assert_eq!(duty_to_compare(f32::NAN, 8500), 0);
        assert_eq!(duty_to_compare(f32::INFINITY, 8500), 0);
        // Half a count rounds up, just under half a count rounds down.
        assert_eq!(duty_to_compare(0.5 / 8500.0, 8500), 1);
        assert_eq!(duty_to_compare(0.49 / 8500.0, 8500), 0);
    }

    #[test]
    fn same_direction_passes_straight_through() {
        let mut m = BridgeMapper::new(8500);
        assert_eq!(
            m.map([0.1, 0.2, 0.0], true),
            ([true; 3], [850, 1700, 0], Flags::NONE)
        );
        assert_eq!(
            m.map([0.3, 0.0, 0.1], true),
            ([true; 3], [2550, 0, 850], Flags::NONE)
        );
    }

    #[test]
    fn reversal_holds_zero_for_one_tick_then_flips() {
        let mut m = BridgeMapper::new(8500);
        let _ = m.map([0.2, 0.0, 0.0], true);
        // Ask for reverse: compare 0, old phase.
        let (p, c, f) = m.map([-0.2, 0.0, 0.0], true);
        assert_eq!((p[0], c[0]), (true, 0));
        assert_eq!(f, Flags::OUTPUT_LIMITED);
        // Zero is in effect now: flip with the new compare.
        let (p, c, f) = m.map([-0.2, 0.0, 0.0], true);
        assert_eq!((p[0], c[0]), (false, 1700));
        assert_eq!(f, Flags::NONE);
    }

    #[test]
    fn reversal_from_an_explicit_zero_flips_at_once() {
        let mut m = BridgeMapper::new(8500);
        let _ = m.map([0.2, 0.0, 0.0], true);
        let _ = m.map([0.0, 0.0, 0.0], true);
        let (p, c, _) = m.map([-0.1, 0.0, 0.0], true);
        assert_eq!((p[0], c[0]), (false, 850));
    }

    #[test]
    fn a_late_write_holds_the_reversal_one_more_tick() {
        let mut m = BridgeMapper::new(8500);
        let _ = m.map([0.2, 0.0, 0.0], true);
        let _ = m.map([-0.2, 0.0, 0.0], true);
        // The zero was written, but too late to be sure it took effect.
        let (p, c, f) = m.map([-0.2, 0.0, 0.0], false);
        assert_eq!((p[0], c[0], f), (true, 0, Flags::OUTPUT_LIMITED));
        let (p, c, _) = m.map([-0.2, 0.0, 0.0], true);
        assert_eq!((p[0], c[0]), (false, 1700));
    }

    /// No sequence of duties and write timings ever changes the phase unless the compare written
    /// by the previous tick was 0 and on time (checked against an independent replay).
    #[test]
    fn phase_changes_only_after_an_on_time_zero() {
        let mut m = BridgeMapper::new(1000);
        let mut seed = 0x1234_5678u32;
        let mut prev = (m.phase, [0u16; 3]);
        for _ in 0..20_000 {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            let d = [
                (seed & 0xff) as f32 / 127.5 - 1.0,
                ((seed >> 8) & 0xff) as f32 / 127.5 - 1.0,
                0.0,
            ];
            let on_time = seed & 0x3000_0000 != 0;
            let (p, c, _) = m.map(d, on_time);
            for i in 0..3 {
                if p[i] != prev.0[i] {
                    assert!(
                        prev.1[i] == 0 && on_time,
                        "phase flip without a settled zero"
                    );
                }
                assert!(c[i] <= 1000);
            }
            prev = (p, c);
        }
    }

    #[test]
    fn duties_reconstruct_the_signed_command() {
        let b = BridgeCommands {
            phase_forward: [true, false, true],
            compare: [4250, 850, 0],
            pwm_enable: true,
            driver_awake: true,
        };
        assert_eq!(b.duties(8500), [0.5, -0.1, 0.0]);
        assert_eq!(
            BridgeCommands {
                pwm_enable: false,
                ..b
            }
            .duties(8500),
            [0.0; 3]
        );
        assert_eq!(
            BridgeCommands {
                driver_awake: false,
                ..b
            }
            .duties(8500),
            [0.0; 3]
        );
    }
}
