//! Where the bootloader, the slots and the settings store live.
//!
//! On the STM32G474RE (512 KiB, dual bank: bank 1 at 0x0800_0000, bank 2 at 0x0804_0000, 2 KiB
//! pages), offsets from 0x0800_0000:
//!
//! | region | offset | size | bank |
//! | --- | --- | --- | --- |
//! | bootloader | 0x0_0000 | 24 KiB | 1 |
//! | boot state | 0x0_6000 | 4 KiB | 1 |
//! | active slot (the application) | 0x0_7000 | 228 KiB | 1 |
//! | DFU slot | 0x4_0000 | 230 KiB (active + 1 page) | 2 |
//! | settings store | 0x7_C000 | 16 KiB | 2 |
//!
//! The DFU slot and the store are in bank 2, so writing them while the application runs from
//! bank 1 does not stall it. The bootloader's and the firmware's `memory.x` use these numbers.

use core::ops::Range;

/// The offsets (from the flash's start) of the three embassy-boot slots and the store.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// The slot the application runs from.
    pub active: Range<u32>,
    /// The slot an update is received in; at least one page larger than `active`.
    pub dfu: Range<u32>,
    /// The bootloader's state: at least `(2 + 4 * active pages) * 8` bytes.
    pub state: Range<u32>,
    /// The settings store (`softfinger-store`).
    pub store: Range<u32>,
}

/// The flash page, bytes.
pub const PAGE: u32 = 2048;

/// The STM32G474RE's layout (see the module doc).
pub const G474: Layout = Layout {
    active: 0x0_7000..0x4_0000,
    dfu: 0x4_0000..0x7_9800,
    state: 0x0_6000..0x0_7000,
    store: 0x7_C000..0x8_0000,
};

/// The G474's flash size, bytes.
pub const G474_FLASH_LEN: u32 = 512 * 1024;

impl Layout {
    /// Check the slots against embassy-boot's rules and each other (no overlap, whole pages).
    pub fn check(&self, flash_len: u32) -> Result<(), &'static str> {
        let rs = [&self.active, &self.dfu, &self.state, &self.store];
        for r in rs {
            if !r.start.is_multiple_of(PAGE)
                || !r.end.is_multiple_of(PAGE)
                || r.end <= r.start
                || r.end > flash_len
            {
                return Err("a region is not whole pages inside the flash");
            }
        }
        for (i, a) in rs.iter().enumerate() {
            for b in rs.iter().skip(i + 1) {
                if a.start < b.end && b.start < a.end {
                    return Err("two regions overlap");
                }
            }
        }
        let active = self.active.end - self.active.start;
        if self.dfu.end - self.dfu.start < active + PAGE {
            return Err("the DFU slot must be at least one page larger than the active slot");
        }
        if (2 + 4 * active / PAGE) * 8 > self.state.end - self.state.start {
            return Err("the state slot is too small for the active slot");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_g474_layout_is_consistent() {
        assert_eq!(G474.check(G474_FLASH_LEN), Ok(()));
        assert_eq!(G474.active.start, 24 * 1024 + 4 * 1024);
        assert_eq!(
            G474.dfu.end - G474.dfu.start,
            G474.active.end - G474.active.start + PAGE
        );
    }

    #[test]
    fn a_dfu_slot_of_the_active_size_is_refused() {
        let mut l = G474;
        l.dfu.end -= PAGE;
        assert!(l.check(G474_FLASH_LEN).is_err());
        let mut l = G474;
        l.state.end -= PAGE;
        assert_eq!(
            l.check(G474_FLASH_LEN),
            Err("the state slot is too small for the active slot")
        );
    }
}
