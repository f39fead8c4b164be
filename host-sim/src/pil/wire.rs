//! The plant link's wire format, host side: fixed 32-byte messages from the board, 16-byte replies
//! to it. The board side is `firmware/src/board/mps2/link.rs`; both must change together.

/// Bytes per message from the board.
pub const MSG_LEN: usize = 32;
/// Bytes per reply to the board.
pub const REPLY_LEN: usize = 16;

/// A message kind the host itself writes into the board's FIFO when QEMU has exited.
pub const KIND_EXITED: u8 = 0xFF;

/// The bridge outputs as the board drives them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Pins {
    pub phase_forward: [bool; 3],
    pub compare: [u16; 3],
    pub pwm_enable: bool,
    pub driver_awake: bool,
}

impl Pins {
    /// Every output off (the state before the board first drives).
    pub const OFF: Pins = Pins {
        phase_forward: [true; 3],
        compare: [0; 3],
        pwm_enable: false,
        driver_awake: false,
    };

    /// The bridges conduct: PWM enabled and drivers awake.
    pub fn enabled(&self) -> bool {
        self.pwm_enable && self.driver_awake
    }

    /// Signed duty per motor the bridges apply: ±compare / full scale, 0 when not enabled.
    pub fn duties(&self, full_scale: u32) -> [f32; 3] {
        let mut d = [0.0f32; 3];
        if self.enabled() {
            for (i, out) in d.iter_mut().enumerate() {
                let m = self.compare[i] as f32 / full_scale as f32;
                *out = if self.phase_forward[i] { m } else { -m };
            }
        }
        d
    }

    /// The signed compare values (negative: reverse phase), 0 when not enabled.
    pub fn signed_compare(&self) -> [i32; 3] {
        let mut c = [0i32; 3];
        if self.enabled() {
            for (i, out) in c.iter_mut().enumerate() {
                let m = i32::from(self.compare[i]);
                *out = if self.phase_forward[i] { m } else { -m };
            }
        }
        c
    }
}

/// The firmware's control configuration as the board reports it at boot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoardConfig {
    /// How the board came out of reset: 0 power-on, 1 watchdog, 2 panic, 3 HardFault.
    pub reset_cause: u32,
    /// PWM compare value for 100 % duty.
    pub full_scale: u32,
    /// The output guard's duty limit.
    pub max_duty: f32,
    /// The output guard's overrun streak that latches.
    pub max_overrun_streak: u32,
    /// The encoder bank's glitch threshold, counts per tick.
    pub max_counts_per_tick: u16,
}

/// One message from the board.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Message {
    Hello(BoardConfig),
    Sense,
    Drive(Pins),
    Report { key: u16, value: u32 },
    Done,
    /// The watchdog fired; the system resets after `counts` more counts.
    ResetPending { counts: u32 },
    /// QEMU exited (written by the host's monitor, not the board).
    Exited,
}

/// A message with the board time it was sent at (25 MHz counts since the board's time base
/// started).
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
pub fn decode(m: &[u8; MSG_LEN]) -> Result<Stamped, String> {
    let bits = m[1];
    let key = u16_at(m, 2);
    let compare = [u16_at(m, 4), u16_at(m, 6), u16_at(m, 8)];
    let (a, b, c) = (u32_at(m, 12), u32_at(m, 16), u32_at(m, 20));
    let message = match m[0] {
        1 => Message::Hello(BoardConfig {
            reset_cause: a,
            full_scale: u32::from(compare[0]),
            max_duty: f32::from_bits(b),
            max_overrun_streak: c,
            max_counts_per_tick: key,
        }),
        2 => Message::Sense,
        3 => Message::Drive(Pins {
            phase_forward: [bits & 1 != 0, bits & 2 != 0, bits & 4 != 0],
            compare,
            pwm_enable: bits & 8 != 0,
            driver_awake: bits & 16 != 0,
        }),
        4 => Message::Report { key, value: a },
        5 => Message::Done,
        6 => Message::ResetPending { counts: a },
        KIND_EXITED => Message::Exited,
        k => return Err(format!("plant link: unknown message kind {k}")),
    };
    let mut t = [0u8; 8];
    t.copy_from_slice(&m[24..32]);
    Ok(Stamped {
        time_counts: u64::from_le_bytes(t),
        message,
    })
}

/// Reply to `Sense`: raw counts, nFAULT, control bits.
pub fn sense_reply(counts: [u16; 6], n_fault: bool, control: u8) -> [u8; REPLY_LEN] {
    let mut r = [0u8; REPLY_LEN];
    for (i, c) in counts.iter().enumerate() {
        r[2 * i..2 * i + 2].copy_from_slice(&c.to_le_bytes());
    }
    r[12] = u8::from(n_fault);
    r[13] = control;
    r
}

/// Reply to `Hello`: control rate, injected fault code, tick of the injection.
pub fn hello_reply(rate_hz: u32, fault_code: u32, fault_tick: u32) -> [u8; REPLY_LEN] {
    let mut r = [0u8; REPLY_LEN];
    r[0..4].copy_from_slice(&rate_hz.to_le_bytes());
    r[4..8].copy_from_slice(&fault_code.to_le_bytes());
    r[8..12].copy_from_slice(&fault_tick.to_le_bytes());
    r
}

/// Reply control bit: the run is over.
pub const CONTROL_STOP: u8 = 1 << 0;
/// Reply control bit: the log reader has stalled.
pub const CONTROL_LOG_STALL: u8 = 1 << 1;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drive_bits_and_compare_decode() {
        let mut m = [0u8; MSG_LEN];
        m[0] = 3;
        m[1] = 0b1_1101; // phase 0 and 2 forward, PWM on, awake
        m[4..6].copy_from_slice(&100u16.to_le_bytes());
        m[6..8].copy_from_slice(&8500u16.to_le_bytes());
        m[24..32].copy_from_slice(&77u64.to_le_bytes());
        let s = decode(&m).unwrap();
        assert_eq!(s.time_counts, 77);
        let Message::Drive(p) = s.message else {
            panic!("{s:?}")
        };
        assert_eq!(p.phase_forward, [true, false, true]);
        assert_eq!(p.signed_compare(), [100, -8500, 0]);
        assert_eq!(p.duties(8500), [100.0 / 8500.0, -1.0, 0.0]);
        // Not enabled (asleep): no drive whatever the compare says.
        let asleep = Pins {
            driver_awake: false,
            ..p
        };
        assert_eq!(asleep.duties(8500), [0.0; 3]);
        m[0] = 9;
        assert!(decode(&m).unwrap_err().contains("kind 9"));
    }
}
