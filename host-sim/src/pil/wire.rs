//! The plant link's wire format, host side: fixed 32-byte messages from the board, 16-byte replies
//! to it. The board side is `firmware/src/board/mps2/link.rs`; both must change together.
//!
//! Message: `[0]` kind, `[1]` bits, `[2..4]` key, `[4..10]` compare\[3\], `[12..16]` a,
//! `[24..32]` board time (25 MHz counts since the tick timer started). Reply to `Sense`:
//! `[0..12]` raw counts\[6\], `[12]` nFAULT asserted, `[13]` control bits, `[14]` operator command;
//! to `Hello`: `[0..4]` control rate, `[4..8]` the fault the board's test hook injects when asked.

use super::PilError;
use softfinger_core::control::pipeline::{BridgeCommands, Mode};

/// Bytes per message from the board.
pub const MSG_LEN: usize = 32;
/// Bytes per reply to the board.
pub const REPLY_LEN: usize = 16;

/// A message kind the host itself writes into the board's FIFO when QEMU has exited.
pub const KIND_EXITED: u8 = 0xFF;

/// Reply control bit: the run is over.
pub const CONTROL_STOP: u8 = 1 << 0;
/// Reply control bit: the log reader has stalled.
pub const CONTROL_LOG_STALL: u8 = 1 << 1;
/// Reply control bit: the board's test hook injects its fault in this tick.
pub const CONTROL_INJECT: u8 = 1 << 2;

/// Signed compare values of bridge commands (negative: reverse phase), 0 when the bridges do
/// not conduct (PWM disabled or drivers asleep).
pub fn signed_compare(b: &BridgeCommands) -> [i32; 3] {
    let mut c = [0i32; 3];
    if enabled(b) {
        for (i, out) in c.iter_mut().enumerate() {
            let m = i32::from(b.compare[i]);
            *out = if b.phase_forward[i] { m } else { -m };
        }
    }
    c
}

/// The bridges conduct.
pub fn enabled(b: &BridgeCommands) -> bool {
    b.pwm_enable && b.driver_awake
}

/// The pipeline mode of a link code (`Mode::code`).
pub fn mode_of(code: u16) -> Mode {
    match code {
        0 => Mode::Unhomed,
        1 => Mode::Homing,
        2 => Mode::Disarmed,
        3 => Mode::Armed,
        _ => Mode::Faulted,
    }
}

/// One message from the board.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Message {
    /// The board booted; how it came out of reset (0 power-on, 1 watchdog).
    Hello {
        reset_cause: u32,
    },
    /// Sample the inputs; the pipeline's mode after the previous tick, and the previous tick's
    /// write time as this tick's pipeline gets it (`RawInput::prev_write_done_counts`: 170 MHz
    /// timer counts, `u32::MAX` when the writes ran into the next period).
    Sense {
        mode: Mode,
        prev_write_done: u32,
    },
    Drive(BridgeCommands),
    Report {
        key: u16,
        value: u32,
    },
    Done,
    /// The watchdog fired; the system resets after `counts` more counts.
    ResetPending {
        counts: u32,
    },
    /// QEMU exited (written by the host's monitor, not the board).
    Exited,
}

/// A message with the board time it was sent at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stamped {
    pub time_counts: u64,
    pub message: Message,
}

fn u16_at(m: &[u8; MSG_LEN], i: usize) -> u16 {
    u16::from_le_bytes([m[i], m[i + 1]])
}
fn u32_at(m: &[u8; MSG_LEN], i: usize) -> u32 {
    u32::from_le_bytes([m[i], m[i + 1], m[i + 2], m[i + 3]])
}

/// Decode one message; an unknown kind is an error naming it.
pub fn decode(m: &[u8; MSG_LEN]) -> Result<Stamped, PilError> {
    let bits = m[1];
    let key = u16_at(m, 2);
    let a = u32_at(m, 12);
    let message = match m[0] {
        1 => Message::Hello { reset_cause: a },
        2 => Message::Sense {
            mode: mode_of(key),
            prev_write_done: a,
        },
        3 => Message::Drive(BridgeCommands {
            phase_forward: [bits & 1 != 0, bits & 2 != 0, bits & 4 != 0],
            compare: [u16_at(m, 4), u16_at(m, 6), u16_at(m, 8)],
            pwm_enable: bits & 8 != 0,
            driver_awake: bits & 16 != 0,
        }),
        4 => Message::Report { key, value: a },
        5 => Message::Done,
        6 => Message::ResetPending { counts: a },
        KIND_EXITED => Message::Exited,
        k => return Err(PilError::UnknownKind(k)),
    };
    let mut t = [0u8; 8];
    t.copy_from_slice(&m[24..32]);
    Ok(Stamped {
        time_counts: u64::from_le_bytes(t),
        message,
    })
}

