//! When the force computed from a sample acts on the device: the sample-to-output delay of a
//! [`BoardTiming`] and the tick's compute time.
//!
//! Timeline of one tick, in timer counts from the tick's timer event (a PWM period start, see
//! [`super::board`]):
//!
//! ```text
//! 0 ── sample (encoders read, `sample_counts`) ── compute ── compare written (`write_counts`)
//!   ── next PWM period start after the write: the compare takes effect (`effect_counts`)
//! ```
//!
//! The compare preload applies a value written during PWM period n at the start of period n + 1,
//! so the force computed from the sample acts from `effect_counts` on and holds for one control
//! tick (the next tick's compare takes effect at the same offset in its own tick). The
//! sample-to-output delay is `effect_counts − sample_counts`; in ticks it is the extra delay `d`
//! of the sampled-wall analysis, whose largest passive wall is about 2b/((1 + 2d)·T).
//!
//! **Low-latency output** (what the firmware must do for the delay computed here): trigger the
//! control tick from the PWM timer's update event (TIM1 update, one tick every
//! `pwm_periods_per_tick()` PWM periods, e.g. with the repetition counter), read the encoders
//! first, and write the three compare registers as soon as the duties are known — before
//! telemetry and statistics. With 40 kHz PWM at 10 kHz control and a compute time under one PWM
//! period (25 µs) the delay is a quarter tick; with 20 kHz PWM it is half a tick; with the PWM
//! period equal to the tick it is a full tick.

use super::board::BoardTiming;

/// Cycles per instruction assumed for the tick's code executing from CCM SRAM (no flash wait
/// states): the FP-heavy pipeline has loads, stores, taken branches and a few `VDIV`/`VSQRT`
/// above one cycle; 1.25 is the middle of the 1.1-1.5 range stated in `mcu-bench/README.md`.
pub const CCM_CYCLES_PER_INSTRUCTION: f32 = 1.25;

/// Instructions from the tick's timer event to the encoder sample: interrupt entry (12 cycles of
/// stacking) and six timer-register reads, rounded up.
pub const SAMPLE_INSTRUCTIONS: u32 = 40;

/// Instructions of the pipeline tick, an upper bound of those between the sample and the compare
/// write: `scripts/mcu-bench`'s `pipeline_tick` row (fast backend, passivity stage included:
/// 2 580 measured). At 1.25 cycles per instruction that is 19.0 µs at 170 MHz. Only whole PWM
/// periods matter: with 40 kHz PWM any figure up to 3 350 gives the same delay.
pub const PIPELINE_TICK_INSTRUCTIONS: u32 = 2_580;

/// The low-latency board timings: 40 kHz PWM (4 250 counts per period at 170 MHz), four PWM
/// periods per 10 kHz tick and two per 20 kHz tick.
pub const LOW_LATENCY_10KHZ: BoardTiming = BoardTiming {
    pwm_hz: 40_000,
    ..BoardTiming::STM32G474_10KHZ
};
/// See [`LOW_LATENCY_10KHZ`].
pub const LOW_LATENCY_20KHZ: BoardTiming = BoardTiming {
    pwm_hz: 40_000,
    ..BoardTiming::STM32G474_20KHZ
};
const _: () = assert!(LOW_LATENCY_10KHZ.is_valid() && LOW_LATENCY_20KHZ.is_valid());

/// The instants of one tick and the delay they give.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct OutputTiming {
    /// Timer counts per control tick.
    pub tick_counts: u32,
    /// Timer counts per PWM period.
    pub pwm_counts: u32,
    /// Encoder sample instant after the tick's timer event, counts.
    pub sample_counts: u32,
    /// Compare-register write instant (sample + compute), counts.
    pub write_counts: u32,
    /// Instant the new compare takes effect: the first PWM period start after the write, counts.
    pub effect_counts: u32,
}

impl OutputTiming {
    /// The timing of `board` with the sample `sample_counts` after the timer event and the
    /// compare written `compute_counts` after the sample. A zero PWM period gives the
    /// conservative answer of a full tick's delay.
    pub const fn new(board: &BoardTiming, sample_counts: u32, compute_counts: u32) -> Self {
        let pwm = board.pwm_period_counts();
        let tick = board.tick_period_counts();
        let write = sample_counts.saturating_add(compute_counts);
        let effect = match write.checked_div(pwm) {
            Some(n) => (n + 1).saturating_mul(pwm),
            None => sample_counts.saturating_add(tick),
        };
        OutputTiming {
            tick_counts: tick,
            pwm_counts: pwm,
            sample_counts,
            write_counts: write,
            effect_counts: effect,
        }
    }

    /// The timing of `board` for a tick of `instructions` instructions between the sample and the
    /// compare write at `cycles_per_instruction`, the core clocked at the timer clock.
    pub fn from_instructions(
        board: &BoardTiming,
        instructions: u32,
        cycles_per_instruction: f32,
    ) -> Self {
        let cpi = if cycles_per_instruction.is_finite() && cycles_per_instruction > 0.0 {
            cycles_per_instruction
        } else {
            1.5
        };
        let compute = instructions as f32 * cpi;
        let compute = if compute < u32::MAX as f32 {
            compute as u32 + 1
        } else {
            u32::MAX
        };
        let sample = (SAMPLE_INSTRUCTIONS as f32 * cpi) as u32 + 1;
        Self::new(board, sample, compute)
    }

