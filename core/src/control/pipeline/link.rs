//! The host link's hold on the force: a host that armed the device must stay connected.
//!
//! Rules (the firmware's link task, the emulated board and the virtual device call the same
//! methods of [`super::Pipeline`]):
//!
//! - an `Arm` from the link ([`super::Pipeline::link_command`]) turns the communication watchdog
//!   on ([`HOST_WATCHDOG_S`]) when it is off, and it cannot be turned off while that host keeps
//!   the device armed ([`super::CommandError::WatchdogRequired`]);
//! - a lost link ([`super::Pipeline::link_lost`]: USB bus reset, suspend, DTR dropped, or the
//!   host not taking the device's writes for the firmware's stated time) while a host has armed
//!   the device fades the force to zero within [`LINK_FADE_S`] and latches
//!   [`Flags::COMM_TIMEOUT`] until the next `Arm`;
//! - a device armed from its button (the bench, no host) is not held by a link.
//!
//! The fade is linear, `1/(LINK_FADE_S·rate)` per tick, so it makes no force step.

use crate::control::local_model::ramp::Ramp;
use crate::flags::Flags;

/// The communication watchdog's timeout a host's `Arm` turns on when it is off, s: ten of the
/// host library's 20 ms pings.
pub const HOST_WATCHDOG_S: f32 = 0.2;

/// Shortest host watchdog timeout a device may be set to, s (the stored settings' 10 ms floor).
pub const HOST_WATCHDOG_MIN_S: f32 = 0.010;

/// Longest host watchdog timeout a device may be set to, s (the stored settings' 10 s ceiling).
pub const HOST_WATCHDOG_MAX_S: f32 = 10.0;

/// Time a lost link takes to fade the force to zero, s.
pub const LINK_FADE_S: f32 = 0.020;

/// Whether a host holds the arming, and the latched fade of a lost link.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LinkHold {
    host_armed: bool,
    lost: bool,
    gain: Ramp,
}

impl LinkHold {
    /// No host, gain 1, at `rate_hz`.
    pub fn new(rate_hz: f32) -> LinkHold {
        LinkHold {
            host_armed: false,
            lost: false,
            gain: Ramp::new(1.0, LINK_FADE_S, rate_hz),
        }
    }

    /// A host armed the device: its link now holds the force; a latched loss clears (the gain
    /// ramps back in over the fade time).
    pub fn armed_by_host(&mut self) {
        self.host_armed = true;
        self.lost = false;
    }

    /// Armed from the button: no host holds the force; a latched loss clears.
    pub fn armed_locally(&mut self) {
        self.host_armed = false;
        self.lost = false;
    }

    /// The device left `Armed` (disarm or fault): no host holds it any more.
    pub fn released(&mut self) {
        self.host_armed = false;
    }

    /// A host holds the arming.
    pub const fn host_armed(&self) -> bool {
        self.host_armed
    }

    /// The link was lost: latches when a host holds the arming. Returns whether it latched.
    pub fn lose(&mut self) -> bool {
        if self.host_armed {
            self.lost = true;
        }
        self.lost
    }

    /// Latched after a loss (until the next `Arm`).
    pub const fn lost(&self) -> bool {
        self.lost
    }

    /// One armed tick: the gain on the force and `COMM_TIMEOUT` while latched.
    #[must_use]
    pub fn tick(&mut self) -> (f32, Flags) {
        let g = self.gain.advance(if self.lost { 0.0 } else { 1.0 });
        let f = if self.lost {
            Flags::COMM_TIMEOUT
        } else {
            Flags::NONE
        };
        (g, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RATE: f32 = 10_000.0;

    /// A loss while a host holds the arming fades the gain to 0 in exactly 200 ticks at 10 kHz
    /// (not 199), by at most 1/200 per tick, and stays latched until re-armed.
    #[test]
    fn a_lost_link_fades_within_20_ms_and_latches() {
        let mut l = LinkHold::new(RATE);
        l.armed_by_host();
        assert_eq!(l.tick(), (1.0, Flags::NONE));
        assert!(l.lose());
        let mut prev = 1.0;
        let mut zero_at = None;
        for k in 1..=400u32 {
            let (g, f) = l.tick();
            assert_eq!(f, Flags::COMM_TIMEOUT);
            assert!(prev - g <= 1.0 / 200.0 + 1e-6, "step at {k}");
            if g == 0.0 && zero_at.is_none() {
                zero_at = Some(k);
            }
            prev = g;
        }
        assert_eq!(zero_at, Some(200));
        l.released();
        assert!(l.lost(), "latched until re-armed");
        l.armed_by_host();
        assert_eq!(l.tick().1, Flags::NONE);
    }

    /// Armed from the button, a lost link does not take the force away.
    #[test]
    fn a_local_arming_is_not_held_by_the_link() {
        let mut l = LinkHold::new(RATE);
        l.armed_locally();
        assert!(!l.lose());
        assert_eq!(l.tick(), (1.0, Flags::NONE));
        l.armed_by_host();
        l.released();
        assert!(!l.lose(), "released: the host no longer holds it");
    }
}