/// Reply to `Sense`: raw counts, nFAULT, control bits, operator command code.
pub fn sense_reply(counts: [u16; 6], n_fault: bool, control: u8, command: u8) -> [u8; REPLY_LEN] {
    let mut r = [0u8; REPLY_LEN];
    for (i, c) in counts.iter().enumerate() {
        r[2 * i..2 * i + 2].copy_from_slice(&c.to_le_bytes());
    }
    r[12] = u8::from(n_fault);
    r[13] = control;
    r[14] = command;
    r
}

/// Reply to `Hello`: control rate, the fault the board's test hook injects when asked.
pub fn hello_reply(
    rate_hz: u32,
    fault_code: u32,
    host_link: bool,
    app_session: bool,
) -> [u8; REPLY_LEN] {
    let mut r = [0u8; REPLY_LEN];
    r[0..4].copy_from_slice(&rate_hz.to_le_bytes());
    r[4..8].copy_from_slice(&fault_code.to_le_bytes());
    r[8] = if host_link { HELLO_HOST_LINK } else { 0 }
        | if app_session { HELLO_APP_SESSION } else { 0 };
    r
}

/// Hello reply byte 8: the board runs the host link on UART0, which owns its command queue (the
/// operator's commands in the sense replies are then ignored).
pub const HELLO_HOST_LINK: u8 = 1 << 0;
/// Hello reply byte 8: the scripted application session runs; a sense reply's command byte
/// [`APP_STEP`] then hands the tick the application's next update.
pub const HELLO_APP_SESSION: u8 = 1 << 1;
/// A sense reply's command byte: the scripted application's next update, after this tick.
pub const APP_STEP: u8 = 5;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hello_reply_carries_rate_fault_and_the_host_link_bit() {
        // The board reads byte 8 bit 0 (firmware/src/board/mps2/link.rs, HELLO_HOST_LINK).
        let on = hello_reply(20_000, 3, true, false);
        let off = hello_reply(20_000, 3, false, false);
        let app = hello_reply(20_000, 3, false, true);
        assert_eq!(on[8], 1);
        assert_eq!(off[8], 0);
        // The board reads bit 1 (HELLO_APP_SESSION).
        assert_eq!(app[8], 2);
        assert_eq!(on[..8], off[..8]);
        assert_eq!(u32::from_le_bytes([on[0], on[1], on[2], on[3]]), 20_000);
        assert_eq!(u32::from_le_bytes([on[4], on[5], on[6], on[7]]), 3);
    }

    #[test]
    fn messages_decode() {
        let mut m = [0u8; MSG_LEN];
        m[0] = 3;
        m[1] = 0b1_1101; // phase 0 and 2 forward, PWM on, awake
        m[4..6].copy_from_slice(&100u16.to_le_bytes());
        m[6..8].copy_from_slice(&8500u16.to_le_bytes());
        m[24..32].copy_from_slice(&77u64.to_le_bytes());
        let s = decode(&m).unwrap();
        assert_eq!(s.time_counts, 77);
        let Message::Drive(b) = s.message else {
            panic!("{s:?}")
        };
        assert_eq!(b.phase_forward, [true, false, true]);
        assert_eq!(signed_compare(&b), [100, -8500, 0]);
        // Asleep: no drive whatever the compare says.
        let asleep = BridgeCommands {
            driver_awake: false,
            ..b
        };
        assert_eq!(signed_compare(&asleep), [0; 3]);
        m[0] = 2;
        m[2] = 3;
        m[12..16].copy_from_slice(&4_321u32.to_le_bytes());
        assert_eq!(
            decode(&m).unwrap().message,
            Message::Sense {
                mode: Mode::Armed,
                prev_write_done: 4_321
            }
        );
        m[0] = 9;
        assert!(decode(&m).unwrap_err().to_string().contains("kind 9"));
    }
}
