//! The `critical-section` implementation: BASEPRI masks every interrupt from priority 1 down, and
//! never priority 0, where only the control tick runs.
//!
//! Contract: the tick (priority 0) is not excluded by a critical section, so it shares data with
//! other contexts only through atomics and lock-free SPSC queues (`tick`, `isr_cell`); every other
//! device interrupt is set below it before the HAL starts (the STM32 binary's
//! `board::stm32g474::prepare_core`).
//! Why BASEPRI rather than PRIMASK: docs/design.md#critical-sections-that-never-mask-the-tick.

use cortex_m::register::{basepri, basepri_max};

/// The critical section that raises BASEPRI to `BASEPRI_BELOW_TICK`: the board's value that masks
/// every priority but 0. A board binary installs it once:
/// `critical_section::set_impl!(BasepriCriticalSection<{ MASK }>);`.
pub struct BasepriCriticalSection<const BASEPRI_BELOW_TICK: u8>;

// SAFETY: acquire raises BASEPRI to mask every priority numerically >= BASEPRI_BELOW_TICK (all but
// priority 0) and returns the previous value; release restores exactly that value, so nested
// sections unwind correctly. Both are compiler memory barriers (the `msr` asm blocks clobber
// memory and are followed by `isb`), so no access moves out of the section. Single core: no other
// CPU to exclude. Priority-0 code shares no data through critical sections (module docs).
unsafe impl<const BASEPRI_BELOW_TICK: u8> critical_section::Impl
    for BasepriCriticalSection<BASEPRI_BELOW_TICK>
{
    unsafe fn acquire() -> critical_section::RawRestoreState {
        let previous = basepri::read();
        // Raises only: BASEPRI_MAX ignores a value that would unmask anything.
        basepri_max::write(BASEPRI_BELOW_TICK);
        u32::from(previous)
    }

    unsafe fn release(previous: critical_section::RawRestoreState) {
        // SAFETY: restores the value read by the matching acquire (a u8 widened to u32).
        unsafe { basepri::write(previous as u8) };
    }
}
