//! Board timing shared by the firmware's timer set-up and host-sim's plant: one definition, so
//! the simulated PWM and tick periods are the firmware's.
//!
//! Conventions (the firmware's timer configuration must honour them):
//! - One timer clock (`timer_clock_hz`) drives the PWM timer (TIM1 on the STM32G474) and the tick
//!   timer; every count in this crate's timing figures is one period of that clock.
//! - PWM is edge-aligned, counting up: `pwm_period_counts()` counts per period (ARR = period − 1),
//!   and a compare value equal to the period is 100 % duty (the full scale).
//! - **Compare preload**: a compare value written during PWM period n takes effect at the start of
//!   period n + 1 (CCR preload, an update event every period). The phase (direction) pins and the
//!   bridge enable are GPIO or output-enable writes: they take effect when written.
//! - The control tick starts on a PWM period boundary and lasts an integer number of PWM periods
//!   (`pwm_periods_per_tick()`), so every tick boundary is a PWM period boundary.

/// Why a [`BoardTiming`] was rejected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TimingError {
    /// A clock or rate is zero.
    ZeroRate,
    /// The timer clock is not an integer multiple of the PWM frequency.
    PwmPeriodNotInteger,
    /// The PWM frequency is not an integer multiple of the control rate.
    PwmNotMultipleOfControl,
    /// The PWM frequency is below 20 kHz (audible).
    PwmAudible,
    /// The control rate is outside 1 kHz ..= 40 kHz.
    ControlRateOutOfRange,
    /// The PWM period does not fit a 16-bit compare register (or is below 100 counts).
    PwmPeriodOutOfRange,
}

impl core::fmt::Display for TimingError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            TimingError::ZeroRate => "timer_clock_hz, pwm_hz and control_hz must be > 0",
            TimingError::PwmPeriodNotInteger => {
                "timer_clock_hz must be an integer multiple of pwm_hz"
            }
            TimingError::PwmNotMultipleOfControl => {
                "pwm_hz must be an integer multiple of control_hz"
            }
            TimingError::PwmAudible => "pwm_hz must be >= 20 kHz (below is audible)",
            TimingError::ControlRateOutOfRange => "control_hz must be in 1 kHz ..= 40 kHz",
            TimingError::PwmPeriodOutOfRange => {
                "the PWM period (timer_clock_hz / pwm_hz) must be in 100 ..= 65535 counts"
            }
        })
    }
}

impl core::error::Error for TimingError {}

/// Timer clock, PWM frequency and control rate of a board.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BoardTiming {
    /// Clock of the PWM and tick timers, Hz.
    pub timer_clock_hz: u32,
    /// Motor PWM frequency, Hz.
    pub pwm_hz: u32,
    /// Control tick rate, Hz.
    pub control_hz: u32,
}

impl BoardTiming {
    /// What the firmware runs (`firmware/src/config.rs`): STM32G474 at 170 MHz, 40 kHz PWM
    /// (4250 counts per period), 10 kHz control (four PWM periods per tick). The low-latency
    /// output of [`super::output_timing`]: a compare written in the tick's first PWM period acts
    /// from its second, a quarter tick after the tick's event.
    pub const STM32G474_10KHZ: BoardTiming = BoardTiming {
        timer_clock_hz: 170_000_000,
        pwm_hz: 40_000,
        control_hz: 10_000,
    };

    /// STM32G474 at 170 MHz, 40 kHz PWM, 20 kHz control (two PWM periods per tick: the
    /// compare acts half a tick after the tick's event).
    pub const STM32G474_20KHZ: BoardTiming = BoardTiming {
        control_hz: 20_000,
        ..BoardTiming::STM32G474_10KHZ
    };

    /// Check the timing; `const` so a firmware can assert it at compile time.
    pub const fn validate(&self) -> Result<(), TimingError> {
        if self.timer_clock_hz == 0 || self.pwm_hz == 0 || self.control_hz == 0 {
            return Err(TimingError::ZeroRate);
        }
        if self.pwm_hz < 20_000 {
            return Err(TimingError::PwmAudible);
        }
        if self.control_hz < 1_000 || self.control_hz > 40_000 {
            return Err(TimingError::ControlRateOutOfRange);
        }
        if !self.timer_clock_hz.is_multiple_of(self.pwm_hz) {
            return Err(TimingError::PwmPeriodNotInteger);
        }
        if !self.pwm_hz.is_multiple_of(self.control_hz) {
            return Err(TimingError::PwmNotMultipleOfControl);
        }
        let period = self.timer_clock_hz / self.pwm_hz;
        if period < 100 || period > u16::MAX as u32 {
            return Err(TimingError::PwmPeriodOutOfRange);
        }
        Ok(())
    }

    /// `validate().is_ok()` as a `const fn` (for `const _: () = assert!(...)`).
    pub const fn is_valid(&self) -> bool {
        self.validate().is_ok()
    }

    /// Timer counts per PWM period, which is also the compare value of 100 % duty.
    pub const fn pwm_period_counts(&self) -> u32 {
        if self.pwm_hz == 0 {
            return 0;
        }
        self.timer_clock_hz / self.pwm_hz
    }

