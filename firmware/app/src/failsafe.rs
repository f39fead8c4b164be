//! Panic, HardFault and unexpected-interrupt handlers: zero the bridge outputs first (the board's
//! `emergency_stop`: raw register writes, no ownership needed), then log, then wait for the
//! independent watchdog to reset the MCU. A board binary installs them with
//! [`install_fail_safe!`](crate::install_fail_safe), naming its emergency stop.
//!
//! Interrupts are masked first (one `cpsid i`), so the control tick cannot run again and re-enable
//! the bridges; it then no longer pets the watchdog, which resets the MCU within
//! `config::WATCHDOG_TIMEOUT_US` (if the fault happens before the watchdog was started, the MCU
//! stays in this state with the outputs zeroed until reset by hand). After reset every pin is an
//! undriven input and the drivers' nSLEEP/EN pull-downs hold them off.

use core::panic::PanicInfo;
use core::sync::atomic::{AtomicBool, Ordering};

use cortex_m_rt::ExceptionFrame;

/// Set by the first panic: a panic while logging the first (e.g. inside the logger) skips logging.
static PANICKED: AtomicBool = AtomicBool::new(false);

/// Wait for the watchdog with the outputs zeroed.
pub fn halt() -> ! {
    loop {
        core::hint::spin_loop();
    }
}

/// The panic path: interrupts off, `emergency_stop`, the location logged once, halt.
pub fn on_panic(info: &PanicInfo, emergency_stop: fn()) -> ! {
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

/// The HardFault path: `emergency_stop`, the faulting pc and lr logged, halt.
pub fn on_hard_fault(frame: &ExceptionFrame, emergency_stop: fn()) -> ! {
    emergency_stop();
    cortex_m::interrupt::disable();
    defmt::error!(
        "HardFault at pc {=u32:#010x} (lr {=u32:#010x}); bridges off, waiting for the watchdog",
        frame.pc(),
        frame.lr()
    );
    halt()
}

/// An exception or interrupt with no handler of its own (`irqn`: the exception number minus 16,
/// negative for a core exception): `emergency_stop`, logged, halt. It does not return: returning
/// would re-enter at once for a pending level-triggered interrupt.
pub fn on_unexpected(irqn: i16, emergency_stop: fn()) -> ! {
    emergency_stop();
    cortex_m::interrupt::disable();
    defmt::error!(
        "unexpected exception (irqn {=i16}); bridges off, waiting for the watchdog",
        irqn
    );
    halt()
}

/// Install the panic handler, the HardFault handler and the default handler (every exception and
/// interrupt without its own), each calling `$emergency_stop: fn()` first. Once per binary.
#[macro_export]
macro_rules! install_fail_safe {
    ($emergency_stop:path) => {
        #[panic_handler]
        fn softfinger_panic(info: &core::panic::PanicInfo) -> ! {
            $crate::failsafe::on_panic(info, $emergency_stop)
        }

        #[cortex_m_rt::exception]
        unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
            $crate::failsafe::on_hard_fault(frame, $emergency_stop)
        }

        #[cortex_m_rt::exception]
        unsafe fn DefaultHandler(irqn: i16) -> ! {
            $crate::failsafe::on_unexpected(irqn, $emergency_stop)
        }
    };
}
