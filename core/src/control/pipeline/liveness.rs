//! Proof that the thread-mode tasks run, for the independent watchdog: the firmware's tick feeds
//! the IWDG only while [`ThreadWatch::tick`] says so.
//!
//! A thread-mode heartbeat task bumps a counter every millisecond; the executor is cooperative,
//! so a task that hangs (a busy loop in the USB stack, the button task, the logger) stops the
//! heartbeat with it. Each tick reads the counter: when it has not moved for `stale_s`, the tick
//! first stops the outputs ([`super::Pipeline::thread_stalled`] latches
//! [`crate::Flags::THREAD_STALLED`]: zero torque, drivers asleep, in that same tick) and then
//! stops feeding the IWDG, which resets the MCU one IWDG timeout later. A stopped tick feeds
//! nothing either, so the IWDG covers the tick and the tasks.

use super::homing::ticks_for;

/// Heartbeat age at which the thread mode counts as hung, s: 50 ms, fifty heartbeats (a USB
/// transfer or a log frame holds the executor for well under 1 ms).
pub const THREAD_STALE_S: f32 = 0.050;

/// The tick's view of the heartbeat.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ThreadWatch {
    stale_ticks: u32,
    last_beat: u32,
    since: u32,
}

impl ThreadWatch {
    /// A watch at `rate_hz` that calls the thread mode hung after `stale_s` without a beat.
    pub fn new(stale_s: f32, rate_hz: f32) -> ThreadWatch {
        ThreadWatch {
            stale_ticks: ticks_for(stale_s, rate_hz),
            last_beat: 0,
            since: 0,
        }
    }

    /// One tick with the heartbeat counter as read. Returns whether the thread mode is alive
    /// (feed the IWDG); `false` from the `stale_ticks`-th tick without a change on.
    pub fn tick(&mut self, beat: u32) -> bool {
        if beat != self.last_beat {
            self.last_beat = beat;
            self.since = 0;
        } else {
            self.since = self.since.saturating_add(1);
        }
        self.since < self.stale_ticks
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 50 ms at 10 kHz: the 499th tick without a beat is alive, the 500th is not; a beat revives.
    #[test]
    fn stale_after_exactly_the_stale_time() {
        let mut w = ThreadWatch::new(THREAD_STALE_S, 10_000.0);
        assert!(w.tick(1));
        for k in 1..500u32 {
            assert!(w.tick(1), "tick {k}");
        }
        assert!(!w.tick(1));
        assert!(w.tick(2));
        // Beats every 10 ticks (1 ms) never go stale.
        for k in 0..10_000u32 {
            assert!(w.tick(3 + k / 10));
        }
    }
}
