//! Register access to the Arm CMSDK peripherals of QEMU's mps2-an386 that the emulated board uses:
//! two APB timers (the control tick and the embassy-time base), the dual timer (a free-running
//! 32-bit time base for the plant link) and the watchdog (its interrupt is the NMI).
//!
//! Addresses and interrupt lines from QEMU hw/arm/mps2.c (AN385/AN386 map); register layouts from
//! the Arm CMSDK technical reference (DDI 0479). All peripherals count at the 25 MHz system clock.
#![allow(unsafe_code)]

use core::ptr::{read_volatile, write_volatile};

/// Peripheral clock of every CMSDK block on mps2-an386, Hz.
pub const PCLK_HZ: u32 = 25_000_000;

/// One 32-bit register at a fixed address.
#[derive(Clone, Copy)]
struct Reg(usize);

impl Reg {
    #[inline(always)]
    fn read(self) -> u32 {
        // SAFETY: every `Reg` is a word-aligned register of a peripheral QEMU maps at that address
        // on mps2-an386 (hw/arm/mps2.c); reads have no side effect but the register's own.
        unsafe { read_volatile(self.0 as *const u32) }
    }
    #[inline(always)]
    fn write(self, v: u32) {
        // SAFETY: as for `read`.
        unsafe { write_volatile(self.0 as *mut u32, v) }
    }
}

/// CMSDK APB timer: a 32-bit down-counter that reloads and raises its interrupt at zero.
#[derive(Clone, Copy)]
pub struct ApbTimer {
    base: usize,
}

/// The control-tick timer (interrupt line 8).
pub const TICK_TIMER: ApbTimer = ApbTimer { base: 0x4000_0000 };
/// The embassy-time base (interrupt line 9).
pub const TIME_BASE_TIMER: ApbTimer = ApbTimer { base: 0x4000_1000 };

impl ApbTimer {
    const CTRL_ENABLE: u32 = 1 << 0;
    const CTRL_IRQ_ENABLE: u32 = 1 << 3;

    fn ctrl(self) -> Reg {
        Reg(self.base)
    }
    fn value_reg(self) -> Reg {
        Reg(self.base + 0x04)
    }
    fn reload(self) -> Reg {
        Reg(self.base + 0x08)
    }
    fn intstatus(self) -> Reg {
        Reg(self.base + 0x0C)
    }

    /// Stop the timer, set a period of `period_counts` counts and enable its interrupt (still
    /// stopped). QEMU's CMSDK timer wraps from 0 to RELOAD, so a period is RELOAD + 1 counts.
    pub fn configure(self, period_counts: u32) {
        self.ctrl().write(0);
        self.reload().write(period_counts.saturating_sub(1));
        self.value_reg().write(period_counts.saturating_sub(1));
        self.intstatus().write(1);
    }

    /// Start counting with the interrupt enabled.
    pub fn start(self) {
        self.ctrl().write(Self::CTRL_ENABLE | Self::CTRL_IRQ_ENABLE);
    }

    /// Stop counting and mask the interrupt output.
    pub fn stop(self) {
        self.ctrl().write(0);
    }

    /// The counter (counts down from RELOAD to 0).
    #[inline(always)]
    pub fn value(self) -> u32 {
        self.value_reg().read()
    }

    /// RELOAD, i.e. the period in counts minus one.
    #[inline(always)]
    pub fn reload_value(self) -> u32 {
        self.reload().read()
    }

    /// The interrupt is pending (the counter reached zero since the last clear).
    #[inline(always)]
    pub fn pending(self) -> bool {
        self.intstatus().read() & 1 != 0
    }

    /// Clear the interrupt.
    #[inline(always)]
    pub fn clear(self) {
        self.intstatus().write(1);
    }
}

/// Timer 1 of the CMSDK dual timer, free-running over 32 bits: the board's time base.
pub struct FreeRunning;

impl FreeRunning {
    const BASE: usize = 0x4000_2000;
    /// CONTROL: enable, 32-bit, free-running (not periodic), no interrupt, prescale 1.
    const CONTROL_RUN: u32 = (1 << 7) | (1 << 1);

    /// Start from 0xFFFF_FFFF, counting down at 25 MHz (wraps after 171.8 s).
    pub fn start() {
        Reg(Self::BASE + 0x08).write(0);
        Reg(Self::BASE).write(u32::MAX);
        Reg(Self::BASE + 0x08).write(Self::CONTROL_RUN);
    }

    /// The counter (counts down).
    #[inline(always)]
    pub fn value() -> u32 {
        Reg(Self::BASE + 0x04).read()
    }
}

/// CMSDK APB watchdog: counts down; at zero it raises its interrupt (the NMI on mps2-an386) and
/// reloads; reaching zero again with the interrupt still raised resets the system.
pub struct Watchdog;

impl Watchdog {
    const BASE: usize = 0x4000_8000;
    const UNLOCK: u32 = 0x1ACC_E551;
    /// CONTROL: interrupt enable, reset enable.
    const CONTROL_RUN: u32 = 0b11;

    fn unlocked(f: impl FnOnce()) {
        Reg(Self::BASE + 0xC00).write(Self::UNLOCK);
        f();
        Reg(Self::BASE + 0xC00).write(0);
    }

    /// Start with `timeout_counts` counts to the first expiry (NMI); the reset follows after as
    /// many again unless the NMI handler stops it.
    pub fn start(timeout_counts: u32) {
        Self::unlocked(|| {
            Reg(Self::BASE).write(timeout_counts);
            Reg(Self::BASE + 0x08).write(Self::CONTROL_RUN);
        });
    }

    /// Stop counting (the end of an emulated run; the STM32's IWDG cannot be stopped).
    pub fn stop() {
        Self::unlocked(|| Reg(Self::BASE + 0x08).write(0));
    }

    /// Proof of life: clear the interrupt and reload the counter.
    #[inline(always)]
    pub fn pet() {
        Self::unlocked(|| Reg(Self::BASE + 0x0C).write(1));
    }
}

/// Interrupt lines of mps2-an386 this board uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u16)]
pub enum Irq {
    /// CMSDK APB timer 0: the control tick.
    Timer0 = 8,
    /// CMSDK APB timer 1: embassy-time.
    Timer1 = 9,
}

// SAFETY: the discriminants are interrupt lines that exist on mps2-an386 (below 32).
unsafe impl cortex_m::interrupt::InterruptNumber for Irq {
    fn number(self) -> u16 {
        self as u16
    }
}