    /// The timing of `board` with the planned pipeline tick ([`PIPELINE_TICK_INSTRUCTIONS`] at
    /// [`CCM_CYCLES_PER_INSTRUCTION`]).
    pub fn planned(board: &BoardTiming) -> Self {
        Self::from_instructions(
            board,
            PIPELINE_TICK_INSTRUCTIONS,
            CCM_CYCLES_PER_INSTRUCTION,
        )
    }

    /// Sample-to-output delay, timer counts.
    pub const fn delay_counts(&self) -> u32 {
        self.effect_counts.saturating_sub(self.sample_counts)
    }

    /// Sample-to-output delay in control ticks (0.25 for 40 kHz PWM at 10 kHz control with a
    /// compute time under 25 µs). 1 when the tick period is 0.
    pub fn delay_ticks(&self) -> f32 {
        if self.tick_counts == 0 {
            return 1.0;
        }
        self.delay_counts() as f32 / self.tick_counts as f32
    }

    /// True when the compare takes effect within the tick that computed it (a delay of less than
    /// a tick beyond the sample).
    pub const fn within_tick(&self) -> bool {
        self.effect_counts <= self.tick_counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LOW_LATENCY: BoardTiming = LOW_LATENCY_10KHZ;

    #[test]
    fn effect_is_the_next_pwm_period_start_after_the_write() {
        // 40 kHz PWM: 4250 counts. A write at 4249 takes effect at 4250; at 4250 (the boundary
        // itself, too late for that update) at 8500.
        let b = LOW_LATENCY;
        assert!(b.is_valid());
        let t = OutputTiming::new(&b, 50, 4_199);
        assert_eq!((t.write_counts, t.effect_counts), (4_249, 4_250));
        assert_eq!(t.delay_counts(), 4_200);
        let t = OutputTiming::new(&b, 50, 4_200);
        assert_eq!(t.effect_counts, 8_500);
        // 20 kHz PWM, 10 kHz control: half a tick for any compute under 50 µs.
        let t = OutputTiming::new(&BoardTiming::STM32G474_10KHZ, 0, 2_000);
        assert_eq!(t.delay_ticks(), 0.5);
        // PWM period = tick: a full tick.
        let t = OutputTiming::new(&BoardTiming::STM32G474_20KHZ, 0, 2_000);
        assert_eq!(t.delay_ticks(), 1.0);
        assert!(t.within_tick());
        // A compute longer than the tick: the delay exceeds a tick.
        let t = OutputTiming::new(&BoardTiming::STM32G474_20KHZ, 0, 8_500);
        assert!(!t.within_tick() && t.delay_ticks() == 2.0);
    }

    /// The measured pipeline tick fits the first 40 kHz PWM period: a quarter tick at 10 kHz,
    /// half a tick at 20 kHz (less the sample instant). Fails when the tick outgrows 25 µs.
    #[test]
    fn planned_tick_fits_the_first_pwm_period() {
        for (b, ticks) in [(LOW_LATENCY_10KHZ, 0.25f32), (LOW_LATENCY_20KHZ, 0.5)] {
            let t = OutputTiming::planned(&b);
            assert_eq!(t.effect_counts, 4_250);
            assert!(t.write_counts < 4_250 && t.within_tick());
            assert!(
                (t.delay_ticks() - ticks).abs() < 0.01,
                "{}",
                t.delay_ticks()
            );
        }
        // On today's 20 kHz PWM the same tick waits half a 10 kHz tick.
        let t = OutputTiming::planned(&BoardTiming::STM32G474_10KHZ);
        assert_eq!(t.effect_counts, 8_500);
    }

    #[test]
    fn from_instructions_uses_the_stated_cpi() {
        // 2000 instructions × 1.25 = 2500 cycles = 14.7 µs at 170 MHz: under 25 µs, so a
        // quarter tick at 40 kHz PWM less the 51-count sample instant.
        let t = OutputTiming::from_instructions(&LOW_LATENCY, 2_000, CCM_CYCLES_PER_INSTRUCTION);
        assert_eq!(t.sample_counts, 51);
        assert_eq!(t.write_counts, 51 + 2_501);
        assert_eq!(t.effect_counts, 4_250);
        assert!((t.delay_ticks() - (4_250.0 - 51.0) / 17_000.0).abs() < 1e-7);
        // 3400 instructions × 1.25 = 4250 cycles: the write misses the first PWM period.
        let t = OutputTiming::from_instructions(&LOW_LATENCY, 3_400, CCM_CYCLES_PER_INSTRUCTION);
        assert_eq!(t.effect_counts, 8_500);
        // A bad CPI falls back to 1.5.
        let t = OutputTiming::from_instructions(&LOW_LATENCY, 1_000, f32::NAN);
        assert_eq!(t.sample_counts, 61);
    }
}
