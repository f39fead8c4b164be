//! A model of the STM32G474's flash for host tests and the virtual device: 2 KiB pages, 8-byte
//! (double-word) write granularity, a write only to erased double words (the G4 refuses the rest
//! with PROGERR), erase to `0xFF`. Optionally backed by a file, so the contents survive a restart
//! of the process; and it can cut the power at a chosen write or erase.
//!
//! A *cut* at operation `n` (writes and erases counted from 0, one per call) tears that operation:
//! [`Tear::Before`] leaves it undone; [`Tear::Torn`] does the first half of it and leaves the next
//! double word (a write) or the rest of the page (an erase) with some of its bits changed, as a
//! program or erase interrupted part-way does. Every later operation fails with
//! [`FlashError::PowerLost`] until [`G474Flash::power_on`].

extern crate std;

use std::fs::{File, OpenOptions};
use std::os::unix::fs::FileExt;
use std::path::Path;
use std::vec;
use std::vec::Vec;

use embedded_storage::nor_flash as blocking;
use embedded_storage_async::nor_flash as nor;

/// The G474's flash page, bytes.
pub const PAGE_SIZE: usize = 2048;
/// The G474's program granularity (a double word), bytes.
pub const WRITE_SIZE: usize = 8;

/// What a cut does to the operation it hits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tear {
    /// The operation never started.
    Before,
    /// Half of it done, the double word (write) or the rest of the page (erase) after that half
    /// partly changed.
    Torn,
}

/// A flash error.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlashError {
    /// Offset or length not a multiple of the write or erase size.
    NotAligned,
    /// Outside the flash.
    OutOfBounds,
    /// A write to a double word that is not erased.
    NotErased,
    /// The power was cut.
    PowerLost,
    /// The backing file could not be written.
    Io,
}

impl nor::NorFlashError for FlashError {
    fn kind(&self) -> nor::NorFlashErrorKind {
        match self {
            FlashError::NotAligned => nor::NorFlashErrorKind::NotAligned,
            FlashError::OutOfBounds => nor::NorFlashErrorKind::OutOfBounds,
            _ => nor::NorFlashErrorKind::Other,
        }
    }
}

/// The flash model (see the module doc).
#[derive(Debug)]
pub struct G474Flash {
    bytes: Vec<u8>,
    file: Option<File>,
    /// Writes and erases done (or attempted) since creation.
    ops: u64,
    cut: Option<(u64, Tear)>,
    dead: bool,
    /// What the cut hit, once it has happened.
    cut_hit: Option<OpKind>,
    /// Erases done, per page (wear).
    pub erases: Vec<u32>,
}

/// A flash operation's kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OpKind {
    /// A program of double words.
    Write,
    /// A page erase.
    Erase,
}

impl G474Flash {
    /// An erased flash of `pages` pages in RAM.
    pub fn new(pages: usize) -> Self {
        Self {
            bytes: vec![0xFF; pages * PAGE_SIZE],
            file: None,
            ops: 0,
            cut: None,
            dead: false,
            cut_hit: None,
            erases: vec![0; pages],
        }
    }

