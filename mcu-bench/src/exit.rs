//! Semihosting exit status, and the panic and fault paths: any panic or hard fault prints a line and
//! ends QEMU with a failure status, so the host script never waits for a hung program.

use cortex_m_semihosting::{debug, hprintln};

/// End the emulation with success (`true`) or failure (`false`).
pub fn exit(success: bool) -> ! {
    debug::exit(if success {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    // Only reached when not running under a semihosting host.
    #[allow(clippy::empty_loop)]
    loop {}
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    hprintln!("PANIC {}", info);
    exit(false)
}

/// Installs a `HardFault` handler that reports the faulting PC and exits with failure. A usage fault
/// from an FP instruction with the FPU disabled (NOCP) escalates to HardFault and lands here. Invoke
/// once in each binary (an exception handler must live in the binary crate to be linked).
#[macro_export]
macro_rules! install_fault_handler {
    () => {
        #[cortex_m_rt::exception]
        unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
            cortex_m_semihosting::hprintln!("HARDFAULT pc={:#010x} {:?}", frame.pc(), frame);
            $crate::exit::exit(false)
        }
    };
}
