//! The STM32G474's flash emulated on a host file through semihosting, so what the program wrote
//! survives a restart of the emulator, and a kill of the emulator is a power cut.
//!
//! The file holds the whole 512 KiB flash. At power-on [`SemiFlash::power_on`] reads it into RAM
//! (the flash's contents as the code reads them); every write and erase changes that copy *and*
//! the file, one semihosting write (after a seek) per double word written and one per page erased,
//! so the file is never more than one operation behind. The rules are the G474's (RM0440 §3.3.7): 2 KiB pages,
//! 8-byte (double-word) programming, erase to `0xFF`, a double word programmed only when erased
//! (or with all zeros), programming only clears bits.
//!
//! **What a kill models.** Killing QEMU between two operations is a power cut at a double-word
//! or page boundary: the double words before it are programmed, the rest untouched. It
//! does **not** model a torn double word or a half-erased page (a host `write` of 8 bytes or of a
//! page is all or nothing); `softfinger_store::flash_model` tears those in the host tests.
//!
//! **Where the cut falls.** [`SemiFlash::cut_at`] arms a stop before operation `n` (writes and
//! erases counted from the arming, one per double word or page): there the program prints
//! `CUT <n>` and spins, and the host script kills the emulator with SIGKILL.

use cortex_m_semihosting::{hprintln, syscall};
use embedded_storage::nor_flash as blocking;
use embedded_storage_async::nor_flash as nor;

/// The flash, bytes (the G474RE's 512 KiB).
pub const FLASH_LEN: usize = 512 * 1024;
/// A page, bytes.
pub const PAGE: usize = 2048;
/// The program granularity (a double word), bytes.
pub const WORD: usize = 8;

/// A flash error.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SemiFlashError {
    /// Offset or length not a multiple of the write or erase size.
    NotAligned,
    /// Outside the flash.
    OutOfBounds,
    /// A write to a double word that is not erased.
    NotErased,
    /// The host file could not be read or written.
    Io,
}

impl nor::NorFlashError for SemiFlashError {
    fn kind(&self) -> nor::NorFlashErrorKind {
        match self {
            SemiFlashError::NotAligned => nor::NorFlashErrorKind::NotAligned,
            SemiFlashError::OutOfBounds => nor::NorFlashErrorKind::OutOfBounds,
            _ => nor::NorFlashErrorKind::Other,
        }
    }
}

/// The flash (see the module doc).
pub struct SemiFlash {
    mem: &'static mut [u8; FLASH_LEN],
    fd: usize,
    /// Writes (double words) and erases (pages) since [`SemiFlash::count_from_here`].
    ops: u32,
    /// Double words written since the count started.
    pub words_written: u32,
    /// Pages erased since the count started.
    pub pages_erased: u32,
    cut: Option<u32>,
}

impl core::fmt::Debug for SemiFlash {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("SemiFlash")
            .field("ops", &self.ops)
            .finish_non_exhaustive()
    }
}

fn open(path: &str, mode: usize) -> Option<usize> {
    // The path must end in a NUL; its length is passed without it.
    let fd = unsafe { syscall!(OPEN, path.as_ptr(), mode, path.len() - 1) };
    (fd as isize >= 0).then_some(fd)
}

fn seek(fd: usize, pos: usize) -> bool {
    unsafe { syscall!(SEEK, fd, pos) == 0 }
}

fn write_at(fd: usize, pos: usize, data: &[u8]) -> bool {
    seek(fd, pos) && unsafe { syscall!(WRITE, fd, data.as_ptr(), data.len()) == 0 }
}

impl SemiFlash {
    /// Power on: open `path` (NUL-terminated; a file of [`FLASH_LEN`] bytes the host made) and
    /// read the flash from it into `mem`. `None` if the file cannot be opened or is short.
    pub fn power_on(path: &str, mem: &'static mut [u8; FLASH_LEN]) -> Option<SemiFlash> {
        let fd = open(path, cortex_m_semihosting::nr::open::RW_BINARY)?;
        if !seek(fd, 0) {
            return None;
        }
        let left = unsafe { syscall!(READ, fd, mem.as_mut_ptr(), FLASH_LEN) };
        if left != 0 {
            return None;
        }
        Some(SemiFlash {
            mem,
            fd,
            ops: 0,
            words_written: 0,
            pages_erased: 0,
            cut: None,
        })
    }

