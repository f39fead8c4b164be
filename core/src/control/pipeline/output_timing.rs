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
//! **Low-latency output** (what the firmware does, `firmware/src/board/stm32g474.rs`): the control
//! tick starts on a PWM period boundary (`pwm_periods_per_tick()` PWM periods per tick), the
//! interrupt reads the encoders first and writes the three compare registers as soon as the duties
//! are known — before telemetry and statistics — and the compare preload loads them at every PWM
//! period boundary. With the board's 40 kHz PWM ([`BoardTiming::STM32G474_10KHZ`]) and a compute
//! time under one PWM period (25 µs) the delay is a quarter tick at 10 kHz and half a tick at
//! 20 kHz ([`BoardTiming::STM32G474_20KHZ`]); with the PWM period equal to the tick it would be a
//! full tick.

use super::board::BoardTiming;

/// Cycles per instruction assumed for the tick's code executing from CCM SRAM (zero wait
/// states): the middle of mcu-bench's 1.1-1.5 range. The 10 kHz tick's write stays in its first
/// 40 kHz PWM period up to 4 250 / (sample + pipeline instructions) cycles per instruction (1.58
/// for the planned tick). Derivation: docs/design.md#tick-timer-and-output-timing-on-the-stm32g474.
pub const CCM_CYCLES_PER_INSTRUCTION: f32 = 1.25;

/// Instructions from the tick's timer event to the encoder sample: interrupt entry (12 cycles of
/// stacking) and six timer-register reads, rounded up.
pub const SAMPLE_INSTRUCTIONS: u32 = 40;

/// Instructions of the pipeline tick planned for, between the sample and the compare write: set
/// from `scripts/mcu-bench`'s `pipeline_tick` row (fast backend, passivity stage included; its
/// current figure is in `mcu-bench/budget.json`; `tests/walls.rs` fails when the two part by more
/// than that file's tolerance). Only whole PWM periods matter: with 40 kHz PWM
/// any figure up to 3 350 gives the same delay. On the firmware `scripts/pil` measures the sample
/// and the latest compare write of every tick (`firmware/pil/README.md`, "Measured").
pub const PIPELINE_TICK_INSTRUCTIONS: u32 = 2_657;

