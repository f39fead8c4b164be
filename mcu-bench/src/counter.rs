//! Counting executed instructions with SysTick under QEMU `-icount shift=0`.
//!
//! With `-icount shift=0` QEMU advances virtual time by exactly 1 ns per executed guest instruction,
//! and on `mps2-an386` SysTick counts at the 25 MHz system clock, i.e. one SysTick count per 40 ns =
//! 40 instructions. Elapsed counts × 40 is therefore an instruction count with a resolution of 40
//! instructions, identical on every run. (The DWT cycle counter reads 0 under QEMU, so it is no use.)
//!
//! SysTick is a 24-bit down-counter; [`Counter`] free-runs it over its full range and computes
//! elapsed counts modulo 2^24, so one measured interval must stay below 2^24 counts (671 million
//! instructions). The harness checks this before it measures.

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;

/// Instructions per SysTick count: 25 MHz SysTick, 1 ns per instruction under `-icount shift=0`.
pub const INSTRUCTIONS_PER_COUNT: u32 = 40;

/// SysTick's full 24-bit range.
const MASK: u32 = 0x00FF_FFFF;

/// The largest interval [`Counter::elapsed`] can measure without ambiguity, in SysTick counts. Kept
/// at half the counter range as a safety margin.
pub const MAX_INTERVAL_COUNTS: u32 = MASK / 2;

/// SysTick free-running over its whole 24-bit range, interrupt off.
pub struct Counter {
    syst: SYST,
}

impl Counter {
    /// Take SysTick and start it: processor clock, reload 2^24 - 1, no interrupt.
    pub fn new(mut syst: SYST) -> Counter {
        syst.disable_counter();
        syst.disable_interrupt();
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(MASK);
        syst.clear_current();
        syst.enable_counter();
        Counter { syst }
    }

    /// The current SysTick value (counts down).
    #[inline(always)]
    pub fn now(&self) -> u32 {
        let _ = &self.syst;
        SYST::get_current()
    }

    /// Counts elapsed from `start` (an earlier [`Counter::now`]) to `end`, modulo 2^24.
    #[inline(always)]
    pub fn elapsed(start: u32, end: u32) -> u32 {
        start.wrapping_sub(end) & MASK
    }
}