    /// The flash kept in `path` (created erased if absent; refused if its length is not `pages`
    /// pages).
    pub fn open_file(path: &Path, pages: usize) -> std::io::Result<Self> {
        let len = (pages * PAGE_SIZE) as u64;
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)?;
        let have = file.metadata()?.len();
        let mut bytes = vec![0xFF; pages * PAGE_SIZE];
        if have == 0 {
            file.write_all_at(&bytes, 0)?;
        } else if have != len {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                std::format!(
                    "{}: {have} bytes, expected {len} ({pages} pages of {PAGE_SIZE} B)",
                    path.display()
                ),
            ));
        } else {
            file.read_exact_at(&mut bytes, 0)?;
        }
        Ok(Self {
            bytes,
            file: Some(file),
            ops: 0,
            cut: None,
            dead: false,
            cut_hit: None,
            erases: vec![0; pages],
        })
    }

    /// A RAM flash holding `image` (whole pages), e.g. a copy of [`Self::bytes`] taken before a save.
    pub fn from_image(image: &[u8]) -> Self {
        let mut f = Self::new(image.len() / PAGE_SIZE);
        let n = f.bytes.len();
        f.bytes.copy_from_slice(&image[..n]);
        f
    }

    /// What the cut hit (`None` before it happens).
    pub fn cut_hit(&self) -> Option<OpKind> {
        self.cut_hit
    }

    /// Cut the power at operation `op` (counted from 0 since creation) in the way `tear` says.
    pub fn cut_at(&mut self, op: u64, tear: Tear) {
        self.cut = Some((op, tear));
    }

    /// Power back on: no cut pending, operations work again.
    pub fn power_on(&mut self) {
        self.cut = None;
        self.dead = false;
    }

    /// Writes and erases so far.
    pub fn ops(&self) -> u64 {
        self.ops
    }

    /// True once a cut has happened (and until [`Self::power_on`]).
    pub fn power_lost(&self) -> bool {
        self.dead
    }

    /// The raw contents.
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// A deterministic pseudo-random byte for op `op`, position `i` (the torn bits).
    fn noise(op: u64, i: usize) -> u8 {
        let mut x =
            op.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (i as u64).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x ^= x >> 31;
        x = x.wrapping_mul(0x94D0_49BB_1331_11EB);
        (x >> 24) as u8
    }

    /// Count an operation; `Ok(Some(tear))` if this one is cut.
    fn begin(&mut self, kind: OpKind) -> Result<Option<Tear>, FlashError> {
        if self.dead {
            return Err(FlashError::PowerLost);
        }
        let op = self.ops;
        self.ops += 1;
        match self.cut {
            Some((at, tear)) if at == op => {
                self.dead = true;
                self.cut_hit = Some(kind);
                Ok(Some(tear))
            }
            _ => Ok(None),
        }
    }

    fn persist(&mut self, from: usize, to: usize) -> Result<(), FlashError> {
        if let Some(f) = &self.file {
            f.write_all_at(&self.bytes[from..to], from as u64)
                .map_err(|_| FlashError::Io)?;
        }
        Ok(())
    }

    fn check(&self, offset: u32, len: usize, align: usize) -> Result<usize, FlashError> {
        let o = offset as usize;
        if !o.is_multiple_of(align) || !len.is_multiple_of(align) {
            return Err(FlashError::NotAligned);
        }
        if o + len > self.bytes.len() {
            return Err(FlashError::OutOfBounds);
        }
        Ok(o)
    }

    fn do_read(&self, offset: u32, out: &mut [u8]) -> Result<(), FlashError> {
        let o = self.check(offset, out.len(), 1)?;
        out.copy_from_slice(&self.bytes[o..o + out.len()]);
        Ok(())
    }

    fn do_write(&mut self, offset: u32, data: &[u8]) -> Result<(), FlashError> {
        let o = self.check(offset, data.len(), WRITE_SIZE)?;
        // RM0440 3.3.7: a double word is programmed only when erased, except with all zeros.
        for (w, new) in self.bytes[o..o + data.len()]
            .chunks(WRITE_SIZE)
            .zip(data.chunks(WRITE_SIZE))
        {
            if w.iter().any(|b| *b != 0xFF) && new.iter().any(|b| *b != 0) {
                return Err(FlashError::NotErased);
            }
        }
        let op = self.ops;
        match self.begin(OpKind::Write)? {
            // Programming only clears bits (an all-zero write over a programmed word gives zero).
            None => self.bytes[o..o + data.len()]
                .iter_mut()
                .zip(data)
                .for_each(|(b, d)| *b &= d),
            Some(Tear::Before) => return Err(FlashError::PowerLost),
            Some(Tear::Torn) => {
                let words = data.len() / WRITE_SIZE;
                let done = words / 2 * WRITE_SIZE;
                self.bytes[o..o + done]
                    .iter_mut()
                    .zip(&data[..done])
                    .for_each(|(b, d)| *b &= d);
                // The double word being programmed: each bit reached its new value or not.
                let end = (done + WRITE_SIZE).min(data.len());
                for (i, d) in data.iter().enumerate().take(end).skip(done) {
                    self.bytes[o + i] &= d | Self::noise(op, i);
                }
                self.persist(o, o + data.len())?;
                return Err(FlashError::PowerLost);
            }
        }
        self.persist(o, o + data.len())
    }

    fn do_erase(&mut self, from: u32, to: u32) -> Result<(), FlashError> {
        if to < from {
            return Err(FlashError::OutOfBounds);
        }
        let f = self.check(from, (to - from) as usize, PAGE_SIZE)?;
        let t = to as usize;
        let op = self.ops;
        match self.begin(OpKind::Erase)? {
            None => {
                self.bytes[f..t].fill(0xFF);
                for p in f / PAGE_SIZE..t / PAGE_SIZE {
                    self.erases[p] += 1;
                }
            }
            Some(Tear::Before) => return Err(FlashError::PowerLost),
            Some(Tear::Torn) => {
                // The first page half erased, the rest of it with some bits set.
                let half = f + PAGE_SIZE / 2;
                self.bytes[f..half].fill(0xFF);
                for i in half..(f + PAGE_SIZE) {
                    self.bytes[i] |= Self::noise(op, i);
                }
                self.persist(f, f + PAGE_SIZE)?;
                return Err(FlashError::PowerLost);
            }
        }
        self.persist(f, t)
    }
}

