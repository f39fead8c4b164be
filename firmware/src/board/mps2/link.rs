//! The plant link: the emulated board's "pins", exchanged in lock step with the host's plant through
//! semihosting.
//!
//! Under QEMU `-icount` a semihosting call is one instruction to the guest however long the host
//! takes to answer, so the exchange never changes the instruction count of the code around it.
//! The host process (`host-sim pil`) creates two FIFOs in QEMU's working directory before it
//! starts QEMU: the board writes fixed 32-byte messages to `pil-to-plant` and reads 16-byte
//! replies from `pil-from-plant`.
//!
//! Message (board -> plant), little-endian:
//! `[0]` kind, `[1]` bits, `[2..4]` key, `[4..10]` compare\[3\] (u16), `[12..16]` a, `[16..20]` b,
//! `[20..24]` c (u32), `[24..32]` board time in 25 MHz counts since the time base started (u64).
//! Reply (plant -> board): `[0..12]` raw encoder counts\[6\] (u16), `[12]` bit 0 nFAULT asserted,
//! `[13]` control bits ([`CONTROL_STOP`], [`CONTROL_LOG_STALL`], [`CONTROL_INJECT`]), `[14]` an
//! operator command ([`HOME`], [`ARM`], [`DISARM`], [`CLEAR_FAULTS`]) or [`APP_STEP`]; to
//! `Hello`: `[0..4]` control rate (Hz), `[4..8]` the fault the test hook injects when asked,
//! `[8]` bit 0: the host link on UART0 owns the command queue ([`HELLO_HOST_LINK`]; the plant's
//! operator commands are then ignored), bit 1: the scripted
//! application session runs ([`HELLO_APP_SESSION`]; byte 14 = [`APP_STEP`] then gives its next
//! update).
//! The host side is host-sim/src/pil/wire.rs; both sides must change together.
#![allow(unsafe_code)]

use core::sync::atomic::{AtomicUsize, Ordering};
use cortex_m_semihosting::{nr, syscall};

use softfinger_core::control::pipeline::BridgeCommands;

use super::cmsdk::FreeRunning;

/// Bytes per message to the plant.
pub const MSG_LEN: usize = 32;
/// Bytes per reply from the plant.
pub const REPLY_LEN: usize = 16;

/// Message kinds.
#[derive(Clone, Copy)]
#[repr(u8)]
pub enum Kind {
    /// The board booted: a = reset cause (`faults::CAUSE_*`). The reply configures the run.
    Hello = 1,
    /// Sample the inputs now; key = the pipeline's mode after the previous tick (the operator's
    /// view of the status LED); a = the previous tick's write time as this tick's pipeline gets it
    /// (`RawInput::prev_write_done_counts`). Reply: encoder counts, nFAULT, control bits,
    /// operator command.
    Sense = 2,
    /// The bridge outputs change now (bits: phase 0..2, bit 3 PWM enable, bit 4 nSLEEP high).
    Drive = 3,
    /// One end-of-run figure: key, value in a.
    Report = 4,
    /// The run ended; the board exits after this.
    Done = 5,
    /// The watchdog fired (NMI); the system resets `a` counts from now.
    ResetPending = 6,
}

/// Reply control bit: the run is over, stop the tick and report.
pub const CONTROL_STOP: u8 = 1 << 0;
/// Reply control bit: the host's log reader has stalled (fault injection).
pub const CONTROL_LOG_STALL: u8 = 1 << 1;
/// Reply control bit: the test hook injects its fault in this tick.
pub const CONTROL_INJECT: u8 = 1 << 2;

/// A reply's byte 14: the scripted application's next update is due after this tick
/// (`softfinger_app::scripted_app`; `host-sim pil --app-session`).
pub const APP_STEP: u8 = 5;

/// A reply's byte 14: the plant's operator gives `Home` (0: no command).
pub const HOME: u8 = 1;
/// A reply's byte 14: `Arm`.
pub const ARM: u8 = 2;
/// A reply's byte 14: `Disarm`.
pub const DISARM: u8 = 3;
/// A reply's byte 14: `ClearFaults`.
pub const CLEAR_FAULTS: u8 = 4;

/// What the plant's inputs read at one sample.
#[derive(Clone, Copy, Debug, Default)]
pub struct Sensed {
    pub counts: [u16; 6],
    pub n_fault_asserted: bool,
    pub control: u8,
    pub command: u8,
}

const NOT_OPEN: usize = usize::MAX;
static TO_PLANT: AtomicUsize = AtomicUsize::new(NOT_OPEN);
static FROM_PLANT: AtomicUsize = AtomicUsize::new(NOT_OPEN);

fn open(path: &[u8], mode: usize) -> Option<usize> {
    // SAFETY: `path` is NUL-terminated and outlives the call; OPEN takes (name, mode, length).
    let fd = unsafe { syscall!(OPEN, path.as_ptr(), mode, path.len() - 1) };
    (fd != usize::MAX).then_some(fd)
}

