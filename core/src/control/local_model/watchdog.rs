//! The communication watchdog: when enabled, no message for `timeout` fades the force to zero
//! within `fade` and latches [`Flags::COMM_TIMEOUT`] until re-armed. Off by default (the
//! standalone bench mode, where no host talks to the device).
//!
//! Per tick the pipeline multiplies its force and torque by [`CommWatchdog::tick`]'s gain. The
//! link task calls [`CommWatchdog::feed`] on every valid message it receives, and the arm command
//! calls [`CommWatchdog::rearm`]. The fade is bounded: the gain reaches 0 at most
//! `ceil(fade·rate)` ticks after the timeout expired, and it changes by at most `1/(fade·rate)`
//! per tick, so the force has no step either way.

use crate::control::local_model::ramp::Ramp;
use crate::flags::Flags;

/// The watchdog's state.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CommWatchdog {
    /// Ticks without a message before the timeout; 0: disabled.
    timeout_ticks: u32,
    since_message: u32,
    latched: bool,
    gain: Ramp,
}

impl CommWatchdog {
    /// A disabled watchdog at `rate_hz` whose fades take `fade_s` (gain 1: no effect).
    pub fn new(rate_hz: f32, fade_s: f32) -> CommWatchdog {
        CommWatchdog {
            timeout_ticks: 0,
            since_message: 0,
            latched: false,
            gain: Ramp::new(1.0, fade_s, rate_hz),
        }
    }

    /// Enable with a timeout of `timeout_s` at `rate_hz` (0 or less, or not finite: disable). The
    /// count restarts, as setting it is itself a message.
    pub fn set_timeout(&mut self, timeout_s: f32, rate_hz: f32) {
        let ticks = timeout_s * rate_hz;
        self.timeout_ticks = if ticks.is_finite() && ticks >= 1.0 {
            if ticks >= u32::MAX as f32 {
                u32::MAX
            } else {
                ticks as u32
            }
        } else {
            0
        };
        self.since_message = 0;
    }

    /// Enabled?
    pub fn enabled(&self) -> bool {
        self.timeout_ticks != 0
    }

    /// Latched after a timeout (until [`Self::rearm`])?
    pub fn latched(&self) -> bool {
        self.latched
    }

    /// A valid message arrived.
    pub fn feed(&mut self) {
        self.since_message = 0;
    }

    /// The operator re-armed: the latch clears (the gain then ramps back in) if a message came
    /// within the timeout; otherwise it stays latched. Returns whether it is clear.
    pub fn rearm(&mut self) -> bool {
        if !self.enabled() || self.since_message < self.timeout_ticks {
            self.latched = false;
        }
        !self.latched
    }

    /// One control tick: the gain to apply to force and torque, and `COMM_TIMEOUT` while latched.
    #[must_use]
    pub fn tick(&mut self) -> (f32, Flags) {
        if self.enabled() {
            self.since_message = self.since_message.saturating_add(1);
            if self.since_message >= self.timeout_ticks {
                self.latched = true;
            }
        }
        let target = if self.latched { 0.0 } else { 1.0 };
        let gain = self.gain.advance(target);
        let flags = if self.latched {
            Flags::COMM_TIMEOUT
        } else {
            Flags::NONE
        };
        (gain, flags)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RATE: f32 = 10_000.0;

    /// 50 ms timeout, 20 ms fade at 10 kHz: no effect at 499 ticks of silence, latched at 500;
    /// the gain is then 0 within 200 more ticks (not at 199), never stepping by more than 1/200.
    #[test]
    fn timeout_fades_within_the_bound_and_latches() {
        let mut w = CommWatchdog::new(RATE, 0.020);
        w.set_timeout(0.050, RATE);
        for _ in 0..499 {
            assert_eq!(w.tick(), (1.0, Flags::NONE));
        }
        let (g, f) = w.tick();
        assert!(f.contains(Flags::COMM_TIMEOUT));
        assert!(g < 1.0);
        let mut prev = g;
        for k in 2..=200 {
            let (g, _) = w.tick();
            assert!(prev - g <= 1.0 / 200.0 + 1e-6, "step {}", prev - g);
            if k == 199 {
                assert!(g > 0.0, "faded too early");
            }
            prev = g;
        }
        assert_eq!(prev, 0.0, "faded within 200 ticks");
        // Messages again: still latched until re-armed.
        w.feed();
        assert!(w.tick().1.contains(Flags::COMM_TIMEOUT));
        assert!(w.rearm());
        let (g, f) = w.tick();
        assert!(
            f.is_empty() && g > 0.0 && g <= 1.0 / 200.0 + 1e-6,
            "ramps back in: {g}"
        );
    }

    #[test]
    fn feeding_keeps_it_quiet_and_disabled_never_fires() {
        let mut w = CommWatchdog::new(RATE, 0.020);
        w.set_timeout(0.050, RATE);
        for k in 0..10_000 {
            if k % 400 == 0 {
                w.feed();
            }
            assert_eq!(w.tick(), (1.0, Flags::NONE));
        }
        let mut off = CommWatchdog::new(RATE, 0.020);
        for _ in 0..100_000 {
            assert_eq!(off.tick(), (1.0, Flags::NONE));
        }
        off.set_timeout(f32::NAN, RATE);
        assert!(!off.enabled());
    }

    /// Re-arming without a recent message leaves it latched.
    #[test]
    fn rearm_needs_a_recent_message() {
        let mut w = CommWatchdog::new(RATE, 0.001);
        w.set_timeout(0.001, RATE);
        let mut flags = Flags::NONE;
        for _ in 0..20 {
            flags = w.tick().1;
        }
        assert_eq!(flags, Flags::COMM_TIMEOUT);
        assert!(!w.rearm());
        assert!(w.latched());
        w.feed();
        assert!(w.rearm());
    }
}