    /// Start counting operations from 0.
    pub fn count_from_here(&mut self) {
        self.ops = 0;
        self.words_written = 0;
        self.pages_erased = 0;
    }

    /// Operations (double-word writes and page erases) since the count started.
    pub fn ops(&self) -> u32 {
        self.ops
    }

    /// Stop before operation `n` of the count (see the module doc).
    pub fn cut_at(&mut self, n: Option<u32>) {
        self.cut = n;
    }

    /// The flash as the code reads it.
    pub fn bytes(&self) -> &[u8] {
        &self.mem[..]
    }

    fn gate(&mut self) {
        if self.cut == Some(self.ops) {
            hprintln!("CUT {}", self.ops);
            // The host kills the emulator here.
            #[allow(clippy::empty_loop)]
            loop {
                cortex_m::asm::nop();
            }
        }
        self.ops += 1;
    }

    fn check(&self, offset: u32, len: usize, align: usize) -> Result<usize, SemiFlashError> {
        let o = offset as usize;
        if !o.is_multiple_of(align) || !len.is_multiple_of(align) {
            return Err(SemiFlashError::NotAligned);
        }
        if o.checked_add(len).is_none_or(|e| e > FLASH_LEN) {
            return Err(SemiFlashError::OutOfBounds);
        }
        Ok(o)
    }

    fn do_read(&self, offset: u32, out: &mut [u8]) -> Result<(), SemiFlashError> {
        let o = self.check(offset, out.len(), 1)?;
        out.copy_from_slice(&self.mem[o..o + out.len()]);
        Ok(())
    }

    fn do_write(&mut self, offset: u32, data: &[u8]) -> Result<(), SemiFlashError> {
        let o = self.check(offset, data.len(), WORD)?;
        for (i, new) in data.chunks(WORD).enumerate() {
            let at = o + i * WORD;
            let mut w = [0u8; WORD];
            w.copy_from_slice(&self.mem[at..at + WORD]);
            if w.iter().any(|b| *b != 0xFF) && new.iter().any(|b| *b != 0) {
                return Err(SemiFlashError::NotErased);
            }
            self.gate();
            // Programming only clears bits.
            w.iter_mut().zip(new).for_each(|(b, n)| *b &= n);
            self.mem[at..at + WORD].copy_from_slice(&w);
            self.words_written += 1;
            if !write_at(self.fd, at, &w) {
                return Err(SemiFlashError::Io);
            }
        }
        Ok(())
    }

    fn do_erase(&mut self, from: u32, to: u32) -> Result<(), SemiFlashError> {
        if to < from {
            return Err(SemiFlashError::OutOfBounds);
        }
        let f = self.check(from, (to - from) as usize, PAGE)?;
        for p in (f..to as usize).step_by(PAGE) {
            self.gate();
            self.mem[p..p + PAGE].fill(0xFF);
            self.pages_erased += 1;
            if !write_at(self.fd, p, &self.mem[p..p + PAGE]) {
                return Err(SemiFlashError::Io);
            }
        }
        Ok(())
    }
}

impl nor::ErrorType for SemiFlash {
    type Error = SemiFlashError;
}

impl nor::ReadNorFlash for SemiFlash {
    const READ_SIZE: usize = 1;
    async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), SemiFlashError> {
        self.do_read(offset, bytes)
    }
    fn capacity(&self) -> usize {
        FLASH_LEN
    }
}

impl nor::NorFlash for SemiFlash {
    const WRITE_SIZE: usize = WORD;
    const ERASE_SIZE: usize = PAGE;
    async fn erase(&mut self, from: u32, to: u32) -> Result<(), SemiFlashError> {
        self.do_erase(from, to)
    }
    async fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), SemiFlashError> {
        self.do_write(offset, bytes)
    }
}

impl blocking::ReadNorFlash for SemiFlash {
    const READ_SIZE: usize = 1;
    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), SemiFlashError> {
        self.do_read(offset, bytes)
    }
    fn capacity(&self) -> usize {
        FLASH_LEN
    }
}

impl blocking::NorFlash for SemiFlash {
    const WRITE_SIZE: usize = WORD;
    const ERASE_SIZE: usize = PAGE;
    fn erase(&mut self, from: u32, to: u32) -> Result<(), SemiFlashError> {
        self.do_erase(from, to)
    }
    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), SemiFlashError> {
        self.do_write(offset, bytes)
    }
}
