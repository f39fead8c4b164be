//! Loads the control tick's code into SRAM (see the top-level `memory.x`): sections
//! `.ccmram_early` and `.ccmram_text` into CCM SRAM, `.sram_text` (the local-model renderer) into
//! SRAM1/2, each from its load image in flash.
//!
//! [`load`] must run before any function placed there is called: it is the first statement of
//! `main`, before the HAL, the executor or any softfinger-core function runs. The copy is a plain
//! word loop with volatile accesses, so it calls no library function (memcpy runs from CCM).

use core::ptr;

extern "C" {
    static __siccm_early: u32;
    static mut __sccm_early: u32;
    static mut __eccm_early: u32;
    static __sisram_text: u32;
    static mut __ssram_text: u32;
    static mut __esram_text: u32;
    static __siccm_text: u32;
    static mut __sccm_text: u32;
    static mut __eccm_text: u32;
}

/// Copy words from `src` to `dst..end`.
///
/// # Safety
/// `dst..end` is a run region defined by memory.x (8-byte aligned, inside SRAM), belonging to no
/// Rust object, none of whose code has run yet; `src` is its load image, of the same length.
unsafe fn copy(mut src: *const u32, mut dst: *mut u32, end: *mut u32) {
    while dst < end {
        // SAFETY: see the function's contract.
        unsafe {
            ptr::write_volatile(dst, ptr::read_volatile(src));
            dst = dst.add(1);
            src = src.add(1);
        }
    }
}

/// Copy the three code images from flash to SRAM, then synchronise the instruction stream.
#[inline(never)]
pub fn load() {
    // SAFETY: the symbols are defined by memory.x with 8-byte alignment; each run region lies in
    // CCMRAM or RAM, belongs to no Rust object (the linker placed nothing else there), and none of
    // its code has run yet (this is the first call in `main`); each load image has its length.
    unsafe {
        copy(
            ptr::addr_of!(__siccm_early),
            ptr::addr_of_mut!(__sccm_early),
            ptr::addr_of_mut!(__eccm_early),
        );
        copy(
            ptr::addr_of!(__sisram_text),
            ptr::addr_of_mut!(__ssram_text),
            ptr::addr_of_mut!(__esram_text),
        );
        copy(
            ptr::addr_of!(__siccm_text),
            ptr::addr_of_mut!(__sccm_text),
            ptr::addr_of_mut!(__eccm_text),
        );
    }
    // The copied code is fetched through the I-bus and the S-bus: complete the writes, refetch.
    cortex_m::asm::dsb();
    cortex_m::asm::isb();
}

/// The CCM addresses the tick's code occupies once loaded, `start..end`.
pub fn loaded_range() -> (u32, u32) {
    (
        ptr::addr_of!(__sccm_early) as u32,
        ptr::addr_of!(__eccm_text) as u32,
    )
}
