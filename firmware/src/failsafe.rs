//! Panic and HardFault handlers: zero the bridge outputs first (raw register writes, no ownership
//! needed), then log, then wait for the independent watchdog to reset the MCU.
//!
//! Interrupts are masked first (one `cpsid i`), so the control tick cannot run again and re-enable
//! the bridges; it then no longer pets the watchdog, which resets the MCU within
//! `config::WATCHDOG_TIMEOUT_US` (if the fault happens before the watchdog was started, the MCU
//! stays in this state with the outputs zeroed until reset by hand). After reset every pin is an
//! undriven input and the drivers' nSLEEP/EN pull-downs hold them off.

use core::panic::PanicInfo;
use core::sync::atomic::{AtomicBool, Ordering};

use cortex_m_rt::{exception, ExceptionFrame};

use crate::board::emergency_stop;

/// Set by the first panic: a panic while logging the first (e.g. inside the logger) skips logging.
static PANICKED: AtomicBool = AtomicBool::new(false);

/// Wait for the watchdog with the outputs zeroed.
pub fn halt() -> ! {
    loop {
        core::hint::spin_loop();
    }
}

#[panic_handler]
fn panic(info: &PanicInfo) -> ! {
    cortex_m::interrupt::disable();
    emergency_stop();
    if !PANICKED.swap(true, Ordering::Relaxed) {
        // Location only: formatting the message would link `core::fmt` (and float formatting).
        match info.location() {
            Some(l) => defmt::error!(
                "PANIC at {=str}:{=u32}; bridges off, waiting for the watchdog",
                l.file(),
                l.line()
            ),
            None => defmt::error!("PANIC; bridges off, waiting for the watchdog"),
        }
    }
    halt()
}

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    emergency_stop();
    defmt::error!(
        "HardFault at pc {=u32:#010x} (lr {=u32:#010x}); bridges off, waiting for the watchdog",
        frame.pc(),
        frame.lr()
    );
    halt()
}