impl nor::ErrorType for G474Flash {
    type Error = FlashError;
}

impl nor::ReadNorFlash for G474Flash {
    const READ_SIZE: usize = 1;
    async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), FlashError> {
        self.do_read(offset, bytes)
    }
    fn capacity(&self) -> usize {
        self.bytes.len()
    }
}

impl nor::NorFlash for G474Flash {
    const WRITE_SIZE: usize = WRITE_SIZE;
    const ERASE_SIZE: usize = PAGE_SIZE;
    async fn erase(&mut self, from: u32, to: u32) -> Result<(), FlashError> {
        self.do_erase(from, to)
    }
    async fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), FlashError> {
        self.do_write(offset, bytes)
    }
}

impl blocking::ReadNorFlash for G474Flash {
    const READ_SIZE: usize = 1;
    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), FlashError> {
        self.do_read(offset, bytes)
    }
    fn capacity(&self) -> usize {
        self.bytes.len()
    }
}

impl blocking::NorFlash for G474Flash {
    const WRITE_SIZE: usize = WRITE_SIZE;
    const ERASE_SIZE: usize = PAGE_SIZE;
    fn erase(&mut self, from: u32, to: u32) -> Result<(), FlashError> {
        self.do_erase(from, to)
    }
    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), FlashError> {
        self.do_write(offset, bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use blocking::{NorFlash, ReadNorFlash};

    #[test]
    fn enforces_granularity_and_erase_before_write() {
        let mut f = G474Flash::new(2);
        assert_eq!(
            NorFlash::write(&mut f, 4, &[0; 8]),
            Err(FlashError::NotAligned)
        );
        assert_eq!(
            NorFlash::write(&mut f, 0, &[0; 7]),
            Err(FlashError::NotAligned)
        );
        assert_eq!(NorFlash::write(&mut f, 0, &[1; 8]), Ok(()));
        assert_eq!(
            NorFlash::write(&mut f, 0, &[1; 8]),
            Err(FlashError::NotErased)
        );
        assert_eq!(
            NorFlash::write(&mut f, 0, &[0; 8]),
            Ok(()),
            "zeros over a programmed double word"
        );
        assert_eq!(
            NorFlash::erase(&mut f, 0, 1024),
            Err(FlashError::NotAligned)
        );
        assert_eq!(NorFlash::erase(&mut f, 0, 2048), Ok(()));
        assert_eq!(NorFlash::write(&mut f, 0, &[1; 8]), Ok(()));
        assert_eq!(
            NorFlash::write(&mut f, 4096, &[1; 8]),
            Err(FlashError::OutOfBounds)
        );
    }

    #[test]
    fn a_cut_tears_the_operation_and_stops_the_rest() {
        let mut f = G474Flash::new(2);
        f.cut_at(1, Tear::Torn);
        NorFlash::write(&mut f, 0, &[0; 32]).unwrap();
        assert_eq!(
            NorFlash::write(&mut f, 32, &[0; 32]),
            Err(FlashError::PowerLost)
        );
        assert_eq!(
            NorFlash::write(&mut f, 64, &[0; 8]),
            Err(FlashError::PowerLost)
        );
        let mut b = [0u8; 72];
        ReadNorFlash::read(&mut f, 0, &mut b).unwrap();
        assert!(
            b[32..48].iter().all(|x| *x == 0),
            "the first half of the torn write is done"
        );
        assert!(
            b[56..72].iter().all(|x| *x == 0xFF),
            "nothing after the torn double word"
        );
        f.power_on();
        assert_eq!(NorFlash::write(&mut f, 64, &[0; 8]), Ok(()));
    }
}
