//! defmt transport of the emulated board: frames go to a RAM ring that never blocks the writer,
//! and a "log reader" drains the ring to a host file through semihosting, as a debug probe drains
//! an RTT up-buffer.
//!
//! - A frame that does not fit the ring, or that starts while another frame is being written (a
//!   handler preempting thread-mode logging), is dropped and counted; nothing ever waits, and no
//!   interrupt is masked (no critical section).
//! - [`drain`] runs in the 1 kHz time-base interrupt (below the control tick), writing what the
//!   ring holds to `pil-defmt.raw` in QEMU's working directory: the raw rzCOBS-encoded frames that
//!   `host-sim pil` decodes with the `defmt-decoder` crate against this ELF. A stalled host reader
//!   (fault injection) stops the drain, the ring fills, frames are dropped, the tick is untouched.
#![allow(unsafe_code)]

use core::cell::UnsafeCell;
use core::sync::atomic::{AtomicBool, AtomicU32, AtomicUsize, Ordering};
use cortex_m_semihosting::{nr, syscall};

/// Ring capacity, bytes (a power of two).
const RING: usize = 4096;
/// Largest frame, bytes; a longer one is dropped.
const FRAME: usize = 256;

/// The frame being assembled.
struct Frame {
    buf: [u8; FRAME],
    len: usize,
    overflow: bool,
}

/// A cell written by one context at a time (see each static).
struct Owned<T>(UnsafeCell<T>);
// SAFETY: each `Owned` static is accessed only as its comment says: the encoder and the frame by
// the single writer that holds `OWNER`, the ring bytes in [TAIL, HEAD) only read by `drain` and
// the rest only written by the owner; the indices are atomics.
unsafe impl<T> Sync for Owned<T> {}

/// defmt's frame encoder (rzCOBS), owned by the writer holding `OWNER`.
static ENCODER: Owned<defmt::Encoder> = Owned(UnsafeCell::new(defmt::Encoder::new()));
/// The frame being assembled, owned by the writer holding `OWNER`.
static CURRENT: Owned<Frame> = Owned(UnsafeCell::new(Frame {
    buf: [0; FRAME],
    len: 0,
    overflow: false,
}));
/// The ring: written by the owner beyond HEAD, read by `drain` between TAIL and HEAD.
static RING_BUF: Owned<[u8; RING]> = Owned(UnsafeCell::new([0; RING]));
/// A frame is being written.
static OWNER: AtomicBool = AtomicBool::new(false);
/// Nested acquisitions (preempting writers) outstanding: their bytes are discarded.
static NESTED: AtomicU32 = AtomicU32::new(0);
/// Ring write and read positions (free-running).
static HEAD: AtomicUsize = AtomicUsize::new(0);
static TAIL: AtomicUsize = AtomicUsize::new(0);
/// Frames put in the ring, frames dropped.
static FRAMES: AtomicU32 = AtomicU32::new(0);
static DROPS: AtomicU32 = AtomicU32::new(0);
/// The host file, once open.
static FD: AtomicUsize = AtomicUsize::new(usize::MAX);
/// The host's log reader has stalled (fault injection): the drain does nothing.
pub static READER_STALLED: AtomicBool = AtomicBool::new(false);

/// Frames logged and frames dropped so far.
pub fn counters() -> (u32, u32) {
    (
        FRAMES.load(Ordering::Relaxed),
        DROPS.load(Ordering::Relaxed),
    )
}

/// Open the host log file. Until then frames stay in the ring.
pub fn open() {
    let path = b"pil-defmt.raw\0";
    // SAFETY: NUL-terminated name valid during the call; OPEN takes (name, mode, length).
    let fd = unsafe {
        syscall!(
            OPEN,
            path.as_ptr(),
            nr::open::W_APPEND_BINARY,
            path.len() - 1
        )
    };
    if fd != usize::MAX {
        FD.store(fd, Ordering::Relaxed);
    }
}

/// Write everything in the ring to the host file (at most two semihosting writes).
pub fn drain() {
    let fd = FD.load(Ordering::Relaxed);
    if fd == usize::MAX || READER_STALLED.load(Ordering::Relaxed) {
        return;
    }
    let head = HEAD.load(Ordering::Acquire);
    let mut tail = TAIL.load(Ordering::Relaxed);
    while tail != head {
        let start = tail % RING;
        let len = head.wrapping_sub(tail).min(RING - start);
        // SAFETY: bytes [tail, head) were published by `release` (Release store of HEAD) and are
        // not written again until TAIL passes them.
        let ptr = unsafe { (*RING_BUF.0.get()).as_ptr().add(start) };
        // SAFETY: `ptr` is valid for `len` bytes; WRITE takes (fd, buffer, length).
        let _ = unsafe { syscall!(WRITE, fd, ptr, len) };
        tail = tail.wrapping_add(len);
    }
    TAIL.store(tail, Ordering::Release);
}

/// Append encoded bytes to the frame being assembled.
///
/// # Safety
/// Only the writer holding `OWNER` may call this.
unsafe fn frame_bytes(bytes: &[u8]) {
    let s = &mut *CURRENT.0.get();
    if s.len + bytes.len() > FRAME {
        s.overflow = true;
        return;
    }
    s.buf[s.len..s.len + bytes.len()].copy_from_slice(bytes);
    s.len += bytes.len();
}

#[defmt::global_logger]
struct Logger;

// SAFETY: `acquire` hands the encoder to one writer at a time (the `OWNER` flag); a writer that
// preempts the owner is counted in `NESTED` and its bytes are discarded, so frames never interleave.
unsafe impl defmt::Logger for Logger {
    fn acquire() {
        if OWNER.swap(true, Ordering::Acquire) {
            NESTED.fetch_add(1, Ordering::Relaxed);
            DROPS.fetch_add(1, Ordering::Relaxed);
            return;
        }
        // SAFETY: this writer holds OWNER (it was false), so it alone touches the frame and the
        // encoder until `release`.
        unsafe {
            let f = &mut *CURRENT.0.get();
            f.len = 0;
            f.overflow = false;
            (*ENCODER.0.get()).start_frame(|b| frame_bytes(b));
        }
    }

    unsafe fn write(bytes: &[u8]) {
        if NESTED.load(Ordering::Relaxed) > 0 {
            return;
        }
        (*ENCODER.0.get()).write(bytes, |b| frame_bytes(b));
    }

    unsafe fn flush() {}

    unsafe fn release() {
        if NESTED.load(Ordering::Relaxed) > 0 {
            NESTED.fetch_sub(1, Ordering::Relaxed);
            return;
        }
        (*ENCODER.0.get()).end_frame(|b| frame_bytes(b));
        let f = &*CURRENT.0.get();
        let head = HEAD.load(Ordering::Relaxed);
        let free = RING - head.wrapping_sub(TAIL.load(Ordering::Acquire));
        if f.overflow || f.len > free {
            DROPS.fetch_add(1, Ordering::Relaxed);
        } else {
            // Raw writes: `drain` may be reading [TAIL, HEAD) of the same array meanwhile.
            let ring = RING_BUF.0.get().cast::<u8>();
            for (i, b) in f.buf[..f.len].iter().enumerate() {
                ring.add(head.wrapping_add(i) % RING).write(*b);
            }
            HEAD.store(head.wrapping_add(f.len), Ordering::Release);
            FRAMES.fetch_add(1, Ordering::Relaxed);
        }
        OWNER.store(false, Ordering::Release);
    }
}