/// The cycles per instruction at which a compare write `write_instructions` after the tick's
/// event reaches the end of the first PWM period of `board`: below it the write is in time for
/// the second period, at or above it the delay grows by a PWM period. Infinite for 0
/// instructions; 0 for a zero PWM period.
pub fn cpi_margin(board: &BoardTiming, write_instructions: u32) -> f32 {
    if write_instructions == 0 {
        return f32::INFINITY;
    }
    board.pwm_period_counts() as f32 / write_instructions as f32
}

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

    const BOARD_10K: BoardTiming = BoardTiming::STM32G474_10KHZ;
    const BOARD_20K: BoardTiming = BoardTiming::STM32G474_20KHZ;

    #[test]
    fn effect_is_the_next_pwm_period_start_after_the_write() {
        // 40 kHz PWM: 4250 counts. A write at 4249 takes effect at 4250; at 4250 (the boundary
        // itself, too late for that update) at 8500.
        let b = BOARD_10K;
        assert!(b.is_valid());
        let t = OutputTiming::new(&b, 50, 4_199);
        assert_eq!((t.write_counts, t.effect_counts), (4_249, 4_250));
        assert_eq!(t.delay_counts(), 4_200);
        let t = OutputTiming::new(&b, 50, 4_200);
        assert_eq!(t.effect_counts, 8_500);
        // 20 kHz PWM, 10 kHz control: half a tick for any compute under 50 µs.
        let pwm_20k = BoardTiming {
            pwm_hz: 20_000,
            ..BOARD_10K
        };
        let t = OutputTiming::new(&pwm_20k, 0, 2_000);
        assert_eq!(t.delay_ticks(), 0.5);
        // PWM period = tick: a full tick.
        let one_period = BoardTiming {
            pwm_hz: 20_000,
            ..BOARD_20K
        };
        let t = OutputTiming::new(&one_period, 0, 2_000);
        assert_eq!(t.delay_ticks(), 1.0);
        assert!(t.within_tick());
        // A compute longer than the tick: the delay exceeds a tick.
        let t = OutputTiming::new(&one_period, 0, 8_500);
        assert!(!t.within_tick() && t.delay_ticks() == 2.0);
    }

    /// The firmware's timing, derived from the board constants: the compare acts one PWM period
    /// after the tick's event, i.e. 1 / pwm_periods_per_tick of a tick (a quarter at 10 kHz,
    /// half at 20 kHz) less the sample instant. Fails when the planned tick outgrows 25 µs or a
    /// board constant changes the PWM multiple.
    #[test]
    fn planned_tick_fits_the_first_pwm_period() {
        for b in [BOARD_10K, BOARD_20K] {
            let t = OutputTiming::planned(&b);
            assert_eq!(t.effect_counts, b.pwm_period_counts());
            assert!(t.write_counts < b.pwm_period_counts() && t.within_tick());
            let expected =
                (b.pwm_period_counts() - t.sample_counts) as f32 / b.tick_period_counts() as f32;
            assert_eq!(t.delay_ticks(), expected);
            let quarter_or_half = 1.0 / b.pwm_periods_per_tick() as f32;
            assert!((t.delay_ticks() - quarter_or_half).abs() < 0.01);
        }
        assert_eq!(BOARD_10K.pwm_periods_per_tick(), 4);
        assert_eq!(BOARD_20K.pwm_periods_per_tick(), 2);
    }

    /// The CPI margin of the planned tick: 4250 / (40 + 2657) = 1.576; just below it the write
    /// is in time for the second PWM period, at it the delay grows by a PWM period.
    #[test]
    fn cpi_margin_is_the_edge_of_the_first_pwm_period() {
        let n = SAMPLE_INSTRUCTIONS + PIPELINE_TICK_INSTRUCTIONS;
        let m = cpi_margin(&BOARD_10K, n);
        // Measured exact; bound 1 ulp of 1.58 (1.2e-7), an ulp argument.
        assert!((m - 4_250.0 / 2_697.0).abs() <= 1.2e-7, "{m}");
        let at = |cpi: f32| OutputTiming::new(&BOARD_10K, 0, (n as f32 * cpi) as u32);
        assert_eq!(at(0.999 * m).effect_counts, 4_250);
        assert_eq!(at(m).effect_counts, 8_500);
        assert!(
            m > 1.5,
            "the planned tick must fit at the top of the 1.1-1.5 range"
        );
        assert_eq!(cpi_margin(&BOARD_10K, 0), f32::INFINITY);
    }

    #[test]
    fn from_instructions_uses_the_stated_cpi() {
        // 2000 instructions × 1.25 = 2500 cycles = 14.7 µs at 170 MHz: under 25 µs, so a
        // quarter tick at 40 kHz PWM less the 51-count sample instant.
        let t = OutputTiming::from_instructions(&BOARD_10K, 2_000, CCM_CYCLES_PER_INSTRUCTION);
        assert_eq!(t.sample_counts, 51);
        assert_eq!(t.write_counts, 51 + 2_501);
        assert_eq!(t.effect_counts, 4_250);
        // Measured exact; bound 1 ulp of 0.247 (1.5e-8), an ulp argument.
        assert!((t.delay_ticks() - (4_250.0 - 51.0) / 17_000.0).abs() <= 1.5e-8);
        // 3400 instructions × 1.25 = 4250 cycles: the write misses the first PWM period.
        let t = OutputTiming::from_instructions(&BOARD_10K, 3_400, CCM_CYCLES_PER_INSTRUCTION);
        assert_eq!(t.effect_counts, 8_500);
        // A bad CPI falls back to 1.5.
        let t = OutputTiming::from_instructions(&BOARD_10K, 1_000, f32::NAN);
        assert_eq!(t.sample_counts, 61);
    }
}
