//! The `critical-section` implementation: BASEPRI masks every interrupt from priority 1 down, and
//! never priority 0, where only the control tick runs.
//!
//! A PRIMASK-based critical section (`cortex-m/critical-section-single-core`) would delay the tick
//! by however long a task holds one: embassy's timer queue, the executor, the button's EXTI
//! driver. With this one the tick is never delayed by software. The price is that the tick is not
//! excluded by a critical section, so it must not share data with other contexts through one: it
//! shares only atomics and lock-free SPSC queues (`tick`, `isr_cell`), and calls nothing that
//! takes a critical section over shared state (register accesses, atomics and SPSC queues only).
//! Every device interrupt other than the tick is set to a lower priority before the HAL starts
//! (`board::stm32g474::prepare_core`). Taken inside the tick (P0), the section masks nothing that
//! could preempt it anyway, so it stays correct there.

use cortex_m::register::{basepri, basepri_max};

use crate::board::BASEPRI_BELOW_TICK;

struct BasepriCriticalSection;
critical_section::set_impl!(BasepriCriticalSection);

// SAFETY: acquire raises BASEPRI to mask every priority numerically >= BASEPRI_BELOW_TICK (all but
// priority 0) and returns the previous value; release restores exactly that value, so nested
// sections unwind correctly. Both are compiler memory barriers (the `msr` asm blocks clobber
// memory and are followed by `isb`), so no access moves out of the section. Single core: no other
// CPU to exclude. Priority-0 code shares no data through critical sections (module docs).
unsafe impl critical_section::Impl for BasepriCriticalSection {
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
