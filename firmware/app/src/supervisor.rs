//! The status LED and the status log: mode transitions, latched faults and operator-command
//! outcomes are logged as they happen; the LED shows the mode, or the latched faults as a blink
//! code.
//!
//! | mode | LED |
//! | --- | --- |
//! | Unhomed | a 100 ms flash every 2 s |
//! | Homing | fast blink, 5 Hz |
//! | Disarmed | slow blink, 1 Hz |
//! | Armed | on |
//! | Faulted | blink code: for each latched fault in turn, `n` flashes (200 ms on, 200 ms off), then 1 s dark; `n` from [`BLINK_CODES`] |

use core::sync::atomic::Ordering;

use defmt::{info, warn};
use embassy_time::{Duration, Ticker};
use heapless::spsc::Consumer;
use softfinger_core::control::pipeline::Mode;
use softfinger_core::Flags;

use crate::board::Indicator;
use crate::config;
use crate::tick::{published_mode, CommandOutcome, STATUS};

/// The latched faults and their blink counts, in the order they are shown: the core's whole
/// latching set (`output_guard::LATCHING`). A latched bit not listed here shows as 8.
pub const BLINK_CODES: [(Flags, u32); 7] = [
    (Flags::DRIVER_FAULT, 1),
    (Flags::ENCODER_GLITCH, 2),
    (Flags::ENCODER_STUCK, 3),
    (Flags::OVERRUN, 4),
    (Flags::NON_FINITE_OUTPUT, 5),
    (Flags::HOMING_FAILED, 6),
    (Flags::THREAD_STALLED, 7),
];
const OTHER_CODE: u32 = 8;
const _: () = {
    let mut all = 0;
    let mut i = 0;
    while i < BLINK_CODES.len() {
        all |= BLINK_CODES[i].0 .0;
        i += 1;
    }
    assert!(all == softfinger_core::control::output_guard::LATCHING.0);
};

/// Polls per time slot.
const fn polls(ms: u64) -> u32 {
    (ms / config::SUPERVISOR_POLL_MS) as u32
}

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

/// The LED sequencer: a poll counter and, for the blink code, which fault is being shown.
struct Led {
    slot: usize,
    poll: u32,
}

impl Led {
    /// LED level for this poll, advancing the pattern.
    fn step(&mut self, mode: Mode, latched: Flags) -> bool {
        let poll = self.poll;
        self.poll = self.poll.wrapping_add(1);
        match mode {
            Mode::Unhomed => poll % polls(2000) < polls(100),
            Mode::Homing => poll % polls(200) < polls(100),
            Mode::Disarmed => poll % polls(1000) < polls(500),
            Mode::Armed => true,
            Mode::Faulted => self.blink_code(&codes(latched), poll),
        }
    }

    fn blink_code(&mut self, codes: &[u32], poll: u32) -> bool {
        let code = match codes.get(self.slot) {
            Some(&c) if c > 0 => c,
            _ => {
                // Past the last latched fault: start again from the first.
                self.slot = 0;
                self.poll = 0;
                return false;
            }
        };
        let flash = polls(200);
        let flashes_end = 2 * code * flash;
        if poll + 1 >= flashes_end + polls(1000) {
            self.slot += 1;
            self.poll = 0;
        }
        poll < flashes_end && (poll / flash).is_multiple_of(2)
    }
}

/// Watch the tick's status forever (the board binary spawns this as a task); each command
/// outcome is also handed to `forward` (the host link's acknowledgements, when there is one).
pub async fn run(
    mut indicator: impl Indicator,
    mut outcomes: Consumer<'static, CommandOutcome>,
    mut forward: impl FnMut(&CommandOutcome),
) {
    let mut ticker = Ticker::every(Duration::from_millis(config::SUPERVISOR_POLL_MS));
    let mut previous_mode = Mode::Unhomed;
    let mut previous = Flags::NONE;
    let mut led = Led { slot: 0, poll: 0 };
    loop {
        while let Some(o) = outcomes.dequeue() {
            match o.result {
                Ok(()) => info!("command {} applied", o.command),
                Err(e) => warn!("command {} REFUSED: {}", o.command, e),
            }
            forward(&o);
        }
        let mode = published_mode();
        let latched = Flags(STATUS.latched.load(Ordering::Relaxed));
        let new = Flags(latched.0 & !previous.0);
        if !new.is_empty() {
            warn!(
                "FAULT latched: {} (blink codes {}); zero torque, drivers asleep until cleared",
                new,
                codes(new)
            );
        }
        if mode != previous_mode {
            info!("mode: {} -> {}", previous_mode, mode);
            led = Led { slot: 0, poll: 0 };
        }
        previous = latched;
        previous_mode = mode;
        indicator.set(led.step(mode, latched));
        ticker.next().await;
    }
}
