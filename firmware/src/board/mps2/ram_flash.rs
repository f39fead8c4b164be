//! The emulated board's flash for the settings store and the update's slots: 512 KiB of the
//! MPS2's SSRAM (outside the 96 KiB the linker gives the app, so the app's RAM figures stay the
//! STM32G474's) with the G474's rules (RM0440 §3.3.7): 2 KiB pages, 8-byte (double-word) writes
//! only to erased double words or of all zeros, reads of any length. Erased at every power-on
//! (a run of the emulator starts from blank flash); the settings survive a restart only on the
//! file-backed flash of `mcu-bench`'s power-cut program (`scripts/flash-cut`).
#![allow(unsafe_code)]

use embedded_storage::nor_flash::{
    ErrorType, NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash,
};

/// Where the emulated flash starts: SSRAM2/3 (4 MiB at 0x2000_0000 on the AN386), 2 MiB in.
const BASE: usize = 0x2020_0000;
/// Its size: the G474's 512 KiB (`softfinger_update::layout::G474_FLASH_LEN`).
const LEN: usize = 512 * 1024;
/// Page, bytes.
const PAGE: usize = 2048;
/// Write unit, bytes.
const DOUBLE_WORD: usize = 8;

/// What the flash refuses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, defmt::Format)]
pub enum RamFlashError {
    /// Outside the 512 KiB.
    OutOfBounds,
    /// Not on the write unit or the page.
    NotAligned,
    /// A double word written twice without an erase (and not to all zeros).
    NotErased,
}

impl NorFlashError for RamFlashError {
    fn kind(&self) -> NorFlashErrorKind {
        match self {
            RamFlashError::OutOfBounds => NorFlashErrorKind::OutOfBounds,
            RamFlashError::NotAligned => NorFlashErrorKind::NotAligned,
            RamFlashError::NotErased => NorFlashErrorKind::Other,
        }
    }
}

/// The emulated flash (one per board: it owns the region).
#[derive(Debug)]
pub struct RamFlash(());

impl RamFlash {
    /// The region, erased (power-on). Call once.
    pub fn erased() -> RamFlash {
        let mut f = RamFlash(());
        f.bytes().fill(0xFF);
        f
    }

    fn bytes(&mut self) -> &mut [u8] {
        // SAFETY: the region is SSRAM that neither the linker (RAM is 96 KiB at 0x2000_0000) nor
        // anything else on this board uses; `RamFlash` is created once and owns it (`&mut self`).
        unsafe { core::slice::from_raw_parts_mut(BASE as *mut u8, LEN) }
    }

    fn range(
        offset: u32,
        len: usize,
        align: usize,
    ) -> Result<core::ops::Range<usize>, RamFlashError> {
        let o = offset as usize;
        if !o.is_multiple_of(align) || !len.is_multiple_of(align) {
            return Err(RamFlashError::NotAligned);
        }
        let end = o.checked_add(len).ok_or(RamFlashError::OutOfBounds)?;
        if end > LEN {
            return Err(RamFlashError::OutOfBounds);
        }
        Ok(o..end)
    }
}

impl ErrorType for RamFlash {
    type Error = RamFlashError;
}

impl ReadNorFlash for RamFlash {
    const READ_SIZE: usize = 1;
    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), RamFlashError> {
        let r = Self::range(offset, bytes.len(), 1)?;
        bytes.copy_from_slice(&self.bytes()[r]);
        Ok(())
    }
    fn capacity(&self) -> usize {
        LEN
    }
}

impl NorFlash for RamFlash {
    const WRITE_SIZE: usize = DOUBLE_WORD;
    const ERASE_SIZE: usize = PAGE;
    fn erase(&mut self, from: u32, to: u32) -> Result<(), RamFlashError> {
        let len = (to as usize)
            .checked_sub(from as usize)
            .ok_or(RamFlashError::OutOfBounds)?;
        let r = Self::range(from, len, PAGE)?;
        self.bytes()[r].fill(0xFF);
        Ok(())
    }
    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), RamFlashError> {
        let r = Self::range(offset, bytes.len(), DOUBLE_WORD)?;
        let flash = &mut self.bytes()[r];
        for (dst, src) in flash
            .chunks_exact_mut(DOUBLE_WORD)
            .zip(bytes.chunks_exact(DOUBLE_WORD))
        {
            let erased = dst.iter().all(|b| *b == 0xFF);
            let zeros = src.iter().all(|b| *b == 0);
            if !erased && !zeros {
                return Err(RamFlashError::NotErased);
            }
            dst.copy_from_slice(src);
        }
        Ok(())
    }
}
