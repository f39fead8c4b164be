//! The softfinger bootloader (STM32G474RE): at every reset, embassy-boot's `prepare_boot` over the
//! slots of `softfinger_update::layout::G474`, the very code `softfinger-update`'s host tests cut
//! the power in (`softfinger_update::boot::run_bootloader`): a marked image is swapped in page by
//! page (a power cut resumes the swap), an image left unconfirmed by its self-test is swapped back.
//! Then it jumps to the active slot. It checks no signature: the application verifies the
//! image's ed25519 signature before it marks the image for swap, and nothing else can mark it.
#![no_std]
#![no_main]

use core::cell::RefCell;

use cortex_m_rt::{entry, exception};
use defmt as _;
use embassy_stm32::flash::Flash;
use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use softfinger_update::boot::run_bootloader;
use softfinger_update::layout::G474;
use softfinger_update::Slots;

/// The flash's address.
const FLASH_BASE: u32 = 0x0800_0000;

#[entry]
fn main() -> ! {
    let p = embassy_stm32::init(Default::default());
    let flash = Mutex::<NoopRawMutex, _>::new(RefCell::new(Flash::new_blocking(p.FLASH)));
    let slots = Slots::new(&flash, G474);
    // A flash error leaves the slots as they are (the state slot records the swap's progress):
    // boot what is active; the next reset tries again.
    let state = run_bootloader(&slots).unwrap_or(embassy_boot_stm32::State::Boot);
    let bl = embassy_boot_stm32::BootLoader { state };
    // SAFETY: the active slot holds an application linked at that address (its memory.x).
    unsafe { bl.load(FLASH_BASE + G474.active.start) }
}

#[exception]
unsafe fn HardFault(_: &cortex_m_rt::ExceptionFrame) -> ! {
    cortex_m::peripheral::SCB::sys_reset()
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    cortex_m::peripheral::SCB::sys_reset()
}
