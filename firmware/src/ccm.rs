//! Loads the control tick's code into CCM SRAM (see `memory.x`: section `.ccmram_text`, load image
//! in flash at `__siccm_text`, run address `__sccm_text..__eccm_text`).
//!
//! [`load`] must run before any function placed there is called: it is the first statement of
//! `main`, before the HAL, the executor or any softfinger-core function runs. The copy is a plain
//! word loop with volatile accesses, so it calls no library function (memcpy stays in flash).

use core::ptr;

extern "C" {
    static __siccm_text: u32;
    static mut __sccm_text: u32;
    static mut __eccm_text: u32;
}

/// Copy the CCM code image from flash to CCM SRAM, then synchronise the instruction stream.
#[inline(never)]
pub fn load() {
    // SAFETY: the three symbols are defined by memory.x with 8-byte alignment; the run region
    // `__sccm_text..__eccm_text` lies inside CCMRAM, belongs to no Rust object, and nothing in it
    // has run yet (this is the first call in `main`); the load image has the same length.
    unsafe {
        let mut src = ptr::addr_of!(__siccm_text);
        let mut dst = ptr::addr_of_mut!(__sccm_text);
        let end = ptr::addr_of_mut!(__eccm_text);
        while dst < end {
            ptr::write_volatile(dst, ptr::read_volatile(src));
            dst = dst.add(1);
            src = src.add(1);
        }
    }
    // The copied code is fetched through the I-bus: complete the writes, then refetch.
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
}

/// The CCM addresses the tick's code occupies once loaded, `start..end`.
pub fn loaded_range() -> (u32, u32) {
    (
        ptr::addr_of!(__sccm_text) as u32,
        ptr::addr_of!(__eccm_text) as u32,
    )
}