    /// PWM periods per control tick (≥ 1 for a valid timing).
    pub const fn pwm_periods_per_tick(&self) -> u32 {
        if self.control_hz == 0 {
            return 0;
        }
        self.pwm_hz / self.control_hz
    }

    /// Timer counts per control tick.
    pub const fn tick_period_counts(&self) -> u32 {
        if self.control_hz == 0 {
            return 0;
        }
        self.timer_clock_hz / self.control_hz
    }

    /// Control tick period, s.
    pub fn tick_period_s(&self) -> f32 {
        1.0 / self.control_hz as f32
    }

    /// PWM period, s.
    pub fn pwm_period_s(&self) -> f32 {
        1.0 / self.pwm_hz as f32
    }
}

const _: () = assert!(BoardTiming::STM32G474_10KHZ.is_valid());
const _: () = assert!(BoardTiming::STM32G474_20KHZ.is_valid());
const _: () = assert!(BoardTiming::STM32G474_10KHZ.pwm_period_counts() == 4_250);
const _: () = assert!(BoardTiming::STM32G474_10KHZ.pwm_periods_per_tick() == 4);
const _: () = assert!(BoardTiming::STM32G474_20KHZ.pwm_periods_per_tick() == 2);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn g474_figures() {
        let t = BoardTiming::STM32G474_10KHZ;
        assert_eq!(t.pwm_period_counts(), 4_250);
        assert_eq!(t.tick_period_counts(), 17_000);
        assert_eq!(t.pwm_periods_per_tick(), 4);
        assert_eq!(BoardTiming::STM32G474_20KHZ.tick_period_counts(), 8_500);
        assert_eq!(BoardTiming::STM32G474_20KHZ.pwm_periods_per_tick(), 2);
    }

    #[test]
    fn every_rule_is_checked_at_its_edge() {
        let ok = BoardTiming::STM32G474_10KHZ;
        let with = |clk, pwm, ctl| BoardTiming {
            timer_clock_hz: clk,
            pwm_hz: pwm,
            control_hz: ctl,
        };
        assert_eq!(
            with(0, 20_000, 10_000).validate(),
            Err(TimingError::ZeroRate)
        );
        assert_eq!(
            with(ok.timer_clock_hz, 0, 10_000).validate(),
            Err(TimingError::ZeroRate)
        );
        assert_eq!(
            with(ok.timer_clock_hz, 20_000, 0).validate(),
            Err(TimingError::ZeroRate)
        );
        // 20 kHz is the lowest PWM allowed; 19 999 Hz is audible.
        assert_eq!(
            with(ok.timer_clock_hz, 19_999, 1_000).validate(),
            Err(TimingError::PwmAudible)
        );
        assert_eq!(with(ok.timer_clock_hz, 20_000, 1_000).validate(), Ok(()));
        // Control 1 kHz ..= 40 kHz.
        assert_eq!(
            with(40_000_000, 40_000, 999).validate(),
            Err(TimingError::ControlRateOutOfRange)
        );
        assert_eq!(with(80_000_000, 80_000, 40_000).validate(), Ok(()));
        assert_eq!(
            with(80_000_000, 80_000, 80_000).validate(),
            Err(TimingError::ControlRateOutOfRange)
        );
        // 25 kHz PWM is not a multiple of 10 kHz control; 30 kHz PWM at 170 MHz is not an
        // integer period (5666.7 counts).
        assert_eq!(
            with(ok.timer_clock_hz, 25_000, 10_000).validate(),
            Err(TimingError::PwmNotMultipleOfControl)
        );
        assert_eq!(
            with(ok.timer_clock_hz, 30_000, 10_000).validate(),
            Err(TimingError::PwmPeriodNotInteger)
        );
        // The period must fit 16 bits: 65 535 counts fits, 65 536 does not.
        assert_eq!(with(65_535 * 20_000, 20_000, 10_000).validate(), Ok(()));
        assert_eq!(
            with(65_536 * 20_000, 20_000, 10_000).validate(),
            Err(TimingError::PwmPeriodOutOfRange)
        );
        assert_eq!(with(100 * 20_000, 20_000, 10_000).validate(), Ok(()));
        assert_eq!(
            with(99 * 20_000, 20_000, 10_000).validate(),
            Err(TimingError::PwmPeriodOutOfRange)
        );
    }

    /// The message names the fields the rule relates.
    #[test]
    fn display_names_the_rule() {
        use std::string::ToString;
        let audible = BoardTiming {
            pwm_hz: 10_000,
            ..BoardTiming::STM32G474_10KHZ
        };
        let e: &dyn core::error::Error = &audible.validate().unwrap_err();
        assert_eq!(e.to_string(), "pwm_hz must be >= 20 kHz (below is audible)");
        assert_eq!(
            TimingError::PwmNotMultipleOfControl.to_string(),
            "pwm_hz must be an integer multiple of control_hz"
        );
    }
}
