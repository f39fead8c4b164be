//! CMSDK APB UART0 of QEMU's mps2-an386 (base 0x4000_4000, hw/arm/mps2.c; register layout from
//! the Arm CMSDK technical reference, DDI 0479): the emulated board's host-link transport. QEMU
//! connects it to whatever `-serial` names (`host-sim pil --link-check`: a Unix socket).
//!
//! Polled by the link task only (never by the tick): one receive holding register, one transmit
//! holding register; QEMU holds further received bytes on its side until the register is read.
#![allow(unsafe_code)]

use core::ptr::{read_volatile, write_volatile};

use softfinger_app::link::task::ByteTransport;

const BASE: usize = 0x4000_4000;
const DATA: usize = BASE;
const STATE: usize = BASE + 0x04;
const CTRL: usize = BASE + 0x08;
const BAUDDIV: usize = BASE + 0x10;

/// STATE: transmit holding register full.
const STATE_TX_FULL: u32 = 1 << 0;
/// STATE: receive holding register full.
const STATE_RX_FULL: u32 = 1 << 1;
/// CTRL: transmitter and receiver enabled, no interrupts.
const CTRL_TX_RX: u32 = 0b11;
/// Smallest divider the CMSDK UART accepts (QEMU does not pace the bytes by it).
const MIN_BAUDDIV: u32 = 16;

fn read(addr: usize) -> u32 {
    // SAFETY: a word-aligned register of UART0, mapped by QEMU on mps2-an386; reading DATA
    // takes the received byte, the others have no side effect.
    unsafe { read_volatile(addr as *const u32) }
}

fn write(addr: usize, v: u32) {
    // SAFETY: as for `read`; writing DATA sends a byte.
    unsafe { write_volatile(addr as *mut u32, v) }
}

/// UART0, owned by the link task.
pub struct Uart0 {
    _private: (),
}

impl Uart0 {
    /// Enable the transmitter and the receiver (no interrupts: the link task polls).
    pub fn open() -> Self {
        write(BAUDDIV, MIN_BAUDDIV);
        write(CTRL, CTRL_TX_RX);
        Uart0 { _private: () }
    }
}

impl ByteTransport for Uart0 {
    fn read_byte(&mut self) -> Option<u8> {
        (read(STATE) & STATE_RX_FULL != 0).then(|| read(DATA) as u8)
    }

    fn write_byte(&mut self, byte: u8) -> bool {
        if read(STATE) & STATE_TX_FULL != 0 {
            return false;
        }
        write(DATA, u32::from(byte));
        true
    }
}
