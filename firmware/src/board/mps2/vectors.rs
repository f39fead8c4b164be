//! The device part of the vector table (cortex-m-rt's `device` feature): the interrupt lines of
//! mps2-an386 this board serves, every other line to `DefaultHandler`.
#![allow(unsafe_code)]

/// One vector table entry: a handler or a reserved word.
pub union Vector {
    handler: unsafe extern "C" fn(),
    _reserved: usize,
}

extern "C" {
    fn DefaultHandler();
    fn TIMER0();
    fn TIMER1();
}

/// Lines 0..31 of mps2-an386 (QEMU hw/arm/mps2.c, AN385/AN386): 8 = APB timer 0 (control tick),
/// 9 = APB timer 1 (embassy-time). The watchdog drives the NMI, not a line.
#[link_section = ".vector_table.interrupts"]
#[no_mangle]
pub static __INTERRUPTS: [Vector; 32] = {
    const D: Vector = Vector {
        handler: DefaultHandler,
    };
    let mut v = [D; 32];
    v[8] = Vector { handler: TIMER0 };
    v[9] = Vector { handler: TIMER1 };
    v
};
