//! Fault reporting: logs every transition of the tick's latched faults and of the operator
//! commands' outcomes, and shows the latched faults on the status LED as a blink code.
//!
//! Blink code: while any fault is latched the LED repeats, for each latched fault in turn, `n`
//! short flashes (200 ms on, 200 ms off) followed by a 1 s pause, where `n` is the fault's number
//! in [`BLINK_CODES`]. With no fault latched the LED is off.

use core::sync::atomic::Ordering;

use defmt::{info, warn};
use embassy_time::{Duration, Ticker};
use softfinger_core::Flags;

use crate::board::Indicator;
use crate::config;
use crate::tick::STATUS;

/// Latched faults and their blink counts, in the order they are shown. A latched bit not listed
/// here is shown as the last code + 1.
pub const BLINK_CODES: [(Flags, u32); 5] = [
    (Flags::DRIVER_FAULT, 1),
    (Flags::ENCODER_GLITCH, 2),
    (Flags::ENCODER_STUCK, 3),
    (Flags::OVERRUN, 4),
    (Flags::NON_FINITE_OUTPUT, 5),
];
/// Blink count of a latched flag missing from [`BLINK_CODES`].
const OTHER_CODE: u32 = 6;

/// LED time slots, in supervisor polls.
const FLASH_POLLS: u32 = (200 / config::SUPERVISOR_POLL_MS) as u32;
const PAUSE_POLLS: u32 = (1000 / config::SUPERVISOR_POLL_MS) as u32;

/// Blink counts of the latched faults, in [`BLINK_CODES`] order; unused slots are 0.
fn codes(latched: Flags) -> [u32; BLINK_CODES.len() + 1] {
    let mut out = [0; BLINK_CODES.len() + 1];
    let mut known = Flags::NONE;
    let mut n = 0;
    for (flag, code) in BLINK_CODES {
        known |= flag;
        if latched.intersects(flag) {
            out[n] = code;
            n += 1;
        }
    }
    if latched.0 & !known.0 != 0 {
        out[n] = OTHER_CODE;
    }
    out
}

/// The blink-code player: which fault is being shown and where in its sequence.
struct BlinkCode {
    slot: usize,
    poll: u32,
}

impl BlinkCode {
    /// LED level for this poll, advancing the sequence.
    fn step(&mut self, codes: &[u32]) -> bool {
        let code = codes.get(self.slot).copied().unwrap_or(0);
        if code == 0 {
            // Past the last latched fault (or none): restart from the first.
            self.slot = 0;
            self.poll = 0;
            return false;
        }
        let flashes_end = 2 * code * FLASH_POLLS;
        let on = self.poll < flashes_end && (self.poll / FLASH_POLLS).is_multiple_of(2);
        self.poll += 1;
        if self.poll >= flashes_end + PAUSE_POLLS {
            self.poll = 0;
            self.slot += 1;
        }
        on
    }
}

/// Watch the tick's status forever (the board binary spawns this as a task).
pub async fn run(mut led: impl Indicator) {
    let mut ticker = Ticker::every(Duration::from_millis(config::SUPERVISOR_POLL_MS));
    let mut previous = Flags::NONE;
    let mut previous_results = 0u32;
    let mut blink = BlinkCode { slot: 0, poll: 0 };
    loop {
        let results = STATUS.command_results.load(Ordering::Relaxed);
        if results != previous_results {
            let accepted = (results & 0xFFFF).wrapping_sub(previous_results & 0xFFFF) & 0xFFFF;
            let rejected = (results >> 16).wrapping_sub(previous_results >> 16) & 0xFFFF;
            if accepted > 0 {
                info!("{=u32} operator command(s) applied", accepted);
            }
            if rejected > 0 {
                warn!("{=u32} operator command(s) REJECTED", rejected);
            }
            previous_results = results;
        }
        let latched = Flags(STATUS.latched.load(Ordering::Relaxed));
        if latched != previous {
            let new = Flags(latched.0 & !previous.0);
            if !new.is_empty() {
                warn!(
                    "FAULT latched: {} (blink code {}); zero torque until cleared",
                    new,
                    codes(new)
                );
            }
            if latched.is_empty() {
                info!("faults cleared");
            }
            previous = latched;
        }
        led.set(blink.step(&codes(latched)));
        ticker.next().await;
    }
}