/// Open both FIFOs. False when the host is not there (the board then never drives).
pub fn open_link() -> bool {
    let (Some(tx), Some(rx)) = (
        open(b"pil-to-plant\0", nr::open::W_TRUNC_BINARY),
        open(b"pil-from-plant\0", nr::open::R_BINARY),
    ) else {
        return false;
    };
    TO_PLANT.store(tx, Ordering::Relaxed);
    FROM_PLANT.store(rx, Ordering::Relaxed);
    true
}

/// Board time: 25 MHz counts since the time base started (wraps after 171.8 s).
#[inline(always)]
pub fn now_counts() -> u32 {
    u32::MAX - FreeRunning::value()
}

/// Send one message stamped with the board time now.
#[inline(always)]
pub fn send(kind: Kind, bits: u8, key: u16, compare: [u16; 3], abc: [u32; 3]) {
    let mut m = [0u8; MSG_LEN];
    m[0] = kind as u8;
    m[1] = bits;
    m[2..4].copy_from_slice(&key.to_le_bytes());
    for (i, c) in compare.iter().enumerate() {
        m[4 + 2 * i..6 + 2 * i].copy_from_slice(&c.to_le_bytes());
    }
    for (i, v) in abc.iter().enumerate() {
        m[12 + 4 * i..16 + 4 * i].copy_from_slice(&v.to_le_bytes());
    }
    m[24..32].copy_from_slice(&u64::from(now_counts()).to_le_bytes());
    let fd = TO_PLANT.load(Ordering::Relaxed);
    if fd != NOT_OPEN {
        // SAFETY: `m` is valid for MSG_LEN bytes during the call; WRITE takes (fd, buffer, length).
        let _ = unsafe { syscall!(WRITE, fd, m.as_ptr(), MSG_LEN) };
    }
}

/// Read one reply; `None` when the host has gone (end of file) or the link is not open.
fn receive() -> Option<[u8; REPLY_LEN]> {
    let fd = FROM_PLANT.load(Ordering::Relaxed);
    if fd == NOT_OPEN {
        return None;
    }
    let mut r = [0u8; REPLY_LEN];
    let mut done = 0;
    while done < REPLY_LEN {
        // SAFETY: the buffer tail is valid for writes; READ returns the bytes NOT read.
        let left = unsafe { syscall!(READ, fd, r.as_mut_ptr().add(done), REPLY_LEN - done) };
        let got = (REPLY_LEN - done).saturating_sub(left);
        if got == 0 {
            return None;
        }
        done += got;
    }
    Some(r)
}

/// Hello reply byte 8: the host link on UART0 owns the command queue.
pub const HELLO_HOST_LINK: u8 = 1 << 0;
/// Hello reply byte 8: the scripted application session runs (its updates on [`APP_STEP`]).
pub const HELLO_APP_SESSION: u8 = 1 << 1;

/// How the plant configures a run.
#[derive(Clone, Copy, Debug)]
pub struct RunConfig {
    /// Control rate, Hz.
    pub rate_hz: u32,
    /// The fault the test hook injects when asked.
    pub fault_code: u32,
    /// The host link on UART0 runs and owns the command queue.
    pub host_link: bool,
    /// The scripted application session runs.
    pub app_session: bool,
}

/// Announce a boot; returns the run's configuration.
pub fn hello(reset_cause: u32) -> Option<RunConfig> {
    send(Kind::Hello, 0, 0, [0; 3], [reset_cause, 0, 0]);
    let r = receive()?;
    let word = |i: usize| u32::from_le_bytes([r[i], r[i + 1], r[i + 2], r[i + 3]]);
    Some(RunConfig {
        rate_hz: word(0),
        fault_code: word(4),
        host_link: r[8] & HELLO_HOST_LINK != 0,
        app_session: r[8] & HELLO_APP_SESSION != 0,
    })
}

/// Sample the inputs (the encoder timers and the nFAULT pin), telling the plant the previous
/// tick's write time as this tick's pipeline gets it.
#[inline(always)]
pub fn sense(mode_code: u8, prev_write_done: u32) -> Option<Sensed> {
    send(
        Kind::Sense,
        0,
        u16::from(mode_code),
        [0; 3],
        [prev_write_done, 0, 0],
    );
    let r = receive()?;
    let mut counts = [0u16; 6];
    for (i, c) in counts.iter_mut().enumerate() {
        *c = u16::from_le_bytes([r[2 * i], r[2 * i + 1]]);
    }
    Some(Sensed {
        counts,
        n_fault_asserted: r[12] & 1 != 0,
        control: r[13],
        command: r[14],
    })
}

/// Write the bridge outputs.
#[inline(always)]
pub fn drive(p: &BridgeCommands) {
    let mut bits = 0u8;
    for (i, f) in p.phase_forward.iter().enumerate() {
        bits |= u8::from(*f) << i;
    }
    bits |= u8::from(p.pwm_enable) << 3 | u8::from(p.driver_awake) << 4;
    send(Kind::Drive, bits, 0, p.compare, [0; 3]);
}

/// One end-of-run figure.
pub fn report(key: u16, value: u32) {
    send(Kind::Report, 0, key, [0; 3], [value, 0, 0]);
}
