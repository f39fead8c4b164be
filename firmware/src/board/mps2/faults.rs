//! The watchdog's NMI on the emulated board (the app's `failsafe` handles panics and HardFaults:
//! bridges off, then wait for the watchdog): bridges off, tell the plant when the reset comes,
//! and leave the reset cause in `.uninit` RAM for the next boot to report.
#![allow(unsafe_code)]

use core::mem::MaybeUninit;
use core::sync::atomic::{compiler_fence, Ordering};

use softfinger_core::control::pipeline::BridgeCommands;

use super::link::{self, Kind};

/// Reset causes as reported in `Hello`.
pub const CAUSE_POWER_ON: u32 = 0;
/// The watchdog reset the MCU (a hung tick, or after a panic or HardFault).
pub const CAUSE_WATCHDOG: u32 = 1;

const MAGIC: u32 = 0x5AFE_0000;

#[link_section = ".uninit.RESET_MARK"]
static mut RESET_MARK: MaybeUninit<u32> = MaybeUninit::uninit();

/// The watchdog timeout in counts, for the NMI's `ResetPending` (set once at start-up).
static mut WATCHDOG_COUNTS: u32 = 0;

fn mark(cause: u32) {
    // SAFETY: single-core; written only from fault handlers, which do not return, and read once
    // at boot before any handler can run.
    unsafe { (*core::ptr::addr_of_mut!(RESET_MARK)).write(MAGIC | cause) };
    compiler_fence(Ordering::SeqCst);
}

/// Read and clear the reset cause (call once, first thing at boot).
pub fn take_reset_cause() -> u32 {
    // SAFETY: see `mark`; an uninitialised word is read as a plain u32 (any bit pattern is valid).
    let raw = unsafe {
        core::ptr::addr_of!(RESET_MARK)
            .cast::<u32>()
            .read_volatile()
    };
    unsafe { (*core::ptr::addr_of_mut!(RESET_MARK)).write(0) };
    if raw & 0xFFFF_0000 == MAGIC {
        raw & 0xFFFF
    } else {
        CAUSE_POWER_ON
    }
}

/// Remember the watchdog timeout for the NMI handler.
pub fn set_watchdog_counts(counts: u32) {
    // SAFETY: written once in thread mode before the watchdog starts.
    unsafe { *core::ptr::addr_of_mut!(WATCHDOG_COUNTS) = counts };
}

/// The watchdog's first expiry: the tick has not petted it for a whole timeout. Outputs off, tell
/// the plant when the reset comes, and wait for it (the second expiry resets the system).
#[cortex_m_rt::exception]
unsafe fn NonMaskableInt() {
    link::drive(&BridgeCommands::OFF);
    // SAFETY: written once before the watchdog started.
    let counts = *core::ptr::addr_of!(WATCHDOG_COUNTS);
    link::send(Kind::ResetPending, 0, 0, [0; 3], [counts, 0, 0]);
    mark(CAUSE_WATCHDOG);
    loop {
        cortex_m::asm::wfi();
    }
}
